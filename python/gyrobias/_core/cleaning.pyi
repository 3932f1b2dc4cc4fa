"""Stubs of ``gyrobias._core.cleaning`` (binding of ``gyrocore::cleaning``)."""

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "MEAN_AD_TO_SD",
    "MIN_OUTLIER_SAMPLES",
    "detrend",
    "detrend_in_place",
    "detrend_into",
    "minmax_envelope",
    "remove_outliers",
    "remove_outliers_in_place",
    "remove_outliers_into",
]

MEAN_AD_TO_SD: float
MIN_OUTLIER_SAMPLES: int

def remove_outliers(
    data: NDArray[np.float64], threshold: float
) -> tuple[
    NDArray[np.float64],
    NDArray[np.bool_],
    NDArray[np.float64],
    NDArray[np.float64],
    NDArray[np.uint64],
]: ...
def detrend(
    data: NDArray[np.float64], fs: float, order: int
) -> tuple[NDArray[np.float64], NDArray[np.float64]]: ...
def remove_outliers_in_place(
    data: NDArray[np.float64], threshold: float
) -> tuple[
    NDArray[np.bool_],
    NDArray[np.float64],
    NDArray[np.float64],
    NDArray[np.uint64],
    int,
]: ...
def remove_outliers_into(
    data: NDArray[np.float64], out: NDArray[np.float64], threshold: float
) -> tuple[
    NDArray[np.bool_],
    NDArray[np.float64],
    NDArray[np.float64],
    NDArray[np.uint64],
    int,
]: ...
def detrend_in_place(
    data: NDArray[np.float64], fs: float, order: int
) -> tuple[NDArray[np.float64], int]: ...
def detrend_into(
    data: NDArray[np.float64], out: NDArray[np.float64], fs: float, order: int
) -> tuple[NDArray[np.float64], int]: ...
def minmax_envelope(
    data: NDArray[np.float64], bins: int
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.uint64]]: ...
