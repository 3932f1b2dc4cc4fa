"""Stubs of ``gyrobias._core.random`` (binding of ``gyrocore::random``)."""

import numpy as np
from numpy.typing import NDArray

__all__ = ["normal", "seeds", "uniform"]

def normal(n: int, seed: int) -> NDArray[np.float64]: ...
def uniform(n: int, seed: int) -> NDArray[np.float64]: ...
def seeds(n: int, seed: int) -> list[int]: ...
