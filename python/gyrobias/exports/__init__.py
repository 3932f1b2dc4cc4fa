"""Estimator parameter files from noise coefficients, and their discrete-time equivalents.

Every estimator wants the same four numbers — white-noise and bias-random-walk strength of the
gyroscope and of the accelerometer — under different names, units and time conventions:

==========  =====================================  ==========================  ===========
format      keys (gyro / accel)                    unit                        time
==========  =====================================  ==========================  ===========
kalibr      gyroscope_noise_density = N            rad/s/√Hz                   continuous
            gyroscope_random_walk = K              rad/s²/√Hz                  continuous
            accelerometer_noise_density = N        m/s²/√Hz                    continuous
            accelerometer_random_walk = K          m/s³/√Hz                    continuous
openvins    same keys under ``imu0:`` (kalibr_imu_chain.yaml, ``model: "kalibr"``)
vins        gyr_n = N·√f, gyr_w = K/√f            rad/s, rad/s                discrete
            acc_n = N·√f, acc_w = K/√f            m/s², m/s²                  discrete
orbslam3    IMU.NoiseGyro = N, IMU.GyroWalk = K    rad/s/√Hz, rad/s²/√Hz       continuous
            IMU.NoiseAcc = N, IMU.AccWalk = K      m/s²/√Hz, m/s³/√Hz          continuous
liosam      imuGyrNoise = N, imuGyrBiasN = K       rad/s/√Hz, rad/s²/√Hz       continuous
            imuAccNoise = N, imuAccBiasN = K       m/s²/√Hz, m/s³/√Hz          continuous
matlab      gyroparams NoiseDensity = N,           (rad/s)/√Hz, rad/s,         continuous
            BiasInstability = B, RandomWalk = K    (rad/s)·√Hz
            accelparams: the same in m/s²
json        every coefficient with uncertainty, unit and conventions
==========  =====================================  ==========================  ===========

``N`` and ``K`` are the IEEE-952 coefficients (two-sided densities: white rate noise of
per-sample standard deviation σ_w at rate f has ``N = σ_w/√f``), ``B`` the bias instability and
``f`` the IMU rate in Hz. Several axes: each value is the largest over the axes (the
conservative choice for a filter that uses one value for all three).

Discretisation (:func:`discrete`) at period ``Δt = 1/f``::

    σ_white = N/√Δt            per-sample standard deviation of the white rate noise
    σ_walk  = K·√Δt            standard deviation of one step of the bias random walk
    φ = exp(−Δt/τ_c),  σ_drive = σ_GM·√(1 − φ²)   first-order Gauss–Markov bias

References
----------
Kalibr wiki, "IMU Noise Model" (ethz-asl/kalibr); OpenVINS ``config/*/kalibr_imu_chain.yaml``;
VINS-Mono/Fusion ``config/*.yaml`` and HKUST-Aerial-Robotics/VINS-Mono issue #280 (discrete
values: divide densities by √Δt, multiply random walks by √Δt); ORB-SLAM3 ``Examples/*/*.yaml``
and ``Tracking.cc`` (continuous densities, discretised with √Frequency); LIO-SAM
``config/params.yaml`` and ``imuPreintegration.cpp`` (GTSAM continuous-time covariances);
MathWorks ``gyroparams``/``accelparams``/``imuSensor`` documentation and the example "Inertial
Sensor Noise Analysis Using Allan Variance" (N, K and B from the Allan deviation entered
directly).
"""

from __future__ import annotations

import os
from typing import Any

from gyrobias import _generics
from gyrobias._files import atomic_binary as atomic_binary
from gyrobias._files import atomic_write
from gyrobias.conservative import ConservativeCoefficients
from gyrobias.datasheet import Datasheet
from gyrobias.exports._types import DiscreteNoise, DiscreteValue
from gyrobias.exports.discretisation import discrete
from gyrobias.exports.formats import DEFAULT_FILENAMES, FORMATS, export, export_all
from gyrobias.exports.kalibr import write_kalibr
from gyrobias.noise._types import NoiseCoefficients

__all__ = [
    # estimator files
    "DEFAULT_FILENAMES",
    "FORMATS",
    "export",
    "export_all",
    "write_kalibr",
    # discrete-time parameters
    "DiscreteNoise",
    "DiscreteValue",
    "discrete",
    # atomic output (gyrobias._files)
    "atomic_write",
]

# --- the result objects' methods -----------------------------------------------------------------
# ``.export()``, ``.export_all()`` and ``.discrete()`` of the coefficient types delegate to the
# generic functions of gyrobias._generics; this module owns the behaviour and registers it.


@_generics.export.register(NoiseCoefficients)
def _export_coefficients(
    coefficients: NoiseCoefficients,
    fmt: str,
    path: str | os.PathLike[str] | None = None,
    **kwargs: Any,
) -> str:
    return export(coefficients, fmt, path, **kwargs)


@_generics.export.register(ConservativeCoefficients)
def _export_conservative(
    conservative: ConservativeCoefficients,
    fmt: str,
    path: str | os.PathLike[str] | None = None,
    **kwargs: Any,
) -> str:
    return export(conservative.coefficients, fmt, path, **kwargs)


@_generics.export.register(Datasheet)
def _export_datasheet(
    sheet: Datasheet,
    fmt: str,
    path: str | os.PathLike[str] | None = None,
    *,
    rate: float | None = None,
    rostopic: str = "/imu0",
) -> str:
    return export(
        sheet.gyro,
        fmt,
        path,
        accel=sheet.accel,
        rate=rate if rate is not None else sheet.rate,
        rostopic=rostopic,
    )


@_generics.export_all.register(Datasheet)
def _export_all_datasheet(
    sheet: Datasheet,
    directory: str | os.PathLike[str] | None = None,
    *,
    rate: float | None = None,
    rostopic: str = "/imu0",
) -> dict[str, str]:
    return export_all(
        sheet.gyro,
        directory,
        accel=sheet.accel,
        rate=rate if rate is not None else sheet.rate,
        rostopic=rostopic,
    )


_generics.discrete.register(NoiseCoefficients, discrete)


@_generics.discrete.register(Datasheet)
def _discrete_datasheet(sheet: Datasheet, rate: float | None = None) -> dict[str, DiscreteNoise]:
    use = rate if rate is not None else sheet.rate
    if use is None:
        raise ValueError("rate: give the filter rate in Hz (the datasheet set has none)")
    return {
        k: discrete(c, use)
        for k, c in (("gyro", sheet.gyro), ("accel", sheet.accel))
        if c is not None
    }
