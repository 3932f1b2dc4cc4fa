"""gyrobias: MEMS gyroscope noise analysis and bias prediction.

The numerics live in a Rust core (``gyrobias._core``); the modules here give them typed,
unit-aware Python interfaces:

- :mod:`gyrobias.allan` — overlapping / non-overlapping Allan, modified, Hadamard and total
  deviations with chi-square confidence intervals (NIST SP 1065, IEEE Std 952).
- :mod:`gyrobias.fractional` — long-memory (1/f) noise: type-II fractional differencing and
  integration, ARFIMA(0, d, 0) simulation, exact local Whittle estimation of ``d``.
- :mod:`gyrobias.predict` — bias prediction from a calibration window ([BP]): the fractional
  (1/f) Kalman predictor (O(n·k) generalized Schur, compiled batch GEMM), moving average and
  calibration mean, and [BP]'s batch test.
- :mod:`gyrobias.kalman` — fixed-gain [rate, bias] Kalman filter for real-time denoising ([NR]):
  steady-state gain, discrete fixed-gain form, bandwidth design, streaming.
- :mod:`gyrobias.noise` — IEEE-952 noise coefficients (Q, N, B, K, R) with uncertainties:
  simulation, joint fit and read-off identification, unit conversion, Kalibr/JSON export.
- :mod:`gyrobias.predict` — bias prediction from a calibration window ([BP]): the fractional
  (1/f) Kalman predictor (O(n·k) generalized Schur, compiled batch GEMM), moving average and
  calibration mean, and [BP]'s batch test.
- :mod:`gyrobias.io` — reading gyro logs (CSV/TSV/NPY) with sampling checks.
"""

from importlib.metadata import PackageNotFoundError, version

from gyrobias import allan, fractional, io, kalman, noise, predict
from gyrobias._core import GyroLinAlgError
from gyrobias.allan import AllanResult, adev, avar
from gyrobias.predict import FractionalKalmanPredictor, Prediction
from gyrobias.kalman import FixedGainKalman

try:
    __version__ = version("gyrobias")
except PackageNotFoundError:  # running from a source tree without installation
    __version__ = "0.0.0+unknown"

__all__ = [
    "AllanResult",
    "FractionalKalmanPredictor",
    "FixedGainKalman",
    "GyroLinAlgError",
    "Prediction",
    "__version__",
    "adev",
    "allan",
    "avar",
    "fractional",
    "io",
    "noise",
    "predict",
    "kalman",
]
