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
from typing import Any

from gyrobias.cli import _types
from gyrobias.cli._common import (
    add_cleaning_arguments,
    add_read_arguments,
    cleaning_options,
    read_log,
    require_fs,
)
from gyrobias.cli.noise import add_fit_range_arguments, fit_range_options

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
    p.add_argument(
        "log",
        type=_types.path,
        metavar="LOG",
        help="log: text (.csv/.tsv/.txt, also compressed), .npy, ROS1/ROS2 bag or .mcap",
    )
    p.add_argument(
        "-o",
        "--output",
        type=_types.path,
        default=None,
        metavar="HTML",
        help="output file (default: LOG with the suffix .html)",
    )
    add_read_arguments(p)
    add_cleaning_arguments(p)
    ana = p.add_argument_group("analysis")
    ana.add_argument(
        "--confidence",
        type=_types.probability,
        default=0.683,
        metavar="P",
        help="level of the Allan confidence intervals (default 0.683 ≈ 1σ)",
    )
    ana.add_argument(
        "--fit-method", choices=("joint", "ieee"), default="joint", help="identification method"
    )
    add_fit_range_arguments(ana)
    ana.add_argument(
        "--conservative",
        type=_types.probability,
        default=0.95,
        metavar="P",
        help="one-sided level of the conservative set (default 0.95)",
    )
    ana.add_argument(
        "--bound-confidence",
        type=_types.finite,  # in (0, 1): the core's check (build_report)
        default=0.95,
        metavar="P",
        help="one-sided confidence level of the upper bounds of terms the log does not show "
        "(default 0.95)",
    )
    ana.add_argument(
        "--rate",
        type=_types.positive,
        default=None,
        metavar="HZ",
        help="IMU rate written into the exports (default: the log's sample rate)",
    )
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Execute ``gyrobias report``."""
    from gyrobias.report import write_report

    extra = fit_range_options(args, args.fit_method)  # refused before the log is read
    log = read_log(args)
    require_fs(log, args.log)
    output = args.output if args.output is not None else args.log.with_suffix(".html")
    write_report(
        output,
        log,
        confidence=args.confidence,
        method=args.fit_method,
        conservative_confidence=args.conservative,
        rate=args.rate,
        bound_confidence=args.bound_confidence,
        **cleaning_options(args),
        **extra,
    )
    print(f"wrote {output}")
    return 0
