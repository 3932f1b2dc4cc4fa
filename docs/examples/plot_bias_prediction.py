"""
Predicting a bias from a calibration window
===========================================

[BP]'s setting: a vehicle stands still for 10 s (1000 samples at 100 Hz), the gyro's output
then is the calibration window, and the bias is predicted for the next 10 s. The bias is 1/f
(type-II ARFIMA(0, ½, 0)) noise plus white noise. The fractional Kalman predictor's forecast
comes with a ±2σ band; the calibration mean is the flat line most systems use. On one window
the three methods are close (the printed errors differ run to run); [BP]'s Table I statistic
over 1000 simulated runs (``gyrobias experiment table1``) gives the fractional Kalman
predictor an RSSE 0.982 ± 0.003 times the calibration mean's. What the predictor adds on every
window is the forecast's *uncertainty*, growing with the horizon.
"""

import matplotlib.pyplot as plt
import numpy as np

from gyrobias import fractional
from gyrobias.predict import FractionalKalmanPredictor, calibration_mean, moving_average

k = h = 1000
truth = fractional.arfima(k + h, 0.5, sigma=0.02, seed=3) + 0.3  # deg/s, 1/f bias + offset
y = truth + np.random.default_rng(4).normal(0.0, 0.05, k + h)  # what the gyro outputs

kf = FractionalKalmanPredictor(d=0.5, q=0.02**2, r=0.05**2)
p = kf.predict(y[:k], h)
cm = calibration_mean(y[:k], h)
ma = moving_average(y[:k], h)
for name, pred in (("fractional KF", p.bias), ("moving average", ma), ("calibration mean", cm)):
    print(
        f"{name:17s} RMS error over the horizon: {np.sqrt(np.mean((pred - truth[k:]) ** 2)):.4f} deg/s"
    )

t = np.arange(k + h) / 100.0
fig, ax = plt.subplots(figsize=(8, 4))
ax.plot(t, y, color="0.8", lw=0.5, label="gyro output")
ax.plot(t, truth, color="k", lw=1, label="true bias")
ax.plot(t[k:], p.bias, color="C0", label="fractional KF forecast")
ax.fill_between(t[k:], p.bias - 2 * p.std, p.bias + 2 * p.std, color="C0", alpha=0.2, label="±2σ")
ax.plot(t[k:], cm, color="C3", ls="--", label="calibration mean")
ax.axvline(k / 100.0, color="0.5", lw=0.8)
ax.set_xlabel("time [s]")
ax.set_ylabel("rate [deg/s]")
ax.set_ylim(0.1, 0.5)
ax.legend(loc="upper left", fontsize=8, ncol=2)
ax.set_title("Calibration window (left), forecast (right)")
fig.tight_layout()
