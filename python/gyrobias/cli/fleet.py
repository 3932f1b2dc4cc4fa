"""``gyrobias fleet``: the noise terms of many IMU logs as one table, a summary and a figure.

Example::

    gyrobias fleet 'logs/*.csv' --units deg/s --out fleet.parquet --plot fleet.png
    gyrobias fleet 'logs/*.npy' --fs 200 --scheduler tcp://scheduler:8786

Every log is analysed by :func:`gyrobias.fleet.analyse` on Dask (the local threaded scheduler,
or the cluster at ``--scheduler``). A log that cannot be read is reported, not fatal.
"""

from __future__ import annotations

import argparse
import math
import os
import sys
from typing import Any

from gyrobias.cli import _types
from gyrobias.cli._common import (
    SELECTION_NAMES,
    add_cleaning_arguments,
    add_read_arguments,
    cleaning_options,
    load_options,
    progress_bar,
    selection_bounds,
)
from gyrobias.cli.noise import add_fit_range_arguments, fit_range_options

__all__ = ["register", "run"]

#: Rows of the per-unit table printed before "…" (the Parquet file has all of them).
MAX_PRINTED_ROWS = 60


def register(subparsers: Any) -> None:
    """Add the ``fleet`` subcommand."""
    p = subparsers.add_parser(
        "fleet",
        help="noise terms of a fleet of IMU logs on Dask: table, summary, out-of-family units, figure",
        description=(
            "Analyse many logs (one per unit) in parallel on Dask: Allan deviation with confidence "
            "intervals and the IEEE-952 noise terms of every axis, robust out-of-family flags, a "
            "summary of the fleet's spread, a Parquet table and a figure."
        ),
        epilog="example: gyrobias fleet 'logs/*.csv' --units deg/s --out fleet.parquet --plot fleet.png",
    )
    p.add_argument(
        "sources",
        nargs="+",
        metavar="LOG",
        help="log files or quoted glob patterns ('logs/*.csv', 'runs/**/*.npy')",
    )
    src = add_read_arguments(p)
    src.add_argument(
        "--axis-names",
        type=_types.column_list,
        metavar="X,Y,…",
        help="names for the channels of every log (compares logs whose headers differ, e.g. CSV and NPY)",
    )
    add_cleaning_arguments(p)
    ana = p.add_argument_group("analysis")
    ana.add_argument(
        "--fit-method",
        choices=("joint", "ieee"),
        default="joint",
        help="joint weighted NNLS fit (default) or IEEE-952 slope read-off",
    )
    ana.add_argument(
        "--terms",
        type=_types.term_list,
        metavar="N,B,K,GM",
        help="noise terms to fit (Q, N, B, K, R, GM, GM2; default the five IEEE terms); GM adds a "
        "Gauss–Markov term (σ and correlation time columns), GM2 two (joint fit only)",
    )
    add_fit_range_arguments(ana)
    ana.add_argument(
        "--taus",
        choices=("octave", "decade", "log", "all"),
        default="octave",
        help="τ grid (default octave)",
    )
    ana.add_argument(
        "--threshold",
        type=_types.positive,
        default=None,
        metavar="Z",
        # the default is read in run(), so that building the parser does not import the fleet
        # package (NumPy, pandas); test_cli checks that this text states its value
        help="robust |z| above which a term is out of family (default 3.5, "
        "gyrobias.fleet.OUT_OF_FAMILY_THRESHOLD)",
    )
    ana.add_argument(
        "--bound-confidence",
        type=_types.finite,  # in (0, 1): the core's check (fleet.analyse)
        default=0.95,
        metavar="P",
        help="one-sided confidence level of the upper bounds of terms a log does not show "
        "(default 0.95)",
    )
    run_group = p.add_argument_group("where it runs")
    run_group.add_argument(
        "--scheduler",
        type=_types.text,
        metavar="ADDRESS",
        help="Dask scheduler address (tcp://host:8786); default: local threads",
    )
    run_group.add_argument(
        "--workers",
        type=_types.positive_int,
        metavar="N",
        help="threads of the local scheduler (default: one per core)",
    )
    out = p.add_argument_group("output")
    out.add_argument(
        "--out",
        type=_types.path,
        metavar="FILE",
        help="write the table: .parquet (pyarrow, with the Allan curves) or .csv (without them)",
    )
    out.add_argument(
        "--plot", type=_types.path, metavar="FILE", help="save the fleet figure (png, pdf, svg)"
    )
    p.set_defaults(func=run)


def _fmt(value: Any, digits: int = 4) -> str:
    if value is None or (isinstance(value, float) and not math.isfinite(value)):
        return "—"
    return f"{value:.{digits}g}"


def _cell(row: Any, term: str) -> str:
    """``value ± 1σ``, or ``≤ bound`` for a term the log does not show."""
    bound = row.get(f"{term}_upper_bound", math.nan)
    value = row[term]
    if (value is None or not math.isfinite(value)) and bound is not None and math.isfinite(bound):
        return f"≤ {_fmt(bound)}"
    return _fmt(value) + " ± " + _fmt(row[f"{term}_uncertainty"], 2)


def _print_table(table: Any) -> None:
    from gyrobias import fleet

    terms = [
        t
        for t in fleet.term_columns(table)
        if table[t].notna().any() or table.get(f"{t}_upper_bound", table[t]).notna().any()
    ]
    ok = table[table["error"].isna()]
    units = {t: next((u for u in ok[f"{t}_unit"] if isinstance(u, str)), None) for t in terms}
    head = (
        f"{'source':<28} {'axis':<6}"
        + "".join(f" {t + (f' [{units[t]}]' if units[t] else ''):>22}" for t in terms)
        + "  flag"
    )
    print(head)
    for i, (_, row) in enumerate(table.iterrows()):
        if i == MAX_PRINTED_ROWS:
            print(f"… {len(table) - MAX_PRINTED_ROWS} more rows (see --out)")
            break
        name = os.path.basename(str(row["source"]))[:28]
        if isinstance(row["error"], str):
            print(f"{name:<28} {'—':<6} error: {row['error']}")
            continue
        cells = "".join(f" {_cell(row, t):>22}" for t in terms)
        terms_out = row["out_of_family_terms"]
        flag = f"OUT ({terms_out})" if isinstance(terms_out, str) else ""
        print(f"{name:<28} {row['axis']!s:<6}{cells}  {flag}")


def _print_summary(summ: Any) -> None:
    from gyrobias import fleet

    pd = fleet.table._require("pandas")
    print(
        f"{'axis':<6} {'term':<4} {'unit':<10} {'n':>4} {'median':>11} {'spread':>10} {'mean 1σ':>10} "
        f"{'Birge':>6} {'p':>8}  spread real?"
    )
    for _, r in summ.iterrows():
        real = r["spread_real"]
        verdict = "—" if pd.isna(real) else ("yes" if bool(real) else "no")
        print(
            f"{r['axis']!s:<6} {r['term']:<4} {r['unit'] or ''!s:<10} {r['n']:>4} {_fmt(r['median']):>11} "
            f"{_fmt(r['spread'], 3):>10} {_fmt(r['mean_uncertainty'], 3):>10} {_fmt(r['birge_ratio'], 3):>6} "
            f"{_fmt(r['p_value'], 2):>8}  {verdict}"
        )


def run(args: argparse.Namespace) -> int:
    """Execute ``gyrobias fleet``."""
    from gyrobias import fleet

    if args.threshold is None:
        args.threshold = fleet.OUT_OF_FAMILY_THRESHOLD
    if args.out is not None and args.out.suffix.lower() not in (".parquet", ".csv"):
        raise ValueError(f"--out must end in .parquet or .csv, got '{args.out}'")
    options = load_options(args)
    fs, units = options.pop("fs"), options.pop("units")
    start, stop = selection_bounds(args)
    extra = fit_range_options(args, args.fit_method)
    show = args.progress if args.progress is not None else sys.stderr.isatty()
    bar = progress_bar("fleet", args) if show else None
    try:
        table = fleet.analyse(
            args.sources,
            fs=fs,
            units=units,
            fit=args.fit_method,
            terms=None
            if args.terms is None
            else [t.strip() for t in args.terms.split(",") if t.strip()],
            client=args.scheduler,
            axis_names=None
            if args.axis_names is None
            else [a.strip() for a in args.axis_names.split(",") if a.strip()],
            load_options=options,
            taus=args.taus,
            gaps="omit" if args.fill_gaps else "error",
            threshold=args.threshold,
            num_workers=args.workers,
            progress=bar,
            start=start,
            stop=stop,
            bound_confidence=args.bound_confidence,
            **cleaning_options(args),
            **extra,
        )
    finally:
        if bar is not None:
            bar.close()
    failed = table[table["error"].notna()]
    ok = table[table["error"].isna()]
    n_sources = table["source"].nunique()
    print(
        f"{n_sources} logs, {len(ok)} unit-axes analysed, {len(failed)} failed"
        f"{f' (scheduler {args.scheduler})' if args.scheduler else ''}"
    )
    if start is not None or stop is not None:
        spans = sorted({s for s in ok["selection"] if isinstance(s, str)})
        print(
            f"τ computed on {SELECTION_NAMES[0]} {start or 0} {SELECTION_NAMES[1]} "
            f"{stop or 'end'} of every log: "
            + ("; ".join(spans[:3]) or "—")
            + (f"; … ({len(spans)} spans)" if len(spans) > 3 else "")
        )
    if args.outliers is not None or args.detrend is not None:
        steps = [
            *([f"outliers > {args.outliers:g}σ (MAD) removed"] if args.outliers else []),
            *([f"{args.detrend} drift removed"] if args.detrend else []),
        ]
        print(f"cleaning of every log: {'; '.join(steps)} (per axis: the 'cleaning' column)")
    print()
    _print_table(table)
    summ = fleet.summary(table)
    if not summ.empty:
        print(
            "\nFleet summary (spread = 1.4826·MAD; mean 1σ = RMS of the reported uncertainties; the spread is "
            f"real when the χ² homogeneity test gives p < {fleet.SPREAD_ALPHA:g} and the Birge ratio "
            f"√(χ²/ν) ≥ {fleet.SPREAD_MIN_RATIO:g}):"
        )
        _print_summary(summ)
    flagged = ok[ok["out_of_family"].fillna(False).astype(bool)]
    print(
        f"\nout of family (|z| > {args.threshold:g}): "
        + (
            ", ".join(
                f"{os.path.basename(str(s))}:{a} ({t})"
                for s, a, t in zip(
                    flagged["source"], flagged["axis"], flagged["out_of_family_terms"]
                )
            )
            or "none"
        )
    )
    for _, row in failed.iterrows():
        print(f"gyrobias: warning: {row['source']}: {row['error']}", file=sys.stderr)
    if args.out is not None:
        if args.out.suffix.lower() == ".csv":
            from gyrobias._files import atomic_write

            atomic_write(args.out, table.drop(columns=["adev_tau", "adev"]).to_csv(index=False))
        else:
            fleet.write_table(table, args.out)
        print(f"wrote {args.out}")
    if args.plot is not None:
        if ok.empty:
            print("gyrobias: warning: no unit was analysed: no plot", file=sys.stderr)
        else:
            from gyrobias.plotting import save_fleet_plot

            save_fleet_plot(table, args.plot, title=f"Fleet of {n_sources} logs")
            print(f"wrote {args.plot}")
    return 0 if not ok.empty else 1
