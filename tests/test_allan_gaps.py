"""Gap-aware Allan deviations (issue 12 item 4): NaN marks a missing sample with ``gaps="omit"``.

Oracle: the direct NumPy definition in ``reference_allan_gaps`` (keep every term whose span is
gap-free). Properties: without gaps ``gaps="omit"`` is the ordinary path bit for bit; with gaps
the estimator equals the reference. Statistical check from the issue: white + random-walk rate
noise with a 10 % block removed gives the gap-free log's ADEV within its confidence interval,
where concatenating the pieces does not.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from hypothesis import event, example, given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from gyrobias import allan
from tests.reference_allan_gaps import gapped_variance

KINDS = [
    ("oavar", lambda d, fs, **kw: allan.adev(d, fs, **kw)),
    ("avar", lambda d, fs, **kw: allan.adev(d, fs, overlapping=False, **kw)),
    ("mvar", lambda d, fs, **kw: allan.mdev(d, fs, **kw)),
    ("hvar", lambda d, fs, **kw: allan.hdev(d, fs, **kw)),
]


def _with_gaps(data: np.ndarray, gaps: list[tuple[int, int]]) -> np.ndarray:
    out = data.copy()
    for a, b in gaps:
        out[a:b] = np.nan
    return out


@pytest.mark.parametrize("data_type", ["rate", "angle"])
@pytest.mark.parametrize(("kind", "function"), KINDS, ids=[k for k, _ in KINDS])
def test_matches_numpy_reference(kind, function, data_type) -> None:
    rng = np.random.default_rng(3)
    data = rng.normal(0.0, 1.0, 3000) + np.cumsum(rng.normal(0.0, 0.05, 3000))
    data = _with_gaps(data, [(0, 3), (400, 401), (1000, 1180), (2990, 3000)])
    r = function(data, 10.0, taus="all", data_type=data_type, gaps="omit", confidence=None)
    for m, var, terms in zip(r.m, r.avar, r.n_terms):
        ref, ref_terms = gapped_variance(data, 0.1, int(m), kind, data_type)
        assert terms == ref_terms, m
        # Per-segment integration vs global prefix sums: rounding only (sums of ~1e3 terms).
        np.testing.assert_allclose(var, ref, rtol=1e-9, err_msg=f"m={m}")


finite = st.floats(-1e3, 1e3, allow_nan=False, allow_infinity=False)


# One valid sample between two holes: no gap-free term at any τ, so both branches run.
@example(data=np.ones(20), holes=[(0.0, 10), (0.55, 15)], kind="oavar", data_type="rate")
@example(data=np.ones(20), holes=[(0.0, 10), (0.55, 15)], kind="hvar", data_type="angle")
@settings(derandomize=True, deadline=None, max_examples=40)
@given(
    data=arrays(np.float64, st.integers(20, 300), elements=finite),
    holes=st.lists(st.tuples(st.floats(0, 1), st.integers(1, 15)), max_size=4),
    kind=st.sampled_from([k for k, _ in KINDS]),
    data_type=st.sampled_from(["rate", "angle"]),
)
def test_property_equals_reference(data, holes, kind, data_type) -> None:
    n = len(data)
    gapped = _with_gaps(data, [(int(p * n), int(p * n) + w) for p, w in holes])
    function = dict(KINDS)[kind]
    with np.errstate(invalid="ignore", divide="ignore"), warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # nanmean of an all-NaN log
        _, first_terms = gapped_variance(gapped, 1.0, 1, kind, data_type)
    if first_terms == 0:
        # Not one gap-free term even at the shortest τ (per the reference): the analysis must
        # refuse, saying why — and only then (an error for analysable data fails below).
        event("refused: no gap-free term at m = 1")
        with pytest.raises(ValueError, match="gap|too short"):
            function(gapped, 1.0, taus="all", data_type=data_type, gaps="omit", confidence=None)
        return
    event("analysed")
    r = function(gapped, 1.0, taus="all", data_type=data_type, gaps="omit", confidence=None)
    scale = float(np.nanmax(np.abs(data))) ** 2 + 1e-300
    for m, var, terms in zip(r.m, r.avar, r.n_terms):
        ref, ref_terms = gapped_variance(gapped, 1.0, int(m), kind, data_type)
        assert terms == ref_terms
        # Relative 1e-9 with an absolute floor at the data's scale: a variance that is a
        # tiny fraction of the data² (near-cancelling differences) is only defined to rounding.
        assert abs(var - ref) <= 1e-9 * abs(ref) + 1e-11 * scale / m**2


@settings(derandomize=True, deadline=None, max_examples=30)
@given(
    data=arrays(np.float64, st.integers(12, 400), elements=finite),
    kind=st.sampled_from([k for k, _ in KINDS]),
    data_type=st.sampled_from(["rate", "angle"]),
)
def test_property_no_gaps_is_the_normal_path(data, kind, data_type) -> None:
    function = dict(KINDS)[kind]
    a = function(data, 2.0, taus="all", data_type=data_type, gaps="omit")
    b = function(data, 2.0, taus="all", data_type=data_type)
    for field in ("taus", "avar", "n_terms", "edf", "alpha", "ci_low", "ci_high"):
        np.testing.assert_array_equal(getattr(a, field), getattr(b, field))


def test_default_nan_is_an_error_naming_its_index() -> None:
    data = np.ones(100)
    data[37] = np.nan
    with pytest.raises(ValueError, match="index 37"):
        allan.adev(data, 1.0)
    data[37] = 1.0
    data[40] = np.inf
    data[20] = np.nan
    with pytest.raises(ValueError, match="index 40"):  # inf stays an error with gaps="omit"
        allan.adev(data, 1.0, gaps="omit")


def test_totdev_with_gaps_is_refused() -> None:
    data = np.random.default_rng(0).normal(size=200)
    data[50] = np.nan
    with pytest.raises(ValueError, match="total deviation"):
        allan.totdev(data, 1.0, gaps="omit")
    with pytest.raises(ValueError, match="gaps"):
        allan.adev(data, 1.0, gaps="skip")


def test_tau_is_limited_by_the_longest_gap_free_stretch() -> None:
    data = np.random.default_rng(1).normal(size=1000)
    data[300] = np.nan  # longest stretch: rows 301..999 (699 samples)
    r = allan.adev(data, 1.0, taus="all", gaps="omit", confidence=None)
    assert r.m.max() == (699 + 1 - 1) // 2  # 700 angle samples: m ≤ 349
    with pytest.raises(ValueError, match="support at most"):
        allan.adev(data, 1.0, taus=[400.0], gaps="omit")
    everything = np.full(10, np.nan)
    with pytest.raises(ValueError, match="NaN"):
        allan.adev(everything, 1.0, gaps="omit")


def test_confidence_intervals_pool_the_segments() -> None:
    rng = np.random.default_rng(7)
    rate = rng.normal(0.0, 1.0, 20_000)
    full = allan.adev(rate, 1.0)
    gapped = allan.adev(_with_gaps(rate, [(10_000, 10_001)]), 1.0, gaps="omit")
    assert isinstance(full, allan.AllanResult) and isinstance(gapped, allan.AllanResult)
    common = np.isin(full.m, gapped.m)
    # One missing sample in the middle: two halves. Fewer terms, a slightly smaller EDF (two
    # independent halves lose the overlap across the cut), the same noise type.
    assert np.all(gapped.n_terms < full.n_terms[common])
    # Where both identify the same noise (the long-τ identification on ~30 points may differ
    # between a half and the whole record):
    same = gapped.alpha == full.alpha[common]
    assert same[:8].all()
    np.testing.assert_array_equal(gapped.alpha[:8], 0)
    assert np.all(gapped.edf[same] <= full.edf[common][same] * 1.0001)
    assert np.all(gapped.edf[same] > 0.5 * full.edf[common][same])


def test_gap_aware_matches_gap_free_where_concatenation_does_not() -> None:
    # Issue 12's check. White + rate random walk; a 10 % block is removed where the bias moved
    # (the block with the largest walk, 2σ of its expected size here — a dropout while the
    # bias drifts). Omitting the terms that touch the gap estimates the gap-free log's ADEV:
    # inside its 68 % interval at every τ ≤ T/100 (beyond, a few independent long-τ differences
    # dominate and the gapped estimate, which lost 10 % of the record, has its own sampling
    # error). Joining the pieces puts a rate step (the walk during the missing block) into the
    # data, which moves the ADEV outside the interval over most of the random-walk region.
    n, fs, width = 200_000, 100.0, 20_000
    rng = np.random.default_rng(11)
    walk = np.cumsum(rng.normal(0.0, 0.05, n))
    rate = rng.normal(0.0, 1.0, n) + walk
    starts = np.arange(n // 10, 8 * n // 10, 1000)
    a = int(starts[np.argmax(np.abs(walk[starts + width] - walk[starts]))])
    b = a + width
    full = allan.adev(rate, fs)
    gapped = allan.adev(_with_gaps(rate, [(a, b)]), fs, gaps="omit")
    joined = allan.adev(np.concatenate((rate[:a], rate[b:])), fs)
    for r in (full, gapped, joined):
        assert isinstance(r, allan.AllanResult)
    assert full.ci_low is not None and full.ci_high is not None
    k = int(np.sum(gapped.m <= n // 100))
    inside = (gapped.adev[:k] >= full.ci_low[:k]) & (gapped.adev[:k] <= full.ci_high[:k])
    assert inside.all(), gapped.taus[:k][~inside]
    rrw = full.m[:k] >= 100  # σ²_white = 1/m meets σ²_rrw = 0.05² m/3 at m ≈ 35
    outside = (joined.adev[:k] < full.ci_low[:k]) | (joined.adev[:k] > full.ci_high[:k])
    assert outside[rrw].mean() > 0.75, outside
