"""Coverage of the noise-identification uncertainties (issue 11 item 5), verified by simulation.

Simulates ``--logs`` static logs per scenario with known terms and prints, per estimator
(``joint`` = :func:`gyrobias.noise.fit`, ``ieee`` = the IEEE-952 read-off, ``gmwm`` =
:func:`gyrobias.noise.gmwm`) and term, the relative bias, the relative RMS error and the
empirical coverage of the ±1σ (68.3 %) and ±1.96σ (95 %) intervals, as a Markdown table.

Scenarios (20 Hz, 2^17 samples ≈ 1.8 h per log):

* ``white+flicker+RRW``: N = 0.2 deg/√h, B = 3 deg/h, K = 10 deg/h^1.5;
* ``white+GM``: N = 0.2 deg/√h and a Gauss–Markov bias σ = 5 deg/h, T = 60 s;
* the same two through a 41-tap FIR low-pass at 3 Hz (a sensor's anti-alias filter with unity
  DC gain: N, B, K and GM are unchanged at long τ, the curve bends below the −½ line at short τ);
* periodic disturbances (issue 26) on white+flicker+RRW: a line at 0.23·fs (4.6 Hz, 0.01
  deg/s; also through the filter, which passes it attenuated), two lines (4.3 and 5.5 Hz) and a
  line near Nyquist (9.8 Hz). The estimators run with their defaults, which detect the lines
  and model them with the sinusoidal term "S".

A term an estimator reports missing counts as not covered (its error is the whole value). The
binomial standard error of a coverage from L logs is √(p(1−p)/L): ±3.3 points at 68 % and ±1.5
at 95 % for L = 200.

Upper bounds of invisible terms (issue 26 item 2), ``--bound-logs L`` (default 400): logs of
20 min and 2 h at 100 Hz with N = 0.2 deg/√h, B = 3 deg/h and a rate random walk K the default
fit often sets to zero; among the logs where it does, the share whose 95 % upper bound
(``Term.upper_bound``) is above the true K (target ≥ 95 %) and below 10× it, and the median
ratio.

Usage: ``python benches/python/bench_coverage.py [--logs 200] [--workers 2] [--bound-logs 400]``.
"""

from __future__ import annotations

import argparse
import math
import time
from concurrent.futures import ProcessPoolExecutor
from typing import Any

import numpy as np

FS = 20.0
N_SAMPLES = 2**17
DEG_H = 1.0 / 3600.0
LINES: dict[str, list[tuple[float, float]]] = {
    "white+flicker+RRW+line": [(4.6, 0.01)],
    "white+flicker+RRW+2 lines": [(4.3, 0.01), (5.5, 0.008)],
    "white+flicker+RRW+line near Nyquist": [(9.8, 0.01)],
}
TRUTH: dict[str, dict[str, float]] = {
    "white+flicker+RRW": {"N": 0.2 / 60.0, "B": 3.0 * DEG_H, "K": 10.0 / 216000.0},
    "white+GM": {"N": 0.2 / 60.0, "GM σ": 5.0 * DEG_H, "GM T": 60.0},
}
TRUTH.update({kind: TRUTH["white+flicker+RRW"] for kind in LINES})
SCENARIOS = [
    ("white+flicker+RRW", False),
    ("white+GM", False),
    ("white+flicker+RRW", True),
    ("white+GM", True),
    ("white+flicker+RRW+line", False),
    ("white+flicker+RRW+line", True),
    ("white+flicker+RRW+2 lines", False),
    ("white+flicker+RRW+line near Nyquist", False),
]


def _simulate(kind: str, filtered: bool, seed: int) -> np.ndarray:
    from scipy import signal

    from gyrobias import noise

    t = TRUTH[kind]
    if kind == "white+GM":
        phi = math.exp(-1.0 / (FS * t["GM T"]))
        sigma_e = t["GM σ"] * math.sqrt(1.0 - phi * phi)
        gm = noise.simulate(N_SAMPLES, FS, ar1=(phi, sigma_e), seed=seed + 10**6)
        white = noise.simulate(N_SAMPLES + 100, FS, arw=t["N"], seed=seed)
        base = white
    else:
        gm = np.zeros(N_SAMPLES)
        base = noise.simulate(
            N_SAMPLES + 100,
            FS,
            arw=t["N"],
            bias_instability=t["B"],
            rrw=t["K"],
            seed=seed,
            sinusoids=[(f, a, 0.37 * seed) for f, a in LINES.get(kind, [])],
        )
    if filtered:
        taps = signal.firwin(41, 3.0, fs=FS)
        out = signal.lfilter(taps, 1.0, base)[100:]
    else:
        out = base[100:]
    return np.asarray(out + gm, dtype=np.float64)


def _estimates(c: Any) -> dict[str, tuple[float | None, float | None]]:
    out: dict[str, tuple[float | None, float | None]] = {}
    for s in ("N", "B", "K"):
        out[s] = (c[s].value, c[s].uncertainty)
    if c.gauss_markov:
        g = c.gauss_markov[0]
        out["GM σ"] = (g.sigma.value, g.sigma.uncertainty)
        out["GM T"] = (g.correlation_time.value, g.correlation_time.uncertainty)
    return out


def _one(job: tuple[str, bool, int]) -> dict[str, dict[str, tuple[float | None, float | None]]]:
    from gyrobias import noise
    from gyrobias.allan import adev

    kind, filtered, seed = job
    rate = _simulate(kind, filtered, seed)
    terms = ("N", "GM") if kind == "white+GM" else ("N", "B", "K")
    r = adev(rate, FS)
    out = {"joint": _estimates(noise.fit(r, terms=terms))}
    if kind != "white+GM":
        out["ieee"] = _estimates(noise.fit(r, method="ieee", terms=terms))
    else:
        out["ieee"] = _estimates(noise.fit(r, method="ieee", terms=("N",)))
    out["gmwm"] = _estimates(noise.gmwm(rate, FS, terms=terms))
    return out


#: (samples at 100 Hz, true K in deg/s^1.5) of the bound-coverage rows.
BOUND_CASES = [(120_000, 1e-5), (120_000, 2e-5), (720_000, 1e-5), (720_000, 2e-5)]


def _bound_one(job: tuple[int, float, int]) -> float | None:
    """Bound/true ratio of K on one simulated log, or None when the fit identifies K."""
    from gyrobias import allan, noise

    n, rrw, seed = job
    rate = noise.simulate(n, 100.0, arw=0.2 / 60, bias_instability=3 / 3600, rrw=rrw, seed=seed)
    c = noise.fit(allan.adev(rate, 100.0, units="deg/s"))
    k = c.K  # type: ignore[union-attr]
    return None if not k.bounded else float(k.upper_bound) / rrw


def bound_coverage(logs: int, pool: ProcessPoolExecutor) -> None:
    """Markdown table of the upper bound's coverage (module docs)."""
    print(
        "\n| log | true K | K bounded | bound ≥ K | bound < 10 K | median bound/K |\n"
        "|---|---|---|---|---|---|"
    )
    for n, rrw in BOUND_CASES:
        jobs = [(n, rrw, 50_000 + seed) for seed in range(logs)]
        ratios = np.array([r for r in pool.map(_bound_one, jobs, chunksize=8) if r is not None])
        if ratios.size == 0:
            continue
        print(
            f"| {n / 100 / 60:.0f} min | {rrw * 216000:.3g} deg/h^1.5 | {ratios.size} of {logs} "
            f"| {100 * np.mean(ratios >= 1):.1f} % | {100 * np.mean(ratios < 10):.1f} % "
            f"| {np.median(ratios):.2f} |",
            flush=True,
        )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--logs", type=int, default=200, help="logs per scenario (default 200)")
    parser.add_argument("--workers", type=int, default=2, help="processes (default 2)")
    parser.add_argument(
        "--bound-logs", type=int, default=400, help="logs per upper-bound row (default 400)"
    )
    args = parser.parse_args()
    print(
        "| scenario | estimator | term | bias | RMS error | 68 % coverage | 95 % coverage |\n"
        "|---|---|---|---|---|---|---|"
    )
    started = time.perf_counter()
    with ProcessPoolExecutor(max_workers=args.workers) as pool:
        for kind, filtered in SCENARIOS:
            jobs = [(kind, filtered, 1000 * (1 + filtered) + seed) for seed in range(args.logs)]
            results = list(pool.map(_one, jobs, chunksize=4))
            name = kind + (" (filtered)" if filtered else "")
            for estimator in ("joint", "ieee", "gmwm"):
                for term, true in TRUTH[kind].items():
                    rows = [res[estimator].get(term, (None, None)) for res in results]
                    if all(v is None for v, _ in rows) and term not in ("N",):
                        continue
                    err = np.array([(v - true) / true if v is not None else -1.0 for v, _ in rows])
                    z = np.array(
                        [abs(v - true) / u if v is not None and u else np.inf for v, u in rows]
                    )
                    print(
                        f"| {name} | {estimator} | {term} | {100 * err.mean():+.1f} % "
                        f"| {100 * math.sqrt(float(np.mean(err**2))):.1f} % "
                        f"| {100 * np.mean(z <= 1.0):.0f} % | {100 * np.mean(z <= 1.96):.0f} % |",
                        flush=True,
                    )
        bound_coverage(args.bound_logs, pool)
    print(f"\n{args.logs} logs per scenario, {time.perf_counter() - started:.0f} s")


if __name__ == "__main__":
    main()
