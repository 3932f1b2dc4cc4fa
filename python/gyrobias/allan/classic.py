"""Allan-family deviations of gyro rate or angle data.

All estimators work on the angle series ``x``. Rate samples ``Ω_i`` at period ``t0 = 1/fs``
are integrated after the mean is removed, with ``x_0 = 0`` prepended (NIST SP 1065, the
AllanTools and Stable32 convention)::

    x_k = t0 · Σ_{i<k} (Ω_i − mean(Ω)),   k = 0..N

and with ``τ = m·t0`` the overlapping Allan variance is (SP 1065 eq. 11, [TS] eq. 1)::

    σ²(τ) = Σ_{k=0}^{N−2m} (x_{k+2m} − 2x_{k+m} + x_k)² / (2 τ² (N + 1 − 2m))

Confidence intervals are chi-square intervals with the equivalent degrees of freedom of the
identified power-law noise (SP 1065 §5). The noise is identified per τ as Stable32 does
(SP 1065 §5.6): by the lag-1 autocorrelation method of Riley & Greenhall on the ``m``-averaged
rate where the decimated series has at least 30 points (below 100 checked against R(n)), and
by the B1 bias ratio (Barnes; Howe et al. 2000) with R(n) = MVAR/AVAR (IEEE 1139) where it has
fewer — both ratios are local estimates of the ADEV/MDEV slope, so the α at long τ agrees with
the curve's slope there. The
EDF is Greenhall's algorithm for the Allan, modified and Hadamard variances and SP 1065's
formulas for the total variance, and never exceeds the number of terms summed (``n_terms``; the
EDF of a sum of T squared Gaussian terms is at most T). On AllanTools' Stable32 reference tables
the bounds agree with Stable32's with a median relative error of 1.0e-4 and a 90th percentile
of 1.2e-3 (``tests/test_allan_stable32_intervals.py``).

References
----------
.. [SP1065] W. J. Riley, "Handbook of Frequency Stability Analysis", NIST SP 1065 (2008).
.. [IEEE952] IEEE Std 952-1997, Annex C (Allan variance of gyro noise terms).
.. [BP] M. Kirkko-Jaakkola, J. Collin, J. Takala, "Bias Prediction for MEMS Gyroscopes",
   IEEE Sensors J. 12 (2012), eq. 2 (non-overlapping estimator).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import replace
from typing import Any, cast

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gyrobias import _core
from gyrobias._line_detection import detect_lines
from gyrobias._spectral_lines import MIN_SAMPLES, SpectralLine
from gyrobias._validation import as_float_array, asarray, callback, choice, sample_rate, string
from gyrobias._validation import axis_names as check_axis_names
from gyrobias.allan import stream as _stream
from gyrobias.allan._options import _axis_units, _options
from gyrobias.allan._types import AllanResult, Kind, Stationarity
from gyrobias.allan.family import _analyse_family
from gyrobias.units import checked_units


def _analyse(
    kind: Kind,
    data: ArrayLike,
    fs: float,
    taus: str | ArrayLike,
    per_decade: int,
    data_type: str,
    overlapping: bool,
    confidence: float | None,
    units: str | Sequence[str | None] | None,
    axis_names: Sequence[str] | None,
    progress: Callable[[float], None] | None,
    gaps: str = "error",
) -> AllanResult | tuple[AllanResult, ...]:
    if _stream._file_readers(data) is not None:
        arr = asarray(
            "data", data
        )  # validated below; not converted (that would read the whole file)
        if arr.ndim not in (1, 2):
            raise ValueError(
                f"data must be a 1-D or 2-D array, got a {arr.ndim}-D array of shape {arr.shape}"
            )
        if arr.size == 0:
            raise ValueError("data is empty")
    else:
        arr = as_float_array("data", data, ndims=(1, 2))
    callback("progress", progress)
    string("gaps", gaps)  # its values are parsed by the core (allan::Gaps)
    if units is None or isinstance(units, str):
        checked_units("units", units)  # a sequence (one per axis) is checked below
    fs, estimator, spec, explicit, confidence = _options(
        kind, fs, taus, per_decade, data_type, overlapping, confidence
    )
    if _stream._file_readers(data) is not None and not (
        estimator == "overlapping" and gaps == "error"
    ):
        arr = as_float_array("data", data, ndims=(1, 2))  # other estimators: in memory
    matrix = arr.reshape(-1, 1) if arr.ndim == 1 else arr
    n_axes = matrix.shape[1]
    check_axis_names(axis_names, n_axes)
    axis_units = _axis_units(units, n_axes)
    readers = (
        _stream._file_readers(data) if estimator == "overlapping" and gaps == "error" else None
    )
    raw: list[Any]
    if readers is not None:
        # A memory-mapped file: stream it through the core in pieces read from the file (the
        # mapping itself is never touched, so its pages do not fill the resident memory).
        raw = []
        for axis, reader in enumerate(readers):
            step = (
                None if progress is None else _stream._axis_progress(progress, axis, len(readers))
            )
            raw.append(
                _core.allan.analyse_stream(
                    reader,
                    reader.n_samples,
                    1.0 / fs,
                    data_type,
                    spec,
                    int(per_decade),
                    explicit,
                    confidence,
                    _stream._STREAM_BLOCK,
                    step,
                )
            )
    else:
        # One core call for all τ and axes; progress is reported from inside the kernel, so the
        # numbers are the same with or without it.
        raw = _core.allan.analyse(
            matrix,
            1.0 / fs,
            data_type,
            estimator,
            spec,
            int(per_decade),
            explicit,
            confidence,
            gaps,
            progress,
        )
    results = tuple(
        AllanResult._from_core(
            r,
            kind=kind,
            fs=fs,
            data_type=data_type,
            overlapping=overlapping if kind == "adev" else True,
            confidence=confidence,
            units=axis_units[i],
            axis=None if axis_names is None else str(axis_names[i]),
        )
        for i, r in enumerate(raw)
    )
    if kind == "adev" and data_type == "rate" and readers is None and gaps == "error":
        # Periodic disturbances bias the Allan fit; noise.fit models the lines found here. The
        # search runs when the lines are first asked for (AllanResult.lines).
        results = tuple(
            replace(r, lines=_LineSearch(matrix[:, i], fs, axis_units[i]))  # type: ignore[arg-type]
            for i, r in enumerate(results)
        )
    if arr.ndim == 1:
        return results[0]
    return results


#: Longest segment searched for spectral lines (samples; see AllanResult.lines).
LINE_SEARCH_SAMPLES = 2**18
#: Logs up to this length are searched whole.
LINE_SEARCH_WHOLE = 2**15


def line_search_length(n: int) -> int:
    """Samples searched for lines in a log of ``n``: all up to :data:`LINE_SEARCH_WHOLE`, else
    ``n/8`` within ``[LINE_SEARCH_WHOLE, LINE_SEARCH_SAMPLES]``.

    Why a segment suffices: a line of amplitude ``A`` biases the Allan fit only where its Allan
    variance is comparable to the estimate's noise, ``A² ≳ σ²·√(2/n)`` at the shortest τ (σ² the
    white-noise variance per sample), while a periodogram of ``n'`` samples detects it from
    ``A² ≈ c·σ²/n'`` with ``c ≈ 30`` (Hann window, Bonferroni over the bins at α = 0.01). With
    ``n' = n/8`` the detection threshold is ``8c/√(2n)`` of the relevant level — below 0.1 for
    ``n ≥ 2¹⁸``; shorter logs are searched whole. The copy (float32, mean removed) is at most
    1/16 of the input's bytes and 1 MB.
    """
    if n <= LINE_SEARCH_WHOLE:
        return n
    return max(LINE_SEARCH_WHOLE, min(n // 8, LINE_SEARCH_SAMPLES))


class _LineSearch:
    """The spectral-line search of one rate column, run when first called: a copy of its central
    :func:`line_search_length` samples (bounded memory, and independent of later changes to the
    caller's array), searched by :func:`gyrobias.noise.detect_lines`. ``None`` below the
    detector's minimum length. The copy is float32 of ``(x − mean)/scale`` computed in float64
    (``scale`` the largest deviation, so any finite data fit): a relative resolution of 6e-8 of
    the noise and drift, far below any periodogram floor; amplitudes are scaled back."""

    def __init__(self, column: NDArray[np.float64], fs: float, units: str | None) -> None:
        n = column.shape[0]
        length = line_search_length(n)
        start = (n - length) // 2
        segment = column[start : start + length]
        mean = float(np.mean(segment)) if length else 0.0
        spread = max(abs(float(np.max(segment)) - mean), abs(float(np.min(segment)) - mean))
        self._scale = spread if math.isfinite(spread) and spread > 0.0 else 1.0
        self._segment = np.empty(length, dtype=np.float32)
        block = 1 << 12  # float64 work in 32 kB blocks: no copy of the segment's size
        for i in range(0, length, block):
            self._segment[i : i + block] = (segment[i : i + block] - mean) / self._scale
        self._fs = fs
        self._units = units

    def __call__(self) -> tuple[SpectralLine, ...] | None:
        if self._segment.shape[0] < MIN_SAMPLES:
            return None
        found = detect_lines(self._segment.astype(np.float64), self._fs, units=self._units)
        lines = cast("tuple[SpectralLine, ...]", found)  # one column in, one tuple out
        return tuple(replace(line, amplitude=line.amplitude * self._scale) for line in lines)


def adev_batch(
    data: ArrayLike,
    fs: float,
    *,
    taus: str | ArrayLike = "octave",
    per_decade: int = 10,
    data_type: str = "rate",
    overlapping: bool = True,
    confidence: float | None = 0.683,
    units: str | None = None,
    axis_names: Sequence[str] | None = None,
    gaps: str = "error",
    progress: Callable[[float], None] | None = None,
) -> tuple[tuple[AllanResult, ...], ...]:
    """Allan deviation of a batch of units (a fleet of equal-length logs) in one core call.

    Parameters
    ----------
    data : array_like, shape (units, n) or (units, n, axes)
        One record per unit (and one column per axis), all of ``n`` samples.
    fs, taus, per_decade, data_type, overlapping, confidence, units, axis_names
        As :func:`avar` (applied to every unit).
    gaps : {"error", "omit"}
        As :func:`avar`.
    progress : callable, optional
        Called with the completed fraction of the whole batch.

    Returns
    -------
    tuple of tuple of AllanResult
        ``result[unit][axis]``; a 2-D input has one axis per unit.

    Raises
    ------
    ValueError
        As :func:`avar`, naming the unit (and row and column) at fault.

    Notes
    -----
    The whole batch runs in one call of the Rust core with the GIL released; units run in
    parallel and reuse their scratch buffers (the angle series, n + 1 values per axis), so a
    fleet does not fault in a fresh n-sized buffer per unit. Every result is bit-identical to
    ``adev(data[u], fs, ...)``.

    Examples
    --------
    >>> import numpy as np, gyrobias
    >>> fleet = np.random.default_rng(0).normal(0.0, 0.1, (4, 20_000, 3))  # 4 units, xyz
    >>> res = gyrobias.allan.adev_batch(fleet, 100.0, units="deg/s", axis_names="xyz")
    >>> len(res), len(res[0]), res[2][1].axis
    (4, 3, 'y')
    >>> single = gyrobias.allan.adev(fleet[2], 100.0, units="deg/s", axis_names="xyz")[1]
    >>> bool(np.array_equal(res[2][1].avar, single.avar))
    True
    """
    arr = as_float_array("data", data, ndims=(2, 3))
    callback("progress", progress)
    string("gaps", gaps)
    units = checked_units("units", units)
    fs, estimator, spec, explicit, confidence = _options(
        "adev", fs, taus, per_decade, data_type, overlapping, confidence
    )
    batch = arr.reshape(arr.shape[0], arr.shape[1], 1) if arr.ndim == 2 else arr
    n_axes = batch.shape[2]
    check_axis_names(axis_names, n_axes)
    raw_batch: list[list[Any]] = _core.allan.analyse_batch(
        batch,
        1.0 / fs,
        data_type,
        estimator,
        spec,
        int(per_decade),
        explicit,
        confidence,
        gaps,
        progress,
    )
    return tuple(
        tuple(
            AllanResult._from_core(
                r,
                kind="adev",
                fs=fs,
                data_type=data_type,
                overlapping=overlapping,
                confidence=confidence,
                units=units,
                axis=None if axis_names is None else str(axis_names[i]),
            )
            for i, r in enumerate(unit)
        )
        for unit in raw_batch
    )


def avar(
    data: ArrayLike,
    fs: float,
    *,
    taus: str | ArrayLike = "octave",
    per_decade: int = 10,
    data_type: str = "rate",
    overlapping: bool = True,
    confidence: float | None = 0.683,
    units: str | Sequence[str | None] | None = None,
    axis_names: Sequence[str] | None = None,
    progress: Callable[[float], None] | None = None,
    gaps: str = "error",
) -> AllanResult | tuple[AllanResult, ...]:
    """Allan variance (and deviation) of rate or angle data with confidence intervals.

    Parameters
    ----------
    data : array_like, shape (n,) or (n, axes)
        Samples. A 2-D array holds one axis per column and gives one result per axis (the
        axes are computed in parallel). Integer and float32 input is converted; the caller's
        array is never modified.
    fs : float
        Sample rate in Hz (t0 = 1/fs).
    taus : {"octave", "decade", "log", "all"} or array_like
        τ values: m = 1, 2, 4, …; Stable32's 1, 2, 4, 10, 20, 40, …; ``per_decade``
        log-spaced points per decade; every m; or explicit τ in seconds (each a multiple of
        1/fs and within what the data support, else ``ValueError``).
    per_decade : int
        Points per decade for ``taus="log"``.
    data_type : {"rate", "angle"}
        ``"rate"``: gyro output (e.g. deg/s), integrated after removing the mean.
        ``"angle"``: integrated rate (e.g. deg), used as given.
    overlapping : bool
        Overlapping estimator (SP 1065 eq. 11, default) or the non-overlapping one ([BP] eq. 2).
    confidence : float or None
        Two-sided confidence level of the chi-square intervals (0.683 ≈ 1σ). ``None`` skips
        noise identification and intervals.
    units : str or sequence of str, optional
        Unit of the input samples (``"deg/s"`` for rate, ``"deg"`` for angle), or one per
        column of a 2-D input (a log's gyro and accelerometer axes in one call, no column
        copied); the result's ``unit`` is the rate unit.
    axis_names : sequence of str, optional
        Names of the columns of a 2-D input.
    progress : callable, optional
        Called with the completed fraction (0..1, non-decreasing) from inside the Rust kernel
        while the analysis runs (possibly from a worker thread, with the GIL held). It only
        observes: the results are bit-identical with or without it. An exception it raises
        stops the analysis and propagates.
    gaps : {"error", "omit"}
        What NaN means. ``"error"`` (default): NaN is an error naming its index. ``"omit"``:
        NaN marks a missing sample (e.g. ``io.load(..., fill_gaps=True)``); every estimator
        term whose span touches a gap is left out, ``n_terms`` counts the terms kept and the
        EDF pools the gap-free segments (Satterthwaite); τ is limited by the longest gap-free
        stretch. Defined for the overlapping and non-overlapping ADEV, MDEV and HDEV; not for
        TOTDEV (its reflection at the record's two ends has no meaning with gaps:
        ``ValueError``). Inf is always an error.

    Returns
    -------
    AllanResult or tuple of AllanResult
        One result for 1-D input, one per column for 2-D input.

    Raises
    ------
    ValueError
        NaN/inf in ``data`` (with its index), too few samples, ``fs`` ≤ 0, τ not a multiple of
        1/fs or beyond the data, unknown option strings, 0-D/3-D input.
    TypeError
        Non-numeric ``data``.

    Notes
    -----
    Overlapping Allan variance on the angle series ``x`` (``x_0 = 0``, N + 1 points):
    ``σ²(τ) = Σ_k (x_{k+2m} − 2x_{k+m} + x_k)² / (2τ²(N + 1 − 2m))``. The interval is
    ``[σ²·edf/χ²_{edf,(1+c)/2}, σ²·edf/χ²_{edf,(1−c)/2}]``, ``edf`` from the noise type
    identified at that τ (``alpha``: lag-1 ACF with ≥ 30 decimated points, B1 ratio and R(n)
    with fewer; see the module docs) and at most ``n_terms``.

    **Larger than memory.** A float array memory-mapped from a file (``np.load(path,
    mmap_mode="r")``, ``np.memmap``) is not loaded: the overlapping ADEV (with its noise
    identification and intervals) streams it through the core, reading pieces of the file
    into a reused buffer in several passes, with a peak resident memory of a few tens of MB
    whatever the log's size, and results identical to the in-memory call. The other estimators
    (and ``gaps="omit"``) read the mapping into memory.

    With ``gaps="omit"`` the record is cut at every NaN into segments j (rate segment
    ``[s, e)`` → angle ``x_s..x_e``, integrated per segment) and
    ``σ²(τ) = Σ_j S_j / (2τ² Σ_j n_j)`` over the terms inside one segment; the EDF is
    ``(Σ n_j)² / Σ n_j²/ν_j`` (Satterthwaite 1946) with ν_j Greenhall's EDF of segment j, and
    the noise type is identified on the longest segment.

    References
    ----------
    NIST SP 1065 eqs. 7, 11 and §5; IEEE Std 952-1997 Annex C; [BP] eq. 2.

    Examples
    --------
    >>> import numpy as np, gyrobias
    >>> rate = np.random.default_rng(0).normal(0.0, 0.1, 100_000)   # deg/s, white noise
    >>> r = gyrobias.allan.adev(rate, fs=100.0, units="deg/s")
    >>> bool(abs(r.adev[0] - 0.1) < 0.005)
    True
    >>> rate[40_000:50_000] = np.nan                                  # a 100 s dropout
    >>> g = gyrobias.allan.adev(rate, fs=100.0, gaps="omit", taus=[0.01, 1.0])
    >>> g.n_terms.tolist()                                            # terms avoiding the gap
    [89998, 89602]
    """
    return _analyse(
        "adev",
        data,
        fs,
        taus,
        per_decade,
        data_type,
        overlapping,
        confidence,
        units,
        axis_names,
        progress,
        gaps,
    )


def adev(
    data: ArrayLike,
    fs: float,
    *,
    taus: str | ArrayLike = "octave",
    per_decade: int = 10,
    data_type: str = "rate",
    overlapping: bool = True,
    confidence: float | None = 0.683,
    units: str | Sequence[str | None] | None = None,
    axis_names: Sequence[str] | None = None,
    progress: Callable[[float], None] | None = None,
    gaps: str = "error",
) -> AllanResult | tuple[AllanResult, ...]:
    """Allan deviation σ(τ); same arguments and result as :func:`avar`.

    The result carries both ``adev`` (σ) and ``avar`` (σ²); the two functions differ only in
    name, for users coming from either convention.
    """
    return _analyse(
        "adev",
        data,
        fs,
        taus,
        per_decade,
        data_type,
        overlapping,
        confidence,
        units,
        axis_names,
        progress,
        gaps,
    )


def mdev(
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
    gaps: str = "error",
) -> AllanResult | tuple[AllanResult, ...]:
    """Modified Allan deviation (SP 1065 eq. 14); arguments as :func:`avar`.

    ``Mod σ²(τ) = Σ_j [Σ_{i=j}^{j+m−1} (x_{i+2m} − 2x_{i+m} + x_i)]² / (2 m² τ² (M − 3m + 1))``
    on the M-point angle series. It separates white from flicker angle noise, which the
    ordinary Allan deviation cannot.
    """
    return _analyse(
        "mdev",
        data,
        fs,
        taus,
        per_decade,
        data_type,
        True,
        confidence,
        units,
        axis_names,
        progress,
        gaps,
    )


def hdev(
    data: ArrayLike,
    fs: float,
    *,
    taus: str | ArrayLike = "octave",
    per_decade: int = 10,
    data_type: str = "rate",
    overlapping: bool = True,
    confidence: float | None = 0.683,
    units: str | Sequence[str | None] | None = None,
    axis_names: Sequence[str] | None = None,
    progress: Callable[[float], None] | None = None,
    gaps: str = "error",
) -> AllanResult | tuple[AllanResult, ...]:
    """Hadamard deviation; overlapping (default, SP 1065 eq. 18) or not (eq. 17); arguments as :func:`avar`.

    ``Hσ²(τ) = Σ_k (x_{k+3m} − 3x_{k+2m} + 3x_{k+m} − x_k)² / (6 τ² n)``. A third
    difference: insensitive to a constant rate ramp (linear bias drift).

    **Naming.** ``overlapping=True`` (the default) sums over every ``k`` (``n = M − 3m``): this
    is Stable32's and AllanTools' **OHDEV** (``allantools.ohdev``). ``overlapping=False`` sums
    only over ``k = 0, m, 2m, …`` (``n = ⌊(M − 1)/m⌋ − 2``): Stable32's and AllanTools' **HDEV**
    (``allantools.hdev``). The two estimate the same quantity with very different confidence,
    and for white angle noise their values differ by orders of magnitude at large m, so compare
    like with like: ``result.label`` and the tables say ``OHDEV`` or
    ``HDEV(non-overlap)``. EDF: Greenhall's algorithm for the respective estimator.

    Examples
    --------
    >>> import numpy as np, gyrobias
    >>> rate = np.random.default_rng(8).normal(0.0, 0.1, 10_000)
    >>> gyrobias.allan.hdev(rate, 100.0, overlapping=False).label
    "HDEV (non-overlapping Hadamard, Stable32's HDEV)"
    >>> gyrobias.allan.hdev(rate, 100.0).label
    'OHDEV (overlapping Hadamard)'
    """
    if not overlapping:
        choice("gaps", gaps, ("error",))  # the disjoint-difference estimator has no gap-aware form
        return _analyse_family(
            "hdev",
            "non-overlapping-hadamard",
            data,
            fs,
            taus,
            per_decade,
            data_type,
            confidence,
            units,
            axis_names,
            progress,
            overlapping=False,
        )
    return _analyse(
        "hdev",
        data,
        fs,
        taus,
        per_decade,
        data_type,
        True,
        confidence,
        units,
        axis_names,
        progress,
        gaps,
    )


def totdev(
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
    gaps: str = "error",
) -> AllanResult | tuple[AllanResult, ...]:
    """Total deviation (SP 1065 eq. 25); arguments as :func:`avar`.

    The overlapping Allan variance of the angle series extended by reflection at both ends,
    divided by ``2τ²(M − 2)``; better confidence at long τ. τ is limited to half the record.
    """
    return _analyse(
        "totdev",
        data,
        fs,
        taus,
        per_decade,
        data_type,
        True,
        confidence,
        units,
        axis_names,
        progress,
        gaps,
    )


def stationarity(
    data: ArrayLike,
    fs: float,
    *,
    units: str | None = None,
    axis_names: Sequence[str] | None = None,
) -> Stationarity | tuple[Stationarity, ...]:
    """Is a rate log static? Steps, motion segments and warm-up trends beyond its own noise.

    The check behind :attr:`AllanResult.stationarity`, on samples (one pass over them, in the
    core: ``gyrocore::stationarity``; NaN samples are skipped). See :class:`Stationarity` for
    the test and its threshold.

    Parameters
    ----------
    data : array_like, shape (n,) or (n, axes)
        Rate samples (a memory-mapped array is read in place).
    fs : float
        Sample rate in Hz.
    units : str, optional
        Rate unit, for the messages.
    axis_names : sequence of str, optional
        One name per column.

    Returns
    -------
    Stationarity or tuple of Stationarity
        One per column (a 1-D input gives one).

    Raises
    ------
    ValueError, TypeError
        Data that are not a 1-D or 2-D numeric array, ``fs`` not finite and > 0, an unknown
        unit, a wrong number of axis names.

    Examples
    --------
    >>> import numpy as np, gyrobias
    >>> rate = gyrobias.noise.simulate(360_000, 100.0, arw=0.2 / 60, seed=1)  # 1 h, deg/s
    >>> rate[180_000:183_000] += 10.0  # a 30 s rotation at 10 deg/s in the middle
    >>> check = gyrobias.allan.stationarity(rate, 100.0, units="deg/s")
    >>> check.static, [d.kind for d in check.disturbances]
    (False, ['segment'])
    >>> print(check.disturbances[0])  # located to a block (0.88 s) each side
    motion or disturbance from 1798.72 s to 1831.28 s (rate off its level by up to +10 deg/s)
    """
    arr = as_float_array("data", data, ndims=(1, 2))
    fs = sample_rate(fs)
    units = checked_units("units", units)
    matrix = arr.reshape(-1, 1) if arr.ndim == 1 else arr
    check_axis_names(axis_names, matrix.shape[1])
    raws = _core.stationarity.check_matrix(matrix)
    out = tuple(
        Stationarity._from_core(raw, fs, None if axis_names is None else str(axis_names[i]), units)
        for i, raw in enumerate(raws)
    )
    return out[0] if arr.ndim == 1 else out
