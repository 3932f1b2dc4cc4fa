"""Options every Allan driver shares (types and names only; ranges are the core's checks)."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gyrobias._validation import as_float_array, integer, real, sample_rate, string
from gyrobias.allan._types import _ESTIMATOR_OF_KIND, Kind
from gyrobias.units import checked_units


def _options(
    kind: Kind,
    fs: float,
    taus: str | ArrayLike,
    per_decade: int,
    data_type: str,
    overlapping: bool,
    confidence: float | None,
) -> tuple[float, str, str, NDArray[np.float64] | None, float | None]:
    """Normalised options: ``(fs, estimator, tau spec, explicit taus, confidence)``."""
    fs, spec, explicit, _, confidence = _tau_options(fs, taus, per_decade, data_type, confidence)
    if kind == "adev":
        estimator = "overlapping" if overlapping else "non-overlapping"
    else:
        estimator = _ESTIMATOR_OF_KIND[kind]
    return fs, estimator, spec, explicit, confidence


def _tau_options(
    fs: float,
    taus: str | ArrayLike,
    per_decade: int,
    data_type: str,
    confidence: float | None,
) -> tuple[float, str, NDArray[np.float64] | None, int, float | None]:
    """Types of the options every Allan driver shares: ``(fs, tau spec, explicit taus,
    per_decade, confidence)``.

    Only types and names are checked here; the ranges (``per_decade >= 1`` for log spacing,
    ``0 < confidence < 1``, τ on the sample grid, ...) are the core's preconditions.
    """
    fs = sample_rate(fs)  # checked by the core before t0 = 1/fs is computed here
    string("data_type", data_type)  # its value is parsed by the core (DataType::parse)
    per_decade = integer("per_decade", per_decade)
    checked = None if confidence is None else real("confidence", confidence)
    explicit: NDArray[np.float64] | None = None
    spec = "octave"
    if isinstance(taus, str):
        spec = string("taus", taus)  # parsed by the core (Taus::parse), whose ValueError names taus
    else:
        explicit = as_float_array("taus", taus, ndims=(1,))
    return fs, spec, explicit, per_decade, checked


def _axis_units(units: str | Sequence[str | None] | None, n_axes: int) -> list[str | None]:
    """``units`` (one unit for every axis, or a sequence of one per axis) as one entry per axis.

    One call for the columns of a log in several units (gyro and accelerometer axes) analyses
    the row-major buffer as it is, where a call per unit would copy its columns first."""
    if units is None or isinstance(units, str):
        return [checked_units("units", units)] * n_axes
    if isinstance(units, np.ndarray) or not isinstance(units, Sequence):
        raise TypeError(
            f"units must be a unit string, a sequence of one per axis or None, "
            f"got {type(units).__name__}"
        )
    if len(units) != n_axes:
        raise ValueError(f"units: {len(units)} units for {n_axes} axes (give one per axis)")
    return [checked_units("units", u) for u in units]
