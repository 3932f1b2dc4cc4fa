"""Independent references for the rest of the Allan family (issue 15) and the test-data readers.

Each statistic is written literally from NIST SP 1065 (eqs. 15, 17, 27, 29, 30, 31) in NumPy —
reflection copies, explicit double sums — with no code shared with gyrobias. Slow, but exact:
the oracle for tests/test_allan_family.py on short series.
"""

from __future__ import annotations

import gzip
from pathlib import Path
from typing import NamedTuple

import numpy as np

DATA = Path(__file__).parent / "data" / "allan_family"


def hvar_non_overlapping(x: np.ndarray, t0: float, m: int) -> tuple[float, int]:
    """SP 1065 eq. 17: third differences at k = 0, m, 2m, …"""
    k = np.arange(0, len(x) - 3 * m, m)
    d = x[k + 3 * m] - 3 * x[k + 2 * m] + 3 * x[k + m] - x[k]
    return float(np.sum(d**2) / (6 * (m * t0) ** 2 * d.size)), d.size


def mvar(x: np.ndarray, t0: float, m: int) -> float:
    """SP 1065 eq. 14 as a double sum."""
    n = len(x) - 3 * m + 1
    s = 0.0
    for j in range(n):
        i = np.arange(j, j + m)
        s += np.sum(x[i + 2 * m] - 2 * x[i + m] + x[i]) ** 2
    return s / (2 * m**2 * (m * t0) ** 2 * n)


def tvar(x: np.ndarray, t0: float, m: int) -> float:
    """SP 1065 eq. 15: TVAR = τ²/3 · MVAR."""
    return (m * t0) ** 2 / 3 * mvar(x, t0, m)


def _total_window_sum(z: np.ndarray, m: int) -> float:
    """Σ over the 3m-windows of Σ_j (S_j − 2S_{j+m} + S_{j+2m})² on the reflected, detrended window."""
    w = 3 * m
    half = w // 2
    dist = (w + 1) // 2
    total = 0.0
    for i in range(len(z) - w + 1):
        xs = z[i : i + w]
        slope = (xs[w - half :].mean() - xs[:half].mean()) / dist
        x0 = xs - slope * np.arange(w)
        star = np.concatenate((x0[::-1], x0, x0[::-1]))
        c = np.concatenate(([0.0], np.cumsum(star)))
        s = c[m:] - c[:-m]  # m-sample sums starting at 0 .. 8m
        d = s[: 6 * m] - 2 * s[m : 7 * m] + s[2 * m : 8 * m]
        total += float(np.sum(d**2))
    return total


def mtotvar(x: np.ndarray, t0: float, m: int) -> float:
    """SP 1065 eq. 27 (phase sub-sequences of 3m points, reflection to 9m)."""
    n = len(x) - 3 * m + 1
    return _total_window_sum(np.asarray(x, float), m) / (m**2 * 6 * m * 2 * (m * t0) ** 2 * n)


def htotvar(x: np.ndarray, t0: float, m: int) -> float:
    """SP 1065 eq. 29 on the frequency series; the overlapping Hadamard variance at m = 1."""
    if m == 1:
        d = x[3:] - 3 * x[2:-1] + 3 * x[1:-2] - x[:-3]
        return float(np.sum(d**2) / (6 * t0**2 * d.size))
    y = np.diff(x) / t0
    n = len(y) - 3 * m + 1
    return _total_window_sum(y, m) / (m**2 * 6 * 6 * m * n)


def theo1(x: np.ndarray, t0: float, m: int) -> float:
    """SP 1065 eq. 30 literally (i outer, δ inner)."""
    n = len(x)
    h = m // 2
    i = np.arange(n - m)
    s = 0.0
    for d in range(h):
        t = x[i] - x[i - d + h] + x[i + m] - x[i + d + h]
        s += float(np.sum(t**2)) / (h - d)
    return s / (0.75 * (n - m) * (m * t0) ** 2)


def oavar(x: np.ndarray, t0: float, m: int) -> float:
    d = x[2 * m :] - 2 * x[m:-m] + x[: -2 * m]
    return float(np.sum(d**2) / (2 * (m * t0) ** 2 * d.size))


def theobr_ratio(x: np.ndarray, t0: float) -> float:
    """SP 1065 eq. 31: mean of AVAR(9 + 3i)/Théo1(12 + 4i), i = 0 … ⌊N/30 − 3⌋."""
    n = int(np.floor(len(x) / 30 - 3))
    return float(
        np.mean([oavar(x, t0, 9 + 3 * i) / theo1(x, t0, 12 + 4 * i) for i in range(n + 1)])
    )


class Stable32Row(NamedTuple):
    m: int
    tau: float
    n: int
    alpha: int
    low: float
    dev: float
    high: float


def read_stable32(name: str) -> list[Stable32Row]:
    """Rows of a Stable32 result table (AF, Tau, #, Alpha, Min Sigma, Sigma, Max Sigma)."""
    rows = []
    for line in (DATA / name).read_text().splitlines():
        if not line.strip() or line.lstrip().startswith("#"):
            continue
        f = line.split()
        rows.append(
            Stable32Row(
                int(f[0]),
                float(f[1]),
                int(f[2]),
                int(f[3]),
                float(f[4]),
                float(f[5]),
                float(f[6]),
            )
        )
    return rows


def read_series(name: str) -> np.ndarray:
    """One number per line ('#' comments), plain or gzip-compressed."""
    path = DATA / name
    opener = gzip.open if path.suffix == ".gz" else open
    with opener(path, "rt") as fh:
        return np.loadtxt(fh, comments="#", dtype=np.float64)


#: SP 1065 Table 30 / Riley's NBS14 10-point phase data (Stable32 conventions).
NBS14_PHASE = np.array(
    [
        0.00000,
        103.11111,
        123.22222,
        157.33333,
        166.44444,
        48.55555,
        -96.33333,
        -2.22222,
        111.88889,
        0.00000,
    ]
)
