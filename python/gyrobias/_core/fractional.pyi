"""Bindings of ``gyrocore::fractional``."""

from typing import TypedDict, type_check_only

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "arfima",
    "diff",
    "elw",
    "elw_confidence_interval",
    "elw_objective",
    "integrate",
    "weights",
]

@type_check_only
class Elw(TypedDict):
    """Exact local Whittle estimates, one entry per row of the data."""

    d: NDArray[np.float64]
    standard_error: NDArray[np.float64]
    objective: NDArray[np.float64]
    at_bound: NDArray[np.bool_]
    m: int
    n: int

def weights(d: float, n: int) -> NDArray[np.float64]: ...
def diff(data: NDArray[np.float64], d: float, method: str) -> NDArray[np.float64]: ...
def integrate(data: NDArray[np.float64], d: float, method: str) -> NDArray[np.float64]: ...
def arfima(
    n: int, d: float, sigma: float, rows: int, seed: int, kind: str
) -> NDArray[np.float64]: ...
def elw(
    data: NDArray[np.float64], m: int | None, lower: float, upper: float, level: str
) -> Elw: ...
def elw_confidence_interval(
    d: NDArray[np.float64], standard_error: float, confidence: float
) -> tuple[NDArray[np.float64], NDArray[np.float64]]: ...
def elw_objective(
    x: NDArray[np.float64], ds: NDArray[np.float64], m: int | None, level: str
) -> NDArray[np.float64]: ...
