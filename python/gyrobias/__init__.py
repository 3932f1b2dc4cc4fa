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

# The package façade, loaded lazily (PEP 562): ``import gyrobias`` runs only this file and the
# leaf ``gyrobias._generics``, so that ``gyrobias --help`` and ``gyrobias --version`` import
# neither NumPy nor the compiled core. A public name is imported at its first use
# (``gyrobias.adev``, ``gyrobias.noise``, ``from gyrobias import *``). The result objects'
# methods (plotting: ``.plot()``; exports (kalibr included), conservative: ``.export()`` and kin;
# codegen: ``.to_c()``) are registered by those modules when they are imported; this module hands
# :func:`_register_methods` to ``gyrobias._generics``, which runs it the first time a generic
# function finds no method, so the methods are in place whatever the caller imported first.
# plotting loads matplotlib only when a plot is drawn. The layers: docs/architecture.md.
from __future__ import annotations

import importlib
import importlib.util
from typing import TYPE_CHECKING, Any

from gyrobias import _generics

if TYPE_CHECKING:  # what the first use binds, for type checkers and editors
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

#: The module each public function, class and constant comes from (the other public names are
#: the subpackages themselves).
_HOMES = {
    "AR1Fit": "gyrobias.thermal",
    "AllanResult": "gyrobias.allan",
    "FixedGainKalman": "gyrobias.kalman",
    "FractionalKalmanPredictor": "gyrobias.predict",
    "GyroLinAlgError": "gyrobias._core",
    "KaiserLowpass": "gyrobias.fir",
    "LSSAResult": "gyrobias.spectral",
    "NoiseCoefficients": "gyrobias.noise",
    "Prediction": "gyrobias.predict",
    "TemperatureModel": "gyrobias.thermal",
    "__version__": "gyrobias._version",
    "adev": "gyrobias.allan",
    "avar": "gyrobias.allan",
    "fit_ar1": "gyrobias.thermal",
    "kaiser_lowpass": "gyrobias.fir",
    "lssa": "gyrobias.spectral",
}


def __getattr__(name: str) -> Any:
    """A name's first use: import it (the module a public name comes from, or a submodule,
    public or not: ``gyrobias.fleet`` and ``gyrobias.report`` work after ``import gyrobias``)."""
    if name in _HOMES:
        value = getattr(importlib.import_module(_HOMES[name]), name)
    elif not name.startswith("__") and importlib.util.find_spec(f"gyrobias.{name}") is not None:
        value = importlib.import_module(f"gyrobias.{name}")
    else:
        raise AttributeError(f"module 'gyrobias' has no attribute {name!r}")
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted({*globals(), *__all__})


def _register_methods() -> None:
    """Import every module that registers the result objects' methods in gyrobias._generics."""
    from gyrobias import codegen, conservative, exports, plotting  # noqa: F401


_generics.set_loader(_register_methods)
