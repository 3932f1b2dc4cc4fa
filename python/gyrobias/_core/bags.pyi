"""Stubs of ``gyrobias._core.bags`` (binding of ``gyrocore::bags``).

``data`` is a writable C-contiguous ``(n, 6)`` float64 array and ``stamps`` a writable
C-contiguous ``(n,)`` int64 array; rows are written from ``start``. Corrupt bytes or a
message that is not a standard ``sensor_msgs/Imu`` raise ``ValueError``.
"""

from collections.abc import Callable, Sequence
from os import PathLike

import numpy as np
from numpy.typing import NDArray

__all__ = ["CHANNELS", "cdr_messages", "mcap_chunk", "read_sqlite", "ros1_chunk", "sqlite_count"]

CHANNELS: int

def ros1_chunk(
    chunk: bytes,
    index: bytes,
    conn: int,
    receive: bool,
    previous: int,
    data: NDArray[np.float64],
    stamps: NDArray[np.int64],
    start: int,
) -> tuple[int, int, bool]: ...
def mcap_chunk(
    records: bytes,
    channel: int,
    receive: bool,
    previous: int,
    data: NDArray[np.float64],
    stamps: NDArray[np.int64],
    start: int,
) -> tuple[int, int, bool]: ...
def cdr_messages(
    buf: bytes,
    lengths: NDArray[np.int64],
    header_stamps: bool,
    data: NDArray[np.float64],
    stamps: NDArray[np.int64],
    start: int,
) -> int: ...
def read_sqlite(
    paths: Sequence[str | PathLike[str]],
    topic: str,
    receive: bool,
    data: NDArray[np.float64],
    stamps: NDArray[np.int64],
    progress: Callable[[float], object] | None = None,
) -> int: ...
def sqlite_count(paths: Sequence[str | PathLike[str]], topic: str) -> int: ...
