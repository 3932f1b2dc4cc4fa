"""Memory-mapped input: stream a ``np.memmap`` column by column from its file through the core.

The mapping's pages are never touched (reads go through ``readinto`` into a reused buffer), so
an analysis of a file larger than RAM does not fill the resident memory.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import NDArray

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
