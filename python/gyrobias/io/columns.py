"""Channel selection and units: which columns of a file are loaded, the time column, the
per-channel units, and the finite-value check."""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

from gyrobias._validation import sequence
from gyrobias.io import _store
from gyrobias.io._store import Store
from gyrobias.units import _parse_unit

#: A time column's header: ``t``, ``time``, ``times`` or ``timestamp``, optionally with its unit
#: as a ``_s``/``_ms``/``_us``/``_ns`` suffix or in parentheses or brackets, as x-io (x-IMU3,
#: NGIMU) and many loggers write it: ``Timestamp (us)``, ``Time (s)``, ``time [ms]``, ``t (µs)``.
_TIME_HEADER = re.compile(
    r"^(?:t|times?|timestamp)(?:_(s|ms|us|ns)|\s*[(\[]\s*(s|ms|us|µs|μs|ns)\s*[)\]])?$",
    re.IGNORECASE,
)


def _time_header(name: str) -> tuple[bool, str | None]:
    """Whether ``name`` is a time column's header, and the unit it states (``None``: none)."""
    m = _TIME_HEADER.match(name.strip())
    if m is None:
        return False, None
    unit = m.group(1) or m.group(2)
    if unit is None:
        return True, None
    unit = unit.lower()
    return True, "us" if unit in ("µs", "μs") else unit


ColumnSpec = str | int
UnitSpec = str | Sequence[str | None] | Mapping[str, str]


def _expand_groups(columns: Sequence[ColumnSpec] | None) -> list[ColumnSpec] | None:
    """``"gyro"``/``"accel"`` → their three bag channels."""
    if columns is None:
        return None
    out: list[ColumnSpec] = []
    for c in columns:
        if isinstance(c, str) and c.strip() in ("gyro", "accel"):
            out += [f"{c.strip()}_{a}" for a in "xyz"]
        else:
            out.append(c)
    return out


def _take_columns(
    src: NDArray[np.float64], idx: Sequence[int], store: Store
) -> NDArray[np.float64]:
    """``src[:, idx]`` copied block by block into a store array."""
    out = store.empty(src.shape[0], len(idx))
    for sl in _store.blocks(src.shape[0]):
        out[sl] = src[sl][:, list(idx)]
    return out


_HEADER_UNIT = re.compile(r"[(\[]\s*([^()\[\]]+?)\s*[)\]]\s*$")


def _header_unit(name: str) -> str | None:
    """The unit a column header states at its end, as ``Gyroscope X (deg/s)`` or ``gx [rad/s]``
    (x-io, Xsens and many loggers): ``None`` when there is none or it is not a known unit."""
    m = _HEADER_UNIT.search(name)
    if m is None:
        return None
    try:
        _parse_unit(m.group(1))
    except ValueError:
        return None
    return m.group(1)


def _resolve_units(
    units: UnitSpec | None,
    names: Sequence[str],
    file_units: tuple[str | None, ...] | None,
    source: str,
) -> tuple[str | None, ...]:
    """Per-channel units from ``units=`` (validated) and the file's own units."""
    k = len(names)
    given: list[str | None] | None = None
    if units is not None:
        if isinstance(units, str):
            items = [u.strip() for u in units.split(",")]
            if all("=" in u for u in items):
                units = dict(u.split("=", 1) for u in items)
            elif len(items) == 1:
                given = [items[0]] * k
            else:
                given = list(items)
        if isinstance(units, Mapping):
            mapping = {str(key).strip(): str(v).strip() for key, v in units.items()}
            unknown = [key for key in mapping if key not in names]
            if unknown:
                raise ValueError(
                    f"units names channel(s) {', '.join(unknown)} not loaded; channels: {', '.join(names)}"
                )
            given = [mapping.get(n) for n in names]
        elif given is None:
            given = [None if u is None else str(u) for u in sequence("units", units)]
        if len(given) != k:
            raise ValueError(
                f"units has {len(given)} entries for {k} channels ({', '.join(names)})"
            )
        for u in given:
            if u is not None:
                try:
                    _parse_unit(u)
                except ValueError as exc:
                    raise ValueError(f"units: {exc}") from None
    if file_units is not None:
        if given is not None:
            for n, u, f in zip(names, given, file_units):
                if u is not None and f is not None and _parse_unit(u) != _parse_unit(f):
                    raise ValueError(
                        f"units: {source} stores {n} in {f} (sensor_msgs/Imu), not {u}; leave units unset for bags"
                    )
        return file_units
    return tuple(given) if given is not None else (None,) * k


def _check_finite(p: Path, table: NDArray[np.float64], names: Sequence[str], line_of: Any) -> None:
    """NaN/inf anywhere is an error naming the first place (block by block: memmaps stay bounded)."""
    first: tuple[int, int] | None = None
    total = 0
    for sl in _store.blocks(table.shape[0]):
        bad = ~np.isfinite(table[sl])
        count = int(bad.sum())
        if count:
            total += count
            if first is None:
                r, c = (int(i) for i in np.argwhere(bad)[0])
                first = (sl.start + r, c)
    if first is not None:
        row, col = first
        where = f"line {line_of(row)}" if line_of else f"row {row}"
        raise ValueError(
            f"{p.name}: {table[row, col]} in column '{names[col]}' at {where} "
            f"({total} non-finite value(s) in all); clean or interpolate the log first"
        )


def _resolve(
    spec: ColumnSpec, header: Sequence[str] | None, n_cols: int, what: str, source: str
) -> int:
    """0-based index of the column ``spec`` (a name, an index, ``"col<i>"`` or ``"<i>"``)."""
    available = list(header) if header is not None else [f"col{i}" for i in range(n_cols)]
    arg = "time_column" if what == "time column" else "columns"  # the argument, for messages
    if isinstance(spec, (int, np.integer)) and not isinstance(spec, bool):
        if 0 <= spec < n_cols:
            return int(spec)
        raise ValueError(
            f"{arg}: {what} index {spec} out of range: {source} has {n_cols} columns (0..{n_cols - 1})"
        )
    if not isinstance(spec, str):
        raise TypeError(f"{what} must be a column name or integer index, got {type(spec).__name__}")
    name = spec.strip()
    if header is not None:
        hits = [i for i, h in enumerate(header) if h == name]
        if len(hits) > 1:
            raise ValueError(
                f"{arg}: {what} '{name}' is ambiguous: the header has it at columns {hits}"
            )
        if hits:
            return hits[0]
    m = re.fullmatch(r"(?:col)?(\d+)", name)
    if m and int(m.group(1)) < n_cols:
        return int(m.group(1))
    raise ValueError(
        f"{arg}: unknown {what} '{name}' in {source}; available: {', '.join(available)}"
    )


def _select(
    columns: Sequence[ColumnSpec] | None,
    time_column: ColumnSpec | Literal[False] | None,
    header: Sequence[str] | None,
    n_cols: int,
    source: str,
) -> tuple[list[int], int | None]:
    """Indices of the channels and of the time column."""
    t_idx: int | None = None
    if time_column is None:
        if header is not None:
            for i, h in enumerate(header):
                if _time_header(h)[0]:
                    t_idx = i
                    break
    elif time_column is not False:
        t_idx = _resolve(time_column, header, n_cols, "time column", source)
    if columns is None:
        idx = [i for i in range(n_cols) if i != t_idx]
        if not idx:
            raise ValueError(f"{source} has no data columns besides the time column")
    else:
        idx = [_resolve(c, header, n_cols, "column", source) for c in columns]
        if t_idx is not None and t_idx in idx:
            if time_column is None:  # auto-detected: the user asked for it as data, so it is data
                t_idx = None
            else:
                raise ValueError("the time column is also listed in columns")
        dup = {i for i in idx if idx.count(i) > 1}
        if dup:
            raise ValueError(f"columns lists column(s) {sorted(dup)} more than once")
    return idx, t_idx
