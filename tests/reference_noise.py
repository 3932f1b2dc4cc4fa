"""NumPy/SciPy references for gyrobias.noise (independent of the Rust core)."""

from __future__ import annotations

import math

import numpy as np
from scipy.optimize import nnls

FLICKER = math.sqrt(2.0 * math.log(2.0) / math.pi)


def basis(taus: np.ndarray) -> np.ndarray:
    """Columns 3/τ², 1/τ, 0.664², τ/3, τ²/2 of the five-term Allan-variance model."""
    t = np.asarray(taus, dtype=float)
    return np.column_stack([3.0 / t**2, 1.0 / t, np.full_like(t, FLICKER**2), t / 3.0, t**2 / 2.0])


def model_avar(squared: np.ndarray, taus: np.ndarray) -> np.ndarray:
    return basis(taus) @ np.asarray(squared, dtype=float)


def joint_irls(taus: np.ndarray, avar: np.ndarray, edf: np.ndarray, passes: int = 50) -> np.ndarray:
    """Iteratively reweighted NNLS (SciPy's Lawson–Hanson) with weights edf/(2·ref²)."""
    a = basis(taus)
    ref = np.asarray(avar, dtype=float).copy()
    c = np.zeros(5)
    for _ in range(passes):
        sw = np.sqrt(edf / 2.0) / ref
        scale = np.linalg.norm(a * sw[:, None], axis=0)
        z, _ = nnls(a * sw[:, None] / scale, sw * avar)
        new = z / scale
        if np.allclose(new, c, rtol=1e-12, atol=0.0):
            break
        c = new
        ref = np.maximum(a @ c, 0.01 * avar)
    return c


def local_slopes(taus: np.ndarray, avar: np.ndarray) -> np.ndarray:
    """Central-difference slopes of ln σ against ln τ (one-sided at the ends)."""
    ls = 0.5 * np.log(avar)
    lt = np.log(taus)
    out = np.empty_like(ls)
    out[1:-1] = (ls[2:] - ls[:-2]) / (lt[2:] - lt[:-2])
    out[0] = (ls[1] - ls[0]) / (lt[1] - lt[0])
    out[-1] = (ls[-1] - ls[-2]) / (lt[-1] - lt[-2])
    return out


def fixed_slope_value(
    taus: np.ndarray, avar: np.ndarray, edf: np.ndarray, slope: float, at: float
) -> float:
    """Weighted (2·edf) LS line of fixed slope in log-log, evaluated at τ = at."""
    w = 2.0 * edf
    ln_c = np.sum(w * (0.5 * np.log(avar) - slope * np.log(taus))) / np.sum(w)
    return float(np.exp(ln_c + slope * math.log(at)))


def gauss_markov_avar_reference(variance: float, correlation_time: float, tau: float) -> float:
    """Allan variance of a Gauss–Markov process by numeric integration of its PSD.

    ``σ²_A(τ) = 4 ∫₀^∞ S(f) sin⁴(πfτ)/(πfτ)² df`` with the two-sided PSD
    ``S(f) = 2q²T/(1 + (2πfT)²)``: independent of the closed form (no angle-increment algebra).
    """
    from scipy.integrate import quad

    def integrand(u: float) -> float:  # u = ln f
        f = math.exp(u)
        x = math.pi * f * tau
        s = 2.0 * variance * correlation_time / (1.0 + (2.0 * math.pi * f * correlation_time) ** 2)
        return 4.0 * s * math.sin(x) ** 4 / x**2 * f

    lo, hi = math.log(1e-6 / tau), math.log(10.0 / tau)
    # Up to 10/τ in ln f, split per decade (a few oscillations of sin⁴ each).
    edges = np.linspace(lo, hi, 8)
    total = sum(
        quad(integrand, a, b, limit=200, epsabs=0.0, epsrel=1e-11)[0]
        for a, b in zip(edges[:-1], edges[1:])
    )
    # Beyond: sin⁴x = 3/8 − cos(2x)/2 + cos(4x)/8, the cosine parts by QAWF (Fourier integrals).
    f_c = 10.0 / tau

    def g(f: float) -> float:
        s = 2.0 * variance * correlation_time / (1.0 + (2.0 * math.pi * f * correlation_time) ** 2)
        return 4.0 * s / (math.pi * f * tau) ** 2

    flat = quad(g, f_c, np.inf, epsabs=0.0, epsrel=1e-11, limit=200)[0]
    c2 = quad(lambda u: g(f_c + u), 0.0, np.inf, weight="cos", wvar=2.0 * math.pi * tau)[0]
    c4 = quad(lambda u: g(f_c + u), 0.0, np.inf, weight="cos", wvar=4.0 * math.pi * tau)[0]
    # cos(2π τ (f_c + u)) = cos(2πτu) since τ f_c = 10 is an integer (likewise for 4π).
    return total + 0.375 * flat - 0.5 * c2 + 0.125 * c4


def sensor_like_log(
    n: int,
    fs: float,
    *,
    arw: float,
    gm_sigma: float,
    gm_time: float,
    lsb: float,
    cutoff: float,
    seed: int,
) -> np.ndarray:
    """A static log of a real-sensor-like gyro: white rate noise through a 41-tap FIR low-pass
    (the sensor's anti-alias/decimation filter, unity DC gain so N is unchanged at long τ), a
    first-order Gauss–Markov bias (exact AR(1) sampling) and quantisation to ``lsb``."""
    from scipy import signal

    rng = np.random.default_rng(seed)
    white = rng.standard_normal(n + 200) * arw * math.sqrt(fs)
    taps = signal.firwin(41, cutoff, fs=fs)
    filtered = signal.lfilter(taps, 1.0, white)[200:]
    phi = math.exp(-1.0 / (fs * gm_time))
    e = rng.standard_normal(n) * gm_sigma * math.sqrt(1.0 - phi * phi)
    e[0] = rng.standard_normal() * gm_sigma
    gm = signal.lfilter([1.0], [1.0, -phi], e)
    return np.round((filtered + gm) / lsb) * lsb
