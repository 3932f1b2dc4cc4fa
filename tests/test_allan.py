"""Allan-family deviations: NumPy references, published values, AllanTools, properties, bad input."""

from __future__ import annotations

import allantools
import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

import gyrobias
from gyrobias import allan
from tests import reference_allan as ref

RATE8 = np.array([1.0, 3.0, 2.0, 5.0, 4.0, 6.0, 8.0, 7.0])

# --------------------------------------------------------------------------- check values


def test_spec_check_values_overlapping_and_non_overlapping() -> None:
    # SPEC §2 check: rate [1,3,2,5,4,6,8,7], t0 = 0.5, x_0 = 0 prepended.
    r = allan.avar(RATE8, fs=2.0, taus="all", confidence=None)
    np.testing.assert_allclose(r.taus, [0.5, 1.0, 1.5, 2.0])
    np.testing.assert_allclose(
        r.avar, [1.714285714286, 2.1, 4.537037037037, 6.125], rtol=0, atol=5e-13
    )
    np.testing.assert_array_equal(r.n_terms, [7, 5, 3, 1])
    nov = allan.avar(RATE8, fs=2.0, taus="all", overlapping=False, confidence=None)
    np.testing.assert_allclose(
        nov.avar, [1.714285714286, 1.791666666667, 4.5, 6.125], rtol=0, atol=5e-13
    )


# NIST SP 1065 Tables 30 and 31 (Stable32 values, 7 significant figures).
NBS9 = np.array([892, 809, 823, 798, 671, 644, 883, 903, 677], dtype=float)
TABLE30 = {  # tau = 1, 2
    "adev": [91.22945, 115.8082],
    "oadev": [91.22945, 85.95287],
    "mdev": [91.22945, 74.78849],
    "hdev": [70.80607, 85.61487],
    "totdev": [91.22945, 93.90379],
}
TABLE31 = {  # tau = 1, 10, 100
    "adev": [2.922319e-01, 9.965736e-02, 3.897804e-02],
    "oadev": [2.922319e-01, 9.159953e-02, 3.241343e-02],
    "mdev": [2.922319e-01, 6.172376e-02, 2.170921e-02],
    "hdev": [2.943883e-01, 9.581083e-02, 3.237638e-02],
    "totdev": [2.922319e-01, 9.134743e-02, 3.406530e-02],
}


def _dev(name: str, data: np.ndarray, taus: list[float]) -> np.ndarray:
    if name == "adev":
        r = allan.adev(data, 1.0, taus=taus, overlapping=False, confidence=None)
    elif name == "oadev":
        r = allan.adev(data, 1.0, taus=taus, confidence=None)
    else:
        r = getattr(allan, name)(data, 1.0, taus=taus, confidence=None)
    assert isinstance(r, allan.AllanResult)
    return r.adev


@pytest.mark.parametrize("name", sorted(TABLE30))
def test_nbs9_published_values(name: str) -> None:
    # Published with 7 significant figures: agreement to half a unit in the last place.
    np.testing.assert_allclose(_dev(name, NBS9, [1.0, 2.0]), TABLE30[name], rtol=6e-7)


@pytest.mark.parametrize("name", sorted(TABLE31))
def test_nbs1000_published_values(name: str) -> None:
    np.testing.assert_allclose(
        _dev(name, ref.nbs_1000(), [1.0, 10.0, 100.0]), TABLE31[name], rtol=6e-7
    )


# --------------------------------------------------------------------------- AllanTools


@pytest.mark.parametrize("taus", ["octave", "all", "decade"])
def test_matches_allantools_oadev_to_1e12(taus: str) -> None:
    rng = np.random.default_rng(5)
    rate = 0.3 + rng.normal(0.0, 0.01, 20_000) + np.cumsum(rng.normal(0.0, 1e-4, 20_000))
    fs = 100.0
    ours = allan.adev(rate, fs, taus=taus, confidence=None)
    at = allantools.oadev(rate, rate=fs, data_type="freq", taus=taus)
    common = np.isin(ours.m, np.rint(at[0] * fs).astype(np.int64))
    assert common.sum() == len(at[0]) > 5
    # Both integrate the mean-removed rate; the difference is summation order only.
    np.testing.assert_allclose(ours.adev[common], at[1], rtol=1e-12)
    np.testing.assert_array_equal(ours.n_terms[common], at[3])


@pytest.mark.parametrize(
    ("ours", "theirs"),
    [("mdev", "mdev"), ("hdev", "ohdev"), ("totdev", "totdev")],
)
def test_matches_allantools_other_deviations(ours: str, theirs: str) -> None:
    rng = np.random.default_rng(11)
    rate = rng.normal(0.0, 1.0, 5000) + np.cumsum(rng.normal(0.0, 0.01, 5000))
    r = getattr(allan, ours)(rate, 10.0, taus="octave", confidence=None)
    at = getattr(allantools, theirs)(rate, rate=10.0, data_type="freq", taus=r.taus)
    common = np.isin(r.m, np.rint(at[0] * 10.0).astype(np.int64))
    assert common.sum() == len(at[0]) > 5
    # MDEV: AllanTools accumulates the inner sums by cumsum over the whole record, we
    # re-seed them every 4096 steps; both are accurate to ~1e-13 relative here.
    np.testing.assert_allclose(r.adev[common], at[1], rtol=1e-10)


# --------------------------------------------------------------------------- NumPy reference

finite_rates = arrays(
    np.float64,
    st.integers(12, 400),
    elements=st.floats(-1e3, 1e3, allow_nan=False, allow_infinity=False),
)


@given(rate=finite_rates, fs=st.floats(0.1, 1e4))
def test_all_estimators_match_numpy_reference(rate: np.ndarray, fs: float) -> None:
    t0 = 1.0 / fs
    x = ref.angle_from_rate(rate, t0)
    scale = float(np.max(np.abs(rate))) + 1e-300
    cases = [
        (allan.avar(rate, fs, taus="all", confidence=None), ref.oavar),
        (allan.mdev(rate, fs, taus="all", confidence=None), ref.mvar),
        (allan.hdev(rate, fs, taus="all", confidence=None), ref.hvar),
        (allan.totdev(rate, fs, taus="all", confidence=None), ref.totvar),
    ]
    for result, reference in cases:
        assert isinstance(result, allan.AllanResult)
        for m, v, n in zip(result.m, result.avar, result.n_terms):
            want, want_n = reference(x, t0, int(m))
            assert n == want_n
            # Absolute floor: removing the mean and differencing the integrated series leave
            # rounding of order eps·N·max|Ω| ≈ 1e-13·max|Ω| in σ (N ≤ 400), so ~1e-11·max|Ω|²
            # bounds the σ² error even for (nearly) constant data where σ² → 0.
            # 1e-300: variances of ~1e-150 data are subnormal and carry no relative precision.
            assert v == pytest.approx(want, rel=1e-9, abs=1e-11 * scale**2 + 1e-300)
    nov = allan.avar(rate, fs, taus="all", overlapping=False, confidence=None)
    for m, v, n in zip(nov.m, nov.avar, nov.n_terms):
        want, want_n = ref.avar_binned(rate, int(m))
        assert n == want_n
        assert v == pytest.approx(want, rel=1e-9, abs=1e-11 * scale**2 + 1e-300)


@given(
    rate=finite_rates,
    fs=st.floats(0.5, 1e3),
    k=st.floats(-1e3, 1e3).filter(lambda v: abs(v) > 1e-3),
)
def test_scaling_is_linear(rate: np.ndarray, fs: float, k: float) -> None:
    a = allan.adev(rate, fs, taus="all", confidence=None)
    b = allan.adev(k * rate, fs, taus="all", confidence=None)
    assert isinstance(a, allan.AllanResult) and isinstance(b, allan.AllanResult)
    # Rounding floor ~eps·N·max|Ω| in σ (see test_all_estimators_match_numpy_reference).
    floor = 1e-12 * float(np.max(np.abs(rate)))
    np.testing.assert_allclose(b.adev, abs(k) * a.adev, rtol=1e-9, atol=abs(k) * floor + 1e-300)


@given(rate=finite_rates, fs=st.floats(0.5, 1e3))
def test_angle_input_equals_rate_input(rate: np.ndarray, fs: float) -> None:
    x = ref.angle_from_rate(rate, 1.0 / fs)
    a = allan.adev(rate, fs, taus="all", confidence=None)
    b = allan.adev(x, fs, taus="all", data_type="angle", confidence=None)
    assert isinstance(a, allan.AllanResult) and isinstance(b, allan.AllanResult)
    np.testing.assert_array_equal(a.taus, b.taus)
    floor = 1e-12 * float(np.max(np.abs(rate))) + 1e-300
    np.testing.assert_allclose(a.adev, b.adev, rtol=1e-9, atol=floor)


@given(
    data=arrays(
        np.float64, st.tuples(st.integers(10, 200), st.integers(2, 4)), elements=st.floats(-10, 10)
    )
)
def test_multi_axis_equals_per_axis(data: np.ndarray) -> None:
    results = allan.adev(data, 50.0, taus="all", confidence=None)
    assert isinstance(results, tuple) and len(results) == data.shape[1]
    for axis, r in enumerate(results):
        single = allan.adev(data[:, axis], 50.0, taus="all", confidence=None)
        assert isinstance(single, allan.AllanResult)
        # Same kernel, same blocking: bit-identical.
        np.testing.assert_array_equal(r.avar, single.avar)


def test_large_bias_does_not_lose_precision() -> None:
    # SPEC §2 property: +1e6 on every rate sample of a 1e6-sample log changes no σ by > 1e-9.
    rng = np.random.default_rng(3)
    rate = rng.normal(0.0, 1.0, 1_000_000)
    a = allan.adev(rate, 100.0, confidence=None)
    b = allan.adev(rate + 1e6, 100.0, confidence=None)
    assert isinstance(a, allan.AllanResult) and isinstance(b, allan.AllanResult)
    np.testing.assert_allclose(b.adev, a.adev, rtol=1e-9)


def test_white_noise_level() -> None:
    # White rate noise σ_w at t0: σ(τ) = σ_w·√(t0/τ) (ARW region, IEEE 952).
    rng = np.random.default_rng(0)
    r = allan.adev(rng.normal(0.0, 0.1, 400_000), 100.0, confidence=None)
    assert isinstance(r, allan.AllanResult)
    expected = 0.1 * np.sqrt(0.01 / r.taus)
    n_eff = r.n_terms / r.m  # roughly independent terms
    # Relative s.d. of an Allan deviation estimate ≈ 1/√(2·n_eff); allow 4 s.d.
    mask = n_eff > 1000
    assert np.all(np.abs(r.adev[mask] / expected[mask] - 1) < 4 / np.sqrt(2 * n_eff[mask]))


# --------------------------------------------------------------------------- tau sets


def test_tau_sets() -> None:
    x = np.random.default_rng(1).normal(size=1000)
    octave = allan.adev(x, 10.0, confidence=None)
    assert isinstance(octave, allan.AllanResult)
    np.testing.assert_array_equal(octave.m, [1, 2, 4, 8, 16, 32, 64, 128, 256])
    decade = allan.adev(x, 10.0, taus="decade", confidence=None)
    assert isinstance(decade, allan.AllanResult)
    np.testing.assert_array_equal(decade.m, [1, 2, 4, 10, 20, 40, 100, 200, 400])
    log = allan.adev(x, 10.0, taus="log", per_decade=20, confidence=None)
    assert isinstance(log, allan.AllanResult)
    assert log.m[0] == 1 and np.all(np.diff(log.m) > 0) and log.m[-1] <= 500
    every = allan.adev(x, 10.0, taus="all", confidence=None)
    assert isinstance(every, allan.AllanResult)
    np.testing.assert_array_equal(every.m, np.arange(1, 501))
    explicit = allan.adev(x, 10.0, taus=[0.3, 0.1, 5.0], confidence=None)
    assert isinstance(explicit, allan.AllanResult)
    np.testing.assert_allclose(explicit.taus, [0.3, 0.1, 5.0])


def test_result_object_units_and_dict() -> None:
    r = allan.adev(np.arange(100.0) % 7, 20.0, units="deg/s", confidence=None, axis_names=None)
    assert isinstance(r, allan.AllanResult)
    assert r.unit == "deg/s" and r.fs == 20.0 and r.data_type == "rate"
    d = r.to_dict()
    assert d["unit"] == "deg/s" and d["tau_unit"] == "s" and len(d["taus"]) == len(r.taus)
    assert "ADEV" in str(r)
    angle = allan.adev(
        np.cumsum(np.arange(100.0) % 7), 20.0, data_type="angle", units="deg", confidence=None
    )
    assert isinstance(angle, allan.AllanResult) and angle.unit == "deg/s"


def test_progress_callback_reports_and_matches() -> None:
    x = np.random.default_rng(2).normal(size=(5000, 2))
    seen: list[float] = []
    a = allan.adev(x, 100.0, taus="all", progress=seen.append, confidence=None)
    b = allan.adev(x, 100.0, taus="all", confidence=None)
    assert seen[0] == 0.0 and seen[-1] == 1.0 and seen == sorted(seen)
    for ra, rb in zip(a, b):
        np.testing.assert_array_equal(ra.avar, rb.avar)


# --------------------------------------------------------------------------- input handling


def test_input_conversions_and_no_mutation() -> None:
    base = np.random.default_rng(4).normal(size=2000)
    want = allan.adev(base, 10.0, confidence=None)
    assert isinstance(want, allan.AllanResult)
    f32 = base.astype(np.float32)
    r32 = allan.adev(f32, 10.0, confidence=None)
    assert isinstance(r32, allan.AllanResult)
    np.testing.assert_allclose(
        r32.adev, allan.adev(f32.astype(np.float64), 10.0, confidence=None).adev
    )  # type: ignore[union-attr]
    ints = (base * 100).astype(np.int32)
    ri = allan.adev(ints, 10.0, confidence=None)
    assert isinstance(ri, allan.AllanResult)
    np.testing.assert_allclose(ri.adev, allan.adev(ints.astype(float), 10.0, confidence=None).adev)  # type: ignore[union-attr]
    wide = np.repeat(base, 2)
    strided = wide[::2]
    assert not strided.flags.c_contiguous
    rs = allan.adev(strided, 10.0, confidence=None)
    assert isinstance(rs, allan.AllanResult)
    np.testing.assert_array_equal(rs.avar, want.avar)
    fortran = np.asfortranarray(np.stack([base, base * 2], axis=1))
    rf = allan.adev(fortran, 10.0, confidence=None)
    assert isinstance(rf, tuple)
    np.testing.assert_allclose(rf[1].adev, 2 * want.adev, rtol=1e-12)
    lst = allan.adev(base.tolist(), 10.0, confidence=None)
    assert isinstance(lst, allan.AllanResult)
    np.testing.assert_array_equal(lst.avar, want.avar)
    copy = base.copy()
    allan.adev(base, 10.0, confidence=None)
    np.testing.assert_array_equal(base, copy)


@pytest.mark.parametrize(
    ("kwargs", "exc", "match"),
    [
        ({"data": [1.0, np.nan, 2.0, 3.0]}, ValueError, r"data.*non-finite.*index 1"),
        ({"data": [1.0, 2.0, np.inf, 3.0]}, ValueError, r"data.*index 2"),
        ({"data": []}, ValueError, "data is empty"),
        ({"data": [1.0]}, ValueError, "data is too short"),
        ({"data": 3.0}, ValueError, "data must be a 1-D or 2-D"),
        ({"data": np.zeros((3, 3, 3))}, ValueError, "data must be a 1-D or 2-D"),
        ({"data": ["a", "b", "c"]}, TypeError, "data must be a real numeric"),
        ({"data": np.ones(10, dtype=complex)}, TypeError, "data must be a real numeric"),
        ({"fs": 0.0}, ValueError, "fs must be finite and > 0"),
        ({"fs": -5.0}, ValueError, "fs must be finite and > 0"),
        ({"fs": np.nan}, ValueError, "fs must be finite and > 0"),
        ({"fs": "100"}, TypeError, "fs must be a real number"),
        ({"taus": [0.015]}, ValueError, "taus.*not a positive multiple"),
        ({"taus": [100.0]}, ValueError, "taus.*needs m = 10000"),
        ({"taus": [-0.01]}, ValueError, "taus"),
        ({"taus": [0.01, 0.01]}, ValueError, "taus.*duplicate"),
        ({"taus": "weekly"}, ValueError, "taus must be 'octave', 'decade', 'log', 'all'"),
        ({"data_type": "phase"}, ValueError, "data_type"),
        ({"data_type": 5}, TypeError, "data_type"),
        ({"confidence": 1.5}, ValueError, "confidence must lie strictly between 0 and 1"),
        ({"confidence": "0.9"}, TypeError, "confidence"),
        ({"per_decade": 0, "taus": "log"}, ValueError, "per_decade"),
        ({"per_decade": -1}, ValueError, "per_decade"),
        ({"units": "furlong"}, ValueError, "units"),
    ],
)
def test_bad_input(kwargs: dict[str, object], exc: type[Exception], match: str) -> None:
    args: dict[str, object] = {"data": np.arange(100.0) % 3, "fs": 100.0}
    args.update(kwargs)
    data = args.pop("data")
    fs = args.pop("fs")
    with pytest.raises(exc, match=match):
        allan.adev(data, fs, **args)  # type: ignore[arg-type]


def test_nan_in_multi_axis_names_row_and_column() -> None:
    data = np.zeros((50, 3))
    data[17, 2] = np.nan
    with pytest.raises(ValueError, match="row 17, column 2"):
        allan.adev(data, 10.0, confidence=None)


def test_top_level_exports() -> None:
    assert gyrobias.adev is allan.adev and gyrobias.avar is allan.avar
    assert issubclass(gyrobias.GyroLinAlgError, ValueError)


@pytest.mark.parametrize(
    ("kind", "options"),
    [
        ("adev", {"taus": "octave", "confidence": 0.683}),
        ("mdev", {"confidence": 0.683}),
        ("hdev", {"overlapping": False}),
        ("totdev", {}),
        ("tdev", {}),
    ],
)
def test_units_one_per_axis_equal_a_call_per_unit(kind: str, options: dict[str, object]) -> None:
    # a log's gyro and accelerometer axes in one call (no column copy): every axis is computed
    # alone, so each result equals the call per unit group bit for bit, with its own unit
    rng = np.random.default_rng(7)
    data = rng.normal(0.0, 0.1, (20_000, 4)) + np.cumsum(rng.normal(0.0, 1e-4, (20_000, 4)), 0)
    units = ["deg/s", "deg/s", "m/s^2", "m/s^2"]
    fn = getattr(allan, kind)
    both = fn(data, 100.0, units=units, axis_names="abcd", **options)
    apart = fn(data[:, :2], 100.0, units="deg/s", axis_names="ab", **options) + fn(
        data[:, 2:], 100.0, units="m/s^2", axis_names="cd", **options
    )
    assert len(both) == 4
    for one, ref_result in zip(both, apart, strict=True):
        assert one.unit == ref_result.unit and one.axis == ref_result.axis
        for name in ("taus", "avar", "deviation", "n_terms", "edf", "ci_low", "ci_high"):
            a, b = getattr(one, name), getattr(ref_result, name)
            assert (a is None and b is None) or np.array_equal(a, b), name
    assert both[0].unit != both[2].unit


def test_units_one_per_axis_refused() -> None:
    data = np.random.default_rng(0).normal(size=(1_000, 3))
    with pytest.raises(ValueError, match="units: 2 units for 3 axes"):
        allan.adev(data, 100.0, units=["deg/s", "deg/s"])
    with pytest.raises(ValueError, match="units: unknown unit 'furlong'"):
        allan.adev(data, 100.0, units=["deg/s", "furlong", "deg/s"])
    with pytest.raises(TypeError, match="units must be a unit string"):
        allan.adev(data, 100.0, units=np.array(["deg/s"] * 3))
    with pytest.raises(TypeError, match="units must be a unit string"):
        allan.adev(data, 100.0, units=3)  # type: ignore[arg-type]
