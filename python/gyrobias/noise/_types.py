"""Noise-coefficient value types: :class:`Term`, :class:`GaussMarkovTerm`,
:class:`FitDiagnostics`, :class:`NoiseCoefficients` (and the constants they use).

Value types only: no fitting, plotting or export module is imported here. The convenience
methods ``.plot()``, ``.export()``, ``.discrete()``, ``.conservative()`` and ``.to_kalibr()`` are
one-line delegations to :mod:`gyrobias._generics`, whose methods the owning modules register.
"""

from __future__ import annotations

import json
import os
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from gyrobias import _core, _files, _generics
from gyrobias._spectral_lines import SpectralLine
from gyrobias._validation import (
    as_float_array,
    asarray,
    choice,
)
from gyrobias.units import CUSTOMARY, _parse_unit, base_unit

if TYPE_CHECKING:
    from gyrobias.allan._types import AllanResult
    from gyrobias.conservative import ConservativeCoefficients
    from gyrobias.exports import DiscreteNoise

__all__ = [
    "FLICKER_FACTOR",
    "REJECT_P",
    "TERM_NAMES",
    "FitDiagnostics",
    "GaussMarkovTerm",
    "NoiseCoefficients",
    "Term",
]

#: Plateau factor of flicker rate noise in the Allan deviation: √(2 ln 2 / π) = 0.664282…
#: (``gyrocore::noise::FLICKER_FACTOR``, the one definition every layer uses.)
FLICKER_FACTOR: float = _core.noise.FLICKER_FACTOR

_SYMBOLS = ("Q", "N", "B", "K", "R")
_GM_SYMBOLS = ("GM", "GM2")

#: p-value below which a fit is reported as rejected by its goodness-of-fit test.
REJECT_P: float = 0.001

#: Names of the terms for gyroscopes and accelerometers.
TERM_NAMES: dict[str, dict[str, str]] = {
    "gyro": {
        "Q": "quantization noise",
        "N": "angle random walk (ARW)",
        "B": "bias instability",
        "K": "rate random walk (RRW)",
        "R": "rate ramp",
    },
    "accel": {
        "Q": "velocity quantization",
        "N": "velocity random walk (VRW)",
        "B": "bias instability",
        "K": "acceleration random walk",
        "R": "acceleration ramp",
    },
}


def _percent(confidence: float | None) -> str:
    """0.95 → ``"95 %"`` (``"?"`` when unknown)."""
    return "?" if confidence is None else f"{100.0 * confidence:.4g} %"


@dataclass(frozen=True)
class Term:
    """One noise coefficient with its standard uncertainty and unit, or why it is missing.

    Attributes
    ----------
    symbol : {"Q", "N", "B", "K", "R"}
        IEEE-952 symbol.
    name : str
        Long name (ARW / VRW etc. depending on the sensor).
    value : float or None
        The coefficient in ``unit``; ``None`` when the term is missing.
    uncertainty : float or None
        Standard (1σ) uncertainty in ``unit``.
    unit : str or None
        Unit of ``value`` and ``uncertainty`` (``None`` if the data unit is unknown).
    tau_range : (float, float) or None
        τ range in seconds of the Allan points that determined the term (read-off: the slope
        region used; joint fit: where the term is ≥ 10 % of the fitted variance).
    marker : (float, float) or None
        (τ [s], σ [data unit]) of the read-off point on an Allan plot: on the term's asymptote at
        τ = √3, 1, 3, √2 s for Q, N, K, R; at the minimum (σ = 0.664·B) for B.
    missing : str or None
        Why the term is missing (``value is None``).
    upper_bound : float or None
        For a term the data do not show (``value is None``, the fit set it to zero or the
        read-off found no region): the largest value consistent with them, in ``unit`` — the
        coefficient whose Allan-variance asymptote stays under the one-sided upper confidence
        bound ``σ̂²·edf/χ²_edf(1 − bound_confidence)`` of the curve at every τ the fit used, the
        other terms held at zero (``gyrocore::noise::bound``: held at their fit they would
        have absorbed part of the term and the bound would under-cover). ``None`` for an
        identified term, a term not requested, or coefficients not from data.
    bound_confidence : float or None
        One-sided confidence level of :attr:`upper_bound`: the ``bound_confidence`` of the
        fit (:func:`gyrobias.noise.fit`, :func:`gyrobias.noise.gmwm`; default 0.95).
    bound_reason : str or None
        How the bound was obtained (points, τ range, the binding τ).

    Examples
    --------
    A log too short to show a rate random walk: K is bounded, not zero.

    >>> import gyrobias
    >>> rate = gyrobias.noise.simulate(60_000, 100.0, arw=0.2 / 60, bias_instability=3 / 3600,
    ...                                rrw=1e-5, seed=4)
    >>> k = gyrobias.noise.fit(gyrobias.allan.adev(rate, 100.0, units="deg/s")).K
    >>> k.value is None, k.bounded, k.bound_confidence
    (True, True, 0.95)
    >>> k.upper_bound > 1e-5
    True
    """

    symbol: str
    name: str
    value: float | None
    uncertainty: float | None
    unit: str | None
    tau_range: tuple[float, float] | None = None
    marker: tuple[float, float] | None = None
    missing: str | None = None
    upper_bound: float | None = None
    bound_confidence: float | None = None
    bound_reason: str | None = None

    @classmethod
    def _from_core(cls, raw: Mapping[str, Any], name: str, unit: str | None) -> Term:
        """The one place a :class:`Term` is built from the core's ``TermEstimate``."""
        bound = raw.get("upper_bound")
        return cls(
            symbol=raw["symbol"],
            name=name,
            value=raw["value"],
            uncertainty=raw["uncertainty"],
            unit=unit,
            tau_range=raw["tau_range"],
            marker=raw["marker"],
            missing=raw["missing"],
            upper_bound=None if bound is None else float(bound["value"]),
            bound_confidence=None if bound is None else float(bound["confidence"]),
            bound_reason=None if bound is None else str(bound["reason"]),
        )

    @property
    def present(self) -> bool:
        """True when the term was identified."""
        return self.value is not None

    @property
    def bounded(self) -> bool:
        """True when the term was not identified but the data bound it from above."""
        return self.value is None and self.upper_bound is not None

    def to(self, unit: str) -> Term:
        """This term converted to ``unit`` (e.g. ``"deg/h"``, ``"rad/s/√Hz"``).

        Raises
        ------
        ValueError
            Unknown unit (the message lists the valid symbols and customary units), a unit of
            another dimension, or a term whose data unit is unknown.
        """
        if self.unit is None:
            raise ValueError(
                f"term {self.symbol} has no unit (the data unit was not given): pass units= to the "
                "Allan analysis or unit= to gyrobias.noise.fit"
            )
        target = _parse_unit(unit)
        source = _parse_unit(self.unit)
        if target.dims != source.dims:
            raise ValueError(
                f"cannot express {self.symbol} ({self.name}, in {self.unit}) in {unit!r}: different "
                f"dimensions; customary units for it: "
                + ", ".join(
                    sorted(
                        {
                            s[self.symbol]
                            for k in CUSTOMARY.values()
                            for s in k.values()
                            if self.symbol in s
                        }
                    )
                )
            )
        f = source.factor / target.factor
        return replace(
            self,
            value=None if self.value is None else self.value * f,
            uncertainty=None if self.uncertainty is None else self.uncertainty * f,
            upper_bound=None if self.upper_bound is None else self.upper_bound * f,
            unit=unit,
        )

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dictionary."""
        return {
            "symbol": self.symbol,
            "name": self.name,
            "value": self.value,
            "uncertainty": self.uncertainty,
            "unit": self.unit,
            "tau_range_s": None if self.tau_range is None else list(self.tau_range),
            "missing": self.missing,
            "upper_bound": self.upper_bound,
            "bound_confidence": self.bound_confidence,
            "bound_reason": self.bound_reason,
        }

    def __str__(self) -> str:
        unit = f" {self.unit}" if self.unit else ""
        if self.value is None and self.upper_bound is not None:
            return (
                f"{self.symbol} ({self.name}) ≤ {self.upper_bound:.4g}{unit} "
                f"({_percent(self.bound_confidence)} upper bound; not identified — {self.missing})"
            )
        if self.value is None:
            return f"{self.symbol} ({self.name}): missing — {self.missing}"
        if self.uncertainty is None:  # datasheet values and conservative sets carry none
            return f"{self.symbol} ({self.name}) = {self.value:.4g}{unit}"
        return f"{self.symbol} ({self.name}) = {self.value:.4g} ± {self.uncertainty:.2g}{unit}"


@dataclass(frozen=True)
class GaussMarkovTerm:
    """A first-order Gauss–Markov (exponentially correlated) rate term.

    The process has autocovariance ``σ² exp(−|t|/T)`` and the Allan variance
    ``σ²(τ) = (σ²T²/τ²)(2τ/T − 3 + 4e^{−τ/T} − e^{−2τ/T})`` (IEEE Std 952-1997 Annex C).

    Attributes
    ----------
    sigma : Term
        Standard deviation σ of the process (rate unit of the data, e.g. deg/s).
    correlation_time : Term
        Correlation time T in seconds (the bias correlation time of an INS filter's
        first-order Gauss–Markov state).
    tau_range : (float, float) or None
        τ range (s) of the Allan points where the term is ≥ 10 % of the fitted variance.
    missing : str or None
        Why the term is missing.
    """

    sigma: Term
    correlation_time: Term
    tau_range: tuple[float, float] | None = None
    missing: str | None = None

    @classmethod
    def _from_core(
        cls, raw: Mapping[str, Any], index: int, rate_unit: str | None
    ) -> GaussMarkovTerm:
        """The one place a :class:`GaussMarkovTerm` is built from the core's ``GaussMarkovTerm``
        (the ``index``-th component: symbol ``GM``, ``GM2``, …)."""
        symbol = "GM" if index == 0 else f"GM{index + 1}"
        rng = (
            None
            if raw["tau_range"] is None
            else (float(raw["tau_range"][0]), float(raw["tau_range"][1]))
        )
        return cls(
            sigma=Term(
                symbol,
                "Gauss–Markov σ",
                raw["sigma"],
                raw["sigma_uncertainty"],
                rate_unit,
                rng,
                None,
                raw["missing"],
            ),
            correlation_time=Term(
                symbol,
                "Gauss–Markov correlation time",
                raw["correlation_time"],
                raw["correlation_time_uncertainty"],
                "s",
                rng,
                None,
                raw["missing"],
            ),
            tau_range=rng,
            missing=raw["missing"],
        )

    @property
    def present(self) -> bool:
        """True when the term was identified."""
        return self.sigma.value is not None

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dictionary."""
        return {
            "sigma": self.sigma.to_dict(),
            "correlation_time": self.correlation_time.to_dict(),
            "tau_range_s": None if self.tau_range is None else list(self.tau_range),
            "missing": self.missing,
        }

    def __str__(self) -> str:
        if not self.present:
            return f"{self.sigma.symbol} (Gauss–Markov): missing — {self.missing}"
        tc = self.correlation_time
        spread = f" ± {tc.uncertainty:.2g}" if tc.uncertainty is not None else ""
        return f"{self.sigma} with correlation time {tc.value:.4g}{spread} s"


@dataclass(frozen=True)
class SinusoidTerm:
    """A sinusoidal rate term (IEEE Std 952-1997 Annex C): a periodic disturbance
    ``Ω₀·sin(2πf₀t + φ)`` (vibration, a fan, an aliased mechanical mode).

    Its Allan variance for data sampled at period t0 is
    ``Ω₀²·sin⁴(πf₀τ)/(m·sin(πf₀t0))²`` at ``τ = m·t0`` (the IEEE form
    ``Ω₀²·(sin²(πf₀τ)/(πf₀τ))²`` is its continuous-time limit).

    Attributes
    ----------
    frequency : Term
        f₀ in Hz: a detected line's is the periodogram maximum, with the periodogram's
        uncertainty (:attr:`gyrobias.noise.SpectralLine.frequency_uncertainty`); a frequency
        refined on the Allan curve (a seed with no detected line, a ``(f, half_width)``
        window) has the fit's standard uncertainty; one held fixed (``lines=[(f, 0.0)]``) is ``f`` exactly, without
        uncertainty (``None``: given, not estimated).
    amplitude : Term
        Ω₀ in the rate unit of the data.
    tau_range : (float, float) or None
        τ range (s) of the Allan points where the term is ≥ 10 % of the fitted variance.
    missing : str or None
        Why the term is missing (the non-negative fit set it to zero).
    """

    frequency: Term
    amplitude: Term
    tau_range: tuple[float, float] | None = None
    missing: str | None = None

    @classmethod
    def _from_core(
        cls,
        raw: Mapping[str, Any],
        index: int,
        rate_unit: str | None,
        held_uncertainty: float | None = None,
    ) -> SinusoidTerm:
        """The one place a :class:`SinusoidTerm` is built from the core's ``LineEstimate``
        (the ``index``-th line: symbol ``S``, ``S2``, …); ``held_uncertainty`` is the
        frequency's uncertainty when the fit held it (a detected line: the periodogram's)."""
        symbol = "S" if index == 0 else f"S{index + 1}"
        rng = (
            None
            if raw["tau_range"] is None
            else (float(raw["tau_range"][0]), float(raw["tau_range"][1]))
        )
        f_unc = float(raw["frequency_uncertainty"])
        if not np.isfinite(f_unc) and held_uncertainty is not None:
            f_unc = float(held_uncertainty)
        return cls(
            frequency=Term(
                symbol,
                "sinusoid frequency",
                float(raw["frequency"]),
                f_unc if np.isfinite(f_unc) else None,
                "Hz",
                rng,
                None,
                raw["missing"],
            ),
            amplitude=Term(
                symbol,
                "sinusoid amplitude",
                raw["amplitude"],
                raw["amplitude_uncertainty"],
                rate_unit,
                rng,
                None,
                raw["missing"],
            ),
            tau_range=rng,
            missing=raw["missing"],
        )

    @property
    def present(self) -> bool:
        """True when the term was identified."""
        return self.amplitude.value is not None

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dictionary."""
        return {
            "frequency": self.frequency.to_dict(),
            "amplitude": self.amplitude.to_dict(),
            "tau_range_s": None if self.tau_range is None else list(self.tau_range),
            "missing": self.missing,
        }

    def __str__(self) -> str:
        f = self.frequency.value
        if not self.present:
            return f"S (sinusoid at {f:.6g} Hz): missing — {self.missing}"
        a = self.amplitude
        unc = f" ± {a.uncertainty:.2g}" if a.uncertainty is not None else ""
        return f"S (sinusoid) at {f:.6g} Hz: amplitude {a.value:.4g}{unc} {a.unit or ''}".rstrip()


@dataclass(frozen=True)
class WaveletVariance:
    """Haar MODWT wavelet variance of one rate series with confidence intervals.

    Attributes
    ----------
    levels : ndarray of int
        Levels j = 1 … J.
    scales : ndarray
        Scales ``τ_j = 2^j/fs`` (s): the Haar filter width, as the R ``wv`` package labels them.
    variance : ndarray
        ``ν̂²_j`` in ``unit`` squared (classical: ``½·σ̂²_OAVAR(τ = 2^{j−1}/fs)`` exactly).
    ci_low, ci_high : ndarray
        Confidence limits of ``ν²_j`` at level ``confidence``.
    edf : ndarray
        Equivalent degrees of freedom of the intervals.
    n_coefficients : ndarray of int
        Wavelet coefficients ``M_j = n − 2^j + 1`` per level.
    robust : bool
        Robust (biweight M-) estimator instead of the mean of squares.
    efficiency : float or None
        Gaussian efficiency of the robust estimator.
    confidence : float
        Confidence level of the intervals.
    fs : float
        Sample rate (Hz).
    unit : str or None
        Rate unit of the data.
    axis : str or None
        Axis name.
    """

    levels: NDArray[np.int64] = field(compare=False)
    scales: NDArray[np.float64] = field(compare=False)
    variance: NDArray[np.float64] = field(compare=False)
    ci_low: NDArray[np.float64] = field(compare=False)
    ci_high: NDArray[np.float64] = field(compare=False)
    edf: NDArray[np.float64] = field(compare=False)
    n_coefficients: NDArray[np.int64] = field(compare=False)
    robust: bool
    efficiency: float | None
    confidence: float
    fs: float
    unit: str | None = None
    axis: str | None = None

    @property
    def allan_variance(self) -> NDArray[np.float64]:
        """The Allan-variance equivalent ``2ν̂²_j`` at ``τ = scales/2``."""
        return np.asarray(2.0 * self.variance, dtype=np.float64)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dictionary with units."""
        return {
            "estimator": "robust (biweight)" if self.robust else "classical",
            "efficiency": self.efficiency,
            "confidence": self.confidence,
            "fs_hz": self.fs,
            "unit": None if self.unit is None else f"({self.unit})^2",
            "axis": self.axis,
            "levels": [int(v) for v in self.levels],
            "scales_s": [float(v) for v in self.scales],
            "variance": [float(v) for v in self.variance],
            "ci_low": [float(v) for v in self.ci_low],
            "ci_high": [float(v) for v in self.ci_high],
            "edf": [float(v) for v in self.edf],
            "n_coefficients": [int(v) for v in self.n_coefficients],
        }

    def plot(self, ax: Any = None) -> Any:
        """Draw ν̂ (the wavelet deviation) against scale with its interval.

        Drawn by :func:`gyrobias.plotting.plot_wvar`; returns the matplotlib Axes.
        """
        return _generics.plot(self, ax)


def _filter_time(raw: tuple[float, float] | None) -> Term | None:
    """The filter correlation time of the core's diagnostics as a :class:`Term` in seconds."""
    if raw is None:
        return None
    return Term(
        "τc",
        "sensor filter correlation time",
        float(raw[0]),
        float(raw[1]),
        "s",
    )


@dataclass(frozen=True)
class FitDiagnostics:
    """Goodness of fit of an identification and what it left out.

    Attributes
    ----------
    chi2 : float
        Generalised chi-square ``zᵀR⁻¹z`` of the standardised log-ratio residuals ``z`` with the
        model correlation ``R`` of the Allan estimates (see :func:`fit`, Notes).
    dof : int
        Degrees of freedom (points used − fitted parameters).
    p_value : float
        Probability of a χ² at least this large if the model were right (NaN without degrees of
        freedom). Below 0.001 the fit is rejected and :attr:`warnings` says so.
    residuals : ndarray
        Standardised residual of each Allan point used in the fit (about N(0, 1) if the model
        holds). Points the fit did not use (outside ``tau_range``, without degrees of freedom)
        have no residual and are omitted, so the array holds no NaN.
    taus : ndarray
        τ (s) of each residual.
    tau_range : (float, float)
        τ range (s) of the points used.
    excluded : tuple of (float, float, str)
        Excluded τ ranges (s) with the reason. Excluded points in a spectral line's τ band
        (where its Allan-variance bump is above half its peak, ``0.182/f ≤ τ ≤ 0.581/f``; a
        line of the data, modelled or not) carry the line's reason, whatever rule dropped them.
    warnings : tuple of str
        Plain sentences about anything to know before trusting the numbers.
    lines : tuple of SpectralLine
        Spectral lines found in the data (frequency, amplitude, p-value) that the fit took into
        account as sinusoidal terms (see :func:`gyrobias.noise.detect_lines`).
    filter_correlation_time : Term or None
        The sensor filter's correlation time ``τ_c`` in seconds, with its standard uncertainty,
        when the automatic range selection saw an anti-alias/decimation filter at the shortest τ
        and the fit modelled what it leaves at the longer ones: a low-pass filter correlates
        the white rate noise, and for ``m`` beyond the filter's length the Allan variance is
        exactly ``N²/τ·(1 − 3τ_c/τ)`` with ``τ_c = t0·Σ_{k≥1} k·ρ(k)`` (``ρ`` the rate's
        normalised autocovariance), so it enters as a negative ``1/τ²`` term. ``None`` when no
        filter was seen (or quantisation outweighs it: then Q is reported).
    data_variance : float or None
        The variance of the data the curve came from (``AllanResult.data_variance``, the rate
        unit squared), which bounded the fit: ``None`` when it was not known (a curve without
        it, the IEEE read-off).
    variance_claimed : float or None
        The least sample variance the fitted terms imply, ``Σ q_j·a_j·c_j`` (each term's
        implied variance ``a_j·c_j`` — sinusoid ``A²/2``, rate ramp ``R²T²/12``, white noise
        ``N²/τ_lo``, rate random walk ``K²T/6``, … — times the lower 0.1 % quantile ``q_j`` of
        its own sample variance; see ``gyrocore::noise::variance_limit``). The fit keeps it
        ``≤ data_variance``; equal means the limit was active (:attr:`variance_limited`).
    """

    chi2: float
    dof: int
    p_value: float
    residuals: NDArray[np.float64] = field(repr=False, compare=False)
    taus: NDArray[np.float64] = field(repr=False, compare=False)
    tau_range: tuple[float, float]
    excluded: tuple[tuple[float, float, str], ...] = ()
    warnings: tuple[str, ...] = ()
    lines: tuple[SpectralLine, ...] = ()
    filter_correlation_time: Term | None = None
    data_variance: float | None = None
    variance_claimed: float | None = None

    @property
    def variance_limited(self) -> bool:
        """True when the fit's terms are as large as the data's variance allows: unconstrained,
        they would have implied more variance than the samples have (see ``variance_claimed``)."""
        if self.data_variance is None or self.variance_claimed is None:
            return False
        return self.variance_claimed >= self.data_variance * (1.0 - 1e-6)

    @property
    def passed(self) -> bool:
        """True unless the goodness-of-fit test rejects the model (p < 0.001)."""
        return not (self.p_value < REJECT_P)

    @classmethod
    def _from_core(cls, raw: Mapping[str, Any], taus: NDArray[np.float64]) -> FitDiagnostics:
        """The one place :class:`FitDiagnostics` are built from the core's ``Diagnostics``."""
        residuals = np.asarray(raw["residuals"], dtype=np.float64)
        used = np.isfinite(residuals)  # the core marks points the fit did not use with NaN
        return cls(
            chi2=float(raw["chi2"]),
            dof=int(raw["dof"]),
            p_value=float(raw["p_value"]),
            residuals=residuals[used].copy(),
            taus=np.asarray(taus, dtype=np.float64)[used].copy(),
            tau_range=(float(raw["tau_range"][0]), float(raw["tau_range"][1])),
            excluded=tuple((float(a), float(b), str(r)) for a, b, r in raw["excluded"]),
            warnings=tuple(str(w) for w in raw["warnings"]),
            filter_correlation_time=_filter_time(raw["filter_correlation_time"]),
            data_variance=_limit_part(raw.get("variance_limit"), 1),
            variance_claimed=_limit_part(raw.get("variance_limit"), 0),
        )

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dictionary (NaN residuals become ``None``)."""
        return {
            "chi2": self.chi2,
            "dof": self.dof,
            "p_value": None if not np.isfinite(self.p_value) else self.p_value,
            "passed": self.passed,
            "tau_range_s": list(self.tau_range),
            "residuals": [None if not np.isfinite(v) else float(v) for v in self.residuals],
            "taus_s": [float(t) for t in self.taus],
            "excluded": [
                {"tau_low_s": a, "tau_high_s": b, "reason": r} for a, b, r in self.excluded
            ],
            "warnings": list(self.warnings),
            "lines": [line.to_dict() for line in self.lines],
            "filter_correlation_time": (
                None
                if self.filter_correlation_time is None
                else self.filter_correlation_time.to_dict()
            ),
            "data_variance": self.data_variance,
            "variance_claimed": self.variance_claimed,
            "variance_limited": self.variance_limited,
        }

    def summary(self) -> str:
        """Plain-text lines: the test, the excluded ranges, the filter and the warnings."""
        verdict = "passed" if self.passed else "REJECTED"
        lines = [
            f"  goodness of fit: χ² = {self.chi2:.4g}, ν = {self.dof}, p = {self.p_value:.3g} ({verdict})"
        ]
        for a, b, r in self.excluded:
            lines.append(f"  excluded τ {_tau_span(a, b)} s: {r}")
        tc = self.filter_correlation_time
        if tc is not None and tc.value is not None:
            unc = f" ± {tc.uncertainty:.2g}" if tc.uncertainty is not None else ""
            lines.append(
                f"  sensor filter modelled at the τ used: −3N²τ_c/τ² with τ_c = {tc.value:.3g}{unc} s"
            )
        for line in self.lines:
            lines.append(f"  spectral {line}")
        for w in self.warnings:
            lines.append(f"  WARNING: {w}")
        return "\n".join(lines)

    def __str__(self) -> str:
        return self.summary()


def _limit_part(raw: Any, index: int) -> float | None:
    """Part ``index`` of the core's ``variance_limit`` ``(claimed, V)``, or ``None``."""
    return None if raw is None else float(raw[index])


def _tau_span(a: float, b: float) -> str:
    """``a–b`` to 3 significant digits, or one value when both print the same (a single τ)."""
    lo, hi = f"{a:.3g}", f"{b:.3g}"
    return lo if lo == hi else f"{lo}–{hi}"


#: A sinusoid's Allan variance ``A²/2·sin⁴(πfτ)/(πfτ)²`` (IEEE 952 C.1) is a bump that peaks at
#: ``fτ = 0.371`` and stays above half its peak for ``0.182 ≤ fτ ≤ 0.581``: a line's τ band.
_LINE_BAND = (0.1821198903, 0.5814472107)
_EDF_REASON = "fewer than 3 equivalent degrees of freedom"


def _line_reason(f: float) -> str:
    return (
        f"σ shaped by the spectral line at {f:.4g} Hz (its Allan-variance bump, above half its "
        f"peak for τ = {_LINE_BAND[0] / f:.3g}–{_LINE_BAND[1] / f:.3g} s)"
    )


def _line_exclusions(
    excluded: Sequence[tuple[float, float, str]],
    taus: NDArray[np.float64],
    frequencies: Iterable[float],
) -> tuple[tuple[float, float, str], ...]:
    """``excluded`` with the excluded τ points that lie in a spectral line's τ band (where its
    Allan-variance bump is above half its peak, :data:`_LINE_BAND`) moved under the line's
    reason: the automatic range selection sees a line's bump as a misfit at short τ (a filter's
    transition) or long τ (drift), but the cause is the line, modelled or not. Ranges of too
    few equivalent degrees of freedom keep their reason."""
    freqs = sorted({float(f) for f in frequencies if f is not None and np.isfinite(f) and f > 0})
    if not freqs or not excluded:
        return tuple(excluded)
    t = np.asarray(taus, dtype=np.float64)
    out: list[tuple[float, float, str]] = []
    moved: dict[float, list[float]] = {}
    for a, b, r in excluded:
        pts = t[(t >= a * (1 - 1e-9)) & (t <= b * (1 + 1e-9))]
        if r == _EDF_REASON or pts.size == 0:
            out.append((a, b, r))
            continue
        keep = np.ones(pts.size, dtype=bool)
        for f in freqs:
            band = keep & (pts >= _LINE_BAND[0] / f) & (pts <= _LINE_BAND[1] / f)
            if band.any():
                moved.setdefault(f, []).extend(pts[band].tolist())
                keep &= ~band
        if keep.all():
            out.append((a, b, r))
            continue
        # the rest keeps its reason, one range per run of consecutive points (a range must
        # not span the line's band)
        edges = np.flatnonzero(np.diff(np.concatenate(([0], keep.astype(np.int8), [0]))))
        for i, j in zip(edges[::2], edges[1::2]):
            out.append((float(pts[i]), float(pts[j - 1]), r))
    for f, p in moved.items():
        out.append((min(p), max(p), _line_reason(f)))
    return tuple(out)


def _line_bands(
    diagnostics: FitDiagnostics, taus: NDArray[np.float64], frequencies: Iterable[Any]
) -> FitDiagnostics:
    """The diagnostics with each spectral line's excluded τ points under the line's reason
    (:func:`_line_exclusions`)."""
    excluded = _line_exclusions(
        diagnostics.excluded, taus, [f for f in frequencies if f is not None]
    )
    return (
        diagnostics if excluded == diagnostics.excluded else replace(diagnostics, excluded=excluded)
    )


def _with_lines(
    diagnostics: FitDiagnostics,
    detected: Sequence[SpectralLine],
    method: str,
    sinusoids: Sequence[SinusoidTerm] = (),
) -> FitDiagnostics:
    """The diagnostics with the spectral lines the fit modelled and the sentence that says so
    (``sinusoids``: the fit's terms for them, to say when the fit found them all at zero)."""
    if not detected:
        return diagnostics
    found = "; ".join(
        f"{x.frequency:.4g} Hz (amplitude {x.amplitude:.3g}{' ' + x.unit if x.unit else ''}, "
        f"p = {x.p_value:.2g})"
        for x in detected
    )
    n = len(detected)
    plural = n > 1
    if sinusoids and all(w.missing is not None for w in sinusoids):
        # A weak line (e.g. 0.065 deg/s under 0.16 deg/s of white noise on a real 6.4 s NGIMU
        # log): significant in the spectrum, invisible in the Allan curve at the τ used.
        warning = (
            f"{n} spectral line{'s' if plural else ''} found in the rate data ({found}): "
            f"periodic disturbance{'s' if plural else ''} (vibration, a fan, an aliased mode), "
            f"too weak to show in the Allan curve at the τ used: the {method} fit's sinusoidal "
            f"term{'s are' if len(sinusoids) > 1 else ' is'} zero (see sinusoids), so "
            f"{'they do' if plural else 'it does'} not measurably bias N and Q"
        )
    else:
        warning = (
            f"{n} spectral line{'s' if plural else ''} found in the rate data ({found}): "
            f"periodic disturbance{'s' if plural else ''} (vibration, a fan, an aliased mode) "
            f"that would bias N and Q; the {method} fit models {'them' if plural else 'it'} "
            "with the IEEE-952 sinusoidal term 'S' (see sinusoids); pass lines=None to fit "
            "without"
        )
    return replace(diagnostics, lines=tuple(detected), warnings=(warning, *diagnostics.warnings))


@dataclass(frozen=True)
class NoiseCoefficients:
    """IEEE-952 noise coefficients identified from one Allan curve.

    Attributes
    ----------
    Q, N, B, K, R : Term
        Quantisation, angle (velocity) random walk, bias instability, rate (acceleration) random
        walk and rate ramp. Values in the base units of the data unless converted with
        :meth:`to`.
    method : {"joint", "ieee"}
        Identification method.
    data_unit : str or None
        Unit of the rate data (``"deg/s"``, ``"rad/s"``, ``"m/s^2"``, …).
    sensor : {"gyro", "accel"} or None
        Derived from ``data_unit``.
    fs : float
        Sample rate of the data in Hz.
    axis : str or None
        Axis name.
    tau_range : (float, float)
        τ range (s) of the Allan points the identification used.
    edf_source : str
        Where the weights' EDF came from: ``"noise identification"`` (the Allan result's EDF)
        or ``"SP1065 simple approximation"``.
    chi2, dof : float or None, int or None
        Weighted residual sum of squares and degrees of freedom of the joint fit.
    squared : tuple of float or None
        Fitted Q², N², B², K², R² in base units (joint fit), used to draw the model.
    gauss_markov : tuple of GaussMarkovTerm
        First-order Gauss–Markov terms (``terms`` containing ``"GM"``/``"GM2"``), sorted by
        correlation time.
    sinusoids : tuple of SinusoidTerm
        Sinusoidal terms ("S", IEEE 952), one per spectral line the fit modelled.
    diagnostics : FitDiagnostics or None
        Goodness of fit, excluded τ ranges and warnings (always set by :func:`fit` and
        :func:`gmwm`; ``None`` only for coefficients that did not come from data).
    allan : AllanResult or None
        The curve the coefficients came from (for plotting).
    """

    Q: Term
    N: Term
    B: Term
    K: Term
    R: Term
    method: str
    data_unit: str | None
    sensor: str | None
    fs: float
    tau_range: tuple[float, float]
    edf_source: str
    axis: str | None = None
    chi2: float | None = None
    dof: int | None = None
    squared: tuple[float, float, float, float, float] | None = None
    gauss_markov: tuple[GaussMarkovTerm, ...] = ()
    diagnostics: FitDiagnostics | None = None
    allan: AllanResult | None = field(default=None, repr=False, compare=False)
    sinusoids: tuple[SinusoidTerm, ...] = ()

    @classmethod
    def _from_core(
        cls,
        raw: Mapping[str, Any],
        diagnostics: Mapping[str, Any],
        taus: NDArray[np.float64],
        *,
        method: str,
        data_unit: str | None,
        sensor: str | None,
        fs: float,
        axis: str | None,
        edf_source: str,
        allan: AllanResult | None,
        detected: Sequence[SpectralLine] = (),
        line_uncertainties: Sequence[float | None] = (),
    ) -> NoiseCoefficients:
        """The one place :class:`NoiseCoefficients` are built from the core's output.

        ``raw`` is the binding's ``JointFit`` or ``Gmwm`` (terms, Gauss–Markov components,
        χ², fitted squares, τ range) or ``ReadOff`` (terms only: the τ range is then the
        curve's, ``taus[0]``…``taus[-1]``); ``diagnostics`` the matching ``Diagnostics``;
        ``detected`` the spectral lines the fit modelled as sinusoidal terms (reported in the
        diagnostics with a warning that says so); ``line_uncertainties`` per sinusoid the
        uncertainty of a frequency the fit held (the periodogram's, for a detected line).
        """
        names = TERM_NAMES[sensor or "gyro"]
        built = {
            d["symbol"]: Term._from_core(
                d,
                names[d["symbol"]],
                None if data_unit is None else base_unit(data_unit, d["symbol"]),
            )
            for d in raw["terms"]
        }
        rate_unit = None if data_unit is None else base_unit(data_unit, "B")
        joint = "chi2" in raw
        given = list(line_uncertainties)
        sinusoids = tuple(
            SinusoidTerm._from_core(d, k, rate_unit, given[k] if k < len(given) else None)
            for k, d in enumerate(raw.get("lines", ()))
        )
        return cls(
            Q=built["Q"],
            N=built["N"],
            B=built["B"],
            K=built["K"],
            R=built["R"],
            method=method,
            data_unit=data_unit,
            sensor=sensor,
            fs=fs,
            axis=axis,
            edf_source=edf_source,
            allan=allan,
            tau_range=tuple(raw["tau_range"]) if joint else (float(taus[0]), float(taus[-1])),
            chi2=float(raw["chi2"]) if joint else None,
            dof=int(raw["dof"]) if joint else None,
            squared=tuple(float(v) for v in raw["squared"]) if joint else None,  # type: ignore[arg-type]
            gauss_markov=tuple(
                GaussMarkovTerm._from_core(g, k, rate_unit)
                for k, g in enumerate(raw.get("gauss_markov", ()))
            ),
            diagnostics=_with_lines(
                _line_bands(
                    FitDiagnostics._from_core(diagnostics, taus),
                    taus,
                    [w.frequency.value for w in sinusoids]
                    + [x.frequency for x in (detected or getattr(allan, "lines", None) or ())],
                ),
                detected,
                method,
                sinusoids,
            ),
            sinusoids=sinusoids,
        )

    @property
    def terms(self) -> tuple[Term, Term, Term, Term, Term]:
        """(Q, N, B, K, R)."""
        return (self.Q, self.N, self.B, self.K, self.R)

    def __getitem__(self, symbol: str) -> Term:
        return {"Q": self.Q, "N": self.N, "B": self.B, "K": self.K, "R": self.R}[
            choice("symbol", symbol, _SYMBOLS)
        ]

    @property
    def quantization(self) -> Term:
        """Q."""
        return self.Q

    @property
    def arw(self) -> Term:
        """N (angle random walk; VRW for an accelerometer)."""
        return self.N

    @property
    def bias_instability(self) -> Term:
        """B."""
        return self.B

    @property
    def rrw(self) -> Term:
        """K (rate random walk)."""
        return self.K

    @property
    def rate_ramp(self) -> Term:
        """R."""
        return self.R

    def to(self, system: str | Mapping[str, str] = "ieee") -> NoiseCoefficients:
        """Coefficients converted to customary units.

        Parameters
        ----------
        system : {"ieee", "si", "kalibr", "base"} or mapping
            ``"ieee"``: gyro Q deg, N deg/√h, B deg/h, K deg/h^1.5, R deg/h²; accelerometer
            Q m/s, N m/s/√h, B mg, K m/s/h^1.5, R m/s/h². ``"si"`` (= ``"kalibr"``): gyro rad,
            rad/s/√Hz, rad/s, rad/s²/√Hz, rad/s²; accelerometer m/s, m/s²/√Hz, m/s², m/s³/√Hz,
            m/s³. ``"base"``: the data's base units. A mapping such as
            ``{"N": "deg/√h", "B": "deg/h"}`` converts only the terms it names.

        Raises
        ------
        ValueError
            Unknown system or unit string (listing the valid ones), unknown data unit.
        """
        if isinstance(system, str):
            choice("system", system, ("ieee", "si", "kalibr", "base"))
            if self.data_unit is None or self.sensor is None:
                raise ValueError(
                    "the data unit is unknown: pass units= to the Allan analysis (e.g. 'deg/s') "
                    "or unit= to gyrobias.noise.fit"
                )
            if system == "base":
                mapping = {s: base_unit(self.data_unit, s) for s in _SYMBOLS}
            else:
                mapping = CUSTOMARY[self.sensor][system]
        else:
            if not isinstance(system, Mapping):
                raise TypeError(
                    "system must be 'ieee', 'si', 'kalibr', 'base' or a mapping symbol → unit, "
                    f"got {type(system).__name__}"
                )
            mapping = dict(system)
            for key in mapping:
                choice("system key", key, _SYMBOLS)
        conv = {s: self[s].to(mapping[s]) if s in mapping else self[s] for s in _SYMBOLS}
        gm = self.gauss_markov
        sines = self.sinusoids
        if "B" in mapping:  # σ of a Gauss–Markov term and Ω₀ have the dimension of B (a rate)
            gm = tuple(
                replace(g, sigma=g.sigma.to(mapping["B"])) if g.sigma.unit is not None else g
                for g in gm
            )
            sines = tuple(
                replace(w, amplitude=w.amplitude.to(mapping["B"]))
                if w.amplitude.unit is not None
                else w
                for w in sines
            )
        return replace(
            self,
            Q=conv["Q"],
            N=conv["N"],
            B=conv["B"],
            K=conv["K"],
            R=conv["R"],
            gauss_markov=gm,
            sinusoids=sines,
        )

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dictionary with units and conventions stated."""
        return {
            "method": self.method,
            "axis": self.axis,
            "sensor": self.sensor,
            "data_unit": self.data_unit,
            "fs_hz": self.fs,
            "tau_range_s": list(self.tau_range),
            "edf_source": self.edf_source,
            "chi2": self.chi2,
            "dof": self.dof,
            "model": "sigma^2(tau) = 3Q^2/tau^2 + N^2/tau + (0.664282 B)^2 + K^2 tau/3 + R^2 tau^2/2"
            " + sum_k sigma_k^2 T_k^2/tau^2 (2 tau/T_k - 3 + 4 exp(-tau/T_k) - exp(-2 tau/T_k))",
            "psd_convention": "two-sided (IEEE 952): white rate noise of per-sample std s at period t0 has N = s*sqrt(t0)",
            "uncertainty": "standard (1 sigma)",
            "terms": {t.symbol: t.to_dict() for t in self.terms},
            "gauss_markov": [g.to_dict() for g in self.gauss_markov],
            "sinusoids": [w.to_dict() for w in self.sinusoids],
            "diagnostics": None if self.diagnostics is None else self.diagnostics.to_dict(),
        }

    def to_json(self, path: str | os.PathLike[str] | None = None, **kwargs: Any) -> str:
        """:meth:`to_dict` as JSON; also written to ``path`` when given."""
        if path is not None:
            path = _files.checked_path("path", path)
        kwargs.setdefault("indent", 2)
        text = json.dumps(self.to_dict(), **kwargs)
        if path is not None:
            _files.atomic_write(path, text + "\n")
        return text

    def summary(self) -> str:
        """A plain-text table of the coefficients with uncertainties, units and τ ranges."""
        sensor = self.sensor or "sensor"
        axis = f" axis {self.axis}" if self.axis else ""
        lines = [
            f"Noise coefficients{axis} ({sensor}, {self.method} identification, "
            f"τ {self.tau_range[0]:.3g}–{self.tau_range[1]:.3g} s, EDF: {self.edf_source})"
        ]
        names = TERM_NAMES.get(self.sensor or "gyro", TERM_NAMES["gyro"])
        for t in self.terms:
            label = f"  {t.symbol}  {names[t.symbol]:<27}"
            if t.value is None and t.upper_bound is not None:
                lines.append(
                    f"{label} ≤ {t.upper_bound:10.5g}   {'':<8} {t.unit or '':<12}  "
                    f"({_percent(t.bound_confidence)} upper bound: not visible above the others)"
                )
                continue
            if t.value is None:
                lines.append(f"{label} missing: {t.missing}")
                continue
            unc = f"{t.uncertainty:.2g}" if t.uncertainty is not None else "?"
            rng = f"  (τ {_tau_span(*t.tau_range)} s)" if t.tau_range else ""
            if t.uncertainty is not None and t.value < 2.0 * t.uncertainty:
                rng += "  not significant (< 2σ)"
            lines.append(f"{label} {t.value:12.5g} ± {unc:<8} {t.unit or '':<12}{rng}")
        for g in self.gauss_markov:
            label = f"  {g.sigma.symbol:<3}{'Gauss–Markov σ, T':<26}"
            if not g.present:
                lines.append(f"{label} missing: {g.missing}")
                continue
            t = g.correlation_time
            lines.append(
                f"{label} {g.sigma.value:12.5g} ± {g.sigma.uncertainty or float('nan'):<8.2g} "
                f"{g.sigma.unit or '':<12}  T = {t.value:.4g} ± {t.uncertainty or float('nan'):.2g} s"
            )
        for w in self.sinusoids:
            lines.append(f"  {w}")
        if self.diagnostics is not None:
            lines.append(self.diagnostics.summary())
        return "\n".join(lines)

    def __str__(self) -> str:
        return self.summary()

    def to_kalibr(
        self,
        path: str | os.PathLike[str],
        *,
        update_rate: float | None = None,
        rostopic: str = "/imu0",
    ) -> str:
        """Write a Kalibr ``imu.yaml`` with this axis' coefficients (see :func:`write_kalibr`)."""
        return _generics.to_kalibr(self, path, update_rate=update_rate, rostopic=rostopic)

    # Estimator parameters (issue 13): thin delegations to gyrobias.conservative/exports.
    def conservative(
        self, confidence: float = 0.95, *, terms: Iterable[str] | None = None
    ) -> ConservativeCoefficients:
        """Coefficients whose model overbounds the curve's upper confidence bound at every τ.

        See :func:`gyrobias.conservative.conservative` (Lethander & Taylor 2023).
        """
        return _generics.conservative(self, confidence, terms=terms)  # type: ignore[no-any-return]

    def export(
        self,
        fmt: str,
        path: str | os.PathLike[str] | None = None,
        *,
        accel: NoiseCoefficients | Sequence[NoiseCoefficients] | None = None,
        rate: float | None = None,
        rostopic: str = "/imu0",
    ) -> str:
        """Write an estimator parameter file (kalibr, openvins, vins, orbslam3, liosam, matlab, json).

        See :func:`gyrobias.exports.export`.
        """
        return _generics.export(self, fmt, path, accel=accel, rate=rate, rostopic=rostopic)

    def discrete(self, rate: float) -> DiscreteNoise:
        """Per-sample noise parameters at ``rate`` Hz (see :func:`gyrobias.exports.discrete`)."""
        return _generics.discrete(self, rate)  # type: ignore[no-any-return]

    def model(self, taus: Any) -> tuple[NDArray[np.float64], dict[str, NDArray[np.float64]]]:
        """Model Allan deviation at ``taus`` and each term's asymptote (data units).

        For the read-off, the model is built from the identified coefficients (missing terms
        count as zero). When the fit modelled a sensor filter
        (:attr:`FitDiagnostics.filter_correlation_time`), the total includes its
        ``−3N²τ_c/τ²`` (it has no asymptote of its own in ``parts``); below τ = 3τ_c, inside
        the filter's length where that law has no meaning, the total is NaN, so a plotted
        model line stops where the model stops being valid (matplotlib and Bokeh leave a gap
        at NaN) instead of plunging towards zero.
        """
        # τ finite and > 0 (the curves have no value at τ ≤ 0): the core's check
        t = as_float_array("taus", np.atleast_1d(asarray("taus", taus)), ndims=(1,))
        squared = self._squared_base()
        tc = None if self.diagnostics is None else self.diagnostics.filter_correlation_time
        filter_time = 0.0 if tc is None or tc.value is None else float(tc.value)
        total, parts = _core.noise.model(squared, t, filter_time)
        out = {s: np.sqrt(p) for s, p in zip(_SYMBOLS, parts)}
        gm = self._gauss_markov_base()
        if gm:
            for g, v in zip(self.gauss_markov, _core.noise.gauss_markov_variance(gm, t)):
                total = total + v
                out[g.sigma.symbol] = np.sqrt(v)
        base = self.to("base") if self.data_unit is not None else self
        for k, w in enumerate(base.sinusoids):
            if w.amplitude.value is None or w.frequency.value is None:
                continue
            v = _core.noise.sinusoid_avar(
                float(w.amplitude.value), float(w.frequency.value), t, 1.0 / self.fs
            )
            total = total + v
            out["S" if k == 0 else f"S{k + 1}"] = np.sqrt(v)
        return np.sqrt(total), out

    def _gauss_markov_base(self) -> list[tuple[float, float]]:
        base = self.to("base") if self.data_unit is not None else self
        return [
            (float(g.sigma.value) ** 2, float(g.correlation_time.value))
            for g in base.gauss_markov
            if g.sigma.value is not None and g.correlation_time.value is not None
        ]

    def _squared_base(self) -> list[float]:
        if self.squared is not None:
            return list(self.squared)
        base = self.to("base") if self.data_unit is not None else self
        return [0.0 if t.value is None else float(t.value) ** 2 for t in base.terms]

    def plot(
        self, ax: Any = None, *, allan: AllanResult | None = None, show_data: bool = True
    ) -> Any:
        """Draw the fitted model, each term's asymptote and the labelled read-off points.

        Parameters
        ----------
        ax : matplotlib Axes, optional
            Axes to draw on (a new figure otherwise).
        allan : AllanResult, optional
            The Allan curve to draw beneath (defaults to the one the coefficients came from).
        show_data : bool
            Draw the Allan deviation points (set False when the caller has drawn them).

        Returns
        -------
        matplotlib Axes
            Drawn by :func:`gyrobias.plotting.plot_noise_model`.
        """
        return _generics.plot(self, ax, allan=allan, show_data=show_data)
