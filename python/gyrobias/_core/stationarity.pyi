"""Stubs of ``gyrobias._core.stationarity`` (binding of ``gyrocore::stationarity``)."""

from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "FALSE_ALARM",
    "MIN_BLOCK",
    "MIN_BLOCKS",
    "TARGET_BLOCKS",
    "block_length",
    "check",
    "check_matrix",
]

FALSE_ALARM: float
MIN_BLOCK: int
MIN_BLOCKS: int
TARGET_BLOCKS: int

def check(means: NDArray[np.float64], block: int, n: int) -> dict[str, Any]: ...
def check_matrix(data: NDArray[np.float64]) -> list[dict[str, Any]]: ...
def block_length(n: int) -> int: ...
