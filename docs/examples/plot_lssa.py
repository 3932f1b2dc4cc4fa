"""
Least-squares spectrum of unequally spaced data
===============================================

[TS]'s least-squares spectral analysis (Vaníček 1969, Pagiatakis 1999) on irregularly sampled
data with a gap: a weak 0.05 Hz oscillation in white noise, a linear trend and a known 86.4 s
constituent fitted simultaneously (so they are suppressed without shifting other peaks), and
the 99 % significance level of the spectrum (a per-frequency test: among 1500 frequencies
about 1 % of pure-noise values exceed it, so read the level for one frequency at a time).
"""

import matplotlib.pyplot as plt
import numpy as np

from gyrobias import spectral

rng = np.random.default_rng(1)
t = np.sort(rng.uniform(0.0, 600.0, 2000))
t = t[(t < 250.0) | (t > 320.0)]  # a 70 s gap
y = (
    0.4 * np.sin(2 * np.pi * 0.05 * t)
    + 0.8 * np.sin(2 * np.pi * t / 86.4)
    + 0.002 * t
    + rng.normal(size=t.size)
)
freqs = np.linspace(0.002, 0.5, 1500)
r = spectral.lssa(t, y, freqs, trend=True, known_periods=[86.4])
best = np.argmax(r.spectrum)
print(
    f"strongest peak: {r.frequencies[best]:.4f} Hz (s = {r.spectrum[best]:.3f}); "
    f"99 % critical value {r.critical_value:.4f}"
)

fig, ax = plt.subplots(figsize=(7, 4))
ax.plot(r.frequencies, r.spectrum, lw=0.8, label="least-squares spectrum s(f)")
ax.axhline(r.critical_value, color="C3", ls="--", label="99 % significance")
ax.set_xlabel("frequency [Hz]")
ax.set_ylabel("s(f)  (fraction of variance)")
ax.legend()
ax.set_title("LSSA of irregular data with a gap, trend and known period removed")
fig.tight_layout()
