"""Bindings of ``gyrocore::noise``."""

from typing import TypedDict, type_check_only

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = [
    "FLICKER_FACTOR",
    "add_lines",
    "biweight_constant",
    "conservative",
    "datasheet_coefficient",
    "detect_lines",
    "diagnose",
    "discrete_gauss_markov",
    "discrete_random_walk",
    "discrete_rate",
    "discrete_white",
    "fit",
    "gauss_markov_avar",
    "gauss_markov_variance",
    "gmwm",
    "model",
    "overbound",
    "read_off",
    "robust_variance",
    "simulate",
    "sinusoid_avar",
    "upper_bound",
    "wvar",
]

#: ``gyrocore::noise::FLICKER_FACTOR``: the Allan-deviation plateau ``√(2 ln 2 / π)`` of flicker
#: rate noise per unit bias instability B.
FLICKER_FACTOR: float

@type_check_only
class TermEstimate(TypedDict):
    """One noise term (Q, N, B, K or R) in the base unit of the curve."""

    symbol: str
    value: float | None
    uncertainty: float | None
    tau_range: tuple[float, float] | None
    marker: tuple[float, float] | None
    missing: str | None
    upper_bound: UpperBound | None

@type_check_only
class UpperBound(TypedDict):
    """Largest value of a term the data do not show (``gyrocore::noise::bound``)."""

    value: float
    confidence: float
    tau: float
    tau_range: tuple[float, float]
    points: int
    reason: str

@type_check_only
class ReadOff(TypedDict):
    """IEEE-952 read-off of the noise terms."""

    terms: list[TermEstimate]
    local_slopes: NDArray[np.float64]

@type_check_only
class GaussMarkovTerm(TypedDict):
    """One fitted first-order Gauss–Markov component (σ and correlation time in seconds)."""

    sigma: float | None
    sigma_uncertainty: float | None
    correlation_time: float | None
    correlation_time_uncertainty: float | None
    tau_range: tuple[float, float] | None
    missing: str | None

@type_check_only
class Diagnostics(TypedDict):
    """Goodness of fit of an identification (generalised χ², residuals, warnings)."""

    chi2: float
    dof: int
    p_value: float
    residuals: NDArray[np.float64]
    tau_range: tuple[float, float]
    excluded: list[tuple[float, float, str]]
    warnings: list[str]
    filter_correlation_time: tuple[float, float] | None
    # (claimed, data variance) of the data-variance constraint (gyrocore::noise::variance_limit)
    variance_limit: tuple[float, float] | None

@type_check_only
class LineEstimate(TypedDict):
    """One fitted sinusoidal term (frequency in Hz, amplitude in the rate unit)."""

    frequency: float
    frequency_uncertainty: float
    amplitude: float | None
    amplitude_uncertainty: float | None
    tau_range: tuple[float, float] | None
    missing: str | None

@type_check_only
class JointFit(TypedDict):
    """Weighted joint fit of the noise model to an Allan curve."""

    terms: list[TermEstimate]
    squared: list[float]
    gauss_markov: list[GaussMarkovTerm]
    chi2: float
    dof: int
    tau_range: tuple[float, float]
    lines: list[LineEstimate]
    diagnostics: Diagnostics
    used: list[int]
    edf: NDArray[np.float64]

@type_check_only
class WaveletVariance(TypedDict):
    """Haar wavelet variance per dyadic scale (GMWM's moments)."""

    m: NDArray[np.uint64]
    scales: NDArray[np.float64]
    variance: NDArray[np.float64]
    n_coefficients: NDArray[np.uint64]

@type_check_only
class Gmwm(TypedDict):
    """GMWM fit: the joint-fit fields (without ``used``/``edf``) plus the wavelet moments and
    the model selection."""

    terms: list[TermEstimate]
    squared: list[float]
    gauss_markov: list[GaussMarkovTerm]
    chi2: float
    dof: int
    tau_range: tuple[float, float]
    lines: list[LineEstimate]
    diagnostics: Diagnostics

    wavelet: WaveletVariance
    selected: list[str]
    criterion: float
    candidates: list[tuple[list[str], float]]
    bootstrap: int

def simulate(
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
def read_off(
    taus: NDArray[np.float64],
    variance: NDArray[np.float64],
    m: ArrayLike,
    n_terms: ArrayLike,
    overlapping: bool,
    edf: NDArray[np.float64] | None,
    terms: list[str],
    regions: list[tuple[float, float] | None],
    tolerance: float,
    min_points: int,
    bound_confidence: float = ...,
) -> ReadOff: ...
def model(
    squared: list[float] | tuple[float, float, float, float, float],
    taus: NDArray[np.float64],
    filter_time: float = ...,
) -> tuple[NDArray[np.float64], list[NDArray[np.float64]]]: ...

@type_check_only
class Overbound(TypedDict):
    """Tightest overbound of a bound by a non-negative combination of columns."""

    coefficients: NDArray[np.float64]
    ratio: NDArray[np.float64]
    objective: float
    pivots: int

@type_check_only
class Conservative(TypedDict):
    """Conservative five-term coefficients (squared, base units) and their inflation."""

    squared: list[float]
    inflation: list[float]
    used: list[int]
    edf: NDArray[np.float64]
    bound: NDArray[np.float64]
    ratio: NDArray[np.float64]
    tau_range: tuple[float, float]

def overbound(
    design: NDArray[np.float64],
    bound: NDArray[np.float64],
    floor: NDArray[np.float64] | None = None,
) -> Overbound: ...
def conservative(
    taus: NDArray[np.float64],
    variance: NDArray[np.float64],
    m: ArrayLike,
    n_terms: ArrayLike,
    overlapping: bool,
    edf: NDArray[np.float64] | None,
    reference: list[float] | tuple[float, float, float, float, float],
    terms: list[str],
    tau_range: tuple[float, float] | None,
    confidence: float,
) -> Conservative: ...
def upper_bound(
    taus: NDArray[np.float64],
    variance: NDArray[np.float64],
    m: ArrayLike,
    n_terms: ArrayLike,
    overlapping: bool,
    used: ArrayLike,
    edf: NDArray[np.float64],
    term: str,
    confidence: float,
) -> UpperBound: ...
def fit(
    taus: NDArray[np.float64],
    variance: NDArray[np.float64],
    m: ArrayLike,
    n_terms: ArrayLike,
    overlapping: bool,
    edf: NDArray[np.float64] | None,
    terms: list[str],
    tau_range: tuple[float, float] | None,
    correlation_time: tuple[float, float] | None,
    automatic_range: bool,
    lines: list[tuple[float, float]] = ...,
    bound_confidence: float = ...,
    data_variance: float | None = ...,
) -> JointFit: ...
def diagnose(
    taus: NDArray[np.float64],
    variance: NDArray[np.float64],
    m: ArrayLike,
    n_terms: ArrayLike,
    overlapping: bool,
    edf: NDArray[np.float64] | None,
    squared: list[float] | tuple[float, float, float, float, float],
    gauss_markov: list[tuple[float, float]],
    n_params: int,
) -> Diagnostics: ...
def gauss_markov_avar(
    sigma: float, correlation_time: float, taus: NDArray[np.float64]
) -> NDArray[np.float64]: ...
def gauss_markov_variance(
    gauss_markov: list[tuple[float, float]], taus: NDArray[np.float64]
) -> list[NDArray[np.float64]]: ...
def gmwm(
    data: NDArray[np.float64],
    t0: float,
    terms: list[str],
    select: bool,
    bootstrap: int,
    seed: int,
    min_blocks: int,
    automatic_range: bool = ...,
    lines: list[tuple[float, float]] = ...,
    bound_confidence: float = ...,
) -> Gmwm: ...

@type_check_only
class SpectralLine(TypedDict):
    """One detected spectral line (frequency Hz, amplitude, peak/floor, adjusted p-value)."""

    frequency: float
    amplitude: float
    ratio: float
    p_value: float
    resolution: float
    frequency_uncertainty: float

def detect_lines(
    data: NDArray[np.float64], t0: float, false_alarm: float, half_width: int, max_lines: int
) -> list[SpectralLine]: ...
def sinusoid_avar(
    amplitude: float, frequency: float, taus: NDArray[np.float64], t0: float | None = None
) -> NDArray[np.float64]: ...
def add_lines(
    data: NDArray[np.float64], t0: float, lines: list[tuple[float, float, float]]
) -> NDArray[np.float64]: ...

@type_check_only
class Wvar(TypedDict):
    """Haar MODWT wavelet variance with chi-square intervals."""

    levels: NDArray[np.uint64]
    m: NDArray[np.uint64]
    scales: NDArray[np.float64]
    variance: NDArray[np.float64]
    n_coefficients: NDArray[np.uint64]
    edf: NDArray[np.float64]
    ci_low: NDArray[np.float64]
    ci_high: NDArray[np.float64]
    tuning: float

def wvar(
    data: NDArray[np.float64],
    t0: float,
    efficiency: float | None,
    confidence: float,
    levels: int | None,
) -> Wvar: ...
def biweight_constant(efficiency: float) -> float: ...
def robust_variance(coefficients: NDArray[np.float64], tuning: float) -> float: ...
def discrete_rate(rate: float) -> float: ...
def discrete_white(
    n: float, uncertainty: float | None, rate: float
) -> tuple[float, float | None]: ...
def discrete_random_walk(
    k: float, uncertainty: float | None, rate: float
) -> tuple[float, float | None]: ...
def discrete_gauss_markov(
    sigma: float,
    sigma_uncertainty: float | None,
    tau: float,
    tau_uncertainty: float | None,
    rate: float,
) -> tuple[tuple[float, float | None], tuple[float, float | None]]: ...
def datasheet_coefficient(
    value: float,
    unit_factor: float,
    symbol: str,
    per_root_hz: bool,
    density: str,
    bias_instability_is: str,
) -> tuple[float, str]: ...
