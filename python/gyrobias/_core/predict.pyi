"""Bindings of ``gyrocore::predict``."""

from typing import TypedDict, final, type_check_only

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "MIN_BOOTSTRAP_SECTIONS",
    "CompiledPredictor",
    "Scores",
    "bootstrap_ratio",
    "evaluate",
    "integrated_error",
    "mean_std",
    "rsse",
    "calibration_mean",
    "fractional_kalman",
    "moving_average",
    "noise_parameters",
    "validate_model",
]

@type_check_only
class BatchPrediction(TypedDict):
    """Forecasts of every calibration row (``bias`` flat windows·h)."""

    bias: NDArray[np.float64]
    std: NDArray[np.float64]
    std_observation: NDArray[np.float64]
    mean: NDArray[np.float64]
    mean_std: float

def noise_parameters(arw: float, bias_instability: float, fs: float) -> tuple[float, float]: ...
def validate_model(
    d: float, q: float, r: float, mean: str, mu0: float, p0: float, algorithm: str
) -> None: ...
def fractional_kalman(
    calibration: NDArray[np.float64],
    horizon: int,
    d: float,
    q: float,
    r: float,
    mean: str,
    mu0: float,
    p0: float,
    algorithm: str,
    n_threads: int,
) -> BatchPrediction: ...
def calibration_mean(calibration: NDArray[np.float64], horizon: int) -> NDArray[np.float64]: ...
def moving_average(calibration: NDArray[np.float64], horizon: int) -> NDArray[np.float64]: ...

@final
class CompiledPredictor:
    def __new__(
        cls,
        calibration_length: int,
        horizon: int,
        d: float,
        q: float,
        r: float,
        mean: str,
        mu0: float,
        p0: float,
        n_threads: int,
    ) -> CompiledPredictor: ...
    def predict(
        self, batch: NDArray[np.float64], n_threads: int
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]: ...
    def predict_sequential(
        self, batch: NDArray[np.float64]
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]: ...
    def predict_sequential_f32(
        self, batch: NDArray[np.float32]
    ) -> tuple[NDArray[np.float32], NDArray[np.float32]]: ...
    @property
    def calibration_length(self) -> int: ...
    @property
    def horizon(self) -> int: ...
    @property
    def weights(self) -> NDArray[np.float64]: ...
    @property
    def offset(self) -> NDArray[np.float64]: ...
    @property
    def std(self) -> NDArray[np.float64]: ...
    @property
    def std_observation(self) -> NDArray[np.float64]: ...
    @property
    def mean_std(self) -> float: ...

MIN_BOOTSTRAP_SECTIONS: int

@final
class Scores:
    @property
    def integrated_error(self) -> NDArray[np.float64]: ...
    @property
    def rsse(self) -> NDArray[np.float64]: ...

def evaluate(
    log: NDArray[np.float64],
    row_width: int | None,
    calibration: int,
    horizon: int,
    methods: list[str],
    d: float,
    q: float,
    r: float,
    mean: str,
    mu0: float,
    p0: float,
    n_threads: int,
) -> list[Scores]: ...
def integrated_error(y: NDArray[np.float64], yhat: NDArray[np.float64]) -> NDArray[np.float64]: ...
def rsse(y: NDArray[np.float64], yhat: NDArray[np.float64]) -> NDArray[np.float64]: ...
def mean_std(values: NDArray[np.float64]) -> tuple[float, float]: ...
def bootstrap_ratio(
    a: NDArray[np.float64],
    b: NDArray[np.float64],
    statistic: str,
    resamples: int,
    seed: int,
) -> tuple[float, float]: ...
