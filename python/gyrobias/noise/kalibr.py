"""Kalibr ``imu.yaml`` files from noise coefficients."""

from __future__ import annotations

import os
from collections.abc import Sequence

from gyrobias import _files, _generics
from gyrobias._validation import (
    positive_float,
)
from gyrobias.noise._types import NoiseCoefficients


def _worst(
    coefficients: Sequence[NoiseCoefficients], symbol: str, unit: str
) -> tuple[float | None, str]:
    """Largest value over axes (the conservative choice for a filter) and a comment."""
    values = []
    missing = []
    for c in coefficients:
        t = c[symbol]
        if t.value is None:
            missing.append(f"{c.axis or '?'}: {t.missing}")
        else:
            values.append((t.to(unit).value, c.axis))
    if not values:
        return None, "; ".join(missing)
    best = max(values, key=lambda v: float(v[0] or 0.0))
    axes = ", ".join(str(c.axis) for c in coefficients if c.axis) or f"{len(coefficients)} axis(es)"
    return best[0], f"max over {axes}"


def write_kalibr(
    path: str | os.PathLike[str],
    *,
    gyro: Sequence[NoiseCoefficients] = (),
    accel: Sequence[NoiseCoefficients] = (),
    update_rate: float | None = None,
    rostopic: str = "/imu0",
) -> str:
    """Write a Kalibr ``imu.yaml`` (no YAML library needed) and return its text.

    Parameters
    ----------
    path : path-like
        Output file.
    gyro, accel : sequence of NoiseCoefficients
        Per-axis coefficients of the gyroscopes (rate unit deg/s, rad/s, …) and
        accelerometers (m/s², g, …). Each value is the largest over the axes given.
    update_rate : float, optional
        IMU rate in Hz (Kalibr discretises with it); default: the data's sample rate.
    rostopic : str
        Kalibr's ``rostopic`` entry.

    Returns
    -------
    str
        The file's text.

    Notes
    -----
    Kalibr's parameters are continuous-time densities: ``gyroscope_noise_density`` = N in
    rad/s/√Hz, ``gyroscope_random_walk`` = K in rad/s²/√Hz, ``accelerometer_noise_density`` =
    N in m/s²/√Hz, ``accelerometer_random_walk`` = K in m/s³/√Hz. Kalibr discretises them as
    ``σ_d = σ·√update_rate`` (white noise) and ``σ_bd = σ_b/√update_rate`` (bias random walk). A
    term that could not be identified is written as a comment with the reason, so that Kalibr
    refuses the file rather than using a made-up number.
    """
    gyro = list(gyro)
    accel = list(accel)
    if not gyro and not accel:
        raise ValueError("write_kalibr needs gyro and/or accel coefficients")
    for name, group, kind in (("gyro", gyro, "gyro"), ("accel", accel, "accel")):
        for c in group:
            if not isinstance(c, NoiseCoefficients):
                raise TypeError(f"{name} must contain NoiseCoefficients, got {type(c).__name__}")
            if c.data_unit is None:
                raise ValueError(
                    f"{name}: the data unit is unknown; Kalibr needs SI units (pass units=)"
                )
            if c.sensor != kind:
                raise ValueError(
                    f"{name}: coefficients of data in {c.data_unit!r} are not {kind} data"
                )
    if update_rate is None:
        update_rate = max(c.fs for c in gyro + accel)
    update_rate = positive_float("update_rate", update_rate)
    lines = [
        "# Kalibr IMU noise model written by gyrobias",
        "# Continuous-time convention (Kalibr): noise densities are the white-noise coefficient N",
        "# (IEEE-952 ARW/VRW, two-sided PSD) and random walks the coefficient K (RRW);",
        "# Kalibr discretises them with update_rate: sigma_d = sigma*sqrt(rate), sigma_bd = sigma_b/sqrt(rate).",
        "# Units: gyroscope_noise_density rad/s/sqrt(Hz), gyroscope_random_walk rad/s^2/sqrt(Hz),",
        "#        accelerometer_noise_density m/s^2/sqrt(Hz), accelerometer_random_walk m/s^3/sqrt(Hz).",
        "# Each value is the largest over the axes analysed.",
    ]
    entries = (
        ("accelerometer", accel, "m/s²/√Hz", "m/s³/√Hz"),
        ("gyroscope", gyro, "rad/s/√Hz", "rad/s²/√Hz"),
    )
    for prefix, group, n_unit, k_unit in entries:
        if not group:
            continue
        lines.append(f"#{prefix.capitalize()}s")
        for key, symbol, unit in (("noise_density", "N", n_unit), ("random_walk", "K", k_unit)):
            value, note = _worst(group, symbol, unit)
            if value is None:
                lines.append(f"# {prefix}_{key}: not identified ({note})")
            else:
                lines.append(f"{prefix}_{key}: {value:.6e}  # {unit}, {note}")
    lines.append(f"rostopic: {rostopic}")
    lines.append(f"update_rate: {update_rate:.6g}  # Hz")
    text = "\n".join(lines) + "\n"
    _files.atomic_write(path, text)
    return text


@_generics.to_kalibr.register(NoiseCoefficients)
def _to_kalibr(
    coefficients: NoiseCoefficients,
    path: str | os.PathLike[str],
    *,
    update_rate: float | None = None,
    rostopic: str = "/imu0",
) -> str:
    """``NoiseCoefficients.to_kalibr``: one axis as the gyro or accel group."""
    if coefficients.sensor == "accel":
        return write_kalibr(path, accel=[coefficients], update_rate=update_rate, rostopic=rostopic)
    return write_kalibr(path, gyro=[coefficients], update_rate=update_rate, rostopic=rostopic)
