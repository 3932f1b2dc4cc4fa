"""The loader's value types: :class:`GyroLog` (the samples, names, units, rate and time),
:class:`SamplingReport` (what the timestamps say about the sampling) and the time selection
(:func:`parse_time_bound`, :class:`TimeBound`, :class:`Selection`, :meth:`GyroLog.select`).
No reading code here."""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gyrobias._validation import as_float_array, count, sample_rate, sequence, string, text


@dataclass(frozen=True)
class SamplingReport:
    """What the timestamps (or their absence) say about the sampling of a log.

    Attributes
    ----------
    n_samples : int
        Number of samples (rows).
    fs : float or None
        Sample rate used for the log, Hz (user-given, else estimated; ``None`` if neither).
    fs_source : {"user", "timestamps", "file", None}
        Where ``fs`` came from (``"file"``: the ``// Sample rate: … Hz`` line of an Xsens-style
        preamble of a log without timestamps).
    fs_estimated : float or None
        Rate from the timestamps, Hz: 1 / mean of the regular intervals (those that are
        neither gaps nor zero), rounded to 9 significant digits.
    median_interval : float or None
        Median interval between timestamps, s.
    jitter : float or None
        Relative standard deviation of the intervals (excluding gaps) about the median interval.
    time_unit : str or None
        Unit the time column was read in (``"s"``, ``"ms"``, ``"us"`` or ``"ns"``).
    duration : float or None
        Last minus first timestamp, s.
    n_gaps : int
        Intervals longer than ``GAP_FACTOR`` (1.5) × the median interval.
    gap_rows : ndarray of int
        Data-row index (0-based) of the sample *after* each gap.
    gap_durations : ndarray of float
        Length of each gap interval, s.
    missing_samples : int
        Samples the gaps would hold at the median interval (Σ round(gap / median) − 1).
    n_duplicates : int
        Intervals of exactly zero (repeated timestamps).
    duplicate_rows : ndarray of int
        Data-row index of the second sample of each repeated timestamp.
    warnings : tuple of str
        Human-readable findings (irregular sampling, disagreeing ``fs``, repairs); empty if
        all is well.
    n_out_of_order : int
        Samples whose timestamp is earlier than the one before them in the file (only
        non-zero with ``repair="sort"``: otherwise they are an error).
    out_of_order_rows : ndarray of int
        File-order index (0-based) of each such sample.
    n_exact_duplicates : int
        Samples repeating the previous one exactly (same timestamp and values), after sorting.
    repairs : tuple of str
        What ``repair=`` and ``fill_gaps=`` changed, one sentence each (also in ``warnings``).
    filled_samples : int
        NaN rows inserted by ``fill_gaps=True``.
    source_format : str or None
        ``"text"``, ``"npy"``, ``"ROS1 bag"``, ``"ROS2 bag (sqlite3)"``, ``"ROS2 bag (mcap)"``,
        ``"MCAP"`` or ``"ROS2 sqlite3 (.db3)"``.

    Notes
    -----
    Row indices (``gap_rows``, ``duplicate_rows``) refer to the samples after the repairs
    and before ``fill_gaps``.
    """

    n_samples: int
    fs: float | None
    fs_source: str | None
    fs_estimated: float | None = None
    median_interval: float | None = None
    jitter: float | None = None
    time_unit: str | None = None
    duration: float | None = None
    n_gaps: int = 0
    gap_rows: NDArray[np.int64] = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    gap_durations: NDArray[np.float64] = field(default_factory=lambda: np.zeros(0))
    missing_samples: int = 0
    n_duplicates: int = 0
    duplicate_rows: NDArray[np.int64] = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    warnings: tuple[str, ...] = ()
    n_out_of_order: int = 0
    out_of_order_rows: NDArray[np.int64] = field(
        default_factory=lambda: np.zeros(0, dtype=np.int64)
    )
    n_exact_duplicates: int = 0
    repairs: tuple[str, ...] = ()
    filled_samples: int = 0
    source_format: str | None = None

    @property
    def longest_gap(self) -> float | None:
        """Longest gap interval in seconds (``None`` without gaps)."""
        return float(self.gap_durations.max()) if self.n_gaps else None

    @property
    def regular(self) -> bool:
        """``True`` when nothing was found to warn about."""
        return not self.warnings

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dictionary (rows 0-based data rows, times in seconds)."""
        return {
            "n_samples": self.n_samples,
            "fs_hz": self.fs,
            "fs_source": self.fs_source,
            "fs_estimated_hz": self.fs_estimated,
            "median_interval_s": self.median_interval,
            "jitter": self.jitter,
            "time_unit": self.time_unit,
            "duration_s": self.duration,
            "n_gaps": self.n_gaps,
            "gap_rows": self.gap_rows.tolist(),
            "gap_durations_s": self.gap_durations.tolist(),
            "longest_gap_s": self.longest_gap,
            "missing_samples": self.missing_samples,
            "n_duplicates": self.n_duplicates,
            "duplicate_rows": self.duplicate_rows.tolist(),
            "n_out_of_order": self.n_out_of_order,
            "out_of_order_rows": self.out_of_order_rows.tolist(),
            "n_exact_duplicates": self.n_exact_duplicates,
            "repairs": list(self.repairs),
            "filled_samples": self.filled_samples,
            "source_format": self.source_format,
            "warnings": list(self.warnings),
        }

    def __str__(self) -> str:
        parts = [f"{self.n_samples} samples"]
        if self.fs is not None:
            parts.append(f"fs = {self.fs:g} Hz ({self.fs_source})")
        if self.jitter is not None:
            parts.append(f"jitter {100 * self.jitter:.3g} %")
        if self.time_unit is not None:
            parts.append(f"{self.n_gaps} gaps, {self.n_duplicates} repeated timestamps")
            if self.n_out_of_order:
                parts.append(f"{self.n_out_of_order} out of order")
        text = ", ".join(parts)
        return "\n".join([text, *("warning: " + w for w in self.warnings)])


@dataclass(frozen=True)
class GyroLog:
    """A loaded gyro log.

    Attributes
    ----------
    data : ndarray or numpy.memmap, shape (n, k)
        The selected channels as float64, one column per channel, in file units. A log
        loaded with ``spill`` is a :class:`numpy.memmap` of a temporary file (read it block
        by block to keep the memory bounded). With ``fill_gaps=True``, missing samples are
        NaN rows.
    columns : tuple of str
        Channel names (header names, ``"col<i>"`` for files without a header / ``.npy``,
        ``gyro_x`` … ``accel_z`` for bags).
    fs : float or None
        Sample rate in Hz: the user's ``fs`` if given, else estimated from the timestamps,
        else ``None``.
    time : ndarray, shape (n,), or None
        Timestamps in seconds relative to the first sample (exact for integer nanosecond stamps).
    time_start : float or None
        First timestamp as given in the file, converted to seconds.
    time_column : str or None
        Name of the time column used.
    path : pathlib.Path
        The source file.
    sampling : SamplingReport
        Findings about the sampling (rate, jitter, gaps, repeated timestamps).
    units : tuple of str or None
        Unit of each channel (``"rad/s"``, ``"m/s^2"`` for bags; from ``units=`` for other
        formats; ``None`` where unknown).
    topic : str or None
        The bag topic read.
    selection : Selection or None
        The part of the log read that this log holds, after :meth:`select` (``None``: the
        whole log).
    """

    data: NDArray[np.float64]
    columns: tuple[str, ...]
    fs: float | None
    time: NDArray[np.float64] | None
    time_start: float | None
    time_column: str | None
    path: Path
    sampling: SamplingReport
    units: tuple[str | None, ...] = ()
    topic: str | None = None
    selection: Selection | None = None

    def __post_init__(self) -> None:
        if not self.units:
            object.__setattr__(self, "units", (None,) * len(self.columns))

    @property
    def warnings(self) -> tuple[str, ...]:
        """The sampling report's warnings (irregular sampling, disagreeing ``fs``)."""
        return self.sampling.warnings

    @property
    def n_samples(self) -> int:
        """Number of samples (rows)."""
        return int(self.data.shape[0])

    def unit_groups(self) -> list[tuple[str | None, list[int]]]:
        """Channels grouped by unit, in order of first appearance: ``[(unit, [column indices])]``.

        A 6-axis IMU log gives ``[("rad/s", [0, 1, 2]), ("m/s^2", [3, 4, 5])]``, so that each
        sensor can be analysed with its own unit.
        """
        groups: dict[str | None, list[int]] = {}
        for i, u in enumerate(self.units):
            groups.setdefault(u, []).append(i)
        return list(groups.items())

    def __getitem__(self, name: str) -> NDArray[np.float64]:
        """One channel by name, as a 1-D view (``KeyError`` for an unknown name, as a mapping)."""
        string("name", name)
        try:
            return self.data[:, self.columns.index(name)]
        except ValueError:
            raise KeyError(f"no channel {name!r}; channels are {', '.join(self.columns)}") from None

    def select(
        self,
        start: str | float | TimeBound | None = None,
        stop: str | float | TimeBound | None = None,
        *,
        names: tuple[str, str] = ("start", "stop"),
    ) -> GyroLog:
        """The samples in the half-open span ``[start, stop)`` of the log, as a new log.

        Parameters
        ----------
        start, stop : float, int, str or None
            Bounds, each read by :func:`parse_time_bound`: seconds from the log's start (time 0
            is the first sample; from :attr:`time` when the log has timestamps, else
            ``index / fs``), a string with a unit (``"1200s"``, ``"90min"``, ``"0.5h"``) or a
            sample index with the suffix ``n`` (``"250000n"``). ``None``: the log's start / end.
            A sample belongs to the selection when its time ``t`` satisfies
            ``start <= t < stop`` (its index ``i``: ``start <= i < stop``); times within
            10⁻⁶ of a sample interval of a sample's time count as that time. A parsed
            :class:`TimeBound` is taken as it is.
        names : (str, str)
            The bounds' names in error messages (the command line passes
            ``("--start", "--stop")``).

        Returns
        -------
        GyroLog
            The same log over the selected samples. Its :attr:`data` (and :attr:`time`) are
            views of this log's arrays, never copies (a memory-mapped log stays mapped).
            :attr:`time` keeps its values: seconds from the start of the log *as read*, not
            re-based to the selection, so ``time_start + time`` stays the absolute time of each
            sample. :attr:`selection` records the span (in the log as read, also for a
            selection of a selection) for outputs such as "τ computed on 0.5–2.3 h of 2.8 h".
            :attr:`sampling` still describes the whole log as read (its row indices too).

        Raises
        ------
        TypeError
            A bound is not a number, a string or ``None``.
        ValueError
            A bound is negative, not finite, unreadable, at or beyond the end of the log
            (``start``) or beyond it (``stop``), ``start >= stop``, the span holds no sample,
            or a bound is in seconds and the log has neither timestamps nor a sample rate.
            The message names the argument.

        Examples
        --------
        >>> import numpy as np
        >>> from pathlib import Path
        >>> from gyrobias.io import GyroLog, SamplingReport
        >>> log = GyroLog(np.zeros((100_800, 1)), ("gx",), 10.0, None, None, None,
        ...               Path("x.csv"), SamplingReport(100_800, 10.0, "user"))  # 2.8 h at 10 Hz
        >>> part = log.select(start="0.5h", stop=8280.0)
        >>> part.data.shape, np.shares_memory(part.data, log.data)
        ((64800, 1), True)
        >>> print(part.selection)
        0.5–2.3 h of 2.8 h (samples 18000–82800 of 100800)
        >>> part.select(stop="1000n").selection.stop_index
        19000
        """
        local = resolve_selection(self.n_samples, self.fs, start, stop, time=self.time, names=names)
        i0, i1 = local.start_index, local.stop_index
        before = self.selection
        if before is None:
            selection = local
        else:  # a selection of a selection: in the log as read
            base_s = before.start_s
            selection = Selection(
                start_s=None if local.start_s is None or base_s is None else base_s + local.start_s,
                stop_s=None if local.stop_s is None or base_s is None else base_s + local.stop_s,
                start_index=before.start_index + i0,
                stop_index=before.start_index + i1,
                total_s=before.total_s,
                total_samples=before.total_samples,
            )
        return replace(
            self,
            data=self.data[i0:i1],
            time=None if self.time is None else self.time[i0:i1],
            selection=selection,
        )


def _bound_names(names: Any) -> tuple[str, str]:
    """``names`` as the two bounds' names ``(start, stop)``, else an error naming ``names``."""
    items = sequence("names", names)
    if len(items) != 2:
        raise ValueError(f"names must be two names (start, stop), got {len(items)}")
    return text("names[0]", items[0]), text("names[1]", items[1])


def resolve_selection(
    n_samples: int,
    fs: float | None,
    start: str | float | TimeBound | None = None,
    stop: str | float | TimeBound | None = None,
    *,
    time: NDArray[np.float64] | None = None,
    names: tuple[str, str] = ("start", "stop"),
) -> Selection:
    """The samples ``[start, stop)`` of a record of ``n_samples`` at ``fs`` (or with ``time``).

    The rules of :meth:`GyroLog.select`, for a bare record (an array of samples rather than a
    :class:`GyroLog`; :func:`gyrobias.fleet.analyse` uses it for arrays).

    Parameters
    ----------
    n_samples : int
        Length of the record.
    fs : float or None
        Sample rate, Hz (``None``: only sample-index bounds are possible without ``time``).
    start, stop : float, int, str, TimeBound or None
        The bounds (:func:`parse_time_bound`).
    time : ndarray, optional
        Timestamps of the samples, s, non-decreasing (time 0 is ``time[0]``).
    names : (str, str)
        The bounds' names in error messages.

    Returns
    -------
    Selection
        Rows ``start_index … stop_index - 1`` of the record; times from its first sample.

    Raises
    ------
    ValueError, TypeError
        As :meth:`GyroLog.select`.

    Examples
    --------
    >>> from gyrobias.io import resolve_selection
    >>> print(resolve_selection(6000, 100.0, "10s", "30s"))
    10–30 s of 60 s (samples 1000–3000 of 6000)
    """
    start_name, stop_name = _bound_names(names)
    first = parse_time_bound(start, name=start_name)
    last = parse_time_bound(stop, name=stop_name)
    n = count("n_samples", n_samples)
    if fs is not None:
        fs = sample_rate(fs)
    if time is not None:
        time = as_float_array("time", time)  # no copy of a float64 vector (a mapped one too)
    if n == 0:
        raise ValueError(f"{start_name}: the log has no samples to select from")
    if time is not None and len(time) != n:
        raise ValueError(f"time has {len(time)} values for n_samples={n}")
    period = 1.0 / fs if fs is not None and fs > 0 and math.isfinite(1.0 / fs) else None
    t0 = float(time[0]) if time is not None else 0.0
    # length of the log in seconds: to the end of the last sample's interval
    if time is not None:
        span = float(time[-1]) - t0 + (period if period is not None else 0.0)
    elif period is not None:
        span = n * period
    else:
        span = None
    tol = 1e-6 * period if period is not None else 0.0

    def offset(i: int) -> float | None:
        """Seconds from this log's first sample to sample ``i`` (``n``: the end)."""
        if i >= n:
            return span
        if time is not None:
            return float(time[i]) - t0
        return i * period if period is not None else None

    def index(bound: TimeBound, name: str) -> int:
        if bound.index is not None:
            return bound.index
        seconds = bound.seconds
        assert seconds is not None
        if span is None:
            raise ValueError(
                f"{name}={bound} is in seconds, and the log has neither timestamps nor a "
                f"sample rate: give fs, or a sample index such as '{n // 2}n'"
            )
        if time is not None:
            return int(np.searchsorted(time, t0 + seconds - tol, side="left"))
        assert period is not None
        k = seconds / period
        nearest = round(k)
        return int(nearest if abs(k - nearest) <= 1e-6 else math.ceil(k))

    def describe_end() -> str:
        return f"{n} samples" + (f", {_format_seconds(span)}" if span is not None else "")

    i0 = 0
    if first is not None:
        too_late = (
            first.index >= n
            if first.index is not None
            else span is not None and first.seconds is not None and first.seconds >= span - tol
        )
        if too_late:
            raise ValueError(
                f"{start_name}={first} is at or beyond the end of the log ({describe_end()})"
            )
        i0 = index(first, start_name)
    i1 = n
    if last is not None:
        too_far = (
            last.index > n
            if last.index is not None
            else span is not None and last.seconds is not None and last.seconds > span + tol
        )
        if too_far:
            raise ValueError(f"{stop_name}={last} is beyond the end of the log ({describe_end()})")
        i1 = min(index(last, stop_name), n)
    if first is not None and last is not None and first._comparable(last) and first >= last:
        raise ValueError(f"{start_name}={first} must be before {stop_name}={last}")
    if i0 >= i1:
        raise ValueError(f"{start_name}={first} and {stop_name}={last} select no sample of the log")

    return Selection(
        start_s=offset(i0),
        stop_s=offset(i1),
        start_index=i0,
        stop_index=i1,
        total_s=span,
        total_samples=n,
    )


_BOUND = re.compile(
    r"^\s*(?P<number>[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)\s*(?P<unit>n|s|min|h)?\s*$"
)
_SECONDS_PER = {None: 1.0, "s": 1.0, "min": 60.0, "h": 3600.0}


@dataclass(frozen=True)
class TimeBound:
    """One bound of a time selection, as :func:`parse_time_bound` read it.

    Exactly one of the attributes is set.

    Attributes
    ----------
    seconds : float or None
        Seconds from the log's start (time 0 is the first sample).
    index : int or None
        A 0-based sample index.
    text : str or None
        The text it was read from (shown in messages as the user wrote it); not compared.
    """

    seconds: float | None = None
    index: int | None = None
    text: str | None = field(default=None, compare=False, repr=False)

    def _comparable(self, other: TimeBound) -> bool:
        """``True`` when both bounds are in the same kind (seconds, or sample index)."""
        return (self.index is None) == (other.index is None)

    def __ge__(self, other: TimeBound) -> bool:
        if self.index is not None and other.index is not None:
            return self.index >= other.index
        if self.seconds is not None and other.seconds is not None:
            return self.seconds >= other.seconds
        return NotImplemented

    def __str__(self) -> str:
        if self.text is not None:
            return self.text.strip()
        return f"{self.index}n" if self.index is not None else f"{self.seconds:g}s"


def parse_time_bound(
    value: str | float | TimeBound | None, *, name: str = "start"
) -> TimeBound | None:
    """Read one bound of a time selection (``--start`` / ``--stop``, :meth:`GyroLog.select`).

    Grammar: a real number is seconds from the log's start (time 0 is the first sample); a
    string is a number with an optional unit — none or ``s`` (seconds), ``min``, ``h`` — or a
    non-negative integer with the suffix ``n``, a 0-based sample index (``"250000n"``).

    Parameters
    ----------
    value : float, int, str, TimeBound or None
        The bound (``None``: no bound, returned as ``None``; a :class:`TimeBound` is returned
        as it is).
    name : str
        The argument's name, for messages.

    Returns
    -------
    TimeBound or None

    Raises
    ------
    TypeError
        ``value`` is not a real number, a string or ``None`` (a bool is refused).
    ValueError
        Unreadable text, a negative or non-finite value, a fractional sample index; the
        message names ``name``.

    Examples
    --------
    >>> from gyrobias.io import parse_time_bound
    >>> parse_time_bound("0.5h"), parse_time_bound("90min"), parse_time_bound(12)
    (TimeBound(seconds=1800.0, index=None), TimeBound(seconds=5400.0, index=None), \
TimeBound(seconds=12.0, index=None))
    >>> parse_time_bound("250000n")
    TimeBound(seconds=None, index=250000)
    """
    if value is None or isinstance(value, TimeBound):
        return value
    if isinstance(value, bool) or not isinstance(value, (str, int, float, np.integer, np.floating)):
        raise TypeError(
            f"{name} must be seconds (a number), a string such as '0.5h' or '250000n', or None; "
            f"got {type(value).__name__}"
        )
    if isinstance(value, str):
        match = _BOUND.match(value)
        if match is None:
            raise ValueError(
                f"{name}={value!r} is not a time: seconds ('1200', '1200s'), minutes ('90min'), "
                "hours ('0.5h') or a sample index ('250000n')"
            )
        number, unit = match.group("number"), match.group("unit")
        if unit == "n":
            if not re.fullmatch(r"\+?\d+", number):
                raise ValueError(
                    f"{name}={value!r}: a sample index is a non-negative integer before 'n'"
                )
            return TimeBound(index=int(number), text=value)
        seconds = float(number) * _SECONDS_PER[unit]
    else:
        seconds = float(value)
    if not math.isfinite(seconds):
        raise ValueError(f"{name}={value!r} must be finite")
    if seconds < 0:
        raise ValueError(f"{name}={value!r} must be >= 0 (seconds from the log's start)")
    return TimeBound(seconds=seconds + 0.0, text=value if isinstance(value, str) else None)


def _format_seconds(seconds: float | None, unit: str | None = None) -> str:
    """``seconds`` in ``unit`` (default: s below 2 min, min below 2 h, else h), 4 digits."""
    if seconds is None:
        return "?"
    unit = unit or _duration_unit(seconds)
    return f"{seconds / _SECONDS_PER[unit]:.4g} {unit}"


def _duration_unit(seconds: float) -> str:
    return "s" if seconds < 120 else "min" if seconds < 7200 else "h"


@dataclass(frozen=True)
class Selection:
    """The span of a log that :meth:`GyroLog.select` kept, in the log as read.

    Attributes
    ----------
    start_s, stop_s : float or None
        Seconds from the start of the log as read to the first selected sample, and to the end
        of the span (the first sample after it, or the end of the log); ``None`` without
        timestamps and sample rate.
    start_index, stop_index : int
        The selected samples are rows ``start_index … stop_index - 1`` of the log as read.
    total_s : float or None
        Length of the log as read, s (to the end of its last sample's interval).
    total_samples : int
        Number of samples of the log as read.
    """

    start_s: float | None
    stop_s: float | None
    start_index: int
    stop_index: int
    total_s: float | None
    total_samples: int

    @property
    def n_samples(self) -> int:
        """Number of selected samples."""
        return self.stop_index - self.start_index

    @property
    def duration_s(self) -> float | None:
        """Length of the span, s."""
        if self.start_s is None or self.stop_s is None:
            return None
        return self.stop_s - self.start_s

    @property
    def whole(self) -> bool:
        """``True`` when every sample of the log is selected."""
        return self.start_index == 0 and self.stop_index == self.total_samples

    def describe(self) -> str:
        """``"0.5–2.3 h of 2.8 h"`` (in one unit, that of the whole log), or sample indices."""
        if self.start_s is None or self.stop_s is None or self.total_s is None:
            return f"samples {self.start_index}–{self.stop_index} of {self.total_samples}"
        unit = _duration_unit(self.total_s)
        scale = _SECONDS_PER[unit]
        return (
            f"{self.start_s / scale:.4g}–{self.stop_s / scale:.4g} {unit} of "
            f"{self.total_s / scale:.4g} {unit}"
        )

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dictionary (seconds, 0-based sample indices)."""
        return {
            "start_s": self.start_s,
            "stop_s": self.stop_s,
            "start_index": self.start_index,
            "stop_index": self.stop_index,
            "n_samples": self.n_samples,
            "total_s": self.total_s,
            "total_samples": self.total_samples,
            "text": self.describe(),
        }

    def __str__(self) -> str:
        text = self.describe()
        if text.startswith("samples"):
            return text
        return f"{text} (samples {self.start_index}–{self.stop_index} of {self.total_samples})"
