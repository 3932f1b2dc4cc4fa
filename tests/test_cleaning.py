"""gyrobias.cleaning: outlier removal, drift removal and the min/max envelope.

Every result is compared with an independent NumPy reference written here (median/MAD with
``np.nanmedian``, ``numpy.polynomial.polynomial.polyfit`` on the finite samples, reshaped
``np.nanmin``/``np.nanmax``), plus hypothesis properties and the bad-input messages.
"""

from __future__ import annotations

import os
import subprocess
import sys

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from gyrobias import allan, cleaning

MAD_TO_SD = 1.482602218505602  # 1/Φ⁻¹(3/4)


# ---------------------------------------------------------------------------------------------
# References (no code shared with gyrobias)


def ref_outliers(data: np.ndarray, threshold: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(mask, center, scale) by NumPy's nanmedian; the MAD = 0 fallback: 1.2533·mean|x − m|."""
    x = np.asarray(data, dtype=float).reshape(len(data), -1)
    finite = np.where(np.isfinite(x), x, np.nan)
    center = np.nanmedian(finite, axis=0)
    dev = np.abs(finite - center)
    mad = np.nanmedian(dev, axis=0)
    scale = np.where(mad > 0, MAD_TO_SD * mad, np.sqrt(np.pi / 2) * np.nanmean(dev, axis=0))
    with np.errstate(divide="ignore", invalid="ignore"):
        z = np.abs(x - center) / scale
    mask = np.where(scale > 0, z > threshold, np.abs(x - center) > 0)
    mask &= ~np.isnan(x)
    return mask, center, scale


def ref_detrend(data: np.ndarray, fs: float, order: int) -> tuple[np.ndarray, np.ndarray]:
    """(residual, coefficients low → high) by numpy.polynomial's least squares on finite samples."""
    x = np.asarray(data, dtype=float).reshape(len(data), -1)
    t = np.arange(len(x)) / fs
    out = np.empty_like(x)
    coefs = []
    for j in range(x.shape[1]):
        ok = np.isfinite(x[:, j])
        c = np.polynomial.polynomial.polyfit(t[ok], x[ok, j], order)
        coefs.append(c)
        out[:, j] = x[:, j] - np.polynomial.polynomial.polyval(t, c)
    return out, np.array(coefs)


# ---------------------------------------------------------------------------------------------
# Outliers


def _spiky(n: int = 20_000, k: int = 3, seed: int = 0) -> np.ndarray:
    rng = np.random.default_rng(seed)
    x = rng.normal(0.0, 1.0, (n, k)) + np.arange(k)
    idx = rng.choice(n, 40, replace=False)
    x[idx, rng.integers(0, k, 40)] += rng.choice([-1, 1], 40) * rng.uniform(6, 50, 40)
    x[rng.choice(n, 30, replace=False), k // 2] = np.nan  # gaps
    return x


def test_outliers_match_the_numpy_reference() -> None:
    x = _spiky()
    before = x.copy()
    r = cleaning.remove_outliers(x, 5.0, units="deg/s")
    mask, center, scale = ref_outliers(x, 5.0)
    np.testing.assert_array_equal(x, before)  # input unchanged (NaN included)
    # The same order statistics: exact; the scale is one product: rtol 1e-15.
    np.testing.assert_array_equal(r.center, center)
    np.testing.assert_allclose(r.scale, scale, rtol=1e-15)
    np.testing.assert_array_equal(r.mask, mask)
    np.testing.assert_array_equal(r.count, mask.sum(axis=0))
    assert r.count.dtype == np.int64 and r.total == int(mask.sum()) > 30
    expected = np.where(mask, np.nan, x)
    np.testing.assert_array_equal(r.data, expected)
    assert r.units == ("deg/s",) * 3 and r.threshold == 5.0 and r.method == "mad"
    assert r.to_dict()["count"] == mask.sum(axis=0).tolist()


def test_outliers_keep_the_shape_of_1d_input_and_chain() -> None:
    x = _spiky(k=1)[:, 0]
    r = cleaning.remove_outliers(x, 4.0)
    assert r.data.shape == r.mask.shape == x.shape and r.count.shape == (1,)
    # A second pass at the same threshold sees the outliers as gaps: it is not the identity
    # (the MAD shrinks) but never flags a gap and never un-flags one.
    again = cleaning.remove_outliers(r.data, 4.0)
    assert not (again.mask & np.isnan(r.data)).any()
    assert np.isnan(again.data[r.mask]).all()


def test_outlier_result_is_analysed_by_allan_with_gaps_omit() -> None:
    rng = np.random.default_rng(3)
    rate = rng.normal(0.0, 0.1, 200_000)
    rate[rng.choice(200_000, 50, replace=False)] = 40.0
    spiky = allan.adev(rate, 100.0, taus=[0.01, 0.1, 1.0])
    clean = cleaning.remove_outliers(rate, 5.0)
    assert clean.count.tolist() == [50]
    r = allan.adev(clean.data, 100.0, gaps="omit", taus=[0.01, 0.1, 1.0])
    assert isinstance(r, allan.AllanResult) and isinstance(spiky, allan.AllanResult)
    # The spikes dominated ADEV; without them the white-noise level 0.1·√(t0/τ) comes back
    # (EDF of 10^5 terms: a 1 % tolerance is > 5σ at τ = 0.01 s, 10 % at 1 s is ~3σ).
    ratio = r.adev / (0.1 * np.sqrt(0.01 / r.taus))
    assert (np.abs(ratio - 1.0) < [0.01, 0.03, 0.1]).all(), ratio
    assert spiky.adev[0] > 3 * r.adev[0]
    with pytest.raises(ValueError, match="NaN"):  # the default gaps="error" names the gap
        allan.adev(clean.data, 100.0)


def test_outliers_of_quantised_and_constant_channels() -> None:
    x = np.zeros((100, 2))
    x[:10, 0] = 1.0  # 90 % at the median: MAD 0, mean |x − m| = 0.1
    r = cleaning.remove_outliers(x, 5.0)
    assert r.scale[0] == pytest.approx(np.sqrt(np.pi / 2) * 0.1, rel=1e-15)
    assert r.count.tolist() == [10, 0] and r.scale[1] == 0.0
    inf = np.arange(10.0)
    inf[4] = np.inf
    assert cleaning.remove_outliers(inf, 5.0).mask[4]
    assert cleaning.remove_outliers(inf, 1e300).mask.tolist() == [i == 4 for i in range(10)]


@settings(max_examples=60, derandomize=True, deadline=None)
@given(
    n=st.integers(3, 400),
    k=st.integers(1, 4),
    seed=st.integers(0, 2**32 - 1),
    threshold=st.floats(0.7, 20.0),
)
def test_outlier_properties(n: int, k: int, seed: int, threshold: float) -> None:
    rng = np.random.default_rng(seed)
    x = rng.standard_t(2, (n, k)) * rng.uniform(1e-3, 1e3)
    before = x.copy()
    r = cleaning.remove_outliers(x, threshold)
    np.testing.assert_array_equal(x, before)
    mask, _, _ = ref_outliers(x, threshold)
    np.testing.assert_array_equal(r.mask, mask)
    # A threshold above every robust z-score flags nothing; a larger threshold flags a subset.
    z_max = float(np.max(np.abs(x - r.center) / r.scale))
    assert not cleaning.remove_outliers(x, z_max * (1 + 1e-9)).mask.any()
    assert not (cleaning.remove_outliers(x, threshold * 2).mask & ~r.mask).any()
    # With threshold >= 1/1.4826 a flagged sample lies beyond the MAD: at most half of them.
    assert (r.count <= n // 2).all()


@pytest.mark.parametrize(
    ("kwargs", "error", "match"),
    [
        ({"threshold": 0.0}, ValueError, "threshold must be finite and > 0"),
        ({"threshold": -3.0}, ValueError, "threshold must be finite and > 0"),
        ({"threshold": float("nan")}, ValueError, "threshold must be finite and > 0"),
        ({"threshold": float("inf")}, ValueError, "threshold must be finite and > 0"),
        ({"threshold": "5"}, TypeError, "threshold must be a real number"),
        ({"method": "iqr"}, ValueError, "method"),
        ({"units": "furlong"}, ValueError, "units"),
        ({"units": ["deg/s"]}, ValueError, "units has 1 entries for 2 channels"),
    ],
)
def test_outlier_bad_arguments(kwargs: dict[str, object], error: type, match: str) -> None:
    with pytest.raises(error, match=match):
        cleaning.remove_outliers(np.ones((10, 2)), **kwargs)  # type: ignore[arg-type]


@pytest.mark.parametrize(
    ("data", "error", "match"),
    [
        (np.full(10, np.nan), ValueError, "column 0 has 0 finite samples"),
        (np.array([[1.0, np.nan], [2.0, np.nan], [3.0, 4.0]]), ValueError, "column 1 has 1"),
        (np.ones(2), ValueError, "data is too short"),
        (np.ones((2, 2, 2)), ValueError, "data must be a 1-D or 2-D array"),
        (np.array([]), ValueError, "data is empty"),
        (np.array(["a", "b", "c"]), TypeError, "data must be a real numeric array"),
        ([[1.0, 2.0], [3.0]], ValueError, "data must be a rectangular array"),
    ],
)
def test_cleaning_bad_data(data: object, error: type, match: str) -> None:
    with pytest.raises(error, match=match):
        cleaning.remove_outliers(data, 5.0)  # type: ignore[arg-type]


# ---------------------------------------------------------------------------------------------
# Drift


@pytest.mark.parametrize("order", [1, 2])
def test_detrend_matches_numpy_polyfit(order: int) -> None:
    rng = np.random.default_rng(1)
    n, fs = 50_001, 200.0
    t = np.arange(n) / fs
    x = np.column_stack([3.0 + 1e-3 * t + 2e-6 * t**2, -0.4 * t, 1e4 + 0.0 * t])
    x += rng.normal(0.0, 0.05, x.shape)
    x[rng.choice(n, 500, replace=False), 0] = np.nan
    before = x.copy()
    r = cleaning.detrend(x, fs, order, units=["deg/s", "deg/s", "m/s^2"])
    residual, coefs = ref_detrend(x, fs, order)
    np.testing.assert_array_equal(x, before)
    # Both are least-squares solutions of a well-conditioned problem (Legendre basis here,
    # polyfit's scaled Vandermonde + lstsq there): agreement to ~1e-9 of the data's scale.
    np.testing.assert_allclose(r.coefficients, coefs, rtol=1e-7, atol=1e-9)
    np.testing.assert_allclose(r.data, residual, atol=1e-8)
    assert np.isnan(r.data[:, 0]).sum() == 500
    assert r.coefficients.shape == (3, order + 1) and r.order == order and r.fs == fs
    assert r.kind == ("linear", "quadratic")[order - 1]
    assert r.coefficient_units[0][: order + 1] == ("deg/s", "deg/s^2", "deg/s^3")[: order + 1]
    assert r.coefficient_units[2][1] == "m/s^3"
    assert r.to_dict()["coefficients"] == r.coefficients.tolist()


def test_detrend_is_stable_on_long_logs_with_a_large_offset() -> None:
    # 10^7 samples at 1 kHz with a 1e3 offset: powers of raw t (up to 1e8 s²) would lose ~8
    # digits in the normal equations; the Legendre fit recovers the drift to 1e-12 relative.
    n, fs = 10_000_000, 1000.0
    t = np.arange(n) / fs
    x = 1e3 + 2e-4 * t - 3e-8 * t**2
    r = cleaning.detrend(x, fs, order=2)
    np.testing.assert_allclose(r.coefficients[0], [1e3, 2e-4, -3e-8], rtol=1e-9)
    assert np.max(np.abs(r.data)) < 1e-8


@settings(max_examples=60, derandomize=True, deadline=None)
@given(
    n=st.integers(4, 2000),
    order=st.sampled_from([1, 2]),
    c=st.tuples(*[st.floats(-1e3, 1e3, allow_subnormal=False)] * 3),
    fs=st.floats(0.01, 1e4),
    gaps=st.integers(0, 10),
)
def test_detrend_of_an_exact_polynomial_leaves_zero(
    n: int, order: int, c: tuple[float, float, float], fs: float, gaps: int
) -> None:
    t = np.arange(n) / fs
    coefs = np.array(c[: order + 1]) / np.array([1.0, t[-1], t[-1] ** 2][: order + 1])
    x = np.polynomial.polynomial.polyval(t, coefs)
    x[np.random.default_rng(n).choice(n, min(gaps, n - order - 2), replace=False)] = np.nan
    r = cleaning.detrend(x, fs, order)
    scale = max(1.0, float(np.nanmax(np.abs(x))))
    # Rounding of the inputs and of the fit: a few hundred ulps of the data's magnitude.
    assert np.nanmax(np.abs(r.data)) <= 1e-11 * scale
    np.testing.assert_array_equal(np.isnan(r.data), np.isnan(x))


@pytest.mark.parametrize(
    ("args", "error", "match"),
    [
        ((np.ones(10), 1.0, 3), ValueError, "order must be 1 .linear. or 2 .quadratic., got 3"),
        ((np.ones(10), 1.0, 0), ValueError, "order must be 1"),
        ((np.ones(10), 1.0, -1), ValueError, "order"),
        ((np.ones(10), 1.0, 1.5), TypeError, "order must be an integer"),
        ((np.ones(10), 0.0, 1), ValueError, "fs must be finite and > 0"),
        ((np.ones(10), float("nan"), 1), ValueError, "fs must be finite"),
        ((np.full(10, np.nan), 1.0, 1), ValueError, "column 0 has 0 finite samples"),
        ((np.ones(3), 1.0, 2), ValueError, "data is too short"),
        ((np.array([1.0, np.inf, 2.0, 3.0]), 1.0, 1), ValueError, "data contains a non-finite"),
        ((np.ones((2, 2, 2)), 1.0, 1), ValueError, "data must be a 1-D or 2-D array"),
    ],
)
def test_detrend_bad_arguments(args: tuple[object, ...], error: type, match: str) -> None:
    with pytest.raises(error, match=match):
        cleaning.detrend(*args)  # type: ignore[arg-type]


def test_cleaning_steps_chain_in_stable32_order() -> None:
    rng = np.random.default_rng(7)
    n, fs = 100_000, 100.0
    t = np.arange(n) / fs
    rate = rng.normal(0.0, 0.1, (n, 2)) + np.column_stack([0.01 * t, -0.02 * t])
    rate[[10, 20_000, 77_777], 0] = 30.0
    part = rate[10_000:90_000]  # the part
    clean = cleaning.remove_outliers(part, 5.0)
    flat = cleaning.detrend(clean.data, fs, 1)
    assert clean.count.tolist() == [2, 0]
    np.testing.assert_allclose(flat.coefficients[:, 1], [0.01, -0.02], rtol=2e-3)
    curves = allan.adev(flat.data, fs, gaps="omit", taus=[0.01, 10.0])
    assert isinstance(curves, tuple)
    # The drift's +1 slope is gone: ADEV at 10 s is white noise's 0.1·√(0.01/10) (~8000 terms
    # of ~80 independent ones: EDF ~ 80, 1σ ≈ 8 %; 25 % is ~3σ).
    np.testing.assert_allclose([c.adev[1] for c in curves], 0.1 * np.sqrt(1e-3), rtol=0.25)


# ---------------------------------------------------------------------------------------------
# Envelope


def test_envelope_matches_numpy() -> None:
    rng = np.random.default_rng(2)
    x = rng.normal(size=(10_007, 3))
    x[5:900, 1] = np.nan  # whole bins of gaps
    x[3000, 2] = np.inf
    e = cleaning.minmax_envelope(x, 100)
    starts = (np.arange(101) * 10_007) // 100
    np.testing.assert_array_equal(e.starts, starts)
    with np.errstate(all="ignore"), pytest.warns(RuntimeWarning, match="All-NaN"):
        lo = np.array([np.nanmin(x[a:b], axis=0) for a, b in zip(starts[:-1], starts[1:])])
        hi = np.array([np.nanmax(x[a:b], axis=0) for a, b in zip(starts[:-1], starts[1:])])
    np.testing.assert_array_equal(e.lower, lo)
    np.testing.assert_array_equal(e.upper, hi)
    assert e.bins == 100 and np.isnan(e.lower[1, 1])


def test_envelope_of_1d_and_tiny_input() -> None:
    e = cleaning.minmax_envelope([3.0, 1.0, 2.0], 10)  # more bins than samples: one per sample
    assert e.starts.tolist() == [0, 1, 2, 3] and e.lower[:, 0].tolist() == [3.0, 1.0, 2.0]
    whole = cleaning.minmax_envelope(np.arange(7.0), 1)
    assert whole.lower.tolist() == [[0.0]] and whole.upper.tolist() == [[6.0]]


@settings(max_examples=60, derandomize=True, deadline=None)
@given(n=st.integers(1, 3000), k=st.integers(1, 7), bins=st.integers(1, 500))
def test_envelope_properties(n: int, k: int, bins: int) -> None:
    x = np.random.default_rng(n * 31 + k).normal(size=(n, k))
    e = cleaning.minmax_envelope(x, bins)
    b = min(bins, n)
    assert e.lower.shape == e.upper.shape == (b, k)
    assert e.starts[0] == 0 and e.starts[-1] == n and (np.diff(e.starts) >= 1).all()
    # The envelope of the envelope is the data's range; every bin contains its extremes.
    np.testing.assert_array_equal(e.lower.min(axis=0), x.min(axis=0))
    np.testing.assert_array_equal(e.upper.max(axis=0), x.max(axis=0))
    assert (e.lower <= e.upper).all()


@pytest.mark.parametrize(
    ("bins", "error", "match"),
    [(0, ValueError, "bins must be >= 1"), (-2, ValueError, "bins"), (2.5, TypeError, "bins")],
)
def test_envelope_bad_bins(bins: object, error: type, match: str) -> None:
    with pytest.raises(error, match=match):
        cleaning.minmax_envelope(np.ones(10), bins)  # type: ignore[arg-type]


# ---------------------------------------------------------------------------------------------
# Threads

_DIGEST = """
import hashlib, numpy as np
from gyrobias import cleaning
rng = np.random.default_rng(0)
x = rng.standard_t(3, (300_001, 4)) + np.linspace(0, 5, 300_001)[:, None]
x[::97, 2] = np.nan
h = hashlib.sha256()
o = cleaning.remove_outliers(x, 4.0)
d = cleaning.detrend(o.data, 100.0, 2)
e = cleaning.minmax_envelope(x, 1234)
for a in (o.data, o.mask, o.center, o.scale, d.data, d.coefficients, e.lower, e.upper):
    h.update(np.ascontiguousarray(a).tobytes())
print(h.hexdigest())
"""


def test_thread_count_does_not_change_results() -> None:
    digests = set()
    for threads in ("1", "2", "5"):
        env = dict(os.environ, RAYON_NUM_THREADS=threads)
        out = subprocess.run(
            [sys.executable, "-c", _DIGEST], env=env, check=True, capture_output=True, text=True
        )
        digests.add(out.stdout.strip())
    assert len(digests) == 1


# ---------------------------------------------------------------------------------------------
# out=: the caller's buffer (an app cleaning again and again reuses one working copy)


def _messy(n: int, k: int, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    x = rng.normal(0.0, 1.0, (n, k)) + 1e-3 * np.arange(n)[:, None]
    x[rng.integers(0, n, 3), rng.integers(0, k, 3)] = 40.0  # spikes
    x[n // 2, 0] = np.nan  # a gap
    return x


def _same_bits(a: np.ndarray, b: np.ndarray) -> bool:
    return a.shape == b.shape and bool(np.array_equal(a.view(np.int64), b.view(np.int64)))


@settings(max_examples=40, derandomize=True, deadline=None)
@given(
    n=st.integers(20, 3000),
    k=st.integers(1, 5),
    seed=st.integers(0, 2**16),
    outliers=st.sampled_from([None, 3.0, 5.0]),
    drift=st.sampled_from([None, "linear", "quadratic"]),
)
def test_out_gives_the_results_of_a_new_copy_bit_for_bit(
    n: int, k: int, seed: int, outliers: float | None, drift: str | None
) -> None:
    x = _messy(n, k, seed)
    before = x.copy()
    fresh = cleaning.clean(x, 100.0, outliers=outliers, detrend=drift)
    buf = np.full_like(x, 7.0)  # stale contents never show through
    into = cleaning.clean(x, 100.0, outliers=outliers, detrend=drift, out=buf)
    assert _same_bits(into.data, fresh.data)
    assert _same_bits(x, before)  # the input is never modified
    if outliers is not None or drift is not None:
        assert np.shares_memory(into.data, buf)
    if outliers is not None:
        assert into.outliers is not None and fresh.outliers is not None
        np.testing.assert_array_equal(into.outliers.mask, fresh.outliers.mask)
        np.testing.assert_array_equal(into.outliers.count, fresh.outliers.count)
        # and as the step alone (the reference path: a new copy, then a new residual)
        alone = cleaning.remove_outliers(x, outliers, out=np.empty_like(x))
        assert _same_bits(alone.data, cleaning.remove_outliers(x, outliers).data)
    if drift is not None:
        assert into.drift is not None and fresh.drift is not None
        assert _same_bits(into.drift.coefficients, fresh.drift.coefficients)
        order = cleaning.ORDERS[drift]
        copy = x.copy()
        inplace = cleaning.detrend(copy, 100.0, order, out=copy)  # in place
        assert _same_bits(inplace.data, cleaning.detrend(x, 100.0, order).data)
        assert np.shares_memory(inplace.data, copy)


def test_clean_runs_both_steps_in_one_copy() -> None:
    x = _messy(5000, 3, 1)
    c = cleaning.clean(x, 100.0, outliers=5.0, detrend="linear")
    assert c.outliers is not None and c.drift is not None
    # the drift is removed where the outlier step left its result (one copy of the data)
    assert np.shares_memory(c.drift.data, c.outliers.data) and c.data is c.drift.data
    ref = cleaning.detrend(cleaning.remove_outliers(x, 5.0).data, 100.0)
    assert _same_bits(c.data, ref.data)


def test_out_of_a_1d_input_and_in_place_outliers() -> None:
    x = _messy(500, 1, 2)[:, 0].copy()
    ref = cleaning.remove_outliers(x, 4.0)
    r = cleaning.remove_outliers(x, 4.0, out=x)  # in place: out is the data itself
    assert r.data.shape == (500,) and np.shares_memory(r.data, x)
    assert _same_bits(x, ref.data)


@pytest.mark.parametrize(
    ("out", "error", "match"),
    [
        ([0.0] * 10, TypeError, "out must be a NumPy array"),
        (np.zeros((10, 2), dtype=np.float32), TypeError, "out must be a writable C-contiguous"),
        (np.zeros((2, 10)).T, TypeError, "out must be a writable C-contiguous"),
        (np.zeros((11, 2)), ValueError, r"out has shape \(11, 2\), the data \(10, 2\)"),
    ],
)
def test_out_bad_buffers(out: object, error: type, match: str) -> None:
    x = _messy(10, 2, 3)
    for call in (
        lambda: cleaning.remove_outliers(x, 5.0, out=out),  # type: ignore[arg-type]
        lambda: cleaning.detrend(x, 100.0, out=out),  # type: ignore[arg-type]
        lambda: cleaning.clean(x, 100.0, detrend="linear", out=out),  # type: ignore[arg-type]
    ):
        with pytest.raises(error, match=match):
            call()


def test_out_read_only_and_overlapping_buffers() -> None:
    x = _messy(10, 2, 4)
    frozen = np.zeros_like(x)
    frozen.flags.writeable = False
    with pytest.raises(TypeError, match="out must be a writable"):
        cleaning.detrend(x, 100.0, out=frozen)
    big = np.zeros((11, 2))
    big[:10] = x
    with pytest.raises(ValueError, match="out overlaps data"):
        cleaning.detrend(big[:10], 100.0, out=big[1:])
