"""
Noise fit with diagnostics, and a rejected fit
==============================================

A static log like a real MEMS sensor's: white rate noise through the sensor's anti-alias
low-pass (which bends the Allan curve *below* the −½ line at short τ), a Gauss–Markov bias and
quantisation. The joint fit selects the τ range the model explains and passes its goodness-of-fit
test; fitting every point instead (``auto_range=False``) is rejected (p ≈ 0), and says so.
"""

import math

import matplotlib.pyplot as plt
import numpy as np
from scipy import signal

from gyrobias import allan, noise

fs, n = 100.0, 1_000_000  # 2.8 h at 100 Hz, like a public ADIS16405 log
rng = np.random.default_rng(0)
white = rng.standard_normal(n + 200) * 0.044 * math.sqrt(fs)  # N = 0.044 deg/√s
filtered = signal.lfilter(signal.firwin(41, 6.0, fs=fs), 1.0, white)[200:]  # 6 Hz anti-alias FIR
phi = math.exp(-1.0 / (fs * 100.0))  # Gauss–Markov bias, σ = 0.005 deg/s, T = 100 s
e = rng.standard_normal(n) * 0.005 * math.sqrt(1.0 - phi * phi)
e[0] = rng.standard_normal() * 0.005
rate = np.round((filtered + signal.lfilter([1.0], [1.0, -phi], e)) / 0.05) * 0.05  # 0.05 deg/s LSB

result = allan.adev(rate, fs, units="deg/s")
good = noise.fit(result, terms=("N", "K", "GM"))
bad = noise.fit(result, terms=("N", "K", "GM"), auto_range=False)
print(good)
print(
    f"every τ: χ² = {bad.diagnostics.chi2:.0f}, ν = {bad.diagnostics.dof}, p = {bad.diagnostics.p_value:.2g}"
)
print(bad.diagnostics.warnings[0])

fig, axes = plt.subplots(1, 2, figsize=(10, 4), sharey=True)
good.plot(axes[0])
axes[0].set_title(f"auto τ range: p = {good.diagnostics.p_value:.2f} (accepted)", fontsize=10)
bad.plot(axes[1])
axes[1].set_title(f"every τ: p = {bad.diagnostics.p_value:.1g} (rejected)", fontsize=10)
fig.tight_layout()
