"""Regenerate docs/performance.md from quick runs of the benchmarks: ``make perf-page``.

Each selected benchmark in ``benches/python`` runs in its own interpreter, in its quick mode where
it has one, and its printed output — the ratios against the peers (AllanTools, SciPy, NumPy,
astropy, filterpy, fracdiff-style loops) measured in the same run — goes into the page verbatim,
under the machine it ran on (CPU, cores, load average before and after, versions, commit). The
page is generated, never edited by hand: rerun this script and commit the result.

Usage: ``python docs/_tools/perf_page.py [--only NAME ...] [--output PATH] [--timeout S]``.
"""

from __future__ import annotations

import argparse
import datetime as dt
import os
import platform
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
BENCHES = ROOT / "benches" / "python"

# (script, arguments, title, what it measures)
SELECTED: list[tuple[str, list[str], str, str]] = [
    (
        "bench_allan.py",
        ["--quick"],
        "Allan deviation against AllanTools",
        "Overlapping ADEV at octave τ of a 10⁶-sample log (quick mode) against AllanTools' "
        "`oadev` on the same data, and the kernel's cost against one pass of `numpy.sum`.",
    ),
    (
        "bench_allan_family.py",
        ["--quick"],
        "Allan family (MTOTDEV, HTOTDEV, Théo1) against AllanTools",
        "The total and Théo statistics against AllanTools' implementations, same data, same run.",
    ),
    (
        "bench_kalman.py",
        [],
        "Fixed-gain Kalman filter against SciPy and filterpy",
        "Samples per second of the Rust loop against a vectorised `lfilter` + `cumsum` form and "
        "filterpy with a fixed gain; streaming in chunks against one shot.",
    ),
    (
        "bench_fir.py",
        [],
        "Kaiser FIR filtering against SciPy",
        "Zero-phase filtering of a 3 h, 100 Hz log against `scipy.signal.filtfilt`.",
    ),
    (
        "bench_spectral.py",
        [],
        "Least-squares spectrum against astropy",
        "LSSA of irregular data against astropy's `LombScargle` (exact methods).",
    ),
    (
        "bench_fractional.py",
        [],
        "Fractional differencing against SciPy",
        "Full-memory type-II fractional differencing against `scipy.signal.fftconvolve` and a "
        "direct loop.",
    ),
    (
        "bench_predict.py",
        [],
        "Bias prediction: generalized Schur against the literal Kalman filter",
        "The O(n·k) predictor against [BP]'s growing-state filter and dense linear algebra.",
    ),
    (
        "bench_io.py",
        ["--only", "csv"],
        "Reading logs against numpy.loadtxt",
        "`gyrobias.io.load` of 17-significant-digit CSV logs (10⁶ rows × (time + 3 channels), "
        "plain and compressed, and 10⁷ rows × (time + 6 channels), 1.5 GB) against "
        "`numpy.loadtxt` of the same file, best of 3 each; peak memory of a fresh process "
        "loading the file, above its imports, next to the size of the result.",
    ),
    (
        "bench_io.py",
        ["--only", "bag"],
        "Reading bags against rosbags",
        "`gyrobias.io.load` of 300,000 `sensor_msgs/Imu` messages in every bag format (ROS1 "
        "plain/lz4/bz2 chunks, ROS2 sqlite3, MCAP plain/zstd/lz4 chunks) against rosbags "
        "opening the same bag and iterating the topic's raw messages without deserializing "
        "them, best of 3 each; peak memory of a fresh process loading the bag, above its "
        "imports, next to the size of the result.",
    ),
]

#: Seconds a benchmark may run (default: ``--timeout``); writing the 1.5 GB CSV and three
#: numpy.loadtxt runs of it take minutes.
TIMEOUTS = {"bench_io.py": 1800.0}


def _cpu() -> str:
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine()


def _load() -> str:
    try:
        return " / ".join(f"{v:.1f}" for v in os.getloadavg())
    except OSError:
        return "n/a"


def _version(module: str) -> str:
    try:
        mod = __import__(module)
        return str(getattr(mod, "__version__", "?"))
    except Exception:  # noqa: BLE001 - a missing peer is reported, not fatal
        return "not installed"


def _commit() -> str:
    try:
        out = subprocess.run(
            ["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, capture_output=True, text=True
        )
        return out.stdout.strip() or "unknown"
    except OSError:
        return "unknown"


def run(script: str, args: list[str], timeout: float) -> tuple[str, float, bool]:
    start = time.perf_counter()
    env = dict(os.environ, PYTHONUNBUFFERED="1")
    try:
        out = subprocess.run(
            [sys.executable, str(BENCHES / script), *args],
            cwd=ROOT,
            capture_output=True,
            text=True,
            timeout=timeout,
            env=env,
        )
        ok = out.returncode == 0
        text = (
            out.stdout
            if ok
            else out.stdout + f"\n[exit code {out.returncode}]\n" + out.stderr[-2000:]
        )
    except subprocess.TimeoutExpired as exc:
        ok = False
        text = (exc.stdout or b"").decode() if isinstance(exc.stdout, bytes) else (exc.stdout or "")
        text += f"\n[stopped after {timeout:.0f} s]\n"
    return text.rstrip() + "\n", time.perf_counter() - start, ok


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument(
        "--only",
        nargs="*",
        help="bench script names to run, or one section as 'script args' (default: all selected)",
    )
    ap.add_argument("--output", default=str(ROOT / "docs" / "performance.md"))
    ap.add_argument("--timeout", type=float, default=300.0, help="seconds per benchmark")
    ap.add_argument(
        "--replace",
        action="store_true",
        help="rewrite only the sections of the --only benchmarks in the existing page (each "
        "then states its own run: date, load, commit), keeping the others",
    )
    opts = ap.parse_args()
    # a script name selects all its sections; "script args" (e.g. "bench_io.py --only bag") one
    chosen = [
        b
        for b in SELECTED
        if not opts.only or b[0] in opts.only or " ".join([b[0], *b[1]]) in opts.only
    ]

    import numpy

    import gyrobias

    load_before = _load()
    sections = []
    failed = []
    for script, args, title, what in chosen:
        print(f"== {script} {' '.join(args)}", flush=True)
        text, seconds, ok = run(script, args, TIMEOUTS.get(script, opts.timeout))
        print(text, flush=True)
        if not ok:
            failed.append(script)
        cmd = " ".join(["python", f"benches/python/{script}", *args])
        run_note = ""
        if opts.replace:
            run_note = (
                f" (this section alone, {dt.datetime.now(dt.UTC).strftime('%Y-%m-%d %H:%M UTC')}, "
                f"commit `{_commit()}`, load average {load_before} before, {_load()} after)"
            )
        sections.append(
            f"## {title}\n\n{what}\n\n`{cmd}` ({seconds:.0f} s{'' if ok else ', FAILED'})"
            f"{run_note}:\n\n```text\n{text}```\n"
        )
    load_after = _load()
    now = dt.datetime.now(dt.UTC).strftime("%Y-%m-%d %H:%M UTC")
    header = f"""<!-- Generated by `make perf-page` (docs/_tools/perf_page.py); do not edit by hand. -->
# Performance

Every number on this page was printed by a benchmark in `benches/python/` in **one run of
`make perf-page`**, each against its peer measured in the same process on the same data, so the
ratios — not the absolute times — are what carries over to another machine. Most benchmarks ran in
their quick mode (smaller sizes than the full `make bench`); their docstrings state the targets.

**Machine**: {_cpu()}, {os.cpu_count()} logical cores, {platform.system()} {platform.release()};
load average (1/5/15 min) {load_before} before and {load_after} after the run (a shared
machine: other jobs ran at the same time, so read the ratios, and expect run-to-run spread).
**Software**: Python {platform.python_version()}, NumPy {numpy.__version__},
gyrobias {gyrobias.__version__} (commit `{_commit()}`), AllanTools {_version("allantools")},
SciPy {_version("scipy")}, astropy {_version("astropy")}, filterpy {_version("filterpy")}.
**Generated**: {now}.

The Rust benchmarks (`cargo bench -p gyrobias-benches`) and the long runs (`bench_coverage.py`,
`bench_fleet.py`, `bench_out_of_core.py`, `bench_allan_confidence.py`) are not part
of this page's quick run; their last measured figures are quoted, with their conditions, on the
pages of the features they measure ([intervals](explanations/intervals.md),
[fleets](explanations/fleets.md), [out-of-core logs](guides/out_of_core.md)).

"""
    if opts.replace:
        page = Path(opts.output).read_text(encoding="utf-8")
        for script, *_ in chosen:  # no longer among the long runs the page leaves out
            page = page.replace(f"`{script}`, ", "", 1)
        page = _replace_sections(page, sections)
    else:
        page = header + "\n".join(sections)
    Path(opts.output).write_text(page, encoding="utf-8")
    print(f"wrote {opts.output}" + (f"; FAILED: {', '.join(failed)}" if failed else ""))
    return 1 if failed else 0


def _replace_sections(page: str, sections: list[str]) -> str:
    """``page`` with each of ``sections`` in place of the section of the same ``## title``
    (appended when the page has none)."""
    parts = page.split("\n## ")
    head, body = parts[0], ["## " + p for p in parts[1:]]
    for new in sections:
        title = new.splitlines()[0]
        hits = [i for i, old in enumerate(body) if old.splitlines()[0] == title]
        if hits:
            body[hits[0]] = new
        else:
            body.append(new)
    return "\n".join([head, *(b if b.endswith("\n") else b + "\n" for b in body)])


if __name__ == "__main__":
    raise SystemExit(main())
