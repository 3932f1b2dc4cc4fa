"""The explorer's state: what is on screen, as one small immutable object, and everything derived
from it.

:class:`Settings` holds the user's choices (the part of the log, the cleaning steps, the
estimator, its terms, τ range and lines, the deviation shown); :class:`Session` holds one log and
the history of its settings, and derives from the current settings every result the app shows
(computed by the public API: :meth:`gyrobias.io.GyroLog.select`,
:mod:`gyrobias.cleaning`, :mod:`gyrobias.allan`, :func:`gyrobias.noise.fit`,
:func:`gyrobias.noise.gmwm`, :func:`gyrobias.exports.export`, :mod:`gyrobias.report`), the
Python code and the ``gyrobias`` command that reproduce them. Nothing here imports the app
framework: the state is tested without a browser, and the app only binds widgets to it.

The pipeline, in the order Stable32 walks it (Part, Outliers, Drift, stability, fit):

1. ``log.select(start, stop)`` (a view of the loaded log: no copy);
2. ``cleaning.clean(data, fs, outliers=, detrend=)`` (Stable32's Outliers then Drift, as
   ``gyrobias allan --outliers --detrend``: flagged samples become NaN gaps) — the one working
   copy of the selection;
3. per unit group (a 6-axis IMU's gyro and accelerometer), ``allan.adev(..., taus="octave",
   confidence=0.683, units=unit)``, as ``gyrobias allan`` computes it;
4. ``noise.fit(results, method, terms, tau_range, lines)`` (τ range and lines: joint fit only)
   or ``noise.gmwm(data, fs, ...)``;
5. ``exports.export(gyro, fmt, accel=accel, rostopic=topic)``.
"""

from __future__ import annotations

import dataclasses
import shlex
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    import numpy as np
    from numpy.typing import NDArray

    from gyrobias.allan import AllanResult
    from gyrobias.conservative import ConservativeCoefficients
    from gyrobias.io import GyroLog
    from gyrobias.noise import NoiseCoefficients, WaveletVariance

__all__ = [
    "DEVIATIONS",
    "METHODS",
    "TERMS",
    "Cleaned",
    "Session",
    "Settings",
    "Source",
]

#: The model terms the app offers (Gauss–Markov terms: joint fit and GMWM only).
TERMS = ("Q", "N", "B", "K", "R", "GM")
#: Estimators: the joint weighted fit, the IEEE-952 read-off, the GMWM.
METHODS = ("joint", "ieee", "gmwm")
#: The stability view's statistics: the Allan family and the wavelet variance.
DEVIATIONS = ("adev", "mdev", "hdev", "totdev", "theo1", "wvar", "wvar-robust")
#: The Allan-family statistics that can skip NaN gaps (outliers removed).
_GAP_AWARE = ("adev", "mdev", "hdev")
#: The export formats (gyrobias.exports.FORMATS, without importing it here).
FORMATS = ("kalibr", "openvins", "vins", "orbslam3", "liosam", "matlab", "json")
#: Confidence of the Allan intervals, as ``gyrobias allan`` (its default).
CONFIDENCE = 0.683


@dataclass(frozen=True)
class Settings:
    """What the user chose: every field appears in the reproducing code and command.

    Attributes
    ----------
    start, stop : float or None
        The part of the log, seconds from its first sample (half-open; ``None``: the end).
    outliers : float or None
        Remove samples further than this many robust σ from the median (``None``: keep all).
    detrend : {None, "linear", "quadratic"}
        Drift removed from each channel after the outliers.
    deviation : str
        Statistic of the stability view (one of :data:`DEVIATIONS`).
    method : {"joint", "ieee", "gmwm"}
        Estimator of the noise terms.
    terms : tuple of str
        Model terms switched on.
    tau_range : (float, float) or None
        τ range (s) of the joint fit (``None``: the fit's automatic range).
    lines : "auto", "none" or tuple of float
        Spectral lines modelled as sinusoids: the detected ones, none, or these frequencies (Hz).
    """

    start: float | None = None
    stop: float | None = None
    outliers: float | None = None
    detrend: str | None = None
    deviation: str = "adev"
    method: str = "joint"
    terms: tuple[str, ...] = ("Q", "N", "B", "K", "R")
    tau_range: tuple[float, float] | None = None
    lines: str | tuple[float, ...] = "auto"

    def __post_init__(self) -> None:
        from gyrobias._validation import names, pair, real

        for name in ("start", "stop", "outliers"):
            value = getattr(self, name)
            if value is not None and not (real(name, value) == real(name, value)):  # NaN
                raise ValueError(f"{name} must be a number, got NaN")
        if self.start is not None and self.start < 0:
            raise ValueError(f"start must be ≥ 0 s, got {self.start}")
        if self.start is not None and self.stop is not None and self.stop <= self.start:
            raise ValueError(f"stop ({self.stop} s) must be after start ({self.start} s)")
        if self.outliers is not None and self.outliers <= 0:
            raise ValueError(f"outliers: the outlier threshold must be > 0 σ, got {self.outliers}")
        if self.detrend not in (None, "linear", "quadratic"):
            raise ValueError(f"detrend must be linear or quadratic, got {self.detrend!r}")
        if self.deviation not in DEVIATIONS:
            raise ValueError(f"deviation must be one of {', '.join(DEVIATIONS)}")
        if self.method not in METHODS:
            raise ValueError(f"method must be one of {', '.join(METHODS)}")
        unknown = [t for t in names("terms", self.terms) if t not in TERMS]
        if unknown:
            raise ValueError(f"unknown terms {', '.join(unknown)}; terms are {', '.join(TERMS)}")
        if not self.terms:
            raise ValueError("terms: switch at least one term on")
        if self.tau_range is not None:
            lo, hi = pair("tau_range", self.tau_range)
            if not (0 < lo < hi):
                raise ValueError(
                    f"tau_range: the τ range must satisfy 0 < min < max, got {lo}, {hi}"
                )
        if isinstance(self.lines, str) and self.lines not in ("auto", "none"):
            raise ValueError(f"lines must be auto, none or frequencies, got {self.lines!r}")

    def replace(self, **changes: Any) -> Settings:
        """A copy with ``changes`` (checked like a new object)."""
        return dataclasses.replace(self, **changes)

    @property
    def fit_lines(self) -> str | list[float] | None:
        """The ``lines`` argument of :func:`gyrobias.noise.fit` / ``gmwm``."""
        if self.lines == "none":
            return None
        if self.lines == "auto":
            return "auto"
        return [float(f) for f in self.lines]

    def steps(self) -> list[str]:
        """The steps applied, in words, in order (for the app's step list)."""
        out = []
        if self.start is not None or self.stop is not None:
            out.append(f"part {_fmt_time(self.start or 0.0)} – {_fmt_time(self.stop)}")
        if self.outliers is not None:
            out.append(f"outliers beyond {self.outliers:g} σ removed")
        if self.detrend is not None:
            out.append(f"{self.detrend} drift removed")
        fit = f"{self.method} fit of {','.join(self.terms)}"
        if self.method == "joint" and self.tau_range:
            fit += f", τ {self.tau_range[0]:g}–{self.tau_range[1]:g} s"
        if self.method != "ieee":
            fit += f", lines {_lines_text(self.lines)}"
        out.append(fit)
        return out


def _fmt_time(t: float | None) -> str:
    return "end" if t is None else f"{t:g} s"


def _lines_text(lines: str | tuple[float, ...]) -> str:
    return lines if isinstance(lines, str) else ",".join(repr(float(f)) for f in lines)


@dataclass(frozen=True)
class Source:
    """Where a log came from and how it was read (for the reproducing code and command).

    Attributes
    ----------
    path : Path or None
        The file or bag directory (``None``: an array or result passed from Python).
    options : tuple of (str, Any)
        The keyword arguments of :func:`gyrobias.io.load` that differ from its defaults.
    label : str
        Name shown in the app.
    """

    path: Path | None
    options: tuple[tuple[str, Any], ...] = ()
    label: str = ""

    @property
    def kwargs(self) -> dict[str, Any]:
        return dict(self.options)

    @classmethod
    def from_options(cls, path: str | Path, options: Mapping[str, Any]) -> Source:
        """The source of ``gyrobias.io.load(path, **options)``, default options dropped."""
        defaults: dict[str, Any] = {
            "columns": None,
            "time_column": None,
            "time_unit": "auto",
            "fs": None,
            "delimiter": None,
            "skip_rows": 0,
            "units": None,
            "topic": None,
            "stamp": "header",
            "repair": "",
            "fill_gaps": False,
            "spill": False,
        }
        from gyrobias._validation import checked_path, mapping

        p = checked_path("path", path)
        kept = []
        for key, value in mapping("options", options).items():
            if key in defaults and (value == defaults[key] or (key == "repair" and not value)):
                continue
            if key in ("progress", "spill"):
                continue
            if isinstance(value, list):
                value = tuple(value)
            kept.append((key, value))
        return cls(p, tuple(kept), p.name)


@dataclass(frozen=True)
class Cleaned:
    """The selection after the cleaning steps.

    Attributes
    ----------
    data : ndarray, shape (n, k)
        The cleaned samples (NaN where an outlier was removed): rows of the session's working
        buffer, overwritten by the next cleaning (the session keeps one cleaned value at a
        time); the selection's own view when no step changes it.
    outliers : tuple of int
        Samples removed per channel.
    outlier_mask : ndarray of bool or None
        Where samples were removed.
    trend : tuple of tuple of float
        The drift polynomial's coefficients per channel (empty without drift removal).
    has_gaps : bool
        Samples were removed (NaN): the Allan deviations skip them (``gaps="omit"``).
    """

    data: NDArray[np.float64]
    outliers: tuple[int, ...]
    outlier_mask: NDArray[np.bool_] | None
    trend: tuple[tuple[float, ...], ...]
    has_gaps: bool = False


@dataclass
class _Memo:
    """Cached values per kind, keyed by the settings they depend on.

    ``"cleaned"`` (a working copy of the log) is kept once: the old copy is released before a
    new one is computed, so at most one working copy exists. The small results (Allan curves,
    fits, bounds: a few hundred numbers per channel, and the line search's float32 segment of
    at most 1 MB per channel) keep the last :data:`_RECENT` settings each, so undo, or
    switching a step off and on again, redraws
    without recomputing."""

    values: dict[str, dict[Any, Any]] = field(default_factory=dict)

    def get(self, name: str, key: Any, compute: Callable[[], Any]) -> Any:
        recent = self.values.setdefault(name, {})
        if key in recent:
            value = recent.pop(key)
            recent[key] = value  # the most recent last
            return value
        if name in _ONE_COPY:
            recent.clear()  # release the old value before computing the new one
        value = compute()
        recent[key] = value
        while len(recent) > _RECENT:
            del recent[next(iter(recent))]
        return value

    def clear(self) -> None:
        self.values.clear()


#: Settings whose small results are kept per kind (see :class:`_Memo`).
_RECENT = 4
#: Kinds that hold a copy of the samples: kept once.
_ONE_COPY = frozenset({"cleaned"})


class Session:
    """One log (or Allan result) explored, its settings and their history (undo).

    Parameters
    ----------
    log : GyroLog or None
        The loaded log (with a sample rate).
    source : Source
        How it was read.
    allan : sequence of AllanResult, optional
        Instead of a log: Allan-deviation results to fit (the log, cleaning and stability
        views then have nothing to show).
    settings : Settings, optional
        The initial settings.
    """

    def __init__(
        self,
        log: GyroLog | None,
        source: Source,
        *,
        allan: Sequence[AllanResult] | None = None,
        settings: Settings | None = None,
    ) -> None:
        from gyrobias._validation import instance, optional_instance, sequence
        from gyrobias.allan import AllanResult
        from gyrobias.io import GyroLog

        optional_instance("log", log, GyroLog, "a GyroLog")
        instance("source", source, Source, "a Source")
        optional_instance("settings", settings, Settings, "Settings")
        if allan is not None:
            allan = sequence("allan", allan)
            for i, r in enumerate(allan):
                instance(f"allan[{i}]", r, AllanResult, "an AllanResult")
        if log is None and not allan:
            raise ValueError("a session needs a log or Allan results")
        if log is not None and log.fs is None:
            raise ValueError(
                f"{source.label or 'the log'} has no sample rate: give fs (--fs HZ) or a time column"
            )
        self.log = log
        self.source = source
        self._allan_input = tuple(allan) if allan else None
        self.history: list[Settings] = [settings or Settings()]
        self._memo = _Memo()
        #: The one working copy of the log the cleaning steps write into (allocated at the
        #: log's size on first use, a selection uses its first rows): every cleaning reuses
        #: its pages instead of mapping a new copy (see :class:`_Memo`: the previous cleaned
        #: value is released before the next is computed, so nothing still reads it).
        self._working: NDArray[np.float64] | None = None
        #: Called with the fraction done (0–1) by the long stability computations (the
        #: library's own ``progress=``; results never depend on it): the app shows it.
        self.progress: Callable[[float], None] | None = None

    # -- settings and history -------------------------------------------------------------

    @property
    def settings(self) -> Settings:
        """The current settings."""
        return self.history[-1]

    def update(self, **changes: Any) -> Settings:
        """Apply ``changes`` (a new step in the history); returns the new settings.

        Raises ``ValueError`` (and keeps the settings) for an invalid change."""
        new = self.settings.replace(**changes)
        if new != self.settings:
            self.history.append(new)
        return new

    def undo(self) -> Settings:
        """Go back one step (nothing happens at the first)."""
        if len(self.history) > 1:
            self.history.pop()
        return self.settings

    @property
    def can_undo(self) -> bool:
        return len(self.history) > 1

    # -- the log ---------------------------------------------------------------------------

    @property
    def fs(self) -> float:
        if self.log is not None:
            assert self.log.fs is not None
            return float(self.log.fs)
        assert self._allan_input is not None
        return float(self._allan_input[0].fs)

    @property
    def duration(self) -> float:
        """Length of the whole log in seconds (n / fs)."""
        assert self.log is not None
        return self.log.n_samples / self.fs

    @property
    def columns(self) -> tuple[str, ...]:
        if self.log is not None:
            return tuple(self.log.columns)
        assert self._allan_input is not None
        return tuple(str(r.axis) for r in self._allan_input)

    def selection(self) -> GyroLog:
        """The selected part (``GyroLog.select``: a view, no copy)."""
        assert self.log is not None, "no log"
        s = self.settings
        if s.start is None and s.stop is None:
            return self.log
        return self.log.select(start=s.start, stop=s.stop)

    def cleaned(self) -> Cleaned:
        """The selection after the outlier and drift steps (cached)."""
        s = self.settings
        key = (s.start, s.stop, s.outliers, s.detrend)
        return self._memo.get("cleaned", key, self._compute_cleaned)  # type: ignore[no-any-return]

    def _compute_cleaned(self) -> Cleaned:
        import numpy as np

        from gyrobias import cleaning

        s = self.settings
        part = self.selection()
        k = part.data.shape[1]
        if s.outliers is None and s.detrend is None:
            return Cleaned(part.data, (0,) * k, None, (), False)
        # the command line's --outliers / --detrend (cli._common.clean_log): one call, into
        # the session's working buffer
        assert self.log is not None
        if self._working is None:
            self._working = np.empty(self.log.data.shape, dtype=np.float64)
        done = cleaning.clean(
            part.data,
            self.fs,
            outliers=s.outliers,
            detrend=s.detrend,
            units=part.units,
            out=self._working[: part.data.shape[0]],
        )
        mask = None if done.outliers is None else np.asarray(done.outliers.mask)
        counts = (
            (0,) * k
            if done.outliers is None
            else tuple(int(c) for c in np.atleast_1d(done.outliers.count))
        )
        trend: tuple[tuple[float, ...], ...] = ()
        if done.drift is not None:
            coef = np.atleast_2d(np.asarray(done.drift.coefficients, dtype=np.float64))
            trend = tuple(tuple(float(v) for v in row) for row in coef)
        return Cleaned(done.data, counts, mask, trend, bool(done.has_gaps))

    def unit_groups(self) -> list[tuple[str | None, list[int]]]:
        assert self.log is not None
        return self.log.unit_groups()

    # -- stability ---------------------------------------------------------------------------

    def allan(self) -> tuple[AllanResult, ...]:
        """Overlapping ADEV at octave τ of every channel, per unit, as ``gyrobias allan``."""
        if self._allan_input is not None:
            return self._allan_input
        s = self.settings
        return self._memo.get(  # type: ignore[no-any-return]
            "adev", (s.start, s.stop, s.outliers, s.detrend), lambda: self._deviation("adev")
        )

    def stability(self) -> tuple[AllanResult | WaveletVariance, ...]:
        """The statistic of the stability view (``settings.deviation``) of every channel."""
        s = self.settings
        if s.deviation == "adev":
            return self.allan()
        if self._allan_input is not None:
            raise ValueError("an Allan result was given, not a log: only its ADEV can be shown")
        return self._memo.get(  # type: ignore[no-any-return]
            "stability",
            (s.start, s.stop, s.outliers, s.detrend, s.deviation),
            lambda: self._deviation(s.deviation),
        )

    def _selection_start_s(self) -> float:
        """Seconds from the log's start to the selection's first sample (0 without one)."""
        sel = self.selection().selection
        return 0.0 if sel is None or sel.start_s is None else float(sel.start_s)

    def _deviation(self, kind: str) -> tuple[Any, ...]:

        from gyrobias import allan, noise

        assert self.log is not None
        cleaned = self.cleaned()
        data = cleaned.data
        gaps = cleaned.has_gaps or bool(self.log.sampling.filled_samples)
        if not kind.startswith("wvar"):
            # one call for every channel, one unit per column: the row-major buffer is analysed
            # as it is (a call per unit would copy its columns first); the results are those of
            # a call per unit (each column is computed alone)
            kw: dict[str, Any] = {
                "confidence": CONFIDENCE,
                "units": list(self.log.units),
                "axis_names": list(self.log.columns),
                "progress": self.progress,
            }
            if gaps:
                if kind not in _GAP_AWARE:
                    raise ValueError(
                        f"{kind.upper()} cannot skip the gaps the outlier removal leaves: "
                        "switch it off or use ADEV, MDEV or HDEV"
                    )
                kw["gaps"] = "omit"
            if kind == "adev":
                kw["taus"] = "octave"
            out = getattr(allan, kind)(data, self.fs, **kw)
            results = tuple(out) if isinstance(out, tuple) else (out,)
            offset = self._selection_start_s()
            if offset:
                # times in the log as read, as `gyrobias allan --start` gives them
                results = tuple(r.in_log_time(offset) for r in results)
            return results
        if gaps:
            raise ValueError(
                "the wavelet variance needs contiguous samples: switch the outlier "
                "removal off (or use ADEV, MDEV or HDEV, which skip the gaps)"
            )
        by_column: dict[int, Any] = {}
        for unit, cols in self.unit_groups():
            part = data if len(cols) == data.shape[1] else data[:, cols]
            names = [self.log.columns[c] for c in cols]
            out = noise.wvar(
                part, self.fs, robust=kind == "wvar-robust", units=unit, axis_names=names
            )
            by_column.update(zip(cols, out if isinstance(out, tuple) else (out,)))
        return tuple(by_column[c] for c in range(len(self.log.columns)))

    # -- the fit ----------------------------------------------------------------------------

    def coefficients(self) -> tuple[NoiseCoefficients, ...]:
        """The noise terms of every channel by the chosen estimator (cached)."""
        s = self.settings
        key = (s.start, s.stop, s.outliers, s.detrend, s.method, s.terms, s.tau_range, s.lines)
        return self._memo.get("fit", key, self._compute_fit)  # type: ignore[no-any-return]

    def _compute_fit(self) -> tuple[NoiseCoefficients, ...]:
        from gyrobias import noise

        s = self.settings
        if s.method == "gmwm":
            if self._allan_input is not None:
                raise ValueError("the GMWM needs the samples; an Allan result was given")
            import numpy as np

            assert self.log is not None
            data = self.cleaned().data
            if np.isnan(data).any():
                raise ValueError(
                    "the GMWM needs contiguous samples: switch the outlier removal off or use "
                    "the joint fit"
                )
            by_column: dict[int, Any] = {}
            for unit, cols in self.unit_groups():
                part = data if len(cols) == data.shape[1] else data[:, cols]
                out = noise.gmwm(
                    part,
                    self.fs,
                    terms=list(s.terms),
                    units=unit,
                    axis_names=[self.log.columns[c] for c in cols],
                    lines=s.fit_lines,
                )
                by_column.update(zip(cols, out if isinstance(out, tuple) else (out,)))
            return tuple(by_column[c] for c in range(len(self.log.columns)))
        out = noise.fit(
            list(self.allan()), method=s.method, terms=list(s.terms), **self.fit_options()
        )
        assert isinstance(out, tuple)
        return out

    def fit_options(self) -> dict[str, Any]:
        """The ``tau_range`` and ``lines`` the fit uses: the settings' for the joint fit; the
        IEEE read-off has its own slope regions and no sinusoid (``gyrobias allan`` refuses
        ``--fit-tau-range`` and ``--lines`` with it), so it gets neither; the GMWM its lines."""
        s = self.settings
        if s.method == "joint":
            return {"tau_range": s.tau_range, "lines": s.fit_lines}
        if s.method == "gmwm":
            return {"lines": s.fit_lines}
        return {}

    def conservative(self, confidence: float = 0.95) -> tuple[ConservativeCoefficients, ...]:
        """The conservative (overbounding) set of every fit (joint and read-off fits)."""
        from gyrobias._validation import real

        confidence = real("confidence", confidence)  # a memo key: the type before hashing
        s = self.settings
        key = (s.start, s.stop, s.outliers, s.detrend, s.method, s.terms, s.tau_range, s.lines)
        return self._memo.get(  # type: ignore[no-any-return]
            "conservative",
            (key, confidence),
            lambda: tuple(c.conservative(confidence) for c in self.coefficients()),
        )

    # -- export ---------------------------------------------------------------------------

    @property
    def rostopic(self) -> str:
        return (self.log.topic if self.log is not None else None) or "/imu0"

    def export(self, fmt: str) -> str:
        """The estimator file ``fmt`` of the current fit (:func:`gyrobias.exports.export`)."""
        from gyrobias import exports

        fits = self.coefficients()
        gyro = [c for c in fits if c.sensor == "gyro"]
        accel = [c for c in fits if c.sensor == "accel"]
        if not gyro and not accel:
            raise ValueError(
                "the exports need the data unit: read the log with units (e.g. --units deg/s)"
            )
        return exports.export(gyro or None, fmt, accel=accel or None, rostopic=self.rostopic)

    def report_html(self) -> str:
        """The HTML report (:func:`gyrobias.report.build_report`) of the selected, cleaned log."""
        from gyrobias import report

        if self.log is None:
            raise ValueError("the report needs a log")
        if self.settings.method == "gmwm":
            raise ValueError("the HTML report fits with the joint or IEEE method, not the GMWM")
        s = self.settings
        return report.build_report(
            self.selection(),
            method=s.method,
            outliers=s.outliers,
            detrend=s.detrend,
            **self.fit_options(),
        )

    # -- reproduction ----------------------------------------------------------------------

    def python_code(self, export: str | None = "kalibr") -> str:
        """A Python script that computes what is on screen and prints the coefficients (each
        fit's ``summary()`` in IEEE units, as the app shows them); with ``export``, it also
        writes that estimator file as ``<fmt>.<ext>``."""
        _check_export(export)
        s = self.settings
        modules = ["allan", "io", "noise"]
        if s.outliers is not None or s.detrend is not None:
            modules.append("cleaning")
        if export:
            modules.append("exports")
        lines = [f"from gyrobias import {', '.join(sorted(modules))}"]
        lines.append("")
        if self.source.path is None:
            lines += [
                "# The log was passed from Python: load it here as you did then, e.g.",
                "# log = io.load('imu.csv', fs=100.0, units='deg/s')",
                "log = ...",
            ]
        else:
            args = [repr(str(self.source.path))]
            args += [f"{k}={v!r}" for k, v in self.source.options]
            lines.append(f"log = io.load({', '.join(args)})")
        if s.start is not None or s.stop is not None:
            lines.append(f"log = log.select(start={s.start!r}, stop={s.stop!r})")
        filled = bool(self.source.kwargs.get("fill_gaps"))
        if s.outliers is not None or s.detrend is not None:
            lines.append(
                f"cleaned = cleaning.clean(log.data, log.fs, outliers={s.outliers!r}, "
                f"detrend={s.detrend!r}, units=log.units)"
            )
            lines.append("data = cleaned.data")
            gaps = ', gaps="omit"' if filled else ', gaps="omit" if cleaned.has_gaps else "error"'
        else:
            lines.append("data = log.data")
            gaps = ', gaps="omit"' if filled else ""
        lines.append("fits = []")
        lines.append("for unit, cols in log.unit_groups():  # gyro and accelerometer apart")
        lines.append("    names = [log.columns[c] for c in cols]")
        if s.method == "gmwm":
            lines.append(
                f"    fits += noise.gmwm(data[:, cols], log.fs, terms={list(s.terms)!r}, "
                f"units=unit, axis_names=names, lines={s.fit_lines!r})"
            )
            gaps = ""
        else:
            lines.append(
                f'    results = allan.adev(data[:, cols], log.fs, taus="octave", '
                f"confidence={CONFIDENCE!r}, units=unit, axis_names=names{gaps})"
            )
            if s.start is not None:
                lines.append("    # times (the stationarity advice) in the log as read")
                lines.append(
                    "    results = [r.in_log_time(log.selection.start_s) for r in results]"
                )
            extra = "".join(f", {k}={v!r}" for k, v in self.fit_options().items())
            lines.append(
                f"    fits += noise.fit(results, method={s.method!r}, "
                f"terms={list(s.terms)!r}{extra})"
            )
        lines.append("for c in fits:")
        lines.append('    print(c.to("ieee").summary())')
        if export:
            name = export_filename(export)
            lines += [
                'gyro = [c for c in fits if c.sensor == "gyro"] or None',
                'accel = [c for c in fits if c.sensor == "accel"] or None',
                f"exports.export(gyro, {export!r}, {name!r}, accel=accel, "
                f"rostopic={self.rostopic!r})",
            ]
        return "\n".join(lines) + "\n"

    def cli_command(self, export: str | None = "kalibr", output: str | None = None) -> str:
        """The ``gyrobias allan`` command that computes the same fit and writes the same
        ``export`` file (``output``, default ``<fmt>.<ext>``).

        Raises ``ValueError`` for what the command line cannot do (the GMWM; an array or
        result passed from Python)."""
        _check_export(export)
        if output is not None:
            from gyrobias._validation import checked_path

            checked_path("output", output)
        s = self.settings
        if self.source.path is None:
            raise ValueError("the log was passed from Python: no command reads it")
        if s.method == "gmwm":
            raise ValueError(
                "gyrobias allan fits with the joint or IEEE method; the GMWM is in the Python code"
            )
        argv = ["gyrobias", "allan", str(self.source.path), *_read_argv(self.source.kwargs)]
        if s.start is not None:
            argv += ["--start", f"{s.start!r}s"]
        if s.stop is not None:
            argv += ["--stop", f"{s.stop!r}s"]
        if s.outliers is not None:
            argv += ["--outliers", f"{s.outliers!r}"]
        if s.detrend is not None:
            argv += ["--detrend", s.detrend]
        argv += ["--fit", "--fit-method", s.method, "--fit-terms", ",".join(s.terms)]
        if s.method == "joint":
            if s.tau_range is not None:
                argv += ["--fit-tau-range", f"{s.tau_range[0]!r},{s.tau_range[1]!r}"]
            argv += ["--lines", _lines_text(s.lines)]
        if export:
            argv += ["--export", f"{export}={output or export_filename(export)}"]
        return shlex.join(argv)


def _check_export(export: Any) -> None:
    """``export``: ``None`` (no file) or one of :data:`FORMATS`, else an error naming it."""
    if export is not None:
        from gyrobias._validation import choice

        choice("export", export, FORMATS)


def export_filename(fmt: str) -> str:
    """The default file name of an export (gyrobias.exports.DEFAULT_FILENAMES)."""
    from gyrobias.exports import DEFAULT_FILENAMES

    return DEFAULT_FILENAMES[fmt]


def _read_argv(options: Mapping[str, Any]) -> list[str]:
    """The ``gyrobias`` reading options (cli._common.add_read_arguments) for load keywords."""
    argv: list[str] = []
    for key, value in options.items():
        if key == "columns":
            cols = value.split(",") if isinstance(value, str) else list(value)
            argv += ["--columns", ",".join(str(c) for c in cols)]
        elif key == "time_column":
            argv += ["--no-time-column"] if value is False else ["--time-column", str(value)]
        elif key == "time_unit":
            argv += ["--time-unit", str(value)]
        elif key == "fs":
            argv += ["--fs", repr(float(value))]
        elif key == "delimiter":
            argv += ["--delimiter", "tab" if value == "\t" else str(value)]
        elif key == "skip_rows":
            argv += ["--skip-rows", str(int(value))]
        elif key == "units":
            if isinstance(value, str):
                argv += ["--units", value]
            elif isinstance(value, Mapping):
                argv += ["--units", ",".join(f"{k}={v}" for k, v in value.items())]
            else:
                argv += ["--units", ",".join(str(u) for u in value)]
        elif key == "topic":
            argv += ["--topic", str(value)]
        elif key == "stamp":
            argv += ["--stamp", str(value)]
        elif key == "repair":
            argv += ["--repair", value if isinstance(value, str) else ",".join(value)]
        elif key == "fill_gaps":
            if value:
                argv.append("--fill-gaps")
        else:  # pragma: no cover - Source.from_options keeps only these keys
            raise ValueError(f"no command-line option for load({key}=...)")
    return argv
