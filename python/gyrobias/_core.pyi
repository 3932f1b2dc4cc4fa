"""Type stubs of the Rust extension module (checked by ``python -m mypy.stubtest gyrobias._core``)."""

from typing import Any, final

import numpy as np
from numpy.typing import NDArray

class GyroLinAlgError(ValueError): ...

# --- allan -------------------------------------------------------------------------------------

def allan_analysis(
    data: NDArray[np.float64],
    t0: float,
    data_type: str,
    estimator: str,
    tau_spec: str,
    per_decade: int,
    taus: NDArray[np.float64] | None,
    confidence: float | None,
) -> list[dict[str, NDArray[np.float64] | NDArray[np.uint64] | NDArray[np.int32]]]: ...
def allan_factors(
    n_samples: int,
    t0: float,
    data_type: str,
    estimator: str,
    tau_spec: str,
    per_decade: int,
    taus: NDArray[np.float64] | None,
) -> NDArray[np.uint64]: ...

# --- fractional --------------------------------------------------------------------------------

def fractional_weights(d: float, n: int) -> NDArray[np.float64]: ...
def fractional_diff(data: NDArray[np.float64], d: float, method: str) -> NDArray[np.float64]: ...
def fractional_integrate(
    data: NDArray[np.float64], d: float, method: str
) -> NDArray[np.float64]: ...
def fractional_arfima(
    n: int, d: float, sigma: float, rows: int, seed: int, kind: str
) -> NDArray[np.float64]: ...
def fractional_elw(
    data: NDArray[np.float64], m: int | None, lower: float, upper: float, level: str
) -> dict[str, NDArray[np.float64] | NDArray[np.bool_] | int]: ...
def fractional_elw_objective(
    x: NDArray[np.float64], ds: NDArray[np.float64], m: int | None, level: str
) -> NDArray[np.float64]: ...

# --- noise -------------------------------------------------------------------------------------

def noise_simulate(
    n: int,
    fs: float,
    quantization: float,
    arw: float,
    bias_instability: float,
    rrw: float,
    rate_ramp: float,
    ar1: tuple[float, float] | None,
    bias: float,
    axes: int,
    seed: int,
) -> NDArray[np.float64]: ...
def noise_fit_joint(
    taus: NDArray[np.float64],
    variance: NDArray[np.float64],
    m: NDArray[np.uint64],
    n_terms: NDArray[np.uint64],
    overlapping: bool,
    edf: NDArray[np.float64] | None,
    terms: list[str],
    tau_range: tuple[float, float] | None,
) -> dict[str, Any]: ...
def noise_read_off(
    taus: NDArray[np.float64],
    variance: NDArray[np.float64],
    m: NDArray[np.uint64],
    n_terms: NDArray[np.uint64],
    overlapping: bool,
    edf: NDArray[np.float64] | None,
    terms: list[str],
    regions: list[tuple[float, float] | None],
    tolerance: float,
    min_points: int,
) -> dict[str, Any]: ...
def noise_model(
    squared: list[float] | tuple[float, float, float, float, float],
    taus: NDArray[np.float64],
) -> tuple[NDArray[np.float64], list[NDArray[np.float64]]]: ...

# --- predict -----------------------------------------------------------------------------------

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
) -> dict[str, Any]: ...
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
