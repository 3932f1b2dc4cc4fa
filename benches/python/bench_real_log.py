"""The whole user path on a real gyro log, as a table (issue 26: "every real log gives a usable,
trusted answer").

Loads LOG as ``gyrobias.io.load`` does (x-io and Xsens headers, timestamps, units), optionally
keeps the static part ``--start``..``--stop`` (seconds), and runs on the gyro channels: the
overlapping Allan deviation and the default joint fit (``noise.fit``), GMWM (``noise.gmwm``), the
classical and robust wavelet variance (``noise.wvar``), the line search (``noise.detect_lines``),
every estimator export (``gyrobias.exports.export``, written to a temporary folder) and the HTML
report (``gyrobias report``, counted: every format's file, no error paragraph). Prints one row per
axis: N, B, K from ``fit`` and ``gmwm`` (value ± 1σ, or ``≤`` the 95 % upper bound when the log
does not show the term), the lines, and what was written, then the time of each step.

Numbers measured with it are in docs/guides/real-log.md. The logs used there ship with
scikit-kinematics 0.10.4 (PyPI) and two of them are in tests/data/real_logs/.

Run: ``PYTHONPATH=python python benches/python/bench_real_log.py [LOG] [--columns A,B,C]
[--units deg/s] [--fs HZ] [--time-column NAME] [--start S] [--stop S]``; without LOG, the static
part of tests/data/real_logs/ngimu_sensors.csv. Exit status 1 when any step refuses or errs.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
import warnings
from html.parser import HTMLParser
from pathlib import Path
from typing import Any

import numpy as np

import gyrobias
from gyrobias import allan, exports, noise
from gyrobias.cli import main as cli_main

#: The real static log measured by default (NGIMU, scikit-kinematics 0.10.4; rows 179-498 at rest).
DEFAULT_LOG = (
    Path(__file__).resolve().parents[2] / "tests" / "data" / "real_logs" / "ngimu_sensors.csv"
)


class _Classes(HTMLParser):
    def __init__(self) -> None:
        super().__init__()
        self.seen: list[tuple[str, str]] = []

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        self.seen += [(tag, c) for c in (dict(attrs).get("class") or "").split()]


def _term(c: Any, symbol: str, unit: str) -> str:
    """``value ± σ unit``, ``≤ bound unit (95 %)`` or ``—`` for one term of a fit."""
    t = getattr(c, symbol)
    if t.upper_bound is not None:
        b = t.to(unit)
        return f"≤ {b.upper_bound:.3g} {unit}"
    if t.value is None or t.missing:
        return "—"
    v = t.to(unit)
    sigma = "" if v.uncertainty is None else f" ± {v.uncertainty:.2g}"
    return f"{v.value:.4g}{sigma} {unit}"


def _parse() -> argparse.Namespace:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument(
        "log",
        nargs="?",
        help="the log (default: the static part of tests/data/real_logs/ngimu_sensors.csv)",
    )
    ap.add_argument("--columns", help="gyro channels by name or index (default: all)")
    ap.add_argument("--units", help="unit of the samples (default: from the header)")
    ap.add_argument("--fs", type=float, help="sample rate (default: timestamps or preamble)")
    ap.add_argument("--time-column")
    ap.add_argument("--start", type=float, default=0.0, help="first second kept (default 0)")
    ap.add_argument("--stop", type=float, help="last second kept (default: the end)")
    return ap.parse_args()


def main() -> int:
    args = _parse()
    if args.log is None:  # `make bench` runs every bench without arguments
        args.log = str(DEFAULT_LOG)
        args.columns, args.start = args.columns or "1,2,3", args.start or 3.58
    path = Path(args.log)
    if not path.is_file():
        print(
            f"bench_real_log: no such file: {path} (see docs/guides/real-log.md for the logs "
            "measured and where to get them)",
            file=sys.stderr,
        )
        return 2
    kw: dict[str, Any] = {}
    if args.columns:
        kw["columns"] = args.columns
    if args.units:
        kw["units"] = args.units
    if args.fs:
        kw["fs"] = args.fs
    if args.time_column:
        kw["time_column"] = args.time_column
    steps: dict[str, float] = {}
    t0 = time.perf_counter()
    log = gyrobias.io.load(path, **kw)
    steps["load"] = time.perf_counter() - t0
    fs = log.fs
    if fs is None:
        print(f"bench_real_log: {path.name} has no time column: give --fs HZ", file=sys.stderr)
        return 2
    units = {u for u in log.units}
    if len(units) != 1 or None in units:
        print(
            f"bench_real_log: channels {', '.join(log.columns)} have units {log.units}: "
            "pick gyro channels of one unit with --columns / --units",
            file=sys.stderr,
        )
        return 2
    unit = str(units.pop())
    i0 = int(round(args.start * fs))
    i1 = len(log.data) if args.stop is None else int(round(args.stop * fs))
    rate = np.ascontiguousarray(np.asarray(log.data, dtype=np.float64)[i0:i1])
    names = list(log.columns)
    print(
        f"{path.name}: {len(rate)} samples ({len(rate) / fs:.4g} s at {fs:.6g} Hz, "
        f"rows {i0}..{i0 + len(rate) - 1}), channels {', '.join(names)} [{unit}]"
    )
    for w in log.warnings:
        print(f"  log: {w}")

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        t0 = time.perf_counter()
        r = allan.adev(rate, fs, units=unit, axis_names=names)
        fits = noise.fit(r)
        steps["adev + fit"] = time.perf_counter() - t0
        t0 = time.perf_counter()
        gm = noise.gmwm(rate, fs, units=unit, axis_names=names)
        steps["gmwm"] = time.perf_counter() - t0
        t0 = time.perf_counter()
        wv = noise.wvar(rate, fs, units=unit, axis_names=names)
        wvr = noise.wvar(rate, fs, units=unit, axis_names=names, robust=True)
        steps["wvar (classical + robust)"] = time.perf_counter() - t0
        t0 = time.perf_counter()
        lines = noise.detect_lines(rate, fs, units=unit)
        steps["detect_lines"] = time.perf_counter() - t0
    assert isinstance(fits, tuple) and isinstance(gm, tuple)
    assert isinstance(wv, tuple) and isinstance(wvr, tuple) and isinstance(lines, tuple)

    with tempfile.TemporaryDirectory() as tmp:
        written: dict[str, str] = {}
        t0 = time.perf_counter()
        for fmt in exports.FORMATS:
            try:
                text = exports.export(fits, fmt, Path(tmp) / fmt, rate=fs)
                written[fmt] = "marked" if "UPPER BOUND" in text else "ok"
            except ValueError as exc:  # a refusal is what this bench is looking for
                written[fmt] = f"REFUSED: {exc}"
        steps["7 exports"] = time.perf_counter() - t0
        segment = Path(tmp) / "segment.npy"
        np.save(segment, rate)
        html = Path(tmp) / "report.html"
        t0 = time.perf_counter()
        rc = cli_main(
            [
                "report",
                str(segment),
                "--fs",
                repr(fs),
                "--units",
                unit,
                "-o",
                str(html),
                "--no-progress",
            ]
        )
        steps["gyrobias report"] = time.perf_counter() - t0
        page = _Classes()
        if rc == 0:
            page.feed(html.read_text())

    arw, bi, rrw = f"{unit}/sqrt(h)" if unit.endswith("/s") else unit, unit, unit
    if unit in ("deg/s", "rad/s"):
        arw, bi, rrw = "deg/√h", "deg/h", "deg/h^1.5"
    print()
    header = f"{'axis':<24} {'method':<6} {'N':<26} {'B':<26} {'K':<28} lines"
    print(header)
    print("-" * len(header))
    for k, name in enumerate(names):
        found = ", ".join(
            f"{x.frequency:.4g} Hz ({x.amplitude:.2g} {unit}, p={x.p_value:.1g})" for x in lines[k]
        )
        for label, c in (("fit", fits[k]), ("gmwm", gm[k])):
            print(
                f"{name[:24]:<24} {label:<6} {_term(c, 'N', arw):<26} {_term(c, 'B', bi):<26} "
                f"{_term(c, 'K', rrw):<28} {found if label == 'fit' else ''}"
            )
        d = fits[k].diagnostics
        gof = "" if d is None else f"χ²/ν = {d.chi2 / max(d.dof, 1):.3g}, p = {d.p_value:.2g}"
        print(
            f"{'':<24} wvar: {len(wv[k].levels)} scales (robust: {len(wvr[k].levels)}); fit {gof}"
        )
    print()
    print("exports: " + ", ".join(f"{f} {s}" for f, s in written.items()))
    n_files = page.seen.count(("div", "export"))
    n_err = page.seen.count(("p", "error"))
    print(
        f"report: exit {rc}, {n_files} export files shown "
        f"(expected {2 * len(exports.FORMATS)}: best fit and conservative set), "
        f"{n_err} error paragraphs"
    )
    for w in caught:
        print(f"warning: {str(w.message)[:200]}")
    print()
    for step, seconds in steps.items():
        print(f"{step:<28} {seconds * 1e3:9.1f} ms")
    ok = rc == 0 and n_err == 0 and n_files == 2 * len(exports.FORMATS)
    ok = ok and not any(s.startswith("REFUSED") for s in written.values())
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
