"""Allan-family benchmark (issue 15): MTOTDEV, HTOTDEV and Théo1 against AllanTools, same run.

Run: ``python benches/python/bench_allan_family.py [--quick]`` (needs ``pip install '.[bench]'``).

Targets: MTOTDEV and HTOTDEV on 1e4 samples at octave τ ≥ 100× faster than
``allantools.mtotdev`` / ``allantools.htotdev``; Théo1 on 1e5 samples ≥ 20× faster than
``allantools.theo1``.

AllanTools evaluates these statistics in pure-Python loops (MTOT/HTOT: O(N·m) per τ with a 9m
reflection copy per window; Théo1: O(N·m/2) per τ), so its full runs take minutes to hours.
Both libraries are therefore timed on the *same* τ set, chosen so that AllanTools finishes:

* MTOTDEV / HTOTDEV on 1e4 samples: m = 1 … 64 (``--quick``: … 16), ≈ 2 min per statistic for
  AllanTools; gyrobias' time for the full octave set (m up to 2048) is printed too, with
  AllanTools' time extrapolated from its measured cost per inner iteration (labelled).
* Théo1 on 1e5 samples: m = 2 … 32 (AllanTools ≈ 3·10⁶ inner iterations). gyrobias' time for
  the full octave set (m up to 65536) is printed too, with AllanTools' time for it extrapolated
  from its measured cost per inner term (labelled as such).

gyrobias times are the best of 3; AllanTools is run once (minutes). Numbers are wall-clock on
whatever machine runs the script — say so when quoting them on a shared host.

The explorer's stability statistics (issue 35) follow: MDEV, TOTDEV, HDEV and ADEV at octave τ
on a (10⁶, 6) row-major log at 100 Hz (``--quick``: 2·10⁵ rows), no intervals, best of 5,
against the same statistic written as NumPy passes per column and τ (integration by
``cumsum``, window sums by ``cumsum`` differences: no compensation, so less accurate on drifting
data, but the fastest plain-NumPy form), timed in the same run. Target: MDEV ≥ 8× the NumPy
passes (the serial running sum it replaced measured 6×).

A scaling table follows (gyrobias only): Théo1 at octave τ and ThéoBR (octave τ plus the bias
ratio's Théo1 at every ``m = 12 + 4i`` up to ≈ 0.13·N) for N = 1e4, 1e5, 1e6 (``--quick``: up
to 1e5). Octave Théo1 is exact and direct, ≈ N²/8 brackets at its largest τ, so its time grows
≈ 100× per decade of N; the bias ratio uses the structure-function sweep, ≈ 0.13·N² squared
increments (it was ≈ N³/1000 brackets summed directly).
"""

from __future__ import annotations

import argparse
import time
from collections.abc import Callable

import numpy as np
from _timing import best_of

import gyrobias


def _once(fn: object) -> float:
    t = time.perf_counter()
    fn()  # type: ignore[operator]
    return time.perf_counter() - t


def bench_total(n: int, max_m_allantools: int) -> list[tuple[str, float, float]]:
    import allantools

    rng = np.random.default_rng(1)
    rate = rng.normal(size=n) + np.cumsum(rng.normal(size=n)) * 1e-2
    full = [m for m in (2**k for k in range(20)) if m <= (n + 1) // 3]
    sub = [m for m in full if m <= max_m_allantools]

    def work(mm):
        return sum((n + 1 - 3 * m) * 6 * m for m in mm)

    rows = []
    for name, ours, theirs in (
        ("mtotdev", gyrobias.allan.mtotdev, allantools.mtotdev),
        ("htotdev", gyrobias.allan.htotdev, allantools.htotdev),
    ):
        taus = np.array(sub, dtype=float)
        t_ours = best_of(lambda f=ours, t=taus: f(rate, 1.0, taus=t, confidence=None))
        t_theirs = _once(lambda f=theirs, t=taus: f(rate, rate=1.0, data_type="freq", taus=t))
        rows.append((f"{name} N={n:.0e} m=1…{sub[-1]}", t_ours, t_theirs))
        t_full = best_of(lambda f=ours: f(rate, 1.0, taus="octave", confidence=None))
        rows.append(
            (
                f"{name} N={n:.0e} octave m=1…{full[-1]} (AllanTools extrapolated)",
                t_full,
                t_theirs / work(sub) * work(full),
            )
        )
    return rows


def bench_theo1(n: int, max_m: int) -> list[tuple[str, float, float]]:
    import allantools

    rng = np.random.default_rng(2)
    rate = rng.normal(size=n)
    ms = [m for m in (2**k for k in range(1, 20)) if m <= max_m]
    taus = 0.75 * np.array(ms, dtype=float)
    t_ours = best_of(lambda: gyrobias.allan.theo1(rate, 1.0, taus=taus, confidence=None))
    phase = allantools.frequency2phase(rate, 1.0)
    t_theirs = _once(
        lambda: allantools.theo1(phase, rate=1.0, data_type="phase", taus=np.array(ms, float))
    )
    rows = [(f"theo1 N={n:.0e} m=2…{ms[-1]}", t_ours, t_theirs)]
    # Full octave set: ours measured, AllanTools extrapolated from its cost per inner term.
    n_ph = n + 1
    full = [m for m in (2**k for k in range(1, 40)) if m <= n_ph - 1]

    def work(mm):
        return sum((n_ph - m) * (m // 2) for m in mm)

    per_term = t_theirs / work(ms)
    t_full = best_of(lambda: gyrobias.allan.theo1(rate, 1.0, confidence=None), repeats=1)
    rows.append(
        (
            f"theo1 N={n:.0e} full octave m=2…{full[-1]} (AllanTools extrapolated)",
            t_full,
            per_term * work(full),
        )
    )
    return rows


def _numpy_octave(m_max: int) -> list[int]:
    return [m for m in (2**k for k in range(40)) if m <= m_max]


def numpy_mvar(x: np.ndarray, t0: float) -> np.ndarray:
    """MVAR at octave τ of one angle series by NumPy passes (SP 1065 eq. 14, t0 units)."""
    out = []
    for m in _numpy_octave(len(x) // 3):
        d = x[2 * m :] - 2.0 * x[m:-m] + x[: -2 * m]
        c = np.concatenate(([0.0], np.cumsum(d)))
        s = c[m:] - c[:-m]
        out.append(np.dot(s, s) / (2.0 * m**4 * t0**2 * len(s)))
    return np.array(out)


def numpy_totvar(x: np.ndarray, t0: float) -> np.ndarray:
    """TOTVAR at octave τ by NumPy passes (SP 1065 eq. 25 on the reflected series)."""
    n = len(x)
    star = np.concatenate((2.0 * x[0] - x[n - 2 : 0 : -1], x, 2.0 * x[-1] - x[n - 2 : 0 : -1]))
    mid = n - 2
    out = []
    for m in _numpy_octave((n - 1) // 2):
        c = star[mid + 1 : mid + n - 1]
        d = star[mid + 1 - m : mid + n - 1 - m] - 2.0 * c + star[mid + 1 + m : mid + n - 1 + m]
        out.append(np.dot(d, d) / (2.0 * (m * t0) ** 2 * (n - 2)))
    return np.array(out)


def numpy_hvar(x: np.ndarray, t0: float) -> np.ndarray:
    """Overlapping HVAR at octave τ by NumPy passes (SP 1065 eq. 18)."""
    out = []
    for m in _numpy_octave((len(x) - 1) // 3):
        d = x[3 * m :] - 3.0 * x[2 * m : -m] + 3.0 * x[m : -2 * m] - x[: -3 * m]
        out.append(np.dot(d, d) / (6.0 * (m * t0) ** 2 * len(d)))
    return np.array(out)


def numpy_avar(x: np.ndarray, t0: float) -> np.ndarray:
    """Overlapping AVAR at octave τ by NumPy passes (SP 1065 eq. 7)."""
    out = []
    for m in _numpy_octave((len(x) - 1) // 2):
        d = x[2 * m :] - 2.0 * x[m:-m] + x[: -2 * m]
        out.append(np.dot(d, d) / (2.0 * (m * t0) ** 2 * len(d)))
    return np.array(out)


def bench_explorer(rows: int) -> list[tuple[str, float, float]]:
    """The explorer's statistics on a (rows, 6) log: gyrobias vs NumPy passes, same run."""
    fs = 100.0
    t0 = 1.0 / fs
    rng = np.random.default_rng(35)
    data = rng.standard_normal((rows, 6))

    def numpy_all(kernel: Callable[[np.ndarray, float], np.ndarray]) -> Callable[[], None]:
        def run() -> None:
            for axis in range(data.shape[1]):
                rate = data[:, axis]
                x = np.concatenate(([0.0], np.cumsum(rate - rate.mean()) * t0))
                kernel(x, t0)

        return run

    out = []
    for name, ours, kernel in (
        ("mdev", gyrobias.allan.mdev, numpy_mvar),
        ("totdev", gyrobias.allan.totdev, numpy_totvar),
        ("hdev", gyrobias.allan.hdev, numpy_hvar),
        ("adev", gyrobias.allan.adev, numpy_avar),
    ):
        t_ours = best_of(lambda f=ours: f(data, fs, taus="octave", confidence=None), repeats=5)
        t_numpy = best_of(numpy_all(kernel), repeats=3)
        out.append((f"{name} ({rows:.0e}, 6) octave, no intervals", t_ours, t_numpy))
    return out


def bench_scaling(fn: object, sizes: tuple[int, ...]) -> list[tuple[int, float]]:
    """Wall-clock of ``fn(rate, 1.0)`` (octave τ, no intervals) on white FM of each size."""
    out = []
    for n in sizes:
        rate = np.random.default_rng(3).normal(size=n)
        repeats = 3 if n <= 100_000 else 1
        t = best_of(lambda r=rate: fn(r, 1.0, confidence=None), repeats=repeats)  # type: ignore[operator]
        out.append((n, t))
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--quick",
        action="store_true",
        help="time AllanTools' MTOT/HTOT up to m = 16 only",
    )
    args = parser.parse_args()
    rows = bench_total(10_000, 16 if args.quick else 64)
    rows += bench_theo1(100_000, 32)
    print(f"{'case':<62} {'gyrobias [s]':>12} {'AllanTools [s]':>15} {'ratio':>9}")
    for name, ours, theirs in rows:
        print(f"{name:<62} {ours:12.4f} {theirs:15.2f} {theirs / ours:8.0f}×")
    print("targets: mtotdev/htotdev N=1e4 octave ≥ 100×, theo1 N=1e5 ≥ 20×")
    print()
    print(f"{'explorer statistics':<46} {'gyrobias [s]':>12} {'NumPy passes [s]':>17} {'ratio':>7}")
    for name, ours, theirs in bench_explorer(200_000 if args.quick else 1_000_000):
        print(f"{name:<46} {ours:12.4f} {theirs:17.4f} {theirs / ours:6.1f}×")
    print("target: mdev ≥ 8× the NumPy passes")
    sizes = (10_000, 100_000) if args.quick else (10_000, 100_000, 1_000_000)
    print()
    print(f"{'scaling (gyrobias only, octave τ)':<40} {'N':>9} {'time [s]':>10} {'× prev.':>8}")
    for name, fn in (("theo1", gyrobias.allan.theo1), ("theobr", gyrobias.allan.theobr)):
        previous = None
        for n, t in bench_scaling(fn, sizes):
            growth = "" if previous is None else f"{t / previous:7.0f}×"
            print(f"{name:<40} {n:9.0e} {t:10.3f} {growth:>8}")
            previous = t


if __name__ == "__main__":
    main()
