"""Bindings of ``gyrocore::thermal``."""

from typing import TypedDict, type_check_only

import numpy as np
from numpy.typing import NDArray

__all__ = ["check_temperatures", "fit_ar1", "interpolate"]

@type_check_only
class Ar1Fit(TypedDict):
    """AR(1) fit ``x_k − μ = β (x_{k−1} − μ) + e_k``."""

    c: float
    c_std_error: float
    sigma_e: float
    mean: float
    n: int
    beta: float
    process_std: float

def check_temperatures(temperatures: NDArray[np.float64]) -> None: ...
def fit_ar1(x: NDArray[np.float64], dt: float, demean: bool) -> Ar1Fit: ...
def interpolate(
    temperatures: NDArray[np.float64],
    values: NDArray[np.float64],
    method: str,
    degree: int,
    at: NDArray[np.float64],
    extrapolate: bool,
) -> NDArray[np.float64]: ...
