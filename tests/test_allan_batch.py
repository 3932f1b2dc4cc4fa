"""Batch Allan analysis (issue 14 item 1): one core call for a fleet, bit-identical to per-unit calls."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from gyrobias import allan

FIELDS = (
    "taus",
    "avar",
    "n_terms",
    "edf",
    "alpha",
    "ci_low",
    "ci_high",
    "noise_type",
    "axis",
    "unit",
)


def _same(a: allan.AllanResult, b: allan.AllanResult) -> None:
    for field in FIELDS:
        x, y = getattr(a, field), getattr(b, field)
        if isinstance(x, np.ndarray):
            np.testing.assert_array_equal(x, y, err_msg=field)
        else:
            assert x == y, field


@pytest.mark.parametrize(
    "kwargs",
    [
        {},
        {"confidence": None},
        {"overlapping": False},
        {"data_type": "angle", "taus": "decade"},
        {"taus": "log", "per_decade": 7, "confidence": 0.95},
    ],
)
def test_batch_equals_per_unit_calls_bit_for_bit(kwargs) -> None:
    rng = np.random.default_rng(2)
    # 5 units × 70 001 samples × 3 axes: crosses the kernels' block boundaries.
    fleet = rng.normal(0.3, 1.0, (5, 70_001, 3)) + np.cumsum(
        rng.normal(0.0, 0.01, (5, 70_001, 3)), axis=1
    )
    res = allan.adev_batch(fleet, 100.0, units="deg/s", axis_names=("x", "y", "z"), **kwargs)
    assert len(res) == 5 and all(len(u) == 3 for u in res)
    for u in range(5):
        single = allan.adev(fleet[u], 100.0, units="deg/s", axis_names=("x", "y", "z"), **kwargs)
        assert isinstance(single, tuple)
        for a in range(3):
            _same(res[u][a], single[a])


def test_two_dimensional_batch_is_one_axis_per_unit() -> None:
    fleet = np.random.default_rng(4).normal(size=(3, 5000))
    res = allan.adev_batch(fleet, 10.0)
    assert [len(u) for u in res] == [1, 1, 1]
    for u in range(3):
        single = allan.adev(fleet[u], 10.0)
        assert isinstance(single, allan.AllanResult)
        _same(res[u][0], single)


@settings(derandomize=True, deadline=None, max_examples=25)
@given(
    fleet=arrays(
        np.float64,
        st.tuples(st.integers(1, 4), st.integers(6, 200), st.integers(1, 3)),
        elements=st.floats(-1e3, 1e3, allow_nan=False, allow_infinity=False),
    ),
    overlapping=st.booleans(),
)
def test_property_batch_equals_per_unit(fleet, overlapping) -> None:
    res = allan.adev_batch(fleet, 3.0, taus="all", overlapping=overlapping)
    for u in range(fleet.shape[0]):
        single = allan.adev(fleet[u], 3.0, taus="all", overlapping=overlapping)
        assert isinstance(single, tuple)
        for a in range(fleet.shape[2]):
            _same(res[u][a], single[a])


def test_progress_covers_the_whole_batch() -> None:
    fleet = np.random.default_rng(5).normal(size=(6, 100_000))
    seen: list[float] = []
    res = allan.adev_batch(fleet, 100.0, progress=seen.append)
    assert seen[0] == 0.0 and seen[-1] == 1.0 and seen == sorted(seen) and len(seen) > 10
    plain = allan.adev_batch(fleet, 100.0)
    for u in range(6):
        _same(res[u][0], plain[u][0])


def test_bad_batches() -> None:
    fleet = np.random.default_rng(6).normal(size=(4, 100, 2))
    fleet[2, 7, 1] = np.nan
    with pytest.raises(ValueError, match="unit 2, row 7, column 1"):
        allan.adev_batch(fleet, 1.0)
    with pytest.raises(ValueError, match="2-D or 3-D"):
        allan.adev_batch(np.ones(100), 1.0)
    with pytest.raises(ValueError, match="axis_names"):
        allan.adev_batch(np.ones((2, 100, 3)), 1.0, axis_names=("x", "y"))
    with pytest.raises(ValueError, match="too short"):
        allan.adev_batch(np.ones((2, 1)), 1.0)
    # gaps="omit" applies per unit
    fleet[2, 7, 1] = np.nan
    res = allan.adev_batch(fleet, 1.0, gaps="omit", taus=[1.0])
    assert res[2][1].n_terms[0] == 99 - 2 and res[1][1].n_terms[0] == 99
