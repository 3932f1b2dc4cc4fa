"""Detection of spectral lines in a rate signal (``gyrobias.noise.detect_lines``).

Its own module below both :mod:`gyrobias.allan` (which attaches the lines of the data to an
Allan result) and :mod:`gyrobias.noise` (whose fit models them), importing neither.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from gyrobias import _core
from gyrobias._spectral_lines import HALF_WIDTH, MIN_HALF_WIDTH, SpectralLine
from gyrobias._validation import as_float_array, integer, real, sample_rate
from gyrobias._validation import axis_names as check_axis_names
from gyrobias.units import checked_units


def detect_lines(
    data: Any,
    fs: float,
    *,
    false_alarm: float = 0.01,
    units: str | None = None,
    max_lines: int = 8,
    axis_names: Sequence[str] | None = None,
) -> tuple[SpectralLine, ...] | tuple[tuple[SpectralLine, ...], ...]:
    """Spectral lines (sinusoids) in a rate signal, with a stated false-alarm level.

    Parameters
    ----------
    data : array_like, shape (n,) or (n, axes)
        Rate samples; one column per axis. At least 64 samples.
    fs : float
        Sample rate (Hz).
    false_alarm : float
        Family-wise false-alarm level α in (0, 1): the probability of reporting one or more
        lines in a record of Gaussian noise without any.
    units : str, optional
        Rate unit of the data (for the amplitudes).
    max_lines : int
        At most this many lines per axis (the most significant).
    axis_names : sequence of str, optional
        Accepted for symmetry with the other analyses (one name per column).

    Returns
    -------
    tuple of SpectralLine, or one such tuple per axis for 2-D data
        Sorted by frequency; empty when nothing is significant.

    Raises
    ------
    ValueError
        Non-finite data, fewer than 64 samples, ``false_alarm`` outside (0, 1).

    Notes
    -----
    The Hann-windowed periodogram ``P_k`` of the whole mean-removed record is divided by a
    running-median floor ``Ŝ_k`` (the lower median of the ``L = 2⌊h/2⌋`` bins at offsets ±3,
    ±5, …, ±(L + 1), over ln 2), with the window half-width ``h = 128`` bins, or ``⌊n/8⌋`` (at
    least 8) on a record of fewer than 1024 samples, so that a short static log (a few seconds
    at rest) is searched too, with the same false-alarm level and less power. For Gaussian noise
    with a spectrum smooth over the window ``P_k/S_k`` is a unit exponential and the median is
    an order statistic of exponentials (Rényi), so the per-bin p-value of ``t = P_k/Ŝ_k`` is
    exactly ``p(t) = Π_{i=1}^{L/2} (1 + t/(ln 2·(L + 1 − i)))⁻¹`` (the floor's own noise
    included; for ``h = 128``: ``Π_{i=1}^{64} (1 + t/(ln 2·(129 − i)))⁻¹``). With K
    frequencies searched a line is declared when ``K·p(t) < α`` (Bonferroni). Significant bins
    within ``2h`` bins of each other are one line. The window needs ``h + 1`` bins below a
    frequency, so lines below ``(h + 1)·fs/n`` are not searched (the lowest quarter of the band
    on a record shorter than 1024 samples).
    The frequency is refined to the maximum of the windowed DTFT within ±1 bin and the
    amplitude is ``2|X(f̂)|/Σw`` (Hann coherent gain). A sinusoid above fs/2 is
    seen at its alias ``|f − k·fs|``. See ``gyrobias.noise.fit`` for how the Allan fit uses the
    lines (IEEE Std 952-1997 Annex C sinusoidal term).

    References
    ----------
    D. B. Percival, A. T. Walden, *Spectral Analysis for Physical Applications* (1993),
    §10.9–10.10 (tests for periodicity against a smooth background).

    Examples
    --------
    >>> import numpy as np
    >>> import gyrobias
    >>> rng = np.random.default_rng(0)
    >>> t = np.arange(50_000) / 100.0
    >>> rate = 0.1 * rng.standard_normal(t.size) + 0.01 * np.sin(2 * np.pi * 23.0 * t)
    >>> (line,) = gyrobias.noise.detect_lines(rate, 100.0, units="deg/s")
    >>> round(line.frequency, 2), round(line.amplitude, 2), line.p_value < 1e-6
    (23.0, 0.01, True)
    """
    arr = as_float_array("data", data, ndims=(1, 2))
    fs = sample_rate(fs)
    units = checked_units("units", units)
    false_alarm = real("false_alarm", false_alarm)
    max_lines = integer("max_lines", max_lines)
    matrix = arr.reshape(-1, 1) if arr.ndim == 1 else arr
    check_axis_names(axis_names, matrix.shape[1])
    out = tuple(
        _detect_column(
            np.ascontiguousarray(matrix[:, a], dtype=np.float64), fs, false_alarm, units, max_lines
        )
        for a in range(matrix.shape[1])
    )
    return out[0] if arr.ndim == 1 else out


def _detect_column(
    column: np.ndarray[Any, np.dtype[np.float64]],
    fs: float,
    false_alarm: float,
    units: str | None,
    max_lines: int,
) -> tuple[SpectralLine, ...]:
    half_width = max(MIN_HALF_WIDTH, min(HALF_WIDTH, column.shape[0] // 8))
    raw = _core.noise.detect_lines(column, 1.0 / fs, false_alarm, half_width, max_lines)
    return tuple(
        SpectralLine(
            frequency=float(d["frequency"]),
            amplitude=float(d["amplitude"]),
            unit=units,
            ratio=float(d["ratio"]),
            p_value=float(d["p_value"]),
            resolution=float(d["resolution"]),
            frequency_uncertainty=float(d["frequency_uncertainty"]),
        )
        for d in raw
    )
