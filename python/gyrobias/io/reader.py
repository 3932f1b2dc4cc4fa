"""The loader: :func:`load` (text, ``.npy``, ROS1/ROS2 bags, MCAP) and :func:`topics`."""

from __future__ import annotations

import lzma
import os
import zlib
from collections.abc import Callable, Sequence
from dataclasses import replace
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

from gyrobias._validation import (
    callback,
    checked_path,
    choice,
    count,
    optional_path,
    sample_rate,
    sequence,
    text,
)
from gyrobias.io import _bag
from gyrobias.io._store import Store
from gyrobias.io._types import GyroLog
from gyrobias.io.columns import (
    ColumnSpec,
    UnitSpec,
    _check_finite,
    _expand_groups,
    _header_unit,
    _resolve_units,
    _select,
    _take_columns,
)
from gyrobias.io.npy import _read_npy
from gyrobias.io.text import _preamble_rate, _read_text
from gyrobias.io.timestamps import (
    _TIME_UNITS,
    _fill_gaps,
    _repair,
    _sampling_report,
    _time_seconds,
)

_REPAIRS = ("sort", "dedup")
_STAMPS = ("header", "receive")


def _column_spec(name: str, value: Any) -> None:
    """A column named by its header (one line of printable text) or by its index."""
    if isinstance(value, str):
        text(name, value)
    elif isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise TypeError(
            f"{name} must be a column name or integer index, got {type(value).__name__}"
        )


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
        suffix or the unit in parentheses or brackets, ``Timestamp (us)``, ``Time (s)``;
        case-insensitive) if there is one; ``False`` means the log has no time column.
    time_unit : {"auto", "s", "ms", "us", "ns"}
        Unit of the timestamps. ``"auto"``: a ``_s``/``_ms``/``_us``/``_ns`` suffix of the
        column name, or the unit in parentheses or brackets (``Timestamp (us)``), decides;
        otherwise the median interval: nanoseconds from 10⁵ (rates up to 10 kHz),
        microseconds from 1000 (10 Hz – 1 kHz: ``micros()`` clocks, x-io, YEI), else seconds.
        Millisecond stamps, and nanosecond stamps above 10 kHz, need ``time_unit``.
    fs : float, optional
        Sample rate in Hz. Required when there is no time column; with one, a value
        differing by more than 1 % from the timestamps' estimate is reported in the warnings
        (and ``fs`` is still used). Without either, the rate an Xsens-style preamble states
        (``// Sample rate: 120.0Hz``) is used (``sampling.fs_source == "file"``).
    delimiter : str, optional
        Field separator. Default: detected among ``,`` ``;`` tab and whitespace.
    skip_rows : int
        Lines to skip at the top of a text file before the header / first data row. A
        preamble of lines starting with ``//`` (Xsens MT Manager exports) is skipped anyway.
    comments : str
        Lines starting with this are ignored in text files.
    units : str, sequence of str, or mapping, optional
        Unit of the samples (``"deg/s"``, ``"rad/s"``, ``"g"``, ``"m/s^2"``, …; see
        :mod:`gyrobias.units`): one unit for every channel, one per channel (a sequence or a
        comma-separated string), or ``{channel: unit}`` (also ``"gx=deg/s,ax=g"``). Bags
        carry their units (rad/s, m/s²); a different ``units`` for a bag is an error. In
        a text file, a channel given no unit takes the one its header states at its end, as
        ``Gyroscope X (deg/s)`` or ``gx [rad/s]`` (x-io, Xsens and many loggers), when it is a
        known unit.
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
    exact intervals. Delimited text (``,`` ``;`` tab ``|`` ``:`` or whitespace, plain or
    ``.gz``/``.bz2``/``.xz``) is parsed by the core (``gyrocore::text``): read in 8 MiB
    chunks of whole lines, parsed on every core straight into the result array (or the
    spill file), numbers rounded correctly as by :func:`float`, with exactly the rows,
    columns and errors of :func:`numpy.loadtxt` (see ``benches/python/bench_io.py``
    for the speed). Files it does not read as loadtxt does (non-ASCII text, quoted
    cells, lone carriage returns, other delimiters) go to pyarrow's CSV reader when
    installed, then :func:`numpy.loadtxt`. Bags are read chunk by chunk by the core's reader
    (``sensor_msgs/Imu`` decoded in bulk from the ROS1/CDR bytes straight into the result:
    ROS1 and MCAP bags 6–25× faster than iterating their raw messages with ``rosbags``, bz2
    chunks 3×; sqlite3 bags about as fast, the row fetch being the limit; see
    ``benches/python/bench_io.py``); any bag it does not read (other layouts, several
    connections on the topic, damage) is read by ``rosbags`` with the same values and errors.
    """
    p = checked_path("path", path)
    if not p.exists():
        raise FileNotFoundError(f"no such file: '{p}'")
    callback("progress", progress)
    choice("time_unit", time_unit, _TIME_UNITS)
    choice("stamp", stamp, _STAMPS)
    if fs is not None:
        fs = sample_rate(fs)
    skip_rows = count("skip_rows", skip_rows)  # checked even where ignored (.npy, bags)
    repairs = _repair_options(repair)
    if spill is not None and not isinstance(spill, (bool, np.bool_)):
        raise TypeError(f"spill must be True, False or None, got {spill!r}")
    if isinstance(columns, str):
        columns = [c.strip() for c in columns.split(",") if c.strip()]
        if not columns:
            raise ValueError("columns is empty")
    elif columns is not None:
        columns = sequence("columns", columns)
        if not columns:
            raise ValueError("columns is empty")
    for i, spec in enumerate(columns or ()):
        _column_spec(f"columns[{i}]", spec)
    if time_column is not None and time_column is not False:
        _column_spec("time_column", time_column)
    if topic is not None:
        text("topic", topic)
    spill_path = optional_path("spill_dir", spill_dir, "a directory path")
    store = Store(
        None if spill is None else bool(spill), None if spill_path is None else str(spill_path)
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
    if fmt == "text":  # a channel without a given unit takes the one its header states
        unit_tuple = tuple(
            u if u is not None else _header_unit(n) for u, n in zip(unit_tuple, names)
        )

    _check_finite(p, table, names, line_of)

    time = time_start = None
    if t_raw is None:
        if repairs or fill_gaps:
            what = "repair" if repairs else "fill_gaps"
            raise ValueError(f"{what} needs timestamps, and {p.name} has no time column")
        # an Xsens-style preamble's "// Sample rate: 120.0Hz" when no rate is given
        stated = _preamble_rate(p, int(skip_rows)) if fmt == "text" and fs is None else None
        report = _sampling_report(
            len(table), None, None, None, fs if stated is None else stated[0], source_format=fmt
        )
        if stated is not None:
            report = replace(report, fs_source="file")
    else:
        assert t_name is not None
        t_raw, table, fixes = _repair(p, t_raw, table, t_name, repairs, line_of, store)
        time, sampling, time_start, unit_used, guessed = _time_seconds(
            p, t_raw, t_name, time_unit, line_of, store
        )
        t_raw = None  # the raw stamps are no longer needed (long logs: free them now)
        report = _sampling_report(
            len(table),
            time,
            sampling,
            unit_used,
            fs,
            unit_guessed=guessed,
            fixes=fixes,
            source_format=fmt,
            filling=fill_gaps,
        )
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
    p = checked_path("path", path)
    if not p.exists():
        raise FileNotFoundError(f"no such file: '{p}'")
    if not _bag.is_bag(p):
        raise ValueError(f"{p.name} is not a bag (.bag, .mcap, .db3 or a ROS2 bag directory)")
    return _bag.topics(p)


def _repair_options(repair: str | Sequence[str]) -> tuple[str, ...]:
    items = (
        [r.strip() for r in repair.split(",")]
        if isinstance(repair, str)
        else sequence("repair", repair)
    )
    out = []
    for r in items:
        if r == "":
            continue
        choice("repair", r, _REPAIRS)
        out.append(r)
    return tuple(dict.fromkeys(out))
