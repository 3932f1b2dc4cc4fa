"""Bindings of ``gyrocore::allan``."""

from collections.abc import Callable
from typing import NotRequired, TypedDict, type_check_only

import numpy as np
from numpy.typing import NDArray

__all__ = ["analyse", "analyse_batch", "factors"]

@type_check_only
class Analysis(TypedDict):
    """One axis of :func:`analyse`: variances (not deviations) and their chi-square bounds."""

    m: NDArray[np.uint64]
    variance: NDArray[np.float64]
    n_terms: NDArray[np.uint64]
    alpha: NotRequired[NDArray[np.int32]]
    edf: NotRequired[NDArray[np.float64]]
    low: NotRequired[NDArray[np.float64]]
    high: NotRequired[NDArray[np.float64]]

def analyse(
    data: NDArray[np.float64],
    t0: float,
    data_type: str,
    estimator: str,
    tau_spec: str,
    per_decade: int,
    taus: NDArray[np.float64] | None,
    confidence: float | None,
    gaps: str = "error",
    progress: Callable[[float], object] | None = None,
) -> list[Analysis]: ...
def analyse_batch(
    data: NDArray[np.float64],
    t0: float,
    data_type: str,
    estimator: str,
    tau_spec: str,
    per_decade: int,
    taus: NDArray[np.float64] | None,
    confidence: float | None,
    gaps: str = "error",
    progress: Callable[[float], object] | None = None,
) -> list[list[Analysis]]: ...
def factors(
    n_samples: int,
    t0: float,
    data_type: str,
    estimator: str,
    tau_spec: str,
    per_decade: int,
    taus: NDArray[np.float64] | None,
) -> NDArray[np.uint64]: ...
