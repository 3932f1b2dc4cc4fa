"""
Dynamic Allan deviation
=======================

One Allan deviation of a whole log averages away what changes during it. The dynamic ADEV
(Galleani & Tavella 2009) computes the ADEV in sliding windows: here the white noise doubles
for five minutes in the middle of a 30-minute log (a vibration burst), which the map shows as
a band at short τ.
"""

from gyrobias import allan, noise

fs = 100.0
rate = noise.simulate(180_000, fs, arw=0.2 / 60, bias_instability=3 / 3600, seed=5)
burst = slice(75_000, 105_000)
rate[burst] += noise.simulate(30_000, fs, arw=0.35 / 60, seed=6)

dyn = allan.dynamic_adev(rate, fs, window=30_000, step=6_000, units="deg/s")
print(f"{len(dyn.times)} windows × {len(dyn.taus)} τ; ADEV at τ = 0.01 s per window [deg/s]:")
print(" ".join(f"{v:.2e}" for v in dyn.adev[:, 0]))
ax = dyn.plot()
ax.set_title("Dynamic ADEV: a 5-minute burst of white noise at t = 12.5–17.5 min")
ax.figure.tight_layout()
