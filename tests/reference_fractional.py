"""Independent NumPy/SciPy references for gyrobias.fractional.

Each routine follows the textbook formula by a different route than the Rust core: weights from
binomial coefficients / Gamma functions instead of the product recursion, plain ``np.convolve``
instead of FFT or lag-wise sums, a direct DFT instead of an FFT periodogram, and the Gamma-function
closed form of the ARFIMA autocovariance instead of its recursion.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy import special


def weights_gamma(d: float, n: int) -> NDArray[np.float64]:
    """``π_l(d) = Γ(l − d)/(Γ(−d)Γ(l + 1))`` (non-integer ``d``; small ``l`` only)."""
    lags = np.arange(n, dtype=np.float64)
    return special.gamma(lags - d) / (special.gamma(-d) * special.gamma(lags + 1.0))


def weights_binomial(d: float, n: int) -> NDArray[np.float64]:
    """``π_l(d) = (−1)^l·C(d, l)`` (any real ``d``)."""
    lags = np.arange(n)
    return (-1.0) ** lags * special.binom(d, lags)


def weights_extended(d: float, n: int) -> NDArray[np.float64]:
    """``π_l(d)`` in extended precision (x87 long double: 64-bit mantissa), rounded to float64.

    The formula itself is checked against Gamma-function values (:func:`weights_gamma`); this is
    the precision oracle for long series, where SciPy's ``binom`` loses ~1e-13 relative and the
    float64 recursion ~1e-14.
    """
    out = np.empty(n, dtype=np.longdouble)
    current = np.longdouble(1.0)
    dd = np.longdouble(d)
    for lag in range(n):
        if lag > 0:
            current *= (np.longdouble(lag) - 1 - dd) / np.longdouble(lag)
        out[lag] = current
    return out.astype(np.float64)


def diff(x: NDArray[np.float64], d: float) -> NDArray[np.float64]:
    """Type-II fractional difference of a 1-D series by direct convolution (``np.convolve``)."""
    x = np.asarray(x, dtype=np.float64)
    return np.convolve(x, weights_extended(d, x.size))[: x.size]


def elw_objective(x: NDArray[np.float64], d: float, m: int, level: str) -> float:
    """``R(d) = log G(d) − 2d·mean log λ_j`` with a direct DFT (Shimotsu & Phillips 2005)."""
    x = np.asarray(x, dtype=np.float64)
    n = x.size
    if level == "shimotsu":
        w = 1.0 if d <= 0.5 else 0.0 if d >= 0.75 else 0.5 * (1.0 + np.cos(4.0 * np.pi * d))
        x = x - (w * x.mean() + (1.0 - w) * x[0])
    u = diff(x, d)
    lam = 2.0 * np.pi * np.arange(1, m + 1) / n
    t = np.arange(n)
    dft = np.exp(-1j * np.outer(lam, t)) @ u
    g = np.mean(np.abs(dft) ** 2 / (2.0 * np.pi * n))
    return float(np.log(g) - 2.0 * d * np.mean(np.log(lam)))


def arfima_autocovariance(d: float, sigma: float, lags: int) -> NDArray[np.float64]:
    """``γ(k) = σ²Γ(1 − 2d)Γ(k + d)/(Γ(d)Γ(1 − d)Γ(k + 1 − d))`` (Hosking 1981, 0 < |d| < ½)."""
    k = np.arange(1, lags, dtype=np.float64)
    scale = sigma**2 * special.gamma(1.0 - 2.0 * d) / special.gamma(1.0 - d)
    gamma0 = scale / special.gamma(1.0 - d)
    rest = scale / special.gamma(d) * np.exp(special.gammaln(k + d) - special.gammaln(k + 1.0 - d))
    return np.concatenate([[gamma0], rest])


def type2_variance(d: float, sigma: float, n: int) -> NDArray[np.float64]:
    """``Var(x_k) = σ²·Σ_{l≤k} ψ_l²`` of type-II ARFIMA, ``ψ_l = π_l(−d)``."""
    return sigma**2 * np.cumsum(weights_binomial(-d, n) ** 2)
