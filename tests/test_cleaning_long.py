"""gyrobias.cleaning on long logs: the sampled-bracket statistics of the outlier step (≥ 32768
rows), the buffer variants (``out=``) and the gap count behind ``CleaningResult.has_gaps``.

The core takes a long column's median and MAD from two passes over the rows (a sample of rows
brackets each order statistic, the values inside the bracket are selected); these tests compare
it with an independent NumPy reference (``np.median`` of the finite samples, the same order
statistics, so equal to the last bit) on logs built to hit every path: spikes, gaps, infinities,
heavy tails, coarse quantisation (MAD 0), constants and signed zeros.
"""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from gyrobias import cleaning

MAD_TO_SD = 1.482602218505602  # 1/Φ⁻¹(3/4)
LONG = 1 << 15  # the core's sampled path starts here (SAMPLED_MIN_ROWS)


def ref_center_scale(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Median and scale per column with NumPy (finite samples; MAD 0 → 1.2533·mean|x − m|)."""
    centers, scales = [], []
    for col in x.T:
        f = col[np.isfinite(col)]
        m = np.median(f)
        dev = np.abs(f - m)
        mad = np.median(dev)
        centers.append(m)
        scales.append(MAD_TO_SD * mad if mad > 0 else np.sqrt(np.pi / 2) * dev.mean())
    return np.array(centers), np.array(scales)


def hostile_log(n: int, seed: int, nan_share: float, step: float, spikes: float) -> np.ndarray:
    rng = np.random.default_rng(seed)
    x = rng.standard_normal((n, 6))
    x[:, 1] = np.round(x[:, 1] / step) * step if step > 0 else x[:, 1]  # quantised
    x[:, 2] = rng.standard_cauchy(n)  # heavy tails
    x[:, 3] = 0.25  # constant
    x[rng.random(n) < 0.9, 4] = 0.0  # 90 % zeros: MAD 0
    x[:, 4][rng.random(n) < 0.5] *= -1.0  # signed zeros
    hit = rng.random((n, 6)) < spikes
    x[hit] += 50.0
    x[rng.random((n, 6)) < nan_share] = np.nan
    x[rng.integers(0, n, 3), 0] = np.inf
    return x


def test_long_log_statistics_match_numpy_exactly() -> None:
    x = hostile_log(LONG + 1001, seed=3, nan_share=0.05, step=0.25, spikes=0.01)
    r = cleaning.remove_outliers(x, 5.0)
    center, scale = ref_center_scale(x)
    # The same order statistics (NumPy's median averages the two middle values as the core's):
    # identical to the last bit; the mean-deviation fallback (MAD 0: the constant and the
    # mostly-zero columns) is a compensated sum in another order: 1e-12 relative.
    fallback = np.array([3, 4])
    np.testing.assert_array_equal(r.center, center)
    np.testing.assert_array_equal(np.delete(r.scale, fallback), np.delete(scale, fallback))
    np.testing.assert_allclose(r.scale[fallback], scale[fallback], rtol=1e-12)
    with np.errstate(invalid="ignore"):
        z = np.abs(x - r.center) / r.scale
    want = np.where(r.scale > 0, z > 5.0, np.abs(x - r.center) > 0) & ~np.isnan(x)
    np.testing.assert_array_equal(r.mask, want)
    np.testing.assert_array_equal(np.isnan(r.data), np.isnan(x) | want)
    np.testing.assert_array_equal(r.data[~np.isnan(r.data)], x[~np.isnan(r.data)])


@settings(max_examples=12, derandomize=True, deadline=None)
@given(
    n=st.integers(LONG, LONG + 5000),
    seed=st.integers(0, 2**16),
    nan_share=st.sampled_from([0.0, 0.01, 0.4]),
    step=st.sampled_from([0.0, 0.5, 4.0]),
    spikes=st.sampled_from([0.0, 0.001, 0.05]),
    threshold=st.floats(1.0, 8.0),
)
def test_buffer_variants_agree_and_count_the_gaps(
    n: int, seed: int, nan_share: float, step: float, spikes: float, threshold: float
) -> None:
    x = hostile_log(n, seed, nan_share, step, spikes)
    before = x.copy()
    plain = cleaning.clean(x, 100.0, outliers=threshold)
    buf = np.full_like(x, 7.0)
    into = cleaning.clean(x, 100.0, outliers=threshold, out=buf)
    same = x.copy()
    inplace = cleaning.clean(same, 100.0, outliers=threshold, out=same)
    np.testing.assert_array_equal(x, before)  # the input is never modified
    for r in (into, inplace):
        assert r.outliers is not None and plain.outliers is not None
        np.testing.assert_array_equal(r.data, plain.data)
        np.testing.assert_array_equal(r.outliers.mask, plain.outliers.mask)
        np.testing.assert_array_equal(r.outliers.center, plain.outliers.center)
        np.testing.assert_array_equal(r.outliers.scale, plain.outliers.scale)
    assert into.data is not None and np.shares_memory(into.data, buf)
    nan = int(np.isnan(plain.data).sum())
    assert plain.gaps == into.gaps == inplace.gaps == nan
    assert plain.has_gaps == bool(nan)
    center, _ = ref_center_scale(x)
    assert plain.outliers is not None
    np.testing.assert_array_equal(plain.outliers.center, center)


def test_detrend_into_a_buffer_and_gap_count() -> None:
    rng = np.random.default_rng(5)
    n = 50_000
    t = np.arange(n) / 100.0
    x = rng.standard_normal((n, 6)) + 0.01 * t[:, None]
    plain = cleaning.clean(x, 100.0, detrend="linear")
    buf = np.empty_like(x)
    into = cleaning.clean(x, 100.0, detrend="linear", out=buf)
    np.testing.assert_array_equal(into.data, plain.data)
    assert plain.gaps == into.gaps == 0 and not into.has_gaps
    # Reference: NumPy's least squares per column (conditioning ≈ 5 in the core's basis; a
    # residual to 1e-9 of the data scale).
    coef = np.polynomial.polynomial.polyfit(t, x, 1)
    ref = x - np.polynomial.polynomial.polyval(t, coef).T
    np.testing.assert_allclose(into.data, ref, atol=1e-9)
    x[::997, 2] = np.nan
    both = cleaning.clean(x, 100.0, outliers=5.0, detrend="quadratic", out=buf)
    assert both.gaps == int(np.isnan(both.data).sum()) and both.has_gaps


def test_counted_gaps_are_a_snapshot_and_uncounted_results_look() -> None:
    x = np.zeros((10, 2))
    x[3, 1] = np.nan
    r = cleaning.CleaningResult(data=x)
    assert r.gaps is None and r.has_gaps  # not counted: looks at the data
    assert not cleaning.CleaningResult(data=x, gaps=0).has_gaps
