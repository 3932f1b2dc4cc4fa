"""Same-run A/B of two gyrobias installs: the Allan and fit workloads, alternating old and new.

Run: ``python benches/python/bench_ab.py OLD_PYTHON NEW_PYTHON [--rounds N] [--quick]``, each
PYTHON an interpreter with its own gyrobias (e.g. the wheels of two commits in two venvs:
``/work/ab-old/bin/python /work/ab-new/bin/python``).

Why: a restructure (issue 24: the Python layer split into packages, numerics moved to the core)
should leave the speed of the quoted workloads unchanged, and timings taken at different times
on a shared machine cannot show that. Here both installs run at once, each in its own worker
process that keeps its data and its warm caches; every round times each workload once in the
old worker and once in the new one, the order alternating from round to round, so load from
other processes falls on both alike. The result per workload is the median of the per-round
ratios new/old with their spread (min–max and the middle half over the rounds); a ratio is
"unchanged" when the spread includes 1.

The workloads are those ``docs/performance.md`` quotes from ``bench_allan.py`` (overlapping
ADEV at octave τ of 10⁶ samples without and with confidence intervals, all τ of 10⁵ samples,
100 τ per decade of 2.6·10⁶ samples at 2 kHz) and the fits of ``bench_noise.py`` (joint and
IEEE fits of a 3-axis octave curve, the joint fit of the 1025-τ curve of 2050 samples). The
data are made with NumPy from fixed seeds in each worker (the two installs share NumPy, so
both get the same arrays; gyrobias' own simulator changed its generator between the commits).
The sizes are those of ``bench_allan.py --quick``; ``--quick`` only runs fewer rounds.
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess

# The worker: builds the data, then answers "name" lines on stdin with the seconds one run
# of that workload took (several calls averaged for the millisecond-scale ones).
WORKER = r"""
import json, sys, time, inspect
import numpy as np
import gyrobias
from gyrobias import allan, noise

rng = np.random.default_rng(1)
fs = 100.0
rate = 0.5 + rng.normal(0.0, 1.0, 1_000_000)
small = rng.normal(0.0, 1.0, 100_000)
big = rng.normal(0.0, 1.0, 2_600_000)
# a gyro-like 3-axis log (1 h at 100 Hz): white rate noise plus a random-walk bias, in deg/s
g = np.random.default_rng(2)
n = 360_000
log = 0.2 / 60.0 * np.sqrt(fs) * g.standard_normal((n, 3)) + np.cumsum(
    10.0 / 216000.0 / np.sqrt(fs) * g.standard_normal((n, 3)), axis=0
)
curves = allan.adev(log, fs, confidence=None, units="deg/s")
short = np.ascontiguousarray(log[:2050, 0])
dense = allan.adev(short, fs, taus="all", confidence=None, units="deg/s")

WORK = {
    "adev octave 1e6": (5, lambda: allan.adev(rate, fs, confidence=None)),
    "adev octave 1e6 + CI": (2, lambda: allan.adev(rate, fs, confidence=0.683)),
    "adev all tau 1e5": (1, lambda: allan.adev(small, fs, taus="all", confidence=None)),
    "adev 100/decade 2.6e6": (
        1, lambda: allan.adev(big, 2000.0, taus="log", per_decade=100, confidence=None)
    ),
    "fit joint, 3 axes": (5, lambda: noise.fit(curves)),
    "fit ieee, 3 axes": (5, lambda: noise.fit(curves, method="ieee")),
    "fit joint, 1025 tau": (1, lambda: noise.fit(dense)),
}
# Each workload is compared with the old install's workload of the same name, or of the name
# BASE gives: variants that take out work a later issue added on top of the restructure.
BASE = {}
if "lines" in inspect.signature(noise.fit).parameters:  # issue 26: the sinusoid term
    WORK["fit joint, 3 axes, lines=None"] = (5, lambda: noise.fit(curves, lines=None))
    BASE["fit joint, 3 axes, lines=None"] = "fit joint, 3 axes"
try:  # issue 26: adev searches the rate for spectral lines (a periodogram of the whole log)
    from gyrobias.allan import classic
except ImportError:
    classic = None
if classic is not None and hasattr(classic, "_lines"):
    def no_search(fn):
        def run():
            saved, classic._lines = classic._lines, lambda *a: None
            try:
                return fn()
            finally:
                classic._lines = saved
        return run
    for name in ("adev octave 1e6", "adev octave 1e6 + CI", "adev 100/decade 2.6e6"):
        calls, fn = WORK[name]
        WORK[name + ", no line search"] = (calls, no_search(fn))
        BASE[name + ", no line search"] = name
for _, fn in WORK.values():  # warm up: first-call costs (imports, caches, thread pools)
    fn()
print(json.dumps({"file": gyrobias.__file__, "version": gyrobias.__version__,
                  "work": list(WORK), "base": BASE}), flush=True)
for line in sys.stdin:
    calls, fn = WORK[line.strip()]
    t = time.perf_counter()
    for _ in range(calls):
        fn()
    print((time.perf_counter() - t) / calls, flush=True)
"""


class Worker:
    """One interpreter running :data:`WORKER`."""

    def __init__(self, python: str) -> None:
        self.proc = subprocess.Popen(
            [python, "-c", WORKER],
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            text=True,
            cwd="/",  # never a source tree: the gyrobias of this interpreter's environment
        )
        assert self.proc.stdout is not None
        self.info = json.loads(self.proc.stdout.readline())

    def time(self, name: str) -> float:
        assert self.proc.stdin is not None and self.proc.stdout is not None
        self.proc.stdin.write(name + "\n")
        self.proc.stdin.flush()
        return float(self.proc.stdout.readline())

    def close(self) -> None:
        assert self.proc.stdin is not None
        self.proc.stdin.close()
        self.proc.wait(timeout=60)


def quartiles(values: list[float]) -> tuple[float, float]:
    """The middle half (25th and 75th percentiles) of ``values``."""
    if len(values) < 4:
        return min(values), max(values)
    q = statistics.quantiles(values, n=4)
    return q[0], q[2]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("old", help="python of the old install")
    parser.add_argument("new", help="python of the new install")
    parser.add_argument("--rounds", type=int, default=None, help="rounds (default 15, quick 7)")
    parser.add_argument("--quick", action="store_true", help="fewer rounds")
    args = parser.parse_args()
    rounds = args.rounds or (7 if args.quick else 15)

    old, new = Worker(args.old), Worker(args.new)
    try:
        for label, w in (("old", old), ("new", new)):
            print(f"{label}: gyrobias {w.info['version']} from {w.info['file']}")
        base = {n: new.info["base"].get(n, n) for n in new.info["work"]}
        names = [n for n in new.info["work"] if base[n] in old.info["work"]]
        only_new = [n for n in new.info["work"] if base[n] not in old.info["work"]]
        times: dict[str, tuple[list[float], list[float]]] = {n: ([], []) for n in names}
        extra: dict[str, list[float]] = {n: [] for n in only_new}
        for r in range(rounds):
            for n in names:
                first, second = (old, new) if r % 2 == 0 else (new, old)
                a = first.time(base[n] if first is old else n)
                b = second.time(base[n] if second is old else n)
                t_old, t_new = (a, b) if first is old else (b, a)
                times[n][0].append(t_old)
                times[n][1].append(t_new)
            for n in only_new:
                extra[n].append(new.time(n))
    finally:
        old.close()
        new.close()

    print(f"\n{rounds} rounds, old and new alternating; ratio = new / old per round")
    print(
        f"{'workload':<40} {'old [ms]':>9} {'new [ms]':>9} {'ratio':>7} "
        f"{'middle half':>15} {'min–max':>15}"
    )
    summary = {}
    for n in names:
        t_old, t_new = times[n]
        ratios = [b / a for a, b in zip(t_old, t_new)]
        lo, hi = quartiles(ratios)
        med = statistics.median(ratios)
        print(
            f"{n:<40} {1e3 * statistics.median(t_old):>9.2f} {1e3 * statistics.median(t_new):>9.2f} "
            f"{med:>7.3f} {lo:>7.3f}–{hi:<7.3f} {min(ratios):>7.3f}–{max(ratios):<7.3f}"
        )
        summary[n] = {
            "ratio_median": med,
            "ratio_q1": lo,
            "ratio_q3": hi,
            "ratio_min": min(ratios),
            "ratio_max": max(ratios),
        }
    for n in only_new:
        print(f"{n:<40} {'—':>9} {1e3 * statistics.median(extra[n]):>9.2f}   (new only)")
    print(json.dumps(summary))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
