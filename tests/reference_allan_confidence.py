"""Reference confidence intervals assembled from AllanTools' own building blocks.

AllanTools (2024.06) has no one-call "deviation with confidence interval" for every estimator;
its ``ci`` module offers the pieces: ``autocorr_noise_id`` (Riley & Greenhall lag-1 ACF),
``edf_greenhall`` (Greenhall & Riley 2003), ``edf_totdev`` (SP1065 TOTVAR EDF),
``edf_simple`` (SP1065 Table 5) and ``confidence_interval`` (chi-square, SP1065 eq. 45).
This module combines them per τ the way gyrobias documents it:

* noise id on the phase (angle) series ``x`` with ``dmax = 2`` (3 for Hadamard) and ``dmin = 1``
  (the decision on the first differences of the decimated phase, i.e. on the averaged rate),
  checked against R(n) below 100 decimated points;
  when the decimated series has fewer than 30 points (AllanTools raises), the B1 ratio and R(n)
  of SP1065 §5.6 (``few_point_alpha``: AllanTools' ``b1_theory``/``rn_theory`` expectations,
  the ratios evaluated here with NumPy), and where those cannot be formed the id at the largest
  requested factor below (``m_fallback``), or at ``m_c = (len(x) - 1) // 29``;
* α clamped to the estimator's convergent range (α ≥ −2 Allan-type, ≥ −4 Hadamard, ≤ 2);
* EDF capped at the number of terms summed (gyrobias' documented rule);
* TOTDEV: ``edf_totdev`` for α ∈ {0, −1, −2}, Greenhall's overlapping-Allan EDF for α = 2
  (Stable32's choice), ``edf_simple`` for α = 1 (AllanTools' choice).
"""

from __future__ import annotations

from dataclasses import dataclass

import allantools
import numpy as np
from numpy.typing import NDArray

#: (d, overlapping, modified) of Greenhall's EDF per gyrobias estimator kind.
GREENHALL_ARGS = {
    "adev": (2, True, False),
    "adev_nonoverlapping": (2, False, False),
    "mdev": (2, True, True),
    "hdev": (3, True, False),
}


@dataclass(frozen=True)
class ReferenceInterval:
    alpha: int
    edf: float
    low: float  # deviation bounds
    high: float


def phase_from_rate(rate: NDArray[np.float64], fs: float) -> NDArray[np.float64]:
    """gyrobias' angle series: mean removed, integrated, x_0 = 0 prepended."""
    y = np.asarray(rate, dtype=np.float64)
    return np.concatenate([[0.0], np.cumsum(y - y.mean()) / fs])


def has_30_points(n: int, m: int) -> bool:
    return -(-n // m) >= 30


def r_n(x: NDArray[np.float64], m: int) -> float:
    """MVAR/AVAR from the overlapping terms at j = 0, q, 2q, … (q = ⌈m/8⌉), direct sums."""
    n = len(x)
    q = -(-m // 8)
    j = np.arange(0, n - 2 * m, q)
    avar = np.mean((x[j + 2 * m] - 2 * x[j + m] + x[j]) ** 2)
    d2 = x[2 * m :] - 2 * x[m:-m] + x[: -2 * m]
    inner = np.array([d2[k : k + m].sum() for k in range(0, n - 3 * m + 1, q)])
    return float(np.mean(inner**2) / m**2 / avar)


def pm_by_r_n(x: NDArray[np.float64], m: int) -> bool:
    """R(n) below √(R_flicker·½): angle (phase) noise."""
    return r_n(x, m) < np.sqrt(allantools.ci.rn_theory(m, -1) * 0.5)


def few_point_alpha(x: NDArray[np.float64], m: int) -> int | None:
    """B1 ratio / R(n) identification (gyrobias' documented rule, written independently).

    R(n) = MVAR/AVAR from the overlapping terms at j = 0, q, 2q, … (q = ⌈m/8⌉); angle noise if
    R(n) < √(R_flicker·½) (or, for m < 4, B1 below its PM boundary), white vs flicker by
    √(R_white·R_flicker); else B1 = s²/AVAR of the ⌊(N−1)/m⌋ rate averages against Howe's
    B1(n, μ) for μ = 1, 0, −1 (geometric-mean boundaries).
    """
    n = len(x)
    nb = (n - 1) // m
    if nb < 3 or n < 3 * m:
        return None
    y = (x[m : (nb + 1) * m : m] - x[0 : nb * m : m]) / m
    b1 = np.var(y, ddof=1) / (np.sum(np.diff(y) ** 2) / (2 * (nb - 1)))
    rn = r_n(x, m)
    ci = allantools.ci

    def geo(mu_a: int, mu_b: int) -> float:
        return float(np.sqrt(ci.b1_theory(nb, mu_a) * ci.b1_theory(nb, mu_b)))

    r_flicker = ci.rn_theory(m, -1)  # AllanTools' b = α − 2
    if rn < np.sqrt(r_flicker * 0.5) or (m < 4 and b1 < geo(-1, -2)):
        return 1 if rn > np.sqrt(r_flicker * ci.rn_theory(m, 0)) else 2
    if b1 > geo(1, 0):
        return -2
    if b1 > geo(0, -1):
        return -1
    return 0


def identify(x: NDArray[np.float64], m: int, dmax: int, m_fallback: int | None = None) -> int:
    """Noise id at factor m (unclamped): AllanTools' lag-1 ACF (dmin = 1) or B1/R(n)."""
    n = len(x)
    if has_30_points(n, m):
        alpha = int(allantools.autocorr_noise_id(x, m, data_type="phase", dmin=1, dmax=dmax)[0])
        # Fewer than 100 points: the ACF's family (angle α ≥ 1 / rate α ≤ 0) must agree with
        # R(n)'s, else B1/R(n) decide (gyrobias' documented consistency check).
        if -(-n // m) < 100 and n >= 3 * m and pm_by_r_n(x, m) != (alpha >= 1):
            checked = few_point_alpha(x, m)
            alpha = checked if checked is not None else alpha
        return alpha
    alpha = few_point_alpha(x, m)
    if alpha is not None:
        return alpha
    if m_fallback is not None:
        return identify(x, m_fallback, dmax)
    m_c = (len(x) - 1) // 29
    if m_c >= 1:
        return int(allantools.autocorr_noise_id(x, m_c, data_type="phase", dmin=1, dmax=dmax)[0])
    return 0


def interval(
    x: NDArray[np.float64],
    kind: str,
    m: int,
    deviation: float,
    level: float,
    requested: list[int] | None = None,
) -> ReferenceInterval | None:
    """AllanTools' interval for one deviation value at averaging factor m.

    ``None`` where AllanTools has no EDF: Greenhall's case 4 (white angle noise, unmodified
    variance) with ⌈M/S⌉ ≤ d raises ``NotImplementedError`` there; gyrobias evaluates the exact
    eq. 13 (checked in the Rust tests: independent terms give edf = M).
    """
    n = len(x)
    dmax = 3 if kind == "hdev" else 2
    valid_below = [
        k
        for k in (requested or [])
        if k < m and (has_30_points(n, k) or few_point_alpha(x, k) is not None)
    ]
    alpha = identify(x, m, dmax, max(valid_below) if valid_below else None)
    alpha = max(min(alpha, 2), -4 if kind == "hdev" else -2)
    if kind == "totdev":
        if alpha in (0, -1, -2):
            edf = allantools.edf_totdev(n, m, alpha)
        elif alpha == 2:
            try:
                edf = allantools.edf_greenhall(
                    alpha=2, d=2, m=m, N=n, overlapping=True, modified=False
                )
            except NotImplementedError:
                return None
        else:
            edf = allantools.edf_simple(n, m, alpha)
    else:
        d, overlapping, modified = GREENHALL_ARGS[kind]
        try:
            edf = allantools.edf_greenhall(
                alpha=alpha, d=d, m=m, N=n, overlapping=overlapping, modified=modified
            )
        except NotImplementedError:
            return None
    # gyrobias' documented cap: never more degrees of freedom than terms in the sum (binds
    # for TOTDEV's b·N/m fits at small m, e.g. white FM at m = 1: 1.5·N > N − 2).
    terms = {
        "adev": n - 2 * m,
        "adev_nonoverlapping": (n - 1) // m - 1,
        "mdev": n - 3 * m + 1,
        "hdev": n - 3 * m,
        "totdev": n - 2,
    }[kind]
    edf = min(float(edf), float(terms))
    low, high = allantools.confidence_interval(deviation, float(edf), ci=level)
    return ReferenceInterval(alpha, float(edf), float(low), float(high))
