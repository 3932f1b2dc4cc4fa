"""``gyrobias allan``: Allan-family deviations of a gyro log, as tables, JSON and a plot.

Example::

    gyrobias allan LOG.csv --columns gx,gy,gz --units deg/s --json out.json --plot out.png

The sample rate comes from ``--fs`` or from the log's time column (a header column named
``t``/``time``/``timestamp``, or ``--time-column``); irregular sampling found in the timestamps
is reported as warnings on stderr and in the JSON.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path
from typing import Any, Protocol

from gyrobias import allan, io
from gyrobias.cli import noise as noise_cli

__all__ = ["ProgressBar", "register", "run"]

_FUNCTIONS = {"adev": allan.adev, "mdev": allan.mdev, "hdev": allan.hdev, "totdev": allan.totdev,
              "tdev": allan.tdev, "mtotdev": allan.mtotdev, "htotdev": allan.htotdev, "theo1": allan.theo1,
              "theobr": allan.theobr, "theoh": allan.theoh}
#: Logs with at least this many samples × channels get a progress bar on a terminal.
PROGRESS_MIN_VALUES = 1_000_000


def register(subparsers: Any) -> None:
    """Add the ``allan`` subcommand."""
    p = subparsers.add_parser(
        "allan",
        help="Allan / modified / Hadamard / total deviation of a gyro log",
        description=(
            "Compute an Allan-family deviation of each channel of a gyro log (CSV/TSV/text or "
            ".npy), print a table per axis with confidence intervals and the identified noise "
            "type, and optionally write JSON and a log-log plot."
        ),
        epilog="example: gyrobias allan log.csv --columns gx,gy,gz --units deg/s --plot adev.png",
    )
    p.add_argument("log", type=Path, metavar="LOG", help="log file: .csv, .tsv, .txt (delimited text) or .npy")
    src = p.add_argument_group("reading the log")
    src.add_argument("--columns", metavar="A,B,…", help="channels by header name or 0-based index (default: all but time)")
    src.add_argument("--fs", type=float, metavar="HZ", help="sample rate (default: from the time column)")
    src.add_argument("--time-column", metavar="NAME", help="column of timestamps (default: a header column named t/time/timestamp)")
    src.add_argument("--no-time-column", action="store_true", help="the log has no time column")
    src.add_argument("--time-unit", choices=("auto", "s", "ms", "us", "ns"), default="auto",
                     help="unit of the timestamps (default auto: ns if the median step ≥ 1000, else s)")
    src.add_argument("--delimiter", metavar="SEP", help="field separator: , ; tab (or \\t) or whitespace (default: detected)")
    src.add_argument("--skip-rows", type=int, default=0, metavar="N", help="lines to skip before the header")
    src.add_argument("--units", metavar="UNIT", help="unit of the samples, e.g. deg/s (for labels)")
    src.add_argument("--data-type", choices=("rate", "angle"), default="rate", help="rate (default) or integrated angle samples")
    ana = p.add_argument_group("analysis")
    ana.add_argument("--kind", choices=tuple(_FUNCTIONS), default="adev",
                     help="deviation (default adev): adev, mdev, hdev (overlapping = Stable32 OHDEV; with "
                          "--non-overlapping Stable32 HDEV), totdev, tdev (time deviation, angle unit), "
                          "mtotdev, htotdev, theo1 / theobr / theoh (τ = 0.75·m/fs out to 75 %% of the log)")
    ana.add_argument("--taus", choices=("octave", "decade", "log", "all"), default="octave",
                     help="τ grid: octave (m = 1, 2, 4, …, default), decade (1, 2, 4, 10, 20, …), log, "
                          "all (every m: slow on long logs)")
    ana.add_argument("--per-decade", type=int, default=10, metavar="N", help="points per decade for --taus log")
    ana.add_argument("--non-overlapping", action="store_true",
                     help="non-overlapping ADEV ([BP] eq. 2) or HDEV (Stable32 HDEV) instead of overlapping")
    ana.add_argument("--confidence", type=float, default=0.683, metavar="P",
                     help="confidence level of the intervals (default 0.683 ≈ 1σ)")
    ana.add_argument("--no-confidence", action="store_true", help="skip noise identification and confidence intervals")
    out = p.add_argument_group("output")
    noise_cli.add_fit_arguments(p)
    out.add_argument("--json", type=Path, metavar="FILE", help="write all axes, units, fs and the sampling report as JSON")
    out.add_argument("--plot", type=Path, metavar="FILE", help="save a log-log plot (png, pdf, svg) with confidence bars")
    out.add_argument("--progress", action=argparse.BooleanOptionalAction, default=None,
                     help="progress bar on stderr (default: on for long logs when stderr is a terminal)")
    p.set_defaults(func=run)


class _Stream(Protocol):
    def write(self, text: str, /) -> int: ...
    def flush(self) -> None: ...


class ProgressBar:
    """A stderr progress callback for the ``progress=`` argument of :func:`gyrobias.allan.adev`.

    On a terminal it redraws one bar in place; elsewhere it prints a line per update.
    """

    def __init__(self, label: str, stream: _Stream | None = None, width: int = 30) -> None:
        self.label = label
        self.stream: _Stream = stream if stream is not None else sys.stderr
        self.width = width
        self.tty = bool(getattr(self.stream, "isatty", lambda: False)())
        self._drawn = False
        self._start = time.perf_counter()

    def __call__(self, fraction: float) -> None:
        fraction = min(max(float(fraction), 0.0), 1.0)
        elapsed = time.perf_counter() - self._start
        if self.tty:
            filled = round(self.width * fraction)
            bar = "#" * filled + "-" * (self.width - filled)
            self.stream.write(f"\r{self.label} [{bar}] {100 * fraction:3.0f} % {elapsed:5.1f} s")
        else:
            self.stream.write(f"{self.label}: {100 * fraction:3.0f} % ({elapsed:.1f} s)\n")
        self.stream.flush()
        self._drawn = True

    def close(self) -> None:
        """End the bar's line."""
        if self._drawn and self.tty:
            self.stream.write("\n")
            self.stream.flush()


def _warn(message: str) -> None:
    print(f"gyrobias: warning: {message}", file=sys.stderr)


def run(args: argparse.Namespace) -> int:
    """Execute ``gyrobias allan``."""
    if args.non_overlapping and args.kind not in ("adev", "hdev"):
        raise ValueError("--non-overlapping applies to --kind adev and hdev only")
    if args.no_time_column and args.time_column is not None:
        raise ValueError("--time-column and --no-time-column contradict each other")
    confidence = None if args.no_confidence else args.confidence
    delimiter = args.delimiter
    if delimiter is not None:
        delimiter = {"\\t": "\t", "tab": "\t", "whitespace": None, "space": None, " ": None}.get(delimiter, delimiter)
    show_progress = args.progress
    if show_progress is None:
        show_progress = sys.stderr.isatty()

    if args.progress or (show_progress and args.log.is_file() and args.log.stat().st_size > 20_000_000):
        print(f"reading {args.log} …", file=sys.stderr, flush=True)
    t_read = time.perf_counter()
    log = io.load(
        args.log,
        columns=args.columns,
        time_column=False if args.no_time_column else args.time_column,
        time_unit=args.time_unit,
        fs=args.fs,
        delimiter=delimiter,
        skip_rows=args.skip_rows,
    )
    t_read = time.perf_counter() - t_read
    report = log.sampling
    if log.fs is None:
        raise ValueError(
            f"{args.log.name} has no time column: give the sample rate with --fs HZ "
            "(or name the time column with --time-column)"
        )
    if report.fs_source == "timestamps":
        print(
            f"fs = {log.fs:.9g} Hz, estimated from the time column '{log.time_column}' "
            f"(read as {report.time_unit}; jitter {100 * (report.jitter or 0.0):.2g} %)"
        )
    for w in log.warnings:
        _warn(w)

    bar = None
    if show_progress and (args.progress or log.data.size >= PROGRESS_MIN_VALUES):
        bar = ProgressBar(f"{args.kind} of {log.n_samples} samples × {len(log.columns)}")
    kw: dict[str, Any] = {
        "taus": args.taus,
        "per_decade": args.per_decade,
        "data_type": args.data_type,
        "confidence": confidence,
        "units": args.units,
        "axis_names": list(log.columns),
        "progress": bar,
    }
    if args.kind in ("adev", "hdev"):
        kw["overlapping"] = not args.non_overlapping
    t_run = time.perf_counter()
    try:
        results = _FUNCTIONS[args.kind](log.data, log.fs, **kw)
    finally:
        if bar is not None:
            bar.close()
    t_run = time.perf_counter() - t_run
    assert isinstance(results, tuple)

    duration = log.n_samples / log.fs
    print(f"{args.log}: {log.n_samples} samples × {len(log.columns)} channels, "
          f"{_duration(duration)} at {log.fs:.9g} Hz")
    for r in results:
        unit = f" [{r.unit}]" if r.unit else ""
        print(f"\n{r.label.split(' (')[0] if r.kind == 'hdev' else r.kind.upper()} of {r.axis}{unit}"
              f"{' (non-overlapping)' if not r.overlapping else ''}"
              f"{f', {100 * r.confidence:.3g} % confidence intervals' if r.confidence else ''}")
        print(r.table())

    noise_cli.run_fit(args, results)

    if args.json is not None:
        doc = {
            "gyrobias_version": _version(),
            "command": "allan",
            "source": str(args.log),
            "kind": args.kind,
            "fs_hz": log.fs,
            "fs_source": report.fs_source,
            "units": args.units,
            "data_type": args.data_type,
            "overlapping": results[0].overlapping,
            "confidence": confidence,
            "columns": list(log.columns),
            "time_column": log.time_column,
            "sampling": report.to_dict(),
            "timing_s": {"read": t_read, "analysis": t_run},
            "axes": [r.to_dict() for r in results],
        }
        if args.noise_coefficients:
            doc["noise_coefficients"] = [c.to_dict() for c in args.noise_coefficients]
        args.json.write_text(json.dumps(doc, indent=2) + "\n", encoding="utf-8")
        print(f"\nwrote {args.json}")
    if args.plot is not None:
        from gyrobias.plotting import save_allan_plot

        title = f"{args.kind.upper()} of {args.log.name} ({log.fs:.6g} Hz, {_duration(duration)})"
        fits = args.noise_coefficients or None
        if fits is not None and len(results) > 1:
            # One figure per axis for the fitted models (overlaying several models, their
            # asymptotes and read-off labels on one axes is unreadable), plus the combined plot.
            save_allan_plot(results, args.plot, title=title)
            print(f"wrote {args.plot}")
            for r, fit in zip(results, fits):
                path = args.plot.with_name(f"{args.plot.stem}_{r.axis}{args.plot.suffix}")
                save_allan_plot([r], path, title=f"{title}, axis {r.axis}", fits=[fit])
                print(f"wrote {path}")
        else:
            save_allan_plot(results, args.plot, title=title, fits=fits)
            print(f"wrote {args.plot}")
    return 0


def _duration(seconds: float) -> str:
    """``7200`` → ``"2 h"``, ``90`` → ``"1.5 min"``, ``10`` → ``"10 s"``."""
    if seconds >= 3600.0:
        return f"{seconds / 3600.0:.3g} h"
    if seconds >= 60.0:
        return f"{seconds / 60.0:.3g} min"
    return f"{seconds:.3g} s"


def _version() -> str:
    from gyrobias import __version__

    return __version__
