"""Timestamps: conversion to seconds, the sampling report (rate, jitter, gaps, duplicates),
the ``sort``/``dedup`` repairs and gap filling.

The analysis is the core's (``gyrocore::timestamps``: the unit guess, backward and repeated
stamps, median, gaps, rate, jitter, missing samples, the filled times); this module reads the
stamps, converts them to seconds, moves rows and words the findings.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gyrobias import _core
from gyrobias.io import _store
from gyrobias.io._store import Store
from gyrobias.io._types import SamplingReport
from gyrobias.io.columns import _time_header

#: Intervals longer than this multiple of the median interval count as gaps (the core's).
GAP_FACTOR: float = _core.timestamps.GAP_FACTOR
#: A user-given ``fs`` differing from the timestamps' estimate by more than this (relative) is reported.
FS_TOLERANCE: float = _core.timestamps.FS_TOLERANCE
#: Relative jitter (s.d. of the regular intervals / median interval) above which a warning is given.
JITTER_WARN: float = _core.timestamps.JITTER_WARN
#: ``time_unit="auto"`` reads timestamps as nanoseconds when the median interval is at least this.
NS_THRESHOLD: float = _core.timestamps.NS_THRESHOLD
#: ``time_unit="auto"`` reads timestamps as microseconds from this median interval up to
#: :data:`NS_THRESHOLD`.
US_THRESHOLD: float = _core.timestamps.US_THRESHOLD

_PER_SECOND = {"s": 1.0, "ms": 1e3, "us": 1e6, "ns": 1e9}
_TIME_UNITS = ("auto", "s", "ms", "us", "ns")


def _time_seconds(
    p: Path, t_raw: NDArray[Any], t_name: str, time_unit: str, line_of: Any, store: Store
) -> tuple[NDArray[np.float64], Any, float, str, bool]:
    """Timestamps (finite, in order: see :func:`_repair`) → seconds since the first sample.

    Returns ``(time, sampling, start, unit, guessed)``: ``sampling`` is the core's analysis of
    the intervals (:func:`gyrobias._core.timestamps.analyse_stamps`, formed on the fly from the
    raw stamps: no full-length array of intervals). The raw stamps are the loader's own copy
    and not needed afterwards: the core overwrites them with the seconds in place (an int64
    buffer then holds float64 bits), so the time vector costs no second column.
    """
    n = len(t_raw)
    unit = time_unit
    guessed = False
    stamps = _stamps(t_raw)
    if unit == "auto":
        stated = _time_header(t_name)[1]
        if stated is not None:
            unit = stated
        else:
            median = _core.timestamps.median_positive_step(stamps)
            unit = _core.timestamps.guess_unit(median)
            guessed = True
    per_second = _PER_SECOND[unit]  # dividing by an exact power of ten rounds correctly
    sampling = _core.timestamps.analyse_stamps(stamps, per_second)
    first = stamps[0].item()
    if not (stamps.flags.writeable and stamps.flags.c_contiguous):
        copy = store.vector(n, stamps.dtype.type)  # spilled with the samples
        for sl in _store.blocks(n):
            copy[sl] = stamps[sl]
        stamps = copy
    _core.timestamps.seconds_in_place(stamps, first, per_second)
    return stamps.view(np.float64), sampling, float(first) / per_second, unit, guessed


def _stamps(t_raw: NDArray[Any]) -> NDArray[Any]:
    """Raw stamps as the core reads them: int64 (exact) or float64; other dtypes converted."""
    if t_raw.dtype in (np.dtype(np.int64), np.dtype(np.float64)):
        return t_raw
    return t_raw.astype(np.int64 if t_raw.dtype.kind in "iu" else np.float64)


def _sampling_report(
    n: int,
    time: NDArray[np.float64] | None,
    sampling: Any,
    unit: str | None,
    fs: float | None,
    *,
    unit_guessed: bool = False,
    fixes: _Fixes | None = None,
    source_format: str | None = None,
    filling: bool = False,
) -> SamplingReport:
    """The one constructor of :class:`SamplingReport`: from the timestamps when there are any
    (``time``, the core's ``sampling`` analysis of them and ``unit`` given), else only the
    sample count and the given rate."""
    if time is None or sampling is None or unit is None:
        return SamplingReport(
            n_samples=n,
            fs=fs,
            fs_source=None if fs is None else "user",
            source_format=source_format,
        )
    fixes = fixes if fixes is not None else _Fixes()
    warnings: list[str] = list(fixes.repairs)
    duration = float(time[-1])
    stats = sampling  # median, gaps, rate, jitter: the core's
    median = stats.median_interval
    gap_rows = stats.gap_rows
    gap_durations = stats.gap_durations
    dup_rows = stats.duplicate_rows
    fs_est = stats.fs_estimated
    jitter = stats.jitter
    missing = int(stats.missing_samples)

    if gap_rows.size:
        longest = int(gap_durations.argmax())
        warnings.append(
            f"{gap_rows.size} gap(s) in the timestamps (intervals > {GAP_FACTOR:g}× the median "
            f"{median:.6g} s): longest {gap_durations[longest]:.6g} s before row {gap_rows[longest]} "
            f"(t = {time[gap_rows[longest]]:.6g} s), ~{missing} sample(s) missing; "
            + (
                "filled with NaN rows (fill_gaps)"
                if filling
                else "the analysis treats the samples as uniformly spaced (fill_gaps=True / --fill-gaps marks them)"
            )
        )
    if dup_rows.size:
        warnings.append(
            f"{dup_rows.size} repeated timestamp(s) (zero intervals), first at row {dup_rows[0]}"
        )
    if fixes.exact_duplicate_rows.size:
        warnings.append(
            f"{fixes.exact_duplicate_rows.size} sample(s) repeat the previous one exactly (same "
            f"timestamp and values), first at row {fixes.exact_duplicate_rows[0]}; "
            "repair='dedup' (--repair dedup) drops them"
        )
    if jitter > JITTER_WARN:
        warnings.append(
            f"sampling jitter {100 * jitter:.3g} % (s.d. of the intervals / median interval) "
            f"exceeds {100 * JITTER_WARN:g} %"
        )
    if unit_guessed and unit == "s" and fs_est < 1.0:
        warnings.append(
            f"the timestamps, read as seconds, give fs = {fs_est:.6g} Hz; if they are milliseconds "
            "or microseconds, pass time_unit (--time-unit)"
        )
    source = "timestamps"
    if fs is not None:
        source = "user"
        if abs(fs - fs_est) > FS_TOLERANCE * fs_est:
            warnings.append(
                f"given fs = {fs:g} Hz disagrees with the timestamps ({fs_est:.6g} Hz) "
                f"by {100 * abs(fs - fs_est) / fs_est:.3g} %; using fs = {fs:g} Hz"
            )
    return SamplingReport(
        n_samples=n,
        fs=fs if fs is not None else fs_est,
        fs_source=source,
        fs_estimated=fs_est,
        median_interval=median,
        jitter=jitter,
        time_unit=unit,
        duration=duration,
        n_gaps=int(gap_rows.size),
        gap_rows=gap_rows,
        gap_durations=gap_durations,
        missing_samples=missing,
        n_duplicates=int(dup_rows.size),
        duplicate_rows=dup_rows,
        warnings=tuple(warnings),
        n_out_of_order=int(fixes.out_of_order_rows.size),
        out_of_order_rows=fixes.out_of_order_rows,
        n_exact_duplicates=int(fixes.exact_duplicate_rows.size + fixes.dropped),
        repairs=fixes.repairs,
        source_format=source_format,
    )


@dataclass(frozen=True)
class _Fixes:
    """What :func:`_repair` found and changed."""

    out_of_order_rows: NDArray[np.int64] = field(
        default_factory=lambda: np.zeros(0, dtype=np.int64)
    )
    exact_duplicate_rows: NDArray[np.int64] = field(
        default_factory=lambda: np.zeros(0, dtype=np.int64)
    )
    dropped: int = 0
    repairs: tuple[str, ...] = ()


def _take_rows(
    table: NDArray[np.float64], rows: NDArray[np.int64], store: Store
) -> NDArray[np.float64]:
    """``table[rows]`` copied block by block into a store array."""
    out = store.empty(len(rows), table.shape[1])
    for sl in _store.blocks(len(rows)):
        out[sl] = table[rows[sl]]
    return out


def _repair(
    p: Path,
    t_raw: NDArray[Any],
    table: NDArray[np.float64],
    t_name: str,
    repairs: tuple[str, ...],
    line_of: Any,
    store: Store,
) -> tuple[NDArray[Any], NDArray[np.float64], _Fixes]:
    """Check the timestamps (finite, in order) and apply ``repair=``; never silently."""
    if t_raw.dtype.kind == "f":
        for sl in _store.blocks(len(t_raw)):  # block by block: a spilled column stays on disk
            bad = np.flatnonzero(~np.isfinite(t_raw[sl]))
            if bad.size:
                row = sl.start + int(bad[0])
                where = f"line {line_of(row)}" if line_of else f"row {row}"
                raise ValueError(f"{p.name}: {t_raw[row]} in the time column '{t_name}' at {where}")
    done: list[str] = []
    back = _core.timestamps.backward_rows(_stamps(t_raw))
    if back.size:
        row = int(back[0])
        if "sort" not in repairs:
            where = f"line {line_of(row)}" if line_of else f"row {row}"
            raise ValueError(
                f"{p.name}: timestamps out of order in '{t_name}' at {where} "
                f"({t_raw[row]} after {t_raw[row - 1]}; {back.size} backward step(s) in all); "
                "sort the log or fix its clock, or pass repair='sort' (--repair sort)"
            )
        order = np.argsort(t_raw, kind="stable")
        t_raw = _take_stamps(t_raw, order, store)
        table = _take_rows(table, order, store)
        done.append(
            f"sorted by timestamp: {back.size} sample(s) were earlier than the one before them, "
            f"the first at row {row} (repair='sort')"
        )
    exact = np.zeros(0, dtype=np.int64)
    cand = _core.timestamps.repeated_rows(_stamps(t_raw))
    if cand.size:
        same = np.ones(cand.size, dtype=bool)
        for sl in _store.blocks(cand.size):
            c = cand[sl]
            same[sl] = np.all(table[c] == table[c - 1], axis=1)
        exact = cand[same].astype(np.int64)
    dropped = 0
    if exact.size and "dedup" in repairs:
        keep = np.ones(len(t_raw), dtype=bool)
        keep[exact] = False
        rows = np.flatnonzero(keep)
        t_raw = _take_stamps(t_raw, rows, store)
        table = _take_rows(table, rows, store)
        done.append(
            f"dropped {exact.size} sample(s) repeating the previous one exactly (same timestamp "
            f"and values), the first at row {exact[0]} (repair='dedup')"
        )
        dropped, exact = int(exact.size), np.zeros(0, dtype=np.int64)
    return t_raw, table, _Fixes(back.astype(np.int64), exact, dropped, tuple(done))


def _take_stamps(t_raw: NDArray[Any], rows: NDArray[np.intp], store: Store) -> NDArray[Any]:
    """``t_raw[rows]`` in a new array of the store (spilled with the samples), block by block."""
    out = store.vector(len(rows), t_raw.dtype.type)
    for sl in _store.blocks(len(rows)):
        out[sl] = t_raw[rows[sl]]
    return out


def _fill_gaps(
    table: NDArray[np.float64], time: NDArray[np.float64], report: SamplingReport, store: Store
) -> tuple[NDArray[np.float64], NDArray[np.float64], SamplingReport]:
    """Insert ``round(gap / median) − 1`` NaN rows into each gap, with evenly spaced times."""
    assert report.median_interval is not None
    n, k = table.shape
    median = report.median_interval
    missing = np.array(
        [_core.timestamps.missing_in_gap(g, median) for g in report.gap_durations.tolist()],
        dtype=np.int64,
    )
    shift = np.zeros(n, dtype=np.int64)
    shift[report.gap_rows] = missing
    dest = np.arange(n, dtype=np.int64) + np.cumsum(shift)  # row bookkeeping: where each row goes
    total = n + int(missing.sum())
    out = store.empty(total, k)
    for sl in _store.blocks(total):
        out[sl] = np.nan
    for sl in _store.blocks(n):
        out[dest[sl]] = table[sl]
    new_time = store.vector(total)
    _core.timestamps.fill_time_into(time, report.gap_rows, missing, new_time)
    note = f"inserted {int(missing.sum())} NaN row(s) for the samples missing in {report.n_gaps} gap(s) (fill_gaps)"
    report = replace(
        report,
        filled_samples=int(missing.sum()),
        repairs=(*report.repairs, note),
    )
    return out, new_time, report
