"""Benchmark: the cleaning steps and the min/max envelope on a long 6-channel log.

Targets (gyrobias issue 35, the explorer's log view and cleaning steps):

- ``cleaning.minmax_envelope`` of a 10⁷ × 6 float64 log (2.8 h at 1 kHz) into 2000 bins at
  least as fast as the NumPy baseline measured in the same run — ``x[:m·b].reshape(b, m, 6)``
  then ``.min(axis=1)`` and ``.max(axis=1)``, which ignores NaN, drops the remainder and makes
  two passes — and fast enough to redraw on a zoom (< 0.3 s);
- ``remove_outliers`` and ``detrend`` of a 10⁶ × 6 log (the interactive size) each well under
  0.3 s, compared with the NumPy reference (``np.nanmedian`` twice; ``polyfit`` per channel).

Run: ``PYTHONPATH=python python benches/python/bench_cleaning.py`` (``--quick``: 10⁶ rows for
the envelope).
"""

from __future__ import annotations

import sys

import numpy as np
from _timing import best_of

from gyrobias import cleaning


def numpy_envelope(x: np.ndarray, bins: int) -> tuple[np.ndarray, np.ndarray]:
    m = x.shape[0] // bins
    v = x[: m * bins].reshape(bins, m, x.shape[1])
    return v.min(axis=1), v.max(axis=1)


def numpy_outliers(x: np.ndarray, threshold: float) -> np.ndarray:
    center = np.nanmedian(x, axis=0)
    scale = 1.4826 * np.nanmedian(np.abs(x - center), axis=0)
    return np.where(np.abs(x - center) > threshold * scale, np.nan, x)


def numpy_detrend(x: np.ndarray, fs: float) -> np.ndarray:
    t = np.arange(x.shape[0]) / fs
    c = np.polynomial.polynomial.polyfit(t, x, 1)
    return x - np.polynomial.polynomial.polyval(t, c).T


def bench_envelope(rows: int, bins: int = 2000) -> bool:
    x = np.random.default_rng(0).normal(size=(rows, 6))
    ours = best_of(lambda: cleaning.minmax_envelope(x, bins), 5)
    base = best_of(lambda: numpy_envelope(x, bins), 5)
    e = cleaning.minmax_envelope(x, bins)
    lo, hi = numpy_envelope(x, bins)
    # Same bins when bins divides the rows (it does here): identical values.
    assert rows % bins == 0 and np.array_equal(e.lower, lo) and np.array_equal(e.upper, hi)
    print(f"minmax_envelope {rows:,} x 6 -> {bins} bins")
    print(
        f"  gyrobias {ours * 1e3:8.1f} ms   NumPy reshape min+max {base * 1e3:8.1f} ms   "
        f"ratio {base / ours:5.2f}x  (target: >= 1x and < 300 ms)"
    )
    return ours <= base and ours < 0.3


def bench_steps(n: int = 1_000_000, fs: float = 100.0) -> bool:
    rng = np.random.default_rng(1)
    y = rng.normal(size=(n, 6)) + np.linspace(0.0, 1.0, n)[:, None]
    y[rng.choice(n, 100, replace=False), 0] = 50.0
    t_out = best_of(lambda: cleaning.remove_outliers(y, 5.0), 3)
    t_out_np = best_of(lambda: numpy_outliers(y, 5.0), 3)
    t_det = best_of(lambda: cleaning.detrend(y, fs, 1), 3)
    t_det_np = best_of(lambda: numpy_detrend(y, fs), 3)
    print(f"cleaning {n:,} x 6")
    print(
        f"  remove_outliers {t_out * 1e3:7.1f} ms   NumPy nanmedian x2 {t_out_np * 1e3:7.1f} ms   "
        f"ratio {t_out_np / t_out:5.2f}x  (target: < 300 ms)"
    )
    print(
        f"  detrend linear  {t_det * 1e3:7.1f} ms   NumPy polyfit       {t_det_np * 1e3:7.1f} ms   "
        f"ratio {t_det_np / t_det:5.2f}x  (target: < 300 ms)"
    )
    return t_out < 0.3 and t_det < 0.3


def main() -> None:
    rows = 1_000_000 if "--quick" in sys.argv else 10_000_000
    ok = bench_envelope(rows)
    ok = bench_steps() and ok
    print("  targets met" if ok else "  TARGET MISSED")


if __name__ == "__main__":
    main()
