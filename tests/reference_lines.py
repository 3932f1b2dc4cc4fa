"""NumPy/SciPy references for spectral lines, the sinusoidal term and the wavelet variance
(independent of the Rust core)."""

from __future__ import annotations

import numpy as np
from scipy import integrate, optimize, stats


def oavar(rate: np.ndarray, m: int) -> float:
    """Overlapping Allan variance of rate samples at averaging factor m (NIST SP 1065 eq. 11),
    directly from the means of m samples: ½·mean((ȳ_{k+m} − ȳ_k)²) over all k."""
    c = np.concatenate([[0.0], np.cumsum(rate - rate.mean())])
    means = (c[m:] - c[:-m]) / m
    d = means[m:] - means[:-m]
    return float(0.5 * np.mean(d * d))


def sine_avar_continuous(amplitude: float, f0: float, tau: np.ndarray) -> np.ndarray:
    """IEEE Std 952-1997 Annex C: Ω₀²·(sin²(πf₀τ)/(πf₀τ))²."""
    x = np.pi * f0 * np.asarray(tau, dtype=float)
    return amplitude**2 * (np.sin(x) ** 2 / x) ** 2


def haar_coefficients(rate: np.ndarray, j: int) -> np.ndarray:
    """Level-j Haar MODWT coefficients free of the boundary: half the difference of adjacent
    means of 2^{j−1} samples (M_j = n − 2^j + 1 of them)."""
    h = 2 ** (j - 1)
    c = np.concatenate([[0.0], np.cumsum(rate - rate.mean())])
    means = (c[h:] - c[:-h]) / h
    return 0.5 * (means[h:] - means[:-h])


def wvar_classical(rate: np.ndarray, levels: int, confidence: float) -> dict[str, np.ndarray]:
    """Classical wavelet variance with Percival's η₃ chi-square interval (R ``wv``)."""
    n = rate.size
    v, lo, hi, edf = [], [], [], []
    alpha = 1.0 - confidence
    for j in range(1, levels + 1):
        w = haar_coefficients(rate, j)
        nu = float(np.mean(w * w))
        eta = max((n - 2**j + 1) / 2**j, 1.0)
        v.append(nu)
        edf.append(eta)
        lo.append(eta * nu / stats.chi2.ppf(1.0 - alpha / 2.0, eta))
        hi.append(eta * nu / stats.chi2.ppf(alpha / 2.0, eta))
    return {
        "variance": np.array(v),
        "ci_low": np.array(lo),
        "ci_high": np.array(hi),
        "edf": np.array(edf),
    }


def rho(r: np.ndarray, c: float) -> np.ndarray:
    """ρ_c(r) = r²(1 − r²/c²)⁴ for |r| ≤ c, else 0 (the square of Tukey's biweight ψ)."""
    r = np.asarray(r, dtype=float)
    inside = np.abs(r) <= c
    rr = np.where(inside, r, 0.0)
    u = 1.0 - rr * rr / (c * c)
    return np.where(inside, rr * rr * u**4, 0.0)


def gaussian_expectation(g) -> float:  # type: ignore[no-untyped-def]
    """E g(Z), Z ~ N(0, 1), by adaptive quadrature."""
    val, _ = integrate.quad(lambda z: g(z) * stats.norm.pdf(z), -np.inf, np.inf, limit=200)
    return float(val)


def biweight_efficiency(c: float) -> float:
    """Gaussian efficiency of the M-estimator of scale with ρ_c: D²/(2·Var ρ) with
    D = E[Z²ρ(Z)] − E ρ(Z), by quadrature over the truncated support."""

    def e(g):  # type: ignore[no-untyped-def]
        val, _ = integrate.quad(lambda z: g(z) * stats.norm.pdf(z), -c, c, limit=200)
        return float(val)

    a = e(lambda z: rho(np.array(z), c))
    d = e(lambda z: z * z * rho(np.array(z), c)) - a
    q = e(lambda z: rho(np.array(z), c) ** 2) - a * a
    return d * d / (2.0 * q)


def robust_variance(w: np.ndarray, c: float) -> float:
    """Literal solution of (1/M) Σ ρ_c(W/ν) = E ρ_c(Z) on the decreasing branch: bracket from
    the MAD scale by doubling/halving, then Brent's method on ν."""
    a = integrate.quad(lambda z: rho(np.array(z), c) * stats.norm.pdf(z), -c, c)[0]

    def lhs(nu: float) -> float:
        return float(np.mean(rho(w / nu, c)) - a)

    nu0 = 1.482602218505602 * float(np.median(np.abs(w)))
    if lhs(nu0) > 0:
        lo, hi = nu0, 2 * nu0
        while lhs(hi) > 0:
            lo, hi = hi, 2 * hi
    else:
        lo, hi = nu0 / 2, nu0
        k = 0
        while lhs(lo) <= 0 and k < 60:
            lo, hi = lo / 2, lo
            k += 1
        if lhs(lo) <= 0:  # no root: the maximum of the left side over [ν₀ 2⁻⁶⁰, ν₀]
            res = optimize.minimize_scalar(
                lambda x: -lhs(float(np.exp(x))),
                bounds=(np.log(lo), np.log(nu0)),
                method="bounded",
                options={"xatol": 1e-12},
            )
            return float(np.exp(2 * res.x))
    nu = optimize.brentq(lhs, lo, hi, xtol=1e-14 * hi, rtol=1e-14)
    return nu * nu
