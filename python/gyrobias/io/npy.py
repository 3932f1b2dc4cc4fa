"""``.npy`` logs: a 1-D or 2-D numeric array, read block by block (or mapped when spilled)."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

from gyrobias.io import _store
from gyrobias.io._store import Store
from gyrobias.io.columns import ColumnSpec, _select

#: Bytes read per block (the conversion buffer's size when the file's rows are not the result's).
_BLOCK_BYTES = 8 << 20


def _read_npy(
    p: Path,
    columns: Sequence[ColumnSpec] | None,
    time_column: ColumnSpec | Literal[False] | None,
    store: Store,
) -> tuple[NDArray[np.float64], list[str], NDArray[Any] | None, str | None]:
    try:
        arr = np.load(p, mmap_mode="r", allow_pickle=False)
    except (ValueError, OSError, EOFError) as exc:
        raise ValueError(f"{p.name}: not a readable .npy file ({exc})") from None
    if arr.dtype.kind not in "iuf":
        raise ValueError(f"{p.name}: array dtype {arr.dtype} is not real numeric")
    if arr.ndim == 1:
        arr = arr.reshape(-1, 1)
    if arr.ndim != 2:
        raise ValueError(
            f"{p.name}: expected a 1-D or 2-D array (samples × channels), got shape {arr.shape}"
        )
    if arr.shape[0] == 0 or arr.shape[1] == 0:
        raise ValueError(f"{p.name}: the array is empty (shape {arr.shape})")
    idx, t_idx = _select(columns, time_column, None, arr.shape[1], p.name)
    names = [f"col{i}" for i in idx]
    t_name = None if t_idx is None else f"col{t_idx}"
    whole = idx == list(range(arr.shape[1]))
    nbytes = arr.shape[0] * len(idx) * 8
    if t_idx is not None:  # the time column leaves the file: spilled with the samples
        store.spilled = store.spilled or store.wants_spill(nbytes)
    if (
        store.wants_spill(nbytes)
        and whole
        and arr.dtype == np.dtype(np.float64)
        and isinstance(arr, np.memmap)
        and arr.flags.c_contiguous
    ):
        store.spilled = True
        t_raw = None
        if t_idx is not None:
            t_raw = store.vector(arr.shape[0], arr.dtype.type)
            for sl in _store.blocks(arr.shape[0]):
                t_raw[sl] = arr[sl, t_idx]
        return arr, names, t_raw, t_name  # the file itself, mapped read-only
    if isinstance(arr, np.memmap) and arr.flags.c_contiguous and arr.ndim == 2:
        # rows in file order: read them block by block with readinto (no mapping of the
        # file, whose pages would count in the resident set beside the copy)
        rows, cols, dtype, offset = arr.shape[0], arr.shape[1], arr.dtype, int(arr.offset)
        del arr
        table = store.empty(rows, len(idx))
        t_raw = None if t_idx is None else store.vector(rows, dtype.type)
        _read_rows(p, offset, rows, cols, dtype, idx, t_idx, whole, table, t_raw)
        return table, names, t_raw, t_name
    # a Fortran-order array: copy from the mapping
    t_raw = None
    if t_idx is not None:
        t_raw = store.vector(arr.shape[0], arr.dtype.type)
        for sl in _store.blocks(arr.shape[0]):
            t_raw[sl] = arr[sl, t_idx]
    table = store.empty(arr.shape[0], len(idx))
    for sl in _store.blocks(arr.shape[0]):
        table[sl] = arr[sl][:, idx] if not whole else arr[sl]
    del arr
    return table, names, t_raw, t_name


def _read_rows(
    p: Path,
    offset: int,
    rows: int,
    cols: int,
    dtype: np.dtype[Any],
    idx: list[int],
    t_idx: int | None,
    whole: bool,
    table: NDArray[np.float64],
    t_raw: NDArray[Any] | None,
) -> None:
    """Read a C-order ``(rows, cols)`` array of ``dtype`` stored at ``offset`` of ``p`` into
    ``table`` (the columns ``idx``, as float64) and ``t_raw`` (column ``t_idx``)."""
    direct = whole and t_idx is None and dtype == np.dtype(np.float64)
    block = max(1, min(rows, _BLOCK_BYTES // (cols * dtype.itemsize)))
    raw: NDArray[Any] = table if direct else np.empty((block, cols), dtype=dtype)
    with open(p, "rb") as f:
        f.seek(offset)
        for sl in _store.blocks(rows, block):
            n = sl.stop - sl.start
            dest = table[sl] if direct else raw[:n]
            view = dest.data.cast("B")
            got = f.readinto(view)
            while got and got < len(view):  # a short read (a pipe-like file system)
                more = f.readinto(view[got:])
                if not more:
                    break
                got += more
            if got != len(view):
                raise ValueError(
                    f"{p.name}: the file ends early (at row {sl.start + got // (cols * dtype.itemsize)}"
                    f" of the {rows} its header declares)"
                )
            if direct:
                continue
            if t_idx is not None and t_raw is not None:
                t_raw[sl] = dest[:, t_idx]
            table[sl] = dest if whole else dest[:, idx]
