"""``gyrobias thermal``: per-temperature noise table of static logs ([TS] Tables 1–5).

Usage::

    gyrobias thermal LOG1@-30 LOG2@0 LOG3@30 LOG4@60 --fs 100 [--column 0] [--units deg/s]
        [--fpass 14 --fstop 18 --apass-db 0.0001 --astop-db 100 | --no-filter]
        [--method pchip] [--json model.json]

Each ``LOG@T`` is a rate log (text, ``.npy``, a ROS bag or an MCAP file, read like every
command's logs by :func:`gyrobias.cli._common.read_log`; ``--column`` selects the channel)
recorded at ``T`` °C.
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path
from typing import TYPE_CHECKING, Any

from gyrobias.cli import _types

if TYPE_CHECKING:
    import numpy as np
    from numpy.typing import NDArray

__all__ = ["register", "run"]


def _load_log(args: argparse.Namespace, path: Path) -> NDArray[np.float64]:
    """One rate channel of a log file (default the first channel after the time column)."""
    import numpy as np

    from gyrobias.cli._common import read_log

    log = read_log(args, path)
    return np.ascontiguousarray(log.data[:, 0])


def _parse_tag(tag: str) -> tuple[Path, float]:
    """``PATH@TEMPERATURE`` → ``(Path, °C)``: the argparse type of the ``LOG@T`` arguments."""
    path, sep, temp = tag.rpartition("@")
    if not sep or not path or any(c in path for c in "\n\r\x00"):
        raise argparse.ArgumentTypeError(
            f"must be PATH@TEMPERATURE (e.g. log_m30.csv@-30), got {tag!r}"
        )
    try:
        t = float(temp)
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"must be PATH@TEMPERATURE with a temperature in °C, got {tag!r}"
        ) from None
    if not math.isfinite(t):
        raise argparse.ArgumentTypeError(
            f"must be PATH@TEMPERATURE with a finite temperature, got {tag!r}"
        )
    return Path(path), t


def register(subparsers: Any) -> None:
    """Add the ``thermal`` subcommand."""
    p = subparsers.add_parser(
        "thermal",
        help="temperature-dependent noise table of static logs ([TS] Tables 1-5)",
        description=(
            "Analyse static rate logs recorded at several temperatures: Allan ARW and bias "
            "instability, PSD noise density, AR(1) drift of the Kaiser-filtered log; print the "
            "table and optionally save the interpolating temperature model as JSON."
        ),
    )
    p.add_argument(
        "logs",
        nargs="+",
        type=_parse_tag,
        metavar="LOG@T",
        help="log file and its temperature in °C",
    )
    p.add_argument(
        "--units",
        type=_types.unit_spec,
        default="deg/s",
        help="unit of the samples (default deg/s)",
    )
    p.add_argument(
        "--fpass",
        type=_types.positive,
        default=None,
        help="FIR pass-band edge, Hz (default 0.14·fs)",
    )
    p.add_argument(
        "--fstop",
        type=_types.positive,
        default=None,
        help="FIR stop-band edge, Hz (default 0.18·fs)",
    )
    p.add_argument(
        "--apass-db", type=_types.positive, default=0.0001, help="pass-band attenuation, dB"
    )
    p.add_argument(
        "--astop-db", type=_types.positive, default=100.0, help="stop-band attenuation, dB"
    )
    p.add_argument("--no-filter", action="store_true", help="fit AR(1) to the raw log")
    p.add_argument("--method", choices=("linear", "pchip", "polynomial"), default="pchip")
    p.add_argument(
        "--degree",
        type=_types.non_negative_int,
        default=2,
        help="polynomial degree (--method polynomial)",
    )
    p.add_argument(
        "--json", type=_types.path, default=None, help="write the temperature model here"
    )
    from gyrobias.cli._common import add_read_arguments

    add_read_arguments(
        p,
        fs_required=True,
        units=False,
        column_help="rate channel: name or 0-based index (default: the first channel)",
    )
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Run ``gyrobias thermal``; returns the exit status."""
    from gyrobias import thermal
    from gyrobias._files import atomic_write

    try:
        tagged = list(args.logs)
        temps = [t for _, t in tagged]
        if len(set(temps)) != len(temps):
            dup = next(t for t in temps if temps.count(t) > 1)
            raise ValueError(f"temperatures must be distinct: {dup:g} °C is given twice")
        logs = [(t, _load_log(args, path)) for path, t in tagged]
        analyses = thermal.analyse_logs(
            logs,
            args.fs,
            prefilter=not args.no_filter,
            fpass=args.fpass,
            fstop=args.fstop,
            apass_db=args.apass_db,
            astop_db=args.astop_db,
            units=args.units,
        )
    except (OSError, ValueError, TypeError) as exc:
        print(f"gyrobias: error: {exc}", file=sys.stderr)
        return 2

    u = args.units
    per_hour = u in ("deg/s", "rad/s")
    ang = u.split("/")[0]
    cut = analyses[0].filter_cutoff
    print(f"Temperature-dependent noise of {len(analyses)} logs at fs = {args.fs:g} Hz ({u})")
    print("  ARW N  = sigma_Allan(tau = 1 s) * sqrt(tau)   (IEEE 952 read-off)")
    print("  B      = min octave sigma_Allan / 0.664282    (IEEE 952 flicker floor)")
    print("  nd     = sqrt(mean one-sided Welch PSD, 0.05-0.25 fs) of the raw log")
    filt = (
        "raw log"
        if cut is None
        else f"log low-passed by a causal Kaiser FIR ([TS] eq. 20), fc = {cut:g} Hz"
    )
    print(f"  AR(1)  b[k+1] = c b[k] + e fitted to the {filt}, mean removed;")
    print("         C_AR = -c is [TS]'s sign convention (b[k+1] + C_AR b[k] = e); tau_c = -dt/ln c")
    print()
    arw_unit = f"{ang}/√h" if per_hour else f"{u}·√s"
    b_unit = f"{ang}/h" if per_hour else u
    head = (
        f"{'T [°C]':>7} {'n':>9} {'ARW [' + arw_unit + ']':>14} {'B [' + b_unit + ']':>12} "
        f"{'nd [' + u + '/√Hz]':>16} {'c':>8} {'C_AR':>8} {'±se':>7} {'σ_e':>10} {'tau_c [s]':>10}"
    )
    print(head)
    print("-" * len(head))
    for a in analyses:
        arw = a.arw * 60.0 if per_hour else a.arw
        b = a.bias_instability * 3600.0 if per_hour else a.bias_instability
        tc = a.ar1.correlation_time
        tcs = f"{tc:10.4g}" if tc is not None else f"{'-':>10}"
        print(
            f"{a.temperature:7.1f} {a.n:9d} {arw:14.5g} {b:12.5g} {a.noise_density:16.5g} "
            f"{a.ar1.c:8.4f} {a.ar1.c_ar:8.4f} {a.ar1.c_std_error:7.4f} {a.ar1.sigma_e:10.4g} {tcs}"
        )
    if args.json is not None:
        try:
            model = thermal.TemperatureModel.from_analyses(
                analyses, method=args.method, degree=args.degree
            )
            atomic_write(args.json, model.to_json(indent=2))
        except (OSError, ValueError) as exc:
            print(f"gyrobias: error: {exc}", file=sys.stderr)
            return 2
        print(f"\ntemperature model ({args.method}) written to {args.json}")
    return 0
