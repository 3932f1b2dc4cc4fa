"""``gyrobias allan``: Allan-family deviations of a gyro log, as tables, JSON and a plot.

Example::

    gyrobias allan LOG.csv --columns gx,gy,gz --units deg/s --json out.json --plot out.png
    gyrobias allan imu.bag --fit --export kalibr=imu.yaml

The sample rate comes from ``--fs`` or from the log's timestamps (a time column, or a bag's
``header.stamp``); irregular sampling found in the timestamps is reported as warnings on
stderr and in the JSON. Channels with different units (a 6-axis IMU: gyro in rad/s,
accelerometer in m/s²) are analysed per unit and labelled with it; ``--export kalibr=PATH`` then writes
both sensors' terms to one file.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from typing import Any

from gyrobias.cli import _types
from gyrobias.cli import noise as noise_cli
from gyrobias.cli._common import (
    ProgressBar,
    add_cleaning_arguments,
    add_read_arguments,
    clean_log,
    describe_source,
    not_static_warnings,
    read_log,
    require_fs,
    selection_note,
)

__all__ = ["ProgressBar", "register", "run"]

#: The ``--kind`` choices: each is the function of that name in :mod:`gyrobias.allan` (imported
#: by :func:`run`, so that building the parser imports neither NumPy nor the core).
_KINDS = (
    "adev",
    "mdev",
    "hdev",
    "totdev",
    "tdev",
    "mtotdev",
    "htotdev",
    "theo1",
    "theobr",
    "theoh",
)
#: The ``--kind`` choices that skip gaps (``gaps="omit"``): the NaN of ``--outliers``.
_GAP_KINDS = ("adev", "mdev", "hdev")
#: Logs with at least this many samples × channels get a progress bar on a terminal.
PROGRESS_MIN_VALUES = 1_000_000


def register(subparsers: Any) -> None:
    """Add the ``allan`` subcommand."""
    p = subparsers.add_parser(
        "allan",
        help="Allan / modified / Hadamard / total deviation of a gyro log",
        description=(
            "Compute an Allan-family deviation of each channel of an IMU log (CSV/TSV/text,\n"
            ".npy, ROS1/ROS2 bag or MCAP), print a table per sensor axis with confidence\n"
            "intervals and the identified noise type, and optionally write JSON and a log-log plot."
        ),
        epilog="examples: gyrobias allan log.csv --columns gx,gy,gz --units deg/s --plot adev.png\n"
        "          gyrobias allan imu.bag --fit --export kalibr=imu.yaml",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument(
        "log",
        type=_types.path,
        metavar="LOG",
        help="log: .csv/.tsv/.txt (delimited text), .npy, .bag, .mcap, .db3 or a ROS2 bag directory",
    )
    src = add_read_arguments(p)
    src.add_argument(
        "--data-type",
        choices=("rate", "angle"),
        default="rate",
        help="rate (default) or integrated angle samples",
    )
    add_cleaning_arguments(p)
    ana = p.add_argument_group("analysis")
    ana.add_argument(
        "--kind",
        choices=_KINDS,
        default="adev",
        help="deviation (default adev): adev, mdev, hdev (overlapping = Stable32 OHDEV; with "
        "--non-overlapping Stable32 HDEV), totdev, tdev (time deviation, angle unit), "
        "mtotdev, htotdev, theo1 / theobr / theoh (τ = 0.75·m/fs out to 75 %% of the log)",
    )
    ana.add_argument(
        "--taus",
        choices=("octave", "decade", "log", "all"),
        default="octave",
        help="τ grid: octave (m = 1, 2, 4, …, default), decade (1, 2, 4, 10, 20, …), log, "
        "all (every m: slow on long logs)",
    )
    ana.add_argument(
        "--per-decade",
        type=_types.positive_int,
        default=10,
        metavar="N",
        help="points per decade for --taus log",
    )
    ana.add_argument(
        "--non-overlapping",
        action="store_true",
        help="non-overlapping ADEV ([BP] eq. 2) or HDEV (Stable32 HDEV) instead of overlapping",
    )
    ana.add_argument(
        "--confidence",
        type=_types.probability,
        default=0.683,
        metavar="P",
        help="confidence level of the intervals (default 0.683 ≈ 1σ)",
    )
    ana.add_argument(
        "--no-confidence",
        action="store_true",
        help="skip noise identification and confidence intervals",
    )
    out = p.add_argument_group("output")
    noise_cli.add_fit_arguments(p)
    out.add_argument(
        "--json",
        type=_types.path,
        metavar="FILE",
        help="write all axes, units, fs and the sampling report as JSON",
    )
    out.add_argument(
        "--plot",
        type=_types.path,
        metavar="FILE",
        help="save a log-log plot (png, pdf, svg) with confidence bars",
    )
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Execute ``gyrobias allan``."""
    from gyrobias import allan

    if args.non_overlapping and args.kind not in ("adev", "hdev"):
        raise ValueError("--non-overlapping applies to --kind adev and hdev only")
    confidence = None if args.no_confidence else args.confidence
    show_progress = args.progress
    if show_progress is None:
        show_progress = sys.stderr.isatty()

    t_read = time.perf_counter()
    log = read_log(args, quiet=True)
    t_read = time.perf_counter() - t_read
    report = log.sampling
    fs = require_fs(log, args.log)
    if report.fs_source == "timestamps":
        print(
            f"fs = {fs:.9g} Hz, estimated from the time column '{log.time_column}' "
            f"(read as {report.time_unit}; jitter {100 * (report.jitter or 0.0):.2g} %)"
        )
    elif report.fs_source == "file":
        print(f"fs = {fs:.9g} Hz, as the file's preamble states (no time column)")
    for w in log.warnings:
        print(f"gyrobias: warning: {w}", file=sys.stderr)
    # --fit-tau-range / --lines against --fit-method: refused before the analysis runs.
    noise_cli.fit_range_options(args, getattr(args, "fit_method", "joint"))
    log, cleaned = clean_log(args, log)

    bar = None
    if show_progress and (args.progress or log.data.size >= PROGRESS_MIN_VALUES):
        bar = ProgressBar(f"{args.kind} of {log.n_samples} samples × {len(log.columns)}")
    groups = log.unit_groups()
    t_run = time.perf_counter()
    by_column: dict[int, Any] = {}
    try:
        done = 0.0
        for unit, cols in groups:
            # one call per unit: a 6-axis IMU's gyro and accelerometer each get their own unit
            part = log.data if len(groups) == 1 else log.data[:, cols]
            share = len(cols) / len(log.columns)
            kw: dict[str, Any] = {
                "taus": args.taus,
                "per_decade": args.per_decade,
                "data_type": args.data_type,
                "confidence": confidence,
                "units": unit,
                "axis_names": [log.columns[c] for c in cols],
                "progress": None if bar is None else (lambda f, d=done, s=share: bar(d + s * f)),
            }
            if args.kind in ("adev", "hdev"):
                kw["overlapping"] = not args.non_overlapping
            if log.sampling.filled_samples or (cleaned is not None and cleaned.has_gaps):
                kw.update(_gap_option(args.kind, cleaned is not None and cleaned.has_gaps))
            out = getattr(allan, args.kind)(part, fs, **kw)
            assert isinstance(out, tuple)
            by_column.update(zip(cols, out))
            done += share
    finally:
        if bar is not None:
            bar.close()
    results = [by_column[c] for c in range(len(log.columns))]
    t_run = time.perf_counter() - t_run
    args.rostopic = log.topic

    duration = log.n_samples / fs
    source = f" ({describe_source(log)})" if log.topic else ""
    print(
        f"{args.log}{source}: {log.n_samples} samples × {len(log.columns)} channels, "
        f"{_duration(duration)} at {fs:.9g} Hz"
    )
    note = selection_note(log)
    if note is not None:
        print(note)
    if cleaned is not None:
        print(f"cleaning: {cleaned.describe()}")
    for r in results:
        unit = f" [{r.unit}]" if r.unit else ""
        print(
            f"\n{r.label.split(' (')[0] if r.kind == 'hdev' else r.kind.upper()} of {r.axis}{unit}"
            f"{' (non-overlapping)' if not r.overlapping else ''}"
            f"{f', {100 * r.confidence:.3g} % confidence intervals' if r.confidence else ''}"
        )
        print(r.table())

    checks = not_static_warnings(log, results)

    noise_cli.run_fit(args, results)

    if args.json is not None:
        doc = {
            "gyrobias_version": _version(),
            "command": "allan",
            "source": str(args.log),
            "kind": args.kind,
            "fs_hz": log.fs,
            "fs_source": report.fs_source,
            "units": _json_units(log.units),
            "data_type": args.data_type,
            "overlapping": results[0].overlapping,
            "confidence": confidence,
            "columns": list(log.columns),
            "time_column": log.time_column,
            "topic": log.topic,
            "sampling": report.to_dict(),
            "selection": None if log.selection is None else log.selection.to_dict(),
            "cleaning": None if cleaned is None else cleaned.to_dict(),
            "fit_options": _fit_options_json(args),
            "timing_s": {"read": t_read, "analysis": t_run},
            "axes": [r.to_dict() for r in results],
            "stationarity": [None if c is None else c.to_dict() for c in checks],
        }
        if args.noise_coefficients:
            doc["noise_coefficients"] = [c.to_dict() for c in args.noise_coefficients]
        from gyrobias._files import atomic_write

        atomic_write(args.json, json.dumps(doc, indent=2) + "\n")
        print(f"\nwrote {args.json}")
    if args.plot is not None:
        from gyrobias.plotting import save_allan_plot

        title = f"{args.kind.upper()} of {args.log.name} ({fs:.6g} Hz, {_duration(duration)})"
        if log.selection is not None:
            title += f", {log.selection.describe()}"
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


def _fit_options_json(args: argparse.Namespace) -> dict[str, Any] | None:
    """The fit's τ range and lines as given (``None`` without a fit)."""
    if not getattr(args, "noise_coefficients", None):
        return None
    tau_range = getattr(args, "fit_tau_range", None)
    return {
        "method": getattr(args, "fit_method", "joint"),
        "tau_range_s": None if tau_range is None else list(tau_range),
        "lines": _types.format_lines(getattr(args, "lines", "auto")),
    }


def _gap_option(kind: str, outliers: bool = False) -> dict[str, str]:
    """``{"gaps": "omit"}`` for the NaN rows of ``--fill-gaps`` (or of the outliers removed by
    ``--outliers``), if the estimator supports it."""
    import inspect

    from gyrobias import allan

    if outliers and kind not in _GAP_KINDS:
        raise ValueError(
            f"--outliers replaces outliers by gaps (NaN), and this {kind.upper()} cannot skip "
            f"gaps; use --kind {', '.join(_GAP_KINDS)}, or leave out --outliers"
        )
    if "gaps" in inspect.signature(getattr(allan, kind)).parameters:
        return {"gaps": "omit"}
    raise ValueError(
        f"--fill-gaps marks missing samples with NaN, and this {kind.upper()} cannot skip gaps; "
        "leave out --fill-gaps to analyse the samples as if contiguous"
    )


def _json_units(units: tuple[str | None, ...]) -> str | list[str | None] | None:
    """One unit for all channels as a string (as before), else one per channel."""
    return units[0] if len(set(units)) == 1 else list(units)


def _duration(seconds: float) -> str:
    """``7200`` → ``"2 h"``, ``90`` → ``"1.5 min"``, ``10`` → ``"10 s"``."""
    if seconds >= 3600.0:
        return f"{seconds / 3600.0:.3g} h"
    if seconds >= 60.0:
        return f"{seconds / 60.0:.3g} min"
    return f"{seconds:.3g} s"


def _version() -> str:
    from gyrobias._version import __version__

    return __version__
