"""Datasheet values in: unit parsing, one-/two-sided densities, bias-instability convention."""

from __future__ import annotations

import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import gyrobias
from gyrobias.units import conversion_factor

FLICKER = math.sqrt(2 * math.log(2) / math.pi)


def test_adis16470_noise_density_is_its_arw() -> None:
    # ADIS16470 datasheet: rate noise density 0.008 °/s/√Hz and ARW 0.34 °/√h — the same
    # noise, one-sided density vs IEEE coefficient: N = nd/√2, ×60 for deg/√h.
    ds = gyrobias.noise.from_datasheet(
        noise_density="0.008 deg/s/sqrt(Hz)", bias_instability="8 deg/h"
    )
    assert ds.gyro is not None and ds.accel is None
    g = ds.gyro.to("ieee")
    assert g.N.value == pytest.approx(0.008 / math.sqrt(2) * 60, rel=1e-12)
    assert round(g.N.value, 2) == 0.34
    assert g.B.value == pytest.approx(8 / FLICKER, rel=1e-12)  # Allan minimum → IEEE B
    assert any("one-sided" in c for c in ds.conventions)
    assert ds.gyro.method == "datasheet" and ds.gyro.N.uncertainty is None
    assert not ds.gyro.K.present and "datasheet" in (ds.gyro.K.missing or "")


def test_conventions_can_be_switched() -> None:
    a = gyrobias.noise.from_datasheet(arw="1e-4 rad/s/sqrt(Hz)", density="two-sided")
    b = gyrobias.noise.from_datasheet(arw="1e-4 rad/s/sqrt(Hz)")
    assert a.gyro is not None and b.gyro is not None
    assert a.gyro.N.value == pytest.approx(1e-4)
    assert b.gyro.N.value == pytest.approx(1e-4 / math.sqrt(2))
    c = gyrobias.noise.from_datasheet(bias_instability="5 deg/h", bias_instability_is="coefficient")
    assert c.gyro is not None
    assert c.gyro.to("ieee").B.value == pytest.approx(5.0)
    # per-√h values are IEEE coefficients whatever the density convention
    d = gyrobias.noise.from_datasheet(arw="0.3 deg/√h", density="one-sided", gyro_unit="deg/s")
    assert d.gyro is not None
    assert d.gyro.N.value == pytest.approx(0.3 / 60)


def test_accelerometer_and_units_forms() -> None:
    ds = gyrobias.noise.from_datasheet(
        vrw=0.05,
        accel_bias_instability=0.05,
        units={"vrw": "m/s/sqrt(h)", "accel_bias_instability": "mg"},
    )
    assert ds.accel is not None and ds.gyro is None
    assert ds.accel.N.value == pytest.approx(0.05 / 60)
    assert ds.accel.B.value == pytest.approx(0.05e-3 * 9.80665 / FLICKER)
    dens = gyrobias.noise.from_datasheet(accel_noise_density="60 ug/√Hz")
    assert dens.accel is not None
    assert dens.accel.N.value == pytest.approx(60e-6 * 9.80665 / math.sqrt(2))
    ieee = gyrobias.noise.from_datasheet(
        arw=0.2, bias_instability=3.0, rrw=10.0, units="ieee", gyro_unit="deg/s"
    )
    assert ieee.gyro is not None
    assert ieee.gyro.to("ieee").K.value == pytest.approx(10.0)
    dps = gyrobias.noise.from_datasheet(noise_density="0.015 dps/√Hz", gyro_unit="deg/s")
    assert dps.gyro is not None
    assert dps.gyro.N.value == pytest.approx(0.015 / math.sqrt(2))


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"bias_instability": "5 deg"}, "bias_instability: unit 'deg' is not a gyro bias"),
        ({"arw": "0.3 m/s/sqrt(h)"}, "arw: unit .* is not a gyro"),
        ({"vrw": "0.3 deg/sqrt(h)"}, "vrw: unit .* is not a accel"),
        ({"arw": "0.3 furlong/sqrt(h)"}, "arw: unknown unit .*valid symbols"),
        ({"arw": 0.3}, "arw: a bare number needs its unit"),
        ({"arw": 0.3, "units": {"rrw": "deg/h^1.5"}}, "arw: a bare number needs its unit"),
        ({"arw": "0.3 deg/√h", "units": {"arw": "deg/√h"}}, "given twice"),
        ({"arw": "fast"}, "arw: 'fast' is not a number"),
        ({"arw": "-1 deg/√h"}, "arw: .*must be finite and >= 0, got -1"),
        ({"arw": "0.3 deg/√h", "noise_density": "0.01 deg/s/√Hz"}, "give one of them"),
        ({}, "at least one value"),
        ({"arw": "0.3 deg/√h", "gyro_unit": "m/s^2"}, "gyro_unit"),
        ({"arw": "0.3 deg/√h", "density": "single"}, "density must be one of"),
        ({"arw": "0.3 deg/√h", "units": {"speed": "m/s"}}, "units key"),
        ({"arw": "0.3 deg/√h", "rate": -5.0}, "rate must be finite and > 0"),
    ],
)
def test_bad_input_names_the_argument(kwargs: dict, match: str) -> None:
    with pytest.raises(ValueError, match=match):
        gyrobias.noise.from_datasheet(**kwargs)


def test_bad_type() -> None:
    with pytest.raises(TypeError, match="arw must be a string"):
        gyrobias.noise.from_datasheet(arw=[0.3])  # type: ignore[arg-type]


UNITS = {
    "arw": ["deg/√h", "deg/sqrt(s)", "rad/√s", "arcsec/√s"],
    "bias_instability": ["deg/h", "deg/s", "rad/s", "arcsec/h"],
    "rrw": ["deg/h^1.5", "deg/h/sqrt(h)", "rad/s^1.5"],
    "vrw": ["m/s/√h", "m/s^1.5", "mg·√s"],
    "accel_random_walk": ["m/s/h^1.5", "m/s^2.5", "ug/√s"],
}


@settings(derandomize=True, max_examples=60, deadline=None)
@given(st.sampled_from(sorted(UNITS)), st.data(), st.floats(1e-6, 1e6))
def test_value_round_trips_through_any_unit(name: str, data: st.DataObject, value: float) -> None:
    unit = data.draw(st.sampled_from(UNITS[name]))
    ds = gyrobias.noise.from_datasheet(
        **{name: f"{value!r} {unit}"}, bias_instability_is="coefficient"
    )
    coeffs = ds.gyro if ds.gyro is not None else ds.accel
    assert coeffs is not None
    symbol = {
        "arw": "N",
        "vrw": "N",
        "bias_instability": "B",
        "rrw": "K",
        "accel_random_walk": "K",
    }[name]
    term = coeffs[symbol]
    # Independent path: the generic unit conversion of gyrobias.units.
    assert term.value == pytest.approx(value * conversion_factor(unit, term.unit or ""), rel=1e-12)
    assert term.to(unit).value == pytest.approx(value, rel=1e-12)


def test_summary_and_discrete() -> None:
    ds = gyrobias.noise.from_datasheet(
        arw="0.6 deg/√h", rrw="6 deg/h^1.5", vrw="0.06 m/s/√h", rate=100
    )
    text = ds.summary()
    assert "Conventions" in text and "ARW" in text
    d = ds.discrete()
    assert set(d) == {"gyro", "accel"}
    assert d["gyro"].white.value == pytest.approx(math.radians(0.01) * 10)
    with pytest.raises(ValueError, match="rate"):
        gyrobias.noise.from_datasheet(arw="0.6 deg/√h").discrete()
