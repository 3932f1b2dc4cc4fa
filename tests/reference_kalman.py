"""Plain NumPy/SciPy references for the fixed-gain Kalman filter ([NR], SPEC §6).

Written straight from the paper's equations (state-space form, matrix exponentials, the
Riccati recursion), independent of the closed forms the Rust core uses.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg
from numpy.typing import NDArray

H = np.array([[1.0, 1.0]])


def discrete_noise(fs: float, arw: float, rrw: float) -> tuple[float, float, float]:
    """(T, R_d = N²/T, Q_b = K²T)."""
    t = 1.0 / fs
    return t, arw**2 / t, rrw**2 * t


def riccati_gain(q_omega: float, q_b: float, r_d: float, iterations: int) -> NDArray[np.float64]:
    """[NR] eqs. 9–11 with Φ = I, Joseph form, from P0 = 0."""
    q = np.diag([q_omega, q_b])
    p = np.zeros((2, 2))
    k = np.zeros((2, 1))
    for _ in range(iterations):
        pp = p + q
        s = (H @ pp @ H.T)[0, 0] + r_d
        k = pp @ H.T / s
        ikh = np.eye(2) - k @ H
        p = ikh @ pp @ ikh.T + k * r_d @ k.T
    return k[:, 0]


def discrete_matrices(k_cont: NDArray[np.float64], t: float) -> tuple[NDArray[np.float64], ...]:
    """A = e^{mT}, B = ∫₀ᵀ e^{mt} dt (block exponential), G = B K for m = −K H."""
    k = np.asarray(k_cont, dtype=float).reshape(2, 1)
    m = -k @ H
    big = np.zeros((4, 4))
    big[:2, :2] = m
    big[:2, 2:] = np.eye(2)
    e = scipy.linalg.expm(big * t)
    a = e[:2, :2]
    b = e[:2, 2:]
    return a, b, (b @ k)[:, 0]


def filter_loop(
    z: NDArray[np.float64], g: NDArray[np.float64], x0: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """X_k = X_{k−1} + G (z_k − H X_{k−1}) for one axis, sample by sample."""
    x = np.array(x0, dtype=float)
    rate = np.empty(len(z))
    bias = np.empty(len(z))
    for i, zi in enumerate(z):
        x = x + g * (zi - x[0] - x[1])
        rate[i], bias[i] = x
    return rate, bias


def impulse_response_fft(g1: float, g2: float, n: int) -> NDArray[np.complex128]:
    """FFT of the rate response to a unit impulse (state-space loop, zero initial state)."""
    z = np.zeros(n)
    z[0] = 1.0
    rate, _ = filter_loop(z, np.array([g1, g2]), np.zeros(2))
    return np.fft.rfft(rate)


def acf(x: NDArray[np.float64], lags: int) -> NDArray[np.float64]:
    """Sample autocorrelation ρ(1..lags) (biased, mean removed)."""
    x = x - x.mean()
    c0 = x @ x
    return np.array([x[:-k] @ x[k:] / c0 for k in range(1, lags + 1)])
