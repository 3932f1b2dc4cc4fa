"""IEEE-952 noise coefficients of rate sensors: simulation, identification, units and exports.

The five-term model of the Allan variance of a rate signal (IEEE Std 952-1997 Annex C,
[NR] Table 1) is::

    σ²(τ) = 3Q²/τ² + N²/τ + (0.664282·B)² + K²τ/3 + R²τ²/2

with quantisation ``Q``, angle random walk ``N`` (ARW; velocity random walk VRW for an
accelerometer), bias instability ``B`` (flicker rate noise, two-sided PSD ``B²/(2πf)``; the
plateau factor is ``√(2 ln 2 / π) = 0.664282``), rate random walk ``K`` (RRW) and rate ramp ``R``.

Coefficients are stored in the base units of the data: for a rate in ``u/s`` (u = deg or rad)
``Q`` is in u, ``N`` in u/√s, ``B`` in u/s, ``K`` in u/s^1.5 and ``R`` in u/s².

The package, by task:

- **Coefficients** (:mod:`gyrobias.noise._types`, value types only): :class:`NoiseCoefficients`,
  :class:`Term`, :class:`GaussMarkovTerm`, :class:`FitDiagnostics`, :data:`TERM_NAMES`,
  :data:`FLICKER_FACTOR`.
- **Simulation** (:mod:`gyrobias.noise.simulation`): :func:`simulate`.
- **Identification** (:mod:`gyrobias.noise.fitting`, :mod:`gyrobias.noise.wavelet`): :func:`fit`
  (joint weighted fit or IEEE read-off on an Allan curve), :func:`gmwm` (wavelet moments on the
  raw data), :func:`gauss_markov_avar`, :func:`sinusoid_avar`.
- **Periodic disturbances and the wavelet variance**: :func:`detect_lines` (spectral lines with a
  false-alarm level, :class:`SpectralLine`; fitted as :class:`SinusoidTerm`), :func:`wvar`
  (Haar wavelet variance, classical and robust, :class:`WaveletVariance`).
- **Datasheet values in** (:mod:`gyrobias.datasheet`): :func:`from_datasheet`, :class:`Datasheet`.
- **Files out**: every estimator format, Kalibr's included, is written by
  :func:`gyrobias.exports.export`; ``write_kalibr`` (here and in :mod:`gyrobias.exports`) is
  its keyword form for Kalibr, the same code.

References
----------
.. [IEEE952] IEEE Std 952-1997, Annex C; IEEE Std 647-2006.
.. [SP1065] W. J. Riley, "Handbook of Frequency Stability Analysis", NIST SP 1065 (2008).
.. [NR] Xue et al., "Noise reduction of MEMS gyroscope based on direct modeling for an angular
   rate signal", Micromachines 6 (2015) 266, Table 1.
"""

from typing import TYPE_CHECKING, Any

from gyrobias._line_detection import detect_lines
from gyrobias._spectral_lines import SpectralLine
from gyrobias.noise._types import (
    FLICKER_FACTOR,
    TERM_NAMES,
    FitDiagnostics,
    GaussMarkovTerm,
    NoiseCoefficients,
    SinusoidTerm,
    Term,
    WaveletVariance,
)
from gyrobias.noise._types import REJECT_P as REJECT_P
from gyrobias.noise.fitting import fit, gauss_markov_avar, sinusoid_avar
from gyrobias.noise.simulation import simulate
from gyrobias.noise.wavelet import gmwm, wvar

if TYPE_CHECKING:
    from gyrobias.datasheet import Datasheet, from_datasheet

__all__ = [
    # coefficients
    "FLICKER_FACTOR",
    "TERM_NAMES",
    "FitDiagnostics",
    "GaussMarkovTerm",
    "NoiseCoefficients",
    "SinusoidTerm",
    "SpectralLine",
    "Term",
    "WaveletVariance",
    # simulation
    "simulate",
    # identification
    "fit",
    "gauss_markov_avar",
    "gmwm",
    "sinusoid_avar",
    # periodic disturbances and the wavelet variance
    "detect_lines",
    "wvar",
    # datasheet values in
    "Datasheet",
    "from_datasheet",
    # files out (gyrobias.exports.write_kalibr, resolved by __getattr__ below)
    "write_kalibr",
]


def __getattr__(name: str) -> Any:
    """``write_kalibr``: the one Kalibr writer, :func:`gyrobias.exports.write_kalibr` (the
    keyword form of ``gyrobias.exports.export(..., "kalibr")``), looked up on first use — the
    exports package builds on these coefficient types, so ``gyrobias.noise`` cannot import it
    while it loads. ``Datasheet`` and ``from_datasheet`` (datasheet values in, issue 13) the
    same way: :mod:`gyrobias.datasheet` builds on ``gyrobias.noise._types``, and importing that
    runs this package first, so a program whose first import is ``gyrobias.datasheet`` would
    find it half loaded here."""
    if name == "write_kalibr":
        from gyrobias.exports.kalibr import write_kalibr

        return write_kalibr
    if name in ("Datasheet", "from_datasheet"):
        from gyrobias import datasheet

        return getattr(datasheet, name)
    raise AttributeError(f"module 'gyrobias.noise' has no attribute {name!r}")
