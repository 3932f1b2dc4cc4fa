"""Stubs of ``gyrobias._core.timestamps`` (binding of ``gyrocore::timestamps``)."""

from typing import final

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "FS_TOLERANCE",
    "GAP_FACTOR",
    "JITTER_WARN",
    "NS_THRESHOLD",
    "US_THRESHOLD",
    "Sampling",
    "analyse",
    "analyse_stamps",
    "backward_rows",
    "fill_time_into",
    "guess_unit",
    "median_positive_step",
    "missing_in_gap",
    "repeated_rows",
    "seconds_in_place",
]

GAP_FACTOR: float
NS_THRESHOLD: float
US_THRESHOLD: float
JITTER_WARN: float
FS_TOLERANCE: float

@final
class Sampling:
    @property
    def median_interval(self) -> float: ...
    @property
    def fs_estimated(self) -> float: ...
    @property
    def jitter(self) -> float: ...
    @property
    def gap_rows(self) -> NDArray[np.int64]: ...
    @property
    def gap_durations(self) -> NDArray[np.float64]: ...
    @property
    def missing_samples(self) -> int: ...
    @property
    def duplicate_rows(self) -> NDArray[np.int64]: ...

def median_positive_step(stamps: NDArray[np.int64] | NDArray[np.float64]) -> float: ...
def guess_unit(median_step: float) -> str: ...
def backward_rows(stamps: NDArray[np.int64] | NDArray[np.float64]) -> NDArray[np.int64]: ...
def repeated_rows(stamps: NDArray[np.int64] | NDArray[np.float64]) -> NDArray[np.int64]: ...
def analyse(intervals: NDArray[np.float64]) -> Sampling: ...
def analyse_stamps(
    stamps: NDArray[np.int64] | NDArray[np.float64], per_second: float
) -> Sampling: ...
def seconds_in_place(
    stamps: NDArray[np.int64] | NDArray[np.float64], first: int | float, per_second: float
) -> None: ...
def missing_in_gap(gap: float, median: float) -> int: ...
def fill_time_into(
    time: NDArray[np.float64],
    gap_rows: NDArray[np.int64],
    counts: NDArray[np.int64],
    out: NDArray[np.float64],
) -> None: ...
