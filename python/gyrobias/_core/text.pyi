"""Stubs of ``gyrobias._core.text`` (binding of ``gyrocore::text``)."""

from typing import final

import numpy as np
from numpy.typing import NDArray

__all__ = ["Format", "Parsed", "lines_in", "parse_float", "parse_int", "parse_into"]

@final
class Format:
    def __new__(
        cls, delimiter: str | None, comment: str, usecols: list[int], stamps: bool
    ) -> Format: ...
    @property
    def width(self) -> int: ...

@final
class Parsed:
    @property
    def rows(self) -> int: ...
    @property
    def consumed(self) -> int: ...
    @property
    def stop(self) -> str: ...
    @property
    def row(self) -> int: ...
    @property
    def column(self) -> int: ...
    @property
    def text(self) -> str: ...

def parse_into(
    text: NDArray[np.uint8],
    format: Format,
    values: NDArray[np.float64],
    stamps: NDArray[np.int64] | NDArray[np.float64] | None = None,
) -> Parsed: ...
def lines_in(text: NDArray[np.uint8]) -> int: ...
def parse_float(cell: bytes) -> float | None: ...
def parse_int(cell: bytes) -> int | None: ...
