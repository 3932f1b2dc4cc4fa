"""The rest of the Allan family (issue 15): TDEV, MTOTDEV, HTOTDEV, Théo1, ThéoBR, ThéoH."""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np
from numpy.typing import ArrayLike

from gyrobias import _core
from gyrobias._validation import as_float_array, callback
from gyrobias._validation import axis_names as check_axis_names
from gyrobias.allan._options import _axis_units, _tau_options
from gyrobias.allan._types import AllanResult
from gyrobias.units import checked_units

#: gyrobias kind → core statistic of :func:`gyrobias._core.allan.family_analyse`.
_FAMILY_STATISTIC = {
    "tdev": "time",
    "mtotdev": "modified-total",
    "htotdev": "hadamard-total",
    "theo1": "theo1",
    "theobr": "theobr",
    "theoh": "theoh",
}


def _analyse_family(
    kind: str,
    statistic: str,
    data: ArrayLike,
    fs: float,
    taus: str | ArrayLike,
    per_decade: int,
    data_type: str,
    confidence: float | None,
    units: str | Sequence[str | None] | None,
    axis_names: Sequence[str] | None,
    progress: Callable[[float], None] | None,
    overlapping: bool = True,
) -> AllanResult | tuple[AllanResult, ...]:
    """Shared driver of the statistics computed by ``gyrocore::allan::family``."""
    arr = as_float_array("data", data, ndims=(1, 2))
    callback("progress", progress)
    if units is None or isinstance(units, str):
        checked_units("units", units)  # a sequence (one per axis) is checked below
    # Types only: the ranges (per_decade >= 1, 0 < confidence < 1, ...) are the core's checks.
    fs, spec, explicit, per_decade, confidence = _tau_options(
        fs, taus, per_decade, data_type, confidence
    )
    matrix = arr.reshape(-1, 1) if arr.ndim == 1 else arr
    n_axes = matrix.shape[1]
    check_axis_names(axis_names, n_axes)
    axis_units = _axis_units(units, n_axes)
    t0 = 1.0 / fs
    if progress is not None:
        progress(0.0)
    raw = _core.allan.family_analyse(
        np.ascontiguousarray(matrix),
        t0,
        data_type,
        statistic,
        spec,
        int(per_decade),
        explicit,
        confidence,
    )
    if progress is not None:
        progress(1.0)
    results = [
        AllanResult._from_core(
            r,
            kind=kind,
            fs=fs,
            data_type=data_type,
            overlapping=overlapping,
            confidence=confidence,
            units=axis_units[i],
            axis=None if axis_names is None else str(axis_names[i]),
        )
        for i, r in enumerate(raw)
    ]
    if arr.ndim == 1:
        return results[0]
    return tuple(results)


def tdev(
    data: ArrayLike,
    fs: float,
    *,
    taus: str | ArrayLike = "octave",
    per_decade: int = 10,
    data_type: str = "rate",
    confidence: float | None = 0.683,
    units: str | Sequence[str | None] | None = None,
    axis_names: Sequence[str] | None = None,
    progress: Callable[[float], None] | None = None,
) -> AllanResult | tuple[AllanResult, ...]:
    """Time deviation TDEV (SP 1065 eq. 15); arguments as :func:`avar`.

    ``σ²_x(τ) = τ²/3 · Mod σ²(τ)``: the modified Allan deviation scaled to an *angle* (phase)
    error, so its unit is the angle unit (``deg/s`` rate input → ``deg``). Confidence intervals
    use the modified Allan variance's EDF (Greenhall). Matches Stable32's TDEV and
    ``allantools.tdev``.

    Examples
    --------
    >>> import numpy as np, gyrobias
    >>> rate = np.random.default_rng(1).normal(0.0, 0.1, 20_000)        # deg/s
    >>> r = gyrobias.allan.tdev(rate, fs=100.0, units="deg/s")
    >>> r.unit, r.label
    ('deg', 'TDEV (time deviation)')
    """
    return _analyse_family(
        "tdev",
        "time",
        data,
        fs,
        taus,
        per_decade,
        data_type,
        confidence,
        units,
        axis_names,
        progress,
    )


def mtotdev(
    data: ArrayLike,
    fs: float,
    *,
    taus: str | ArrayLike = "octave",
    per_decade: int = 10,
    data_type: str = "rate",
    confidence: float | None = 0.683,
    units: str | Sequence[str | None] | None = None,
    axis_names: Sequence[str] | None = None,
    progress: Callable[[float], None] | None = None,
) -> AllanResult | tuple[AllanResult, ...]:
    """Modified total deviation MTOTDEV (SP 1065 eq. 27); arguments as :func:`avar`.

    For each of the ``M − 3m + 1`` sub-sequences of ``3m`` angle samples: remove the linear
    trend given by the means of its two halves, extend it by uninverted even reflection at both
    ends to ``9m`` samples and average the ``6m`` squared second differences of ``m``-sample
    means; ``Mod σ²_total = ⟨…⟩ / (2τ²)``. τ ≤ M/3 (M angle samples). No bias correction
    (as Stable32 and AllanTools). EDF: SP 1065 Table 12, ``b·N/m − c``. Computed without
    reflection copies (prefix sums), so long records take seconds, not hours.

    Examples
    --------
    >>> import numpy as np, gyrobias
    >>> rate = np.random.default_rng(2).normal(0.0, 0.1, 5_000)
    >>> r = gyrobias.allan.mtotdev(rate, fs=10.0)
    >>> int(r.m[-1]) <= 5_001 // 3
    True
    """
    return _analyse_family(
        "mtotdev",
        "modified-total",
        data,
        fs,
        taus,
        per_decade,
        data_type,
        confidence,
        units,
        axis_names,
        progress,
    )


def htotdev(
    data: ArrayLike,
    fs: float,
    *,
    taus: str | ArrayLike = "octave",
    per_decade: int = 10,
    data_type: str = "rate",
    confidence: float | None = 0.683,
    units: str | Sequence[str | None] | None = None,
    axis_names: Sequence[str] | None = None,
    progress: Callable[[float], None] | None = None,
) -> AllanResult | tuple[AllanResult, ...]:
    """Hadamard total deviation HTOTDEV (SP 1065 eq. 29); arguments as :func:`avar`.

    The total recipe of :func:`mtotdev` applied to the *rate* series (``3m``-sample
    sub-sequences, half-mean detrending, even reflection to ``9m``, second differences of
    ``m``-sample rate means, ``/6``), averaged over the ``M − 3m`` windows; at ``m = 1`` the
    overlapping Hadamard deviation (SP 1065's recommendation, as Stable32 and AllanTools).
    Insensitive to a rate ramp, with better long-τ confidence than HDEV. EDF: SP 1065 Table 13.

    Examples
    --------
    >>> import numpy as np, gyrobias
    >>> rate = np.random.default_rng(3).normal(0.0, 0.1, 5_000)
    >>> r = gyrobias.allan.htotdev(rate, fs=10.0, confidence=None)
    >>> r.label
    'HTOTDEV (Hadamard total deviation)'
    """
    return _analyse_family(
        "htotdev",
        "hadamard-total",
        data,
        fs,
        taus,
        per_decade,
        data_type,
        confidence,
        units,
        axis_names,
        progress,
    )


def theo1(
    data: ArrayLike,
    fs: float,
    *,
    taus: str | ArrayLike = "octave",
    per_decade: int = 10,
    data_type: str = "rate",
    confidence: float | None = 0.683,
    units: str | Sequence[str | None] | None = None,
    axis_names: Sequence[str] | None = None,
    progress: Callable[[float], None] | None = None,
) -> AllanResult | tuple[AllanResult, ...]:
    """Théo1 deviation (Howe & Peppler 2003; SP 1065 eq. 30); arguments as :func:`avar`.

    At even averaging factors ``2 ≤ m ≤ N − 1`` (N angle samples) Théo1 estimates the Allan
    deviation at ``τ = 0.75·m/fs`` — out to 75 % of the record, where rate random walk and rate
    ramp are read::

        Théo1(m) = Σ_{i=0}^{N−m−1} Σ_{δ=0}^{m/2−1} [(x_i − x_{i−δ+m/2}) + (x_{i+m} − x_{i+δ+m/2})]²
                   / ((m/2 − δ) · 0.75 (N − m) (m/fs)²)

    ``taus``: a specification selects the even ``m`` of the octave/decade/log/all grid; explicit
    τ must be ``0.75·m/fs`` with ``m`` even. ``result.taus`` holds τ = 0.75·m/fs and
    ``result.m`` the Théo1 factors. Théo1 is biased for some noises: :func:`theobr` removes the
    bias. EDF: Howe & Tasset's formulas (SP 1065 Table 14). Matches ``allantools.theo1``
    (which reports ``m/fs`` as its τ) and Stable32.

    Examples
    --------
    >>> import numpy as np, gyrobias
    >>> rate = np.random.default_rng(4).normal(0.0, 0.1, 2_000)
    >>> r = gyrobias.allan.theo1(rate, fs=1.0, taus=[1.5, 3.0, 750.0])
    >>> r.m.tolist(), r.taus.tolist()
    ([2, 4, 1000], [1.5, 3.0, 750.0])
    """
    return _analyse_family(
        "theo1",
        "theo1",
        data,
        fs,
        taus,
        per_decade,
        data_type,
        confidence,
        units,
        axis_names,
        progress,
    )


def theobr(
    data: ArrayLike,
    fs: float,
    *,
    taus: str | ArrayLike = "octave",
    per_decade: int = 10,
    data_type: str = "rate",
    confidence: float | None = 0.683,
    units: str | Sequence[str | None] | None = None,
    axis_names: Sequence[str] | None = None,
    progress: Callable[[float], None] | None = None,
) -> AllanResult | tuple[AllanResult, ...]:
    """Bias-removed Théo1, ThéoBR (Howe & Tasset 2006; SP 1065 eq. 31); arguments as :func:`theo1`.

    ``ThéoBR(m) = Théo1(m) · 1/(n+1) Σ_{i=0}^{n} AVAR(9 + 3i) / Théo1(12 + 4i)``,
    ``n = ⌊N/30 − 3⌋``: the ratio of the overlapping Allan variance to Théo1 at the same τ over
    the short-τ region, where AVAR is trustworthy, removes Théo1's noise-dependent bias. Needs at
    least 90 angle samples. The ratio needs Théo1 at every ``m = 12 + 4i`` up to ``≈ 0.13·N``;
    an exact structure-function sweep evaluates them together in ``≈ 0.17·N²`` operations
    (direct sums would take ``≈ N³/1000``), so ThéoBR grows as ``N²`` while the octave Théo1
    itself is ``O(N log² N)``: measured on 2 cores ≈ 0.03 s for 10⁴ samples, ≈ 1.2 s for 10⁵,
    ≈ 26 s for 10⁶.

    Examples
    --------
    >>> import numpy as np, gyrobias
    >>> rate = np.random.default_rng(5).normal(0.0, 0.1, 1_000)
    >>> r = gyrobias.allan.theobr(rate, fs=1.0, confidence=None)
    >>> int(r.m[-1]), float(r.taus[-1])            # octave m; τ = 0.75·m/fs
    (512, 384.0)
    """
    return _analyse_family(
        "theobr",
        "theobr",
        data,
        fs,
        taus,
        per_decade,
        data_type,
        confidence,
        units,
        axis_names,
        progress,
    )


def theoh(
    data: ArrayLike,
    fs: float,
    *,
    taus: str | ArrayLike = "octave",
    per_decade: int = 10,
    data_type: str = "rate",
    confidence: float | None = 0.683,
    units: str | Sequence[str | None] | None = None,
    axis_names: Sequence[str] | None = None,
    progress: Callable[[float], None] | None = None,
) -> AllanResult | tuple[AllanResult, ...]:
    """Hybrid ThéoH deviation (Howe & Tasset 2006; SP 1065 eq. 32); arguments as :func:`theo1`.

    The overlapping Allan deviation for τ below ``k`` and ThéoBR (τ = 0.75·m/fs, m even) from
    ``k`` up, with ``k`` the largest τ ≤ 10 % of the record ``(N − 1)/fs``: one curve with
    AVAR's resolution at short τ and ThéoBR's reach and confidence at long τ. ``result.m`` holds
    the AVAR factor below ``k`` and the Théo1 factor above it. Explicit τ below ``k`` must be
    multiples of 1/fs, above ``k`` of the form ``0.75·m/fs`` with ``m`` even.

    Examples
    --------
    >>> import numpy as np, gyrobias
    >>> rate = np.random.default_rng(6).normal(0.0, 0.1, 1_000)
    >>> r = gyrobias.allan.theoh(rate, fs=1.0, confidence=None)
    >>> bool(np.all(np.diff(r.taus) > 0))
    True
    """
    return _analyse_family(
        "theoh",
        "theoh",
        data,
        fs,
        taus,
        per_decade,
        data_type,
        confidence,
        units,
        axis_names,
        progress,
    )
