"""Type stubs of the Rust extension module (checked by ``python -m mypy.stubtest gyrobias._core``)."""

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

# --- kalman ------------------------------------------------------------------------------------

from typing import final

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
