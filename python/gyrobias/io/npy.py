"""``.npy`` logs: a 1-D or 2-D numeric array, mapped (float64) or copied block by block."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

from gyrobias.io import _store
from gyrobias.io._store import Store
from gyrobias.io.columns import ColumnSpec, _select


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
    t_raw = None
    if t_idx is not None:  # a copy (the time column leaves the file), spilled with the samples
        store.spilled = store.spilled or store.wants_spill(arr.shape[0] * len(idx) * 8)
        t_raw = store.vector(arr.shape[0], arr.dtype.type)
        for sl in _store.blocks(arr.shape[0]):
            t_raw[sl] = arr[sl, t_idx]
    if (
        store.wants_spill(arr.shape[0] * len(idx) * 8)
        and whole
        and arr.dtype == np.dtype(np.float64)
        and isinstance(arr, np.memmap)
        and arr.flags.c_contiguous
    ):
        store.spilled = True
        return arr, names, t_raw, t_name  # the file itself, mapped read-only
    table = store.empty(arr.shape[0], len(idx))
    for sl in _store.blocks(arr.shape[0]):
        table[sl] = arr[sl][:, idx] if not whole else arr[sl]
    del arr
    return table, names, t_raw, t_name
