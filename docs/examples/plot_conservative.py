"""
A conservative set
==================

Estimator tuning needs noise values that are not *under*-estimated. The conservative set
(Lethander & Taylor 2023) is the tightest model whose Allan variance lies above the one-sided
95 % upper confidence bound at every τ the fit used; each term's inflation factor says how much
larger than the best fit it had to be.
"""

import matplotlib.pyplot as plt
import numpy as np

from gyrobias import allan, noise

fs = 100.0
rate = noise.simulate(
    180_000, fs, arw=0.2 / 60, bias_instability=3 / 3600, rrw=10 / 216_000, seed=4
)
result = allan.adev(rate, fs, units="deg/s", confidence=0.9)  # 90 % two-sided = 95 % one-sided
fit = noise.fit(result)
cons = fit.conservative(0.95)
print(cons)

taus = np.logspace(np.log10(result.taus[0]), np.log10(result.taus[-1]), 200)
fig, ax = plt.subplots(figsize=(7, 4.5))
ax.errorbar(
    result.taus,
    result.adev,
    yerr=[result.adev - result.ci_low, result.ci_high - result.adev],
    fmt="o",
    ms=3,
    color="0.3",
    label="ADEV with 90 % interval",
)
ax.loglog(cons.taus, cons.upper_bound, "v", color="C3", ms=5, label="95 % one-sided upper bound")
ax.loglog(taus, fit.model(taus)[0], label="best fit")
ax.loglog(taus, cons.coefficients.model(taus)[0], "--", label="conservative (95 %)")
ax.set_xlabel("τ [s]")
ax.set_ylabel("σ(τ) [deg/s]")
ax.legend()
ax.set_title("The conservative model overbounds the upper bound at every τ")
fig.tight_layout()
