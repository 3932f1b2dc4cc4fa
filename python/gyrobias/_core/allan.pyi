"""Bindings of ``gyrocore::allan``."""

from collections.abc import Callable
from typing import NotRequired, TypedDict, type_check_only

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "analyse",
    "analyse_batch",
    "analyse_stream",
    "dynamic_avar",
    "factors",
    "family_analyse",
]

@type_check_only
class Analysis(TypedDict):
    """One axis of :func:`analyse`: variances, deviations and their chi-square bounds.

    ``deviation`` (and its bounds) are computed before the data's scale is restored, so they
    stay finite where the variance over- or underflows float64 (data of extreme magnitude).
    """

    m: NDArray[np.uint64]
    variance: NDArray[np.float64]
    deviation: NDArray[np.float64]
    n_terms: NDArray[np.uint64]
    alpha: NotRequired[NDArray[np.int32]]
    edf: NotRequired[NDArray[np.float64]]
    low: NotRequired[NDArray[np.float64]]
    high: NotRequired[NDArray[np.float64]]
    deviation_low: NotRequired[NDArray[np.float64]]
    deviation_high: NotRequired[NDArray[np.float64]]
    # the stationarity check's block means (gyrocore::stationarity), not from the gap-aware
    # or out-of-core kernels
    block_means: NotRequired[NDArray[np.float64]]
    block_length: NotRequired[int]
    block_samples: NotRequired[int]
    # the data's variance (rate unit², gyrocore::allan::Moments); absent below two samples
    data_variance: NotRequired[float]
    data_deviation: NotRequired[float]

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
def analyse_stream(
    read: Callable[[int, int], NDArray[np.float64]],
    n_samples: int,
    t0: float,
    data_type: str,
    tau_spec: str,
    per_decade: int,
    taus: NDArray[np.float64] | None,
    confidence: float | None,
    block: int,
    progress: Callable[[float], object] | None = None,
) -> Analysis: ...
def factors(
    n_samples: int,
    t0: float,
    data_type: str,
    estimator: str,
    tau_spec: str,
    per_decade: int,
    taus: NDArray[np.float64] | None,
) -> NDArray[np.uint64]: ...

@type_check_only
class FamilyAnalysis(TypedDict):
    """One axis of :func:`family_analyse`: τ/t0 per point, Théo flags, variances and bounds."""

    m: NDArray[np.uint64]
    tau_factor: NDArray[np.float64]
    theo: list[bool]
    variance: NDArray[np.float64]
    deviation: NDArray[np.float64]
    n_terms: NDArray[np.uint64]
    alpha: NotRequired[NDArray[np.int32]]
    edf: NotRequired[NDArray[np.float64]]
    low: NotRequired[NDArray[np.float64]]
    high: NotRequired[NDArray[np.float64]]
    deviation_low: NotRequired[NDArray[np.float64]]
    deviation_high: NotRequired[NDArray[np.float64]]
    # the data's variance (rate unit², gyrocore::allan::Moments); absent below two samples
    data_variance: NotRequired[float]
    data_deviation: NotRequired[float]

@type_check_only
class DynamicAvar(TypedDict):
    """:func:`dynamic_avar`: window starts, factors, terms and the (windows × τ) variances."""

    starts: NDArray[np.uint64]
    m: NDArray[np.uint64]
    n_terms: NDArray[np.uint64]
    variance: NDArray[np.float64]

def family_analyse(
    data: NDArray[np.float64],
    t0: float,
    data_type: str,
    statistic: str,
    tau_spec: str,
    per_decade: int,
    taus: NDArray[np.float64] | None,
    confidence: float | None,
) -> list[FamilyAnalysis]: ...
def dynamic_avar(
    data: NDArray[np.float64],
    t0: float,
    data_type: str,
    window: int,
    step: int,
    tau_spec: str,
    per_decade: int,
    taus: NDArray[np.float64] | None,
) -> DynamicAvar: ...
