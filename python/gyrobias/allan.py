"""Allan-family deviations of gyro rate or angle data.

All estimators work on the angle series ``x``. Rate samples ``Ω_i`` at period ``t0 = 1/fs``
are integrated after the mean is removed, with ``x_0 = 0`` prepended (NIST SP 1065, the
AllanTools and Stable32 convention)::

    x_k = t0 · Σ_{i<k} (Ω_i − mean(Ω)),   k = 0..N

and with ``τ = m·t0`` the overlapping Allan variance is (SP 1065 eq. 11, [TS] eq. 1)::

    σ²(τ) = Σ_{k=0}^{N−2m} (x_{k+2m} − 2x_{k+m} + x_k)² / (2 τ² (N + 1 − 2m))

Confidence intervals are chi-square intervals with the equivalent degrees of freedom of the
identified power-law noise (SP 1065 §5; noise identified per τ by the lag-1 autocorrelation
method of Riley & Greenhall, EDF by Greenhall's algorithm for the Allan, modified and Hadamard
variances and by SP 1065's formulas for the total variance).

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
from gyrobias._validation import as_float_array, choice, positive_float

__all__ = [
    "NOISE_NAMES",
    "AllanResult",
    "adev",
    "adev_batch",
    "avar",
    "hdev",
    "mdev",
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
_ESTIMATOR_OF_KIND = {"mdev": "modified", "hdev": "hadamard", "totdev": "total"}
_TAU_SPECS = ("octave", "decade", "log", "all")


@dataclass(frozen=True)
class AllanResult:
    """One axis of an Allan-family analysis.

    Attributes
    ----------
    taus : ndarray
        Averaging times τ in seconds.
    avar : ndarray
        Variance estimates σ²(τ) in ``unit``².
    adev : ndarray
        Deviations σ(τ) in ``unit`` (for ``kind="mdev"`` etc. the respective deviation).
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

    @property
    def adev(self) -> NDArray[np.float64]:
        """Deviation σ(τ) = √σ²(τ) in ``unit``."""
        return np.sqrt(self.avar)

    @property
    def m(self) -> NDArray[np.int64]:
        """Averaging factors m = τ·fs."""
        return np.rint(self.taus * self.fs).astype(np.int64)

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
        head = f"{'tau [s]':>12} {self.kind.upper() + unit:>22}"
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
        return f"{self.kind.upper()}{name} (fs = {self.fs:g} Hz, {self.data_type} data)\n{self.table()}"

    def plot(self, ax: Any = None, *, label: str | None = None, fit: Any = None, **kwargs: Any) -> Any:
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
    fs = positive_float("fs", fs)
    choice("data_type", data_type, ("rate", "angle"))
    if isinstance(per_decade, bool) or not isinstance(per_decade, (int, np.integer)) or per_decade < 1:
        raise ValueError(f"per_decade must be an integer >= 1, got {per_decade!r}")
    if confidence is not None:
        c = float(confidence)
        if not 0.0 < c < 1.0:
            raise ValueError(f"confidence must lie strictly between 0 and 1 (or be None), got {confidence!r}")
        confidence = c
    if kind == "adev":
        estimator = "overlapping" if overlapping else "non-overlapping"
    else:
        estimator = _ESTIMATOR_OF_KIND[kind]
    explicit: NDArray[np.float64] | None = None
    spec = "octave"
    if isinstance(taus, str):
        spec = choice("taus", taus, _TAU_SPECS)
    else:
        explicit = as_float_array("taus", taus, ndims=(1,))
    return fs, estimator, spec, explicit, confidence


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
            "ci_low": np.sqrt(np.asarray(r["low"], dtype=np.float64)),
            "ci_high": np.sqrt(np.asarray(r["high"], dtype=np.float64)),
            "noise_type": tuple(NOISE_NAMES.get(int(a), f"alpha={a}") for a in alpha),
        }
    unit = units
    if units is not None and data_type == "angle":
        unit = f"{units}/s"
    return AllanResult(
        taus=np.asarray(m * t0, dtype=np.float64),
        avar=var,
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
    arr = as_float_array("data", data, ndims=(1, 2))
    fs, estimator, spec, explicit, confidence = _options(
        kind, fs, taus, per_decade, data_type, overlapping, confidence
    )
    matrix = arr.reshape(-1, 1) if arr.ndim == 1 else arr
    n_axes = matrix.shape[1]
    if axis_names is not None and len(axis_names) != n_axes:
        raise ValueError(f"axis_names has {len(axis_names)} names for {n_axes} axes")
    # One core call for all τ and axes; progress is reported from inside the kernel, so the
    # numbers are the same with or without it.
    raw: list[Any] = _core.allan.analyse(
        matrix, 1.0 / fs, data_type, estimator, spec, int(per_decade), explicit, confidence, gaps, progress
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
    fs, estimator, spec, explicit, confidence = _options(
        "adev", fs, taus, per_decade, data_type, overlapping, confidence
    )
    batch = arr.reshape(arr.shape[0], arr.shape[1], 1) if arr.ndim == 2 else arr
    n_axes = batch.shape[2]
    if axis_names is not None and len(axis_names) != n_axes:
        raise ValueError(f"axis_names has {len(axis_names)} names for {n_axes} axes")
    raw_batch: list[list[Any]] = _core.allan.analyse_batch(
        batch, 1.0 / fs, data_type, estimator, spec, int(per_decade), explicit, confidence, gaps, progress
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
    ``[σ²·edf/χ²_{edf,(1+c)/2}, σ²·edf/χ²_{edf,(1−c)/2}]``.

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
    return _analyse("adev", data, fs, taus, per_decade, data_type, overlapping, confidence, units, axis_names, progress, gaps)


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
    return _analyse("adev", data, fs, taus, per_decade, data_type, overlapping, confidence, units, axis_names, progress, gaps)


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
    return _analyse("mdev", data, fs, taus, per_decade, data_type, True, confidence, units, axis_names, progress, gaps)


def hdev(
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
    """Overlapping Hadamard deviation (SP 1065 eq. 18); arguments as :func:`avar`.

    ``Hσ²(τ) = Σ_k (x_{k+3m} − 3x_{k+2m} + 3x_{k+m} − x_k)² / (6 τ² (M − 3m))``. A third
    difference: insensitive to a constant rate ramp (linear bias drift).
    """
    return _analyse("hdev", data, fs, taus, per_decade, data_type, True, confidence, units, axis_names, progress, gaps)


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
    return _analyse("totdev", data, fs, taus, per_decade, data_type, True, confidence, units, axis_names, progress, gaps)
