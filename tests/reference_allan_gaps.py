"""Direct NumPy definition of the gap-aware Allan-family estimators (no code shared with gyrobias).

A term of an estimator is kept when every sample it spans is present (not NaN); the variance is
the mean of the kept squared differences over its normalisation (NIST SP 1065 eqs. 7, 11, 14,
18 restricted to the kept terms). For rate input the differences are built from prefix sums of
the mean-removed rate (the mean cancels in every difference); a term at angle index k with
span s (2m, 3m − 1 or 3m angle steps) uses the rate samples k .. k + s − 1.
"""

from __future__ import annotations

import numpy as np


def _prefix(values: np.ndarray) -> np.ndarray:
    return np.concatenate(([0], np.cumsum(values)))


def gapped_variance(
    data: np.ndarray, t0: float, m: int, kind: str, data_type: str = "rate"
) -> tuple[float, int]:
    """``(variance, kept terms)`` of ``kind`` in {"oavar", "avar", "mvar", "hvar"} at factor m."""
    data = np.asarray(data, dtype=float)
    missing = np.isnan(data)
    bad = _prefix(missing.astype(np.int64))  # bad[i] = NaN count in data[:i]
    if data_type == "rate":
        centred = np.where(missing, 0.0, data - np.nanmean(data))
        x = _prefix(centred) * t0  # angle, meaningful only across gap-free spans

        # A term spanning angle indices k..k+s uses rate samples k..k+s−1.
        def clean(k: np.ndarray, s: int) -> np.ndarray:
            return bad[k + s] - bad[k] == 0
    else:
        x = np.where(missing, 0.0, data)

        # ... and phase samples k..k+s.
        def clean(k: np.ndarray, s: int) -> np.ndarray:
            return bad[k + s + 1] - bad[k] == 0

    tau = m * t0
    n = len(x)
    if kind in ("oavar", "avar"):
        step = 1 if kind == "oavar" else m
        k = np.arange(0, n - 2 * m, step)
        d = x[k + 2 * m] - 2 * x[k + m] + x[k]
        keep = clean(k, 2 * m)
        return float(np.sum(d[keep] ** 2) / (2 * tau**2 * keep.sum())), int(keep.sum())
    if kind == "hvar":
        k = np.arange(0, n - 3 * m)
        d = x[k + 3 * m] - 3 * x[k + 2 * m] + 3 * x[k + m] - x[k]
        keep = clean(k, 3 * m)
        return float(np.sum(d[keep] ** 2) / (6 * tau**2 * keep.sum())), int(keep.sum())
    if kind == "mvar":
        i = np.arange(0, n - 2 * m)
        d2 = x[i + 2 * m] - 2 * x[i + m] + x[i]
        c = _prefix(d2)
        j = np.arange(0, n - 3 * m + 1)
        inner = c[j + m] - c[j]
        keep = clean(j, 3 * m - 1)
        return float(np.sum(inner[keep] ** 2) / (2 * m**2 * tau**2 * keep.sum())), int(keep.sum())
    raise ValueError(kind)
