"""The Allan-family result types: :class:`AllanResult` and :class:`DynamicAllanResult`.

Value types only: this module imports no algorithm and no plotting module. ``.plot()`` is a
one-line delegation to the generic :func:`gyrobias._generics.plot`, whose methods for these
types are registered by :mod:`gyrobias.plotting`.
"""

from __future__ import annotations

import json
import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field, replace
from typing import Any, Literal, overload

import numpy as np
from numpy.typing import NDArray

from gyrobias import _generics
from gyrobias._spectral_lines import SpectralLine

__all__ = [
    "KINDS",
    "NOISE_NAMES",
    "AllanResult",
    "Disturbance",
    "DynamicAllanResult",
    "Kind",
    "Stationarity",
]

#: Power-law exponent α of the rate PSD (S(f) ∝ f^α) → gyro noise name (IEEE 952 terms).
NOISE_NAMES: dict[int, str] = {
    2: "white angle (quantisation)",
    1: "flicker angle",
    0: "white rate (angle random walk)",
    -1: "flicker rate (bias instability)",
    -2: "rate random walk",
    -3: "flicker walk (rate ramp region)",
    -4: "random run (rate ramp)",
}

Kind = Literal["adev", "mdev", "hdev", "totdev"]
#: Every ``AllanResult.kind``.
KINDS = ("adev", "mdev", "hdev", "totdev", "tdev", "mtotdev", "htotdev", "theo1", "theobr", "theoh")
_ESTIMATOR_OF_KIND = {"mdev": "modified", "hdev": "hadamard", "totdev": "total"}


_LONG_LABEL = {
    "tdev": "TDEV (time deviation)",
    "mtotdev": "MTOTDEV (modified total deviation)",
    "htotdev": "HTOTDEV (Hadamard total deviation)",
    "theo1": "THEO1 (Théo1 deviation)",
    "theobr": "THEOBR (bias-removed Théo1 deviation)",
    "theoh": "THEOH (hybrid ADEV / ThéoBR deviation)",
}


def _statistic_unit(units: str | None, kind: str, data_type: str) -> str | None:
    """Unit of the statistic from the data unit: the rate unit (``deg`` angle → ``deg/s``), or
    for TDEV the angle unit (``deg/s`` rate → ``deg``)."""
    if units is None:
        return None
    if kind == "tdev":
        if data_type == "angle":
            return units
        return units[:-2] if units.endswith("/s") else f"{units}·s"
    return f"{units}/s" if data_type == "angle" else units


def _rate_unit_of(unit: str | None, kind: str) -> str | None:
    """The rate unit of a result whose statistic is in ``unit`` (TDEV's is an angle unit)."""
    if unit is None or kind != "tdev":
        return unit
    return f"{unit}/s"


def _variance_unit(unit: str | None) -> str | None:
    """``unit`` squared, as the results spell it (``(deg/s)²``)."""
    if unit is None:
        return None
    return f"({unit})²" if "/" in unit or "·" in unit else f"{unit}²"


def _label(kind: str, overlapping: bool) -> str:
    if kind == "hdev":
        return (
            "OHDEV (overlapping Hadamard)"
            if overlapping
            else "HDEV (non-overlapping Hadamard, Stable32's HDEV)"
        )
    return _LONG_LABEL.get(kind, kind.upper())


def _short_label(kind: str, overlapping: bool) -> str:
    if kind == "hdev":
        return "OHDEV" if overlapping else "HDEV(non-overlap)"
    return _label(kind, overlapping).split(" (")[0]


#: The spectral lines of a result, or how to find them on first use.
LinesValue = tuple[SpectralLine, ...] | None | Callable[[], tuple[SpectralLine, ...] | None]


class _LazyLines:
    """Data descriptor behind :attr:`AllanResult.lines`: holds the lines, or a search to run on
    first access (then remembered). The line search costs more than the Allan kernel itself
    (about 10× on 10⁶ samples), and most results never need it: only the fit's
    ``lines="auto"``, the report and the user who asks."""

    _slot = "_lines"

    @overload
    def __get__(self, obj: None, objtype: type | None = None) -> None: ...
    @overload
    def __get__(
        self, obj: object, objtype: type | None = None
    ) -> tuple[SpectralLine, ...] | None: ...
    def __get__(
        self, obj: object | None, objtype: type | None = None
    ) -> tuple[SpectralLine, ...] | None:
        if obj is None:
            return None  # the dataclass default
        value = obj.__dict__.get(self._slot)
        if callable(value):
            value = value()
            obj.__dict__[self._slot] = value
        return value

    def __set__(self, obj: object, value: LinesValue) -> None:
        obj.__dict__[self._slot] = value


@dataclass(frozen=True)
class AllanResult:
    """One axis of an Allan-family analysis.

    Attributes
    ----------
    taus : ndarray
        Averaging times τ in seconds.
    avar : ndarray
        Variance estimates σ²(τ) in units of ``unit`` squared (``inf`` or 0 where σ² is beyond float64, for
        data of extreme magnitude: ``adev`` stays exact there).
    adev : ndarray
        Deviations σ(τ) in ``unit`` (for ``kind="mdev"`` etc. the respective deviation).
    deviation : ndarray or None
        The deviations as computed by the core (what ``adev`` returns); ``None`` for results
        built from variances alone (``adev`` is then ``√avar``).
    n_terms : ndarray
        Number of terms in each estimator sum.
    ci_low, ci_high : ndarray or None
        Confidence bounds of the *deviation* at level ``confidence`` (chi-square with ``edf``).
    edf : ndarray or None
        Equivalent degrees of freedom per τ.
    alpha : ndarray or None
        Identified power-law exponent of the rate PSD per τ (S ∝ f^α).
    noise_type : tuple of str
        Gyro name of the identified noise per τ (see :data:`NOISE_NAMES`); empty without CIs.
    fs : float
        Sample rate of the input in Hz.
    unit : str or None
        Unit of the deviation (the rate unit, e.g. ``"deg/s"``); ``None`` if not given.
    data_type : {"rate", "angle"}
        What the input samples were.
    kind : {"adev", "mdev", "hdev", "totdev"}
        Which deviation this is.
    overlapping : bool
        Overlapping estimator (``False`` only for the non-overlapping ADEV of [BP] eq. 2).
    confidence : float or None
        Confidence level of ``ci_low``/``ci_high``.
    axis : str or None
        Axis name (column name), if known.
    lines : tuple of SpectralLine or None
        Spectral lines (periodic disturbances) found in the rate data at false-alarm level 0.01
        (:func:`gyrobias.noise.detect_lines`); :func:`gyrobias.noise.fit` models them with the
        sinusoidal term "S" by default. ``None`` when the data were not searched (angle input,
        other deviations, files read in pieces, too few samples). The search runs on first
        access (it costs more than the Allan variance itself), on the central eighth of logs
        over 2¹⁵ samples (at least 2¹⁵, at most 2¹⁸ samples: 44 min at 100 Hz): a line strong
        enough to bias the Allan fit is far above that segment's detection threshold
        (``gyrobias.allan.classic.line_search_length``).
    stationarity : Stationarity or None
        Whether the rate log is static: steps, motion segments and warm-up trends beyond the
        log's own noise, where they are and how to select around them (:class:`Stationarity`).
        Checked on first access from about 4096 block means the Allan kernel reads off its
        angle series (no extra pass over the data); ``None`` for results of the gap-aware or
        out-of-core kernels and the GMWM's wavelet variance. :func:`gyrobias.noise.fit` adds
        its warnings to the fit's diagnostics.
    data_variance : float or None
        The variance of the data analysed, ``Σ(Ω − Ω̄)²/n`` (NumPy's ``var``) in the rate unit
        squared (``unit`` squared; for ``kind="tdev"`` the rate unit's square, not TDEV's): of
        the rate samples, or for angle input of the rate differences ``(x[i+1] − x[i])·fs``;
        with gaps, over the samples present. Computed by the Allan kernel in the pass that
        builds the angle series (no extra pass over the data). :func:`gyrobias.noise.fit` uses
        it to keep every estimated term within what the data's variance allows. ``None`` where
        it is not known (a result built from stored deviations, the GMWM's wavelet variance,
        fewer than two samples); ``inf`` or 0 where it is beyond float64 (extreme data, like
        ``avar``).
    data_deviation : float or None
        ``√data_variance``, computed before the data's scale was restored: finite for data of
        extreme magnitude whose variance over- or underflows float64 (as ``deviation`` next to
        ``avar``).
    """

    taus: NDArray[np.float64]
    avar: NDArray[np.float64]
    n_terms: NDArray[np.int64]
    fs: float
    data_type: str
    kind: str
    overlapping: bool
    unit: str | None = None
    confidence: float | None = None
    edf: NDArray[np.float64] | None = None
    alpha: NDArray[np.int64] | None = None
    ci_low: NDArray[np.float64] | None = None
    ci_high: NDArray[np.float64] | None = None
    axis: str | None = None
    noise_type: tuple[str, ...] = field(default=())
    factors: NDArray[np.int64] | None = None
    deviation: NDArray[np.float64] | None = None
    lines: tuple[SpectralLine, ...] | None = field(default=None, repr=False, compare=False)
    stationarity: Stationarity | None = field(default=None, repr=False, compare=False)
    data_variance: float | None = None
    data_deviation: float | None = None

    @classmethod
    def _from_core(
        cls,
        raw: Mapping[str, Any],
        *,
        kind: str,
        fs: float,
        data_type: str,
        overlapping: bool,
        confidence: float | None,
        units: str | None,
        axis: str | None,
    ) -> AllanResult:
        """The one place an :class:`AllanResult` is built from the core's output for one axis.

        ``raw`` is one of the binding's dictionaries (``gyrobias._core.allan``/``noise`` stubs):
        ``Analysis`` (:func:`~gyrobias._core.allan.analyse`, ``analyse_batch``,
        ``analyse_stream``: τ = m·t0), ``FamilyAnalysis`` (``family_analyse``: τ = tau_factor·t0,
        the averaging factors kept for Théo1's τ = 0.75·m·t0) or ``WaveletVariance`` (GMWM's
        Haar wavelet variance ν², shown as the Allan variance σ² = 2ν², Percival & Guttorp
        1994). ``units`` is the data unit; the statistic's unit is derived from it.
        """
        t0 = 1.0 / fs
        kw: dict[str, Any] = {}
        if confidence is not None:
            alpha = np.asarray(raw["alpha"]).astype(np.int64)
            kw = {
                "edf": np.asarray(raw["edf"], dtype=np.float64),
                "alpha": alpha,
                "ci_low": np.asarray(raw["deviation_low"], dtype=np.float64),
                "ci_high": np.asarray(raw["deviation_high"], dtype=np.float64),
                "noise_type": tuple(NOISE_NAMES.get(int(a), f"alpha={a}") for a in alpha),
            }
        m = np.asarray(raw["m"]).astype(np.int64)
        if "n_coefficients" in raw:  # GMWM's wavelet variance
            return cls(
                taus=np.asarray(m * t0, dtype=np.float64),
                avar=2.0 * np.asarray(raw["variance"], dtype=np.float64),
                n_terms=np.asarray(raw["n_coefficients"]).astype(np.int64),
                fs=fs,
                data_type=data_type,
                kind=kind,
                overlapping=overlapping,
                unit=_statistic_unit(units, kind, data_type),
                axis=axis,
            )
        family = "tau_factor" in raw
        return cls(
            taus=(
                np.asarray(raw["tau_factor"], dtype=np.float64) * t0
                if family
                else np.asarray(m * t0, dtype=np.float64)
            ),
            avar=np.asarray(raw["variance"], dtype=np.float64),
            deviation=np.asarray(raw["deviation"], dtype=np.float64),
            n_terms=np.asarray(raw["n_terms"]).astype(np.int64),
            fs=fs,
            data_type=data_type,
            kind=kind,
            overlapping=overlapping,
            unit=_statistic_unit(units, kind, data_type),
            confidence=confidence,
            axis=axis,
            factors=m if family else None,
            stationarity=_Blocks._from_core(raw),  # type: ignore[arg-type]  # checked lazily
            data_variance=float(raw["data_variance"]) if "data_variance" in raw else None,
            data_deviation=float(raw["data_deviation"]) if "data_deviation" in raw else None,
            **kw,
        )

    @property
    def adev(self) -> NDArray[np.float64]:
        """Deviation σ(τ) = √σ²(τ) in ``unit``.

        Taken from ``deviation`` when the core gave it: computed before the data's scale was
        restored, it stays finite for data of extreme magnitude whose variance over- or
        underflows float64 (and equals ``√avar`` bit for bit otherwise).
        """
        if self.deviation is not None:
            return self.deviation
        return np.sqrt(self.avar)

    @property
    def m(self) -> NDArray[np.int64]:
        """Averaging factors: m = τ·fs, except Théo1/ThéoBR points (τ = 0.75·m/fs, m even)."""
        if self.factors is not None:
            return self.factors
        return np.rint(self.taus * self.fs).astype(np.int64)

    @property
    def label(self) -> str:
        """Unambiguous name of the statistic, e.g. ``"OHDEV (overlapping Hadamard)"``."""
        return _label(self.kind, self.overlapping)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dictionary (arrays as lists, units stated)."""
        out: dict[str, Any] = {
            "kind": self.kind,
            "axis": self.axis,
            "fs_hz": self.fs,
            "data_type": self.data_type,
            "overlapping": self.overlapping,
            "unit": self.unit,
            "tau_unit": "s",
            "confidence": self.confidence,
            "taus": self.taus.tolist(),
            "deviation": self.adev.tolist(),
            "variance": self.avar.tolist(),
            "n_terms": self.n_terms.tolist(),
            "data_variance": self.data_variance,
            "data_deviation": self.data_deviation,
            "data_variance_unit": _variance_unit(_rate_unit_of(self.unit, self.kind)),
        }
        if self.edf is not None:
            assert self.ci_low is not None and self.ci_high is not None and self.alpha is not None
            out["edf"] = self.edf.tolist()
            out["ci_low"] = self.ci_low.tolist()
            out["ci_high"] = self.ci_high.tolist()
            out["alpha"] = self.alpha.tolist()
            out["noise_type"] = list(self.noise_type)
        return out

    def in_log_time(self, offset_s: float) -> AllanResult:
        """The same result with its times in the log as read, for data selected from a log.

        The stationarity check (:attr:`stationarity`) counts time from the first sample of the
        data analysed; for ``log.select(start=...)`` that is ``offset_s`` =
        ``log.selection.start_s`` seconds into the log as read, where its advice
        (``--start``/``--stop``, ``select(...)``) must point. ``gyrobias allan --start`` and the
        explorer place their results this way. Returns a shallow copy; ``self`` is unchanged.

        >>> import numpy as np
        >>> from gyrobias import allan
        >>> r = allan.adev(np.random.default_rng(0).normal(size=40_000), 100.0)
        >>> r.in_log_time(60.0).stationarity.total_s - r.stationarity.total_s
        60.0
        """
        import copy

        offset_s = _offset(offset_s)
        out = copy.copy(self)
        check = self.stationarity
        if check is not None and offset_s:
            object.__setattr__(out, "stationarity", check.shifted(offset_s))
        return out

    def to_json(self, **kwargs: Any) -> str:
        """:meth:`to_dict` as a JSON string."""
        return json.dumps(self.to_dict(), **kwargs)

    def table(self) -> str:
        """A plain-text table: τ, deviation, confidence interval, EDF, noise type."""
        unit = f" [{self.unit}]" if self.unit else ""
        head = f"{'tau [s]':>12} {_short_label(self.kind, self.overlapping) + unit:>22}"
        if self.ci_low is not None:
            head += f" {'CI low':>12} {'CI high':>12} {'edf':>9}  noise"
        lines = [head]
        for i, tau in enumerate(self.taus):
            row = f"{tau:12.6g} {self.adev[i]:22.6e}"
            if self.ci_low is not None and self.ci_high is not None and self.edf is not None:
                row += (
                    f" {self.ci_low[i]:12.4e} {self.ci_high[i]:12.4e} {self.edf[i]:9.1f}"
                    f"  {self.noise_type[i]}"
                )
            lines.append(row)
        return "\n".join(lines)

    def __str__(self) -> str:
        name = f" axis {self.axis}" if self.axis else ""
        return f"{self.label}{name} (fs = {self.fs:g} Hz, {self.data_type} data)\n{self.table()}"

    def plot(
        self, ax: Any = None, *, label: str | None = None, fit: Any = None, **kwargs: Any
    ) -> Any:
        """Log-log plot of the deviation with confidence bars (needs ``matplotlib``).

        Parameters
        ----------
        ax : matplotlib Axes, optional
            Where to draw (a new figure otherwise).
        label : str, optional
            Legend entry.
        fit : NoiseCoefficients or True, optional
            Overlay a fitted noise model (model curve, per-term asymptotes and the labelled
            read-off points); ``True`` fits one now with :func:`gyrobias.noise.fit`.
        **kwargs
            Passed to :func:`gyrobias.plotting.plot_allan`.

        Returns the matplotlib ``Axes``.
        """
        return _generics.plot(self, ax, label=label, fit=fit, **kwargs)


# After the dataclass is built: its __init__ keeps the default None, and every assignment
# (construction, dataclasses.replace) goes through the descriptor, which may hold a search.
AllanResult.lines = _LazyLines()  # type: ignore[assignment]


@dataclass(frozen=True)
class DynamicAllanResult:
    """A dynamic (time-resolved) Allan deviation: one overlapping ADEV curve per window.

    Attributes
    ----------
    times : ndarray, shape (windows,)
        Centre of each window in seconds from the first sample.
    starts : ndarray, shape (windows,)
        Index of each window's first sample.
    taus : ndarray, shape (n_tau,)
        Averaging times τ in seconds (common to all windows).
    avar : ndarray, shape (windows, n_tau)
        Overlapping Allan variance of each window in units of ``unit`` squared.
    n_terms : ndarray, shape (n_tau,)
        Terms of each window's sum.
    window, step : int
        Window length and window step in samples.
    fs : float
        Sample rate in Hz.
    unit : str or None
        Unit of the deviation (the rate unit).
    data_type : {"rate", "angle"}
        What the input samples were.
    """

    times: NDArray[np.float64]
    starts: NDArray[np.int64]
    taus: NDArray[np.float64]
    avar: NDArray[np.float64]
    n_terms: NDArray[np.int64]
    window: int
    step: int
    fs: float
    data_type: str
    unit: str | None = None

    @classmethod
    def _from_core(
        cls,
        raw: Mapping[str, Any],
        *,
        fs: float,
        window: int,
        step: int,
        data_type: str,
        units: str | None,
    ) -> DynamicAllanResult:
        """The one place a :class:`DynamicAllanResult` is built from the core's ``DynamicAvar``
        (:func:`gyrobias._core.allan.dynamic_avar`); ``units`` is the data unit."""
        t0 = 1.0 / fs
        starts = np.asarray(raw["starts"]).astype(np.int64)
        return cls(
            times=np.asarray((starts + window / 2.0) * t0, dtype=np.float64),
            starts=starts,
            taus=np.asarray(raw["m"]).astype(np.float64) * t0,
            avar=np.asarray(raw["variance"], dtype=np.float64),
            n_terms=np.asarray(raw["n_terms"]).astype(np.int64),
            window=window,
            step=step,
            fs=fs,
            data_type=data_type,
            unit=_statistic_unit(units, "adev", data_type),
        )

    @property
    def adev(self) -> NDArray[np.float64]:
        """Deviation σ(t, τ) = √σ²(t, τ) in ``unit``, shape (windows, n_tau)."""
        return np.sqrt(self.avar)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dictionary (arrays as nested lists, units stated)."""
        return {
            "kind": "dynamic_adev",
            "fs_hz": self.fs,
            "data_type": self.data_type,
            "unit": self.unit,
            "time_unit": "s",
            "tau_unit": "s",
            "window_samples": self.window,
            "step_samples": self.step,
            "times": self.times.tolist(),
            "taus": self.taus.tolist(),
            "deviation": self.adev.tolist(),
            "n_terms": self.n_terms.tolist(),
        }

    def plot(self, ax: Any = None, **kwargs: Any) -> Any:
        """Heat map of log10 σ(t, τ) over time and τ with a colour bar in ``unit`` (needs matplotlib).

        ``kwargs`` go to :func:`gyrobias.plotting.plot_dynamic_allan`; returns the ``Axes``.
        """
        return _generics.plot(self, ax, **kwargs)


# ----------------------------------------------------------------------------- stationarity


def _seconds(t: float) -> str:
    """Seconds as typed on the command line (``--start 1234.5``)."""
    return f"{t:.6g}"


def _offset(value: Any) -> float:
    """A time offset: a finite real number of seconds (``ValueError``/``TypeError`` naming it)."""
    from gyrobias._validation import real

    offset = real("offset_s", value)
    if not math.isfinite(offset):
        raise ValueError(f"offset_s must be finite, got {offset}")
    return offset


def _span(seconds: float) -> str:
    if seconds >= 7200.0:
        return f"{seconds / 3600.0:.3g} h"
    if seconds >= 120.0:
        return f"{seconds / 60.0:.3g} min"
    return f"{seconds:.3g} s"


@dataclass(frozen=True)
class Disturbance:
    """Something in a rate log that is not noise: a step, a motion segment or a warm-up trend
    (:attr:`AllanResult.stationarity`, found by ``gyrocore::stationarity``).

    Attributes
    ----------
    kind : {"step", "segment", "trend"}
        ``"step"``: the rate changes level and stays there; ``"segment"``: it leaves its level
        and comes back (a motion, a knock); ``"trend"``: a monotone drift over the first part
        of the log (warm-up).
    start_s, stop_s : float
        The span of the blocks it affects, s from the start of the data.
    at_s : float
        Time of the largest change (a step's position), s.
    size : float
        Step: level after − level before; segment: the largest excursion from the level before
        (signed); trend: the level at the start − the level after the trend. In ``unit``.
    unit : str or None
        The rate unit.
    z : float
        Largest change in units of the log's own noise at the scale that found it (``ŝ``, the
        robust spread of consecutive block-mean differences, i.e. ``√2·σ_A(τ)``).
    threshold : float
        The threshold ``z`` had to exceed at that scale.
    block_s : float
        Block length of that scale, s (the resolution of ``start_s``/``stop_s``/``at_s``).
    """

    kind: str
    start_s: float
    stop_s: float
    at_s: float
    size: float
    unit: str | None
    z: float
    threshold: float
    block_s: float

    def describe(self) -> str:
        """One sentence: what and where."""
        u = f" {self.unit}" if self.unit else ""
        if self.kind == "step":
            return f"rate step of {self.size:+.3g}{u} at {_seconds(self.at_s)} s"
        if self.kind == "segment":
            return (
                f"motion or disturbance from {_seconds(self.start_s)} s to "
                f"{_seconds(self.stop_s)} s (rate off its level by up to {self.size:+.3g}{u})"
            )
        return (
            f"warm-up trend over the first {_span(self.stop_s)} (the rate starts "
            f"{self.size:+.3g}{u} off the level it settles at)"
        )

    def shifted(self, offset_s: float) -> Disturbance:
        """The same disturbance with its times ``offset_s`` later (e.g. in the log as read)."""
        offset_s = _offset(offset_s)
        return replace(
            self,
            start_s=self.start_s + offset_s,
            stop_s=self.stop_s + offset_s,
            at_s=self.at_s + offset_s,
        )

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dictionary (times in s)."""
        return {
            "kind": self.kind,
            "start_s": self.start_s,
            "stop_s": self.stop_s,
            "at_s": self.at_s,
            "size": self.size,
            "unit": self.unit,
            "z": self.z,
            "threshold": self.threshold,
            "block_s": self.block_s,
            "text": self.describe(),
        }

    def __str__(self) -> str:
        return self.describe()


@dataclass(frozen=True)
class Stationarity:
    """Whether a rate log is static: the :class:`Disturbance` s found in it and how to select
    around them (:attr:`AllanResult.stationarity`, :func:`gyrobias.allan.stationarity`).

    The test (``gyrocore::stationarity``): block means at several scales (≈ 4096 blocks at the
    finest, at least 16 samples each, coarser by factors of 2 down to 32 blocks); at each scale
    a difference of consecutive block means beyond ``t_K`` times the log's own robust spread of
    those differences (``√2·σ_A(τ)`` for any stationary noise: white, quantisation, bias
    instability, random walk, Gauss–Markov, filtered) is a change the noise cannot explain.
    ``t_K`` is the Bonferroni normal quantile at a family-wise false-alarm level of 10⁻⁶ per
    scale, inflated for the uncertainty of the spread estimated from ``K`` differences (6.8 at
    4096 blocks, 14 at 32).

    Attributes
    ----------
    disturbances : tuple of Disturbance
        In order of their start; empty for a static log.
    checked : bool
        ``False`` when the log is too short to tell (under 1024 samples).
    n_samples : int
        Samples of the data checked.
    fs : float
        Sample rate, Hz.
    quiet_s : (float, float)
        The longest stretch free of disturbances, s from the start of the data.
    axis, unit : str or None
        The axis and the rate unit.
    total_s : float
        Length of the data, s.
    """

    disturbances: tuple[Disturbance, ...]
    checked: bool
    n_samples: int
    fs: float
    quiet_s: tuple[float, float]
    axis: str | None = None
    unit: str | None = None
    total_s: float = 0.0

    @classmethod
    def _from_core(
        cls, raw: Mapping[str, Any], fs: float, axis: str | None, unit: str | None
    ) -> Stationarity:
        """From the binding's dictionary (``gyrobias._core.stationarity.check``; samples)."""
        t0 = 1.0 / fs
        n = int(raw["n"])
        return cls(
            disturbances=tuple(
                Disturbance(
                    kind=str(d["kind"]),
                    start_s=int(d["start"]) * t0,
                    stop_s=int(d["stop"]) * t0,
                    at_s=int(d["at"]) * t0,
                    size=float(d["size"]),
                    unit=unit,
                    z=float(d["z"]),
                    threshold=float(d["threshold"]),
                    block_s=int(d["block"]) * t0,
                )
                for d in raw["disturbances"]
            ),
            checked=bool(raw["checked"]),
            n_samples=n,
            fs=fs,
            quiet_s=(int(raw["quiet"][0]) * t0, int(raw["quiet"][1]) * t0),
            axis=axis,
            unit=unit,
            total_s=n * t0,
        )

    @property
    def static(self) -> bool:
        """``True`` when nothing but noise was found (or the log was too short to check)."""
        return not self.disturbances

    def advice(self) -> str | None:
        """How to select the longest quiet stretch (``None`` for a static log)."""
        if self.static:
            return None
        a, b = self.quiet_s
        parts = []
        if a > 0.0:
            parts.append(f"--start {_seconds(a)}")
        if b < self.total_s:
            parts.append(f"--stop {_seconds(b)}")
        args = ", ".join(
            [
                *([f"start={_seconds(a)}"] if a > 0.0 else []),
                *([f"stop={_seconds(b)}"] if b < self.total_s else []),
            ]
        )
        return (
            f"analyse the longest quiet stretch, {_seconds(a)}–{_seconds(b)} s ({_span(b - a)} "
            f"of {_span(self.total_s)}): {' '.join(parts)} or select({args})"
        )

    @property
    def warnings(self) -> tuple[str, ...]:
        """One line per disturbance, with where it is and how to select around it."""
        if self.static:
            return ()
        where = f"axis {self.axis}: " if self.axis else ""
        found = "; ".join(d.describe() for d in self.disturbances)
        return (
            f"{where}the log is not static: {found}. Allan deviations and noise terms describe "
            f"this, not the sensor's noise: {self.advice()}",
        )

    def shifted(self, offset_s: float) -> Stationarity:
        """Times ``offset_s`` later: in the log as read, for data selected from it."""
        offset_s = _offset(offset_s)
        return replace(
            self,
            disturbances=tuple(d.shifted(offset_s) for d in self.disturbances),
            quiet_s=(self.quiet_s[0] + offset_s, self.quiet_s[1] + offset_s),
            total_s=self.total_s + offset_s,
        )

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dictionary (times in s)."""
        return {
            "static": self.static,
            "checked": self.checked,
            "axis": self.axis,
            "n_samples": self.n_samples,
            "fs_hz": self.fs,
            "quiet_s": list(self.quiet_s),
            "disturbances": [d.to_dict() for d in self.disturbances],
            "advice": self.advice(),
        }

    def __str__(self) -> str:
        if not self.checked:
            return "too short to check whether the log is static"
        return (
            "static: no step, segment or trend beyond the noise"
            if self.static
            else "\n".join(self.warnings)
        )


class _LazyStationarity:
    """Data descriptor behind :attr:`AllanResult.stationarity`: the check of the block means
    the core kept, run on first access (O(4096)) and remembered."""

    _slot = "_stationarity"

    @overload
    def __get__(self, obj: None, objtype: type | None = None) -> None: ...
    @overload
    def __get__(self, obj: object, objtype: type | None = None) -> Stationarity | None: ...
    def __get__(self, obj: object | None, objtype: type | None = None) -> Stationarity | None:
        if obj is None:
            return None
        value = obj.__dict__.get(self._slot)
        if isinstance(value, _Blocks):
            from gyrobias import _core

            raw = _core.stationarity.check(value.means, value.length, value.n)
            r = _as_result(obj)
            value = Stationarity._from_core(raw, r.fs, r.axis, _rate_unit(r))
            obj.__dict__[self._slot] = value
        return value

    def __set__(self, obj: object, value: Stationarity | _Blocks | None) -> None:
        obj.__dict__[self._slot] = value


@dataclass(frozen=True)
class _Blocks:
    """The core's block means of one rate column (``gyrocore::stationarity::BlockMeans``)."""

    means: NDArray[np.float64]
    length: int
    n: int

    @classmethod
    def _from_core(cls, raw: Mapping[str, Any]) -> _Blocks | None:
        if "block_means" not in raw:
            return None
        return cls(
            np.asarray(raw["block_means"], dtype=np.float64),
            int(raw["block_length"]),
            int(raw["block_samples"]),
        )


def _as_result(obj: object) -> AllanResult:
    assert isinstance(obj, AllanResult)
    return obj


def _rate_unit(r: AllanResult) -> str | None:
    """The rate unit of a result (its deviation's unit; for tdev the rate unit is not kept)."""
    return r.unit if r.kind != "tdev" else None


AllanResult.stationarity = _LazyStationarity()  # type: ignore[assignment]
