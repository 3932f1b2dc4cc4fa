"""NumPy references for gyrobias.predict (test oracles and the benchmark baseline).

- :func:`literal_filter`: [BP] §IV-A's growing-state Kalman filter, written directly in NumPy
  (O(n³)); the baseline the benchmark compares against.
- :func:`dense_predict`: the forecast as the conditional Gaussian of the joint (mean, future bias,
  calibration) distribution with dense linear algebra — independent of both Rust algorithms.
- :func:`arfima_type2`: type-II ARFIMA(0, d, 0) test data (x = Δ^{−d} w, w_t = 0 for t < 0).
"""

from __future__ import annotations

import numpy as np
from scipy.linalg import solve, toeplitz
from scipy.signal import fftconvolve


def weights(d: float, n: int) -> np.ndarray:
    """π_0..π_{n−1} of (1 − B)^d by the product recursion."""
    out = np.empty(n)
    out[0] = 1.0
    if n > 1:
        ls = np.arange(1, n, dtype=float)
        out[1:] = np.cumprod((ls - 1.0 - d) / ls)
    return out


def arfima_type2(n: int, d: float, sigma: float, size: int, rng: np.random.Generator) -> np.ndarray:
    """``size`` type-II ARFIMA(0, d, 0) series of length n with driving std sigma: (size, n)."""
    w = rng.standard_normal((size, n)) * sigma
    psi = weights(-d, n)
    return fftconvolve(w, psi[None, :], axes=1)[:, :n]


def _mean_prior(mean, y):
    if mean == "sample":
        return float(np.mean(y)), 0.0
    if mean == "none":
        return 0.0, 0.0
    if mean == "diffuse":
        return None
    mu0, p0 = mean
    return float(mu0), float(p0)


def literal_filter(y, h, d, q, r, mean="sample"):
    """[BP] §IV-A literally: state [m, x_0..x_t] grows by one every step. Returns
    (bias, std, std_observation, m̂)."""
    y = np.asarray(y, dtype=float)
    k = y.size
    n = k + h
    pi = weights(d, n)
    dim = n + 1
    xs = np.zeros(dim)
    P = np.zeros((dim, dim))
    prior = _mean_prior(mean, y)
    diffuse = prior is None
    if not diffuse:
        xs[0], P[0, 0] = prior
    bias, var = [], []
    for t in range(n):
        it = t + 1
        a = np.zeros(it)
        if t > 0:
            a[1 : t + 1] = -pi[t:0:-1]  # a[1 + t − l] = φ_l = −π_l, l = 1..t
        row = a @ P[:it, :it]
        xs[it] = a @ xs[:it]
        P[it, :it] = row
        P[:it, it] = row
        P[it, it] = row @ a + q
        if t < k:
            if t == 0 and diffuse:
                xs[0] = y[0]
                P[0, 0] = q + r
                P[0, 1] = P[1, 0] = -q
                continue
            g = P[: it + 1, 0] + P[: it + 1, it]
            s = g[0] + g[it] + r
            xs[: it + 1] += g * (y[t] - xs[0] - xs[it]) / s
            P[: it + 1, : it + 1] -= np.outer(g, g) / s
        else:
            bias.append(xs[0] + xs[it])
            var.append(P[0, 0] + 2 * P[0, it] + P[it, it])
    var = np.maximum(np.array(var), 0.0)
    return np.array(bias), np.sqrt(var), np.sqrt(var + r), xs[0]


def dense_predict(y, h, d, q, r, mean="sample"):
    """Conditional Gaussian forecast by dense linear algebra. Returns (bias, std, std_obs, m̂)."""
    y = np.asarray(y, dtype=float)
    k = y.size
    n = k + h
    psi = weights(-d, n)
    L = np.tril(toeplitz(psi))
    X = q * L @ L.T
    C = X[:k, :k] + r * np.eye(k)
    Xfc, Xff = X[k:, :k], X[k:, k:]
    ones = np.ones(k)
    prior = _mean_prior(mean, y)
    if prior is None:  # GLS / BLUP with an infinite prior on m
        cinv_y = solve(C, y, assume_a="pos")
        cinv_1 = solve(C, ones, assume_a="pos")
        uu = ones @ cinv_1
        m = (ones @ cinv_y) / uu
        F = solve(C, Xfc.T, assume_a="pos").T
        g = 1.0 - F @ ones
        b = F @ y + m * g
        v = np.diag(Xff - F @ Xfc.T) + g**2 / uu
        return b, np.sqrt(v), np.sqrt(v + r), m
    mu0, p0 = prior
    Cy = C + p0 * np.outer(ones, ones)
    Cby = Xfc + p0
    G = solve(Cy, Cby.T, assume_a="pos").T
    b = mu0 + G @ (y - mu0)
    v = np.diag(Xff + p0 - G @ Cby.T)
    m = mu0 + (p0 * ones) @ solve(Cy, y - mu0, assume_a="pos")
    return b, np.sqrt(v), np.sqrt(v + r), m
