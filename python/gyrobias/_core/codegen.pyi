"""Bindings of ``gyrocore::codegen``."""

from typing import TypedDict, type_check_only

import numpy as np
from numpy.typing import NDArray

__all__ = ["dot_q31", "kalman_q31"]

@type_check_only
class Scaled(TypedDict):
    """A coefficient stored as ``value = round(c·2**shift)``."""

    value: int
    shift: int
    represented: float
    error: float

@type_check_only
class KalmanQ31(TypedDict):
    """Q31 realisation of the fixed-gain Kalman recursion."""

    a: Scaled
    rate_gain: Scaled
    bias_gain: Scaled
    error_bound: tuple[float, float]
    noise_rms: tuple[float, float]

@type_check_only
class DotQ31(TypedDict):
    """Q31 realisation of ``W·x + w0``."""

    values: list[int]
    shift: int
    offsets: list[int]
    error_bound: float
    coefficient_error: float
    noise_rms: float

def kalman_q31(
    pole: float, one_minus_pole: float, g1: float, g2: float, amplitude: float
) -> KalmanQ31: ...
def dot_q31(
    weights: NDArray[np.float64], offsets: NDArray[np.float64], amplitude: float
) -> DotQ31: ...
