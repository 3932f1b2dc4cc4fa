"""NumPy references for the AR(1) fit (SPEC §9) by explicit least squares."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray


def ar1(x: NDArray[np.float64], demean: bool = True) -> tuple[float, float, float]:
    """(c, se(c), sigma_e) of b[k+1] = c b[k] + e via numpy.linalg.lstsq without intercept."""
    b = x - x.mean() if demean else x
    a = b[:-1, None]
    c, rss, *_ = np.linalg.lstsq(a, b[1:], rcond=None)
    s2 = float(rss[0]) / (b.size - 2)
    se = np.sqrt(s2 / float(a[:, 0] @ a[:, 0]))
    return float(c[0]), float(se), float(np.sqrt(s2))
