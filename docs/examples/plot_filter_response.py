"""
The fixed-gain filter's frequency response
==========================================

[NR]'s 2-state [rate, bias] Kalman filter run with its steady-state gain is a first-order
low-pass of the rate, ``g1/(1 − p z⁻¹)``, with unity DC gain. Designed for 10, 20 and 30 Hz at
200 Hz, its response sits at −3 dB exactly at the requested bandwidth.
"""

import matplotlib.pyplot as plt
import numpy as np

from gyrobias.kalman import FixedGainKalman

fs = 200.0
freqs = np.logspace(-1, np.log10(fs / 2), 400)
fig, ax = plt.subplots(figsize=(7, 4))
for bw in (10.0, 20.0, 30.0):
    kf = FixedGainKalman(fs, arw=0.08, rrw=7e-4, bandwidth=bw)
    gain_db = 20 * np.log10(np.abs(kf.frequency_response(freqs)))
    at_bw = 20 * np.log10(abs(kf.frequency_response([bw])[0]))
    print(
        f"{bw:4.0f} Hz design: pole {kf.pole:.4f}, response at {bw:.0f} Hz = {at_bw:.3f} dB, "
        f"white-noise s.d. ×{kf.white_noise_gain:.3f}"
    )
    ax.semilogx(freqs, gain_db, label=f"bandwidth {bw:.0f} Hz")
ax.axhline(-3.0103, color="0.5", lw=0.8, ls=":")
ax.set_xlabel("frequency [Hz]")
ax.set_ylabel("|H| [dB]")
ax.set_ylim(-20, 1)
ax.legend()
ax.set_title("Fixed-gain [rate, bias] filter, fs = 200 Hz")
fig.tight_layout()
