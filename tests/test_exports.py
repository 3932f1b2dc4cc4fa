"""Estimator exports: every format parsed back, conventions checked, errors, atomic writes,
and the discrete-time parameters against simulation."""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

import numpy as np
import pytest
import yaml
from hypothesis import given
from hypothesis import strategies as st

import gyrobias
from gyrobias import allan, exports, noise
from gyrobias.noise import NoiseCoefficients

RATE = 200.0


def datasheet() -> gyrobias.noise.Datasheet:
    return gyrobias.noise.from_datasheet(
        noise_density="0.008 deg/s/sqrt(Hz)",
        bias_instability="8 deg/h",
        rrw="3 deg/h^1.5",
        vrw="0.05 m/s/sqrt(h)",
        accel_bias_instability="0.05 mg",
        accel_random_walk="1e-4 m/s^2.5",
        rate=RATE,
    )


def si(c: NoiseCoefficients, symbol: str, unit: str) -> float:
    value = c[symbol].to(unit).value
    assert value is not None
    return value


def expected(gyro: NoiseCoefficients, accel: NoiseCoefficients) -> dict[str, float]:
    return {
        "gN": si(gyro, "N", "rad/s/sqrt(Hz)"),
        "gK": si(gyro, "K", "rad/s^2/sqrt(Hz)"),
        "gB": si(gyro, "B", "rad/s"),
        "aN": si(accel, "N", "m/s^2/sqrt(Hz)"),
        "aK": si(accel, "K", "m/s^3/sqrt(Hz)"),
        "aB": si(accel, "B", "m/s^2"),
    }


def load_yaml(text: str) -> dict:
    """OpenCV-style files start with '%YAML:1.0', which PyYAML does not accept."""
    lines = text.splitlines()
    if lines and lines[0].startswith("%YAML:"):
        lines = lines[1:]
    return yaml.safe_load("\n".join(lines))


def parse_matlab(text: str) -> dict[str, dict[str, float]]:
    out: dict[str, dict[str, float]] = {}
    for var, body in re.findall(r"(\w+) = (?:gyro|accel)params\((.*?)\);", text, flags=re.DOTALL):
        out[var] = {k: float(v) for k, v in re.findall(r"'(\w+)',\s*([-+0-9.eE]+)", body)}
    rate = re.search(r"'SampleRate',\s*([0-9.eE+]+)", text)
    if rate:
        out["imu"] = {"SampleRate": float(rate.group(1))}
    return out


# Values are written with 7 significant digits.
REL = 1e-6


def check_all(texts: dict[str, str], e: dict[str, float], rate: float) -> None:
    k = load_yaml(texts["kalibr"])
    assert k["gyroscope_noise_density"] == pytest.approx(e["gN"], rel=REL)
    assert k["gyroscope_random_walk"] == pytest.approx(e["gK"], rel=REL)
    assert k["accelerometer_noise_density"] == pytest.approx(e["aN"], rel=REL)
    assert k["accelerometer_random_walk"] == pytest.approx(e["aK"], rel=REL)
    assert k["update_rate"] == pytest.approx(rate) and k["rostopic"] == "/imu0"

    o = load_yaml(texts["openvins"])["imu0"]
    for key in (
        "gyroscope_noise_density",
        "gyroscope_random_walk",
        "accelerometer_noise_density",
        "accelerometer_random_walk",
    ):
        assert o[key] == k[key]
    assert o["model"] == "kalibr" and o["update_rate"] == pytest.approx(rate)
    assert np.array_equal(o["T_i_b"], np.eye(4)) and np.array_equal(o["Tg"], np.zeros((3, 3)))

    v = load_yaml(texts["vins"])  # discrete: n = N·√f, w = K/√f
    assert v["gyr_n"] == pytest.approx(e["gN"] * math.sqrt(rate), rel=REL)
    assert v["acc_n"] == pytest.approx(e["aN"] * math.sqrt(rate), rel=REL)
    assert v["gyr_w"] == pytest.approx(e["gK"] / math.sqrt(rate), rel=REL)
    assert v["acc_w"] == pytest.approx(e["aK"] / math.sqrt(rate), rel=REL)

    s = load_yaml(texts["orbslam3"])
    assert s["IMU.NoiseGyro"] == pytest.approx(e["gN"], rel=REL)
    assert s["IMU.NoiseAcc"] == pytest.approx(e["aN"], rel=REL)
    assert s["IMU.GyroWalk"] == pytest.approx(e["gK"], rel=REL)
    assert s["IMU.AccWalk"] == pytest.approx(e["aK"], rel=REL)
    assert s["IMU.Frequency"] == pytest.approx(rate)

    li = load_yaml(texts["liosam"])["lio_sam"]
    assert li["imuGyrNoise"] == pytest.approx(e["gN"], rel=REL)
    assert li["imuAccNoise"] == pytest.approx(e["aN"], rel=REL)
    assert li["imuGyrBiasN"] == pytest.approx(e["gK"], rel=REL)
    assert li["imuAccBiasN"] == pytest.approx(e["aK"], rel=REL)

    m = parse_matlab(texts["matlab"])
    assert m["gyro"]["NoiseDensity"] == pytest.approx(e["gN"], rel=REL)
    assert m["gyro"]["RandomWalk"] == pytest.approx(e["gK"], rel=REL)
    assert m["gyro"]["BiasInstability"] == pytest.approx(e["gB"], rel=REL)
    assert m["accel"]["NoiseDensity"] == pytest.approx(e["aN"], rel=REL)
    assert m["accel"]["BiasInstability"] == pytest.approx(e["aB"], rel=REL)
    assert m["imu"]["SampleRate"] == pytest.approx(rate)
    assert "imuSensor(" in texts["matlab"]

    j = json.loads(texts["json"])
    assert j["estimator_values"]["gyro"]["N"]["value"] == pytest.approx(e["gN"], rel=1e-12)
    assert j["estimator_values"]["accel"]["K"]["unit"] == "m/s³/√Hz"
    assert j["rate_hz"] == pytest.approx(rate)
    assert j["discrete"]["gyro"][0]["white"]["value"] == pytest.approx(
        e["gN"] * math.sqrt(rate), rel=1e-12
    )


def test_datasheet_user_gets_all_seven_in_one_call(tmp_path: Path) -> None:
    ds = datasheet()
    assert ds.gyro is not None and ds.accel is not None
    texts = ds.export_all(tmp_path)
    assert sorted(texts) == sorted(exports.FORMATS)
    for fmt, name in exports.DEFAULT_FILENAMES.items():
        assert (tmp_path / name).read_text(encoding="utf-8") == texts[fmt]
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".")]  # no temporary files left
    check_all(texts, expected(ds.gyro, ds.accel), RATE)


def simulated_axes(seed: int) -> tuple[list[NoiseCoefficients], list[NoiseCoefficients]]:
    fs = 100.0
    gyro_rate = gyrobias.noise.simulate(
        400_000, fs, arw=0.3 / 60, rrw=60 / 216000, axes=2, seed=seed
    )
    acc = gyrobias.noise.simulate(400_000, fs, arw=0.05 / 60, rrw=3e-4, axes=2, seed=seed + 1)
    g = gyrobias.allan.adev(gyro_rate, fs, units="deg/s", axis_names=["x", "y"], confidence=None)
    a = gyrobias.allan.adev(acc, fs, units="m/s^2", axis_names=["x", "y"], confidence=None)
    return list(gyrobias.noise.fit(g, terms=("N", "K"))), list(
        gyrobias.noise.fit(a, terms=("N", "K"))
    )


def test_log_user_gets_all_seven_with_the_largest_axis() -> None:
    gyro, accel = simulated_axes(5)
    texts = exports.export_all(gyro, accel=accel)
    e = {
        "gN": max(si(c, "N", "rad/s/√Hz") for c in gyro),
        "gK": max(si(c, "K", "rad/s²/√Hz") for c in gyro),
        "aN": max(si(c, "N", "m/s²/√Hz") for c in accel),
        "aK": max(si(c, "K", "m/s³/√Hz") for c in accel),
        "gB": 0.0,
        "aB": 0.0,
    }
    k = load_yaml(texts["kalibr"])
    assert k["gyroscope_noise_density"] == pytest.approx(e["gN"], rel=REL)
    assert k["update_rate"] == pytest.approx(100.0)  # the data's rate by default
    assert "largest over axes x, y" in texts["kalibr"]
    m = parse_matlab(texts["matlab"])
    assert "BiasInstability" not in m["gyro"] and "not identified" in texts["matlab"]
    assert load_yaml(texts["vins"])["gyr_n"] == pytest.approx(e["gN"] * 10.0, rel=REL)
    assert json.loads(texts["json"])["gyro"][1]["axis"] == "y"
    # The method on NoiseCoefficients writes the same file as the function.
    assert gyro[0].export("orbslam3", accel=accel[0]) == exports.export(
        [gyro[0]], "orbslam3", accel=[accel[0]]
    )


def test_kalibr_export_agrees_with_write_kalibr(tmp_path: Path) -> None:
    gyro, accel = simulated_axes(9)
    ours = load_yaml(exports.export(gyro, "kalibr", accel=accel))
    theirs = load_yaml(gyrobias.exports.write_kalibr(tmp_path / "k.yaml", gyro=gyro, accel=accel))
    for key in (
        "gyroscope_noise_density",
        "gyroscope_random_walk",
        "accelerometer_noise_density",
        "accelerometer_random_walk",
        "update_rate",
    ):
        assert ours[key] == pytest.approx(theirs[key], rel=REL)


def test_gyro_only_writes_accel_keys_as_comments() -> None:
    ds = gyrobias.noise.from_datasheet(arw="0.3 deg/√h", rrw="3 deg/h^1.5")
    text = ds.export("kalibr", rate=100)
    parsed = load_yaml(text)
    assert "accelerometer_noise_density" not in parsed and "gyroscope_noise_density" in parsed
    assert "# accelerometer_noise_density: not written: no accelerometer coefficients given" in text
    accel_only = gyrobias.noise.from_datasheet(vrw="0.05 m/s/√h", accel_random_walk="1e-4 m/s^2.5")
    assert accel_only.accel is not None
    assert "imuAccNoise" in load_yaml(accel_only.accel.export("liosam"))["lio_sam"]


def test_missing_required_term_and_rate_are_named() -> None:
    ds = gyrobias.noise.from_datasheet(arw="0.3 deg/√h")
    with pytest.raises(
        ValueError, match=r"gyro K \(random walk K\): required by the kalibr format"
    ):
        ds.export("kalibr", rate=100)
    full = gyrobias.noise.from_datasheet(arw="0.3 deg/√h", rrw="1 deg/h^1.5")
    with pytest.raises(ValueError, match="rate: the openvins format needs the IMU rate"):
        full.export("openvins")
    assert "SampleRate" not in full.export("matlab")  # matlab: the rate is optional
    with pytest.raises(ValueError, match="fmt must be one of"):
        full.export("rovio")
    with pytest.raises(ValueError, match="rate must be finite"):
        full.export("kalibr", rate=0.0)
    with pytest.raises(ValueError, match="accel: coefficients of data in 'rad/s' are gyro"):
        exports.export(None, "json", accel=full.gyro)
    r = gyrobias.allan.adev(
        gyrobias.noise.simulate(5000, 100.0, arw=0.01, seed=1), 100.0, confidence=None
    )
    with pytest.raises(ValueError, match="data unit is unknown"):
        exports.export(gyrobias.noise.fit(r), "json")


def test_atomic_write_keeps_the_old_file_on_error(tmp_path: Path) -> None:
    target = tmp_path / "imu.yaml"
    target.write_text("old\n")
    ds = gyrobias.noise.from_datasheet(arw="0.3 deg/√h")
    with pytest.raises(ValueError):
        ds.export("kalibr", target, rate=100)
    assert target.read_text() == "old\n"
    exports.atomic_write(target, "new\n")
    assert target.read_text() == "new\n"
    assert [p.name for p in tmp_path.iterdir()] == ["imu.yaml"]


def test_discrete_matches_simulation() -> None:
    fs = 250.0
    n = 400_000
    arw, rrw = 0.01, 2e-4  # deg/√s, deg/s^1.5
    white = gyrobias.noise.simulate(n, fs, arw=arw, seed=3)
    walk = gyrobias.noise.simulate(n, fs, rrw=rrw, seed=4)
    ds = gyrobias.noise.from_datasheet(
        arw=f"{arw} deg/√s", rrw=f"{rrw} deg/s^1.5", gyro_unit="deg/s"
    )
    assert ds.gyro is not None
    d = ds.gyro.discrete(fs)
    assert d.white.unit == "deg/s" and d.white.value is not None and d.bias_walk.value is not None
    # Monte Carlo: sample std of the white samples and of the random walk's steps; relative
    # standard error 1/√(2n) ≈ 0.0011, so 1 % is > 9σ.
    assert np.std(white) == pytest.approx(d.white.value, rel=0.01)
    assert np.std(np.diff(walk)) == pytest.approx(d.bias_walk.value, rel=0.01)
    assert d.white.value == pytest.approx(arw * math.sqrt(fs), rel=1e-12)
    assert d.bias_walk.value == pytest.approx(rrw / math.sqrt(fs), rel=1e-12)
    assert d.gauss_markov == ()
    with pytest.raises(ValueError, match="rate"):
        ds.gyro.discrete(-1.0)


def test_gauss_markov_terms_export_as_sigma_and_correlation_time(tmp_path: Path) -> None:
    # A white + first-order Gauss–Markov log (σ ≈ 0.063 deg/s, T = 20 s): the fitted GM term
    # goes into the JSON (σ and T with units), MATLAB's bias-instability filter
    # (1/(1 − φz⁻¹), φ = exp(−Δt/T), driven by σ√(1 − φ²)) and coeffs.discrete().
    fs, tc = 100.0, 20.0
    phi_true = math.exp(-1.0 / (fs * tc))
    rate = noise.simulate(400_000, fs, arw=0.01, ar1=(phi_true, 0.002), seed=3)
    c = noise.fit(allan.adev(rate, fs, units="deg/s"), terms=("N", "GM"))
    assert isinstance(c, NoiseCoefficients)
    gm = c.gauss_markov[0]
    assert gm.present and gm.correlation_time.value is not None and gm.sigma.value is not None
    sigma_si = math.radians(gm.sigma.value)
    tau_c = gm.correlation_time.value
    phi = math.exp(-1.0 / (fs * tau_c))

    c.export("json", tmp_path / "imu.json", rate=fs)
    doc = json.loads((tmp_path / "imu.json").read_text())
    (entry,) = doc["gauss_markov"]["gyro"]
    assert entry["sigma"]["value"] == pytest.approx(gm.sigma.value, rel=1e-12)
    assert entry["sigma"]["unit"] == "deg/s"
    assert entry["correlation_time"]["value"] == pytest.approx(tau_c, rel=1e-12)
    assert entry["correlation_time"]["unit"] == "s"

    c.export("matlab", tmp_path / "imu.m", rate=fs)
    text = (tmp_path / "imu.m").read_text()
    denominator = re.search(r"'Denominator', \[1 (-[0-9.eE+-]+)\]", text)
    instability = re.search(r"'BiasInstability', ([0-9.eE+-]+)", text)
    assert denominator is not None and instability is not None
    assert -float(denominator.group(1)) == pytest.approx(phi, rel=1e-9)
    assert float(instability.group(1)) == pytest.approx(sigma_si * math.sqrt(1 - phi**2), rel=1e-6)

    d = c.discrete(fs)
    (phi_d, drive) = d.gauss_markov[0]
    assert phi_d.value == pytest.approx(phi, rel=1e-12)
    assert drive.value == pytest.approx(gm.sigma.value * math.sqrt(1 - phi**2), rel=1e-12)
    # And the fit found the simulated process: T within 3σ of 20 s.
    assert gm.correlation_time.uncertainty is not None
    assert abs(tau_c - tc) < 3 * gm.correlation_time.uncertainty


@given(
    st.floats(0.0, 10.0),
    st.floats(0.0, 1.0),
    st.floats(1e-3, 1e6),
    st.floats(0.0, 1.0),
    st.floats(1.0, 1e4),
)
def test_discretisation_formulas_against_numpy(
    sigma: float, u_sigma: float, tau: float, u_tau_rel: float, rate: float
) -> None:
    """The core's discretisation (``gyrocore::noise::discrete``) against the formulas in NumPy:
    white ``N·√f``, walk ``K/√f``, ``φ = e^{−Δt/τ}``, ``u(φ) = φΔt·u(τ)/τ²``, drive
    ``σ√(1 − φ²)`` (the core uses ``−expm1(−2Δt/τ)``: 1e-12 where the direct form is still
    accurate, i.e. Δt/τ ≥ 1e-4)."""
    from gyrobias import _core

    dt = 1.0 / rate
    u_tau = u_tau_rel * tau
    assert _core.noise.discrete_white(sigma, u_sigma, rate) == pytest.approx(
        (sigma * np.sqrt(rate), u_sigma * np.sqrt(rate)), rel=1e-14, abs=1e-300
    )
    assert _core.noise.discrete_random_walk(sigma, None, rate) == (
        pytest.approx(sigma / np.sqrt(rate), rel=1e-14, abs=1e-300),
        None,
    )
    (phi, u_phi), (drive, u_drive) = _core.noise.discrete_gauss_markov(
        sigma, u_sigma, tau, u_tau, rate
    )
    assert phi == pytest.approx(np.exp(-dt / tau), rel=1e-15)
    assert u_phi == pytest.approx(phi * dt * u_tau / tau**2, rel=1e-14, abs=1e-300)
    exact = np.sqrt(-np.expm1(-2.0 * dt / tau))
    assert drive == pytest.approx(sigma * exact, rel=1e-14, abs=1e-300)
    assert u_drive == pytest.approx(u_sigma * exact, rel=1e-14, abs=1e-300)
    if dt / tau >= 1e-4:
        assert drive == pytest.approx(sigma * np.sqrt(1.0 - phi * phi), rel=1e-11, abs=1e-300)
