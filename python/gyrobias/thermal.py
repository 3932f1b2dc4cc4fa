"""Temperature-dependent noise models: AR(1) drift fits and interpolation in temperature ([TS] §4).

[TS] log static MEMS gyros and accelerometers at −30, 0, +30 and +60 °C and show that the
Allan-variance coefficients and the first-order AR drift coefficient depend on temperature.
This module fits the AR(1) model (:func:`fit_ar1`), analyses one log per temperature
(:func:`analyse_log`), and interpolates any named parameter in temperature
(:class:`TemperatureModel`, linear / PCHIP / low-order polynomial, JSON round trip).
:func:`build_temperature_model` does it all from several temperature-tagged logs.

Conventions
-----------
- AR(1): ``b_{k+1} = c·b_k + e``. [TS]'s tables use ``b_{k+1} + C_AR·b_k = e``, i.e.
  ``C_AR = −c`` (white noise low-passed by its own Kaiser filters gives c = +0.961 / +0.844 /
  +0.671 at fc = 8/16/24 Hz where [TS] prints ≈ −0.96 / −0.9 / −0.7); :class:`AR1Fit` reports
  both (``c`` and ``c_ar``).
- Temperatures in °C; parameters in whatever unit the caller states in ``units``.

References
----------
.. [TS] N. El-Diasty, A. El-Rabbany, S. Pagiatakis, "Stochastic characteristics of
   temperature-dependent MEMS-based inertial sensor error", §4, Tables 1–5.
.. [IEEE952] IEEE Std 952-1997, Annex C (reading N at τ = 1 s, B from the flicker floor).
"""

from __future__ import annotations

import json
import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from typing import Any, cast

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gyrobias import _core
from gyrobias._validation import (
    as_float_array,
    boolean,
    integer,
    mapping,
    real,
    sample_rate,
    sequence,
    string,
)
from gyrobias.units import checked_units

__all__ = [
    "AR1Fit",
    "TemperatureModel",
    "ThermalAnalysis",
    "analyse_log",
    "analyse_logs",
    "build_temperature_model",
    "fit_ar1",
]


@dataclass(frozen=True)
class AR1Fit:
    """Least-squares first-order autoregressive fit ``b_{k+1} = c·b_k + e``.

    Attributes
    ----------
    c : float
        AR coefficient in ``b_{k+1} = c·b_k + e``.
    c_std_error : float
        Standard error of ``c``, ``√(s_e²/Σb_k²) ≈ √((1 − c²)/n)``.
    sigma_e : float
        Innovation standard deviation ``s_e = √(RSS/(n − 2))`` (unit of the data).
    mean : float
        Mean removed before the fit (0 with ``demean=False``).
    n : int
        Number of samples.
    dt : float
        Sample interval in seconds.
    beta : float or None
        Equivalent first-order Gauss–Markov rate ``β = −ln(c)/Δt`` (1/s); ``None`` unless
        ``0 < c < 1``.
    process_std : float or None
        Stationary standard deviation ``s_e/√(1 − c²)``; ``None`` unless ``|c| < 1``.
    """

    c: float
    c_std_error: float
    sigma_e: float
    mean: float
    n: int
    dt: float
    beta: float | None
    process_std: float | None

    @property
    def c_ar(self) -> float:
        """The coefficient in [TS]'s convention ``b_{k+1} + C_AR·b_k = e``: ``C_AR = −c``."""
        return -self.c

    @property
    def correlation_time(self) -> float | None:
        """Gauss–Markov correlation time ``1/β`` in seconds (``None`` if undefined)."""
        return None if self.beta is None else 1.0 / self.beta

    def to_dict(self) -> dict[str, Any]:
        """Plain-Python representation, with both sign conventions."""
        return {
            "c": self.c,
            "c_ar": self.c_ar,
            "c_std_error": self.c_std_error,
            "sigma_e": self.sigma_e,
            "mean": self.mean,
            "n": self.n,
            "dt": self.dt,
            "beta": self.beta,
            "correlation_time": self.correlation_time,
            "process_std": self.process_std,
        }


def fit_ar1(x: ArrayLike, fs: float = 1.0, *, demean: bool = True) -> AR1Fit:
    """Fit the first-order AR model ``b_{k+1} = c·b_k + e`` by least squares.

    Parameters
    ----------
    x : array_like, 1-D
        Drift samples (e.g. FIR-filtered gyro rate), regularly sampled.
    fs : float
        Sample rate in Hz (``Δt = 1/fs``, used for β and the correlation time).
    demean : bool
        Remove the sample mean first (default; a gyro's constant bias would otherwise
        dominate and give c ≈ 1).

    Returns
    -------
    AR1Fit

    Raises
    ------
    ValueError
        NaN/inf, fewer than 3 samples, ``fs ≤ 0``.
    gyrobias.GyroLinAlgError
        A constant series (c undefined).

    Notes
    -----
    ``ĉ = Σ b_k b_{k+1} / Σ b_k²`` (sums over the n − 1 pairs), ``s_e² = RSS/(n − 2)``,
    ``se(ĉ) = √(s_e²/Σ b_k²)``; ``β = −ln(ĉ)/Δt`` for 0 < ĉ < 1. [TS]'s ``C_AR = −ĉ`` (SPEC §9).

    Examples
    --------
    >>> import numpy as np
    >>> from gyrobias.thermal import fit_ar1
    >>> rng = np.random.default_rng(1)
    >>> b = np.zeros(20_000)
    >>> for k in range(1, b.size):
    ...     b[k] = 0.9 * b[k - 1] + rng.normal()
    >>> f = fit_ar1(b, fs=100.0)
    >>> round(f.c, 2), round(f.c_ar, 2)
    (0.9, -0.9)
    """
    arr = as_float_array("x", x)
    fs = sample_rate(fs)  # the core checks fs before dt = 1/fs is formed
    r = _core.thermal.fit_ar1(arr, 1.0 / fs, bool(demean))
    beta = float(r["beta"])
    pstd = float(r["process_std"])
    return AR1Fit(
        c=float(r["c"]),
        c_std_error=float(r["c_std_error"]),
        sigma_e=float(r["sigma_e"]),
        mean=float(r["mean"]),
        n=int(r["n"]),
        dt=1.0 / fs,
        beta=None if math.isnan(beta) else beta,
        process_std=None if math.isnan(pstd) else pstd,
    )


@dataclass(frozen=True)
class TemperatureModel:
    """Named noise parameters tabulated at distinct temperatures, interpolated in between.

    Parameters
    ----------
    temperatures : array_like
        Calibration temperatures (°C), distinct, any order (stored sorted).
    parameters : mapping of str to array_like
        Parameter name → one value per temperature (same order as ``temperatures``), e.g.
        ``{"arw": [...], "ar1_c": [...]}``. Any coefficients plug in.
    units : mapping of str to str, optional
        Unit of each parameter (for display and JSON).
    method : {"linear", "pchip", "polynomial"}
        Interpolation: piecewise linear, shape-preserving cubic (PCHIP, no overshoot between
        calibration points; SciPy's ``PchipInterpolator``), or least-squares polynomial.
    degree : int
        Polynomial degree (≤ number of temperatures − 1); ignored otherwise.

    Raises
    ------
    ValueError
        Fewer than 2 temperatures, duplicate temperatures, NaN/inf, a parameter with the wrong
        number of values, an unknown method or a degree the data cannot support.

    Examples
    --------
    >>> from gyrobias.thermal import TemperatureModel
    >>> m = TemperatureModel([-30, 0, 30, 60], {"arw": [2.23, 1.62, 1.95, 1.95]},
    ...                      units={"arw": "deg/sqrt(h)"}, method="linear")
    >>> round(m("arw", 15.0), 3)
    1.785
    """

    temperatures: NDArray[np.float64]
    parameters: Mapping[str, NDArray[np.float64]]
    units: Mapping[str, str] = field(default_factory=dict)
    method: str = "pchip"
    degree: int = 2

    def __post_init__(self) -> None:
        # Types and shapes here; the values (finite, at least 2 distinct temperatures, the
        # method's name, a degree the temperatures support) are the core's checks, run now by
        # evaluating each parameter's interpolant once (thermal::interpolate, which names them).
        temps = as_float_array("temperatures", self.temperatures)
        string("method", self.method)
        degree = integer("degree", self.degree)
        if not isinstance(self.parameters, Mapping) or not self.parameters:
            raise ValueError("parameters must be a non-empty mapping of name -> values")
        order = np.argsort(temps, kind="stable")
        st = temps[order]
        params: dict[str, NDArray[np.float64]] = {}
        for name, values in self.parameters.items():
            if not isinstance(name, str):
                raise TypeError(f"parameter names must be strings, got {name!r}")
            v = as_float_array(f"parameters[{name!r}]", values)
            if v.size != temps.size:
                raise ValueError(
                    f"parameters[{name!r}] has {v.size} values for {temps.size} temperatures"
                )
            try:
                _core.thermal.interpolate(temps, v, self.method, degree, temps[:1], False)
            except ValueError as exc:
                if str(exc).startswith("values "):  # the core calls them values
                    raise ValueError(f"parameters[{name!r}]: {exc}") from None
                raise
            params[name] = v[order].copy()
        object.__setattr__(self, "temperatures", st.copy())
        object.__setattr__(self, "parameters", params)
        if not isinstance(self.units, Mapping):
            raise TypeError(
                f"units must be a mapping parameter name -> unit, got {type(self.units).__name__}"
            )
        object.__setattr__(self, "units", dict(self.units))
        object.__setattr__(self, "degree", degree)

    @property
    def names(self) -> tuple[str, ...]:
        """Parameter names."""
        return tuple(self.parameters)

    @property
    def range(self) -> tuple[float, float]:
        """Calibrated temperature range (°C)."""
        return float(self.temperatures[0]), float(self.temperatures[-1])

    def __call__(self, name: str, temperature: ArrayLike, *, extrapolate: bool = False) -> Any:
        """Parameter ``name`` at ``temperature`` (scalar in → float out, array in → array out).

        Raises ``ValueError`` for a temperature outside the calibrated range unless
        ``extrapolate=True`` (then the end segment / end cubic / polynomial is continued).
        """
        if not isinstance(name, str) or name not in self.parameters:
            raise ValueError(
                f"name must be one of {', '.join(map(repr, self.names))}; got {name!r} "
                "(unknown parameter)"
            )
        as_float_array("temperature", temperature, ndims=tuple(range(33)))  # type and shape
        at = np.asarray(temperature, dtype=np.float64)
        flat = np.ascontiguousarray(at.reshape(-1))
        if flat.size == 0:
            raise ValueError("temperature is empty")
        out = _core.thermal.interpolate(
            self.temperatures,
            self.parameters[name],
            self.method,
            self.degree,
            flat,
            bool(extrapolate),
        )
        if at.ndim == 0:
            return float(out[0])
        return out.reshape(at.shape)

    def evaluate(self, temperature: float, *, extrapolate: bool = False) -> dict[str, float]:
        """All parameters at one temperature."""
        t = real("temperature", temperature)
        return {n: float(self(n, t, extrapolate=extrapolate)) for n in self.names}

    def to_dict(self) -> dict[str, Any]:
        """Plain-Python representation (what :meth:`to_json` writes)."""
        return {
            "temperatures": self.temperatures.tolist(),
            "parameters": {k: v.tolist() for k, v in self.parameters.items()},
            "units": dict(self.units),
            "method": self.method,
            "degree": self.degree,
        }

    def to_json(self, **kwargs: Any) -> str:
        """JSON text of :meth:`to_dict`."""
        return json.dumps(self.to_dict(), **kwargs)

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> TemperatureModel:
        """Inverse of :meth:`to_dict`."""
        mapping("data", data)
        try:
            return cls(
                temperatures=np.asarray(data["temperatures"], dtype=np.float64),
                parameters={
                    k: np.asarray(v, dtype=np.float64) for k, v in data["parameters"].items()
                },
                units=dict(data.get("units", {})),
                method=data.get("method", "pchip"),
                degree=int(data.get("degree", 2)),
            )
        except KeyError as exc:
            raise ValueError(f"temperature model data lacks the key {exc.args[0]!r}") from exc
        except (AttributeError, TypeError) as exc:
            # e.g. "parameters" not a mapping, or "temperatures" of strings
            raise ValueError(
                "data must be a temperature model (keys temperatures, parameters: name → values, "
                f"units, method, degree), got an invalid structure: {exc}"
            ) from None

    @classmethod
    def from_json(cls, text: str) -> TemperatureModel:
        """Inverse of :meth:`to_json`.

        Raises ``ValueError`` naming the line and column for text that is not JSON, and for
        JSON that is not a temperature model; ``TypeError`` if ``text`` is not a string.
        """
        if not isinstance(text, (str, bytes, bytearray)):
            raise TypeError(f"text must be a JSON string, got {type(text).__name__}")
        try:
            data = json.loads(text)
        except json.JSONDecodeError as exc:
            raise ValueError(
                f"text is not valid JSON: {exc.msg} at line {exc.lineno}, column {exc.colno}"
            ) from None
        except UnicodeDecodeError as exc:
            raise ValueError(f"text is not valid JSON: {exc}") from None
        if not isinstance(data, Mapping):
            raise ValueError(
                f"text must hold a JSON object (a temperature model), got {type(data).__name__}"
            )
        return cls.from_dict(data)

    @classmethod
    def from_analyses(
        cls, analyses: Iterable[ThermalAnalysis], *, method: str = "pchip", degree: int = 2
    ) -> TemperatureModel:
        """Model of the scalar parameters of per-temperature :class:`ThermalAnalysis` results."""
        items = sequence("analyses", analyses)
        if not items:
            raise ValueError("analyses is empty")
        for i, a in enumerate(items):
            if not isinstance(a, ThermalAnalysis):
                raise TypeError(f"analyses[{i}] must be a ThermalAnalysis, got {type(a).__name__}")
        names = list(items[0].parameters())
        params = {n: np.array([a.parameters()[n] for a in items]) for n in names}
        return cls(
            np.array([a.temperature for a in items]),
            params,
            units=items[0].parameter_units(),
            method=method,
            degree=degree,
        )

    def table(self) -> str:
        """Text table, one row per calibration temperature."""
        names = self.names
        head = f"{'T [°C]':>8} " + " ".join(f"{n:>16}" for n in names)
        unit_row = f"{'':>8} " + " ".join(f"{self.units.get(n, ''):>16}" for n in names)
        rows = [head, unit_row]
        for i, t in enumerate(self.temperatures):
            rows.append(f"{t:8.2f} " + " ".join(f"{self.parameters[n][i]:16.6g}" for n in names))
        return "\n".join(rows)


@dataclass(frozen=True)
class ThermalAnalysis:
    """Noise analysis of one static log at one temperature ([TS] Tables 1–5 in one row).

    Attributes
    ----------
    temperature : float
        °C.
    fs : float
        Sample rate in Hz.
    n : int
        Samples.
    arw : float
        White-noise coefficient N read off the Allan deviation at τ ≈ 1 s,
        ``N = σ(τ)·√τ`` (IEEE 952), in unit·√s (e.g. deg/√s = (deg/s)/√Hz).
    bias_instability : float
        ``min σ(τ) / 0.664282`` over octave τ (IEEE 952 flicker floor), in the unit of the data.
    noise_density : float
        One-sided PSD white-noise density (unit/√Hz) of the raw log (:func:`noise_density`).
    ar1 : AR1Fit
        AR(1) fit of the (FIR-filtered) log.
    filter_cutoff : float or None
        Cut-off (Hz) of the Kaiser prefilter, ``None`` if the log was not filtered.
    unit : str or None
        Unit of the samples.
    """

    temperature: float
    fs: float
    n: int
    arw: float
    bias_instability: float
    noise_density: float
    ar1: AR1Fit
    filter_cutoff: float | None
    unit: str | None = None

    def parameters(self) -> dict[str, float]:
        """Scalar parameters for a :class:`TemperatureModel`."""
        p = {
            "arw": self.arw,
            "bias_instability": self.bias_instability,
            "noise_density": self.noise_density,
            "ar1_c": self.ar1.c,
            "ar1_c_std_error": self.ar1.c_std_error,
            "ar1_sigma_e": self.ar1.sigma_e,
        }
        return p

    def parameter_units(self) -> dict[str, str]:
        """Units of :meth:`parameters`."""
        u = self.unit or "unit"
        return {
            "arw": f"{u}·√s",
            "bias_instability": u,
            "noise_density": f"{u}/√Hz",
            "ar1_c": "1",
            "ar1_c_std_error": "1",
            "ar1_sigma_e": u,
        }

    def to_dict(self) -> dict[str, Any]:
        """Plain-Python representation."""
        return {
            "temperature": self.temperature,
            "fs": self.fs,
            "n": self.n,
            "arw": self.arw,
            "bias_instability": self.bias_instability,
            "noise_density": self.noise_density,
            "ar1": self.ar1.to_dict(),
            "filter_cutoff": self.filter_cutoff,
            "unit": self.unit,
        }


def analyse_log(
    x: ArrayLike,
    fs: float,
    temperature: float,
    *,
    prefilter: bool = True,
    zero_phase: bool = False,
    fpass: float | None = None,
    fstop: float | None = None,
    apass_db: float = 0.0001,
    astop_db: float = 100.0,
    units: str | None = None,
) -> ThermalAnalysis:
    """Analyse one static log recorded at ``temperature``.

    Parameters
    ----------
    x : array_like, 1-D
        Rate samples (e.g. deg/s) of one axis.
    fs : float
        Sample rate in Hz.
    temperature : float
        °C.
    prefilter : bool
        Low-pass the log with a Kaiser FIR before the AR(1) fit, as [TS] §4.3.
    zero_phase : bool
        Filter forward–backward instead of causally. Default ``False``: the causal convolution
        of [TS] eq. 20 (its first ``N − 1`` output samples, the start-up transient, are dropped
        before the fit), which reproduces the SPEC §9 check (white noise → c = 0.961 / 0.846 /
        0.670 at fc = 8/16/24 Hz); forward–backward filtering squares the magnitude response
        and gives a slightly larger c (0.964 / 0.851 / 0.677).
    fpass, fstop : float, optional
        Filter band edges in Hz; default ``0.14·fs`` and ``0.18·fs`` ([TS] Fig. 12: 14/18 Hz at
        100 Hz, cut-off 16 Hz).
    apass_db, astop_db : float
        Filter attenuations in dB (Skaloud's 0.0001 and 100 dB).
    units : str, optional
        Unit of ``x``.

    Notes
    -----
    ARW from the overlapping Allan deviation at τ = m/fs with ``m = round(fs)`` (τ ≈ 1 s),
    ``N = σ(τ)√τ``; bias instability ``min_τ σ(τ)/0.664282`` over octave τ — both the IEEE-952
    read-off of :func:`gyrobias.noise.fit` (``method="ieee"``) on those regions; noise density
    from the Welch PSD of the raw log; AR(1) on the filtered log (mean removed).
    """
    from gyrobias import allan, fir, noise, spectral

    arr = as_float_array("x", x)
    fs = sample_rate(fs)  # the core checks fs before round(fs) and m/fs
    temperature = real("temperature", temperature)  # a real number (10**400 included)
    try:  # finite: the core's check (of a set of temperatures, here one)
        _core.thermal.check_temperatures(np.array([temperature]))
    except ValueError:
        raise ValueError(f"temperature must be finite, got {temperature!r}") from None
    units = checked_units("units", units)
    boolean("prefilter", prefilter)
    # The prefilter is designed (its options checked) even when prefilter=False ignores it:
    # an out-of-range option is refused whether or not this call reads it.
    design = fir.kaiser_lowpass(
        fs,
        0.14 * fs if fpass is None else fpass,
        0.18 * fs if fstop is None else fstop,
        apass_db=apass_db,
        astop_db=astop_db,
    )
    m = max(1, int(round(fs)))
    if 2 * m > len(arr):  # the τ ≈ 1 s read-off this function chooses (adev needs n >= 2m)
        raise ValueError(
            f"x is too short for the ARW read-off at τ = 1 s: {len(arr)} samples at fs = {fs:g} "
            f"Hz hold {len(arr) / fs:.3g} s, at least 2 s ({2 * m} samples) are needed"
        )
    one = cast("allan.AllanResult", allan.adev(arr, fs, taus=[m / fs], confidence=None))
    oct_ = cast("allan.AllanResult", allan.adev(arr, fs, taus="octave", confidence=None))
    # The IEEE-952 read-off of the noise module, on the regions [TS] reads: N on the −½ line
    # through the point at τ ≈ 1 s (σ(τ)·√τ), B = min σ / FLICKER_FACTOR over the octave curve.
    everywhere = (0.0, math.inf)
    arw = _read(noise.fit(one, method="ieee", terms=("N",), regions={"N": everywhere}), "N")
    bias = _read(noise.fit(oct_, method="ieee", terms=("B",), regions={"B": everywhere}), "B")
    nd = spectral.noise_density(arr, fs, units=units).density
    cutoff: float | None = None
    data = arr
    if prefilter:
        cutoff = design.cutoff
        data = design.apply(arr, zero_phase=bool(zero_phase))
        if not zero_phase:
            # The causal filter's transient is dropped; too few samples left is fit_ar1's
            # (the core's) TooShort error.
            data = data[design.numtaps - 1 :]
    return ThermalAnalysis(
        temperature=float(temperature),
        fs=fs,
        n=int(arr.size),
        arw=arw,
        bias_instability=bias,
        noise_density=nd,
        ar1=fit_ar1(data, fs),
        filter_cutoff=cutoff,
        unit=units,
    )


def _read(coefficients: Any, symbol: str) -> float:
    """The value of one read-off term (NaN if the read-off reports it missing)."""
    value = coefficients[symbol].value
    return math.nan if value is None else float(value)


def analyse_logs(
    logs: Mapping[float, ArrayLike] | Iterable[tuple[float, ArrayLike]],
    fs: float,
    **kwargs: Any,
) -> tuple[ThermalAnalysis, ...]:
    """:func:`analyse_log` for each ``temperature → samples`` pair, sorted by temperature.

    Raises ``ValueError`` if two logs carry the same temperature.
    """
    pairs = list(logs.items()) if isinstance(logs, Mapping) else sequence("logs", logs)
    for i, pair in enumerate(pairs):
        if isinstance(pair, (str, bytes)) or not isinstance(pair, (tuple, list)) or len(pair) != 2:
            raise TypeError(
                "logs must be a mapping temperature -> samples or a sequence of (temperature, "
                f"samples) pairs; item {i} is {type(pair).__name__}"
            )
    if not pairs:
        raise ValueError("logs is empty")
    temps = [real("temperature", t) for t, _ in pairs]
    # Finite and distinct: the core's check, before any log is analysed.
    _core.thermal.check_temperatures(np.array(temps, dtype=np.float64))
    out = [analyse_log(x, fs, t, **kwargs) for t, x in pairs]
    return tuple(sorted(out, key=lambda a: a.temperature))


def build_temperature_model(
    logs: Mapping[float, ArrayLike] | Iterable[tuple[float, ArrayLike]],
    fs: float,
    *,
    method: str = "pchip",
    degree: int = 2,
    **kwargs: Any,
) -> TemperatureModel:
    """Analyse several temperature-tagged logs and interpolate their parameters in temperature.

    ``logs`` maps temperature (°C) → rate samples (or is a sequence of such pairs); ``kwargs``
    go to :func:`analyse_log` (``prefilter``, ``fpass``, ``fstop``, ``units``, …). The model's
    parameters are those of :meth:`ThermalAnalysis.parameters`.

    Examples
    --------
    >>> import numpy as np
    >>> from gyrobias.thermal import build_temperature_model
    >>> rng = np.random.default_rng(0)
    >>> logs = {t: rng.normal(0.0, 0.01 * (1 + t / 100), 20_000) for t in (-30.0, 0.0, 30.0, 60.0)}
    >>> m = build_temperature_model(logs, fs=100.0, units="deg/s")
    >>> bool(m("arw", -30.0) < m("arw", 60.0))
    True
    """
    return TemperatureModel.from_analyses(
        analyse_logs(logs, fs, **kwargs), method=method, degree=degree
    )
