"""Noise coefficients from a datasheet, with the conventions stated and converted.

Datasheets quote the same physics in several conventions; :func:`from_datasheet` turns them into
IEEE-952 coefficients (:class:`gyrobias.noise.NoiseCoefficients`) so that every export works from
a datasheet as well as from a measurement:

* **Angle / velocity random walk** in ``deg/√h`` (or ``m/s/√h``) is the IEEE coefficient ``N``:
  the Allan deviation of the white noise at τ = 1 s. Taken as is.
* **Noise density** in ``…/√Hz`` (``deg/s/√Hz``, ``µg/√Hz``) is a *one-sided* PSD amplitude on
  almost every MEMS datasheet: ``N = nd/√2`` (SPEC §1; ADIS16470: 0.008 °/s/√Hz ↔ 0.34 °/√h).
  Any value given per √Hz — for ``arw``/``vrw``/random walks too — is a density and converted
  this way unless ``density="two-sided"`` (Kalibr's convention, where the density *is* ``N``).
* **In-run bias stability / bias instability** is the *minimum of the Allan deviation* on
  datasheets (ADI, Bosch, TDK): ``B = σ_min/0.664282`` (IEEE 952's flicker plateau). Use
  ``bias_instability_is="coefficient"`` when the value already is the IEEE ``B``.
* **Rate random walk** ``K`` in ``deg/h^1.5`` (= ``deg/h/√h``) or ``rad/s²/√Hz`` (a density:
  converted as above), quantisation ``Q`` and rate ramp ``R`` are taken as given.

Values are strings with a unit (``"0.3 deg/sqrt(h)"``, ``"5 °/h"``, ``"60 ug/√Hz"``,
``"0.015 dps/√Hz"``) or numbers with ``units=`` (a mapping from the argument name to its unit,
or ``"ieee"``/``"si"`` for the customary units of :data:`gyrobias.units.CUSTOMARY`). The unit
grammar is :mod:`gyrobias.units`'.
"""

from __future__ import annotations

import math
import os
import re
from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from gyrobias import _core, _generics
from gyrobias._validation import choice, optional_text, real, string
from gyrobias.noise._types import TERM_NAMES, NoiseCoefficients, Term
from gyrobias.units import CUSTOMARY, _parse_unit, base_unit, sensor_kind

if TYPE_CHECKING:
    from gyrobias.exports import DiscreteNoise

__all__ = ["Datasheet", "from_datasheet"]

#: Argument → (sensor, IEEE symbol, is a density by definition).
_PARAMETERS: dict[str, tuple[str, str, bool]] = {
    "quantization": ("gyro", "Q", False),
    "arw": ("gyro", "N", False),
    "noise_density": ("gyro", "N", True),
    "bias_instability": ("gyro", "B", False),
    "rrw": ("gyro", "K", False),
    "rate_ramp": ("gyro", "R", False),
    "accel_quantization": ("accel", "Q", False),
    "vrw": ("accel", "N", False),
    "accel_noise_density": ("accel", "N", True),
    "accel_bias_instability": ("accel", "B", False),
    "accel_random_walk": ("accel", "K", False),
    "accel_ramp": ("accel", "R", False),
}

#: Units a user is likely to have, per sensor and symbol (for error messages).
_EXAMPLES: dict[str, dict[str, str]] = {
    "gyro": {
        "Q": "deg, rad, arcsec",
        "N": "deg/√h, deg/s/√Hz, rad/s/√Hz, rad/√s",
        "B": "deg/h, deg/s, rad/s",
        "K": "deg/h^1.5, deg/h/√h, rad/s²/√Hz",
        "R": "deg/h², rad/s²",
    },
    "accel": {
        "Q": "m/s",
        "N": "m/s/√h, m/s²/√Hz, mg/√Hz, ug/√Hz",
        "B": "mg, ug, m/s²",
        "K": "m/s/h^1.5, m/s³/√Hz, ug/√s",
        "R": "m/s/h², m/s³",
    },
}

_WHAT = {
    "Q": "quantization (angle or velocity)",
    "N": "white-noise coefficient (rate/√time or density per √Hz)",
    "B": "bias (a rate for a gyro, an acceleration for an accelerometer)",
    "K": "random-walk coefficient (rate per √time)",
    "R": "ramp (rate per time)",
}

_NUMBER = re.compile(r"^\s*([+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)\s*(.*?)\s*$")


@dataclass(frozen=True)
class Datasheet:
    """Gyroscope and accelerometer coefficients read from a datasheet.

    Attributes
    ----------
    gyro, accel : NoiseCoefficients or None
        Coefficients (``method="datasheet"``, no uncertainties) in the base units of
        ``gyro_unit``/``accel_unit``; terms not given are missing with that reason.
    rate : float or None
        IMU rate in Hz, if given (used by exports that need it).
    conventions : tuple of str
        Every interpretation and conversion applied, in words.
    """

    gyro: NoiseCoefficients | None
    accel: NoiseCoefficients | None
    rate: float | None
    conventions: tuple[str, ...]

    def export(
        self,
        fmt: str,
        path: str | os.PathLike[str] | None = None,
        *,
        rate: float | None = None,
        rostopic: str = "/imu0",
    ) -> str:
        """Write one estimator file (see :func:`gyrobias.exports.export`)."""
        return _generics.export(self, fmt, path, rate=rate, rostopic=rostopic)

    def export_all(
        self,
        directory: str | os.PathLike[str] | None = None,
        *,
        rate: float | None = None,
        rostopic: str = "/imu0",
    ) -> dict[str, str]:
        """Every format at once (see :func:`gyrobias.exports.export_all`)."""
        return _generics.export_all(self, directory, rate=rate, rostopic=rostopic)

    def discrete(self, rate: float | None = None) -> dict[str, DiscreteNoise]:
        """Per-sample parameters of each sensor at ``rate`` (see :func:`gyrobias.exports.discrete`)."""
        return _generics.discrete(self, rate)  # type: ignore[no-any-return]

    def summary(self) -> str:
        """Coefficients in IEEE units and the conventions applied."""
        parts = [c.to("ieee").summary() for c in (self.gyro, self.accel) if c is not None]
        parts.append("Conventions:\n" + "\n".join(f"  - {c}" for c in self.conventions))
        return "\n\n".join(parts)

    def __str__(self) -> str:
        return self.summary()


def _split_value(
    name: str, value: Any, units: str | Mapping[str, str] | None, sensor: str, symbol: str
) -> tuple[float, str]:
    """(number, unit text) of one argument."""
    if isinstance(value, str):
        m = _NUMBER.match(value)
        if m is None or not m.group(2):
            raise ValueError(
                f"{name}: {value!r} is not a number followed by a unit, e.g. "
                f"'0.3 deg/sqrt(h)'; valid units for {name}: {_EXAMPLES[sensor][symbol]}"
            )
        if isinstance(units, Mapping) and name in units:
            raise ValueError(
                f"{name}: the unit is given twice (in {value!r} and in units=); give it once"
            )
        number, unit = float(m.group(1)), m.group(2)
    elif isinstance(value, bool) or not isinstance(value, (int, float)):
        raise TypeError(
            f"{name} must be a string with a unit or a number with units=, got {type(value).__name__}"
        )
    else:
        number = real(name, value)
        if isinstance(units, Mapping):
            if name not in units:
                raise ValueError(
                    f"{name}: a bare number needs its unit, e.g. units={{{name!r}: ...}}; valid units "
                    f"for {name}: {_EXAMPLES[sensor][symbol]}"
                )
            unit = units[name]
        elif units is None:
            raise ValueError(
                f"{name}: a bare number needs its unit: write it as a string ('{number:g} <unit>') or pass "
                f"units= (a mapping or 'ieee'/'si'); valid units for {name}: {_EXAMPLES[sensor][symbol]}"
            )
        else:
            system = choice("units", units, ("ieee", "si"))
            unit = CUSTOMARY[sensor][system][symbol]
    unit = re.sub(r"\bdps\b", "deg/s", unit.strip())
    return number, unit


#: How each conversion of the core (``gyrocore::noise::discrete::datasheet_coefficient``) is
#: worded in ``Datasheet.conventions`` (``{}``: the term's symbol).
_CONVENTION_NOTES = {
    "one-sided density": "read as a one-sided density: IEEE {} = value/√2",
    "two-sided density": "read as a two-sided density: IEEE {} = value",
    "allan minimum": "read as the Allan-deviation minimum: IEEE {} = value/0.664282",
    "coefficient": "taken as the IEEE coefficient {}",
}


def from_datasheet(
    *,
    arw: str | float | None = None,
    bias_instability: str | float | None = None,
    rrw: str | float | None = None,
    quantization: str | float | None = None,
    rate_ramp: str | float | None = None,
    noise_density: str | float | None = None,
    vrw: str | float | None = None,
    accel_bias_instability: str | float | None = None,
    accel_random_walk: str | float | None = None,
    accel_quantization: str | float | None = None,
    accel_ramp: str | float | None = None,
    accel_noise_density: str | float | None = None,
    rate: float | None = None,
    units: str | Mapping[str, str] | None = None,
    density: str = "one-sided",
    bias_instability_is: str = "allan_minimum",
    gyro_unit: str = "rad/s",
    accel_unit: str = "m/s^2",
    axis: str | None = None,
) -> Datasheet:
    """IEEE-952 coefficients of a gyroscope and/or accelerometer from datasheet values.

    Parameters
    ----------
    arw, noise_density : str or float, optional
        Gyro angle random walk (``"0.3 deg/sqrt(h)"``) or rate noise density
        (``"0.008 deg/s/sqrt(Hz)"``, one-sided by default). Give one of them.
    bias_instability : str or float, optional
        Gyro in-run bias stability (``"5 deg/h"``); see ``bias_instability_is``.
    rrw, quantization, rate_ramp : str or float, optional
        Gyro rate random walk K, quantisation Q, rate ramp R.
    vrw, accel_noise_density : str or float, optional
        Accelerometer velocity random walk (``"0.05 m/s/sqrt(h)"``) or noise density
        (``"60 ug/sqrt(Hz)"``). Give one of them.
    accel_bias_instability : str or float, optional
        Accelerometer in-run bias stability (``"0.05 mg"``).
    accel_random_walk, accel_quantization, accel_ramp : str or float, optional
        Accelerometer K, Q and R.
    rate : float, optional
        IMU output rate in Hz (for the exports that need it).
    units : mapping or {"ieee", "si"}, optional
        Units of arguments given as bare numbers: ``{"arw": "deg/√h", ...}`` or a system of
        customary units (:data:`gyrobias.units.CUSTOMARY`).
    density : {"one-sided", "two-sided"}
        Convention of values given per √Hz. One-sided (datasheets): ``N = nd/√2``; two-sided
        (Kalibr): ``N = nd``.
    bias_instability_is : {"allan_minimum", "coefficient"}
        ``"allan_minimum"`` (datasheets): the value is the Allan-deviation minimum and
        ``B = value/0.664282``; ``"coefficient"``: the value is the IEEE ``B``.
    gyro_unit, accel_unit : str
        Rate units of the resulting coefficients' data (their base units follow from them).
    axis : str, optional
        Axis name to record.

    Returns
    -------
    Datasheet
        ``.gyro``/``.accel`` coefficients, ``.conventions`` (the conversions applied) and
        ``.export``/``.export_all``/``.discrete``.

    Raises
    ------
    ValueError
        No value given; unknown unit (the message lists valid ones); a unit of the wrong kind
        for its argument (e.g. ``bias_instability="5 deg"``, which is not a rate — the message
        names the argument); a bare number without ``units``; both ``arw`` and
        ``noise_density`` (or ``vrw`` and ``accel_noise_density``); unknown conventions.

    Examples
    --------
    ADIS16470: noise density 0.008 °/s/√Hz (one-sided) is an ARW of 0.34 °/√h:

    >>> import gyrobias
    >>> ds = gyrobias.noise.from_datasheet(noise_density="0.008 deg/s/sqrt(Hz)", bias_instability="8 deg/h")
    >>> g = ds.gyro.to("ieee")
    >>> round(g.N.value, 3), g.N.unit, round(g.B.value, 2)
    (0.339, 'deg/√h', 12.04)
    """
    optional_text("axis", axis)  # written into estimator files and reports
    density = string("density", density)  # the names are parsed by the core
    bias_instability_is = string("bias_instability_is", bias_instability_is)
    data_units = {"gyro": gyro_unit, "accel": accel_unit}
    for label, unit, kind in (
        ("gyro_unit", gyro_unit, "gyro"),
        ("accel_unit", accel_unit, "accel"),
    ):
        try:
            found = sensor_kind(unit)
        except ValueError as exc:
            raise ValueError(f"{label}: {exc}") from None
        except TypeError:
            raise TypeError(f"{label} must be a unit string, got {type(unit).__name__}") from None
        if found != kind:
            raise ValueError(
                f"{label}: {unit!r} is not {'an angular rate' if kind == 'gyro' else 'an acceleration'}"
            )
    if rate is not None:
        rate = _core.noise.discrete_rate(real("rate", rate))  # finite and > 0: the core's check
    if isinstance(units, Mapping):
        for key in units:
            choice("units key", key, tuple(_PARAMETERS))
    elif units is not None:
        choice("units", units, ("ieee", "si"))
    given = {
        "quantization": quantization,
        "arw": arw,
        "noise_density": noise_density,
        "bias_instability": bias_instability,
        "rrw": rrw,
        "rate_ramp": rate_ramp,
        "accel_quantization": accel_quantization,
        "vrw": vrw,
        "accel_noise_density": accel_noise_density,
        "accel_bias_instability": accel_bias_instability,
        "accel_random_walk": accel_random_walk,
        "accel_ramp": accel_ramp,
    }
    for a, b in (("arw", "noise_density"), ("vrw", "accel_noise_density")):
        if given[a] is not None and given[b] is not None:
            raise ValueError(f"{a} and {b} describe the same term (N): give one of them")
    if all(v is None for v in given.values()):
        raise ValueError(
            "from_datasheet needs at least one value (arw=, bias_instability=, vrw=, …)"
        )
    values: dict[str, dict[str, float]] = {"gyro": {}, "accel": {}}
    notes: list[str] = []
    for name, value in given.items():
        if value is None:
            continue
        sensor, symbol, is_density = _PARAMETERS[name]
        number, unit = _split_value(name, value, units, sensor, symbol)
        target = base_unit(data_units[sensor], symbol)
        try:
            parsed = _parse_unit(unit)
        except ValueError as exc:
            raise ValueError(
                f"{name}: {exc}; valid units for {name}: {_EXAMPLES[sensor][symbol]}"
            ) from None
        want = _parse_unit(target)
        if parsed.dims != want.dims:
            raise ValueError(
                f"{name}: unit {unit!r} is not a {sensor} {_WHAT[symbol]}; valid units for {name}: "
                f"{_EXAMPLES[sensor][symbol]}"
            )
        per_hz = "Hz" in re.findall(r"[A-Za-zµ°]+", unit)
        # The unit factor is a unit conversion (here); the density and Allan-minimum
        # conventions and the value's range (finite, >= 0) are the core's.
        try:
            v, conversion = _core.noise.datasheet_coefficient(
                number,
                parsed.factor / want.factor,
                symbol,
                is_density or per_hz,
                density,
                bias_instability_is,
            )
        except ValueError as exc:
            raise ValueError(f"{name}: {exc}") from None
        notes.append(f"{name} = {number:g} {unit} " + _CONVENTION_NOTES[conversion].format(symbol))
        values[sensor][symbol] = v

    def build(sensor: str) -> NoiseCoefficients | None:
        if not values[sensor]:
            return None
        unit = data_units[sensor]
        terms = {}
        for s in ("Q", "N", "B", "K", "R"):
            v = values[sensor].get(s)
            terms[s] = Term(
                symbol=s,
                name=TERM_NAMES[sensor][s],
                value=v,
                uncertainty=None,
                unit=base_unit(unit, s),
                missing=None if v is not None else "not given in the datasheet",
            )
        return NoiseCoefficients(
            Q=terms["Q"],
            N=terms["N"],
            B=terms["B"],
            K=terms["K"],
            R=terms["R"],
            method="datasheet",
            data_unit=unit,
            sensor=sensor,
            fs=rate if rate is not None else math.nan,
            tau_range=(math.nan, math.nan),
            edf_source="datasheet",
            axis=axis,
        )

    return Datasheet(gyro=build("gyro"), accel=build("accel"), rate=rate, conventions=tuple(notes))
