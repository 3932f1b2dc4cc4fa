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


def fixed_slope_value(taus: np.ndarray, avar: np.ndarray, edf: np.ndarray, slope: float, at: float) -> float:
    """Weighted (2·edf) LS line of fixed slope in log-log, evaluated at τ = at."""
    w = 2.0 * edf
    ln_c = np.sum(w * (0.5 * np.log(avar) - slope * np.log(taus))) / np.sum(w)
    return float(np.exp(ln_c + slope * math.log(at)))
