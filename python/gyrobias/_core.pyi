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
) -> dict[str, Any]: ...
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
def noise_fit(
    taus: NDArray[np.float64],
    variance: NDArray[np.float64],
    m: NDArray[np.uint64],
    n_terms: NDArray[np.uint64],
    overlapping: bool,
    edf: NDArray[np.float64] | None,
    terms: list[str],
    tau_range: tuple[float, float] | None,
    correlation_time: tuple[float, float] | None,
    automatic_range: bool,
) -> dict[str, Any]: ...
def noise_diagnose(
    taus: NDArray[np.float64],
    variance: NDArray[np.float64],
    m: NDArray[np.uint64],
    n_terms: NDArray[np.uint64],
    overlapping: bool,
    edf: NDArray[np.float64] | None,
    squared: list[float] | tuple[float, float, float, float, float],
    gauss_markov: list[tuple[float, float]],
    n_params: int,
) -> dict[str, Any]: ...
def noise_gauss_markov_variance(
    gauss_markov: list[tuple[float, float]], taus: NDArray[np.float64]
) -> list[NDArray[np.float64]]: ...
def noise_gmwm(
    data: NDArray[np.float64],
    t0: float,
    terms: list[str],
    select: bool,
    bootstrap: int,
    seed: int,
    min_blocks: int,
) -> dict[str, Any]: ...

# --- fir ---------------------------------------------------------------------------------------

def kaiser_design(
    fs: float, fpass: float, fstop: float, apass_db: float, astop_db: float
) -> dict[str, float | NDArray[np.float64]]: ...
def fir_filter(
    taps: NDArray[np.float64], x: NDArray[np.float64], zero_phase: bool, padtype: str, padlen: int
) -> NDArray[np.float64]: ...
def fir_response(
    taps: NDArray[np.float64], fs: float, freqs: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]: ...
def fir_stream(
    taps: NDArray[np.float64], x: NDArray[np.float64], state: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]: ...

# --- spectral ----------------------------------------------------------------------------------

def lssa(
    t: NDArray[np.float64],
    y: NDArray[np.float64],
    freqs: NDArray[np.float64],
    weights: NDArray[np.float64] | None,
    cov: NDArray[np.float64] | None,
    trend: bool,
    known_periods: NDArray[np.float64],
    columns: NDArray[np.float64] | None,
) -> dict[str, float | int | NDArray[np.float64]]: ...
def lssa_critical(n: int, n_known: int, alpha: float) -> float: ...
def lssa_frequencies(t: NDArray[np.float64]) -> NDArray[np.float64]: ...
def welch_psd(
    x: NDArray[np.float64], fs: float, nperseg: int, noverlap: int, window: str
) -> tuple[NDArray[np.float64], NDArray[np.float64]]: ...

# --- thermal -----------------------------------------------------------------------------------

def ar1_fit(x: NDArray[np.float64], dt: float, demean: bool) -> dict[str, float | int]: ...
def temperature_interpolate(
    temperatures: NDArray[np.float64],
    values: NDArray[np.float64],
    method: str,
    degree: int,
    at: NDArray[np.float64],
    extrapolate: bool,
) -> NDArray[np.float64]: ...

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

# --- kalman ------------------------------------------------------------------------------------

@final
class FixedGainKalmanCore:
    def __new__(
        cls,
        fs: float,
        arw: float,
        rrw: float,
        q_omega: float | None,
        bandwidth: float | None,
        form: str,
    ) -> FixedGainKalmanCore: ...
    @property
    def q_omega(self) -> float: ...
    @property
    def r_d(self) -> float: ...
    @property
    def q_b(self) -> float: ...
    @property
    def kappa(self) -> float: ...
    @property
    def pole(self) -> float: ...
    @property
    def dc_gain(self) -> float: ...
    @property
    def white_noise_gain(self) -> float: ...
    @property
    def bandwidth(self) -> float | None: ...
    @property
    def gain(self) -> NDArray[np.float64]: ...
    @property
    def continuous_gain(self) -> NDArray[np.float64]: ...
    @property
    def g(self) -> NDArray[np.float64]: ...
    @property
    def a(self) -> NDArray[np.float64]: ...
    @property
    def b(self) -> NDArray[np.float64]: ...
    def frequency_response(
        self, freqs: NDArray[np.float64]
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]: ...
    def initial_state(self, rate0: list[float], bias0: list[float]) -> KalmanState: ...
    def estimates(self, state: KalmanState) -> tuple[list[float], list[float]]: ...
    def filter_into(
        self,
        z: NDArray[np.float64],
        rate: NDArray[np.float64],
        bias: NDArray[np.float64],
        state: KalmanState,
    ) -> KalmanState: ...

@final
class KalmanState:
    def __new__(
        cls,
        level: list[float] | tuple[float, ...],
        offset: list[float] | tuple[float, ...],
        rate: list[float] | tuple[float, ...],
        bias: list[float] | tuple[float, ...],
        gain: tuple[float, float],
        samples: int = 0,
    ) -> KalmanState: ...
    @property
    def level(self) -> tuple[float, ...]: ...
    @property
    def offset(self) -> tuple[float, ...]: ...
    @property
    def rate(self) -> tuple[float, ...]: ...
    @property
    def bias(self) -> tuple[float, ...]: ...
    @property
    def gain(self) -> tuple[float, float]: ...
    @property
    def samples(self) -> int: ...
    @property
    def n_axes(self) -> int: ...
    def __reduce__(self) -> tuple[type[KalmanState], tuple[object, ...]]: ...

def kalman_steady_state_gain(q_omega: float, q_b: float, r_d: float) -> NDArray[np.float64]: ...
def kalman_riccati_gain(
    q_omega: float, q_b: float, r_d: float, iterations: int
) -> NDArray[np.float64]: ...
def kalman_q_omega_for_bandwidth(
    bandwidth: float, fs: float, arw: float, rrw: float, form: str
) -> float: ...
