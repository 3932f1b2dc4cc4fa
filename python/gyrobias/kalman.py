"""Fixed-gain 2-state Kalman filter for real-time gyro denoising ([NR], SPEC §6).

The gyro output is modelled as ``y = ω + b + n``: the true rate ``ω`` and the bias ``b`` are
random walks (per-step variances ``q_ω`` and ``Q_b = K²·T``) observed in white noise of variance
``R_d = N²/T`` (``N`` = ARW, ``K`` = RRW, ``T = 1/fs``). The filter runs with the precomputed
steady-state gain, which is what a microcontroller implementation does::

    q_s = q_ω + Q_b,   P⁻ = (q_s + √(q_s² + 4 q_s R_d)) / 2,   κ = P⁻ / (P⁻ + R_d)
    K_s = κ · [q_ω, Q_b] / q_s
    X_k = X_{k−1} + G (z_k − H X_{k−1}),   H = [1 1],   G = K_s (form="standard")

The rate response is exactly first order, ``H_ω(z) = g1 / (1 − p z⁻¹)`` with
``p = 1 − (g1 + g2)`` and DC gain ``q_ω / q_s``; its −3 dB point satisfies
``sin(π·BW·T) = (1 − p) / (2√p)``, i.e. ``q_s / R_d = 4 sin²(π·BW·T)`` for the standard form.

Units: ``arw`` in u/√s, ``rrw`` in u/s^1.5 and ``q_omega`` in (u/s)² per step, where u is the
angle unit of the rate (deg or rad). [NR] quotes ``q_ω`` in (°/h)², ARW in °/√h and RRW in
°/h^1.5: convert with :func:`q_omega_from_deg_per_hour`, :func:`arw_from_deg_per_sqrt_hour`
and :func:`rrw_from_deg_per_hour_1p5`.

Misprints in [NR] handled here (SPEC §6): the eigenvalue of ``m = −K_s H`` is ``−(k1 + k2)``
(printed ``+``); eqs. 12–17 use the dimensionless discrete gain in a continuous-time equation,
which makes the filter ~1/T times slower and caps its bandwidth at 1/(2π) Hz (available as
``form="paper"``); and the linear bandwidth fit (eq. 18) is not reproducible — the bandwidth
grows like √q_ω and is computed here from the true response.

References
----------
.. [NR] L. Xue, C. Jiang, L. Wang, J. Liu, W. Yuan, "Noise Reduction of MEMS Gyroscope Based on
   Direct Modeling for an Angular Rate Signal", Micromachines 6 (2015) 266–280.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gyrobias import _core, _generics
from gyrobias._validation import (
    as_float_array,
    asarray,
    finite_result,
    integer,
    non_negative_float,
    real,
    string,
)

__all__ = [
    "FilterResult",
    "FixedGainKalman",
    "KalmanState",
    "arw_from_deg_per_sqrt_hour",
    "bandwidth_for_qomega",
    "q_omega_from_deg_per_hour",
    "q_omega_to_deg_per_hour",
    "qomega_for_bandwidth",
    "riccati_gain",
    "rrw_from_deg_per_hour_1p5",
    "steady_state_gain",
]

Form = Literal["standard", "paper"]


# --- unit helpers ---------------------------------------------------------------------------


def _converted(name: str, value: float, convert: Callable[[float], float]) -> float:
    # A variance or density: finite and >= 0 (the core's check; bools are refused as types),
    # and the converted value must be finite too.
    v = non_negative_float(name, value)
    return finite_result(name, value, convert(v))


def q_omega_from_deg_per_hour(q_omega: float) -> float:
    """[NR]'s per-step ``q_ω`` in (°/h)² → (°/s)² (divide by 3600²).

    ``q_omega`` must be finite and ≥ 0 (a variance): ``ValueError`` naming it otherwise.
    """
    return _converted("q_omega", q_omega, lambda v: v / 3600.0**2)


def q_omega_to_deg_per_hour(q_omega: float) -> float:
    """Per-step ``q_ω`` in (°/s)² → (°/h)², the unit [NR] quotes (``q_omega`` finite, ≥ 0)."""
    return _converted("q_omega", q_omega, lambda v: v * 3600.0**2)


def arw_from_deg_per_sqrt_hour(arw: float) -> float:
    """ARW in °/√h → °/√s (divide by 60; ``arw`` finite and ≥ 0)."""
    return _converted("arw", arw, lambda v: v / 60.0)


def rrw_from_deg_per_hour_1p5(rrw: float) -> float:
    """RRW in °/h^1.5 → °/s^1.5 (divide by 216000; ``rrw`` finite and ≥ 0)."""
    return _converted("rrw", rrw, lambda v: v / 216000.0)


# --- design functions -----------------------------------------------------------------------


def steady_state_gain(q_omega: float, q_b: float, r_d: float) -> NDArray[np.float64]:
    """Closed-form steady-state gain ``K_s = κ·[q_ω, q_b]/q_s`` (all variances per step).

    Examples
    --------
    >>> k = steady_state_gain(1000.0, 2.0, 2.0e4)   # [NR]'s example, (°/h)²
    >>> k.round(6).tolist()
    [0.199778, 0.0004]
    """
    return _core.kalman.steady_state_gain(
        real("q_omega", q_omega), real("q_b", q_b), real("r_d", r_d)
    )


def riccati_gain(
    q_omega: float, q_b: float, r_d: float, *, iterations: int = 2000
) -> NDArray[np.float64]:
    """Gain after ``iterations`` steps of [NR] eqs. 9–11 (Joseph form) from ``P₀ = 0``.

    The paper's off-line procedure; it converges to :func:`steady_state_gain` although the
    covariance itself diverges along the unobservable direction ``[1, −1]``. The iteration
    stops early once a step returns exactly the previous gain and observable part of ``P``
    (a fixed point), so ``iterations=2**40`` costs what convergence costs; past convergence the
    gain then differs from the full recursion only by that recursion's rounding noise (at most
    1.3e-11 relative over a grid of 150 cases, both 7e-13 from the steady-state gain).
    """
    return _core.kalman.riccati_gain(
        real("q_omega", q_omega),
        real("q_b", q_b),
        real("r_d", r_d),
        integer("iterations", iterations),
    )


def qomega_for_bandwidth(
    bandwidth: float, fs: float, *, arw: float, rrw: float, form: Form = "standard"
) -> float:
    """Per-step ``q_ω`` ((u/s)²) that gives a −3 dB bandwidth ``bandwidth`` (Hz).

    Closed form for both forms: the pole ``p`` solving ``(1 − p)/(2√p) = sin(π·BW·T)``, then
    ``κ = 1 − p`` (standard) or ``κ = −ln(p)/T`` (paper), ``q_ω = R_d κ²/(1 − κ) − Q_b``. For the
    standard form this is ``q_ω = 4 R_d sin²(π·BW·T) − Q_b``.

    Raises
    ------
    ValueError
        If the bandwidth is unreachable: not below Nyquist, above ≈ 1/(2π) Hz for
        ``form="paper"``, or so low that the bias random walk alone exceeds it.
    """
    return _core.kalman.q_omega_for_bandwidth(
        real("bandwidth", bandwidth),
        real("fs", fs),
        real("arw", arw),
        real("rrw", rrw),
        string("form", form),
    )


def bandwidth_for_qomega(
    q_omega: float, fs: float, *, arw: float, rrw: float, form: Form = "standard"
) -> float | None:
    """True −3 dB bandwidth (Hz) of the rate response for ``q_omega``; ``None`` above Nyquist."""
    return FixedGainKalman(fs, arw=arw, rrw=rrw, q_omega=q_omega, form=form).bandwidth


# --- state and results ----------------------------------------------------------------------


#: Carried state of :meth:`FixedGainKalman.filter` (immutable, picklable, compared by value).
#:
#: The filter runs as ``u_k = p·u_{k−1} + z_k``, ``ω̂_k = g1·u_k + c``, ``b̂_k = g2·u_k − c``
#: (``u = (ω̂ + b̂)/(1 − p)`` is the scaled observable level, ``c`` the constant offset of the
#: unobservable mode). Attributes (tuples, one value per axis unless noted): ``level`` (u) and
#: ``offset`` (c), exactly the loop variables, so resuming from a state reproduces one-shot
#: filtering bit for bit; ``rate`` and ``bias``, the estimates after the last sample (u/s);
#: ``gain``, the ``G`` of the filter that produced it (checked on resume); ``samples``, the
#: rows processed so far; ``n_axes``.
KalmanState = _core.kalman.KalmanState


@dataclass(frozen=True)
class FilterResult:
    """Output of :meth:`FixedGainKalman.filter`.

    Unpacks as ``rate, bias = kf.filter(z)``; ``state`` resumes filtering on the next chunk.

    Attributes
    ----------
    rate : ndarray
        Rate estimates ``ω̂`` (u/s), same shape as the input.
    bias : ndarray
        Bias estimates ``b̂`` (u/s), same shape as the input.
    state : KalmanState
        State after the last sample.
    """

    rate: NDArray[np.float64]
    bias: NDArray[np.float64]
    state: KalmanState

    def __iter__(self) -> Iterator[NDArray[np.float64]]:
        yield self.rate
        yield self.bias


# --- the filter -----------------------------------------------------------------------------


def _rebuild(
    fs: float, arw: float, rrw: float, q_omega: float, form: str, x0: Any
) -> FixedGainKalman:
    return FixedGainKalman(fs, arw=arw, rrw=rrw, q_omega=q_omega, form=form, x0=x0)  # type: ignore[arg-type]


class FixedGainKalman:
    """Fixed-gain [rate, bias] Kalman filter of [NR] with its steady-state gain.

    Parameters
    ----------
    fs : float
        Sampling rate in Hz (``T = 1/fs``).
    arw : float
        Angle random walk ``N`` in u/√s (u = the rate's angle unit); must be > 0.
    rrw : float
        Rate random walk ``K`` in u/s^1.5; ≥ 0 (0 gives a pure unity-DC low-pass).
    q_omega : float, optional
        Per-step variance of the rate random walk in (u/s)². Give this or ``bandwidth``.
    bandwidth : float, optional
        Target −3 dB bandwidth of the rate response in Hz (``q_ω`` from
        :func:`qomega_for_bandwidth`).
    form : {"standard", "paper"}
        ``"standard"``: the steady-state discrete KF ``X ← X + K_s (z − H X)``. ``"paper"``:
        [NR] eqs. 12–17 taken literally (``G = K_s (1 − e^{−κT})/κ ≈ T·K_s``), for reproducing
        the paper; its bandwidth cannot exceed 1/(2π) Hz.
    x0 : array_like, optional
        Initial ``[ω₀, b₀]`` (state before the first sample), shape (2,) for every axis or
        (axes, 2). Default ``[z₀, 0]`` per axis. The initial split persists: the difference
        ``ω − b`` is unobservable.

    Raises
    ------
    ValueError
        Non-positive ``fs``/``arw``/``q_omega``/``bandwidth``, negative ``rrw``, both or neither
        of ``q_omega`` and ``bandwidth``, an unreachable bandwidth.

    Notes
    -----
    ``X_k = A X_{k−1} + G z_k`` with ``A = I − G H`` ([NR] eq. 17) is a first-order IIR on the
    observable sum ``s = ω̂ + b̂`` plus an accumulation, and both move by multiples of the
    innovation, so ``ω̂ − g1·s/(1 − p)`` is a constant ``c`` (the unobservable mode). The core
    runs it as ``u_k = p·u_{k−1} + z_k``, ``ω̂_k = g1·u_k + c``, ``b̂_k = g2·u_k − c`` with
    ``u = s/(1 − p)``: one multiply-add on the loop-carried path.
    A unity-DC-gain low-pass reduces the per-sample white noise by ``1/white_noise_gain`` but
    leaves the ARW and bias instability read at τ ≥ 1 s unchanged; the output is autocorrelated
    with ``ρ(k) = p^k``.

    Examples
    --------
    >>> import numpy as np
    >>> kf = FixedGainKalman(200.0, arw=0.08, rrw=7e-4, bandwidth=10.0)
    >>> round(kf.bandwidth, 9)
    10.0
    >>> rate, bias = kf.filter(np.random.default_rng(0).normal(size=1000))
    """

    def __init__(
        self,
        fs: float,
        *,
        arw: float,
        rrw: float,
        q_omega: float | None = None,
        bandwidth: float | None = None,
        form: Form = "standard",
        x0: ArrayLike | None = None,
    ) -> None:
        fs, arw, rrw = real("fs", fs), real("arw", arw), real("rrw", rrw)
        form = string("form", form)  # type: ignore[assignment]
        q = None if q_omega is None else real("q_omega", q_omega)
        bw = None if bandwidth is None else real("bandwidth", bandwidth)
        self._core = _core.kalman.FixedGainKalman(fs, arw, rrw, q, bw, form)
        self._fs, self._arw, self._rrw, self._form = fs, arw, rrw, form
        self._x0 = None if x0 is None else self._check_x0(x0)

    def _check_x0(self, x0: ArrayLike) -> NDArray[np.float64]:
        arr = as_float_array("x0", x0, ndims=(1, 2))
        if arr.shape[-1] != 2:
            raise ValueError(
                f"x0 must have shape (2,) or (axes, 2) of [rate, bias], got {arr.shape}"
            )
        arr = arr.copy()
        arr.flags.writeable = False
        # The core checks the values (finite, representable) when it builds the state: build
        # one now so that a bad x0 fails here rather than at the first filter call.
        pairs = arr.reshape(-1, 2)
        self._core.initial_state(pairs[:, 0].tolist(), pairs[:, 1].tolist())
        return arr

    def __reduce__(self) -> tuple[Any, ...]:
        return (_rebuild, (self._fs, self._arw, self._rrw, self.q_omega, self._form, self._x0))

    def __repr__(self) -> str:
        bw = self.bandwidth
        bw_s = "none" if bw is None else f"{bw:.6g} Hz"
        return (
            f"FixedGainKalman(fs={self._fs:g}, arw={self._arw:g}, rrw={self._rrw:g}, "
            f"q_omega={self.q_omega:.6g}, form={self._form!r}; bandwidth {bw_s})"
        )

    # design --------------------------------------------------------------------------------

    @property
    def fs(self) -> float:
        """Sampling rate (Hz)."""
        return self._fs

    @property
    def form(self) -> str:
        """``"standard"`` or ``"paper"``."""
        return self._form

    @property
    def q_omega(self) -> float:
        """Per-step rate process noise ``q_ω`` in (u/s)²."""
        return float(self._core.q_omega)

    @property
    def r_d(self) -> float:
        """Per-sample white-noise variance ``R_d = N²/T`` in (u/s)²."""
        return float(self._core.r_d)

    @property
    def q_b(self) -> float:
        """Per-step bias random-walk variance ``Q_b = K²·T`` in (u/s)²."""
        return float(self._core.q_b)

    @property
    def gain(self) -> NDArray[np.float64]:
        """Steady-state discrete gain ``K_s = [k1, k2]`` (dimensionless)."""
        return self._core.gain

    @property
    def kappa(self) -> float:
        """``κ = k1 + k2``."""
        return float(self._core.kappa)

    @property
    def continuous_gain(self) -> NDArray[np.float64]:
        """Gain ``K`` used in the continuous eq. 12 (``K_s`` itself for ``form="paper"``)."""
        return self._core.continuous_gain

    @property
    def A(self) -> NDArray[np.float64]:  # noqa: N802 - the paper's name
        """``A = e^{mT} = I − K H (1 − e^{−κ_c T})/κ_c`` ([NR] eqs. 15–16)."""
        return self._core.a

    @property
    def B(self) -> NDArray[np.float64]:  # noqa: N802 - the paper's name
        """``B = ∫₀ᵀ e^{mt} dt = T·I − K H T² φ₂(κ_c T)``, ``φ₂(x) = (x − 1 + e^{−x})/x²``."""
        return self._core.b

    @property
    def G(self) -> NDArray[np.float64]:  # noqa: N802 - the paper's name
        """``G = B K``: ``X_{k+1} = A X_k + G z_{k+1} = X_k + G (z_{k+1} − H X_k)`` (eq. 17)."""
        return self._core.g

    @property
    def pole(self) -> float:
        """Pole ``p = 1 − (g1 + g2)`` of the rate response."""
        return float(self._core.pole)

    @property
    def dc_gain(self) -> float:
        """DC gain ``q_ω/(q_ω + Q_b)`` of the rate response (slightly below 1 when rrw > 0)."""
        return float(self._core.dc_gain)

    @property
    def bandwidth(self) -> float | None:
        """True −3 dB frequency (Hz) of the rate response; ``None`` if above Nyquist."""
        bw = self._core.bandwidth
        return None if bw is None else float(bw)

    @property
    def white_noise_gain(self) -> float:
        """Output/input std ratio for white noise, ``g1/√(1 − p²)`` (``√(κ/(2−κ))`` at DC gain 1)."""
        return float(self._core.white_noise_gain)

    def frequency_response(self, freqs: ArrayLike) -> NDArray[np.complex128]:
        """Complex response ``g1/(1 − p e^{−j2πf/fs})`` of ``z → ω̂`` at ``freqs`` (Hz)."""
        f = asarray("freqs", freqs)
        shape = f.shape
        flat = as_float_array("freqs", f.reshape(-1) if f.ndim != 1 else f)
        re, im = self._core.frequency_response(flat)
        return (re + 1j * im).reshape(shape)

    # filtering -----------------------------------------------------------------------------

    def initial_state(self, z: ArrayLike) -> KalmanState:
        """The state before the first sample of ``z``: ``x0`` if given, else ``[z₀, 0]``."""
        return self._initial(as_float_array("z", z, ndims=(1, 2)))

    def _initial(self, data: NDArray[np.float64]) -> KalmanState:
        if self._x0 is None:
            return self._core.initial_state_from_first_sample(data)
        n_axes = data.shape[1] if data.ndim == 2 else 1
        x0 = self._x0 if self._x0.ndim == 2 else np.broadcast_to(self._x0, (n_axes, 2))
        if x0.shape[0] != n_axes:
            raise ValueError(f"x0 gives {x0.shape[0]} axes but z has {n_axes}")
        return self._core.initial_state(x0[:, 0].tolist(), x0[:, 1].tolist())

    def estimates(self, state: KalmanState) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """The estimates ``(ω̂, b̂)`` per axis that ``state`` stands for (computed by the core)."""
        self._check_state_type(state)
        rate, bias = self._core.estimates(state)
        return np.array(rate), np.array(bias)

    def filter(
        self,
        z: ArrayLike,
        *,
        state: KalmanState | None = None,
        out: tuple[NDArray[np.float64], NDArray[np.float64]] | None = None,
        dtype: Any = np.float64,
    ) -> FilterResult:
        """Filter ``z`` and return the rate and bias estimates with the new state.

        Parameters
        ----------
        z : array_like, shape (n,) or (n, axes)
            Gyro rate samples (u/s); each column of a 2-D array is filtered independently.
        state : KalmanState, optional
            State returned by a previous call, to continue a stream. Without it the filter
            starts from ``x0`` (default ``[z₀, 0]``).
        out : (ndarray, ndarray), optional
            Preallocated C-contiguous float64 arrays of the shape of ``z`` receiving the rate
            and bias estimates (returned as ``rate`` and ``bias``); reusing them across calls
            avoids allocation when streaming. They must not overlap each other or ``z``.
        dtype : {np.float64, np.float32}
            Arithmetic. ``np.float32`` rounds ``z``, the coefficients and the state to float32
            and performs the float64 path's operations in the same order in float32 (the
            initial state too): the outputs (float32) equal the C from
            :meth:`to_c` with ``dtype="float32"`` bit for bit. ``out`` is float64 only.

        Returns
        -------
        FilterResult
            ``rate`` and ``bias`` (shape of ``z``) and ``state``; unpacks as
            ``rate, bias = kf.filter(z)``. Filtering in chunks, passing ``state`` along,
            gives exactly (bit for bit) the one-shot result.

        Raises
        ------
        ValueError
            Empty ``z``, a NaN/inf in ``z`` (the message gives sample and axis; the passed
            ``state`` remains valid), a state with another number of axes or from another
            filter.
        TypeError
            Non-numeric ``z`` or a ``state`` that is not a :class:`KalmanState`.
        """
        if dtype is np.float32 or (isinstance(dtype, (str, np.dtype)) and dtype == "float32"):
            return self._filter_f32(z, state, out)
        if not (dtype is np.float64 or (isinstance(dtype, (str, np.dtype)) and dtype == "float64")):
            raise ValueError(f"dtype must be np.float64 or np.float32, got {dtype!r}")
        if (
            type(z) is np.ndarray
            and z.dtype == np.float64
            and 1 <= z.ndim <= 2
            and z.size
            and z.flags.c_contiguous
        ):
            data = z  # fast path for streaming: nothing to convert
        else:
            data = as_float_array("z", z, ndims=(1, 2))
        if state is None:
            state = self._initial(data)
        elif type(state) is not _core.kalman.KalmanState:
            self._check_state_type(state)
        if out is None:
            rate = np.empty(data.shape)
            bias = np.empty(data.shape)
        else:
            if type(out) is not tuple or len(out) != 2:
                raise TypeError("out must be a tuple (rate, bias) of float64 arrays")
            rate, bias = out
            for name, arr in (("out[0]", rate), ("out[1]", bias)):
                # the binding writes into the arrays: exactly C-contiguous float64 ndarrays,
                # else the binding's "'list' object is not an instance of 'ndarray'"
                if (
                    not isinstance(arr, np.ndarray)
                    or arr.dtype != np.float64
                    or not arr.flags.c_contiguous
                    or not arr.flags.writeable
                ):
                    shown = arr.dtype if isinstance(arr, np.ndarray) else type(arr).__name__
                    raise TypeError(
                        f"{name} must be a writable C-contiguous float64 ndarray, got {shown}"
                    )
        new_state = self._core.filter_into(data, rate, bias, state)
        return FilterResult(rate, bias, new_state)

    def _filter_f32(self, z: ArrayLike, state: KalmanState | None, out: object) -> FilterResult:
        if out is not None:
            raise ValueError("out must be None with dtype=np.float32 (out arrays are float64)")
        if (
            type(z) is np.ndarray
            and z.dtype == np.float32
            and 1 <= z.ndim <= 2
            and z.size
            and z.flags.c_contiguous
        ):
            data = z  # nothing to convert (the core checks the values)
        else:
            data = np.ascontiguousarray(as_float_array("z", z, ndims=(1, 2)), dtype=np.float32)
        if state is None:
            first = data[0] if data.ndim == 2 else data[:1]
            if self._x0 is None:
                rate0, bias0 = first.tolist(), [0.0] * first.size
            else:
                x0 = np.broadcast_to(self._x0, (first.size, 2)).astype(np.float32)
                rate0, bias0 = x0[:, 0].tolist(), x0[:, 1].tolist()
            if not np.all(np.isfinite(first)):
                axis = int(np.flatnonzero(~np.isfinite(first))[0])
                raise ValueError(f"z has a non-finite value (NaN or inf) at sample 0 axis {axis}")
            state = self._core.initial_state_f32(rate0, bias0)
        else:
            self._check_state_type(state)
        rate, bias, new_state = self._core.filter_f32(data, state)
        return FilterResult(rate, bias, new_state)  # type: ignore[arg-type]

    def to_c(
        self, path: Any, *, name: str = "gyro_kf", dtype: Any = "float32", **options: Any
    ) -> Any:
        """Write this filter as C99 (``<name>.h``, ``<name>.c`` in the directory ``path``).

        ``dtype`` is ``"float64"``, ``"float32"`` or ``"q31"`` (option ``full_scale``, u/s,
        states the Q31 error in the rate's unit). See :mod:`gyrobias.codegen`; returns its
        :class:`~gyrobias.codegen.GeneratedC`.
        """
        return _generics.to_c(self, path, name=name, dtype=dtype, **options)

    @staticmethod
    def _check_state_type(state: object) -> None:
        if type(state) is not _core.kalman.KalmanState:
            raise TypeError(
                f"state must be a KalmanState returned by FixedGainKalman.filter, "
                f"got {type(state).__name__}"
            )
