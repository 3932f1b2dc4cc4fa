"""Stubs of ``gyrobias._core.fleet`` (binding of ``gyrocore::fleet``)."""

from typing import final

import numpy as np
from numpy.typing import NDArray

__all__ = ["MAD_TO_SD", "Spread", "SpreadTest", "robust_z", "spread"]

MAD_TO_SD: float

@final
class Spread:
    @property
    def median(self) -> float: ...
    @property
    def spread(self) -> float: ...
    @property
    def mean_uncertainty(self) -> float: ...
    @property
    def intrinsic_spread(self) -> float: ...
    @property
    def chi2(self) -> float: ...
    @property
    def dof(self) -> int | None: ...
    @property
    def birge_ratio(self) -> float: ...
    @property
    def p_value(self) -> float: ...
    @property
    def real(self) -> bool | None: ...

@final
class SpreadTest:
    def __new__(cls, alpha: float, min_ratio: float) -> SpreadTest: ...
    @property
    def alpha(self) -> float: ...
    @property
    def min_ratio(self) -> float: ...

def robust_z(
    values: NDArray[np.float64], uncertainties: NDArray[np.float64]
) -> NDArray[np.float64]: ...
def spread(
    values: NDArray[np.float64],
    uncertainties: NDArray[np.float64],
    test: SpreadTest,
) -> Spread: ...
