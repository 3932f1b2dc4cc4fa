"""Discrete-time noise parameters: :class:`DiscreteValue` and :class:`DiscreteNoise` (value
types only)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

__all__ = ["DiscreteNoise", "DiscreteValue"]


@dataclass(frozen=True)
class DiscreteValue:
    """One discrete-time noise parameter with its uncertainty, unit and formula."""

    name: str
    value: float | None
    uncertainty: float | None
    unit: str
    formula: str

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dictionary."""
        return {
            "name": self.name,
            "value": self.value,
            "uncertainty": self.uncertainty,
            "unit": self.unit,
            "formula": self.formula,
        }


@dataclass(frozen=True)
class DiscreteNoise:
    """Per-sample noise parameters of one sensor axis at a given rate.

    Attributes
    ----------
    rate : float
        Rate in Hz (``Δt = 1/rate``).
    white : DiscreteValue
        Per-sample standard deviation of the white rate noise, ``σ_white = N/√Δt`` (data unit).
    bias_walk : DiscreteValue
        Standard deviation of one step of the bias random walk, ``σ_walk = K·√Δt`` (data unit).
    gauss_markov : tuple of (DiscreteValue, DiscreteValue)
        Per Gauss–Markov term: ``φ = exp(−Δt/τ_c)`` (dimensionless) and the driving standard
        deviation ``σ_GM·√(1 − φ²)`` (data unit) of ``b_{k+1} = φ·b_k + w_k``.
    axis : str or None
        Axis name.
    """

    rate: float
    white: DiscreteValue
    bias_walk: DiscreteValue
    gauss_markov: tuple[tuple[DiscreteValue, DiscreteValue], ...] = ()
    axis: str | None = None

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dictionary."""
        return {
            "axis": self.axis,
            "rate_hz": self.rate,
            "white": self.white.to_dict(),
            "bias_walk": self.bias_walk.to_dict(),
            "gauss_markov": [
                {"phi": p.to_dict(), "driving_sigma": d.to_dict()} for p, d in self.gauss_markov
            ],
        }
