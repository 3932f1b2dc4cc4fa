"""``gyrobias report``: a self-contained HTML noise report of an IMU log.

Example::

    gyrobias report LOG.csv --columns gx,gy,gz --units deg/s -o report.html

The page holds the log summary and timestamp report, an Allan plot per channel with confidence
intervals and the fitted and conservative models, the coefficient tables with uncertainties,
goodness of fit and warnings, and every estimator export as copyable text
(:mod:`gyrobias.report`). It needs no network access and prints on A4.
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

__all__ = ["register", "run"]


def register(subparsers: Any) -> None:
    """Add the ``report`` subcommand."""
    p = subparsers.add_parser(
        "report",
        help="one-page HTML noise report of a log (plots, coefficients, conservative set, exports)",
        description=(
            "Analyse every channel of an IMU log and write a self-contained HTML report: log and "
            "timestamp summary, Allan plots with intervals and fitted models, noise coefficients "
            "with uncertainties and goodness of fit, the conservative set, and every estimator "
            "export (Kalibr, OpenVINS, VINS, ORB-SLAM3, LIO-SAM, MATLAB, JSON) as copyable text."
        ),
        epilog="example: gyrobias report log.csv --columns gx,gy,gz --units deg/s -o report.html",
    )
    p.add_argument("log", type=Path, metavar="LOG", help="log file: .csv, .tsv, .txt (delimited text) or .npy")
    p.add_argument("-o", "--output", type=Path, default=None, metavar="HTML",
                   help="output file (default: LOG with the suffix .html)")
    src = p.add_argument_group("reading the log")
    src.add_argument("--columns", metavar="A,B,…", help="channels by header name or 0-based index (default: all but time)")
    src.add_argument("--fs", type=float, metavar="HZ", help="sample rate (default: from the time column)")
    src.add_argument("--time-column", metavar="NAME", help="column of timestamps (default: a header column named t/time/timestamp)")
    src.add_argument("--no-time-column", action="store_true", help="the log has no time column")
    src.add_argument("--time-unit", choices=("auto", "s", "ms", "us", "ns"), default="auto", help="unit of the timestamps")
    src.add_argument("--delimiter", metavar="SEP", help="field separator (default: detected)")
    src.add_argument("--skip-rows", type=int, default=0, metavar="N", help="lines to skip before the header")
    src.add_argument("--units", metavar="UNIT[,UNIT…]",
                     help="unit of the samples, one for all channels or one per channel, e.g. deg/s or "
                          "deg/s,deg/s,deg/s,m/s^2,m/s^2,m/s^2 (needed for the estimator exports)")
    ana = p.add_argument_group("analysis")
    ana.add_argument("--confidence", type=float, default=0.683, metavar="P",
                     help="level of the Allan confidence intervals (default 0.683 ≈ 1σ)")
    ana.add_argument("--fit-method", choices=("joint", "ieee"), default="joint", help="identification method")
    ana.add_argument("--conservative", type=float, default=0.95, metavar="P",
                     help="one-sided level of the conservative set (default 0.95)")
    ana.add_argument("--rate", type=float, default=None, metavar="HZ",
                     help="IMU rate written into the exports (default: the log's sample rate)")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Execute ``gyrobias report``."""
    from gyrobias import io
    from gyrobias.report import write_report

    if args.no_time_column and args.time_column is not None:
        raise ValueError("--time-column and --no-time-column contradict each other")
    delimiter = args.delimiter
    if delimiter is not None:
        delimiter = {"\\t": "\t", "tab": "\t", "whitespace": None, "space": None, " ": None}.get(delimiter, delimiter)
    log = io.load(
        args.log,
        columns=args.columns,
        time_column=False if args.no_time_column else args.time_column,
        time_unit=args.time_unit,
        fs=args.fs,
        delimiter=delimiter,
        skip_rows=args.skip_rows,
    )
    if log.fs is None:
        raise ValueError(f"{args.log.name} has no time column: give the sample rate with --fs HZ")
    units: list[str | None] | str | None = None
    if args.units:
        parts = [u.strip() for u in args.units.split(",")]
        units = parts[0] if len(parts) == 1 else list(parts)
    output = args.output if args.output is not None else args.log.with_suffix(".html")
    write_report(
        output,
        log,
        units=units,
        confidence=args.confidence,
        method=args.fit_method,
        conservative_confidence=args.conservative,
        rate=args.rate,
    )
    print(f"wrote {output}")
    return 0
