"""Pieces shared by the ``gyrobias`` commands: reading a log, warnings, progress bars.

Every command that reads logs adds the same argument group with :func:`add_read_arguments`
and reads with :func:`read_log`, so that every format, option and check of
:func:`gyrobias.io.load` (text, ``.npy``, ROS bags, MCAP; topics, timestamps, repairs, gaps,
units, spilling to disk) works the same way everywhere::

    def register(subparsers):
        p = subparsers.add_parser("mycommand")
        p.add_argument("log", type=_types.path)
        add_read_arguments(p)
        p.set_defaults(func=run)

    def run(args):
        log = read_log(args)            # a GyroLog; warnings already printed to stderr
        fs = require_fs(log, args.log)

Progress bars use ``tqdm`` on stderr: shown on a terminal for long work, never in pipes
(unless ``--progress``), never with ``--no-progress``; they never change results.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path
from typing import TYPE_CHECKING, Any, Protocol

from gyrobias.cli import _types

if TYPE_CHECKING:
    from gyrobias import io
    from gyrobias.cleaning import CleaningResult

__all__ = [
    "ProgressBar",
    "add_cleaning_arguments",
    "add_progress_argument",
    "add_read_arguments",
    "add_selection_arguments",
    "clean_log",
    "cleaning_options",
    "load_options",
    "not_static_warnings",
    "progress_bar",
    "read_log",
    "require_fs",
    "selection_bounds",
    "selection_note",
    "warn",
]

#: Files larger than this get a progress bar while being read (on a terminal).
PROGRESS_MIN_BYTES = 20_000_000

_DELIMITERS = {"\\t": "\t", "tab": "\t", "whitespace": None, "space": None, " ": None}


def add_read_arguments(
    parser: argparse.ArgumentParser,
    *,
    fs_required: bool = False,
    units: bool = True,
    column_help: str | None = None,
) -> argparse._ArgumentGroup:
    """Add the "reading the log" option group (and ``--progress``) to ``parser``.

    Parameters
    ----------
    parser : argparse.ArgumentParser
        The command's parser; its positional log argument is the caller's.
    fs_required : bool
        Make ``--fs`` mandatory.
    units : bool
        Add ``--units`` (commands with their own ``--units`` pass ``False``).
    column_help : str, optional
        Help text of ``--columns`` (alias ``--column``).
    """
    src = parser.add_argument_group(
        "reading the log",
        "text (CSV/TSV/whitespace, also .gz/.bz2/.xz), .npy, ROS1 .bag, ROS2 bag directories "
        "(sqlite3 or MCAP) and .mcap/.db3 files; see gyrobias.io.load",
    )
    src.add_argument(
        "--columns",
        "--column",
        dest="columns",
        type=_types.column_list,
        metavar="A,B,…",
        help=column_help
        or "channels by name or 0-based index (default: all but time; for bags "
        "gyro_x … accel_z, or 'gyro' / 'accel')",
    )
    src.add_argument(
        "--fs",
        type=_types.positive,
        metavar="HZ",
        required=fs_required,
        help="sample rate" + ("" if fs_required else " (default: from the timestamps)"),
    )
    src.add_argument(
        "--time-column",
        type=_types.text,
        metavar="NAME",
        help="column of timestamps (default: a header column named t/time/timestamp)",
    )
    src.add_argument("--no-time-column", action="store_true", help="the log has no time column")
    src.add_argument(
        "--time-unit",
        choices=("auto", "s", "ms", "us", "ns"),
        default="auto",
        help="unit of the timestamps (default auto: by the median step: ns from 1e5, us from 1000, else s)",
    )
    src.add_argument(
        "--delimiter",
        type=_types.delimiter,
        metavar="SEP",
        help="field separator: , ; tab (or \\t) or whitespace (default: detected)",
    )
    src.add_argument(
        "--skip-rows",
        type=_types.non_negative_int,
        default=0,
        metavar="N",
        help="lines to skip before the header",
    )
    if units:
        src.add_argument(
            "--units",
            type=_types.unit_spec,
            metavar="UNIT",
            help="unit of the samples: one for all channels (deg/s), one per channel "
            "(deg/s,deg/s,deg/s,g,g,g) or per name (gx=deg/s,ax=m/s^2); bags are rad/s and m/s^2",
        )
    src.add_argument(
        "--topic",
        type=_types.text,
        metavar="TOPIC",
        help="bag topic (default: the only sensor_msgs/Imu topic)",
    )
    src.add_argument(
        "--stamp",
        choices=("header", "receive"),
        default="header",
        help="bag timestamps: header.stamp (default) or the receive time",
    )
    src.add_argument(
        "--repair",
        type=_types.repair_spec,
        metavar="sort,dedup",
        default="",
        help="sort out-of-order samples by timestamp and/or drop exact duplicates (reported)",
    )
    src.add_argument(
        "--fill-gaps",
        action="store_true",
        help="insert NaN rows for samples missing in gaps of the timestamps",
    )
    src.add_argument(
        "--spill",
        choices=("auto", "always", "never"),
        default="auto",
        help="keep the samples in a memory-mapped temporary file (auto: when larger than "
        "a quarter of the memory)",
    )
    add_selection_arguments(src)
    parser.set_defaults(read_units=units)
    add_progress_argument(parser)
    return src


def add_selection_arguments(group: argparse._ArgumentGroup) -> None:
    """Add ``--start`` / ``--stop`` (the span of the log analysed, :meth:`GyroLog.select`)."""
    what = (
        "seconds from the log's start (time 0 = first sample), with an optional unit "
        "(1200s, 90min, 0.5h), or a sample index with the suffix n (250000n)"
    )
    group.add_argument(
        "--start",
        type=_types.text,
        metavar="TIME",
        help=f"analyse from this time on (included): {what}",
    )
    group.add_argument(
        "--stop",
        type=_types.text,
        metavar="TIME",
        help="analyse up to this time (excluded), same forms as --start",
    )


def add_cleaning_arguments(parser: argparse.ArgumentParser) -> argparse._ArgumentGroup:
    """Add the "cleaning" option group: ``--outliers SIGMA`` and ``--detrend linear|quadratic``
    (Stable32's Outliers and Drift steps, :func:`gyrobias.cleaning.clean`), applied after
    ``--start``/``--stop`` and before the statistics."""
    group = parser.add_argument_group(
        "cleaning",
        "applied in this order after --start/--stop, before the statistics "
        "(gyrobias.cleaning.clean)",
    )
    group.add_argument(
        "--outliers",
        type=_types.positive,
        metavar="SIGMA",
        help="replace samples whose robust z-score |x - median|/(1.4826·MAD) exceeds SIGMA "
        "(per channel; Stable32's default is 5) by gaps, which the statistics skip",
    )
    group.add_argument(
        "--detrend",
        choices=("linear", "quadratic"),
        help="remove each channel's least-squares linear or quadratic drift in time",
    )
    return group


def cleaning_options(args: argparse.Namespace) -> dict[str, Any]:
    """``{"outliers": …, "detrend": …}`` of :func:`add_cleaning_arguments`' options."""
    return {
        "outliers": getattr(args, "outliers", None),
        "detrend": getattr(args, "detrend", None),
    }


def clean_log(
    args: argparse.Namespace, log: io.GyroLog
) -> tuple[io.GyroLog, CleaningResult | None]:
    """``log`` with ``--outliers`` / ``--detrend`` applied (a new :class:`GyroLog` whose data is
    the cleaned copy; the input is untouched) and the record of the steps, or ``(log, None)``
    when neither was given."""
    options = cleaning_options(args)
    if options["outliers"] is None and options["detrend"] is None:
        return log, None
    import dataclasses

    from gyrobias import cleaning

    fs = require_fs(log, Path(log.path))
    done = cleaning.clean(log.data, fs, units=log.units, **options)
    return dataclasses.replace(log, data=done.data), done


def add_progress_argument(parser: argparse.ArgumentParser) -> None:
    """Add ``--progress`` / ``--no-progress`` (once per parser)."""
    if any("--progress" in a.option_strings for a in parser._actions):
        return
    parser.add_argument(
        "--progress",
        action=argparse.BooleanOptionalAction,
        default=None,
        help="progress bars on stderr (default: for long work when stderr is a terminal)",
    )


def warn(message: str) -> None:
    """Print ``gyrobias: warning: message`` to stderr."""
    print(f"gyrobias: warning: {message}", file=sys.stderr)


def read_log(
    args: argparse.Namespace,
    path: Path | None = None,
    *,
    quiet: bool = False,
    fs: float | None = None,
) -> io.GyroLog:
    """Read ``path`` (default ``args.log``) with the options of :func:`add_read_arguments`.

    ``--start`` / ``--stop`` select the span analysed (:meth:`gyrobias.io.GyroLog.select`: a
    view, never a copy; ``log.selection`` records it). The sampling warnings are printed to stderr (unless ``quiet``). ``fs`` overrides
    ``args.fs``. Raises ``ValueError`` for contradictory options and whatever
    :func:`gyrobias.io.load` raises.
    """
    path = Path(args.log if path is None else path)
    options = load_options(args)
    if fs is not None:
        options["fs"] = fs
    # gyrobias.io (NumPy, the core) only when a log is read: building the parser stays light.
    from gyrobias import io

    start, stop = selection_bounds(args)  # a bad --start/--stop fails before the log is read

    bar = None
    if _wants_progress(args, path):
        bar = progress_bar(f"reading {path.name}", args)
    try:
        log = io.load(path, **options, progress=bar)
    finally:
        if bar is not None:
            bar.close()
    if not quiet:
        for w in log.warnings:
            warn(f"{path.name}: {w}")
    if start is not None or stop is not None:
        log = log.select(start, stop, names=SELECTION_NAMES)
    return log


#: The names of the selection options in messages.
SELECTION_NAMES = ("--start", "--stop")


def selection_bounds(
    args: argparse.Namespace,
) -> tuple[io.TimeBound | None, io.TimeBound | None]:
    """``--start`` and ``--stop`` parsed by :func:`gyrobias.io.parse_time_bound` (or ``None``)."""
    from gyrobias.io import parse_time_bound

    start, stop = SELECTION_NAMES
    return (
        parse_time_bound(getattr(args, "start", None), name=start),
        parse_time_bound(getattr(args, "stop", None), name=stop),
    )


def load_options(args: argparse.Namespace) -> dict[str, Any]:
    """The keyword arguments of :func:`gyrobias.io.load` given by :func:`add_read_arguments`' options.

    Raises ``ValueError`` for contradictory options. ``gyrobias fleet`` passes them to every log.
    """
    no_time = bool(getattr(args, "no_time_column", False))
    time_column = getattr(args, "time_column", None)
    if no_time and time_column is not None:
        raise ValueError("--time-column and --no-time-column contradict each other")
    delimiter = getattr(args, "delimiter", None)
    if delimiter is not None:
        delimiter = _DELIMITERS.get(delimiter, delimiter)
    return {
        "columns": getattr(args, "columns", None),
        "time_column": False if no_time else time_column,
        "time_unit": getattr(args, "time_unit", "auto"),
        "fs": getattr(args, "fs", None),
        "delimiter": delimiter,
        "skip_rows": getattr(args, "skip_rows", 0),
        "units": getattr(args, "units", None) if getattr(args, "read_units", True) else None,
        "topic": getattr(args, "topic", None),
        "stamp": getattr(args, "stamp", "header"),
        "repair": getattr(args, "repair", ""),
        "fill_gaps": bool(getattr(args, "fill_gaps", False)),
        "spill": {"auto": None, "always": True, "never": False}[getattr(args, "spill", "auto")],
    }


def require_fs(log: io.GyroLog, path: Path) -> float:
    """The log's sample rate, or a ``ValueError`` asking for ``--fs``."""
    if log.fs is None:
        raise ValueError(
            f"{path.name} has no time column: give the sample rate with --fs HZ "
            "(or name the time column with --time-column)"
        )
    return float(log.fs)


def _wants_progress(args: argparse.Namespace, path: Path) -> bool:
    flag = getattr(args, "progress", None)
    if flag is not None:
        return bool(flag)
    if not sys.stderr.isatty():
        return False
    try:
        size = (
            path.stat().st_size if path.is_file() else sum(f.stat().st_size for f in path.iterdir())
        )
    except OSError:
        return False
    return size > PROGRESS_MIN_BYTES


class _Stream(Protocol):
    def write(self, text: str, /) -> int: ...
    def flush(self) -> None: ...


class ProgressBar:
    """A progress callback (``bar(fraction)``, 0..1) drawn by ``tqdm`` on stderr.

    On a terminal tqdm redraws one line in place; on other streams it writes its updates
    as they come (used only when progress was asked for with ``--progress``).

    Parameters
    ----------
    label : str
        Text before the bar.
    stream : file-like, optional
        Where to draw (default ``sys.stderr``).
    """

    def __init__(self, label: str, stream: _Stream | None = None) -> None:
        from tqdm import tqdm  # type: ignore[import-untyped, unused-ignore]

        self.label = label
        self.stream: _Stream = stream if stream is not None else sys.stderr
        self._start = time.perf_counter()
        self._bar = tqdm(
            total=100,
            desc=label,
            file=self.stream,
            unit="%",
            leave=False,
            dynamic_ncols=True,
            mininterval=0.2,
            bar_format="{desc}: {bar} {n:3.0f} % {elapsed}",
        )

    def __call__(self, fraction: float) -> None:
        fraction = min(max(float(fraction), 0.0), 1.0)
        self._bar.n = round(100 * fraction, 1)
        self._bar.refresh()

    def close(self) -> None:
        """Remove the bar."""
        self._bar.close()


def progress_bar(label: str, args: argparse.Namespace | None = None) -> ProgressBar | None:
    """A :class:`ProgressBar` unless ``--no-progress`` was given."""
    if args is not None and getattr(args, "progress", None) is False:
        return None
    return ProgressBar(label)


def describe_source(log: io.GyroLog) -> str:
    """``"/imu (ROS1 bag)"`` for bags, the format name otherwise (for headings)."""
    fmt = log.sampling.source_format or ""
    return f"topic {log.topic} of a {fmt}" if log.topic else fmt


def selection_note(log: io.GyroLog) -> str | None:
    """``"τ computed on 0.5–2.3 h of 2.8 h (samples 18000–82800 of 100800)"`` after
    ``--start``/``--stop``, else ``None``."""
    return None if log.selection is None else f"τ computed on {log.selection}"


def not_static_warnings(log: io.GyroLog, results: list[Any]) -> list[Any]:
    """Each result's stationarity check (times in the log as read, also after ``--start``:
    the results' checks are moved there), with a stderr warning for each axis that is not
    static; ``None`` where there is no check."""
    offset = 0.0
    if log.selection is not None and log.selection.start_s is not None:
        offset = log.selection.start_s
    checks = []
    for i, r in enumerate(results):
        if offset and getattr(r, "stationarity", None) is not None:
            # the command's own result, placed in the log as read: the fit's warnings then
            # give the same times as this one
            r = results[i] = r.in_log_time(offset)
        check = getattr(r, "stationarity", None)
        checks.append(check)
        if check is not None:
            for w in check.warnings:
                warn(w)
    return checks
