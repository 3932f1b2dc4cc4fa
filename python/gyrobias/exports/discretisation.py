"""Discrete-time (per-sample) noise parameters from continuous-time IEEE-952 coefficients,
with delta-method uncertainties: the formulas are the core's (``gyrocore::noise::discrete``);
this module picks the terms, converts units and builds the result."""

from __future__ import annotations

from typing import Any

from gyrobias import _core
from gyrobias._validation import real
from gyrobias.exports._types import DiscreteNoise, DiscreteValue
from gyrobias.noise._types import NoiseCoefficients

__all__ = ["discrete"]


def discrete(coefficients: NoiseCoefficients, rate: float) -> DiscreteNoise:
    """Discrete-time (per-sample) noise parameters at ``rate`` for a hand-written filter.

    Parameters
    ----------
    coefficients : NoiseCoefficients
        Coefficients with a known data unit.
    rate : float
        Filter rate in Hz; ``Δt = 1/rate``.

    Returns
    -------
    DiscreteNoise
        Values in the data unit of ``coefficients`` (e.g. deg/s or m/s²).

    Raises
    ------
    ValueError
        ``rate`` not finite and positive, unknown data unit.

    Notes
    -----
    White rate noise with IEEE coefficient N (two-sided PSD ``N²``) averaged over Δt has
    variance ``N²/Δt``: ``σ_white = N/√Δt = N·√rate`` (Kalibr's ``σ_d``; SPEC §1).
    Rate random walk ``ḃ = w``, ``E[w(t)w(s)] = K²δ(t−s)``, over one step:
    ``σ_walk = K·√Δt`` (Kalibr's ``σ_bd``). A first-order Gauss–Markov bias with stationary
    standard deviation σ and correlation time τ_c, sampled exactly:
    ``b_{k+1} = φ b_k + w_k``, ``φ = exp(−Δt/τ_c)``, ``std(w) = σ√(1 − φ²)``.
    Uncertainties scale linearly (φ's by the delta method, ``u(φ) = φ·Δt·u(τ_c)/τ_c²``).
    Bias instability (flicker noise) has no finite-state exact discretisation and is not
    converted.

    Examples
    --------
    >>> import gyrobias
    >>> ds = gyrobias.noise.from_datasheet(arw="0.6 deg/sqrt(h)", rrw="6 deg/h^1.5", gyro_unit="deg/s")
    >>> d = ds.gyro.discrete(100.0)
    >>> round(d.white.value, 6), d.white.unit
    (0.1, 'deg/s')
    """
    if not isinstance(coefficients, NoiseCoefficients):
        raise TypeError(
            f"coefficients must be NoiseCoefficients, got {type(coefficients).__name__}"
        )
    rate = _core.noise.discrete_rate(real("rate", rate))  # finite and > 0: the core's check
    if coefficients.data_unit is None:
        raise ValueError(
            "coefficients: the data unit is unknown (pass units= to the Allan analysis)"
        )
    base = coefficients.to("base")
    unit = coefficients.data_unit

    def scaled(symbol: str, convert: Any, name: str, formula: str) -> DiscreteValue:
        t = base[symbol]
        value, uncertainty = (
            (None, None) if t.value is None else convert(t.value, t.uncertainty, rate)
        )
        return DiscreteValue(name, value, uncertainty, unit, formula)

    white = scaled(
        "N",
        _core.noise.discrete_white,
        "white rate noise per sample",
        "sigma_white = N/sqrt(dt) = N*sqrt(rate)",
    )
    walk = scaled(
        "K",
        _core.noise.discrete_random_walk,
        "bias random-walk step",
        "sigma_walk = K*sqrt(dt) = K/sqrt(rate)",
    )
    gm_out = []
    for t in coefficients.gauss_markov:
        tau = t.correlation_time.to("s")
        sigma = t.sigma.to(unit)
        if tau.value is None or sigma.value is None:
            continue
        (phi, u_phi), (drive, u_drive) = _core.noise.discrete_gauss_markov(
            sigma.value, sigma.uncertainty, tau.value, tau.uncertainty, rate
        )
        gm_out.append(
            (
                DiscreteValue("Gauss-Markov phi", phi, u_phi, "1", "phi = exp(-dt/tau_c)"),
                DiscreteValue(
                    "Gauss-Markov driving noise",
                    drive,
                    u_drive,
                    unit,
                    "sigma_drive = sigma*sqrt(1 - phi^2)",
                ),
            )
        )
    return DiscreteNoise(
        rate=rate, white=white, bias_walk=walk, gauss_markov=tuple(gm_out), axis=coefficients.axis
    )
