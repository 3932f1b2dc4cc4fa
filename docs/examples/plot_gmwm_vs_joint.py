"""
GMWM against the joint fit
==========================

Two estimators of the same noise model from one log of white noise plus a first-order
Gauss–Markov bias (σ = 0.005 deg/s, T = 60 s): the joint weighted least-squares fit on the
Allan variance (the default of :func:`gyrobias.noise.fit`) and the generalized method of
wavelet moments (:func:`gyrobias.noise.gmwm`, Guerrier et al. 2013). On a log whose shortest
scales are white they agree term by term, within their uncertainties.
"""

import matplotlib.pyplot as plt
import numpy as np

from gyrobias import allan, noise

fs, n = 100.0, 2**19
phi = np.exp(-1 / (60 * fs))
rate = noise.simulate(n, fs, arw=0.05 / 60, ar1=(phi, 0.005 * np.sqrt(1 - phi**2)), seed=7)

result = allan.adev(rate, fs, units="deg/s")
joint = noise.fit(result, terms=("N", "GM"))
wavelet = noise.gmwm(rate, fs, terms=("N", "GM"), units="deg/s")
for name, c in (("joint", joint), ("gmwm", wavelet)):
    g = c.gauss_markov[0]
    print(
        f"{name:6s} N = {c.N.value:.5f} ± {c.N.uncertainty:.5f} {c.N.unit}, "
        f"GM σ = {g.sigma.value:.5f} ± {g.sigma.uncertainty:.5f} {g.sigma.unit}, "
        f"T = {g.correlation_time.value:.0f} ± {g.correlation_time.uncertainty:.0f} s"
    )

taus = np.logspace(np.log10(result.taus[0]), np.log10(result.taus[-1]), 200)
fig, ax = plt.subplots(figsize=(7, 4.5))
ax.errorbar(
    result.taus,
    result.adev,
    yerr=[result.adev - result.ci_low, result.ci_high - result.adev],
    fmt="o",
    ms=3,
    color="0.3",
    label="ADEV (68 %)",
)
ax.loglog(taus, joint.model(taus)[0], label="joint fit")
ax.loglog(taus, wavelet.model(taus)[0], "--", label="GMWM")
ax.set_xlabel("τ [s]")
ax.set_ylabel("σ(τ) [deg/s]")
ax.legend()
ax.set_title("White noise + Gauss–Markov: joint fit and GMWM")
fig.tight_layout()
