"""Fleets: the noise terms of many IMU logs in one table, on Dask, locally or on a cluster.

:func:`analyse` runs the single-unit pipeline — :func:`gyrobias.io.load`,
:func:`gyrobias.allan.adev` with confidence intervals, :func:`gyrobias.noise.fit` — on every unit
of a fleet and returns one pandas ``DataFrame`` row per unit and axis. The work is a Dask task
per log file (or per block of units of an in-memory array): by default on Dask's local threaded
scheduler (the Rust kernels release the GIL, so threads run them in parallel), or on a
``distributed.Client`` (a ``LocalCluster`` or a remote scheduler's address). A log that cannot be
read or analysed is a row with its ``error``, never a crashed run. :func:`summary` condenses the
table per axis and term: median, robust spread, the mean reported uncertainty and whether the
unit-to-unit spread is real.

Needs the ``fleet`` extra: ``pip install "gyrobias[fleet]"`` (dask[distributed], pandas, pyarrow).

Out-of-family flag
------------------
For each term ``X`` (Q, N, B, K, R and the Gauss–Markov columns ``GMk_sigma``,
``GMk_correlation_time`` when they were fitted) and axis, over the ``n`` units whose fit has
the term (at least
:data:`MIN_UNITS`), with ``u_i`` the unit's standard uncertainty::

    m       = median_i X_i
    s       = 1.4826 · median_i |X_i − m|                 (MAD: the s.d. for normal data)
    σ_fleet = √max(s² − median_i u_i², 0)                 (unit-to-unit spread, noise removed)
    z_i     = (X_i − m) / √(σ_fleet² + u_i² + (π/2)·s²/n)

``(π/2)·s²/n`` is the variance of the median itself. A unit whose own estimate is uncertain
(short log, a term barely visible) therefore needs a larger deviation to be flagged. A row is
``out_of_family`` when ``|z_i| > 3.5`` for any term (:data:`OUT_OF_FAMILY_THRESHOLD`, the
modified-z-score cut-off of Iglewicz & Hoaglin 1993); ``out_of_family_terms`` names them and the
``X_z`` columns hold the scores. With fewer than :data:`MIN_UNITS` units the flag is ``<NA>``.
Scores are compared within an axis name (``x`` with ``x``); name the axes alike
(``axis_names=``) when logs of different formats are mixed.

False alarms (Monte Carlo, ``tests/test_fleet.py``; one family with a 5 % true spread and 1σ
uncertainties of 1–8 %): ``z`` has unit standard deviation, and ``|z| > 3.5`` happens for
0.9 % / 0.5 % / 0.06 % of the terms at 10 / 40 / 400 units (0.05 % for a known normal law; small
fleets pay for estimating the median and MAD). A unit 6 family standard deviations away is
flagged in more than 90 % of the cases at 40 units.

References
----------
.. [IH93] B. Iglewicz, D. C. Hoaglin, "How to Detect and Handle Outliers", ASQC (1993), §3.
.. [IEEE952] IEEE Std 952-1997, Annex C (the noise terms).

Examples
--------
>>> import numpy as np, gyrobias
>>> from gyrobias import fleet
>>> rate = np.stack([gyrobias.noise.simulate(20_000, 100.0, arw=0.2 / 60, seed=s) for s in range(6)])
>>> table = fleet.analyse(rate, fs=100.0, units="deg/s")          # (units, n): 6 units, 1 axis
>>> len(table), table.loc[0, "N_unit"], bool(abs(table.N.median() * 60 - 0.2) < 0.02)
(6, 'deg/√s', True)
>>> int(table.out_of_family.sum())
0
"""

from __future__ import annotations

import glob
import importlib
import math
import os
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gyrobias import _core, allan, io, noise
from gyrobias._files import atomic_binary
from gyrobias._fleet_table import GM_PARAMETERS, TERMS, _gm_columns, term_columns
from gyrobias._validation import as_float_array, positive_float, real
from gyrobias._validation import axis_names as check_axis_names
from gyrobias.units import base_unit, sensor_kind

__all__ = [
    "MIN_UNITS",
    "OUT_OF_FAMILY_THRESHOLD",
    "SPREAD_ALPHA",
    "SPREAD_MIN_RATIO",
    "GM_PARAMETERS",
    "TERMS",
    "analyse",
    "summary",
    "term_columns",
    "write_table",
]

#: ``|z|`` above which a term is out of family (Iglewicz & Hoaglin's modified-z cut-off).
OUT_OF_FAMILY_THRESHOLD: float = 3.5
#: Fewest units with a term (per axis) for a median/MAD comparison.
MIN_UNITS: int = 5
#: Significance level of the "is the spread real?" chi-square test in :func:`summary`.
SPREAD_ALPHA: float = 0.01
#: The spread must also exceed the uncertainties by this factor (Birge ratio) to count as real:
#: the joint fit's uncertainties are calibrated to about 15 % (README, noise coefficients).
SPREAD_MIN_RATIO: float = 1.2

_MAD_TO_SD = 1.482602218505602  # 1 / Φ⁻¹(3/4)
_GLOB_CHARS = frozenset("*?[")

#: A pandas DataFrame (pandas is imported lazily: it belongs to the ``fleet`` extra).
DataFrame = Any


def _require(name: str) -> Any:
    try:
        return importlib.import_module(name)
    except ImportError as exc:
        raise ImportError(
            f"gyrobias.fleet needs {name}, which is not installed; install the fleet extra with "
            'pip install "gyrobias[fleet]" (dask[distributed], pandas, pyarrow)'
        ) from exc


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
    """``name`` and ``name_uncertainty`` of a row from a fitted term (NaN when missing)."""
    value = None if term is None else term.value
    unc = None if term is None else term.uncertainty
    row[name] = math.nan if value is None else float(value)
    row[f"{name}_uncertainty"] = math.nan if unc is None else float(unc)


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
) -> list[dict[str, Any]]:
    """Allan analysis and fit of one unit (``data`` is ``(n,)`` or ``(n, axes)``)."""
    matrix = data.reshape(-1, 1) if data.ndim == 1 else data
    results = allan.adev(matrix, fs, **_allan_options(axis_names, axis_units, opts))
    assert isinstance(results, tuple)
    return _fit_rows(source, results, int(matrix.shape[0]), fs, axis_units, opts, sampling)


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
) -> list[dict[str, Any]]:
    """The noise fit of each axis' Allan result, one row per axis."""
    common: dict[str, Any] = {
        "fs": fs,
        "duration": n / fs,
        "n_samples": n,
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
        row["adev_tau"] = np.asarray(r.taus, dtype=np.float64)
        row["adev"] = np.asarray(r.adev, dtype=np.float64)
        fit_options: dict[str, Any] = {"method": opts.fit, "unit": unit}
        if opts.terms is not None:
            fit_options["terms"] = opts.terms
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
        # A wrong number of axis_names is allan.adev's error (one check, _validation.axis_names),
        # reported in this file's row.
        names: Sequence[str] = log.columns if opts.axis_names is None else opts.axis_names
        units = (
            tuple(log.units) if len(log.units) == len(log.columns) else (None,) * len(log.columns)
        )
        return _rows_for(path, log.data, float(log.fs), names, units, opts, log.sampling)
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
    n = int(block.shape[1])
    batch: tuple[tuple[allan.AllanResult, ...], ...] | None
    try:
        batch = allan.adev_batch(block, opts.fs, **_allan_options(names, units, opts))
    except Exception:  # noqa: BLE001 - find the failing unit below, one at a time
        batch = None
    rows: list[dict[str, Any]] = []
    for i in range(block.shape[0]):
        source = f"array[{start + i}]"
        try:
            if batch is None:
                rows.extend(_rows_for(source, block[i], opts.fs, names, units, opts, None))
            else:
                rows.extend(_fit_rows(source, batch[i], n, opts.fs, units, opts, None))
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
        text = os.fspath(item)
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
        distributed = _require("distributed")
        return distributed.Client(client), True
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

    Returns
    -------
    pandas.DataFrame
        One row per unit and axis (a failed file: one row with ``error`` set), in the order of
        ``sources``. Columns: ``source``, ``axis``, ``sensor``, ``data_unit``, ``fs`` [Hz],
        ``duration`` [s] (``n_samples / fs``), ``n_samples``; the gap summary of the
        timestamps (``<NA>`` without them): ``n_gaps``, ``missing_samples``, ``longest_gap``
        [s], ``n_duplicates``, ``sampling_warnings``; ``fit_method``; for every term X in Q, N,
        B, K, R (and, with Gauss–Markov ``terms``, ``GM1_sigma``, ``GM1_correlation_time``,
        ``GM2_sigma``, ``GM2_correlation_time``): ``X`` and ``X_uncertainty`` (1σ) in the base
        unit ``X_unit`` (NaN when the fit has no such term), ``X_z`` (robust z-score against
        the fleet); the goodness of fit
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
    if isinstance(units, str) and not set(units) & {",", "="}:
        sensor_kind(units)  # an unknown or non-rate unit fails here, once, not in every row
    if confidence is not None:
        confidence = real("confidence", confidence)
    term_tuple = None
    if terms is not None:
        term_tuple = (terms,) if isinstance(terms, str) else tuple(terms)
    threshold = positive_float("threshold", threshold)
    if num_workers is not None and (
        isinstance(num_workers, bool) or not isinstance(num_workers, int) or num_workers < 1
    ):
        raise ValueError(f"num_workers must be an integer >= 1, got {num_workers!r}")
    tau_spec: str | tuple[float, ...]
    if isinstance(taus, str):
        tau_spec = taus
    else:
        tau_spec = tuple(float(t) for t in as_float_array("taus", taus, ndims=(1,)))
    load = dict(load_options or {})
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
    names = None if axis_names is None else tuple(str(a) for a in axis_names)
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
    probe = np.random.default_rng(0).standard_normal(_PROBE_SAMPLES)
    grid = opts.taus if isinstance(opts.taus, str) else "octave"
    fs = 1.0 if opts.fs is None else opts.fs
    result = allan.adev(probe, fs, taus=grid, confidence=opts.confidence, gaps=opts.gaps)
    if grid != "octave":
        # The fit is checked on the octave grid: its checks do not depend on the grid, and a
        # joint fit of every τ of even this short series takes seconds.
        result = allan.adev(probe, fs, confidence=opts.confidence, gaps=opts.gaps)
    assert isinstance(result, allan.AllanResult)
    try:
        if opts.terms is None:
            noise.fit(result, method=opts.fit)
        else:
            noise.fit(result, method=opts.fit, terms=opts.terms)
    except ValueError as exc:  # noise.fit calls them method and terms: say which were given
        given = f"fit={opts.fit!r}" + ("" if opts.terms is None else f", terms={opts.terms!r}")
        raise ValueError(f"{given}: {exc}") from None


# --------------------------------------------------------------------------------- the table

_COUNTS = ("n_samples", "n_gaps", "missing_samples", "n_duplicates", "dof")


def _columns(n_gm: int = 0) -> list[str]:
    cols = [
        "source",
        "axis",
        "sensor",
        "data_unit",
        "fs",
        "duration",
        "n_samples",
        "n_gaps",
        "missing_samples",
        "longest_gap",
        "n_duplicates",
        "sampling_warnings",
        "fit_method",
    ]
    for t in (*TERMS, *_gm_columns(n_gm)):
        cols += [t, f"{t}_uncertainty", f"{t}_unit", f"{t}_z"]
    cols += [
        "chi2",
        "dof",
        "chi2_reduced",
        "p_value",
        "fit_warnings",
        "out_of_family",
        "out_of_family_terms",
        "error",
        "adev_tau",
        "adev",
    ]
    return cols


def _finish(pd: Any, rows: list[dict[str, Any]], threshold: float, n_gm: int = 0) -> DataFrame:
    table = pd.DataFrame.from_records(rows, columns=_columns(n_gm))
    terms = (*TERMS, *_gm_columns(n_gm))
    for name in _COUNTS:
        table[name] = table[name].astype("Int64")
    for name in (
        "fs",
        "duration",
        "longest_gap",
        "chi2",
        "chi2_reduced",
        "p_value",
        *terms,
        *(f"{t}_uncertainty" for t in terms),
    ):
        table[name] = table[name].astype("float64")
    z = {t: np.full(len(table), np.nan) for t in terms}
    flag = np.zeros(len(table), dtype=bool)
    known = np.zeros(len(table), dtype=bool)
    ok = table["error"].isna().to_numpy()
    for idx in table[ok].groupby("axis", dropna=False, sort=False).groups.values():
        pos = table.index.get_indexer(idx)
        for t in terms:
            values = table[t].to_numpy()[pos]
            unc = table[f"{t}_uncertainty"].to_numpy()[pos]
            have = np.isfinite(values)
            if have.sum() < MIN_UNITS:
                continue
            z[t][pos[have]] = _robust_z(
                values[have], np.where(np.isfinite(unc[have]), unc[have], 0.0)
            )
            known[pos[have]] = True
    terms_out = []
    for i in range(len(table)):
        out = [t for t in terms if np.isfinite(z[t][i]) and abs(z[t][i]) > threshold]
        flag[i] = bool(out)
        terms_out.append(",".join(out) or None)
    for t in terms:
        table[f"{t}_z"] = z[t]
    table["out_of_family"] = pd.array(
        [bool(f) if k else None for f, k in zip(flag, known)], dtype="boolean"
    )
    table["out_of_family_terms"] = terms_out
    return table


def _robust_z(values: NDArray[np.float64], unc: NDArray[np.float64]) -> NDArray[np.float64]:
    """z_i = (X_i − m) / √(σ_fleet² + u_i² + (π/2)s²/n) (module docs)."""
    m = float(np.median(values))
    s = _MAD_TO_SD * float(np.median(np.abs(values - m)))
    fleet_var = max(s * s - float(np.median(unc * unc)), 0.0)
    denom = np.sqrt(fleet_var + unc * unc + (math.pi / 2.0) * s * s / values.size)
    dev = values - m
    with np.errstate(divide="ignore", invalid="ignore"):
        z = np.where(
            denom > 0.0,
            dev / np.where(denom > 0.0, denom, 1.0),
            np.where(dev == 0.0, 0.0, np.sign(dev) * np.inf),
        )
    return np.asarray(z, dtype=np.float64)


def _chi2_sf(x: float, dof: int) -> float:
    """Upper tail ``P(χ²_ν > x)``: the core's regularised incomplete gamma ``Q(ν/2, x/2)``."""
    return _core.stats.chi2_sf(x, float(dof))


def _spread(
    x: NDArray[np.float64], u: NDArray[np.float64], alpha: float, min_ratio: float
) -> dict[str, Any]:
    """The statistics of one term over the units that have it (see :func:`summary`)."""
    med = float(np.median(x))
    spread = _MAD_TO_SD * float(np.median(np.abs(x - med)))
    good = np.isfinite(u) & (u > 0.0)
    mean_u = float(np.sqrt(np.mean(u[good] ** 2))) if good.any() else math.nan
    dof = int(good.sum()) - 1
    chi2 = p = ratio = math.nan
    if dof >= 1:
        w = 1.0 / u[good] ** 2
        xm = float(np.sum(w * x[good]) / np.sum(w))
        chi2 = float(np.sum(w * (x[good] - xm) ** 2))
        p = _chi2_sf(chi2, dof)
        ratio = math.sqrt(chi2 / dof)
    return {
        "median": med,
        "spread": spread,
        "mean_uncertainty": mean_u,
        "intrinsic_spread": math.sqrt(max(spread * spread - mean_u * mean_u, 0.0))
        if math.isfinite(mean_u)
        else math.nan,
        "chi2": chi2,
        "dof": dof if dof >= 1 else None,
        "birge_ratio": ratio,
        "p_value": p,
        "spread_real": None if dof < 1 else bool(p < alpha and ratio >= min_ratio),
    }


def summary(
    table: DataFrame, *, alpha: float = SPREAD_ALPHA, min_ratio: float = SPREAD_MIN_RATIO
) -> DataFrame:
    """Per axis and term: median, spread, mean uncertainty, and whether the spread is real.

    Parameters
    ----------
    table : pandas.DataFrame
        The result of :func:`analyse` (or its Parquet file read back).
    alpha : float
        Significance level of the homogeneity test.
    min_ratio : float
        Smallest Birge ratio that counts as a real spread (see Notes).

    Returns
    -------
    pandas.DataFrame
        One row per (axis, term) with any value: ``axis``, ``term`` (Q, N, B, K, R, or a
        Gauss–Markov column such as ``GM1_sigma``), ``unit``, ``n`` (units
        with the term), ``median``, ``spread`` (1.4826·MAD), ``mean_uncertainty`` (RMS of the
        reported 1σ uncertainties), ``intrinsic_spread`` (``√max(spread² − mean_uncertainty²,
        0)``), ``chi2``, ``dof``, ``birge_ratio`` (``√(χ²/dof)``), ``p_value``,
        ``spread_real`` and ``n_out_of_family``.

    Notes
    -----
    "Is the spread real?" is a homogeneity test: if every unit had the same true value, the
    statistic ``χ² = Σ_i (X_i − X̄_w)²/u_i²`` about the weighted mean ``X̄_w = Σ X_i/u_i² /
    Σ 1/u_i²`` would follow a chi-square law with ``n − 1`` degrees of freedom. The spread is
    called real when ``p < alpha`` (exact upper tail, :func:`_chi2_sf`) **and** the
    Birge ratio ``√(χ²/(n−1)) ≥ min_ratio``: the joint fit's uncertainties are themselves
    right to about 15 %, so a scatter only slightly larger than them is not evidence of real
    unit-to-unit differences however many units there are.
    """
    pd = _require("pandas")
    alpha = positive_float("alpha", alpha)
    out = []
    ok = table[table["error"].isna()]
    for axis, group in ok.groupby("axis", dropna=False, sort=False):
        for t in term_columns(table):
            values = group[t].to_numpy(dtype=np.float64)
            unc = group[f"{t}_uncertainty"].to_numpy(dtype=np.float64)
            have = np.isfinite(values)
            if not have.any():
                continue
            stats = _spread(values[have], unc[have], alpha, min_ratio)
            units = group[f"{t}_unit"].dropna()
            flagged = (
                group["out_of_family_terms"]
                .dropna()
                .map(lambda text, t=t: t in str(text).split(","))
            )
            out.append(
                {
                    "axis": axis,
                    "term": t,
                    "unit": None if units.empty else str(units.iloc[0]),
                    "n": int(have.sum()),
                    **stats,
                    # astype(bool): under pandas 3 an empty map result keeps the string
                    # dtype, whose sum is "" (int("") fails)
                    "n_out_of_family": int(flagged.astype(bool).sum()),
                }
            )
    result = pd.DataFrame.from_records(
        out,
        columns=[
            "axis",
            "term",
            "unit",
            "n",
            "median",
            "spread",
            "mean_uncertainty",
            "intrinsic_spread",
            "chi2",
            "dof",
            "birge_ratio",
            "p_value",
            "spread_real",
            "n_out_of_family",
        ],
    )
    result["dof"] = result["dof"].astype("Int64")
    result["spread_real"] = result["spread_real"].astype("boolean")
    return result


def write_table(table: DataFrame, path: str | os.PathLike[str]) -> None:
    """Write the fleet table as Parquet (pyarrow), atomically (temp file beside it, then rename).

    The Allan curves ``adev_tau``/``adev`` become list columns; ``pandas.read_parquet`` reads
    the file back.
    """
    _require("pyarrow")
    with atomic_binary(path) as fh:
        table.to_parquet(fh, engine="pyarrow", index=False)
