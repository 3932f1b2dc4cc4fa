"""
Allan family on one log
=======================

One simulated hour of a MEMS gyro at 100 Hz (angle random walk, bias instability and rate
random walk with known values) analysed by the overlapping Allan (ADEV), modified (MDEV),
overlapping Hadamard (OHDEV) and total (TOTDEV) deviations, each with its chi-square
confidence interval, plus Théo1 (whose τ is 0.75·m·τ₀) reaching longer τ.
"""

import matplotlib.pyplot as plt

from gyrobias import allan, noise, plotting

fs = 100.0
rate = noise.simulate(
    360_000, fs, arw=0.2 / 60, bias_instability=3 / 3600, rrw=10 / 216_000, seed=1
)  # deg/s: N = 0.2 deg/√h, B = 3 deg/h, K = 10 deg/h^1.5

results = [
    allan.adev(rate, fs, units="deg/s"),
    allan.mdev(rate, fs, units="deg/s"),
    allan.hdev(rate, fs, units="deg/s"),
    allan.totdev(rate, fs, units="deg/s"),
    allan.theo1(rate[:36_000], fs, units="deg/s"),
]
for r in results:
    print(f"{r.label:40s} {len(r.taus):3d} τ from {r.taus[0]:.3g} s to {r.taus[-1]:.4g} s")

fig, ax = plt.subplots(figsize=(7, 4.5))
plotting.plot_allan(
    results, ax=ax, labels=["ADEV", "MDEV", "OHDEV", "TOTDEV", "Théo1 (first 6 min)"]
)
ax.set_title("One simulated gyro log, five statistics (68 % intervals)")
fig.tight_layout()
