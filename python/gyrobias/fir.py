"""Kaiser-window FIR low-pass design and filtering ([TS] eqs. 14–20, Orfanidis §10.2).

[TS] (El-Diasty, El-Rabbany, Pagiatakis) denoise MEMS gyro and accelerometer logs with a
Kaiser-window FIR low-pass before their Allan and least-squares spectral analyses. This module
designs that filter from the specification ``{fpass, fstop, apass_db, astop_db}`` and applies it
causally or with zero phase; the numerics run in the Rust core with the GIL released.

Conventions
-----------
- Frequencies in Hz, the sample rate ``fs`` in Hz.
- ``apass_db`` is the pass-band attenuation (peak-to-peak ripple) and ``astop_db`` the stop-band
  attenuation, both positive dB. [TS] prints "f_pass = 1000 dB" for Skaloud's
  ``apass_db = 0.0001`` (a misprint), and ``δstop = 10^(−Apass/20)`` for
  ``δstop = 10^(−Astop/20)`` (another). The defaults are Skaloud's/[TS]'s 0.0001 dB and 100 dB.
- Causal filtering delays the signal by ``M = (N − 1)/2`` samples; zero-phase filtering runs the
  filter forward and backward (magnitude squared: −12 dB at the cut-off, no delay).

References
----------
.. [TS] N. El-Diasty, A. El-Rabbany, S. Pagiatakis, "Stochastic characteristics of
   temperature-dependent MEMS-based inertial sensor error", eqs. 14–20 and Fig. 12.
.. [Orfanidis] S. J. Orfanidis, "Introduction to Signal Processing" (1996), §10.2.
.. [Skaloud] J. Skaloud, "Optimizing georeferencing of airborne survey systems by INS/DGPS",
   PhD thesis, University of Calgary (1999).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gyrobias import _core, _generics
from gyrobias._validation import as_float_array, asarray, count, integer, real, string

__all__ = ["FrequencyResponse", "KaiserLowpass", "apply", "kaiser_lowpass", "stream"]


@dataclass(frozen=True)
class FrequencyResponse:
    """Frequency response of an FIR filter.

    Attributes
    ----------
    frequencies : ndarray
        Frequencies in Hz.
    response : ndarray of complex
        ``H(f) = Σ_n h_n exp(−2πi f n/fs)`` (causal form), or ``|H(f)|²`` (real, zero phase).
    zero_phase : bool
        Whether this is the response of forward–backward filtering.
    """

    frequencies: NDArray[np.float64]
    response: NDArray[np.complex128]
    zero_phase: bool

    @property
    def magnitude(self) -> NDArray[np.float64]:
        """``|H(f)|`` (linear)."""
        return np.abs(self.response)

    @property
    def magnitude_db(self) -> NDArray[np.float64]:
        """``20 log10 |H(f)|`` in dB (−inf where the response is exactly 0)."""
        with np.errstate(divide="ignore"):
            return 20.0 * np.log10(self.magnitude)

    @property
    def phase(self) -> NDArray[np.float64]:
        """Unwrapped phase in radians (linear, ``−2π f M/fs``, for the causal form)."""
        return np.unwrap(np.angle(self.response))


@dataclass(frozen=True)
class KaiserLowpass:
    """A Kaiser-window FIR low-pass filter designed by :func:`kaiser_lowpass`.

    Attributes
    ----------
    fs, fpass, fstop : float
        Sample rate and band edges in Hz.
    apass_db, astop_db : float
        Requested pass-band and stop-band attenuations in dB.
    cutoff : float
        ``fc = (fpass + fstop)/2`` in Hz (the −6 dB point of the causal filter).
    delta_pass, delta_stop : float
        Ripples ``δpass``, ``δstop`` of the specification.
    attenuation_db : float
        Design attenuation ``A = −20 log10 min(δpass, δstop)`` in dB.
    alpha : float
        Kaiser shape parameter α.
    taps : ndarray
        Impulse response ``h(n)``, ``n = 0..N−1`` (symmetric, N odd).
    """

    fs: float
    fpass: float
    fstop: float
    apass_db: float
    astop_db: float
    cutoff: float
    delta_pass: float
    delta_stop: float
    attenuation_db: float
    alpha: float
    taps: NDArray[np.float64]

    @property
    def numtaps(self) -> int:
        """Filter length N."""
        return int(self.taps.size)

    @property
    def delay(self) -> int:
        """Group delay ``M = (N − 1)/2`` of the causal filter, in samples."""
        return (self.numtaps - 1) // 2

    def frequency_response(
        self, frequencies: ArrayLike | None = None, *, n: int = 1024, zero_phase: bool = False
    ) -> FrequencyResponse:
        """Response at ``frequencies`` (Hz), or at ``n`` points from 0 to ``fs/2``.

        With ``zero_phase=True`` the response of forward–backward filtering, ``|H(f)|²``.
        """
        if frequencies is None:
            n = count("n", n)
            if n < 2:  # a grid from 0 to fs/2 (no core call): checked here
                raise ValueError(f"n must be an integer >= 2, got {n!r}")
            freqs = np.linspace(0.0, 0.5 * self.fs, n)
        else:
            freqs = as_float_array("frequencies", frequencies)
        re, im = _core.fir.frequency_response(self.taps, self.fs, freqs)
        resp = re + 1j * im
        if zero_phase:
            resp = (np.abs(resp) ** 2).astype(np.complex128)
        return FrequencyResponse(freqs, resp, bool(zero_phase))

    def apply(
        self,
        x: ArrayLike,
        *,
        zero_phase: bool = True,
        axis: int = -1,
        padtype: str = "odd",
        padlen: int | None = None,
    ) -> NDArray[np.float64]:
        """Filter ``x`` with this filter; see :func:`apply`."""
        return apply(self.taps, x, zero_phase=zero_phase, axis=axis, padtype=padtype, padlen=padlen)

    def to_c(
        self, path: Any, *, name: str = "gyro_fir", dtype: Any = "float32", **options: Any
    ) -> Any:
        """Write this filter as streaming C99 (``<name>.h``, ``<name>.c`` in directory ``path``).

        ``dtype`` is ``"float64"``, ``"float32"`` or ``"q31"``; CMSIS-DSP coefficient arrays are
        included. See :mod:`gyrobias.codegen`; returns its :class:`~gyrobias.codegen.GeneratedC`.
        """
        return _generics.to_c(self, path, name=name, dtype=dtype, **options)

    def to_dict(self) -> dict[str, Any]:
        """Plain-Python representation (taps as a list)."""
        return {
            "fs": self.fs,
            "fpass": self.fpass,
            "fstop": self.fstop,
            "apass_db": self.apass_db,
            "astop_db": self.astop_db,
            "cutoff": self.cutoff,
            "delta_pass": self.delta_pass,
            "delta_stop": self.delta_stop,
            "attenuation_db": self.attenuation_db,
            "alpha": self.alpha,
            "numtaps": self.numtaps,
            "taps": self.taps.tolist(),
        }


def kaiser_lowpass(
    fs: float,
    fpass: float,
    fstop: float,
    *,
    apass_db: float = 0.0001,
    astop_db: float = 100.0,
) -> KaiserLowpass:
    """Design a Kaiser-window FIR low-pass filter ([TS] eqs. 14–20).

    Parameters
    ----------
    fs : float
        Sample rate in Hz.
    fpass, fstop : float
        Pass-band and stop-band edges in Hz, ``0 < fpass < fstop ≤ fs/2``.
    apass_db : float
        Pass-band attenuation in dB (> 0). Default 0.0001 dB ([TS]'s "1000 dB" misprint).
    astop_db : float
        Stop-band attenuation in dB (> 0). Default 100 dB.

    Returns
    -------
    KaiserLowpass

    Raises
    ------
    ValueError
        ``fpass ≥ fstop``, a band edge above the Nyquist frequency ``fs/2``, non-positive
        frequencies or attenuations, or a transition band so narrow that the filter would exceed
        10⁶ taps.

    Notes
    -----
    ``fc = (fpass + fstop)/2``, ``Δf = fstop − fpass``,
    ``δpass = (10^(Apass/20) − 1)/(10^(Apass/20) + 1)``, ``δstop = 10^(−Astop/20)``,
    ``A = −20 log10 min(δpass, δstop)``; ``α = 0.1102(A − 8.7)`` for A ≥ 50,
    ``0.5842(A − 21)^0.4 + 0.07886(A − 21)`` for 21 < A < 50, else 0;
    ``D = (A − 7.95)/14.36`` (0.922 if A ≤ 21); ``N = 1 + ⌈D·fs/Δf⌉`` rounded up to odd;
    ``h(n) = w(n)·sin(ωc(n − M))/(π(n − M))`` with the Kaiser window
    ``w(n) = I0(α√(1 − ((n − M)/M)²))/I0(α)`` and ``ωc = 2π fc/fs``. The taps equal
    ``scipy.signal.firwin(N, fc, window=("kaiser", α), fs=fs, scale=False)`` (SciPy's
    ``kaiserord`` would give an even N: it does not force N odd).

    References
    ----------
    [TS] eqs. 14–20; Orfanidis (1996) §10.2.

    Examples
    --------
    >>> from gyrobias.fir import kaiser_lowpass
    >>> f = kaiser_lowpass(100.0, 14.0, 18.0, apass_db=0.0001, astop_db=100.0)
    >>> f.numtaps, round(f.alpha, 6), round(f.attenuation_db, 6)
    (171, 10.589877, 104.796886)
    """
    fs, fpass, fstop = real("fs", fs), real("fpass", fpass), real("fstop", fstop)
    apass_db, astop_db = real("apass_db", apass_db), real("astop_db", astop_db)
    d = _core.fir.kaiser_lowpass(fs, fpass, fstop, apass_db, astop_db)
    return KaiserLowpass(
        fs=fs,
        fpass=fpass,
        fstop=fstop,
        apass_db=apass_db,
        astop_db=astop_db,
        cutoff=float(d["cutoff"]),
        delta_pass=float(d["delta_pass"]),
        delta_stop=float(d["delta_stop"]),
        attenuation_db=float(d["attenuation_db"]),
        alpha=float(d["alpha"]),
        taps=np.asarray(d["taps"], dtype=np.float64),
    )


def apply(
    taps: ArrayLike,
    x: ArrayLike,
    *,
    zero_phase: bool = True,
    axis: int = -1,
    padtype: str = "odd",
    padlen: int | None = None,
) -> NDArray[np.float64]:
    """Filter ``x`` along ``axis`` with the FIR filter ``taps``.

    Parameters
    ----------
    taps : array_like, 1-D
        Impulse response (e.g. ``kaiser_lowpass(...).taps``).
    x : array_like
        Signal(s); any number of dimensions, filtered along ``axis`` (all other axes in
        parallel). The caller's array is not modified.
    zero_phase : bool
        ``True`` (default): forward–backward filtering, zero phase, magnitude ``|H|²``.
        ``False``: causal filtering ``y_n = Σ_k h_k x_{n−k}`` with zero initial state, equal to
        ``scipy.signal.lfilter(taps, 1, x)``; the output lags by ``M = (N − 1)/2`` samples.
    axis : int
        Axis along which to filter.
    padtype : {"odd", "even", "constant", "none"}
        Zero phase only: how the signal is extended at both ends before filtering (as
        ``scipy.signal.filtfilt``; ``"none"`` means no extension).
    padlen : int, optional
        Zero phase only: extension length per end; default ``3·len(taps)`` (filtfilt's default),
        0 for ``padtype="none"``. Must be smaller than the signal length.

    Returns
    -------
    ndarray
        Filtered signal, same shape as ``x``.

    Raises
    ------
    ValueError
        NaN/inf in ``taps`` or ``x``, a signal not longer than ``padlen``, unknown ``padtype``,
        an ``axis`` out of range.

    Notes
    -----
    Edges in zero-phase mode follow ``scipy.signal.filtfilt(taps, [1], x, padtype=..,
    padlen=..)`` (``method="pad"``) exactly: extend by ``padlen`` samples (odd: ``2x₀ − x_j``),
    run each pass from the steady state of its first input sample (``lfilter_zi`` scaled by it,
    i.e. an infinite history of that sample), cut the extension off. The result equals
    filtfilt's to rounding (~1e-15 relative). Within about ``N`` samples of either end the output
    depends on this edge convention; in the interior it does not.
    """
    h = as_float_array("taps", taps)
    arr = asarray("x", x)
    if arr.ndim == 0:
        raise ValueError("x must have at least one dimension")
    arr = as_float_array("x", arr, ndims=(arr.ndim,))
    if (
        isinstance(axis, bool)
        or not isinstance(axis, (int, np.integer))
        or not -arr.ndim <= axis < arr.ndim
    ):
        raise ValueError(f"axis {axis!r} is out of range for an array of {arr.ndim} dimensions")
    string("padtype", padtype)
    if padlen is None:
        padlen = 0 if padtype == "none" else 3 * h.size
    else:
        padlen = integer("padlen", padlen)
    moved = np.moveaxis(arr, axis, -1)
    shape = moved.shape
    rows = np.ascontiguousarray(moved.reshape(-1, shape[-1]))
    # padlen is converted by the binding (which refuses a negative one) and ignored by the core
    # unless zero_phase.
    try:
        out = _core.fir.filter_rows(h, rows, bool(zero_phase), padtype, padlen)
    except ValueError as exc:
        if str(exc).startswith("x is too short") and padlen is not None and zero_phase:
            # an explicit padlen longer than the signal: name the argument the caller gave
            raise ValueError(
                f"padlen must be less than the length of x along axis={axis} "
                f"({shape[-1]} samples), got {padlen} ({exc})"
            ) from None
        if str(exc).startswith("x is too short") and arr.ndim > 1:
            # the core sees rows: say which axis of the caller's array was too short
            raise ValueError(
                f"{exc} along axis={axis} of x (shape {arr.shape}): filter along the axis of "
                "time (axis=-1 by default)"
            ) from None
        raise
    return np.moveaxis(out.reshape(shape), -1, axis)


def stream(
    taps: ArrayLike,
    x: ArrayLike,
    state: ArrayLike | None = None,
    *,
    axis: int = -1,
    dtype: Any = np.float64,
) -> tuple[NDArray[Any], NDArray[Any]]:
    """Causal filtering of one chunk of a stream, with the filter state in and out.

    Parameters
    ----------
    taps : array_like, 1-D
        Impulse response (N taps).
    x : array_like
        The next chunk of the signal(s), filtered along ``axis``.
    state : array_like, optional
        The state returned by the previous call: the last ``N − 1`` input samples, shape of
        ``x`` with ``axis`` replaced by ``N − 1`` (moved last). ``None`` starts a stream
        (zero history, like ``scipy.signal.lfilter`` without ``zi``).
    axis : int
        Axis of time in ``x``.
    dtype : {np.float64, np.float32}
        Arithmetic. ``np.float32`` rounds the taps, ``x`` and ``state`` to float32 and runs the
        float64 kernel's operations in the same order in float32: equal bit for bit to the C
        from :meth:`KaiserLowpass.to_c` with ``dtype="float32"``.

    Returns
    -------
    (y, state) : tuple of ndarray
        The filtered chunk (shape of ``x``, delayed by ``M = (N − 1)/2`` samples) and the new
        state to pass to the next call.

    Notes
    -----
    Processing a signal in chunks gives bit for bit the same output as one call on the whole
    signal (both use the direct convolution); it equals :func:`apply` with
    ``zero_phase=False`` to rounding (``apply`` uses FFT convolution for long signals).

    Examples
    --------
    >>> import numpy as np
    >>> from gyrobias import fir
    >>> f = fir.kaiser_lowpass(100.0, 14.0, 18.0)
    >>> x = np.random.default_rng(0).normal(size=1000)
    >>> y1, s = fir.stream(f.taps, x[:300])
    >>> y2, s = fir.stream(f.taps, x[300:], s)
    >>> bool(np.array_equal(np.r_[y1, y2], fir.stream(f.taps, x)[0]))
    True
    """
    single = dtype is np.float32 or (isinstance(dtype, (str, np.dtype)) and dtype == "float32")
    if not single and not (
        dtype is np.float64 or (isinstance(dtype, (str, np.dtype)) and dtype == "float64")
    ):
        raise ValueError(f"dtype must be np.float64 or np.float32, got {dtype!r}")
    h = as_float_array("taps", taps)
    arr = asarray("x", x)
    if arr.ndim == 0:
        raise ValueError("x must have at least one dimension")
    arr = as_float_array("x", arr, ndims=(arr.ndim,))
    if (
        isinstance(axis, bool)
        or not isinstance(axis, (int, np.integer))
        or not -arr.ndim <= axis < arr.ndim
    ):
        raise ValueError(f"axis {axis!r} is out of range for an array of {arr.ndim} dimensions")
    moved = np.moveaxis(arr, axis, -1)
    shape = moved.shape
    rows = moved.reshape(-1, shape[-1])
    width = h.size - 1
    if state is None:
        st = np.zeros((rows.shape[0], width))
    else:
        st = as_float_array("state", state, ndims=tuple(range(1, 33)))
        if st.shape != (*shape[:-1], width):
            raise ValueError(f"state must have shape {(*shape[:-1], width)}, got {st.shape}")
        st = st.reshape(rows.shape[0], width)
    y: NDArray[Any]
    new_state: NDArray[Any]
    if single:
        y, new_state = _core.fir.filter_stream_rows_f32(
            h.astype(np.float32),
            np.ascontiguousarray(rows, dtype=np.float32),
            np.ascontiguousarray(st, dtype=np.float32),
        )
    else:
        y, new_state = _core.fir.filter_stream_rows(
            h, np.ascontiguousarray(rows, dtype=np.float64), np.ascontiguousarray(st)
        )
    return np.moveaxis(y.reshape(shape), -1, axis), new_state.reshape(*shape[:-1], width)
