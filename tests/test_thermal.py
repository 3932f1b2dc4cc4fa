"""Tests of gyrobias.thermal (AR(1) fits, SPEC §9; temperature models) and `gyrobias thermal`."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import scipy.signal as ss
from hypothesis import example, given
from hypothesis import strategies as st
from numpy.testing import assert_allclose
from scipy.interpolate import PchipInterpolator

import gyrobias
from gyrobias import fir, thermal
from tests.reference_thermal import ar1 as ar1_ref


def simulate_ar1(c: float, n: int, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return ss.lfilter([1.0], [1.0, -c], rng.normal(size=n))


@given(seed=st.integers(0, 2**32 - 1), c=st.floats(-0.95, 0.95), n=st.integers(5, 2000))
def test_ar1_equals_lstsq_reference(seed: int, c: float, n: int) -> None:
    x = simulate_ar1(c, n, seed) + 3.0
    f = thermal.fit_ar1(x, 100.0)
    rc, rse, rsig = ar1_ref(x)
    # Normal-equation sums vs LAPACK least squares: agreement to ~n·ε.
    assert f.c == pytest.approx(rc, rel=1e-10, abs=1e-12)
    assert f.c_std_error == pytest.approx(rse, rel=1e-8)
    assert f.sigma_e == pytest.approx(rsig, rel=1e-8)
    assert f.c_ar == -f.c


def test_ar1_recovers_coefficient_and_gauss_markov() -> None:
    c = 0.9
    x = simulate_ar1(c, 200_000, 1)
    f = thermal.fit_ar1(x, fs=100.0)
    # 4 standard errors (se ≈ √((1 − c²)/n) ≈ 1e-3).
    assert abs(f.c - c) < 4 * f.c_std_error
    assert f.c_std_error == pytest.approx(np.sqrt((1 - c**2) / x.size), rel=0.05)
    assert f.sigma_e == pytest.approx(1.0, rel=0.01)
    assert f.beta == pytest.approx(-np.log(f.c) * 100.0)
    assert f.correlation_time == pytest.approx(1 / f.beta)
    assert f.process_std == pytest.approx(1 / np.sqrt(1 - c**2), rel=0.02)
    d = f.to_dict()
    assert d["c_ar"] == -d["c"]
    neg = thermal.fit_ar1(simulate_ar1(-0.5, 5000, 2))
    assert neg.beta is None and neg.correlation_time is None


@pytest.mark.parametrize(("fc", "expected"), [(8.0, 0.961), (16.0, 0.844), (24.0, 0.671)])
def test_ts_sign_convention_with_its_filters(fc: float, expected: float) -> None:
    """SPEC §9: white noise through [TS]'s Kaiser filters (4 Hz transition, 0.0001/100 dB) gives
    c ≈ +0.961/+0.844/+0.671 where [TS] prints C_AR ≈ −0.96/−0.9/−0.7."""
    filt = fir.kaiser_lowpass(100.0, fc - 2.0, fc + 2.0)
    x = np.random.default_rng(int(fc)).normal(size=300_000)
    y = filt.apply(x, zero_phase=False)[filt.numtaps :]
    f = thermal.fit_ar1(y, 100.0)
    # Exact lag-1 autocorrelation of the filtered white noise: ρ(1) = Σh_k h_{k+1}/Σh_k².
    h = filt.taps
    rho = float(h[:-1] @ h[1:] / (h @ h))
    assert f.c == pytest.approx(rho, abs=0.004)  # sampling error ~ few × 1e-3 at n = 3e5
    assert f.c == pytest.approx(expected, abs=0.005)  # SPEC's 3-digit values
    assert f.c_ar == pytest.approx(-expected, abs=0.005)


def test_bad_ar1_input() -> None:
    with pytest.raises(ValueError, match="x is too short"):
        thermal.fit_ar1([1.0, 2.0])
    with pytest.raises(gyrobias.GyroLinAlgError, match="constant"):
        thermal.fit_ar1(np.full(10, 2.0))
    with pytest.raises(ValueError, match="x .*index 1"):
        thermal.fit_ar1([1.0, np.nan, 2.0, 3.0])
    with pytest.raises(ValueError, match="fs"):
        thermal.fit_ar1(np.arange(10.0), fs=0.0)


# --- TemperatureModel ------------------------------------------------------------------------

TEMPS = np.array([30.0, -30.0, 60.0, 0.0])  # deliberately unsorted
ARW = np.array([1.9547, 2.2292, 1.9549, 1.6224])  # [TS] Table 1, MotionPakII gyro (deg/√h)
CAR = np.array([0.2935, -0.1413, -0.2444, -0.1223])  # [TS] Table 2, MotionPakII gyro


def model(method: str, degree: int = 2) -> thermal.TemperatureModel:
    return thermal.TemperatureModel(
        TEMPS, {"arw": ARW, "c_ar": CAR}, units={"arw": "deg/√h"}, method=method, degree=degree
    )


def test_linear_equals_numpy_interp() -> None:
    m = model("linear")
    at = np.linspace(-30, 60, 37)
    o = np.argsort(TEMPS)
    assert_allclose(m("arw", at), np.interp(at, TEMPS[o], ARW[o]), rtol=1e-14)
    assert m("arw", 0.0) == pytest.approx(1.6224)
    assert m.range == (-30.0, 60.0)


def pchip_reference(temps: np.ndarray, vals: np.ndarray, at: np.ndarray) -> np.ndarray:
    """SciPy's PCHIP, evaluated on the data scaled by a power of two to max|y| in [1, 2).

    PCHIP is homogeneous in y, and a power-of-two scale is exact for normal numbers, so for
    ordinary data this *is* ``PchipInterpolator(temps, vals)(at)`` bit for bit. It keeps the
    reference defined on subnormal or tiny-span data, where SciPy's harmonic-mean slopes
    ``w/m`` overflow (RuntimeWarning) and it silently flattens the curve.
    """
    span = float(np.max(np.abs(vals)))
    e = int(np.frexp(span)[1]) - 1 if span > 0 else 0
    scaled = np.ldexp(vals, -e)
    # After scaling, w/m can still overflow only for a slope below ~1e-306 of the data's
    # scale (data mixing O(1) and subnormal values). SciPy then takes the slope as 0, the
    # limit of the harmonic mean and what gyrobias computes too (to within 1e-306 of the
    # scale), so that overflow — and only that one — is expected here.
    with np.errstate(over="ignore"):
        return np.ldexp(PchipInterpolator(temps, scaled, extrapolate=True)(at), e)


@given(vals=st.lists(st.floats(-5, 5), min_size=5, max_size=5), extra=st.floats(-40, 70))
@example(vals=[0.0, 0.0, 0.0, 0.0, 2.2e-311], extra=0.0)  # issue 19: SciPy overflowed in divide
@example(vals=[1e-310, 3e-310, 0.0, 2e-309, 1e-311], extra=65.0)
@example(vals=[5.0, 1e-310, 2e-310, 3e-310, 0.0], extra=-35.0)  # O(1) beside subnormal values
def test_pchip_equals_scipy(vals: list[float], extra: float) -> None:
    temps = np.array([-30.0, -5.0, 0.0, 30.0, 60.0])
    m = thermal.TemperatureModel(temps, {"p": vals}, method="pchip")
    at = np.r_[np.linspace(-30, 60, 50), extra]
    ref = pchip_reference(temps, np.array(vals), at)
    # Same Fritsch–Carlson slopes and end conditions; Hermite evaluation in another form:
    # ~1e-15 relative to the data's scale. atol is relative to that scale (not absolute, so
    # tiny data are compared too) plus two subnormal ulps for the final rounding into the
    # subnormal range.
    scale = float(np.max(np.abs(vals)))
    assert_allclose(m("p", at, extrapolate=True), ref, rtol=1e-12, atol=1e-12 * scale + 1e-323)


def test_pchip_two_points_is_linear_and_polynomial_equals_polyfit() -> None:
    m2 = thermal.TemperatureModel([0.0, 10.0], {"p": [1.0, 3.0]}, method="pchip")
    assert m2("p", 2.5) == pytest.approx(1.5)
    for deg in (1, 2, 3):
        m = model("polynomial", deg)
        o = np.argsort(TEMPS)
        coef = np.polyfit(TEMPS[o], ARW[o], deg)
        at = np.linspace(-30, 60, 11)
        assert_allclose(m("arw", at), np.polyval(coef, at), rtol=1e-10)


def test_extrapolation_refused_unless_asked() -> None:
    m = model("pchip")
    with pytest.raises(ValueError, match="temperature.*outside the calibrated range"):
        m("arw", 61.0)
    with pytest.raises(ValueError, match="extrapolate"):
        m.evaluate(-40.0)
    assert np.isfinite(m("arw", 80.0, extrapolate=True))
    assert set(m.evaluate(20.0)) == {"arw", "c_ar"}
    assert m("arw", np.array([[0.0, 30.0]])).shape == (1, 2)
    with pytest.raises(ValueError, match="unknown parameter"):
        m("vrw", 0.0)


def test_json_round_trip() -> None:
    m = model("polynomial", 2)
    back = thermal.TemperatureModel.from_json(m.to_json())
    assert back.to_dict() == m.to_dict()
    assert back("c_ar", 12.0) == m("c_ar", 12.0)
    assert json.loads(m.to_json())["temperatures"] == [-30.0, 0.0, 30.0, 60.0]
    assert "arw" in m.table()
    with pytest.raises(ValueError, match="temperatures"):
        thermal.TemperatureModel.from_dict({"parameters": {}})


def test_bad_model_input() -> None:
    with pytest.raises(ValueError, match="distinct"):
        thermal.TemperatureModel([0.0, 0.0, 10.0], {"p": [1, 2, 3]})
    with pytest.raises(ValueError, match="temperatures"):
        thermal.TemperatureModel([0.0], {"p": [1]})
    with pytest.raises(ValueError, match=r"parameters\['p'\] has 2 values"):
        thermal.TemperatureModel([0.0, 1.0, 2.0], {"p": [1, 2]})
    with pytest.raises(ValueError, match="degree 3"):
        thermal.TemperatureModel([0.0, 1.0, 2.0], {"p": [1, 2, 3]}, method="polynomial", degree=3)
    with pytest.raises(ValueError, match="method"):
        thermal.TemperatureModel([0.0, 1.0], {"p": [1, 2]}, method="spline")
    with pytest.raises(ValueError, match="non-finite"):
        thermal.TemperatureModel([0.0, np.nan], {"p": [1, 2]})


# --- per-log analysis and the builder ----------------------------------------------------------


def white_logs(n: int = 60_000) -> dict[float, np.ndarray]:
    rng = np.random.default_rng(0)
    return {t: rng.normal(0.0, 0.01 * (1 + t / 100), n) for t in (-30.0, 0.0, 30.0, 60.0)}


def test_build_temperature_model() -> None:
    logs = white_logs()
    m = thermal.build_temperature_model(logs, 100.0, units="deg/s", method="linear")
    assert m.range == (-30.0, 60.0)
    for t in (-30.0, 60.0):
        sigma = 0.01 * (1 + t / 100)
        # White noise: N = σ/√fs (IEEE 952), read off at τ = 1 s with ~6 % scatter (EDF ~ 600).
        assert m("arw", t) == pytest.approx(sigma / 10, rel=0.1)
        assert m("noise_density", t) == pytest.approx(sigma * np.sqrt(2 / 100), rel=0.03)
    # The 16 Hz prefilter makes the white noise AR(1)-like with c ≈ 0.846 (SPEC §9).
    assert m("ar1_c", 15.0) == pytest.approx(0.846, abs=0.01)
    analyses = thermal.analyse_logs(list(logs.items()), 100.0, prefilter=False)
    assert [a.temperature for a in analyses] == [-30.0, 0.0, 30.0, 60.0]
    assert all(abs(a.ar1.c) < 0.02 for a in analyses)  # raw white noise: c ≈ 0
    assert analyses[0].to_dict()["filter_cutoff"] is None


def test_builder_bad_input() -> None:
    x = np.random.default_rng(0).normal(size=5000)
    with pytest.raises(ValueError, match="distinct"):
        thermal.analyse_logs([(0.0, x), (0.0, x)], 100.0)
    with pytest.raises(ValueError, match="logs is empty"):
        thermal.analyse_logs({}, 100.0)
    with pytest.raises(ValueError, match="temperatures"):
        thermal.build_temperature_model({0.0: x}, 100.0)


# --- CLI -----------------------------------------------------------------------------------------


def run_cli(argv: list[str]) -> int:
    # through main(): LOG@T and the option values are checked by the argument layer (exit 2)
    from gyrobias.cli import main

    return main(["thermal", *argv])


def test_cli_prints_table_and_writes_model(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    logs = white_logs(30_000)
    tags = []
    for t, x in logs.items():
        if t == 0.0:
            p = tmp_path / "zero.csv"
            np.savetxt(
                p,
                np.c_[np.arange(x.size) / 100.0, x],
                delimiter=",",
                header="time,rate",
                comments="",
            )
            tags.append(f"{p}@{t:g}")
        else:
            p = tmp_path / f"log{t:g}.npy"
            np.save(p, x.reshape(-1, 1))
            tags.append(f"{p}@{t:g}")
    out_json = tmp_path / "model.json"
    assert run_cli([*tags, "--fs", "100", "--json", str(out_json)]) == 0
    text = capsys.readouterr().out
    assert "C_AR = -c" in text and "IEEE 952" in text
    rows = [
        line
        for line in text.splitlines()
        if line.strip().startswith(("-30.0", "0.0", "30.0", "60.0"))
    ]
    assert len(rows) == 4
    model = thermal.TemperatureModel.from_json(out_json.read_text())
    assert model("arw", 0.0) == pytest.approx(0.001, rel=0.1)


def test_cli_errors(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    p = tmp_path / "a.npy"
    np.save(p, np.random.default_rng(0).normal(size=3000))
    assert run_cli([f"{p}@0", f"{p}@0", "--fs", "100"]) == 2
    assert "distinct" in capsys.readouterr().err
    assert run_cli([str(p), "--fs", "100"]) == 2
    assert "PATH@TEMPERATURE" in capsys.readouterr().err
    assert run_cli([f"{p}@warm", "--fs", "100"]) == 2
    assert run_cli([f"{tmp_path / 'missing.npy'}@0", "--fs", "100"]) == 2
    assert run_cli([f"{p}@0", "--fs", "100", "--column", "3"]) == 2
    assert "column" in capsys.readouterr().err
    assert run_cli([f"{p}@0", f"{p}@10", "--fs", "100", "--column", "0", "--no-filter"]) == 0


def test_analyse_log_reads_n_and_b_like_ieee_952() -> None:
    # The read-off of gyrobias.noise on [TS]'s regions equals the textbook formulas computed
    # here with NumPy: N = σ(τ)·√τ at τ = round(fs)/fs, B = min over octave τ of σ / √(2 ln 2/π)
    # (to a few ulp: the read-off goes through a log-log line of fixed slope −½).
    x = np.random.default_rng(5).normal(0.0, 0.02, 40_000) + np.cumsum(
        np.random.default_rng(6).normal(0.0, 1e-4, 40_000)
    )
    for fs in (100.0, 37.5):
        a = thermal.analyse_log(x, fs, 20.0, prefilter=False)
        tau = round(fs) / fs
        one = gyrobias.allan.adev(x, fs, taus=[tau], confidence=None)
        octave = gyrobias.allan.adev(x, fs, taus="octave", confidence=None)
        assert a.arw == pytest.approx(float(one.adev[0]) * np.sqrt(tau), rel=1e-14)
        flicker = np.sqrt(2 * np.log(2) / np.pi)
        assert a.bias_instability == pytest.approx(float(octave.adev.min()) / flicker, rel=1e-15)
