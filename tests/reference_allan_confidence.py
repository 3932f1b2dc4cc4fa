"""Reference confidence intervals assembled from AllanTools' own building blocks.

AllanTools (2024.06) has no one-call "deviation with confidence interval" for every estimator;
its ``ci`` module offers the pieces: ``autocorr_noise_id`` (Riley & Greenhall lag-1 ACF),
``edf_greenhall`` (Greenhall & Riley 2003), ``edf_totdev`` (SP1065 TOTVAR EDF),
``edf_simple`` (SP1065 Table 5) and ``confidence_interval`` (chi-square, SP1065 eq. 45).
This module combines them per τ the way gyrobias documents it:

* noise id on the phase (angle) series ``x`` with ``dmax = 2`` (3 for Hadamard); when the
  decimated series has fewer than 30 points (AllanTools raises), the id at the largest
  requested factor below that had 30 points (``m_fallback``), or, if none had,
  at ``m_c = (len(x) - 1) // 29``;
* α clamped to the estimator's convergent range (α ≥ −2 Allan-type, ≥ −4 Hadamard, ≤ 2);
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


def identify(x: NDArray[np.float64], m: int, dmax: int, m_fallback: int | None = None) -> int:
    """AllanTools' lag-1 ACF noise id with gyrobias' too-few-points rule (unclamped)."""
    if not has_30_points(len(x), m):
        m = m_fallback if m_fallback is not None else (len(x) - 1) // 29
    return int(allantools.autocorr_noise_id(x, m, data_type="phase", dmin=0, dmax=dmax)[0])


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
    valid_below = [k for k in (requested or []) if k < m and has_30_points(n, k)]
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
    low, high = allantools.confidence_interval(deviation, float(edf), ci=level)
    return ReferenceInterval(alpha, float(edf), float(low), float(high))
