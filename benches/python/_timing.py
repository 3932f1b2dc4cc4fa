"""Timing helper shared by the benchmark scripts (imported from this folder)."""

from __future__ import annotations

import time
from collections.abc import Callable


def best_of(fn: Callable[[], object], repeats: int = 3) -> float:
    """Best (minimum) wall-clock time of ``repeats`` calls of ``fn``, in seconds.

    The minimum is the least disturbed measurement on a shared machine.
    """
    times = []
    for _ in range(repeats):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return min(times)
