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

import json
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gyrobias import _core
from gyrobias._validation import as_float_array, choice, integer, real, sample_rate, string
from gyrobias._validation import axis_names as check_axis_names
from gyrobias.units import checked_units

__all__ = [
    "NOISE_NAMES",
    "AllanResult",
    "DynamicAllanResult",
    "adev",
    "adev_batch",
    "avar",
    "dynamic_adev",
    "hdev",
    "htotdev",
    "mdev",
    "mtotdev",
    "tdev",
    "theo1",
    "theobr",
    "theoh",
    "totdev",
]

#: Power-law exponent α of the rate PSD (S(f) ∝ f^α) → gyro noise name (IEEE 952 terms).
NOISE_NAMES: dict[int, str] = {
    2: "white angle (quantisation)",
    1: "flicker angle",
    0: "white rate (angle random walk)",
    -1: "flicker rate (bias instability)",
    -2: "rate random walk",
    -3: "flicker walk (rate ramp region)",
    -4: "random run (rate ramp)",
}

Kind = Literal["adev", "mdev", "hdev", "totdev"]
#: Every ``AllanResult.kind``.
KINDS = ("adev", "mdev", "hdev", "totdev", "tdev", "mtotdev", "htotdev", "theo1", "theobr", "theoh")
_ESTIMATOR_OF_KIND = {"mdev": "modified", "hdev": "hadamard", "totdev": "total"}


@dataclass(frozen=True)
class AllanResult:
    """One axis of an Allan-family analysis.

    Attributes
    ----------
    taus : ndarray
        Averaging times τ in seconds.
    avar : ndarray
        Variance estimates σ²(τ) in units of ``unit`` squared (``inf`` or 0 where σ² is beyond float64, for
        data of extreme magnitude: ``adev`` stays exact there).
    adev : ndarray
        Deviations σ(τ) in ``unit`` (for ``kind="mdev"`` etc. the respective deviation).
    deviation : ndarray or None
        The deviations as computed by the core (what ``adev`` returns); ``None`` for results
        built from variances alone (``adev`` is then ``√avar``).
    n_terms : ndarray
        Number of terms in each estimator sum.
    ci_low, ci_high : ndarray or None
        Confidence bounds of the *deviation* at level ``confidence`` (chi-square with ``edf``).
    edf : ndarray or None
        Equivalent degrees of freedom per τ.
    alpha : ndarray or None
        Identified power-law exponent of the rate PSD per τ (S ∝ f^α).
    noise_type : tuple of str
        Gyro name of the identified noise per τ (see :data:`NOISE_NAMES`); empty without CIs.
    fs : float
        Sample rate of the input in Hz.
    unit : str or None
        Unit of the deviation (the rate unit, e.g. ``"deg/s"``); ``None`` if not given.
    data_type : {"rate", "angle"}
        What the input samples were.
    kind : {"adev", "mdev", "hdev", "totdev"}
        Which deviation this is.
    overlapping : bool
        Overlapping estimator (``False`` only for the non-overlapping ADEV of [BP] eq. 2).
    confidence : float or None
        Confidence level of ``ci_low``/``ci_high``.
    axis : str or None
        Axis name (column name), if known.
    """

    taus: NDArray[np.float64]
    avar: NDArray[np.float64]
    n_terms: NDArray[np.int64]
    fs: float
    data_type: str
    kind: str
    overlapping: bool
    unit: str | None = None
    confidence: float | None = None
    edf: NDArray[np.float64] | None = None
    alpha: NDArray[np.int64] | None = None
    ci_low: NDArray[np.float64] | None = None
    ci_high: NDArray[np.float64] | None = None
    axis: str | None = None
    noise_type: tuple[str, ...] = field(default=())
    factors: NDArray[np.int64] | None = None
    deviation: NDArray[np.float64] | None = None

    @property
    def adev(self) -> NDArray[np.float64]:
        """Deviation σ(τ) = √σ²(τ) in ``unit``.

        Taken from ``deviation`` when the core gave it: computed before the data's scale was
        restored, it stays finite for data of extreme magnitude whose variance over- or
        underflows float64 (and equals ``√avar`` bit for bit otherwise).
        """
        if self.deviation is not None:
            return self.deviation
        return np.sqrt(self.avar)

    @property
    def m(self) -> NDArray[np.int64]:
        """Averaging factors: m = τ·fs, except Théo1/ThéoBR points (τ = 0.75·m/fs, m even)."""
        if self.factors is not None:
            return self.factors
        return np.rint(self.taus * self.fs).astype(np.int64)

    @property
    def label(self) -> str:
        """Unambiguous name of the statistic, e.g. ``"OHDEV (overlapping Hadamard)"``."""
        return _label(self.kind, self.overlapping)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dictionary (arrays as lists, units stated)."""
        out: dict[str, Any] = {
            "kind": self.kind,
            "axis": self.axis,
            "fs_hz": self.fs,
            "data_type": self.data_type,
            "overlapping": self.overlapping,
            "unit": self.unit,
            "tau_unit": "s",
            "confidence": self.confidence,
            "taus": self.taus.tolist(),
            "deviation": self.adev.tolist(),
            "variance": self.avar.tolist(),
            "n_terms": self.n_terms.tolist(),
        }
        if self.edf is not None:
            assert self.ci_low is not None and self.ci_high is not None and self.alpha is not None
            out["edf"] = self.edf.tolist()
            out["ci_low"] = self.ci_low.tolist()
            out["ci_high"] = self.ci_high.tolist()
            out["alpha"] = self.alpha.tolist()
            out["noise_type"] = list(self.noise_type)
        return out

    def to_json(self, **kwargs: Any) -> str:
        """:meth:`to_dict` as a JSON string."""
        return json.dumps(self.to_dict(), **kwargs)

    def table(self) -> str:
        """A plain-text table: τ, deviation, confidence interval, EDF, noise type."""
        unit = f" [{self.unit}]" if self.unit else ""
        head = f"{'tau [s]':>12} {_short_label(self.kind, self.overlapping) + unit:>22}"
        if self.ci_low is not None:
            head += f" {'CI low':>12} {'CI high':>12} {'edf':>9}  noise"
        lines = [head]
        for i, tau in enumerate(self.taus):
            row = f"{tau:12.6g} {self.adev[i]:22.6e}"
            if self.ci_low is not None and self.ci_high is not None and self.edf is not None:
                row += (
                    f" {self.ci_low[i]:12.4e} {self.ci_high[i]:12.4e} {self.edf[i]:9.1f}"
                    f"  {self.noise_type[i]}"
                )
            lines.append(row)
        return "\n".join(lines)

    def __str__(self) -> str:
        name = f" axis {self.axis}" if self.axis else ""
        return f"{self.label}{name} (fs = {self.fs:g} Hz, {self.data_type} data)\n{self.table()}"

    def plot(
        self, ax: Any = None, *, label: str | None = None, fit: Any = None, **kwargs: Any
    ) -> Any:
        """Log-log plot of the deviation with confidence bars (needs ``matplotlib``).

        Parameters
        ----------
        ax : matplotlib Axes, optional
            Where to draw (a new figure otherwise).
        label : str, optional
            Legend entry.
        fit : NoiseCoefficients or True, optional
            Overlay a fitted noise model (model curve, per-term asymptotes and the labelled
            read-off points); ``True`` fits one now with :func:`gyrobias.noise.fit`.
        **kwargs
            Passed to :func:`gyrobias.plotting.plot_allan`.

        Returns the matplotlib ``Axes``.
        """
        from gyrobias.plotting import plot_allan

        if fit is True:
            from gyrobias.noise import fit as fit_noise

            fit = fit_noise(self)
        fits = None if fit is None or fit is False else [fit]
        return plot_allan([self], ax=ax, labels=[label] if label else None, fits=fits, **kwargs)


def _options(
    kind: Kind,
    fs: float,
    taus: str | ArrayLike,
    per_decade: int,
    data_type: str,
    overlapping: bool,
    confidence: float | None,
) -> tuple[float, str, str, NDArray[np.float64] | None, float | None]:
    """Normalised options: ``(fs, estimator, tau spec, explicit taus, confidence)``."""
    fs, spec, explicit, _, confidence = _tau_options(fs, taus, per_decade, data_type, confidence)
    if kind == "adev":
        estimator = "overlapping" if overlapping else "non-overlapping"
    else:
        estimator = _ESTIMATOR_OF_KIND[kind]
    return fs, estimator, spec, explicit, confidence


def _tau_options(
    fs: float,
    taus: str | ArrayLike,
    per_decade: int,
    data_type: str,
    confidence: float | None,
) -> tuple[float, str, NDArray[np.float64] | None, int, float | None]:
    """Types of the options every Allan driver shares: ``(fs, tau spec, explicit taus,
    per_decade, confidence)``.

    Only types and names are checked here; the ranges (``per_decade >= 1`` for log spacing,
    ``0 < confidence < 1``, τ on the sample grid, ...) are the core's preconditions.
    """
    fs = sample_rate(fs)  # checked by the core before t0 = 1/fs is computed here
    string("data_type", data_type)  # its value is parsed by the core (DataType::parse)
    per_decade = integer("per_decade", per_decade)
    checked = None if confidence is None else real("confidence", confidence)
    explicit: NDArray[np.float64] | None = None
    spec = "octave"
    if isinstance(taus, str):
        spec = taus  # parsed by the core (Taus::parse), whose ValueError names taus
    else:
        explicit = as_float_array("taus", taus, ndims=(1,))
    return fs, spec, explicit, per_decade, checked


def _result(
    r: dict[str, Any],
    *,
    kind: Kind,
    fs: float,
    data_type: str,
    overlapping: bool,
    confidence: float | None,
    units: str | None,
    axis: str | None,
) -> AllanResult:
    """One :class:`AllanResult` from the core's dict for one axis."""
    t0 = 1.0 / fs
    var = np.asarray(r["variance"], dtype=np.float64)
    m = np.asarray(r["m"]).astype(np.int64)
    kw: dict[str, Any] = {}
    if confidence is not None:
        alpha = np.asarray(r["alpha"]).astype(np.int64)
        kw = {
            "edf": np.asarray(r["edf"], dtype=np.float64),
            "alpha": alpha,
            "ci_low": np.asarray(r["deviation_low"], dtype=np.float64),
            "ci_high": np.asarray(r["deviation_high"], dtype=np.float64),
            "noise_type": tuple(NOISE_NAMES.get(int(a), f"alpha={a}") for a in alpha),
        }
    unit = units
    if units is not None and data_type == "angle":
        unit = f"{units}/s"
    return AllanResult(
        taus=np.asarray(m * t0, dtype=np.float64),
        avar=var,
        deviation=np.asarray(r["deviation"], dtype=np.float64),
        n_terms=np.asarray(r["n_terms"]).astype(np.int64),
        fs=fs,
        data_type=data_type,
        kind=kind,
        overlapping=overlapping if kind == "adev" else True,
        unit=unit,
        confidence=confidence,
        axis=axis,
        **kw,
    )


def _analyse(
    kind: Kind,
    data: ArrayLike,
    fs: float,
    taus: str | ArrayLike,
    per_decade: int,
    data_type: str,
    overlapping: bool,
    confidence: float | None,
    units: str | None,
    axis_names: Sequence[str] | None,
    progress: Callable[[float], None] | None,
    gaps: str = "error",
) -> AllanResult | tuple[AllanResult, ...]:
    if _file_readers(data) is not None:
        arr = np.asarray(data)  # validated below; not converted (that would read the whole file)
        if arr.ndim not in (1, 2):
            raise ValueError(
                f"data must be a 1-D or 2-D array, got a {arr.ndim}-D array of shape {arr.shape}"
            )
        if arr.size == 0:
            raise ValueError("data is empty")
    else:
        arr = as_float_array("data", data, ndims=(1, 2))
    units = checked_units("units", units)
    fs, estimator, spec, explicit, confidence = _options(
        kind, fs, taus, per_decade, data_type, overlapping, confidence
    )
    if _file_readers(data) is not None and not (estimator == "overlapping" and gaps == "error"):
        arr = as_float_array("data", data, ndims=(1, 2))  # other estimators: in memory
    matrix = arr.reshape(-1, 1) if arr.ndim == 1 else arr
    n_axes = matrix.shape[1]
    check_axis_names(axis_names, n_axes)
    readers = _file_readers(data) if estimator == "overlapping" and gaps == "error" else None
    raw: list[Any]
    if readers is not None:
        # A memory-mapped file: stream it through the core in pieces read from the file (the
        # mapping itself is never touched, so its pages do not fill the resident memory).
        raw = []
        for axis, reader in enumerate(readers):
            step = None if progress is None else _axis_progress(progress, axis, len(readers))
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
                    _STREAM_BLOCK,
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
        _result(
            r,
            kind=kind,
            fs=fs,
            data_type=data_type,
            overlapping=overlapping,
            confidence=confidence,
            units=units,
            axis=None if axis_names is None else str(axis_names[i]),
        )
        for i, r in enumerate(raw)
    )
    if arr.ndim == 1:
        return results[0]
    return results


#: Samples per read when a memory-mapped file is streamed (tests set it small).
_STREAM_BLOCK = 1 << 18


class _ColumnReader:
    """``read(start, count)``: samples of one column of a memory-mapped array, read from its file.

    Reads the bytes of rows ``start .. start + count`` with ``readinto`` into a reused buffer
    and converts the column to float64 (any float dtype and byte order), so the mapping's pages
    are never touched and do not count in the resident memory.
    """

    def __init__(
        self, path: str, position: int, row_stride: int, dtype: np.dtype[Any], n_samples: int
    ) -> None:
        self.path = path
        self.position = position
        self.row_stride = row_stride
        self.dtype = dtype
        self.n_samples = n_samples
        self._raw = bytearray()
        self._out = np.empty(0)

    def __call__(self, start: int, count: int) -> NDArray[np.float64]:
        span = (count - 1) * self.row_stride + self.dtype.itemsize
        if len(self._raw) < span:
            self._raw = bytearray(span)
        view = memoryview(self._raw)[:span]
        with open(self.path, "rb", buffering=0) as f:
            f.seek(self.position + start * self.row_stride)
            done = 0
            while done < span:
                got = f.readinto(view[done:])
                if not got:
                    raise OSError(
                        f"{self.path}: file ended while reading rows {start}..{start + count}"
                    )
                done += got
        column = np.ndarray(
            (count,), dtype=self.dtype, buffer=self._raw, strides=(self.row_stride,)
        )
        if self._out.size < count:
            self._out = np.empty(count)
        out = self._out[:count]
        out[...] = column
        return out


def _file_readers(data: object) -> list[_ColumnReader] | None:
    """One reader per column when ``data`` is a float array memory-mapped from a file
    (``np.load(path, mmap_mode="r")``, ``np.memmap``) with positive strides, else ``None``."""
    if not isinstance(data, np.memmap) or data.ndim not in (1, 2) or data.size == 0:
        return None
    mapping = getattr(data, "_mmap", None)
    path = getattr(data, "filename", None)
    if (
        mapping is None
        or path is None
        or data.dtype.kind != "f"
        or any(s <= 0 for s in data.strides)
    ):
        return None
    import mmap
    import os

    if not os.path.isfile(path):  # e.g. io's spill files, unlinked once mapped: read in memory
        return None

    base = np.frombuffer(mapping, dtype=np.uint8)
    first = int(data.offset) - int(data.offset) % mmap.ALLOCATIONGRANULARITY
    position = first + (data.__array_interface__["data"][0] - base.__array_interface__["data"][0])
    del base
    n_axes = 1 if data.ndim == 1 else data.shape[1]
    col_stride = 0 if data.ndim == 1 else data.strides[1]
    return [
        _ColumnReader(
            str(path), position + axis * col_stride, data.strides[0], data.dtype, data.shape[0]
        )
        for axis in range(n_axes)
    ]


def _axis_progress(
    progress: Callable[[float], None], axis: int, n_axes: int
) -> Callable[[float], None]:
    """``progress`` for axis ``axis`` of ``n_axes`` analysed one after the other."""
    return lambda fraction: progress((axis + fraction) / n_axes)


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
            _result(
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
    units: str | None = None,
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
    units : str, optional
        Unit of the input samples (``"deg/s"`` for rate, ``"deg"`` for angle); the result's
        ``unit`` is the rate unit.
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
    units: str | None = None,
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
    units: str | None = None,
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
    units: str | None = None,
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
    units: str | None = None,
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


# --- the rest of the Allan family (issue 15) -----------------------------------------------------

#: gyrobias kind → core statistic of :func:`gyrobias._core.allan.family_analyse`.
_FAMILY_STATISTIC = {
    "tdev": "time",
    "mtotdev": "modified-total",
    "htotdev": "hadamard-total",
    "theo1": "theo1",
    "theobr": "theobr",
    "theoh": "theoh",
}
_LONG_LABEL = {
    "tdev": "TDEV (time deviation)",
    "mtotdev": "MTOTDEV (modified total deviation)",
    "htotdev": "HTOTDEV (Hadamard total deviation)",
    "theo1": "THEO1 (Théo1 deviation)",
    "theobr": "THEOBR (bias-removed Théo1 deviation)",
    "theoh": "THEOH (hybrid ADEV / ThéoBR deviation)",
}


def _label(kind: str, overlapping: bool) -> str:
    if kind == "hdev":
        return (
            "OHDEV (overlapping Hadamard)"
            if overlapping
            else "HDEV (non-overlapping Hadamard, Stable32's HDEV)"
        )
    return _LONG_LABEL.get(kind, kind.upper())


def _short_label(kind: str, overlapping: bool) -> str:
    if kind == "hdev":
        return "OHDEV" if overlapping else "HDEV(non-overlap)"
    return _label(kind, overlapping).split(" (")[0]


def _time_unit(units: str | None, data_type: str) -> str | None:
    """Unit of TDEV: the angle unit (``deg/s`` rate → ``deg``)."""
    if units is None:
        return None
    if data_type == "angle":
        return units
    return units[:-2] if units.endswith("/s") else f"{units}·s"


def _analyse_family(
    kind: str,
    statistic: str,
    data: ArrayLike,
    fs: float,
    taus: str | ArrayLike,
    per_decade: int,
    data_type: str,
    confidence: float | None,
    units: str | None,
    axis_names: Sequence[str] | None,
    progress: Callable[[float], None] | None,
    overlapping: bool = True,
) -> AllanResult | tuple[AllanResult, ...]:
    """Shared driver of the statistics computed by ``gyrocore::allan::family``."""
    arr = as_float_array("data", data, ndims=(1, 2))
    units = checked_units("units", units)
    # Types only: the ranges (per_decade >= 1, 0 < confidence < 1, ...) are the core's checks.
    fs, spec, explicit, per_decade, confidence = _tau_options(
        fs, taus, per_decade, data_type, confidence
    )
    matrix = arr.reshape(-1, 1) if arr.ndim == 1 else arr
    n_axes = matrix.shape[1]
    check_axis_names(axis_names, n_axes)
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
    unit = units
    if kind == "tdev":
        unit = _time_unit(units, data_type)
    elif units is not None and data_type == "angle":
        unit = f"{units}/s"
    results = []
    for i, r in enumerate(raw):
        kw: dict[str, Any] = {}
        if confidence is not None:
            alpha = np.asarray(r["alpha"]).astype(np.int64)
            kw = {
                "edf": np.asarray(r["edf"], dtype=np.float64),
                "alpha": alpha,
                "ci_low": np.asarray(r["deviation_low"], dtype=np.float64),
                "ci_high": np.asarray(r["deviation_high"], dtype=np.float64),
                "noise_type": tuple(NOISE_NAMES.get(int(a), f"alpha={a}") for a in alpha),
            }
        results.append(
            AllanResult(
                taus=np.asarray(r["tau_factor"], dtype=np.float64) * t0,
                avar=np.asarray(r["variance"], dtype=np.float64),
                deviation=np.asarray(r["deviation"], dtype=np.float64),
                n_terms=np.asarray(r["n_terms"]).astype(np.int64),
                fs=fs,
                data_type=data_type,
                kind=kind,
                overlapping=overlapping,
                unit=unit,
                confidence=confidence,
                axis=None if axis_names is None else str(axis_names[i]),
                factors=np.asarray(r["m"]).astype(np.int64),
                **kw,
            )
        )
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
    units: str | None = None,
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
    units: str | None = None,
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
    units: str | None = None,
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
    units: str | None = None,
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
    units: str | None = None,
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
    units: str | None = None,
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


@dataclass(frozen=True)
class DynamicAllanResult:
    """A dynamic (time-resolved) Allan deviation: one overlapping ADEV curve per window.

    Attributes
    ----------
    times : ndarray, shape (windows,)
        Centre of each window in seconds from the first sample.
    starts : ndarray, shape (windows,)
        Index of each window's first sample.
    taus : ndarray, shape (n_tau,)
        Averaging times τ in seconds (common to all windows).
    avar : ndarray, shape (windows, n_tau)
        Overlapping Allan variance of each window in units of ``unit`` squared.
    n_terms : ndarray, shape (n_tau,)
        Terms of each window's sum.
    window, step : int
        Window length and window step in samples.
    fs : float
        Sample rate in Hz.
    unit : str or None
        Unit of the deviation (the rate unit).
    data_type : {"rate", "angle"}
        What the input samples were.
    """

    times: NDArray[np.float64]
    starts: NDArray[np.int64]
    taus: NDArray[np.float64]
    avar: NDArray[np.float64]
    n_terms: NDArray[np.int64]
    window: int
    step: int
    fs: float
    data_type: str
    unit: str | None = None

    @property
    def adev(self) -> NDArray[np.float64]:
        """Deviation σ(t, τ) = √σ²(t, τ) in ``unit``, shape (windows, n_tau)."""
        return np.sqrt(self.avar)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dictionary (arrays as nested lists, units stated)."""
        return {
            "kind": "dynamic_adev",
            "fs_hz": self.fs,
            "data_type": self.data_type,
            "unit": self.unit,
            "time_unit": "s",
            "tau_unit": "s",
            "window_samples": self.window,
            "step_samples": self.step,
            "times": self.times.tolist(),
            "taus": self.taus.tolist(),
            "deviation": self.adev.tolist(),
            "n_terms": self.n_terms.tolist(),
        }

    def plot(self, ax: Any = None, **kwargs: Any) -> Any:
        """Heat map of log10 σ(t, τ) over time and τ with a colour bar in ``unit`` (needs matplotlib).

        ``kwargs`` go to :func:`gyrobias.plotting.plot_dynamic_allan`; returns the ``Axes``.
        """
        from gyrobias.plotting import plot_dynamic_allan

        return plot_dynamic_allan(self, ax=ax, **kwargs)


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
    fs, spec, explicit, per_decade, _ = _tau_options(fs, taus, per_decade, data_type, None)
    window = integer("window", window)  # window <= n, step >= 1: the core's checks
    step = integer("step", step)
    t0 = 1.0 / fs
    raw = _core.allan.dynamic_avar(
        np.ascontiguousarray(arr), t0, data_type, window, step, spec, int(per_decade), explicit
    )
    starts = np.asarray(raw["starts"]).astype(np.int64)
    unit = units
    if units is not None and data_type == "angle":
        unit = f"{units}/s"
    return DynamicAllanResult(
        times=np.asarray((starts + window / 2.0) * t0, dtype=np.float64),
        starts=starts,
        taus=np.asarray(raw["m"]).astype(np.float64) * t0,
        avar=np.asarray(raw["variance"], dtype=np.float64),
        n_terms=np.asarray(raw["n_terms"]).astype(np.int64),
        window=window,
        step=step,
        fs=fs,
        data_type=data_type,
        unit=unit,
    )
