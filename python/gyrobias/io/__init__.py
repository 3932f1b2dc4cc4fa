"""Reading IMU logs (CSV/TSV/text, ``.npy``, ROS1/ROS2 bags, MCAP) with sampling checks.

:func:`load` returns a :class:`GyroLog`: the selected channels as an ``(n, k)`` float64 array,
their names and units, the sample rate, the time vector (if the log has one) and a
:class:`SamplingReport`. Allan analysis assumes uniform sampling, so the loader does not
silently assume a rate: when the log carries timestamps it estimates the rate from the
intervals and reports jitter, gaps (positions and sizes), repeated and out-of-order stamps,
and a user-given ``fs`` that disagrees with the timestamps. Out-of-order stamps are an error
unless ``repair="sort"`` is asked for; every repair is stated in the report's warnings.

Formats (chosen by the file name):

- CSV/TSV/whitespace-separated text, also ``.gz``/``.bz2``/``.xz``: the columns by header name
  (or ``col<i>``), time from a ``t``/``time``/``timestamp`` column; units from ``units=``.
- ``.npy`` (1-D or 2-D): columns ``col<i>``, time from ``time_column=``.
- ROS1 ``.bag``, ROS2 bag directories (sqlite3 or MCAP storage), ``.db3`` and ``.mcap`` files: a
  ``sensor_msgs/Imu`` topic as ``gyro_x``, ``gyro_y``, ``gyro_z`` in rad/s and ``accel_x``,
  ``accel_y``, ``accel_z`` in m/s², time from ``header.stamp`` (or the receive time).

Logs larger than memory
-----------------------
``spill=True`` (``None``: when the samples exceed a quarter of the memory) puts the samples,
the raw stamps and the time vector in memory-mapped, already unlinked temporary files, written
block by block; a float64 ``.npy`` is mapped directly. A bag is decoded batch by batch
(65 536 messages) into that spill file rather than fed to the Allan analysis message by
message, by design: the out-of-core Allan kernel (``_core.allan.analyse_stream``) reads its
source several times and at several places at once (the mean, the integration constants,
then every τ's windows ``x[c]``, ``x[c+m]``, ``x[c+2m]`` through up to 13 cursors per pass, then
the noise identification), so a bag as source would be decompressed and deserialised a dozen
times or more, while the spill file is a decoded float64 copy (48 bytes per message for six
channels, a fraction of a ``sensor_msgs/Imu`` message) that the kernel reads with bounded
memory. Not bounded yet: the sampling report's statistics take full-length temporaries of the
intervals (the exact median needs them), about one time column each.

Examples
--------
>>> import gyrobias, tempfile, pathlib
>>> path = pathlib.Path(tempfile.mkdtemp()) / "log.csv"
>>> _ = path.write_text("t,gx\\n0.00,0.1\\n0.01,0.2\\n0.02,0.1\\n0.03,0.3\\n")
>>> log = gyrobias.io.load(path, columns=["gx"], time_column="t", units="deg/s")
>>> log.columns, log.units, log.fs, log.data.shape
(('gx',), ('deg/s',), 100.0, (4, 1))
"""

from __future__ import annotations

import bz2
import gzip
import lzma
import math
import os
import re
import zlib
from collections.abc import Callable, Iterator, Mapping, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

from gyrobias._validation import choice, sample_rate
from gyrobias.io import _bag
from gyrobias.io._store import Sink, Store, blocks

__all__ = ["GyroLog", "SamplingReport", "load", "topics"]

#: Intervals longer than this multiple of the median interval count as gaps.
GAP_FACTOR = 1.5
#: A user-given ``fs`` differing from the timestamps' estimate by more than this (relative) is reported.
FS_TOLERANCE = 0.01
#: Relative jitter (s.d. of the regular intervals / median interval) above which a warning is given.
JITTER_WARN = 0.01
#: ``time_unit="auto"`` reads timestamps as nanoseconds when the median interval is at least this.
NS_THRESHOLD = 1e3

_PER_SECOND = {"s": 1.0, "ms": 1e3, "us": 1e6, "ns": 1e9}
_TIME_UNITS = ("auto", "s", "ms", "us", "ns")
_TIME_NAMES = (
    "t",
    "time",
    "timestamp",
    "times",
    "time_s",
    "t_s",
    "time_ns",
    "t_ns",
    "timestamp_ns",
    "time_us",
    "t_us",
    "timestamp_us",
    "time_ms",
    "t_ms",
    "timestamp_ms",
)
_OPENERS: dict[str, Any] = {".gz": gzip.open, ".bz2": bz2.open, ".xz": lzma.open}  # as np.loadtxt
_INT_RE = re.compile(r"^[+-]?\d+$")
_LOADTXT_CELL = re.compile(r"could not convert string '(.*)' to \w+ at row (\d+), column (\d+)")
_LOADTXT_COLS = re.compile(r"number of columns changed from (\d+) to (\d+) at row (\d+)")
_LOADTXT_INDEX = re.compile(r"invalid column index (\d+) at row (\d+) with (\d+) columns")


@dataclass(frozen=True)
class SamplingReport:
    """What the timestamps (or their absence) say about the sampling of a log.

    Attributes
    ----------
    n_samples : int
        Number of samples (rows).
    fs : float or None
        Sample rate used for the log, Hz (user-given, else estimated; ``None`` if neither).
    fs_source : {"user", "timestamps", None}
        Where ``fs`` came from.
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
        """One channel by name, as a 1-D view."""
        try:
            return self.data[:, self.columns.index(name)]
        except ValueError:
            raise KeyError(f"no channel {name!r}; channels are {', '.join(self.columns)}") from None


ColumnSpec = str | int
UnitSpec = str | Sequence[str | None] | Mapping[str, str]

_REPAIRS = ("sort", "dedup")
_STAMPS = ("header", "receive")


def load(
    path: str | os.PathLike[str],
    *,
    columns: Sequence[ColumnSpec] | str | None = None,
    time_column: ColumnSpec | Literal[False] | None = None,
    time_unit: str = "auto",
    fs: float | None = None,
    delimiter: str | None = None,
    skip_rows: int = 0,
    comments: str = "#",
    units: UnitSpec | None = None,
    topic: str | None = None,
    stamp: str = "header",
    repair: str | Sequence[str] = (),
    fill_gaps: bool = False,
    spill: bool | None = False,
    spill_dir: str | os.PathLike[str] | None = None,
    progress: Callable[[float], None] | None = None,
) -> GyroLog:
    """Load an IMU log: CSV/TSV/whitespace text, ``.npy``, a ROS1/ROS2 bag or an MCAP file.

    Parameters
    ----------
    path : str or path-like
        The file (or ROS2 bag directory). ``.npy`` files hold a 1-D or 2-D numeric array
        (rows = samples); ``.bag``, ``.mcap``, ``.db3`` and directories with a
        ``metadata.yaml`` are bags; anything else is read as delimited text.
    columns : sequence of str/int, or comma-separated str, optional
        Channels to load, by name or 0-based column index (``"col2"`` or ``"2"`` also work
        for index 2). For bags the names are ``gyro_x``, ``gyro_y``, ``gyro_z``, ``accel_x``,
        ``accel_y``, ``accel_z`` (``"gyro"`` and ``"accel"`` stand for three each). Default:
        every column except the time column; all six bag channels.
    time_column : str or int, optional
        Column of timestamps (text and ``.npy``). Default ``None`` uses a header column named
        ``t``, ``time``, ``timestamp`` (optionally with a ``_s``/``_ms``/``_us``/``_ns``
        suffix; case-insensitive) if there is one; ``False`` means the log has no time column.
    time_unit : {"auto", "s", "ms", "us", "ns"}
        Unit of the timestamps. ``"auto"``: a ``_s``/``_ms``/``_us``/``_ns`` suffix of the
        column name decides; otherwise nanoseconds if the median interval is ≥ 1000 (no gyro
        log has samples 1000 s apart, and every rate below 1 MHz is ≥ 1000 ns apart), else
        seconds. Millisecond or microsecond stamps without such a suffix need ``time_unit``.
    fs : float, optional
        Sample rate in Hz. Required when there is no time column; with one, a value
        differing by more than 1 % from the timestamps' estimate is reported in the warnings
        (and ``fs`` is still used).
    delimiter : str, optional
        Field separator. Default: detected among ``,`` ``;`` tab and whitespace.
    skip_rows : int
        Lines to skip at the top of a text file before the header / first data row.
    comments : str
        Lines starting with this are ignored in text files.
    units : str, sequence of str, or mapping, optional
        Unit of the samples (``"deg/s"``, ``"rad/s"``, ``"g"``, ``"m/s^2"``, …; see
        :mod:`gyrobias.units`): one unit for every channel, one per channel (a sequence or a
        comma-separated string), or ``{channel: unit}`` (also ``"gx=deg/s,ax=g"``). Bags
        carry their units (rad/s, m/s²); a different ``units`` for a bag is an error.
    topic : str, optional
        Bag topic to read (a ``sensor_msgs/Imu`` topic). Default: the only IMU topic; with
        none or several, the error lists every topic with its type and message count.
    stamp : {"header", "receive"}
        Bag timestamps: the messages' ``header.stamp`` (default) or the time the recorder
        received them.
    repair : str or sequence of {"sort", "dedup"}
        ``"sort"``: put out-of-order samples in timestamp order (stable); ``"dedup"``: drop
        samples repeating the previous one exactly (same timestamp and values). Each repair
        made is stated in the report's ``repairs`` and ``warnings``. Without ``"sort"``,
        out-of-order timestamps are an error.
    fill_gaps : bool
        Insert NaN rows for the samples missing in the gaps of the timestamps (an interval of
        ``g`` median intervals holds ``round(g) − 1`` missing samples), so that the samples
        after a gap keep their place in time; their times are spaced evenly across the gap.
        Needs a time column. NaN marks the gaps for gap-aware analyses.
    spill : bool or None
        ``True``: put the data in a memory-mapped temporary file (``GyroLog.data`` is then a
        :class:`numpy.memmap`, and the file vanishes with the array); ``None``: do so when the
        data would take more than a quarter of the physical memory; ``False`` (default):
        keep it in memory. For a float64 ``.npy`` whose columns are all loaded, spilling maps
        the file itself (read-only) instead of copying it.
    spill_dir : path-like, optional
        Directory of the temporary file (default: the system's temporary directory).
    progress : callable, optional
        Called with the fraction read (0..1) during long reads (text and bags).

    Returns
    -------
    GyroLog

    Raises
    ------
    FileNotFoundError
        ``path`` does not exist.
    ValueError
        Not a regular file (pipe, device) or directory; empty file or no data rows;
        unknown column (the available ones are listed); a cell that is not a number (line
        and column given); NaN or infinite values (where); rows with a different number of
        fields; out-of-order timestamps without ``repair="sort"`` (the row); a time column
        among the channels; an unreadable, corrupt or truncated bag, or one without a unique
        IMU topic (every topic listed); bad option values.
    ImportError
        A bag without the ``rosbags`` package (``pip install 'gyrobias[io]'``).

    Notes
    -----
    Rows are reported 1-based as *lines of the file* in text errors (``line 12``) and as
    0-based data-row indices in :class:`SamplingReport`. Gaps are intervals
    ``Δt > 1.5 · median(Δt)``; the regular intervals are ``0 < Δt ≤ 1.5 · median(Δt)``; the
    estimated rate is ``fs = 1 / mean(regular Δt)`` and the jitter ``std(regular Δt) /
    median(Δt)``. Integer timestamps are read as int64, so epoch nanoseconds keep their
    exact intervals. Delimited text is parsed by pyarrow's streaming CSV reader when pyarrow
    is installed (``gyrobias[io]``; about 4× faster than :func:`numpy.loadtxt`, see
    ``benches/python/bench_io.py``; 4 MB blocks, written into one preallocated array),
    with :func:`numpy.loadtxt` for whitespace-separated or compressed files and for any
    file pyarrow rejects (comment lines between the rows, bad cells: the error then
    names the line and column). Bags are read in batches of 65 536 messages; messages of
    the standard layout are decoded at fixed byte offsets, others by ``rosbags``.
    """
    p = Path(os.fspath(path))
    if not p.exists():
        raise FileNotFoundError(f"no such file: '{p}'")
    choice("time_unit", time_unit, _TIME_UNITS)
    choice("stamp", stamp, _STAMPS)
    if fs is not None:
        fs = sample_rate(fs)
    if isinstance(skip_rows, bool) or not isinstance(skip_rows, (int, np.integer)) or skip_rows < 0:
        raise ValueError(f"skip_rows must be an integer >= 0, got {skip_rows!r}")
    repairs = _repair_options(repair)
    if spill is not None and not isinstance(spill, (bool, np.bool_)):
        raise TypeError(f"spill must be True, False or None, got {spill!r}")
    if isinstance(columns, str):
        columns = [c.strip() for c in columns.split(",") if c.strip()]
        if not columns:
            raise ValueError("columns is empty")
    elif columns is not None:
        columns = list(columns)
        if not columns:
            raise ValueError("columns is empty")
    store = Store(
        None if spill is None else bool(spill), None if spill_dir is None else os.fspath(spill_dir)
    )

    topic_used: str | None = None
    file_units: tuple[str | None, ...] | None = None
    line_of: Any = None
    t_raw: NDArray[Any] | None
    t_name: str | None
    if _bag.is_bag(p):
        for name, value, default in (
            ("time_column", time_column, None),
            ("delimiter", delimiter, None),
            ("skip_rows", skip_rows, 0),
        ):
            if value != default:
                raise ValueError(f"{name} does not apply to bags ({p.name}); see topic= and stamp=")
        if time_unit not in ("auto", "ns"):
            raise ValueError(
                f"time_unit does not apply to bags ({p.name}): their stamps are nanoseconds"
            )
        data6, t_raw, t_name, topic_used, fmt = _bag.read_bag(
            p,
            topic,
            stamp,
            progress,
            lambda n: store.empty(n, 6),
            allocate_stamps=lambda n: store.vector(n, np.int64),
        )
        idx, _ = _select(_expand_groups(columns), False, _bag.CHANNELS, 6, p.name)
        table = data6 if idx == list(range(6)) else _take_columns(data6, idx, store)
        names = [_bag.CHANNELS[i] for i in idx]
        file_units = tuple(_bag.UNITS[i] for i in idx)
        time_unit = "ns"
    elif p.is_dir():
        raise ValueError(
            f"'{p}' is a directory, not a log file (a ROS2 bag directory has a metadata.yaml)"
        )
    elif not p.is_file():
        raise ValueError(
            f"'{p}' is not a regular file (a pipe or a device?); save the log to a file first"
        )
    elif topic is not None or stamp != "header":
        raise ValueError(f"topic= and stamp= apply to bags only, and {p.name} is not one")
    elif p.suffix.lower() == ".npy":
        table, names, t_raw, t_name = _read_npy(p, columns, time_column, store)
        fmt = "npy"
    else:
        try:
            table, names, t_raw, t_name, line_of = _read_text(
                p,
                columns,
                time_column,
                time_unit,
                delimiter,
                int(skip_rows),
                comments,
                store,
                progress,
            )
        except PermissionError:
            raise
        except (
            OSError,
            EOFError,
            lzma.LZMAError,
            zlib.error,
        ) as exc:  # corrupt/truncated .gz/.bz2/.xz
            raise ValueError(
                f"{p.name}: cannot read the file ({' '.join(str(exc).split())})"
            ) from None
        fmt = "text"
    unit_tuple = _resolve_units(units, names, file_units, p.name)

    _check_finite(p, table, names, line_of)

    time = time_start = None
    if t_raw is None:
        if repairs or fill_gaps:
            what = "repair" if repairs else "fill_gaps"
            raise ValueError(f"{what} needs timestamps, and {p.name} has no time column")
        report = SamplingReport(
            n_samples=len(table), fs=fs, fs_source=None if fs is None else "user", source_format=fmt
        )
    else:
        assert t_name is not None
        t_raw, table, fixes = _repair(p, t_raw, table, t_name, repairs, line_of, store)
        time, intervals, time_start, unit_used, guessed = _time_seconds(
            p, t_raw, t_name, time_unit, line_of, store
        )
        t_raw = None  # the raw stamps are no longer needed (long logs: free them now)
        report = _sampling_report(
            len(table),
            time,
            intervals,
            unit_used,
            fs,
            unit_guessed=guessed,
            fixes=fixes,
            source_format=fmt,
            filling=fill_gaps,
        )
        del intervals
        if fill_gaps and report.n_gaps:
            table, time, report = _fill_gaps(table, time, report, store)
    return GyroLog(
        data=table,
        columns=tuple(names),
        fs=report.fs,
        time=time,
        time_start=time_start,
        time_column=t_name,
        path=p,
        sampling=report,
        units=unit_tuple,
        topic=topic_used,
    )


def topics(path: str | os.PathLike[str]) -> list[tuple[str, str, int]]:
    """Topics of a ROS1/ROS2 bag or MCAP file: ``(name, message type, message count)``, by name.

    Raises
    ------
    FileNotFoundError
        ``path`` does not exist.
    ValueError
        Not a bag, or unreadable.
    """
    p = Path(os.fspath(path))
    if not p.exists():
        raise FileNotFoundError(f"no such file: '{p}'")
    if not _bag.is_bag(p):
        raise ValueError(f"{p.name} is not a bag (.bag, .mcap, .db3 or a ROS2 bag directory)")
    return _bag.topics(p)


# --------------------------------------------------------------------------- helpers


def _repair_options(repair: str | Sequence[str]) -> tuple[str, ...]:
    items = [r.strip() for r in repair.split(",")] if isinstance(repair, str) else list(repair)
    out = []
    for r in items:
        if r == "":
            continue
        choice("repair", r, _REPAIRS)
        out.append(r)
    return tuple(dict.fromkeys(out))


def _expand_groups(columns: Sequence[ColumnSpec] | None) -> list[ColumnSpec] | None:
    """``"gyro"``/``"accel"`` → their three bag channels."""
    if columns is None:
        return None
    out: list[ColumnSpec] = []
    for c in columns:
        if isinstance(c, str) and c.strip() in ("gyro", "accel"):
            out += [f"{c.strip()}_{a}" for a in "xyz"]
        else:
            out.append(c)
    return out


def _take_columns(
    src: NDArray[np.float64], idx: Sequence[int], store: Store
) -> NDArray[np.float64]:
    """``src[:, idx]`` copied block by block into a store array."""
    out = store.empty(src.shape[0], len(idx))
    for sl in blocks(src.shape[0]):
        out[sl] = src[sl][:, list(idx)]
    return out


def _resolve_units(
    units: UnitSpec | None,
    names: Sequence[str],
    file_units: tuple[str | None, ...] | None,
    source: str,
) -> tuple[str | None, ...]:
    """Per-channel units from ``units=`` (validated) and the file's own units."""
    from gyrobias.units import parse_unit

    k = len(names)
    given: list[str | None] | None = None
    if units is not None:
        if isinstance(units, str):
            items = [u.strip() for u in units.split(",")]
            if all("=" in u for u in items):
                units = dict(u.split("=", 1) for u in items)
            elif len(items) == 1:
                given = [items[0]] * k
            else:
                given = list(items)
        if isinstance(units, Mapping):
            mapping = {str(key).strip(): str(v).strip() for key, v in units.items()}
            unknown = [key for key in mapping if key not in names]
            if unknown:
                raise ValueError(
                    f"units names channel(s) {', '.join(unknown)} not loaded; channels: {', '.join(names)}"
                )
            given = [mapping.get(n) for n in names]
        elif given is None:
            given = [None if u is None else str(u) for u in units]
        if len(given) != k:
            raise ValueError(
                f"units has {len(given)} entries for {k} channels ({', '.join(names)})"
            )
        for u in given:
            if u is not None:
                try:
                    parse_unit(u)
                except ValueError as exc:
                    raise ValueError(f"units: {exc}") from None
    if file_units is not None:
        if given is not None:
            for n, u, f in zip(names, given, file_units):
                if u is not None and f is not None and parse_unit(u) != parse_unit(f):
                    raise ValueError(
                        f"units: {source} stores {n} in {f} (sensor_msgs/Imu), not {u}; leave units unset for bags"
                    )
        return file_units
    return tuple(given) if given is not None else (None,) * k


def _check_finite(p: Path, table: NDArray[np.float64], names: Sequence[str], line_of: Any) -> None:
    """NaN/inf anywhere is an error naming the first place (block by block: memmaps stay bounded)."""
    first: tuple[int, int] | None = None
    total = 0
    for sl in blocks(table.shape[0]):
        bad = ~np.isfinite(table[sl])
        count = int(bad.sum())
        if count:
            total += count
            if first is None:
                r, c = (int(i) for i in np.argwhere(bad)[0])
                first = (sl.start + r, c)
    if first is not None:
        row, col = first
        where = f"line {line_of(row)}" if line_of else f"row {row}"
        raise ValueError(
            f"{p.name}: {table[row, col]} in column '{names[col]}' at {where} "
            f"({total} non-finite value(s) in all); clean or interpolate the log first"
        )


def _resolve(
    spec: ColumnSpec, header: Sequence[str] | None, n_cols: int, what: str, source: str
) -> int:
    """0-based index of the column ``spec`` (a name, an index, ``"col<i>"`` or ``"<i>"``)."""
    available = list(header) if header is not None else [f"col{i}" for i in range(n_cols)]
    if isinstance(spec, (int, np.integer)) and not isinstance(spec, bool):
        if 0 <= spec < n_cols:
            return int(spec)
        raise ValueError(
            f"{what} index {spec} out of range: {source} has {n_cols} columns (0..{n_cols - 1})"
        )
    if not isinstance(spec, str):
        raise TypeError(f"{what} must be a column name or integer index, got {type(spec).__name__}")
    name = spec.strip()
    if header is not None:
        hits = [i for i, h in enumerate(header) if h == name]
        if len(hits) > 1:
            raise ValueError(f"{what} '{name}' is ambiguous: the header has it at columns {hits}")
        if hits:
            return hits[0]
    m = re.fullmatch(r"(?:col)?(\d+)", name)
    if m and int(m.group(1)) < n_cols:
        return int(m.group(1))
    raise ValueError(f"unknown {what} '{name}' in {source}; available: {', '.join(available)}")


def _select(
    columns: Sequence[ColumnSpec] | None,
    time_column: ColumnSpec | Literal[False] | None,
    header: Sequence[str] | None,
    n_cols: int,
    source: str,
) -> tuple[list[int], int | None]:
    """Indices of the channels and of the time column."""
    t_idx: int | None = None
    if time_column is None:
        if header is not None:
            for i, h in enumerate(header):
                if h.lower() in _TIME_NAMES:
                    t_idx = i
                    break
    elif time_column is not False:
        t_idx = _resolve(time_column, header, n_cols, "time column", source)
    if columns is None:
        idx = [i for i in range(n_cols) if i != t_idx]
        if not idx:
            raise ValueError(f"{source} has no data columns besides the time column")
    else:
        idx = [_resolve(c, header, n_cols, "column", source) for c in columns]
        if t_idx is not None and t_idx in idx:
            if time_column is None:  # auto-detected: the user asked for it as data, so it is data
                t_idx = None
            else:
                raise ValueError("the time column is also listed in columns")
        dup = {i for i in idx if idx.count(i) > 1}
        if dup:
            raise ValueError(f"columns lists column(s) {sorted(dup)} more than once")
    return idx, t_idx


def _read_npy(
    p: Path,
    columns: Sequence[ColumnSpec] | None,
    time_column: ColumnSpec | Literal[False] | None,
    store: Store,
) -> tuple[NDArray[np.float64], list[str], NDArray[Any] | None, str | None]:
    try:
        arr = np.load(p, mmap_mode="r", allow_pickle=False)
    except (ValueError, OSError, EOFError) as exc:
        raise ValueError(f"{p.name}: not a readable .npy file ({exc})") from None
    if arr.dtype.kind not in "iuf":
        raise ValueError(f"{p.name}: array dtype {arr.dtype} is not real numeric")
    if arr.ndim == 1:
        arr = arr.reshape(-1, 1)
    if arr.ndim != 2:
        raise ValueError(
            f"{p.name}: expected a 1-D or 2-D array (samples × channels), got shape {arr.shape}"
        )
    if arr.shape[0] == 0 or arr.shape[1] == 0:
        raise ValueError(f"{p.name}: the array is empty (shape {arr.shape})")
    idx, t_idx = _select(columns, time_column, None, arr.shape[1], p.name)
    names = [f"col{i}" for i in idx]
    t_name = None if t_idx is None else f"col{t_idx}"
    whole = idx == list(range(arr.shape[1]))
    t_raw = None
    if t_idx is not None:  # a copy (the time column leaves the file), spilled with the samples
        store.spilled = store.spilled or store.wants_spill(arr.shape[0] * len(idx) * 8)
        t_raw = store.vector(arr.shape[0], arr.dtype.type)
        for sl in blocks(arr.shape[0]):
            t_raw[sl] = arr[sl, t_idx]
    if (
        store.wants_spill(arr.shape[0] * len(idx) * 8)
        and whole
        and arr.dtype == np.dtype(np.float64)
        and isinstance(arr, np.memmap)
        and arr.flags.c_contiguous
    ):
        store.spilled = True
        return arr, names, t_raw, t_name  # the file itself, mapped read-only
    table = store.empty(arr.shape[0], len(idx))
    for sl in blocks(arr.shape[0]):
        table[sl] = arr[sl][:, idx] if not whole else arr[sl]
    del arr
    return table, names, t_raw, t_name


def _content_lines(p: Path, skip_rows: int, comments: str) -> Iterator[tuple[int, str]]:
    """(1-based line number, stripped text) of non-blank, non-comment lines after ``skip_rows``."""
    opener = _OPENERS.get(p.suffix.lower(), open)
    with opener(p, "rt", encoding="utf-8-sig", errors="replace") as fh:
        for number, line in enumerate(fh, start=1):
            if number <= skip_rows:
                continue
            text = line.strip()
            if not text or (comments and text.startswith(comments)):
                continue
            yield number, text


def _split(line: str, delimiter: str | None) -> list[str]:
    return [f.strip().strip("\"'") for f in (line.split(delimiter) if delimiter else line.split())]


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def _detect_delimiter(lines: list[str]) -> str | None:
    """The first of ``;``, tab, ``,`` that occurs in every sample line, else ``None`` (whitespace).

    ``;`` and tab come first: where they separate fields, a comma is a decimal separator
    (which is then reported as a non-numeric cell), never the other way round. Lines with a
    different number of fields are reported by the parser, naming the line.
    """
    for cand in (";", "\t", ","):
        if all(cand in line for line in lines):
            return cand
    return None


def _read_text(
    p: Path,
    columns: Sequence[ColumnSpec] | None,
    time_column: ColumnSpec | Literal[False] | None,
    time_unit: str,
    delimiter: str | None,
    skip_rows: int,
    comments: str,
    store: Store,
    progress: Callable[[float], None] | None,
) -> tuple[NDArray[np.float64], list[str], NDArray[Any] | None, str | None, Any]:
    sample: list[tuple[int, str]] = []
    for item in _content_lines(p, skip_rows, comments):
        sample.append(item)
        if len(sample) >= 20:
            break
    if not sample:
        raise ValueError(f"{p.name}: the file is empty (no data rows)")
    if delimiter is None:
        delimiter = _detect_delimiter([s for _, s in sample])
    first_fields = _split(sample[0][1], delimiter)
    has_header = not all(_is_number(f) for f in first_fields)
    header = first_fields if has_header else None
    data_start = sample[1][0] if has_header and len(sample) > 1 else sample[0][0]
    if has_header and len(sample) == 1:
        raise ValueError(
            f"{p.name}: the file has a header ({', '.join(first_fields)}) but no data rows"
        )
    n_cols = len(_split(sample[1 if has_header else 0][1], delimiter))
    if header is not None and len(header) != n_cols:
        raise ValueError(
            f"{p.name}: the header has {len(header)} names but line {data_start} has {n_cols} fields"
        )
    idx, t_idx = _select(columns, time_column, header, n_cols, p.name)
    names = [header[i] if header is not None else f"col{i}" for i in idx]
    t_name = None if t_idx is None else (header[t_idx] if header is not None else f"col{t_idx}")

    def line_of(row: int) -> int:
        """File line (1-based) of data row ``row`` (0-based); scans the file, error path only."""
        for k, (number, _) in enumerate(
            item for item in _content_lines(p, skip_rows, comments) if item[0] >= data_start
        ):
            if k == row:
                return number
        return -1

    usecols = ([t_idx] if t_idx is not None else []) + idx
    first_data = _split(sample[1 if has_header else 0][1], delimiter)
    int_time = t_idx is not None and bool(_INT_RE.match(first_data[t_idx])) and time_unit != "s"
    if int_time and t_idx is not None:  # every sampled stamp must be an integer, not just the first
        for number, text in sample:
            fields = _split(text, delimiter)
            if number >= data_start and len(fields) > t_idx and not _INT_RE.match(fields[t_idx]):
                int_time = False
    if delimiter is not None and len(delimiter) == 1 and p.suffix.lower() not in _OPENERS:
        data_lines = [text for number, text in sample if number >= data_start]
        mean_line = (sum(len(t) for t in data_lines) + len(data_lines)) / max(len(data_lines), 1)
        estimated_rows = int(p.stat().st_size / max(mean_line, 1.0)) + 1
        for as_int in (True, False) if int_time else (False,):
            fast = _read_arrow(
                p,
                delimiter,
                data_start,
                n_cols,
                t_idx,
                idx,
                as_int,
                store,
                progress,
                estimated_rows,
            )
            if fast is not None:
                return fast[1], names, fast[0], t_name, line_of
    kw: dict[str, Any] = {
        "delimiter": delimiter,
        "skiprows": data_start - 1,
        "comments": comments or None,
        "usecols": usecols,
        "ndmin": 2,
        "encoding": "utf-8-sig",
    }

    def col_name(file_col: int) -> str:
        """Name of 0-based file column ``file_col`` for messages."""
        return f"'{header[file_col]}'" if header is not None else f"{file_col}"

    if int_time:
        # integer stamps (typically epoch nanoseconds, ~1e18) are read exactly as int64: as
        # float64 they would carry a ±128 ns rounding error that shows up as jitter
        dtype = [("t", np.int64)] + [(f"c{k}", np.float64) for k in range(len(idx))]
        try:
            rec = _loadtxt(p, kw, dtype, col_name, line_of, int_column=t_idx)
        except _NotInteger:
            int_time = False
        else:
            rec = rec.reshape(-1)
            t_raw: NDArray[Any] | None = rec["t"].copy()
            table = np.empty((len(rec), len(idx)))
            for k in range(len(idx)):
                table[:, k] = rec[f"c{k}"]
            del rec
            return table, names, t_raw, t_name, line_of
    full = _loadtxt(p, kw, np.float64, col_name, line_of)
    if t_idx is not None:
        t_raw = full[:, 0].copy()
        table = np.ascontiguousarray(full[:, 1:])
    else:
        t_raw = None
        table = full
    del full
    return table, names, t_raw, t_name, line_of


def _line_offset(p: Path, line: int) -> int:
    """Byte offset of the start of 1-based ``line`` (counting lines as :func:`open` does)."""
    offset = 0
    with open(p, "rb") as fh:
        for _ in range(line - 1):
            chunk = fh.readline()
            if not chunk:
                break
            offset += len(chunk)
    return offset


def _read_arrow(
    p: Path,
    delimiter: str,
    data_start: int,
    n_cols: int,
    t_idx: int | None,
    idx: Sequence[int],
    int_time: bool,
    store: Store,
    progress: Callable[[float], None] | None,
    estimated_rows: int,
) -> tuple[NDArray[Any] | None, NDArray[np.float64]] | None:
    """Parse the data rows with pyarrow's streaming CSV reader: (raw times, table), or ``None``.

    ``None`` means "use numpy.loadtxt": pyarrow is missing, or it rejected the file (a bad
    cell, a ragged row, a comment line, a non-integer time); loadtxt then either reads it or
    reports the exact line and column. Nothing pyarrow reads differently from loadtxt is
    accepted: empty cells and NA spellings are not missing values here, and the rows start at
    the byte offset of the first data line (no row counting).
    """
    try:
        import pyarrow as pa  # type: ignore[import-untyped, unused-ignore]
        import pyarrow.csv as pacsv  # type: ignore[import-untyped, unused-ignore]
    except ImportError:
        return None
    names = [f"c{i}" for i in range(n_cols)]
    types = {names[i]: pa.float64() for i in idx}
    if t_idx is not None:
        types[names[t_idx]] = pa.int64() if int_time else pa.float64()
    include = ([names[t_idx]] if t_idx is not None else []) + [names[i] for i in idx]
    read_opts = pacsv.ReadOptions(column_names=names, block_size=1 << 22, use_threads=True)
    parse_opts = pacsv.ParseOptions(delimiter=delimiter, ignore_empty_lines=True)
    convert_opts = pacsv.ConvertOptions(
        column_types=types,
        include_columns=include,
        null_values=[],
        true_values=[],
        false_values=[],
        strings_can_be_null=False,
        quoted_strings_can_be_null=False,
    )
    sink = store.sink(len(idx), estimated_rows)
    # the raw stamps go to disk with the samples (a log larger than memory)
    stamps = Sink(store, 1, sink.spilled, estimated_rows, np.int64 if int_time else np.float64)
    try:
        source = pa.OSFile(str(p), "r")  # plain reads: a mapping would count the file as resident
        try:
            source.seek(_line_offset(p, data_start))
            reader = pacsv.open_csv(
                source,
                read_options=read_opts,
                parse_options=parse_opts,
                convert_options=convert_opts,
            )
            for batch in reader:
                m = batch.num_rows
                block = sink.reserve(m)
                for k, i in enumerate(idx):
                    block[:, k] = batch.column(names[i]).to_numpy()
                sink.commit(m)
                if t_idx is not None:
                    stamps.reserve(m)[:, 0] = batch.column(names[t_idx]).to_numpy()
                    stamps.commit(m)
                if progress is not None:
                    progress(min(sink.rows / estimated_rows, 0.99))
        finally:
            source.close()
    except (pa.ArrowException, ValueError, OSError):
        sink.finish()
        return None
    table = sink.finish()
    if table.shape[0] == 0:
        return None  # loadtxt reports the empty file in its words
    if progress is not None:
        progress(1.0)
    t_raw = None
    if t_idx is not None:
        t_raw = stamps.finish().reshape(-1)
    return t_raw, table


class _NotInteger(Exception):
    pass


def _loadtxt(
    p: Path,
    kw: dict[str, Any],
    dtype: Any,
    col_name: Any,
    line_of: Any,
    int_column: int | None = None,
) -> Any:
    """np.loadtxt with its errors turned into messages naming the file line and column.

    Raises ``_NotInteger`` when the ``int_column`` (0-based file column) holds a non-integer
    number, so that the caller can re-read it as float.
    """
    try:
        out = np.loadtxt(p, dtype=dtype, **kw)
    except ValueError as exc:
        msg = str(exc)
        m = _LOADTXT_CELL.search(msg)
        if m:
            text, row, col = m.group(1), int(m.group(2)), int(m.group(3))
            # numpy counts data rows from 0 (skipping comments) and file columns from 1
            if int_column is not None and col == int_column + 1 and _is_number(text):
                raise _NotInteger from None
            what = "an empty cell" if not text.strip() else f"'{text}' (not a number)"
            hint = ""
            if re.fullmatch(r"[+-]?\d+,\d+", text.strip()):
                hint = " (decimal commas are not supported)"
            raise ValueError(
                f"{p.name}: {what} in column {col_name(col - 1)} at line {line_of(row)}{hint}"
            ) from None
        m = _LOADTXT_COLS.search(msg)
        if m:
            raise ValueError(
                f"{p.name}: line {line_of(int(m.group(3)))} has {m.group(2)} fields, "
                f"the lines before it have {m.group(1)}"
            ) from None
        m = _LOADTXT_INDEX.search(msg)
        if m:  # this numpy message counts rows from 1
            raise ValueError(
                f"{p.name}: line {line_of(int(m.group(2)) - 1)} has only {m.group(3)} fields"
            ) from None
        raise ValueError(f"{p.name}: {msg}") from None
    except IndexError:
        raise ValueError(
            f"{p.name}: some line has fewer fields than the selected columns need"
        ) from None
    if len(out) == 0:
        raise ValueError(f"{p.name}: the file is empty (no data rows)")
    return out


def _time_seconds(
    p: Path, t_raw: NDArray[Any], t_name: str, time_unit: str, line_of: Any, store: Store
) -> tuple[NDArray[np.float64], NDArray[np.float64], float, str, bool]:
    """Timestamps (finite, in order: see :func:`_repair`) → seconds since the first sample.

    Returns ``(time, intervals, start, unit, guessed)``; ``time`` and ``intervals`` are
    written block by block into arrays spilled with the samples (no full-length temporary).
    """
    n = len(t_raw)
    unit = time_unit
    guessed = False
    if unit == "auto":
        m = re.search(r"_(s|ms|us|ns)$", t_name.lower())
        if m:
            unit = m.group(1)
        else:
            steps = np.diff(t_raw)  # exact in int64 for integer stamps
            positive = steps[steps > 0]
            del steps
            median = float(np.median(positive, overwrite_input=True)) if positive.size else 0.0
            del positive
            unit = "ns" if median >= NS_THRESHOLD else "s"
            guessed = True
    per_second = _PER_SECOND[unit]  # dividing by an exact power of ten rounds correctly
    # Block by block into arrays that are spilled with the samples (store.vector).
    # The intervals from the raw differences: exact for integer stamps, so a perfectly
    # regular nanosecond log has exactly zero jitter.
    first = t_raw[0]
    intervals = store.vector(max(n - 1, 0))
    # The raw stamps are the loader's own copy and not needed afterwards: the seconds overwrite
    # them in place when they are 8-byte numbers (int64 or float64), one column less at peak.
    in_place = t_raw.dtype in (np.dtype(np.int64), np.dtype(np.float64)) and t_raw.flags.writeable
    time = t_raw.view(np.float64) if in_place else store.vector(n)
    previous = None  # the raw stamp before the block (already overwritten in place)
    for sl in blocks(n):
        chunk = t_raw[sl]
        rel = chunk - first  # exact in int64 for integer stamps
        last = chunk[-1]
        if previous is not None:
            intervals[sl.start - 1] = (chunk[0] - previous) / per_second
        if chunk.size > 1:
            steps = np.diff(chunk).astype(np.float64)
            steps /= per_second
            intervals[sl.start : sl.stop - 1] = steps
        converted = rel.astype(np.float64) if rel.dtype != np.float64 else rel
        converted /= per_second
        time[sl] = converted
        previous = last
    return time, intervals, float(first) / per_second, unit, guessed


def _std_in_place(x: NDArray[np.float64]) -> float:
    """``np.std(x)`` computed in ``x`` itself (overwritten): the same operations in the same
    order as NumPy's ``_var`` (sum / n, subtract, square, sum / n, sqrt), hence the same bits,
    without its full-length temporary."""
    mean = np.add.reduce(x) / x.size
    x -= mean
    np.multiply(x, x, out=x)
    return math.sqrt(np.add.reduce(x) / x.size)


def _sampling_report(
    n: int,
    time: NDArray[np.float64],
    steps: NDArray[np.float64],
    unit: str,
    fs: float | None,
    *,
    unit_guessed: bool = False,
    fixes: _Fixes | None = None,
    source_format: str | None = None,
    filling: bool = False,
) -> SamplingReport:
    fixes = fixes if fixes is not None else _Fixes()
    warnings: list[str] = list(fixes.repairs)
    duration = float(time[-1])
    dup_rows = np.flatnonzero(steps == 0) + 1
    positive = steps[steps > 0]
    if positive.size == 0:
        raise ValueError(
            f"the time column does not advance ({n} samples, all with the same timestamp)"
        )
    mean_positive = float(np.mean(positive))
    median = float(np.median(positive, overwrite_input=True))  # partitions in place: no copy
    del positive
    gap_mask = steps > GAP_FACTOR * median
    gap_rows = np.flatnonzero(gap_mask) + 1
    gap_durations = steps[gap_mask]
    regular_mask = steps > 0
    regular_mask &= ~gap_mask
    del gap_mask
    regular = steps[regular_mask]
    del regular_mask
    # the mean of the regular intervals: unaffected by gaps like the median, but not stuck on
    # one quantised interval value; 9 significant digits drop the decimal-rounding noise of
    # timestamps written as text (0.0100 → 100.00000000000213 Hz)
    fs_est = float(f"{1.0 / (float(np.mean(regular)) if regular.size else mean_positive):.9g}")
    jitter = _std_in_place(regular) / median if regular.size > 1 else 0.0
    del regular
    missing = int(np.sum(np.rint(gap_durations / median) - 1)) if gap_rows.size else 0

    if gap_rows.size:
        longest = int(np.argmax(gap_durations))
        warnings.append(
            f"{gap_rows.size} gap(s) in the timestamps (intervals > {GAP_FACTOR:g}× the median "
            f"{median:.6g} s): longest {gap_durations[longest]:.6g} s before row {gap_rows[longest]} "
            f"(t = {time[gap_rows[longest]]:.6g} s), ~{missing} sample(s) missing; "
            + (
                "filled with NaN rows (fill_gaps)"
                if filling
                else "the analysis treats the samples as uniformly spaced (fill_gaps=True / --fill-gaps marks them)"
            )
        )
    if dup_rows.size:
        warnings.append(
            f"{dup_rows.size} repeated timestamp(s) (zero intervals), first at row {dup_rows[0]}"
        )
    if fixes.exact_duplicate_rows.size:
        warnings.append(
            f"{fixes.exact_duplicate_rows.size} sample(s) repeat the previous one exactly (same "
            f"timestamp and values), first at row {fixes.exact_duplicate_rows[0]}; "
            "repair='dedup' (--repair dedup) drops them"
        )
    if jitter > JITTER_WARN:
        warnings.append(
            f"sampling jitter {100 * jitter:.3g} % (s.d. of the intervals / median interval) "
            f"exceeds {100 * JITTER_WARN:g} %"
        )
    if unit_guessed and unit == "s" and fs_est < 1.0:
        warnings.append(
            f"the timestamps, read as seconds, give fs = {fs_est:.6g} Hz; if they are milliseconds "
            "or microseconds, pass time_unit (--time-unit)"
        )
    source = "timestamps"
    if fs is not None:
        source = "user"
        if abs(fs - fs_est) > FS_TOLERANCE * fs_est:
            warnings.append(
                f"given fs = {fs:g} Hz disagrees with the timestamps ({fs_est:.6g} Hz) "
                f"by {100 * abs(fs - fs_est) / fs_est:.3g} %; using fs = {fs:g} Hz"
            )
    return SamplingReport(
        n_samples=n,
        fs=fs if fs is not None else fs_est,
        fs_source=source,
        fs_estimated=fs_est,
        median_interval=median,
        jitter=jitter,
        time_unit=unit,
        duration=duration,
        n_gaps=int(gap_rows.size),
        gap_rows=gap_rows.astype(np.int64),
        gap_durations=gap_durations.astype(np.float64),
        missing_samples=missing,
        n_duplicates=int(dup_rows.size),
        duplicate_rows=dup_rows.astype(np.int64),
        warnings=tuple(warnings),
        n_out_of_order=int(fixes.out_of_order_rows.size),
        out_of_order_rows=fixes.out_of_order_rows,
        n_exact_duplicates=int(fixes.exact_duplicate_rows.size + fixes.dropped),
        repairs=fixes.repairs,
        source_format=source_format,
    )


@dataclass(frozen=True)
class _Fixes:
    """What :func:`_repair` found and changed."""

    out_of_order_rows: NDArray[np.int64] = field(
        default_factory=lambda: np.zeros(0, dtype=np.int64)
    )
    exact_duplicate_rows: NDArray[np.int64] = field(
        default_factory=lambda: np.zeros(0, dtype=np.int64)
    )
    dropped: int = 0
    repairs: tuple[str, ...] = ()


def _take_rows(
    table: NDArray[np.float64], rows: NDArray[np.int64], store: Store
) -> NDArray[np.float64]:
    """``table[rows]`` copied block by block into a store array."""
    out = store.empty(len(rows), table.shape[1])
    for sl in blocks(len(rows)):
        out[sl] = table[rows[sl]]
    return out


def _repair(
    p: Path,
    t_raw: NDArray[Any],
    table: NDArray[np.float64],
    t_name: str,
    repairs: tuple[str, ...],
    line_of: Any,
    store: Store,
) -> tuple[NDArray[Any], NDArray[np.float64], _Fixes]:
    """Check the timestamps (finite, in order) and apply ``repair=``; never silently."""
    if t_raw.dtype.kind == "f":
        for sl in blocks(len(t_raw)):  # block by block: a spilled column stays on disk
            bad = np.flatnonzero(~np.isfinite(t_raw[sl]))
            if bad.size:
                row = sl.start + int(bad[0])
                where = f"line {line_of(row)}" if line_of else f"row {row}"
                raise ValueError(f"{p.name}: {t_raw[row]} in the time column '{t_name}' at {where}")
    done: list[str] = []
    back = _step_rows(t_raw, np.less)
    if back.size:
        row = int(back[0])
        if "sort" not in repairs:
            where = f"line {line_of(row)}" if line_of else f"row {row}"
            raise ValueError(
                f"{p.name}: timestamps out of order in '{t_name}' at {where} "
                f"({t_raw[row]} after {t_raw[row - 1]}; {back.size} backward step(s) in all); "
                "sort the log or fix its clock, or pass repair='sort' (--repair sort)"
            )
        order = np.argsort(t_raw, kind="stable")
        t_raw = _take_stamps(t_raw, order, store)
        table = _take_rows(table, order, store)
        done.append(
            f"sorted by timestamp: {back.size} sample(s) were earlier than the one before them, "
            f"the first at row {row} (repair='sort')"
        )
    exact = np.zeros(0, dtype=np.int64)
    cand = _step_rows(t_raw, np.equal)
    if cand.size:
        same = np.ones(cand.size, dtype=bool)
        for sl in blocks(cand.size):
            c = cand[sl]
            same[sl] = np.all(table[c] == table[c - 1], axis=1)
        exact = cand[same].astype(np.int64)
    dropped = 0
    if exact.size and "dedup" in repairs:
        keep = np.ones(len(t_raw), dtype=bool)
        keep[exact] = False
        rows = np.flatnonzero(keep)
        t_raw = _take_stamps(t_raw, rows, store)
        table = _take_rows(table, rows, store)
        done.append(
            f"dropped {exact.size} sample(s) repeating the previous one exactly (same timestamp "
            f"and values), the first at row {exact[0]} (repair='dedup')"
        )
        dropped, exact = int(exact.size), np.zeros(0, dtype=np.int64)
    return t_raw, table, _Fixes(back.astype(np.int64), exact, dropped, tuple(done))


def _take_stamps(t_raw: NDArray[Any], rows: NDArray[np.intp], store: Store) -> NDArray[Any]:
    """``t_raw[rows]`` in a new array of the store (spilled with the samples), block by block."""
    out = store.vector(len(rows), t_raw.dtype.type)
    for sl in blocks(len(rows)):
        out[sl] = t_raw[rows[sl]]
    return out


def _step_rows(t_raw: NDArray[Any], compare: Any) -> NDArray[np.intp]:
    """Rows ``i ≥ 1`` with ``compare(t[i] − t[i−1], 0)``, found block by block.

    Equal to ``np.flatnonzero(compare(np.diff(t_raw), 0)) + 1`` without a full-length
    difference array (the stamps of a spilled log stay on disk).
    """
    found = []
    for sl in blocks(len(t_raw)):
        lo = max(sl.start - 1, 0)
        steps = np.diff(t_raw[lo : sl.stop])
        found.append(np.flatnonzero(compare(steps, 0)) + lo + 1)
    return np.concatenate(found) if found else np.zeros(0, dtype=np.intp)


def _fill_gaps(
    table: NDArray[np.float64], time: NDArray[np.float64], report: SamplingReport, store: Store
) -> tuple[NDArray[np.float64], NDArray[np.float64], SamplingReport]:
    """Insert ``round(gap / median) − 1`` NaN rows into each gap, with evenly spaced times."""
    assert report.median_interval is not None
    n, k = table.shape
    missing = np.rint(report.gap_durations / report.median_interval).astype(np.int64) - 1
    missing = np.maximum(missing, 0)
    shift = np.zeros(n, dtype=np.int64)
    shift[report.gap_rows] = missing
    dest = np.arange(n, dtype=np.int64) + np.cumsum(shift)
    total = n + int(missing.sum())
    out = store.empty(total, k)
    for sl in blocks(total):
        out[sl] = np.nan
    for sl in blocks(n):
        out[dest[sl]] = table[sl]
    new_time = store.vector(total)
    new_time[dest] = time
    for row, count in zip(report.gap_rows.tolist(), missing.tolist()):
        t0, t1 = time[row - 1], time[row]
        new_time[dest[row - 1] + 1 : dest[row]] = t0 + (t1 - t0) * np.arange(1, count + 1) / (
            count + 1
        )
    note = f"inserted {int(missing.sum())} NaN row(s) for the samples missing in {report.n_gaps} gap(s) (fill_gaps)"
    report = replace(
        report,
        filled_samples=int(missing.sum()),
        repairs=(*report.repairs, note),
    )
    return out, new_time, report
