"""The modified Allan and total variance kernels against exact integer arithmetic.

The modified Allan sum runs four re-seeded segments of its running sum in lockstep
(``crates/gyrocore/src/allan/modified.rs``) and the total variance reads the interior of the
record without the reflection lookup (``sum_total``); both keep the additions of the serial
loops, so they are exact wherever those are. On integer angle data every second difference and
every inner m-sum ``s_j`` is an integer below 2**53, so the running sums are exact and the only
rounding left is the summation of the squares: the results must equal the exact rational
formula (NIST SP 1065 eqs. 14 and 25, Python integers) to that summation's rounding.
"""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from gyrobias import allan

# Σ s_j² is accumulated in segments of at most max(4096, 4m) terms (then compensated across
# segments): relative error ≤ (terms per segment)·eps ≈ 4096·1.1e-16 = 4.5e-13 in the worst
# case (all terms equal), plus a few ulps for the normalisation.
RTOL = 1e-12


def _integer_angles(seed: int, n: int, amplitude: int) -> np.ndarray:
    """Quantised angle samples: white + random walk + drift, rounded to integers (LSB counts)."""
    rng = np.random.default_rng(seed)
    rate = rng.normal(0.0, 1.0, n) + np.cumsum(rng.normal(0.0, 0.02, n)) + 0.3
    x = np.cumsum(rate) * (amplitude / max(1.0, float(np.max(np.abs(np.cumsum(rate))))))
    return np.round(x).astype(np.int64)


def _exact_mvar(x: np.ndarray, m: int) -> float:
    """SP 1065 eq. 14 in Python integers: Σ_j (Σ_{i=j}^{j+m-1} d_i)² / (2 m⁴ (N − 3m + 1)), t0 = 1."""
    d = x[2 * m :] - 2 * x[m:-m] + x[: -2 * m]
    c = np.concatenate([[0], np.cumsum(d)])
    s = c[m:] - c[:-m]  # exact: |values| far below 2**63
    total = sum(int(v) * int(v) for v in s)
    terms = len(s)
    return total / (2 * m**4 * terms)


def _exact_totvar(x: np.ndarray, m: int) -> float:
    """SP 1065 eq. 25 on the reflected series, in Python integers, t0 = 1."""
    n = len(x)
    star = np.concatenate([2 * x[0] - x[n - 2 : 0 : -1], x, 2 * x[-1] - x[n - 2 : 0 : -1]])
    mid = n - 2
    i = np.arange(1, n - 1) + mid
    d = star[i - m] - 2 * star[i] + star[i + m]
    total = sum(int(v) * int(v) for v in d)
    return total / (2 * m**2 * (n - 2))


@settings(max_examples=12, deadline=None)
@given(
    seed=st.integers(0, 2**32 - 1),
    # ≥ 2 segments of 4096 terms for small m (lockstep groups, partial groups, the short
    # last segment); the factors below reach m with a lone segment and m % 4 ≠ 0
    n=st.integers(8_300, 21_000),
    amplitude=st.sampled_from([1_000, 100_000, 10_000_000]),
)
def test_mdev_equals_exact_integer_formula(seed: int, n: int, amplitude: int) -> None:
    x = _integer_angles(seed, n, amplitude).astype(np.float64)
    ms = [1, 2, 3, 5, 64, 1023, 1500, 2100, (n - 1) // 3]
    r = allan.mdev(x, 1.0, taus=[float(m) for m in ms], data_type="angle", confidence=None)
    assert isinstance(r, allan.AllanResult)
    want = [_exact_mvar(x.astype(np.int64), m) for m in ms]
    np.testing.assert_allclose(r.avar, want, rtol=RTOL, atol=0)


@settings(max_examples=8, deadline=None)
@given(
    seed=st.integers(0, 2**32 - 1),
    n=st.integers(20, 9_000),
    amplitude=st.sampled_from([1_000, 1_000_000]),
)
def test_totdev_equals_exact_integer_formula(seed: int, n: int, amplitude: int) -> None:
    x = _integer_angles(seed, n, amplitude).astype(np.float64)
    top = (n - 1) // 2
    ms = sorted({1, 2, 7, 8, 9, max(1, top // 3), top})
    r = allan.totdev(x, 1.0, taus=[float(m) for m in ms], data_type="angle", confidence=None)
    assert isinstance(r, allan.AllanResult)
    want = [_exact_totvar(x.astype(np.int64), m) for m in ms]
    # Σ d² in blocks of 4096 lane sums, compensated across blocks: as RTOL above.
    np.testing.assert_allclose(r.avar, want, rtol=RTOL, atol=0)


def test_mdev_multi_axis_is_each_column_alone() -> None:
    # The column is copied out of the row-major matrix before the passes: same bits as a
    # contiguous column, for the lockstep kernel as for the integration.
    rng = np.random.default_rng(35)
    data = rng.normal(0.0, 1.0, (40_000, 3)) + np.cumsum(rng.normal(0.0, 1e-3, (40_000, 3)), 0)
    results = allan.mdev(data, 100.0, confidence=None)
    assert isinstance(results, tuple)
    for axis, r in enumerate(results):
        single = allan.mdev(np.ascontiguousarray(data[:, axis]), 100.0, confidence=None)
        assert isinstance(single, allan.AllanResult)
        np.testing.assert_array_equal(r.avar, single.avar)
