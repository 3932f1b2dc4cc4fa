"""Tests of gyrobias.noise: simulation, identification, units and exports."""

from __future__ import annotations

import argparse
import json
import math

import numpy as np
import pytest
import yaml
from hypothesis import example, given
from hypothesis import strategies as st

import gyrobias
from gyrobias import noise
from gyrobias.allan import AllanResult, adev
from gyrobias.cli import noise as cli_noise
from gyrobias.units import base_unit, conversion_factor, parse_unit, sensor_kind
from tests.reference_noise import FLICKER, fixed_slope_value, joint_irls, local_slopes, model_avar

FS = 100.0
# The SPEC §3 example: 8 h at 100 Hz, N = 0.2 deg/√h, B = 3 deg/h, K = 10 deg/h^1.5.
TRUE = {"arw": 0.2 / 60.0, "bias_instability": 3.0 / 3600.0, "rrw": 10.0 / 216000.0}
N_8H = 8 * 3600 * 100


def _curve(rate: np.ndarray, **kw: object) -> AllanResult:
    r = adev(rate, FS, confidence=None, units="deg/s", **kw)  # type: ignore[arg-type]
    assert isinstance(r, AllanResult)
    return r


@pytest.fixture(scope="module")
def eight_hour_all() -> dict[str, list[tuple[noise.NoiseCoefficients, noise.NoiseCoefficients]]]:
    """Joint and read-off fits of 3 seeds × 3 axes of the SPEC's 8 h log (seeds 0, 1, 2), with
    the SP1065 approximate EDF (``confidence=None``) and with the Allan result's own EDF."""
    out: dict[str, list] = {"approximate": [], "identified": []}
    for seed in range(3):
        rate = noise.simulate(N_8H, FS, axes=3, seed=seed, **TRUE)
        for key, conf in (("approximate", None), ("identified", 0.683)):
            results = adev(rate, FS, confidence=conf, units="deg/s", axis_names=["x", "y", "z"])
            for r in results:  # type: ignore[union-attr]
                out[key].append((noise.fit(r), noise.fit(r, method="ieee")))
    return out


@pytest.fixture(scope="module")
def eight_hour_fits(
    eight_hour_all: dict,
) -> list[tuple[noise.NoiseCoefficients, noise.NoiseCoefficients]]:
    return eight_hour_all["approximate"]


# --- simulate --------------------------------------------------------------------------------------


def test_simulate_shapes_and_reproducibility() -> None:
    one = noise.simulate(1000, FS, arw=0.01, seed=3)
    assert one.shape == (1000,) and one.dtype == np.float64
    three = noise.simulate(1000, FS, arw=0.01, axes=3, seed=3)
    assert three.shape == (1000, 3)
    np.testing.assert_array_equal(three[:, 0], one)  # axis a does not depend on `axes`
    np.testing.assert_array_equal(noise.simulate(1000, FS, arw=0.01, axes=3, seed=3), three)
    assert not np.array_equal(three[:, 0], three[:, 1])
    assert not np.array_equal(noise.simulate(1000, FS, arw=0.01, seed=4), one)
    # Each component has its own stream: adding flicker leaves the white part unchanged.
    both = noise.simulate(1000, FS, arw=0.01, bias_instability=0.001, seed=3)
    flick = noise.simulate(1000, FS, bias_instability=0.001, seed=3)
    np.testing.assert_allclose(both - flick, one, rtol=0, atol=1e-15)
    assert noise.simulate(10, FS, seed=None).shape == (10,)


def test_simulate_white_ramp_bias_and_rrw_statistics() -> None:
    n = 200_000
    arw = 0.3
    white = noise.simulate(n, FS, arw=arw, seed=1)
    # Per-sample s.d. N/√t0 = N·√fs; s.e. of a sample s.d. is 1/√(2n) = 0.16 %: 1 % margin.
    assert np.std(white) == pytest.approx(arw * math.sqrt(FS), rel=0.01)
    ramp = noise.simulate(5, FS, rate_ramp=2.0, bias=1.5, seed=1)
    np.testing.assert_allclose(ramp, 1.5 + 2.0 * np.arange(5) / FS, rtol=0, atol=1e-15)
    # RRW: increments are K√t0·ξ exactly.
    walk = noise.simulate(n, FS, rrw=0.5, seed=2)
    assert np.std(np.diff(walk)) == pytest.approx(0.5 / math.sqrt(FS), rel=0.01)
    # AR(1): lag-1 autocorrelation c and stationary s.d. σ/√(1−c²); s.e. ≈ 1/√n-ish, 3 % margin.
    ar = noise.simulate(n, FS, ar1=(0.9, 0.1), seed=5)
    rho = np.corrcoef(ar[:-1], ar[1:])[0, 1]
    assert rho == pytest.approx(0.9, abs=0.01)
    assert np.std(ar) == pytest.approx(0.1 / math.sqrt(1 - 0.81), rel=0.05)


def test_simulate_each_term_has_its_allan_variance() -> None:
    n = 400_000
    q = noise.simulate(n, FS, quantization=1e-3, seed=7)
    r = _curve(q)
    # White angle: σ²(τ) = 3Q²/τ²; EDF ≥ 1e4 at the τ used → ≤ 1.4 % s.d. of σ²; 5 % margin.
    sel = r.taus <= 1.0
    np.testing.assert_allclose(r.avar[sel], 3e-6 / r.taus[sel] ** 2, rtol=0.05)
    b = noise.simulate(n, FS, bias_instability=1e-3, seed=8)
    r = _curve(b)
    # Flicker plateau (0.664 B)² for 0.1 s ≤ τ ≤ 40 s; flicker EDF ≥ 5n/(4m) ≥ 1200 → ≤ 4 %
    # s.d. of σ², 12 % margin (3σ).
    sel = (r.taus >= 0.1) & (r.taus <= 40)
    np.testing.assert_allclose(r.avar[sel], (FLICKER * 1e-3) ** 2, rtol=0.12)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"n": 0}, "n"),
        ({"fs": 0.0}, "fs"),
        ({"arw": -1.0}, "arw"),
        ({"bias_instability": float("nan")}, "bias_instability"),
        ({"rrw": float("inf")}, "rrw"),
        ({"axes": 0}, "axes"),
        ({"ar1": (1.0, 0.1)}, "ar1"),
        ({"ar1": (0.5, -0.1)}, "ar1"),
        ({"seed": -1}, "seed"),
    ],
)
def test_simulate_rejects_bad_input(kwargs: dict[str, object], match: str) -> None:
    args: dict[str, object] = {"n": 10, "fs": FS}
    args.update(kwargs)
    with pytest.raises(ValueError, match=match):
        noise.simulate(**args)  # type: ignore[arg-type]


def test_simulate_rejects_bad_types() -> None:
    with pytest.raises(TypeError, match="arw"):
        noise.simulate(10, FS, arw="1")  # type: ignore[arg-type]
    with pytest.raises(TypeError, match="seed"):
        noise.simulate(10, FS, seed=1.5)  # type: ignore[arg-type]
    with pytest.raises(TypeError, match="ar1"):
        noise.simulate(10, FS, ar1=0.5)  # type: ignore[arg-type]


# --- recovery ----------------------------------------------------------------------------------------


@pytest.mark.parametrize("edf", ["approximate", "identified"])
def test_recovery_on_eight_hour_logs(eight_hour_all: dict, edf: str) -> None:
    """The issue's targets: N within 2 %, B within 10 %, K within its uncertainty.

    K is a standard (1σ) uncertainty, so a single run lies within ±1u only ~68 % of the time:
    each run must lie within ±2.5u (99 %) and the RMS of the z-scores over the 9 runs must be
    ≤ 1.5 (for calibrated uncertainties it is ≈ 1; the 9-run RMS has ≈ 24 % s.d.). A Monte Carlo
    of 42 runs gave z RMS 1.02 (N), 1.11 (B), 0.93 (K) with the approximate EDF, and of 24 runs
    0.91, 1.14, 1.06 with the identified (Greenhall) EDF.
    """
    z: dict[str, list[float]] = {"N": [], "B": [], "K": []}
    expected_source = (
        "noise identification" if edf == "identified" else "SP1065 simple approximation"
    )
    for joint, _ in eight_hour_all[edf]:
        assert joint.edf_source == expected_source
        assert joint.N.value == pytest.approx(TRUE["arw"], rel=0.02)
        assert joint.B.value == pytest.approx(TRUE["bias_instability"], rel=0.10)
        for sym, key in (("N", "arw"), ("B", "bias_instability"), ("K", "rrw")):
            t = joint[sym]
            assert t.value is not None and t.uncertainty is not None and t.uncertainty > 0
            z[sym].append((t.value - TRUE[key]) / t.uncertainty)
        assert abs(z["K"][-1]) <= 2.5
        assert joint.Q.missing is not None or joint.Q.value < 1e-4 * TRUE["arw"] * 60
    for sym in z:
        assert math.sqrt(np.mean(np.square(z[sym]))) <= 1.5, (sym, z[sym])


def test_read_off_is_biased_high_on_b_as_spec_says(eight_hour_fits: list) -> None:
    """SPEC §3: the read-off gives B ≈ 3.6 deg/h (biased high), the joint fit ≈ 3."""
    ieee_b = [i.to("ieee").B.value for _, i in eight_hour_fits]
    joint_b = [j.to("ieee").B.value for j, _ in eight_hour_fits]
    assert 3.3 < np.mean(ieee_b) < 4.2
    assert abs(np.mean(joint_b) - 3.0) < 0.2
    for _, i in eight_hour_fits:
        assert i.N.value == pytest.approx(TRUE["arw"], rel=0.02)
        assert i.N.tau_range[0] == pytest.approx(0.01)


@given(
    arw=st.floats(1e-3, 10.0),
    seed=st.integers(0, 2**32),
)
@example(arw=1.0, seed=965260)  # issue 19 explore run: N 3.0 % low, 2.9 σ (Q free beside it)
def test_white_noise_recovery_property(arw: float, seed: int) -> None:
    rate = noise.simulate(20_000, FS, arw=arw, seed=seed)
    c = noise.fit(_curve(rate))
    # m = 1 alone would give N to 0.45 %, but the joint fit estimates Q beside N and the two
    # are strongly correlated at short τ: N's reported s.d. is ~1 %. Judge the error in those
    # units: 5 σ (a false failure every ~2e6 examples) and a reported s.d. below 3 %.
    assert c.N.value is not None and c.N.uncertainty is not None
    assert abs(c.N.value - arw) < 5.0 * c.N.uncertainty
    assert c.N.uncertainty < 0.03 * arw


def test_joint_fit_matches_scipy_nnls_reference() -> None:
    rate = noise.simulate(300_000, FS, seed=11, **TRUE)
    r = _curve(rate)
    edf = np.maximum(r.n_terms / (2.0 * r.m), 1.0)  # any fixed positive EDF: same in both
    given_edf = AllanResult(
        taus=r.taus,
        avar=r.avar,
        n_terms=r.n_terms,
        fs=FS,
        data_type="rate",
        kind="adev",
        overlapping=True,
        unit="deg/s",
        edf=edf,
    )
    # Every point (no automatic range selection): the reference solves the same problem.
    c = noise.fit(given_edf, auto_range=False)
    assert c.edf_source == "noise identification"
    ref = joint_irls(r.taus, r.avar, edf)
    got = np.array([0.0 if t.value is None else t.value**2 for t in c.terms])
    # Same weighted NNLS solved two ways (subset enumeration vs Lawson–Hanson), both iterated
    # to 1e-10..1e-12 relative change.
    np.testing.assert_allclose(got, ref, rtol=1e-6, atol=1e-12 * ref.max())


def test_exact_model_curve_is_recovered_by_both_methods() -> None:
    # Octave factors an 8 h record supports (N + 1 − 2m > 0 terms): m = 2**21 had a negative
    # n_terms, which the uint64 cast used to wrap and the binding now refuses.
    m = 2 ** np.arange(21)
    taus = m / FS
    sq = np.array([0.0, TRUE["arw"] ** 2, 0.0, 0.0, 0.0])
    avar = model_avar(sq, taus)
    r = AllanResult(
        taus=taus,
        avar=avar,
        n_terms=N_8H + 1 - 2 * m,
        fs=FS,
        data_type="rate",
        kind="adev",
        overlapping=True,
        unit="deg/s",
    )
    j = noise.fit(r)
    i = noise.fit(r, method="ieee")
    assert j.N.value == pytest.approx(TRUE["arw"], rel=1e-10)
    assert i.N.value == pytest.approx(TRUE["arw"], rel=1e-10)
    assert i.N.marker == pytest.approx((1.0, TRUE["arw"]))
    assert i.B.missing and "no flat region" in i.B.missing
    assert i.K.missing and "+0.5" in i.K.missing


def test_read_off_matches_numpy_reference() -> None:
    rate = noise.simulate(200_000, FS, seed=5, **TRUE)
    r = _curve(rate)
    c = noise.fit(r, method="ieee", regions={"N": (0.01, 1.0)})
    sel = (r.taus >= 0.01) & (r.taus <= 1.0)
    # The read-off's EDF for white rate noise: SP1065 simple formula (allantools.edf_simple).
    import allantools

    n_phase = int(r.n_terms[0] + 2 * r.m[0])
    edf = np.array([allantools.edf_simple(n_phase, int(m), 0) for m in r.m[sel]])
    expect = fixed_slope_value(r.taus[sel], r.avar[sel], edf, -0.5, 1.0)
    assert c.N.value == pytest.approx(expect, rel=1e-6)
    assert c.N.tau_range == (0.01, pytest.approx(r.taus[sel][-1]))
    slopes = local_slopes(r.taus, r.avar)
    assert np.all(np.abs(slopes[r.taus <= 1.0] + 0.5) < 0.1)


# --- units -------------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("src", "dst", "factor"),
    [
        ("deg/√s", "deg/√h", 60.0),
        ("deg/s", "deg/h", 3600.0),
        ("deg/s^1.5", "deg/h^1.5", 216000.0),
        ("deg/s²", "deg/h²", 3600.0**2),
        ("deg/√s", "rad/s/√Hz", math.pi / 180.0),
        ("rad/s^1.5", "rad/s²/sqrt(Hz)", 1.0),
        ("deg/s^1.5", "deg/h/√h", 216000.0),
        ("deg", "arcsec", 3600.0),
        ("m/s^1.5", "m/s/√h", 60.0),
        ("m/s^2", "mg", 1.0 / 9.80665e-3),
        ("m/s^2.5", "m/s³/√Hz", 1.0),
        ("m/s^1.5", "m/s²/√Hz", 1.0),
        ("g", "m/s^2", 9.80665),
        ("deg/h", "deg/s", 1.0 / 3600.0),
    ],
)
def test_conversion_factors_hand_computed(src: str, dst: str, factor: float) -> None:
    assert conversion_factor(src, dst) == pytest.approx(factor, rel=1e-14)


def test_coefficients_to_customary_units(eight_hour_fits: list) -> None:
    joint = eight_hour_fits[0][0]
    assert joint.N.unit == "deg/√s" and joint.B.unit == "deg/s" and joint.K.unit == "deg/s^1.5"
    assert joint.Q.unit == "deg" and joint.R.unit == "deg/s²"
    ieee = joint.to("ieee")
    assert ieee.N.unit == "deg/√h"
    assert ieee.N.value == pytest.approx(joint.N.value * 60.0, rel=1e-14)
    assert ieee.N.uncertainty == pytest.approx(joint.N.uncertainty * 60.0, rel=1e-14)
    assert ieee.B.value == pytest.approx(joint.B.value * 3600.0, rel=1e-14)
    assert ieee.K.value == pytest.approx(joint.K.value * 216000.0, rel=1e-14)
    si = joint.to("si")
    assert si.N.unit == "rad/s/√Hz" and si.K.unit == "rad/s²/√Hz"
    assert si.N.value == pytest.approx(joint.N.value * math.pi / 180.0, rel=1e-14)
    assert joint.to("kalibr") == si
    mixed = joint.to({"B": "deg/h"})
    assert mixed.B.unit == "deg/h" and mixed.N == joint.N
    back = ieee.to("base")
    assert back.N.value == pytest.approx(joint.N.value, rel=1e-14)
    assert joint.N.to("deg/h/√Hz").value == pytest.approx(joint.N.value * 3600.0, rel=1e-14)


@given(st.sampled_from(["deg/s", "rad/s", "m/s^2", "g", "mg"]), st.sampled_from("QNBKR"))
def test_base_units_parse_and_have_the_model_dimension(data_unit: str, symbol: str) -> None:
    unit = parse_unit(base_unit(data_unit, symbol))
    data = parse_unit(data_unit)
    p = {"Q": 1, "N": 0.5, "B": 0, "K": -0.5, "R": -1}[symbol]
    assert unit.dims[2] == data.dims[2] + p
    assert unit.dims[:2] == data.dims[:2]
    kind = sensor_kind(data_unit)
    from gyrobias.units import CUSTOMARY

    for system in ("ieee", "si"):
        assert parse_unit(CUSTOMARY[kind][system][symbol]).dims == unit.dims


def test_unknown_units_list_the_valid_ones(eight_hour_fits: list) -> None:
    joint = eight_hour_fits[0][0]
    with pytest.raises(ValueError, match="valid symbols are .*deg.*rad"):
        joint.N.to("furlong/fortnight")
    with pytest.raises(ValueError, match="different dimensions"):
        joint.N.to("deg/h")
    with pytest.raises(ValueError, match="system"):
        joint.to("imperial")
    with pytest.raises(ValueError, match="unit"):
        parse_unit("deg//s")
    with pytest.raises(ValueError, match="neither an angular rate"):
        sensor_kind("deg")


def test_accelerometer_terms_are_named_and_converted() -> None:
    rate = noise.simulate(100_000, FS, arw=0.002, bias_instability=1e-4, seed=2)
    r = adev(rate, FS, confidence=None, units="m/s^2")
    c = noise.fit(r)
    assert c.sensor == "accel" and "VRW" in c.N.name
    assert c.N.unit == "m/s^1.5"
    si = c.to("si")
    assert si.N.unit == "m/s²/√Hz" and si.N.value == pytest.approx(c.N.value, rel=1e-14)
    assert c.to("ieee").B.unit == "mg"


# --- exports -----------------------------------------------------------------------------------------


def test_kalibr_file_round_trips_through_yaml(eight_hour_fits: list, tmp_path) -> None:
    axes = [j for j, _ in eight_hour_fits[:3]]
    path = tmp_path / "imu.yaml"
    text = gyrobias.exports.write_kalibr(path, gyro=axes, update_rate=200.0)
    data = yaml.safe_load(path.read_text())
    assert text == path.read_text()
    expect_n = max(a.N.value for a in axes) * math.pi / 180.0
    expect_k = max(a.K.value for a in axes) * math.pi / 180.0
    assert data["gyroscope_noise_density"] == pytest.approx(expect_n, rel=1e-6)
    assert data["gyroscope_random_walk"] == pytest.approx(expect_k, rel=1e-6)
    assert data["update_rate"] == 200.0
    assert data["rostopic"] == "/imu0"
    assert ", continuous" in text.lower()
    assert "accelerometer_noise_density" not in data
    # Single-axis method; update rate defaults to fs.
    axes[0].to_kalibr(tmp_path / "one.yaml")
    one = yaml.safe_load((tmp_path / "one.yaml").read_text())
    assert one["update_rate"] == FS


def test_kalibr_missing_term_is_a_comment_and_bad_input(tmp_path) -> None:
    rate = noise.simulate(50_000, FS, arw=0.01, seed=1)
    c = noise.fit(_curve(rate), terms=("N", "B"))
    # K not requested: neither identified nor bounded; the one writer (exports) refuses it.
    with pytest.raises(ValueError, match=r"gyro K \(random walk K\): required by the kalibr"):
        gyrobias.exports.write_kalibr(tmp_path / "k.yaml", gyro=[c])
    assert not (tmp_path / "k.yaml").exists()
    # K requested but invisible: the bound is written, marked.
    bounded = noise.fit(_curve(rate))
    assert bounded.K.bounded
    text = gyrobias.exports.write_kalibr(tmp_path / "k.yaml", gyro=[bounded])
    data = yaml.safe_load(text)
    assert data["gyroscope_random_walk"] == pytest.approx(
        bounded.K.to("rad/s²/√Hz").upper_bound, rel=1e-6
    )
    assert "UPPER BOUND" in text
    # gyrobias.noise.write_kalibr is the exports writer itself (one Kalibr writer).
    assert noise.write_kalibr is gyrobias.exports.write_kalibr
    with pytest.raises(AttributeError, match="no attribute 'nope'"):
        _ = noise.nope  # type: ignore[attr-defined]
    with pytest.raises(ValueError, match="gyro and/or accel"):
        gyrobias.exports.write_kalibr(tmp_path / "x.yaml")
    with pytest.raises(ValueError, match="not accel"):
        gyrobias.exports.write_kalibr(tmp_path / "x.yaml", accel=[c])
    unitless = noise.fit(adev(rate, FS, confidence=None))
    with pytest.raises(ValueError, match="unit"):
        gyrobias.exports.write_kalibr(tmp_path / "x.yaml", gyro=[unitless])
    with pytest.raises(ValueError, match="unit"):
        unitless.to("ieee")


def test_json_and_summary(eight_hour_fits: list, tmp_path) -> None:
    joint = eight_hour_fits[0][0].to("ieee")
    text = joint.to_json(tmp_path / "c.json")
    data = json.loads((tmp_path / "c.json").read_text())
    assert json.loads(text) == data
    assert data["terms"]["N"]["unit"] == "deg/√h"
    assert data["terms"]["N"]["value"] == pytest.approx(joint.N.value)
    assert data["terms"]["R"]["value"] is None and data["terms"]["R"]["missing"]
    s = joint.summary()
    for needle in ("deg/√h", "deg/h", "±", "angle random walk", "upper bound"):
        assert needle in s


# --- bad input -----------------------------------------------------------------------------------


def test_constant_data_is_an_error() -> None:
    r = adev(np.full(1000, 0.5), FS, confidence=None, units="deg/s")
    for method in ("joint", "ieee"):
        with pytest.raises(ValueError, match="constant"):
            noise.fit(r, method=method)


def test_nan_data_is_rejected_before_the_fit() -> None:
    with pytest.raises(ValueError, match="non-finite"):
        adev(np.full(100, np.nan), FS, confidence=None)


def test_short_curves() -> None:
    r = adev(np.random.default_rng(0).normal(size=5), FS, confidence=None, units="deg/s")
    with pytest.raises(ValueError, match="too short"):
        noise.fit(r)
    # The read-off reports every term missing with its reason rather than guessing.
    c = noise.fit(r, method="ieee")
    assert all(t.value is None and t.missing for t in c.terms)
    long = _curve(noise.simulate(10_000, FS, arw=0.1, seed=1))
    with pytest.raises(ValueError, match="too short"):
        noise.fit(long, tau_range=(1.0, 2.0))


def test_bad_arguments() -> None:
    r = _curve(noise.simulate(10_000, FS, arw=0.1, seed=1))
    with pytest.raises(ValueError, match="method"):
        noise.fit(r, method="magic")
    with pytest.raises(ValueError, match="terms"):
        noise.fit(r, terms=("N", "X"))
    with pytest.raises(ValueError, match="tau_range"):
        noise.fit(r, tau_range=(2.0, 1.0))
    with pytest.raises(ValueError, match="regions"):
        noise.fit(r, regions={"N": (0.01, 1.0)})
    with pytest.raises(ValueError, match="regions"):
        noise.fit(r, method="ieee", regions={"N": (1e5, 1e6)})
    with pytest.raises(ValueError, match="slope_tolerance"):
        noise.fit(r, method="ieee", slope_tolerance=0.0)
    with pytest.raises(ValueError, match="min_points"):
        noise.fit(r, method="ieee", min_points=0)
    with pytest.raises(TypeError, match="min_points"):
        noise.fit(r, method="ieee", min_points=2.5)  # type: ignore[arg-type]
    m = gyrobias.allan.mdev(noise.simulate(1000, FS, arw=0.1, seed=1), FS, confidence=None)
    with pytest.raises(ValueError, match="adev"):
        noise.fit(m)  # type: ignore[arg-type]
    with pytest.raises(TypeError):
        noise.fit("curve")  # type: ignore[arg-type]


def test_sequence_of_results_gives_tuple() -> None:
    rate = noise.simulate(10_000, FS, arw=0.1, axes=2, seed=1)
    results = adev(rate, FS, confidence=None, units="deg/s")
    out = noise.fit(results)
    assert isinstance(out, tuple) and len(out) == 2


# --- plot and CLI --------------------------------------------------------------------------------


def test_plot_draws_model_asymptotes_and_labelled_markers(eight_hour_fits: list) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    joint = eight_hour_fits[0][0]
    ax = joint.plot()
    labels = [line.get_label() for line in ax.get_lines()]
    assert "joint model" in labels and "N asymptote" in labels and "K asymptote" in labels
    texts = [t.get_text() for t in ax.texts]
    assert any(t.startswith("N = ") and "τ = 1 s" in t for t in texts)
    assert any(t.startswith("B = ") and "0.664" in t for t in texts)
    assert any(t.startswith("K = ") and "τ = 3 s" in t for t in texts)
    low, _ = ax.get_ylim()
    assert low <= joint.K.marker[1]  # every read-off marker is in view
    plt.close("all")


def test_cli_run_fit_prints_and_writes_kalibr(tmp_path, capsys) -> None:
    parser = argparse.ArgumentParser()
    cli_noise.add_fit_arguments(parser)
    path = tmp_path / "imu.yaml"
    args = parser.parse_args(["--fit", "--kalibr", str(path)])
    rate = noise.simulate(200_000, FS, axes=3, seed=1, **TRUE)
    results = adev(rate, FS, confidence=None, units="deg/s", axis_names=["x", "y", "z"])
    cli_noise.run_fit(args, list(results))  # type: ignore[arg-type]
    out = capsys.readouterr().out
    assert "deg/√h" in out and "±" in out and "axis z" in out
    assert yaml.safe_load(path.read_text())["gyroscope_noise_density"] > 0
    assert len(args.noise_coefficients) == 3
    args = parser.parse_args([])
    cli_noise.run_fit(args, list(results))  # type: ignore[arg-type]
    assert args.noise_coefficients == []
    unitless = adev(rate, FS, confidence=None)
    args = parser.parse_args(["--kalibr", str(path)])
    with pytest.raises(ValueError, match="unit"):  # main() prints it as one error line, exit 2
        cli_noise.run_fit(args, list(unitless))  # type: ignore[arg-type]


def test_demo_section_prints_true_and_recovered(tmp_path, capsys) -> None:
    rate = noise.simulate(200_000, FS, axes=3, seed=4, **TRUE)
    cli_noise.demo_section(rate, FS, tmp_path, TRUE)
    out = capsys.readouterr().out
    assert "true" in out and "(0.2)" in out and "(3)" in out and "axis x" in out
    assert (tmp_path / "noise_fit.png").exists()
    # The demo's per-axis customary table is understood too, and the truth is optional.
    table = {"arw_deg_per_sqrt_h": [0.2, 0.25, 0.3], "bias_instability_deg_per_h": [3.0, 4.0, 5.0]}
    cli_noise.demo_section(rate, FS, tmp_path, table)
    out = capsys.readouterr().out
    assert "(0.25)" in out and "(5)" in out
    cli_noise.demo_section(rate, FS, tmp_path)
    assert "deg/√h" in capsys.readouterr().out


def test_terms_without_uncertainty_print() -> None:
    # Datasheet values and conservative sets have no uncertainty: printing must not fail.
    gyro = noise.from_datasheet(arw="0.3 deg/sqrt(h)", bias_instability="5 deg/h").gyro
    assert gyro is not None and gyro.N.uncertainty is None
    text = str(gyro.N)
    assert text.startswith("N (angle random walk") and "±" not in text
