"""Where loaded samples live: in memory, or spilled to a memory-mapped temporary file.

A spilled array is an :class:`numpy.memmap` of an unlinked temporary ``.npy`` file: the pages
are backed by the file, not by swap, so a log larger than memory can be analysed by code that
reads it block by block, and the file disappears when the last reference to the array goes
(the name is removed at once; only the open mapping keeps the data).
"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Iterator
from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["BLOCK_ROWS", "Store", "blocks", "physical_memory"]

#: Rows per block when a (possibly memory-mapped) array is processed piecewise.
BLOCK_ROWS = 1 << 20
#: ``spill=None`` spills results larger than this fraction of the physical memory.
SPILL_FRACTION = 0.25


def physical_memory() -> int:
    """Physical memory of the machine in bytes (16 GiB if it cannot be found)."""
    try:
        return int(os.sysconf("SC_PHYS_PAGES")) * int(os.sysconf("SC_PAGE_SIZE"))
    except (ValueError, OSError, AttributeError):  # pragma: no cover - not POSIX
        return 16 << 30


def blocks(n: int, rows: int = BLOCK_ROWS) -> Iterator[slice]:
    """Consecutive row slices covering ``0..n``."""
    for start in range(0, n, rows):
        yield slice(start, min(start + rows, n))


class Store:
    """Allocates the loader's output arrays, in memory or spilled to disk.

    Parameters
    ----------
    spill : bool or None
        ``True``: always spill; ``False``: never; ``None``: spill arrays larger than
        ``SPILL_FRACTION`` (a quarter) of the physical memory.
    directory : str or None
        Where the temporary files go (default: :func:`tempfile.gettempdir`).
    """

    def __init__(self, spill: bool | None, directory: str | None = None) -> None:
        self.spill = spill
        self.directory = directory
        self.spilled = False

    def wants_spill(self, nbytes: int) -> bool:
        """Whether an array of ``nbytes`` goes to disk."""
        if self.spill is None:
            return nbytes > SPILL_FRACTION * physical_memory()
        return self.spill

    def empty(self, rows: int, cols: int) -> NDArray[np.float64]:
        """An uninitialised ``(rows, cols)`` float64 array (a memmap when spilled)."""
        if not self.wants_spill(rows * cols * 8):
            return np.empty((rows, cols))
        fd, name = tempfile.mkstemp(prefix="gyrobias-", suffix=".npy", dir=self.directory)
        os.close(fd)
        try:
            out = np.lib.format.open_memmap(name, mode="w+", dtype=np.float64, shape=(rows, cols))
        finally:
            os.unlink(name)  # the mapping keeps the data; the name goes now
        self.spilled = True
        return out

    def vector(self, n: int, dtype: type[np.generic] = np.float64) -> NDArray[Any]:
        """An uninitialised 1-D array for a per-sample column (timestamps, intervals).

        It goes to disk with the samples: when they were spilled (or it alone is large
        enough to be), so that a log larger than memory has no full-length column in memory.
        """
        itemsize = np.dtype(dtype).itemsize
        if not (self.spilled or self.wants_spill(n * itemsize)):
            return np.empty(n, dtype=dtype)
        fd, name = tempfile.mkstemp(prefix="gyrobias-", suffix=".npy", dir=self.directory)
        os.close(fd)
        try:
            out = np.lib.format.open_memmap(name, mode="w+", dtype=dtype, shape=(n,))
        finally:
            os.unlink(name)  # the mapping keeps the data; the name goes now
        self.spilled = True
        return out

    def sink(self, cols: int, estimated_rows: int) -> Sink:
        """A writer of row blocks whose total count is not known in advance."""
        return Sink(self, cols, self.wants_spill(estimated_rows * cols * 8), estimated_rows)


class Sink:
    """Collects ``(m, cols)`` float64 blocks; :meth:`finish` returns them as one array.

    In memory, the rows go into one array allocated for the estimated row count, grown by half
    when the estimate was short and trimmed in place at the end (no second copy of the data).
    Spilled, they are appended to an anonymous temporary file that is then memory-mapped.
    """

    def __init__(
        self,
        store: Store,
        cols: int,
        spill: bool,
        estimated_rows: int = 0,
        dtype: type[np.generic] = np.float64,
    ) -> None:
        self.cols = cols
        self.rows = 0
        self.dtype = np.dtype(dtype)
        self._buf: NDArray[Any] = np.empty((0, cols), dtype=self.dtype)
        self._estimate = max(int(estimated_rows * 1.05) + 16, 16)
        self._file = None
        self._block: NDArray[Any] | None = None
        if spill:
            self._file = tempfile.TemporaryFile(
                prefix="gyrobias-", suffix=".f64", dir=store.directory
            )
            store.spilled = True

    @property
    def spilled(self) -> bool:
        """True when the rows go to a temporary file."""
        return self._file is not None

    def reserve(self, m: int) -> NDArray[Any]:
        """A writable ``(m, cols)`` view for the next ``m`` rows; :meth:`commit` adds them.

        In memory it is the result array itself (no intermediate copy); spilled, a block
        buffer reused from call to call (no fresh pages to fault in).
        """
        if self._file is not None:
            if self._block is None or self._block.shape[0] < m:
                self._block = np.empty((m, self.cols), dtype=self.dtype)
            return self._block[:m]
        self._grow(m)
        return self._buf[self.rows : self.rows + m]

    def commit(self, m: int) -> None:
        """Add the ``m`` rows written into the view from :meth:`reserve`."""
        if self._file is not None:
            assert self._block is not None
            self._file.write(self._block[:m].data)  # the buffer itself, no bytes copy
        self.rows += m

    def _grow(self, m: int) -> None:
        if self.rows + m > self._buf.shape[0]:
            size = max(self._estimate, int(1.5 * self._buf.shape[0]), self.rows + m)
            if self._buf.shape[0] and self._buf.flags.owndata:
                # in place (realloc, which moves large blocks by remapping their pages): no
                # second copy of the rows at the peak; the views from reserve() are gone by now
                self._buf.resize((size, self.cols), refcheck=False)
                return
            bigger = np.empty((size, self.cols), dtype=self.dtype)
            bigger[: self.rows] = self._buf[: self.rows]
            self._buf = bigger

    def append(self, block: NDArray[Any]) -> None:
        """Add rows (copied)."""
        block = np.ascontiguousarray(block, dtype=self.dtype).reshape(-1, self.cols)
        m = block.shape[0]
        if self._file is not None:
            self._file.write(block.tobytes())
        else:
            self._grow(m)
            self._buf[self.rows : self.rows + m] = block
        self.rows += m

    def finish(self) -> NDArray[Any]:
        """All rows as an ``(n, cols)`` array (a memmap of the anonymous temporary file if spilled)."""
        if self._file is None:
            out, self._buf = self._buf, np.empty((0, self.cols), dtype=self.dtype)
            if out.shape[0] != self.rows:
                out.resize((self.rows, self.cols), refcheck=False)  # in place: frees the tail
            return out
        self._file.flush()
        if self.rows == 0:
            self._file.close()
            return np.empty((0, self.cols), dtype=self.dtype)
        mapped = np.memmap(self._file, dtype=self.dtype, mode="r+", shape=(self.rows, self.cols))
        self._file.close()  # the mapping keeps its own reference to the file
        return mapped
