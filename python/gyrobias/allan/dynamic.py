"""Dynamic (time-resolved) Allan deviation: overlapping ADEV in sliding windows."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from gyrobias import _core
from gyrobias._validation import as_float_array, integer
from gyrobias.allan._options import _tau_options
from gyrobias.allan._types import DynamicAllanResult
from gyrobias.units import checked_units


def dynamic_adev(
    data: ArrayLike,
    fs: float,
    *,
    window: int,
    step: int,
    taus: str | ArrayLike = "octave",
    per_decade: int = 10,
    data_type: str = "rate",
    units: str | None = None,
) -> DynamicAllanResult:
    """Dynamic Allan deviation: overlapping ADEV in sliding windows (Galleani & Tavella 2009).

    The log is cut into windows of ``window`` samples starting every ``step`` samples; each
    window is analysed on its own exactly as :func:`adev` would analyse it (rate windows are
    integrated after removing their own mean), at one τ set resolved for the window length.
    A curve that changes from row to row reveals non-stationarity — warm-up, temperature steps,
    vibration bursts — that one ADEV of the whole log averages away.

    Parameters
    ----------
    data : array_like, shape (n,)
        One axis of rate (or angle) samples.
    fs : float
        Sample rate in Hz.
    window : int
        Window length in samples (at most ``n``).
    step : int
        Distance between window starts in samples (≥ 1).
    taus, per_decade, data_type, units
        As in :func:`avar`; τ must fit the window.

    Returns
    -------
    DynamicAllanResult
        ``adev`` of shape (windows, τ) and the window centre times; ``.plot()`` draws the heat map.

    Raises
    ------
    ValueError
        ``window`` longer than the log or too short for one τ, ``step`` < 1, τ beyond the window,
        NaN/inf in ``data``.

    Notes
    -----
    Every row depends only on its own window, so results do not depend on thread count, and
    analysing a log in pieces that overlap by ``window − step`` samples gives the same rows.

    Examples
    --------
    >>> import numpy as np, gyrobias
    >>> rate = np.random.default_rng(7).normal(0.0, 0.1, 10_000)
    >>> rate[5_000:] *= 3.0                                  # noise triples halfway
    >>> d = gyrobias.allan.dynamic_adev(rate, 100.0, window=2_000, step=1_000, units="deg/s")
    >>> d.adev.shape
    (9, 10)
    >>> bool(d.adev[-1, 0] > 2.5 * d.adev[0, 0])
    True
    """
    arr = as_float_array("data", data, ndims=(1,))
    units = checked_units("units", units)
    fs, spec, explicit, per_decade, _ = _tau_options(fs, taus, per_decade, data_type, None)
    window = integer("window", window)  # window <= n, step >= 1: the core's checks
    step = integer("step", step)
    t0 = 1.0 / fs
    raw = _core.allan.dynamic_avar(
        np.ascontiguousarray(arr), t0, data_type, window, step, spec, int(per_decade), explicit
    )
    return DynamicAllanResult._from_core(
        raw, fs=fs, window=window, step=step, data_type=data_type, units=units
    )
