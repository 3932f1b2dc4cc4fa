"""Cleaning a log before its stability analysis: Stable32's *Outliers* and *Drift* steps.

Stable32 (and NIST SP 1065 §6.2, "Data Preprocessing") walks an engineer through *pick a
part → remove outliers → remove drift → analyse*. The part is a slice of the log
(``log.data[i0:i1]`` or the CLI's ``--start/--stop``); the other two steps are here, one function
each, with a typed result that records what was done:

- :func:`remove_outliers` — flag the samples whose robust z-score ``|x − median| / (1.4826·MAD)``
  exceeds a threshold (per channel) and replace them by NaN (gaps);
- :func:`detrend` — remove each channel's least-squares linear or quadratic drift in time;
- :func:`clean` — both steps in that order, as the command line's ``--outliers`` and
  ``--detrend`` run them;
- :func:`minmax_envelope` — per bin of samples each channel's minimum and maximum, to draw a
  log of 10⁷ samples with a few thousand points without hiding a spike.

The steps never modify their input, skip NaN (gaps) and keep them NaN, so they chain in
Stable32's order, and the Allan functions analyse the result with ``gaps="omit"`` (every
estimator term that spans a gap is left out; see :func:`gyrobias.allan.adev`)::

    clean = cleaning.remove_outliers(log.data, 5.0)
    flat = cleaning.detrend(clean.data, log.fs, order=1)
    curves = allan.adev(flat.data, log.fs, gaps="omit", units="deg/s")

The numerics are the core's (``gyrocore::cleaning``).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gyrobias import _core
from gyrobias._validation import as_float_array, choice, integer, real, sample_rate
from gyrobias.cleaning._types import (
    ORDER_NAMES,
    CleaningResult,
    DetrendResult,
    Envelope,
    OutlierResult,
)
from gyrobias.units import checked_units

__all__ = [
    "ORDERS",
    "CleaningResult",
    "DetrendResult",
    "Envelope",
    "OutlierResult",
    "clean",
    "detrend",
    "minmax_envelope",
    "remove_outliers",
]

#: The ``order`` of :func:`detrend` for each drift name (the CLI's ``--detrend``).
ORDERS: dict[str, int] = {name: order for order, name in ORDER_NAMES.items()}


def _matrix(data: ArrayLike) -> tuple[NDArray[np.float64], tuple[int, ...]]:
    """``data`` as a C-contiguous float64 ``(n, k)`` matrix and the input's shape."""
    arr = as_float_array("data", data, ndims=(1, 2))
    shape = arr.shape
    return (arr.reshape(-1, 1) if arr.ndim == 1 else arr), shape


def _channel_units(units: Any, n_channels: int) -> tuple[str | None, ...]:
    """``units`` (one unit for every channel, or one per channel) as one entry per channel."""
    if units is None or isinstance(units, str):
        return (checked_units("units", units),) * n_channels
    if not isinstance(units, Sequence):
        raise TypeError(
            f"units must be a unit string, a sequence of them or None, got {type(units).__name__}"
        )
    if len(units) != n_channels:
        raise ValueError(f"units has {len(units)} entries for {n_channels} channels")
    return tuple(checked_units("units", u) for u in units)


def _out(
    out: Any, matrix: NDArray[np.float64], shape: tuple[int, ...]
) -> tuple[NDArray[np.float64], bool]:
    """The caller's buffer ``out`` as an ``(n, k)`` view of it, and whether it is the data
    itself (in place). Otherwise the core writes its result into it in the pass that computes
    it (no separate copy of the data)."""
    if not isinstance(out, np.ndarray):
        raise TypeError(f"out must be a NumPy array, got {type(out).__name__}")
    if out.dtype != np.float64 or not out.flags.c_contiguous or not out.flags.writeable:
        raise TypeError("out must be a writable C-contiguous float64 array")
    if out.shape != shape:
        raise ValueError(
            f"out has shape {out.shape}, the data {shape}: give one of the data's shape"
        )
    view = out.reshape(matrix.shape)
    same = (
        view.__array_interface__["data"][0] == matrix.__array_interface__["data"][0]
        and view.strides == matrix.strides
    )
    if not same and np.shares_memory(view, matrix):
        raise ValueError("out overlaps data: give the data itself (in place) or another buffer")
    return view, same


def remove_outliers(
    data: ArrayLike,
    threshold: float = 5.0,
    *,
    method: str = "mad",
    units: str | Sequence[str | None] | None = None,
    out: NDArray[np.float64] | None = None,
) -> OutlierResult:
    """Flag outliers by their robust z-score and replace them by NaN (gaps), per channel.

    Parameters
    ----------
    data : array_like, shape (n,) or (n, k)
        Samples, one column per channel (e.g. ``log.data``). NaN marks a gap: skipped by the
        statistics, kept NaN, never flagged. Never modified.
    threshold : float
        Robust z-score above which a sample is an outlier, finite and > 0 (default 5,
        Stable32's default sigma factor).
    method : {"mad"}
        The median absolute deviation, Stable32's outlier recognition (the only method).
    units : str or sequence of str, optional
        Unit of the samples (one for all channels, or one per channel); labels ``center`` and
        ``scale``.
    out : ndarray, optional
        A writable C-contiguous float64 array of the data's shape to write the result into
        (``data`` of the result is then ``out``): a caller that cleans repeatedly reuses one
        buffer instead of a new copy each time. ``out`` may be ``data`` itself (in place) but
        not overlap it otherwise. After an error its contents are unspecified.

    Returns
    -------
    OutlierResult
        ``data`` (a copy with the outliers replaced by NaN, the input's shape; ``out`` when
        given), ``mask``, ``count``, ``center`` and ``scale`` per channel.

    Raises
    ------
    ValueError
        ``threshold`` not finite and > 0; a channel with fewer than 3 finite samples (NaN only);
        ``data`` empty, 0-D or 3-D; ``units`` not a unit or not one per channel; an unknown
        ``method``.
    TypeError
        Non-numeric ``data`` or ``threshold``.

    Notes
    -----
    Per channel, over its finite samples,
    ``m = median(x)``, ``s = 1.482602·median|x − m|`` (the MAD scaled to a normal standard
    deviation) and a sample is an outlier when ``|x − m| / s > threshold``. When more than half
    of the samples equal the median (coarse quantisation) the MAD is 0 and ``s`` falls back to
    ``1.253314·mean|x − m|`` (Iglewicz & Hoaglin's modified z-score convention); a constant
    channel has nothing flagged. An infinite sample is always flagged.

    The outliers become **gaps**: :func:`gyrobias.allan.adev` and its siblings analyse the
    result with ``gaps="omit"`` (every estimator term whose span touches a NaN is left out,
    ``n_terms`` counts the terms kept and the EDF pools the gap-free segments); with the default
    ``gaps="error"`` they refuse NaN, naming its index. :func:`detrend` fits over the finite
    samples and keeps the NaN.

    References
    ----------
    W. J. Riley, *Handbook of Frequency Stability Analysis*, NIST SP 1065 (2008), §6.2 (data
    preprocessing, outlier recognition by the median absolute deviation); the Stable32
    "Outliers" function; B. Iglewicz and D. Hoaglin, *How to Detect and Handle Outliers* (1993).

    Examples
    --------
    >>> import numpy as np
    >>> from gyrobias import allan, cleaning
    >>> rate = np.random.default_rng(0).normal(0.0, 0.1, 100_000)   # deg/s
    >>> rate[[1_000, 50_000]] = 25.0                                 # two spikes
    >>> clean = cleaning.remove_outliers(rate, 5.0, units="deg/s")
    >>> clean.count.tolist(), bool(np.isnan(clean.data[1_000])), bool(rate[1_000] == 25.0)
    ([2], True, True)
    >>> r = allan.adev(clean.data, 100.0, gaps="omit", taus=[0.01, 1.0])
    >>> bool(abs(r.adev[0] - 0.1) < 0.005)
    True
    """
    return _remove_outliers(data, threshold, method=method, units=units, out=out)[0]


def _remove_outliers(
    data: ArrayLike,
    threshold: float,
    *,
    method: str,
    units: str | Sequence[str | None] | None,
    out: NDArray[np.float64] | None,
) -> tuple[OutlierResult, int]:
    """:func:`remove_outliers` and the number of NaN in its ``data`` (counted by the core)."""
    choice("method", method, ("mad",))
    threshold = real("threshold", threshold)  # finite and > 0: the core's check
    matrix, shape = _matrix(data)
    channel_units = _channel_units(units, matrix.shape[1])
    flat, same = _out(out, matrix, shape) if out is not None else (np.empty(matrix.shape), False)
    if same:
        mask, center, scale, count, gaps = _core.cleaning.remove_outliers_in_place(flat, threshold)
    else:
        mask, center, scale, count, gaps = _core.cleaning.remove_outliers_into(
            matrix, flat, threshold
        )
    result = OutlierResult(
        data=flat.reshape(shape),
        mask=mask.reshape(shape),
        count=count.astype(np.int64),
        threshold=threshold,
        center=center,
        scale=scale,
        units=channel_units,
        method=method,
    )
    return result, gaps


def detrend(
    data: ArrayLike,
    fs: float,
    order: int = 1,
    *,
    units: str | Sequence[str | None] | None = None,
    out: NDArray[np.float64] | None = None,
) -> DetrendResult:
    """Remove each channel's least-squares polynomial drift (linear or quadratic) in time.

    Parameters
    ----------
    data : array_like, shape (n,) or (n, k)
        Evenly sampled data, one column per channel; NaN marks a gap (not fitted, kept NaN).
        Never modified.
    fs : float
        Sample rate in Hz: sample ``i`` is at ``t = i/fs`` seconds from the first sample.
    order : {1, 2}
        1: linear drift (Stable32's "Linear" drift removal), 2: quadratic.
    units : str or sequence of str, optional
        Unit of the samples (one for all channels, or one per channel); gives the
        coefficients' units (rate, rate/s, rate/s²).
    out : ndarray, optional
        A writable C-contiguous float64 array of the data's shape to write the residual into
        (as :func:`remove_outliers`; ``out=data`` detrends in place).

    Returns
    -------
    DetrendResult
        ``data`` (the residual, the input's shape; ``out`` when given) and ``coefficients``
        (k, order + 1) of ``c0 + c1·t + c2·t²``.

    Raises
    ------
    ValueError
        ``order`` not 1 or 2; ``fs`` not finite and > 0; an infinite sample; a channel with
        fewer than ``order + 2`` finite samples; ``data`` empty, 0-D or 3-D.
    TypeError
        Non-numeric ``data``, ``fs`` or a non-integer ``order``.

    Notes
    -----
    The polynomial minimises ``Σ_i (x_i − p(t_i))²`` over the finite samples. It is fitted in
    the Legendre basis of the scaled time ``u = 2i/(n − 1) − 1`` (``1, u, (3u² − 1)/2``: a
    Gram matrix of condition ≈ 5 for any length and rate, where powers of raw ``t`` give
    ~10¹⁵ at 10⁷ samples), with the values taken relative to the channel's first finite sample,
    and converted to the monomial coefficients reported. Removing a linear drift changes ADEV
    at long τ only; a quadratic drift is the "rate ramp" R term of IEEE 952 (slope +1 in ADEV),
    which the noise fit can model instead.

    References
    ----------
    W. J. Riley, *Handbook of Frequency Stability Analysis*, NIST SP 1065 (2008), §6.2
    ("Drift removal"); the Stable32 "Drift" function.

    Examples
    --------
    >>> import numpy as np
    >>> from gyrobias import cleaning
    >>> t = np.arange(10_000) / 100.0                       # 100 s at 100 Hz
    >>> rate = 0.5 + 0.002 * t                              # deg/s with a 0.002 deg/s² drift
    >>> flat = cleaning.detrend(rate, 100.0, order=1, units="deg/s")
    >>> np.round(flat.coefficients, 6).tolist(), flat.coefficient_units
    ([[0.5, 0.002]], (('deg/s', 'deg/s^2'),))
    >>> bool(np.max(np.abs(flat.data)) < 1e-12)
    True
    """
    return _detrend(data, fs, order, units=units, out=out)[0]


def _detrend(
    data: ArrayLike,
    fs: float,
    order: int,
    *,
    units: str | Sequence[str | None] | None,
    out: NDArray[np.float64] | None,
) -> tuple[DetrendResult, int]:
    """:func:`detrend` and the number of NaN in its ``data`` (counted by the core)."""
    fs = sample_rate(fs)
    order = integer("order", order)  # 1 or 2: the core's check
    matrix, shape = _matrix(data)
    channel_units = _channel_units(units, matrix.shape[1])
    flat, same = _out(out, matrix, shape) if out is not None else (np.empty(matrix.shape), False)
    if same:
        coefficients, gaps = _core.cleaning.detrend_in_place(flat, fs, order)
    else:
        coefficients, gaps = _core.cleaning.detrend_into(matrix, flat, fs, order)
    result = DetrendResult(
        data=flat.reshape(shape),
        coefficients=coefficients.reshape(matrix.shape[1], -1),
        order=order,
        fs=fs,
        units=channel_units,
    )
    return result, gaps


def minmax_envelope(data: ArrayLike, bins: int) -> Envelope:
    """Each channel's minimum and maximum over ``bins`` consecutive bins of samples.

    The server-side decimation that draws a long log: plotting ``lower`` and ``upper`` of a
    few thousand bins shows every spike of 10⁷ samples, where taking every N-th sample would
    hide them. One pass over the data in the core, the bins in parallel.

    Parameters
    ----------
    data : array_like, shape (n,) or (n, k)
        Samples, one column per channel. NaN (gaps) are ignored. A float64 C-contiguous array
        is read without a copy.
    bins : int
        Number of bins, ≥ 1; more bins than samples gives one bin per sample.

    Returns
    -------
    Envelope
        ``lower`` and ``upper`` of shape (bins, k) (NaN for a bin of gaps only) and
        ``starts``: bin ``b`` holds samples ``starts[b]`` to ``starts[b + 1] − 1``
        (``starts[b] = ⌊b·n/bins⌋``).

    Raises
    ------
    ValueError
        ``bins`` < 1; ``data`` empty, 0-D or 3-D.
    TypeError
        Non-numeric ``data``; a non-integer ``bins``.

    Examples
    --------
    >>> import numpy as np
    >>> from gyrobias import cleaning
    >>> x = np.arange(10.0)
    >>> x[3] = 100.0
    >>> e = cleaning.minmax_envelope(x, 3)
    >>> e.starts.tolist(), e.lower[:, 0].tolist(), e.upper[:, 0].tolist()
    ([0, 3, 6, 10], [0.0, 4.0, 6.0], [2.0, 100.0, 9.0])
    """
    bins = integer("bins", bins)  # >= 1: the core's check
    matrix, _ = _matrix(data)
    k = matrix.shape[1]
    lower, upper, starts = _core.cleaning.minmax_envelope(matrix, bins)
    return Envelope(
        lower=lower.reshape(-1, k),
        upper=upper.reshape(-1, k),
        starts=starts.astype(np.int64),
    )


def clean(
    data: ArrayLike,
    fs: float,
    *,
    outliers: float | None = None,
    detrend: str | None = None,
    units: str | Sequence[str | None] | None = None,
    out: NDArray[np.float64] | None = None,
) -> CleaningResult:
    """Stable32's Outliers then Drift steps in one call (the command line's ``--outliers
    SIGMA --detrend linear|quadratic``).

    Parameters
    ----------
    data : array_like, shape (n,) or (n, k)
        Samples (e.g. ``log.data`` of a selected part); never modified.
    fs : float
        Sample rate in Hz.
    outliers : float, optional
        Robust z-score threshold of :func:`remove_outliers` (``None``: keep every sample).
    detrend : {"linear", "quadratic"}, optional
        Drift removed by :func:`detrend` after the outliers (``None``: none).
    units : str or sequence of str, optional
        Unit of the samples (one for all channels, or one per channel).
    out : ndarray, optional
        A writable C-contiguous float64 array of the data's shape that receives the cleaned
        samples when a step runs (as :func:`remove_outliers`): an app that cleans again and
        again reuses one working buffer.

    Returns
    -------
    CleaningResult
        ``data`` and the record of each step (``outliers``, ``drift``).

    Notes
    -----
    Both steps run in one buffer (a copy of ``data``, or ``out``): the drift is removed where
    the outlier step left its result, so cleaning costs one copy of the data, not two. The
    ``data`` of both step records is then that buffer (the cleaned samples); the outlier step
    is recorded by its ``mask``, ``count``, ``center`` and ``scale``.

    Raises
    ------
    ValueError, TypeError
        As :func:`remove_outliers` and :func:`detrend`; an unknown ``detrend`` name.

    Examples
    --------
    >>> import numpy as np
    >>> from gyrobias import allan, cleaning
    >>> rng = np.random.default_rng(1)
    >>> rate = rng.normal(0.0, 0.1, 50_000) + 1e-4 * np.arange(50_000)   # drifting
    >>> rate[123] = 40.0
    >>> c = cleaning.clean(rate, 100.0, outliers=5.0, detrend="linear", units="deg/s")
    >>> c.describe()
    'outliers > 5σ (MAD) removed per channel: 1; linear drift removed'
    >>> r = allan.adev(c.data, 100.0, gaps="omit" if c.has_gaps else "error")
    """
    order = None if detrend is None else ORDERS[choice("detrend", detrend, tuple(ORDERS))]
    fs = sample_rate(fs)
    if outliers is not None:  # named as the caller knows it (remove_outliers says threshold)
        outliers = _core.validate.positive("outliers", real("outliers", outliers))
    current: Any = data
    found = drift = None
    gaps: int | None = None
    if outliers is not None:
        found, gaps = _remove_outliers(current, outliers, method="mad", units=units, out=out)
        current = found.data
    if order is not None:
        # in the outlier step's output (a buffer of ours or the caller's out): one copy in all
        drift, gaps = _detrend(
            current, fs, order, units=units, out=current if found is not None else out
        )
        current = drift.data
    if found is None and drift is None:
        current = as_float_array("data", data, ndims=(1, 2))
    return CleaningResult(data=current, outliers=found, drift=drift, gaps=gaps)
