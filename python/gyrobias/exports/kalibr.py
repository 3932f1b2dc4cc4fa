"""Kalibr ``imu.yaml`` files from noise coefficients: the keyword form of the one exports writer
(:func:`gyrobias.exports.export` with ``fmt="kalibr"``)."""

from __future__ import annotations

import os
from collections.abc import Sequence

from gyrobias import _generics
from gyrobias._validation import positive_float, sequence
from gyrobias.exports.formats import export
from gyrobias.noise._types import NoiseCoefficients


def write_kalibr(
    path: str | os.PathLike[str],
    *,
    gyro: Sequence[NoiseCoefficients] = (),
    accel: Sequence[NoiseCoefficients] = (),
    update_rate: float | None = None,
    rostopic: str = "/imu0",
    strict: bool = False,
) -> str:
    """Write a Kalibr ``imu.yaml`` and return its text: ``export(gyro, "kalibr", path, ...)``.

    One Kalibr writer: this function is the keyword form of
    :func:`gyrobias.exports.export` with ``fmt="kalibr"`` (the same code, the same numbers as
    ``gyrobias allan LOG --fit --export kalibr=PATH`` and the HTML report).

    Parameters
    ----------
    path : path-like
        Output file (written atomically).
    gyro, accel : sequence of NoiseCoefficients
        Per-axis coefficients of the gyroscopes (rate unit deg/s, rad/s, …) and
        accelerometers (m/s², g, …). Each value is the largest over the axes given.
    update_rate : float, optional
        IMU rate in Hz (Kalibr discretises with it); default: the data's sample rate.
    rostopic : str
        Kalibr's ``rostopic`` entry.
    strict : bool
        Refuse a noise density or random walk the data only bound from above (default: write
        the bound, marked ``UPPER BOUND`` in the line's comment).

    Returns
    -------
    str
        The file's text.

    Notes
    -----
    Kalibr's parameters are continuous-time densities: ``gyroscope_noise_density`` = N in
    rad/s/√Hz, ``gyroscope_random_walk`` = K in rad/s²/√Hz, ``accelerometer_noise_density`` =
    N in m/s²/√Hz, ``accelerometer_random_walk`` = K in m/s³/√Hz. Kalibr discretises them as
    ``σ_d = σ·√update_rate`` (white noise) and ``σ_bd = σ_b/√update_rate`` (bias random walk).
    The keys of a sensor not given are written as comments saying so.
    """
    if update_rate is not None:
        update_rate = positive_float("update_rate", update_rate)
    gyro = sequence("gyro", gyro)
    accel = sequence("accel", accel)
    if not gyro and not accel:
        raise ValueError("gyro and accel: write_kalibr needs gyro and/or accel coefficients")
    return export(
        gyro or None,
        "kalibr",
        path,
        accel=accel or None,
        rate=update_rate,
        rostopic=rostopic,
        strict=strict,
    )


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
