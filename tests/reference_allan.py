"""Direct NumPy implementations of the Allan-family estimators (NIST SP 1065 eqs. 7, 11, 14, 18, 25).

Written from the formulas, loop-free where NumPy allows, with no shared code with gyrobias: the
oracle for the property tests in test_allan.py.
"""

from __future__ import annotations

import numpy as np


def angle_from_rate(rate: np.ndarray, t0: float) -> np.ndarray:
    """x_0 = 0, x_k = t0·Σ_{i<k}(Ω_i − mean Ω)."""
    rate = np.asarray(rate, dtype=float)
    return np.concatenate(([0.0], np.cumsum(rate - rate.mean()) * t0))


def oavar(x: np.ndarray, t0: float, m: int) -> tuple[float, int]:
    d = x[2 * m :] - 2 * x[m:-m] + x[: -2 * m]
    return float(np.sum(d**2) / (2 * (m * t0) ** 2 * d.size)), d.size


def avar_binned(rate: np.ndarray, m: int) -> tuple[float, int]:
    """[BP] eq. 2 from disjoint bin means of the rate (t0 cancels)."""
    k = len(rate) // m
    means = np.asarray(rate[: k * m], dtype=float).reshape(k, m).mean(axis=1)
    diffs = np.diff(means)
    return float(np.sum(diffs**2) / (2 * (k - 1))), k - 1


def mvar(x: np.ndarray, t0: float, m: int) -> tuple[float, int]:
    n = len(x) - 3 * m + 1
    d = x[2 * m :] - 2 * x[m:-m] + x[: -2 * m]  # length len(x) − 2m
    c = np.concatenate(([0.0], np.cumsum(d)))
    inner = c[m : m + n] - c[:n]
    return float(np.sum(inner**2) / (2 * m**2 * (m * t0) ** 2 * n)), n


def hvar(x: np.ndarray, t0: float, m: int) -> tuple[float, int]:
    d = x[3 * m :] - 3 * x[2 * m : -m] + 3 * x[m : -2 * m] - x[: -3 * m]
    return float(np.sum(d**2) / (6 * (m * t0) ** 2 * d.size)), d.size


def totvar(x: np.ndarray, t0: float, m: int) -> tuple[float, int]:
    n = len(x)
    left = (2 * x[0] - x[1 : n - 1])[::-1]  # x*_{-(n-2)} .. x*_{-1}
    right = 2 * x[-1] - x[-2:0:-1]  # x*_{n} .. x*_{2n-3}
    star = np.concatenate((left, x, right))
    mid = n - 2
    i = np.arange(1, n - 1) + mid
    d = star[i - m] - 2 * star[i] + star[i + m]
    return float(np.sum(d**2) / (2 * (m * t0) ** 2 * (n - 2))), n - 2


def nbs_1000() -> np.ndarray:
    """The NIST SP 1065 §12.4 (NBS14) 1000-point test set, n_{i+1} = 16807 n_i mod (2^31 − 1).

    Not a random generator for tests: the published data set is *defined* by this recurrence
    (Park–Miller, seed 1234567890), and SP 1065 prints its first values, checked here. The
    one copy every NBS14 test uses.
    """
    n = [1234567890]
    for _ in range(999):
        n.append((16807 * n[-1]) % 2147483647)
    assert n[1:4] == [395529916, 1209410747, 633705974]  # printed in SP 1065
    return np.asarray(n, dtype=np.float64) / 2147483647.0
