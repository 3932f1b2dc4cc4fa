"""Bindings of ``gyrocore::fir``."""

from typing import TypedDict, type_check_only

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "filter_rows",
    "filter_stream_rows",
    "filter_stream_rows_f32",
    "frequency_response",
    "kaiser_lowpass",
]

@type_check_only
class KaiserLowpass(TypedDict):
    """A Kaiser-window low-pass design."""

    cutoff: float
    delta_pass: float
    delta_stop: float
    attenuation_db: float
    alpha: float
    d: float
    taps: NDArray[np.float64]

def kaiser_lowpass(
    fs: float, fpass: float, fstop: float, apass_db: float, astop_db: float
) -> KaiserLowpass: ...
def filter_rows(
    taps: NDArray[np.float64], x: NDArray[np.float64], zero_phase: bool, padtype: str, padlen: int
) -> NDArray[np.float64]: ...
def frequency_response(
    taps: NDArray[np.float64], fs: float, freqs: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]: ...
def filter_stream_rows(
    taps: NDArray[np.float64], x: NDArray[np.float64], state: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]: ...
def filter_stream_rows_f32(
    taps: NDArray[np.float32], x: NDArray[np.float32], state: NDArray[np.float32]
) -> tuple[NDArray[np.float32], NDArray[np.float32]]: ...
