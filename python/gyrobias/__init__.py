"""gyrobias: MEMS gyroscope noise analysis and bias prediction.

The numerics live in a Rust core (``gyrobias._core``); the modules here give them typed,
unit-aware Python interfaces:

- :mod:`gyrobias.allan` — overlapping / non-overlapping Allan, modified, Hadamard and total
  deviations with chi-square confidence intervals (NIST SP 1065, IEEE Std 952).
- :mod:`gyrobias.fir` — Kaiser-window FIR low-pass design, causal and zero-phase filtering ([TS]).
- :mod:`gyrobias.spectral` — least-squares spectral analysis of unequally spaced data with
  significance tests, Welch PSD and noise density ([TS] §2.2, Pagiatakis 1999).
- :mod:`gyrobias.thermal` — AR(1) drift fits and temperature-dependent noise models ([TS] §4).
- :mod:`gyrobias.fractional` — long-memory (1/f) noise: type-II fractional differencing and
  integration, ARFIMA(0, d, 0) simulation, exact local Whittle estimation of ``d``.
- :mod:`gyrobias.predict` — bias prediction from a calibration window ([BP]): the fractional
  (1/f) Kalman predictor (O(n·k) generalized Schur, compiled batch GEMM), moving average and
  calibration mean, and [BP]'s batch test.
- :mod:`gyrobias.kalman` — fixed-gain [rate, bias] Kalman filter for real-time denoising ([NR]):
  steady-state gain, discrete fixed-gain form, bandwidth design, streaming.
- :mod:`gyrobias.noise` — IEEE-952 noise coefficients (Q, N, B, K, R) with uncertainties:
  simulation, joint fit and read-off identification, unit conversion, Kalibr/JSON export.
- :mod:`gyrobias.datasheet`, :mod:`gyrobias.conservative`, :mod:`gyrobias.exports` — datasheet
  values in, conservative (overbounding) sets, estimator files (Kalibr, OpenVINS, VINS, ORB-SLAM3,
  LIO-SAM, MATLAB, JSON) and discrete-time parameters; ``gyrobias report`` for the HTML page.
- :mod:`gyrobias.codegen` — C99 (float64, float32, Q31) for the fixed-gain Kalman filter, the FIR
  and the compiled predictor, bit-exact or with a stated Q31 error bound.
- :mod:`gyrobias.io` — reading gyro logs (CSV/TSV/NPY) with sampling checks.
- :mod:`gyrobias.fleet`, :mod:`gyrobias.plotting` — many logs at once on Dask; every plot.

``gyrobias.__version__`` is the version of the compiled core, set once in the workspace's
``Cargo.toml`` (the wheel, ``gyrobias --version`` and the CHANGELOG's release use the same).
"""

# The package façade: it imports the science modules and every module that registers the
# result objects' methods (plotting: ``.plot()``; exports (kalibr included), conservative:
# ``.export()`` and kin; see gyrobias._generics), so these are loaded whatever the caller
# imports first. plotting loads matplotlib only when a plot is drawn. The layers:
# docs/architecture.md.
from gyrobias import (
    allan,
    codegen,
    conservative,
    datasheet,
    exports,
    fir,
    fractional,
    io,
    kalman,
    noise,
    plotting,
    predict,
    spectral,
    thermal,
)
from gyrobias._core import GyroLinAlgError
from gyrobias._version import __version__
from gyrobias.allan import AllanResult, adev, avar
from gyrobias.fir import KaiserLowpass, kaiser_lowpass
from gyrobias.kalman import FixedGainKalman
from gyrobias.noise import NoiseCoefficients
from gyrobias.predict import FractionalKalmanPredictor, Prediction
from gyrobias.spectral import LSSAResult, lssa
from gyrobias.thermal import AR1Fit, TemperatureModel, fit_ar1

__all__ = [
    "AR1Fit",
    "AllanResult",
    "FixedGainKalman",
    "FractionalKalmanPredictor",
    "GyroLinAlgError",
    "KaiserLowpass",
    "LSSAResult",
    "NoiseCoefficients",
    "Prediction",
    "TemperatureModel",
    "__version__",
    "adev",
    "allan",
    "avar",
    "codegen",
    "conservative",
    "datasheet",
    "exports",
    "fir",
    "fit_ar1",
    "fractional",
    "io",
    "kalman",
    "kaiser_lowpass",
    "lssa",
    "noise",
    "plotting",
    "predict",
    "spectral",
    "thermal",
]
