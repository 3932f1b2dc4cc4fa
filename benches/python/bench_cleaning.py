"""Benchmark: the cleaning steps and the min/max envelope on a long 6-channel log.

Targets (gyrobias issue 35, the explorer's log view and cleaning steps):

- ``cleaning.minmax_envelope`` of a 10⁷ × 6 float64 log (2.8 h at 1 kHz) into 2000 bins at
  least as fast as the NumPy baseline measured in the same run — ``x[:m·b].reshape(b, m, 6)``
  then ``.min(axis=1)`` and ``.max(axis=1)``, which ignores NaN, drops the remainder and makes
  two passes — and fast enough to redraw on a zoom (< 0.3 s);
- ``remove_outliers`` and ``detrend`` of a 10⁶ × 6 log (the interactive size) each well under
  0.3 s, compared with the NumPy reference (``np.nanmedian`` twice; ``polyfit`` per channel);
- the explorer's calls on 10⁶ × 6 (``clean(..., outliers=5, out=buffer).has_gaps`` and
  ``clean(..., detrend="linear", out=buffer).has_gaps``) at least 4x faster than the lightest
  NumPy equivalent measured in the same run (``np.median`` twice over a copy, no gap
  handling, then ``np.where`` and ``np.isnan(...).any()``; a column ``polyfit`` plus the scan).

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


def numpy_explorer_outliers(x: np.ndarray, buf: np.ndarray, threshold: float) -> bool:
    """The lightest NumPy equivalent of the explorer's outlier step: medians by
    ``np.median`` (introselect, gaps not handled), the result into ``buf``, the gap scan."""
    center = np.median(x, axis=0)
    dev = np.abs(x - center)
    scale = MAD_TO_SD * np.median(dev, axis=0)
    np.copyto(buf, x)
    buf[dev > threshold * scale] = np.nan
    return bool(np.isnan(buf).any())


def numpy_explorer_detrend(x: np.ndarray, buf: np.ndarray, fs: float) -> bool:
    np.copyto(buf, numpy_detrend(x, fs))
    return bool(np.isnan(buf).any())


MAD_TO_SD = 1.482602218505602


def bench_explorer(n: int = 1_000_000, fs: float = 100.0) -> bool:
    """The explorer's calls (``explore/state.py``: one working buffer, ``has_gaps`` next)."""
    rng = np.random.default_rng(2)
    x = rng.normal(size=(n, 6)) + np.linspace(0.0, 1.0, n)[:, None]
    x[rng.choice(n, 100, replace=False), 2] = 50.0
    buf = np.empty_like(x)
    units = ["deg/s"] * 3 + ["m/s^2"] * 3

    def ours_out() -> bool:
        return cleaning.clean(x, fs, outliers=5.0, units=units, out=buf).has_gaps

    def ours_det() -> bool:
        return cleaning.clean(x, fs, detrend="linear", units=units, out=buf).has_gaps

    t_out = best_of(ours_out, 7)
    t_out_np = best_of(lambda: numpy_explorer_outliers(x, buf, 5.0), 3)
    t_det = best_of(ours_det, 7)
    t_det_np = best_of(lambda: numpy_explorer_detrend(x, buf, fs), 3)
    c = cleaning.clean(x, fs, outliers=5.0, out=buf)
    assert c.outliers is not None and c.has_gaps and c.outliers.total >= 100
    print(f"explorer cleaning {n:,} x 6 into a working buffer, then has_gaps")
    print(
        f"  outliers 5σ     {t_out * 1e3:7.1f} ms   NumPy median x2     {t_out_np * 1e3:7.1f} ms   "
        f"ratio {t_out_np / t_out:5.2f}x  (target: >= 4x)"
    )
    print(
        f"  linear drift    {t_det * 1e3:7.1f} ms   NumPy polyfit       {t_det_np * 1e3:7.1f} ms   "
        f"ratio {t_det_np / t_det:5.2f}x  (target: >= 4x)"
    )
    return t_out * 4 <= t_out_np and t_det * 4 <= t_det_np


def main() -> None:
    rows = 1_000_000 if "--quick" in sys.argv else 10_000_000
    ok = bench_envelope(rows)
    ok = bench_steps() and ok
    ok = bench_explorer() and ok
    print("  targets met" if ok else "  TARGET MISSED")


if __name__ == "__main__":
    main()
