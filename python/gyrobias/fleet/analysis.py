"""Fleet analysis: the single-unit pipeline (load, ADEV, noise fit) on every unit of a fleet, as
Dask tasks, into the fleet table."""

from __future__ import annotations

import glob
import math
import os
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gyrobias import _core, allan, cleaning, io, noise
from gyrobias._validation import (
    as_float_array,
    callback,
    checked_path,
    mapping,
    pair,
    positive_float,
    real,
    sequence,
    string,
    text,
)
from gyrobias._validation import axis_names as check_axis_names
from gyrobias._validation import names as name_list
from gyrobias.fleet.spread import OUT_OF_FAMILY_THRESHOLD, _finish
from gyrobias.fleet.table import GM_PARAMETERS, DataFrame, _require
from gyrobias.units import base_unit, sensor_kind

_GLOB_CHARS = frozenset("*?[")

#: Most threads of the local scheduler (a larger count is a mistake, not a machine).
_MAX_WORKERS = 65536


@dataclass(frozen=True)
class _Options:
    """Everything a worker needs to analyse one unit (picklable)."""

    fs: float | None
    fit: str
    taus: str | tuple[float, ...]
    confidence: float | None
    axis_names: tuple[str, ...] | None
    gaps: str = "error"
    load: dict[str, Any] = field(default_factory=dict)
    array_units: tuple[str | None, ...] = ()
    terms: tuple[str, ...] | None = None  # None: noise.fit's default (the five IEEE terms)
    start: io.TimeBound | None = None  # the span of every log analysed (GyroLog.select)
    stop: io.TimeBound | None = None
    bound_confidence: float = 0.95
    outliers: float | None = None  # cleaning.clean after the span, before the analysis
    detrend: str | None = None
    tau_range: tuple[float, float] | None = None  # noise.fit's (joint fit)
    lines: str | tuple[float | tuple[float, float], ...] | None = "auto"

    @property
    def cleans(self) -> bool:
        """Whether a cleaning step runs on every unit."""
        return self.outliers is not None or self.detrend is not None

    @property
    def fit_extra(self) -> dict[str, Any]:
        """``tau_range`` and ``lines`` for noise.fit when given (the joint fit's options)."""
        if self.tau_range is None and self.lines == "auto":
            return {}
        lines = list(self.lines) if isinstance(self.lines, tuple) else self.lines
        return {"tau_range": self.tau_range, "lines": lines}

    @property
    def n_gauss_markov(self) -> int:
        """Gauss–Markov terms the fit has (``"GM"``: one, ``"GM2"``: two, as in noise.fit)."""
        return _gauss_markov_count(self.terms)


def _gauss_markov_count(terms: Sequence[str] | None) -> int:
    if not terms:
        return 0
    return 2 if "GM2" in terms else 1 if "GM" in terms else 0


# --------------------------------------------------------------------------------- per unit


def _term_unit(units: str | None, symbol: str) -> str | None:
    return None if units is None else base_unit(units, symbol)


def _empty_row(source: str) -> dict[str, Any]:
    return {"source": source, "axis": None, "error": None}


def _put_term(row: dict[str, Any], name: str, term: noise.Term | None) -> None:
    """``name``, ``name_uncertainty`` and ``name_upper_bound`` of a row from a fitted term (NaN
    when missing; the upper bound only for a term the log does not show)."""
    value = None if term is None else term.value
    unc = None if term is None else term.uncertainty
    bound = term.upper_bound if term is not None and term.bounded else None
    row[name] = math.nan if value is None else float(value)
    row[f"{name}_uncertainty"] = math.nan if unc is None else float(unc)
    row[f"{name}_upper_bound"] = math.nan if bound is None else float(bound)


def _error_text(exc: BaseException) -> str:
    text = " ".join(str(exc).split()) or "(no message)"
    return f"{type(exc).__name__}: {text}"


def _rows_for(
    source: str,
    data: NDArray[np.float64],
    fs: float,
    axis_names: Sequence[str],
    axis_units: Sequence[str | None],
    opts: _Options,
    sampling: io.SamplingReport | None,
    selection: io.Selection | None = None,
) -> list[dict[str, Any]]:
    """Allan analysis and fit of one unit (``data`` is ``(n,)`` or ``(n, axes)``), after the
    cleaning steps of ``opts`` (whose gaps the Allan analysis then skips)."""
    matrix = data.reshape(-1, 1) if data.ndim == 1 else data
    allan_options = _allan_options(axis_names, axis_units, opts)
    cleaned = None
    if opts.cleans:
        cleaned = cleaning.clean(
            matrix, fs, outliers=opts.outliers, detrend=opts.detrend, units=list(axis_units)
        )
        matrix = cleaned.data
        if cleaned.has_gaps:
            allan_options["gaps"] = "omit"
    results = allan.adev(matrix, fs, **allan_options)
    assert isinstance(results, tuple)
    rows = _fit_rows(
        source, results, int(matrix.shape[0]), fs, axis_units, opts, sampling, selection
    )
    if cleaned is not None:
        for row in rows:
            row["cleaning"] = cleaned.describe()
    return rows


def _allan_options(
    axis_names: Sequence[str], axis_units: Sequence[str | None], opts: _Options
) -> dict[str, Any]:
    """Keyword arguments of ``allan.adev``/``adev_batch`` (one unit label when all axes share it)."""
    return {
        "taus": opts.taus if isinstance(opts.taus, str) else np.asarray(opts.taus),
        "confidence": opts.confidence,
        "gaps": opts.gaps,
        "units": axis_units[0] if len(set(axis_units)) == 1 else None,
        "axis_names": list(axis_names),
    }


def _fit_rows(
    source: str,
    results: Sequence[allan.AllanResult],
    n: int,
    fs: float,
    axis_units: Sequence[str | None],
    opts: _Options,
    sampling: io.SamplingReport | None,
    selection: io.Selection | None = None,
) -> list[dict[str, Any]]:
    """The noise fit of each axis' Allan result, one row per axis."""
    common: dict[str, Any] = {
        "fs": fs,
        "duration": n / fs,
        "n_samples": n,
        "selection": None if selection is None else str(selection),
        "cleaning": None,
        "n_gaps": None,
        "missing_samples": None,
        "longest_gap": math.nan,
        "n_duplicates": None,
        "sampling_warnings": None,
    }
    if sampling is not None and sampling.time_unit is not None:
        common.update(
            n_gaps=sampling.n_gaps,
            missing_samples=sampling.missing_samples,
            longest_gap=math.nan if sampling.longest_gap is None else sampling.longest_gap,
            n_duplicates=sampling.n_duplicates,
            sampling_warnings="; ".join(sampling.warnings) or None,
        )
    rows = []
    for r, unit in zip(results, axis_units):
        row = _empty_row(source)
        row.update(common)
        row["axis"] = r.axis
        row["data_unit"] = unit
        row["fit_method"] = opts.fit
        row["bound_confidence"] = opts.bound_confidence
        row["adev_tau"] = np.asarray(r.taus, dtype=np.float64)
        row["adev"] = np.asarray(r.adev, dtype=np.float64)
        fit_options: dict[str, Any] = {
            "method": opts.fit,
            "unit": unit,
            "bound_confidence": opts.bound_confidence,
        }
        if opts.terms is not None:
            fit_options["terms"] = opts.terms
        fit_options.update(opts.fit_extra)
        try:
            row["sensor"] = None if unit is None else sensor_kind(unit)
            c = noise.fit(r, **fit_options)
        except Exception as exc:  # noqa: BLE001 - one failed fit is one error row, never a crash
            row["error"] = f"noise fit: {_error_text(exc)}"
            rows.append(row)
            continue
        for t in c.terms:
            _put_term(row, t.symbol, t)
            row[f"{t.symbol}_unit"] = _term_unit(unit, t.symbol)
        # Gauss–Markov terms in noise.fit's order (increasing correlation time); a term the fit
        # reports missing is NaN, with its units still given.
        gm = c.gauss_markov
        for k in range(opts.n_gauss_markov):
            for p in GM_PARAMETERS:
                name = f"GM{k + 1}_{p}"
                term = getattr(gm[k], p) if k < len(gm) else None
                _put_term(row, name, term)
                row[f"{name}_unit"] = None if term is None else term.unit
        row["chi2"] = math.nan if c.chi2 is None else float(c.chi2)
        row["dof"] = c.dof
        row["chi2_reduced"] = math.nan if c.chi2 is None or not c.dof else float(c.chi2) / c.dof
        d = c.diagnostics
        row["p_value"] = math.nan if d is None else float(d.p_value)
        row["fit_warnings"] = None if d is None else "; ".join(d.warnings) or None
        rows.append(row)
    return rows


def _analyse_file(path: str, opts: _Options) -> list[dict[str, Any]]:
    """Load and analyse one log; every failure becomes an error row."""
    try:
        log = io.load(path, fs=opts.fs, **opts.load)
        if log.fs is None:
            raise ValueError(
                f"{os.path.basename(path)} has no time column: give the sample rate (fs)"
            )
        fs = float(log.fs)
        if opts.start is not None or opts.stop is not None:
            log = log.select(opts.start, opts.stop)
        # A wrong number of axis_names is allan.adev's error (one check, _validation.axis_names),
        # reported in this file's row.
        names: Sequence[str] = log.columns if opts.axis_names is None else opts.axis_names
        units = (
            tuple(log.units) if len(log.units) == len(log.columns) else (None,) * len(log.columns)
        )
        return _rows_for(path, log.data, fs, names, units, opts, log.sampling, log.selection)
    except Exception as exc:  # noqa: BLE001 - a failed file is a row with its error
        row = _empty_row(path)
        row["error"] = _error_text(exc)
        return [row]


def _analyse_block(block: NDArray[np.float64], start: int, opts: _Options) -> list[dict[str, Any]]:
    """Analyse units ``start …`` of an array block ``(units, n)`` or ``(units, n, axes)``.

    One :func:`gyrobias.allan.adev_batch` call for the block (the core reuses its scratch
    buffers across units; bit-identical to one ``adev`` per unit). If the batch call fails
    (a unit with NaN, say), the units are analysed one by one so that only the bad one is an
    error row.
    """
    assert opts.fs is not None and opts.axis_names is not None
    names, units = opts.axis_names, opts.array_units
    selection = None
    if opts.start is not None or opts.stop is not None:
        # checked in analyse() for the whole array: here only the view is taken
        selection = io.resolve_selection(int(block.shape[1]), opts.fs, opts.start, opts.stop)
        block = block[:, selection.start_index : selection.stop_index]
    n = int(block.shape[1])
    batch: tuple[tuple[allan.AllanResult, ...], ...] | None = None
    if not opts.cleans:  # cleaning is per unit: then one adev per cleaned unit
        try:
            batch = allan.adev_batch(block, opts.fs, **_allan_options(names, units, opts))
        except Exception:  # noqa: BLE001 - find the failing unit below, one at a time
            batch = None
    rows: list[dict[str, Any]] = []
    for i in range(block.shape[0]):
        source = f"array[{start + i}]"
        try:
            if batch is None:
                rows.extend(
                    _rows_for(source, block[i], opts.fs, names, units, opts, None, selection)
                )
            else:
                rows.extend(_fit_rows(source, batch[i], n, opts.fs, units, opts, None, selection))
        except Exception as exc:  # noqa: BLE001 - one failed unit is one error row
            row = _empty_row(source)
            row["error"] = _error_text(exc)
            rows.append(row)
    return rows


# --------------------------------------------------------------------------------- sources


def _expand(sources: Any) -> list[str] | NDArray[np.float64]:
    """File paths (globs expanded, in order) or the validated array."""
    items: list[Any]
    if isinstance(sources, (str, os.PathLike)):
        items = [sources]
    elif isinstance(sources, np.ndarray):
        return as_float_array("sources", sources, ndims=(2, 3))
    elif (
        isinstance(sources, Sequence)
        and sources
        and all(isinstance(s, (str, os.PathLike)) for s in sources)
    ):
        items = list(sources)
    elif isinstance(sources, Sequence) and not sources:
        raise ValueError("sources is empty")
    else:
        try:
            return as_float_array("sources", sources, ndims=(2, 3))
        except (TypeError, ValueError) as exc:
            raise TypeError(
                "sources must be a glob pattern, a path, a list of paths, or an array of shape "
                f"(units, n) or (units, n, axes); {exc}"
            ) from None
    paths: list[str] = []
    for item in items:
        text = str(checked_path("sources", item))
        if isinstance(item, str) and _GLOB_CHARS & set(text):
            hits = sorted(glob.glob(text, recursive=True))
            if not hits:
                raise ValueError(f"sources: no file matches {text!r}")
            paths.extend(hits)
        else:
            paths.append(str(text))
    return paths


def _blocks(n_units: int, workers: int) -> list[tuple[int, int]]:
    """Contiguous unit ranges: about four tasks per worker (load balance), ≥ 1 unit each."""
    size = max(1, math.ceil(n_units / (4 * max(1, workers))))
    return [(s, min(s + size, n_units)) for s in range(0, n_units, size)]


# --------------------------------------------------------------------------------- Dask


def _run(
    tasks: list[tuple[Any, tuple[Any, ...], str]],
    client: Any,
    num_workers: int | None,
    progress: Callable[[float], None] | None,
) -> list[Any]:
    """Run ``(function, args, source)`` tasks; a task lost on a worker becomes an error row.

    ``progress(fraction)`` is called as tasks finish (in any order); results keep task order.
    """
    dask = _require("dask")
    total = max(1, len(tasks))
    if client is None:
        delayed = [dask.delayed(fn, pure=False)(*args) for fn, args, _ in tasks]
        if progress is None:
            return list(dask.compute(*delayed, scheduler="threads", num_workers=num_workers))
        callbacks = _require("dask.callbacks")
        done = 0

        def posttask(*_: Any) -> None:
            nonlocal done
            done += 1
            progress(min(done / total, 1.0))

        with callbacks.Callback(posttask=posttask):
            out = list(dask.compute(*delayed, scheduler="threads", num_workers=num_workers))
        progress(1.0)
        return out
    futures = [client.submit(fn, *args, pure=False) for fn, args, _ in tasks]
    if progress is not None:
        distributed = _require("distributed")
        for done, _ in enumerate(distributed.as_completed(futures), start=1):
            progress(done / total)
    results: list[Any] = []
    for future, (_, _, source) in zip(futures, tasks):
        try:
            results.append(future.result())
        except Exception as exc:  # noqa: BLE001 - worker died, task cancelled: report, go on
            row = _empty_row(source)
            row["error"] = f"task failed on the cluster: {_error_text(exc)}"
            results.append([row])
    return results


def _connect(client: Any) -> tuple[Any, bool]:
    """A ``distributed.Client`` (given, or connected to the address given) and whether we own it."""
    if client is None:
        return None, False
    if isinstance(client, str):
        text("client", client)
        distributed = _require("distributed")
        try:
            return distributed.Client(client), True
        except ValueError as exc:  # distributed's address parser: "missing port number in …"
            raise ValueError(
                f"client must be a scheduler address such as 'tcp://host:8786', got {client!r} "
                f"({exc})"
            ) from None
    if not (hasattr(client, "submit") and hasattr(client, "scatter")):
        raise TypeError(
            "client must be a distributed.Client, a scheduler address such as 'tcp://host:8786', "
            f"or None (the local threaded scheduler); got {type(client).__name__}"
        )
    return client, False


def analyse(
    sources: str | os.PathLike[str] | Sequence[str | os.PathLike[str]] | ArrayLike,
    *,
    fs: float | None = None,
    units: str | Sequence[str | None] | Mapping[str, str] | None = None,
    fit: str = "joint",
    terms: Sequence[str] | str | None = None,
    client: Any = None,
    columns: Sequence[str | int] | str | None = None,
    time_column: str | int | bool | None = None,
    load_options: Mapping[str, Any] | None = None,
    axis_names: Sequence[str] | None = None,
    taus: str | ArrayLike = "octave",
    confidence: float | None = 0.683,
    gaps: str = "error",
    threshold: float = OUT_OF_FAMILY_THRESHOLD,
    num_workers: int | None = None,
    progress: Callable[[float], None] | None = None,
    start: str | float | io.TimeBound | None = None,
    stop: str | float | io.TimeBound | None = None,
    bound_confidence: float = 0.95,
    outliers: float | None = None,
    detrend: str | None = None,
    tau_range: tuple[float, float] | None = None,
    lines: str | Sequence[float | tuple[float, float]] | None = "auto",
) -> DataFrame:
    """Noise terms of every unit of a fleet, one row per unit and axis, computed on Dask.

    Parameters
    ----------
    sources : str, path, sequence of paths, or array_like
        A glob pattern (``"logs/*.csv"``, ``**`` recurses), a path, a list of paths and/or
        patterns (any format :func:`gyrobias.io.load` reads), or an array of rate samples of
        shape ``(units, n)`` or ``(units, n, axes)``.
    fs : float, optional
        Sample rate in Hz. Required for arrays and for logs without a time column; for logs
        with timestamps it is the user-given rate of :func:`gyrobias.io.load`.
    units : str, sequence or mapping, optional
        Unit of the rate samples (``"deg/s"``, ``"rad/s"``, ``"m/s^2"``, …), one per channel,
        or per channel name, as :func:`gyrobias.io.load` takes it (bags carry their own: rad/s
        and m/s²). Each row's terms are then in the base units of its channel (``N`` in deg/√s
        for deg/s, …) and ``sensor`` is ``"gyro"`` or ``"accel"``.
    fit : {"joint", "ieee"}
        Noise-coefficient method of :func:`gyrobias.noise.fit`.
    terms : sequence of {"Q", "N", "B", "K", "R", "GM", "GM2"}, optional
        Terms of :func:`gyrobias.noise.fit` (default: its default, the five IEEE terms).
        ``"GM"`` adds a first-order Gauss–Markov term, ``"GM2"`` two (joint fit only), with the
        columns ``GM1_sigma`` and ``GM1_correlation_time`` (``GM2_…`` for the second term, in
        noise.fit's order: increasing correlation time).
    client : distributed.Client or str, optional
        Run on this Dask cluster (a ``Client`` of a ``LocalCluster`` or of a remote
        scheduler), or connect to the scheduler at this address for the call. Default: Dask's
        local threaded scheduler.
    columns, time_column, load_options
        Passed to :func:`gyrobias.io.load` for every file (``load_options`` is a dict of its
        other keyword arguments, e.g. ``{"time_unit": "ns"}``).
    axis_names : sequence of str, optional
        Names of the axes (default: the log's channel names; ``col0``, ``col1``, … for arrays).
    taus : {"octave", "decade", "log", "all"} or array_like
        τ grid of the Allan analysis (:func:`gyrobias.allan.adev`).
    confidence : float or None
        Confidence level of the Allan intervals; their EDFs weight the joint fit.
    gaps : {"error", "omit"}
        What NaN samples mean (:func:`gyrobias.allan.adev`): ``"omit"`` analyses logs read
        with ``load_options={"fill_gaps": True}`` (NaN rows in the gaps of the timestamps)
        with the gap-aware estimators.
    threshold : float
        ``|z|`` above which a term is out of family (module docs).
    num_workers : int, optional
        Threads of the local threaded scheduler (default: one per core). Ignored with ``client``.
    progress : callable, optional
        Called with the completed fraction (0..1) of the tasks as they finish; never changes
        a result.
    start, stop : float, str or None
        The span of every log analysed, ``[start, stop)`` (:meth:`gyrobias.io.GyroLog.select`:
        seconds from each log's start, ``"90min"``, ``"0.5h"``, or a sample index
        ``"250000n"``); the ``selection`` column states it. A log that the span does not fit
        is an error row.
    bound_confidence : float
        One-sided confidence level of the upper bounds of terms a log does not show
        (:func:`gyrobias.noise.fit`; default 0.95).
    outliers : float, optional
        Remove every unit's outliers above this robust z-score after the span and before the
        analysis (:func:`gyrobias.cleaning.clean`; they become gaps, skipped by the Allan
        analysis); the ``cleaning`` column states what was removed.
    detrend : {"linear", "quadratic"}, optional
        Remove every unit's drift after the outliers (:func:`gyrobias.cleaning.clean`).
    tau_range : (float, float), optional
        ``fit="joint"``: fit the Allan points in this τ range (seconds) (:func:`gyrobias.noise.fit`).
    lines : "auto", sequence or None
        ``fit="joint"``: the lines modelled by a sinusoidal term (:func:`gyrobias.noise.fit`).

    Returns
    -------
    pandas.DataFrame
        One row per unit and axis (a failed file: one row with ``error`` set), in the order of
        ``sources``. Columns: ``source``, ``axis``, ``sensor``, ``data_unit``, ``fs`` [Hz],
        ``duration`` [s] (``n_samples / fs``), ``n_samples`` (of the span analysed),
        ``selection`` (the span, ``"0.5–2.3 h of 2.8 h (samples …)"``, with ``start``/``stop``;
        else ``None``), ``cleaning`` (the steps of ``outliers``/``detrend`` and the outliers
        removed per axis, else ``None``); the gap summary of the
        timestamps (``<NA>`` without them): ``n_gaps``, ``missing_samples``, ``longest_gap``
        [s], ``n_duplicates``, ``sampling_warnings``; ``fit_method``; for every term X in Q, N,
        B, K, R (and, with Gauss–Markov ``terms``, ``GM1_sigma``, ``GM1_correlation_time``,
        ``GM2_sigma``, ``GM2_correlation_time``): ``X`` and ``X_uncertainty`` (1σ) in the base
        unit ``X_unit`` (NaN when the fit has no such term), ``X_z`` (robust z-score against
        the fleet), ``X_upper_bound`` (a term the log does not show: the largest value the data
        allow, at the one-sided level ``bound_confidence``; else NaN); the goodness of fit
        ``chi2``, ``dof``, ``chi2_reduced`` (joint fit), ``p_value`` and ``fit_warnings`` of
        :attr:`gyrobias.noise.NoiseCoefficients.diagnostics`; ``out_of_family`` (nullable bool),
        ``out_of_family_terms``; ``error``; ``adev_tau`` [s] and ``adev`` [data unit], the
        Allan curve (arrays).

    Raises
    ------
    ValueError
        A glob that matches nothing, an empty list, an array without ``fs``, bad options (the
        options of :func:`gyrobias.allan.adev` and :func:`gyrobias.noise.fit` are judged once,
        up front, by those functions themselves: their messages name the argument).
    TypeError
        ``sources`` or ``client`` of the wrong kind.
    ImportError
        The ``fleet`` extra is not installed.

    Notes
    -----
    Every row equals the single-unit API: ``allan.adev(data, fs, taus=taus,
    confidence=confidence, units=units)`` then ``noise.fit(result, method=fit, terms=terms)``;
    results do
    not depend on the scheduler, the number of workers or how units are grouped into tasks.
    Files are read on the workers (give paths that the workers can see). Arrays are cut into
    blocks of units; on a cluster each block is sent to a worker once.
    """
    pd = _require("pandas")
    # Types here; values are judged by their owners (_check_options: allan.adev and the core
    # for fs, confidence, gaps and the τ grid, noise.fit for fit and terms).
    if fs is not None:
        fs = real("fs", fs)
    if isinstance(units, str) and not set(text("units", units)) & {",", "="}:
        sensor_kind(units)  # an unknown or non-rate unit fails here, once, not in every row
    if confidence is not None:
        confidence = real("confidence", confidence)
    term_tuple = None
    if terms is not None:
        term_tuple = tuple(name_list("terms", terms))
    threshold = positive_float("threshold", threshold)
    callback("progress", progress)
    first = io.parse_time_bound(start, name="start")
    last = io.parse_time_bound(stop, name="stop")
    if num_workers is not None and (
        isinstance(num_workers, bool)
        or not isinstance(num_workers, int)
        or not 1 <= num_workers <= _MAX_WORKERS
    ):
        raise ValueError(
            f"num_workers must be an integer from 1 to {_MAX_WORKERS}, got {num_workers!r}"
        )
    tau_spec: str | tuple[float, ...]
    if isinstance(taus, str):
        tau_spec = string("taus", taus)
    else:
        tau_spec = tuple(float(t) for t in as_float_array("taus", taus, ndims=(1,)))
    load = dict(mapping("load_options", load_options)) if load_options is not None else {}
    for key in ("path", "fs"):
        if key in load:
            raise ValueError(
                f"load_options must not contain {key!r} (it is an argument of analyse)"
            )
    if columns is not None:
        load["columns"] = columns
    if time_column is not None:
        load["time_column"] = time_column
    if units is not None:
        load["units"] = units
    names = (
        None
        if axis_names is None
        else tuple(
            str(a)
            for a in (
                axis_names if isinstance(axis_names, str) else sequence("axis_names", axis_names)
            )
        )
    )
    expanded = _expand(sources)
    array_units: tuple[str | None, ...] = ()
    if isinstance(expanded, np.ndarray):
        if fs is None:
            raise ValueError("fs is required when sources is an array")
        n_axes = 1 if expanded.ndim == 2 else int(expanded.shape[2])
        check_axis_names(names, n_axes)  # before any unit runs (an error, not a row per unit)
        names = names or tuple(f"col{i}" for i in range(n_axes))
        array_units = io.columns._resolve_units(
            units, names, None, "sources"
        )  # the reader's rules for units=
        if first is not None or last is not None:  # the same span for every unit: check it once
            io.resolve_selection(int(expanded.shape[1]), fs, first, last)
    opts = _Options(
        fs=fs,
        fit=fit,
        taus=tau_spec,
        confidence=confidence,
        axis_names=names,
        gaps=gaps,
        load=load,
        array_units=array_units,
        terms=term_tuple,
        start=first,
        stop=last,
        bound_confidence=_core.validate.probability(
            "bound_confidence", real("bound_confidence", bound_confidence)
        ),
        outliers=None if outliers is None else real("outliers", outliers),
        detrend=detrend,
        tau_range=None if tau_range is None else pair("tau_range", tau_range),
        lines=(
            tuple(sequence("lines", lines))
            if lines is not None and not isinstance(lines, str)
            else lines
        ),
    )
    _check_options(opts)

    client, owned = _connect(client)
    tasks: list[tuple[Any, tuple[Any, ...], str]]
    try:
        if isinstance(expanded, np.ndarray):
            workers = num_workers or os.cpu_count() or 1
            if client is not None:
                workers = max(1, sum(client.nthreads().values()))
            ranges = _blocks(int(expanded.shape[0]), workers)
            blocks: list[Any] = [expanded[a:b] for a, b in ranges]
            if client is not None:
                blocks = client.scatter(blocks)
            tasks = [
                (_analyse_block, (blk, a, opts), f"array[{a}:{b}]")
                for blk, (a, b) in zip(blocks, ranges)
            ]
        else:
            tasks = [(_analyse_file, (p, opts), p) for p in expanded]
        parts = _run(tasks, client, num_workers, progress)
    finally:
        if owned:
            client.close()
    rows = [row for part in parts for row in part]
    return _finish(pd, rows, threshold, opts.n_gauss_markov)


#: The fixed series on which :func:`_check_options` runs the options (white noise, 2¹¹ samples:
#: every τ grid and term list gives a result on it, see tests/test_fleet.py).
_PROBE_SAMPLES = 2048


def _check_options(opts: _Options) -> None:
    """Run the options through the single-unit API once, on a short fixed series.

    ``allan.adev`` (and the core behind it) owns the checks of ``fs``, ``confidence``,
    ``gaps`` and the τ-grid name, ``noise.fit`` those of ``fit`` (its ``method``) and
    ``terms``: a bad option raises their error, naming the argument, before any work is
    scheduled instead of one error row per unit. Explicit τ values are judged per unit (they
    depend on the record's length).
    """
    probe = _core.random.normal(_PROBE_SAMPLES, 0)  # the core's generator
    grid = opts.taus if isinstance(opts.taus, str) else "octave"
    fs = 1.0 if opts.fs is None else opts.fs
    result = allan.adev(probe, fs, taus=grid, confidence=opts.confidence, gaps=opts.gaps)
    if grid != "octave":
        # The fit is checked on the octave grid: its checks do not depend on the grid, and a
        # joint fit of every τ of even this short series takes seconds.
        result = allan.adev(probe, fs, confidence=opts.confidence, gaps=opts.gaps)
    assert isinstance(result, allan.AllanResult)
    if opts.cleans:  # the cleaning options, judged by cleaning.clean itself
        cleaning.clean(np.asarray(probe), fs, outliers=opts.outliers, detrend=opts.detrend)
    try:
        if opts.terms is None:
            noise.fit(result, method=opts.fit)
        else:
            noise.fit(result, method=opts.fit, terms=opts.terms)
    except ValueError as exc:  # noise.fit calls them method and terms: say which were given
        given = f"fit={opts.fit!r}" + ("" if opts.terms is None else f", terms={opts.terms!r}")
        raise ValueError(f"{given}: {exc}") from None
