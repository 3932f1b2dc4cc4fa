"""Bindings of ``gyrocore::spectral``."""

from typing import TypedDict, type_check_only

import numpy as np
from numpy.typing import NDArray

__all__ = ["critical_value", "default_frequencies", "lssa", "welch"]

@type_check_only
class Lssa(TypedDict):
    """Least-squares spectrum and the fit of the known constituents."""

    spectrum: NDArray[np.float64]
    n_known: int
    known_params: NDArray[np.float64]
    t_ref: float
    residual_norm: float

def lssa(
    t: NDArray[np.float64],
    y: NDArray[np.float64],
    freqs: NDArray[np.float64],
    weights: NDArray[np.float64] | None,
    cov: NDArray[np.float64] | None,
    trend: bool,
    known_periods: NDArray[np.float64],
    columns: NDArray[np.float64] | None,
) -> Lssa: ...
def critical_value(n: int, n_known: int, alpha: float) -> float: ...
def default_frequencies(t: NDArray[np.float64]) -> NDArray[np.float64]: ...
def welch(
    x: NDArray[np.float64], fs: float, nperseg: int, noverlap: int, window: str
) -> tuple[NDArray[np.float64], NDArray[np.float64]]: ...
