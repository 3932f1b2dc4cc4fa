"""Bias prediction from a calibration window ([BP] §IV–V).

A vehicle stops; the gyro output during the standstill (``k`` samples) is a calibration window
and the bias is predicted for the ``h`` samples of the drive that follows. Three predictors:

- :func:`calibration_mean` — the mean of the window ([BP] eq. 9);
- :func:`moving_average` — the mean of the last ``j`` samples for the ``j``-th step ([BP] eq. 8);
- :class:`FractionalKalmanPredictor` — the optimal predictor under a 1/f (ARFIMA(0, d, 0)) bias
  plus white noise ([BP] §IV-A), with the standard deviations of the forecast.

plus the metrics :func:`integrated_error` and :func:`rsse` and :func:`evaluate`, which runs
[BP]'s batch test (§V-C, Table I) on a long static log. All computations run in the Rust core;
a window or horizon is in samples, rates in the caller's unit.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gyrobias import _core, _generics
from gyrobias._validation import (
    as_float_array,
    choice,
    integer,
    real,
    sequence,
    string,
)
from gyrobias._validation import seed as seed_value

__all__ = [
    "CompiledPredictor",
    "Evaluation",
    "FractionalKalmanPredictor",
    "MethodStats",
    "Prediction",
    "calibration_mean",
    "evaluate",
    "integrated_error",
    "moving_average",
    "rsse",
]

_MEAN_MODES = ("sample", "diffuse", "none")


def _n_threads(n_threads: int | None) -> int:
    """``n_threads`` for the core, where 0 means "one per core": ``None`` → 0; an explicit 0 is
    refused here, since the core would read it as that default."""
    if n_threads is None:
        return 0
    n = integer("n_threads", n_threads)
    if n <= 0:
        raise ValueError(f"n_threads must be a positive integer or None, got {n}")
    return n


def _windows(name: str, value: Any) -> tuple[NDArray[np.float64], bool]:
    """``value`` as a C-contiguous (windows × k) array and whether it was 1-D."""
    try:
        arr = as_float_array(name, value, ndims=(1, 2))
    except ValueError as exc:
        if "inhomogeneous" in str(exc) or "sequence" in str(exc):
            raise ValueError(
                f"{name} has ragged rows: every window must have the same length"
            ) from exc
        raise
    one = arr.ndim == 1  # k >= 2 and finite samples: the core's checks
    return (arr.reshape(1, -1) if one else arr), one


def _asarray_ragged(name: str, value: Any) -> Any:
    if (
        isinstance(value, (list, tuple))
        and value
        and all(isinstance(v, (list, tuple, np.ndarray)) for v in value)
    ):
        lengths = {len(v) for v in value}
        if len(lengths) > 1:
            raise ValueError(
                f"{name} has ragged rows (lengths {sorted(lengths)}): every window must have the same length"
            )
    return value


def _named(name: str, kernel: Any, *args: Any) -> NDArray[np.float64]:
    """``kernel(*args)``, a core error about the calibration window prefixed with ``name``, the
    caller's name for it (the core calls it ``calibration``)."""
    try:
        return kernel(*args)  # type: ignore[no-any-return]
    except ValueError as exc:
        if "calibration" in str(exc):
            raise ValueError(f"{name}: {exc}") from None
        raise


def calibration_mean(y: Any, horizon: int) -> NDArray[np.float64]:
    """Calibration-mean bias forecast ([BP] eq. 9).

    Parameters
    ----------
    y : array_like, shape (k,) or (windows, k)
        Calibration window(s), k ≥ 2 finite samples.
    horizon : int
        Number of future samples h ≥ 1.

    Returns
    -------
    ndarray, shape (h,) or (windows, h)
        ``ŷ_j = mean(y_0..y_{k−1})`` for every step j.
    """
    arr, one = _windows("y", _asarray_ragged("y", y))
    h = integer("horizon", horizon)
    out = _named("y", _core.predict.calibration_mean, arr, h).reshape(arr.shape[0], h)
    return out[0] if one else out


def moving_average(y: Any, horizon: int) -> NDArray[np.float64]:
    """Moving-average bias forecast ([BP] eq. 8, extended by eq. 9).

    Notes
    -----
    For ``1 ≤ j ≤ k`` the forecast of step ``j`` is the mean of the last ``j`` calibration samples
    (``ŷ_1 = y_{k−1}``); for ``j > k`` it is the calibration mean.

    Parameters and returns as :func:`calibration_mean`.
    """
    arr, one = _windows("y", _asarray_ragged("y", y))
    h = integer("horizon", horizon)
    out = _named("y", _core.predict.moving_average, arr, h).reshape(arr.shape[0], h)
    return out[0] if one else out


def _pair(y: Any, yhat: Any) -> tuple[NDArray[np.float64], NDArray[np.float64], bool]:
    """``y`` and ``yhat`` as 2-D float64 arrays (rows along the first axis) and whether 1-D."""
    a = as_float_array("y", y, ndims=(1, 2))
    b = as_float_array("yhat", yhat, ndims=(1, 2))
    if a.ndim != b.ndim:  # a type/shape check; equal row lengths are the core's
        raise ValueError(f"y and yhat must have the same shape, got {a.shape} and {b.shape}")
    one = a.ndim == 1
    return (a.reshape(1, -1), b.reshape(1, -1), one) if one else (a, b, one)


def integrated_error(y: Any, yhat: Any) -> NDArray[np.float64] | float:
    """Integrated error ``IE = Σ_j (y_j − ŷ_j)`` (data minus prediction) along the last axis.

    Computed in the core (``gyrocore::predict::evaluate::integrated_error``, a compensated sum).
    """
    a, b, one = _pair(y, yhat)
    out = _core.predict.integrated_error(a, b)
    return float(out[0]) if one else out


def rsse(y: Any, yhat: Any) -> NDArray[np.float64] | float:
    """Root of the sum of squared errors ``√Σ_j (y_j − ŷ_j)²`` along the last axis.

    Where the squares overflow it is computed as ``s·√Σ(d_j/s)²`` with ``s = max|d_j|``, so
    errors up to the float64 limit give a finite root; ``y`` and ``yhat`` must be finite.

    Notes
    -----
    [BP]'s text defines the plain sum of squares; its Table I values need the root (SPEC §5).
    Computed in the core (``gyrocore::predict::evaluate::rsse``).
    """
    a, b, one = _pair(y, yhat)
    out = _core.predict.rsse(a, b)
    return float(out[0]) if one else out


@dataclass(frozen=True)
class Prediction:
    """A bias forecast with its uncertainty.

    Attributes
    ----------
    bias : ndarray, shape (h,) or (windows, h)
        Predicted bias for the h samples after the calibration window (caller's rate unit).
    std : ndarray, same shape
        Standard deviation of the bias forecast error (±2·std is the ~95 % band of the bias).
    std_observation : ndarray, same shape
        Standard deviation of a future *observation* around the forecast (white noise included).
    mean : float or ndarray, shape (windows,)
        Estimated mean state m̂ (the constant part of the bias).
    mean_std : float
        Standard deviation of m̂ (0 for ``mean="sample"``/``"none"``).
    """

    bias: NDArray[np.float64]
    std: NDArray[np.float64]
    std_observation: NDArray[np.float64]
    mean: NDArray[np.float64] | float
    mean_std: float

    def to_dict(self) -> dict[str, Any]:
        """Plain-Python dictionary (lists), e.g. for JSON."""
        mean = self.mean.tolist() if isinstance(self.mean, np.ndarray) else self.mean
        return {
            "bias": self.bias.tolist(),
            "std": self.std.tolist(),
            "std_observation": self.std_observation.tolist(),
            "mean": mean,
            "mean_std": self.mean_std,
        }


def _mean_spec(mean: Any) -> tuple[str, float, float]:
    """(mode, mu0, p0) for the core from ``mean`` (types here; values are the core's checks)."""
    if isinstance(mean, str):
        return string("mean", mean), 0.0, 0.0
    if isinstance(mean, (tuple, list)) and len(mean) == 2:
        mu0, p0 = real("mu0", mean[0]), real("p0", mean[1])
        if p0 == math.inf:
            return "diffuse", 0.0, 0.0
        return "proper", mu0, p0
    raise TypeError(f"mean must be 'sample', 'diffuse', 'none' or a pair (mu0, p0); got {mean!r}")


def _is_dtype(dtype: Any, name: str) -> bool:
    """``dtype`` names the NumPy float type ``name`` (the type, a str or an np.dtype)."""
    if dtype is getattr(np, name):
        return True
    return isinstance(dtype, (str, np.dtype)) and dtype == name


class CompiledPredictor:
    """A fractional Kalman predictor compiled to the linear map ``ŷ = W·y + w0``.

    Built by :meth:`FractionalKalmanPredictor.compile`. :meth:`predict` on a (windows × k) batch
    is one matrix product in the Rust core (multi-threaded, GIL released). Immutable and safe to
    share between threads.
    """

    def __init__(self, inner: Any, predictor: FractionalKalmanPredictor) -> None:
        self._inner = inner
        self.predictor = predictor

    @property
    def calibration_length(self) -> int:
        """k, the window length the map was compiled for."""
        return int(self._inner.calibration_length)

    @property
    def horizon(self) -> int:
        """h, the number of predicted samples."""
        return int(self._inner.horizon)

    @property
    def weights(self) -> NDArray[np.float64]:
        """W, shape (h, k)."""
        return self._inner.weights  # type: ignore[no-any-return]

    @property
    def offset(self) -> NDArray[np.float64]:
        """w0, shape (h,) (nonzero only for a proper mean prior)."""
        return self._inner.offset  # type: ignore[no-any-return]

    def to_c(
        self, path: Any, *, name: str = "gyro_pred", dtype: Any = "float32", **options: Any
    ) -> Any:
        """Write ``ŷ = W·y + w0`` over a sliding window as C99 (``<name>.h``/``.c`` in ``path``).

        ``dtype`` is ``"float64"``, ``"float32"`` or ``"q31"``. See :mod:`gyrobias.codegen`;
        returns its :class:`~gyrobias.codegen.GeneratedC`.
        """
        return _generics.to_c(self, path, name=name, dtype=dtype, **options)

    def predict(self, batch: Any, *, n_threads: int | None = None, dtype: Any = None) -> Prediction:
        """Forecast every window of ``batch`` (shape (windows, k) or (k,)).

        Parameters
        ----------
        batch : array_like, shape (windows, k) or (k,)
            Calibration windows, oldest sample first.
        n_threads : int, optional
            Threads of the matrix product (default: one per core; unused with ``dtype``).
        dtype : {None, np.float64, np.float32}
            ``None`` (default): one matrix product ``Y·Wᵀ + w0`` (blocked, multi-threaded; the
            fast path, float64). ``np.float64`` or ``np.float32``: the evaluation order of the
            C that :meth:`to_c` writes, in that precision — per forecast ``acc = 0;
            acc += W[j][i]·y[i]`` for ``i = 0..k−1``, then ``+ w0[j]``, with ``W``, ``w0`` and
            the windows rounded to the type first — so ``bias`` (of that dtype) equals
            ``to_c(dtype="float64"/"float32")`` bit for bit. Sequential, one thread; it
            differs from the default by rounding only (a k-term sum in another order).
        """
        arr, one = _windows("batch", _asarray_ragged("batch", batch))
        threads = _n_threads(n_threads)
        if dtype is None:
            # A window length other than calibration_length is the core's ShapeMismatch.
            bias, mean = self._inner.predict(arr, threads)
        elif _is_dtype(dtype, "float32"):
            with np.errstate(over="ignore"):  # beyond float32: inf, refused by the core
                arr32 = np.ascontiguousarray(arr, dtype=np.float32)
            bias, mean = self._inner.predict_sequential_f32(arr32)
        elif _is_dtype(dtype, "float64"):
            bias, mean = self._inner.predict_sequential(arr)
        else:
            raise ValueError(f"dtype must be None, np.float64 or np.float32, got {dtype!r}")
        rows, h = arr.shape[0], self.horizon
        bias = bias.reshape(rows, h)
        std = np.broadcast_to(self._inner.std, (rows, h))
        std_obs = np.broadcast_to(self._inner.std_observation, (rows, h))
        if one:
            return Prediction(
                bias[0], std[0], std_obs[0], float(mean[0]), float(self._inner.mean_std)
            )
        return Prediction(bias, std, std_obs, mean, float(self._inner.mean_std))


@dataclass(frozen=True)
class FractionalKalmanPredictor:
    """The fractional (1/f) Kalman bias predictor of [BP] §IV-A.

    Parameters
    ----------
    d : float
        Memory parameter of the ARFIMA(0, d, 0) bias, −½ < d < 3/2 (½ is flicker / 1/f noise).
    q : float
        Variance of the driving white noise per sample (> 0), in (rate unit)².
    r : float
        Variance of the white measurement noise per sample (≥ 0), in (rate unit)².
    mean : {"sample", "diffuse", "none"} or (mu0, p0)
        Prior of the constant mean state m: the calibration sample mean held fixed ("sample",
        [BP]'s reading and the default), an exactly infinite prior ("diffuse": the GLS/BLUP
        estimate), m = 0 ("none"), or a proper prior N(mu0, p0) (p0 = 0: known mean,
        p0 = inf: diffuse).
    algorithm : {"schur", "literal"}
        "schur" (default): generalized Schur algorithm, O(n·k) time and O(n) memory;
        "literal": [BP]'s growing-state Kalman filter, O(n³) (reference, small n only).

    Notes
    -----
    Model (SPEC §5), with time 0 the first calibration sample::

        x_t = Σ_{l=1}^{t} φ_l x_{t−l} + w_t,  φ_l = −π_l(d),  w_t ~ N(0, q),  x_0 = w_0
        y_t = m + x_t + v_t,                   v_t ~ N(0, r)

    with ``π_0 = 1, π_l = π_{l−1}(l − 1 − d)/l`` (the type-II fractional difference; [BP] eq. 3 is
    misprinted, SPEC §4). The forecast is ``b̂_t = m̂ + x̂_t`` with variance
    ``P_mm + 2P_mx + P_xx``; an observation adds ``r``. Both algorithms give the same numbers
    (to ~1e-13).

    References
    ----------
    [BP] M. Kirkko-Jaakkola, J. Collin, J. Takala, "Bias prediction for MEMS gyroscopes",
    IEEE Sensors Journal 12(6), 2012, §IV-A.

    Examples
    --------
    >>> import numpy as np
    >>> from gyrobias.predict import FractionalKalmanPredictor
    >>> y = np.cumsum(np.random.default_rng(0).standard_normal(200)) * 0.01 + 0.3
    >>> p = FractionalKalmanPredictor(d=0.5, q=1e-4, r=1e-4).predict(y, 100)
    >>> p.bias.shape, bool(np.all(p.std > 0))
    ((100,), True)
    """

    d: float = 0.5
    q: float = 1.0
    r: float = 0.0
    mean: Any = "sample"
    algorithm: str = "schur"
    _spec: tuple[str, float, float] = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        for name in ("d", "q", "r"):
            object.__setattr__(self, name, real(name, getattr(self, name)))
        object.__setattr__(self, "_spec", _mean_spec(self.mean))
        string("algorithm", self.algorithm)
        # The model's preconditions (−½ < d < 3/2, q > 0, r ≥ 0, the prior, the algorithm's
        # name) are the core's; checked now so that a bad predictor fails where it is made.
        _core.predict.validate_model(*self._args(), self.algorithm)

    def _args(self) -> tuple[float, float, float, str, float, float]:
        mode, mu0, p0 = self._spec
        return self.d, self.q, self.r, mode, mu0, p0

    def predict(
        self, calibration: Any, horizon: int, *, n_threads: int | None = None
    ) -> Prediction:
        """Forecast the bias for ``horizon`` samples after each calibration window.

        Parameters
        ----------
        calibration : array_like, shape (k,) or (windows, k)
            Calibration window(s) of k ≥ 2 finite samples.
        horizon : int
            Number of samples to predict, h ≥ 1.
        n_threads : int, optional
            Threads for many windows (default: all).

        Returns
        -------
        Prediction
            1-D fields for 1-D input, (windows, h) fields for 2-D input.

        Raises
        ------
        ValueError
            Bad input (too short, non-finite, ragged rows, parameters out of range).
        gyrobias.GyroLinAlgError
            The problem is numerically singular or ill-conditioned (never a silent NaN).
        """
        arr, one = _windows("calibration", _asarray_ragged("calibration", calibration))
        h = integer("horizon", horizon)
        res = _core.predict.fractional_kalman(
            arr, h, *self._args(), self.algorithm, _n_threads(n_threads)
        )
        rows = arr.shape[0]
        bias = res["bias"].reshape(rows, h)
        if one:
            return Prediction(
                bias[0],
                res["std"],
                res["std_observation"],
                float(res["mean"][0]),
                float(res["mean_std"]),
            )
        std = np.broadcast_to(res["std"], (rows, h))
        std_obs = np.broadcast_to(res["std_observation"], (rows, h))
        return Prediction(bias, std, std_obs, res["mean"], float(res["mean_std"]))

    def compile(
        self, calibration_length: int, horizon: int, *, n_threads: int | None = None
    ) -> CompiledPredictor:
        """Precompute the linear map ``ŷ = W·y + w0`` for windows of ``calibration_length``.

        Compiling costs O(n·k) memory and one triangular solve; afterwards a batch of R windows
        is one (R × k)·(k × h) matrix product.
        """
        k = integer("calibration_length", calibration_length)  # k >= 2: the core's check
        h = integer("horizon", horizon)
        inner = _core.predict.CompiledPredictor(k, h, *self._args(), _n_threads(n_threads))
        return CompiledPredictor(inner, self)

    @classmethod
    def from_noise(
        cls,
        coefficients: Any = None,
        fs: float | None = None,
        d: float = 0.5,
        *,
        arw: float | None = None,
        bias_instability: float | None = None,
        mean: Any = "sample",
    ) -> FractionalKalmanPredictor:
        """Model parameters from Allan-variance noise coefficients.

        Parameters
        ----------
        coefficients : object with attributes ``N`` and ``B``, optional
            E.g. :class:`gyrobias.noise.NoiseCoefficients`; ``N.value`` is the angle random walk
            in (rate unit)·√s (u/√s for u = deg/s: deg/√s), ``B.value`` the bias instability in
            the rate unit (both base units).
        fs : float
            Sample rate in Hz.
        d : float
            Memory parameter (default ½; e.g. from :func:`gyrobias.fractional.elw`).
        arw, bias_instability : float, optional
            N and B as plain floats instead of ``coefficients``.
        mean : see :class:`FractionalKalmanPredictor`

        Notes
        -----
        White noise: rate white noise of per-sample variance σ_w² at period t0 has the two-sided
        PSD N², i.e. ``N² = σ_w²·t0`` (IEEE 952), so ``r = N²·fs``.

        1/f noise: the ARFIMA(0, d, 0) process driven by variance q has the two-sided PSD
        ``S(f) = q·t0·|2 sin(π f t0)|^(−2d)``, which for d = ½ and f ≪ fs is ``q/(2π f)``; the
        flicker PSD with bias instability B is ``B²/(2π f)`` (IEEE 952; Allan plateau
        0.664·B). Hence **q = B²** for d = ½, independent of fs (per-sample units). For d ≠ ½
        the spectra have different slopes; q = B² then matches them at ω = 2π f t0 = 1 rad/sample
        — treat it as a starting value and estimate d from data.
        """
        if coefficients is not None:
            if arw is not None or bias_instability is not None:
                raise ValueError("give either coefficients or arw=/bias_instability=, not both")
            try:
                arw = float(coefficients.N.value)
                bias_instability = float(coefficients.B.value)
            except AttributeError as exc:
                raise TypeError(
                    "coefficients must have attributes N and B with a float .value (e.g. "
                    "gyrobias.noise.NoiseCoefficients)"
                ) from exc
        if arw is None or bias_instability is None:
            raise ValueError("from_noise needs coefficients or both arw= and bias_instability=")
        if fs is None:
            raise ValueError("fs (the sample rate in Hz) is required")
        # q = B², r = N²·fs and the ranges of arw, bias_instability and fs are the core's.
        q, r = _core.predict.noise_parameters(
            real("arw", arw), real("bias_instability", bias_instability), real("fs", fs)
        )
        return cls(d=d, q=q, r=r, mean=mean)


# --- batch test ([BP] §V-C, Table I) -------------------------------------------------------------

_METHOD_NAMES = {"kf": "fractional Kalman", "ma": "moving average", "cm": "calibration mean"}


@dataclass(frozen=True)
class MethodStats:
    """Table I statistics of one method over the sections of a log.

    ``ie``/``rsse`` hold the per-section values; the summary fields are their mean and sample
    standard deviation (ddof = 1).
    """

    method: str
    ie: NDArray[np.float64]
    rsse: NDArray[np.float64]

    @property
    def mean_ie(self) -> float:
        """Mean integrated error."""
        return _core.predict.mean_std(self.ie)[0]

    @property
    def ie_std(self) -> float:
        """Standard deviation of the integrated error."""
        return _core.predict.mean_std(self.ie)[1]

    @property
    def mean_rsse(self) -> float:
        """Mean RSSE."""
        return _core.predict.mean_std(self.rsse)[0]

    @property
    def rsse_std(self) -> float:
        """Standard deviation of the RSSE."""
        return _core.predict.mean_std(self.rsse)[1]

    def to_dict(self) -> dict[str, Any]:
        """Summary statistics as a dictionary."""
        return {
            "method": self.method,
            "mean_ie": self.mean_ie,
            "ie_std": self.ie_std,
            "mean_rsse": self.mean_rsse,
            "rsse_std": self.rsse_std,
        }


@dataclass(frozen=True)
class Evaluation:
    """Result of :func:`evaluate`: per-method statistics over ``sections`` disjoint sections."""

    calibration: int
    horizon: int
    sections: int
    methods: dict[str, MethodStats]

    def ratio(
        self,
        method: str,
        reference: str = "cm",
        statistic: str = "rsse",
        *,
        resamples: int = 400,
        seed: int = 12345,
    ) -> tuple[float, float]:
        """Ratio of a statistic to the reference method's with a paired bootstrap standard error.

        ``statistic`` is ``"rsse"`` (ratio of mean RSSEs) or ``"ie_std"`` (ratio of IE standard
        deviations). The standard error is the s.d. of the ratio over ``resamples`` paired
        bootstrap resamples of the sections, drawn by the core's generator from ``seed`` (fixed
        by default, so the numbers are reproducible); NaN with fewer than 10 sections
        (``gyrocore::predict::evaluate::bootstrap_ratio``).
        """
        names = tuple(self.methods)
        a = self.methods[choice("method", method, names)]
        b = self.methods[choice("reference", reference, names)]
        pick = "rsse" if statistic == "rsse" else "ie"  # the core parses statistic itself
        return _core.predict.bootstrap_ratio(
            getattr(a, pick),
            getattr(b, pick),
            string("statistic", statistic),
            integer("resamples", resamples),
            seed_value("seed", seed),
        )

    def table(self) -> str:
        """Text table as [BP] Table I, with ratios to CM when it was evaluated."""
        lines = [
            f"{self.sections} sections, calibration {self.calibration} + horizon {self.horizon} samples",
            f"{'method':<18} {'mean IE':>12} {'IE std':>12} {'mean RSSE':>12} {'RSSE std':>12}",
        ]
        for key, st in self.methods.items():
            lines.append(
                f"{_METHOD_NAMES.get(key, key):<18} {st.mean_ie:>12.4g} {st.ie_std:>12.4g} "
                f"{st.mean_rsse:>12.4g} {st.rsse_std:>12.4g}"
            )
        if "cm" in self.methods and self.sections > 2:
            lines.append("ratios to calibration mean (± bootstrap s.e.):")
            for key in self.methods:
                if key == "cm":
                    continue
                r1, s1 = self.ratio(key, "cm", "rsse")
                r2, s2 = self.ratio(key, "cm", "ie_std")
                lines.append(
                    f"  {key.upper()}/CM  RSSE {r1:.4f} ± {s1:.4f}   IE std {r2:.4f} ± {s2:.4f}"
                )
        return "\n".join(lines)

    def to_dict(self) -> dict[str, Any]:
        """Summary as a dictionary."""
        return {
            "calibration": self.calibration,
            "horizon": self.horizon,
            "sections": self.sections,
            "methods": {k: v.to_dict() for k, v in self.methods.items()},
        }


def evaluate(
    log: Any,
    *,
    calibration: int,
    horizon: int,
    methods: Sequence[str] = ("kf", "ma", "cm"),
    predictor: FractionalKalmanPredictor | None = None,
    n_threads: int | None = None,
) -> Evaluation:
    """[BP]'s batch test (§V-C): split a long static log into disjoint sections and predict.

    Parameters
    ----------
    log : array_like, shape (n,) or (sections, k + h)
        A long static gyro log (split into ``n // (k + h)`` disjoint sections, the remainder
        dropped) or the sections themselves.
    calibration, horizon : int
        k and h in samples.
    methods : sequence of {"kf", "ma", "cm"}
        Fractional Kalman, moving average, calibration mean.
    predictor : FractionalKalmanPredictor, optional
        The Kalman predictor ("kf"); default ``FractionalKalmanPredictor(d=0.5, q=1, r=0)`` as in
        [BP]'s simulation (with r = 0 and the sample mean the forecast does not depend on q).

    Returns
    -------
    Evaluation
        Per method the integrated error and RSSE of every section and their mean and standard
        deviation ([BP] Table I); ``.table()`` prints it with ratios to CM.
    """
    k = integer("calibration", calibration)  # k >= 2, h >= 1, the sections: the core's checks
    h = integer("horizon", horizon)
    arr = as_float_array("log", log, ndims=(1, 2))
    names = [string("methods", m) for m in sequence("methods", methods)]
    if predictor is not None and not isinstance(predictor, FractionalKalmanPredictor):
        raise TypeError(
            f"predictor must be a FractionalKalmanPredictor or None, got {type(predictor).__name__}"
        )
    pred = predictor or FractionalKalmanPredictor()
    d, q, r, mode, mu0, p0 = pred._args()
    scores = _core.predict.evaluate(
        arr.reshape(-1),
        None if arr.ndim == 1 else arr.shape[1],
        k,
        h,
        names,
        d,
        q,
        r,
        mode,
        mu0,
        p0,
        _n_threads(n_threads),
    )
    out = {m: MethodStats(m, sc.integrated_error, sc.rsse) for m, sc in zip(names, scores)}
    sections = len(next(iter(out.values())).ie) if out else 0
    return Evaluation(k, h, sections, out)


# Paper values ([BP] Table I, simulated columns) used by the table1 experiment.
PAPER_TABLE1 = {
    "kf": {"mean_rsse": 136.0, "ie_std": 2120.0, "rsse_std": 23.3},
    "ma": {"mean_rsse": 139.0, "ie_std": 2210.0, "rsse_std": 25.4},
    "cm": {"mean_rsse": 138.0, "ie_std": 2280.0, "rsse_std": 24.9},
}
