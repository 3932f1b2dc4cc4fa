"""Dense NumPy references for the least-squares spectrum ([TS] eqs. 5–11, SPEC §8).

Each frequency is an explicit weighted least-squares fit of [Φ_K, cos ωt, sin ωt] with
``numpy.linalg.lstsq``; s(ω) is the drop of the weighted residual norm divided by the norm after
the known constituents alone. O(n²) per frequency with a covariance: small n only.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray


def known_design(
    t: NDArray[np.float64],
    trend: bool,
    periods: tuple[float, ...],
    columns: NDArray[np.float64] | None = None,
) -> NDArray[np.float64]:
    cols = [np.ones_like(t)]
    if trend:
        cols.append(t - t.mean())
    for p in periods:
        cols += [np.cos(2 * np.pi * t / p), np.sin(2 * np.pi * t / p)]
    if columns is not None:
        cols += list(np.asarray(columns).reshape(t.size, -1).T)
    return np.column_stack(cols)


def lssa(
    t: NDArray[np.float64],
    y: NDArray[np.float64],
    freqs: NDArray[np.float64],
    *,
    weights: NDArray[np.float64] | None = None,
    cov: NDArray[np.float64] | None = None,
    trend: bool = False,
    periods: tuple[float, ...] = (),
    columns: NDArray[np.float64] | None = None,
) -> NDArray[np.float64]:
    if cov is not None:
        white = np.linalg.inv(np.linalg.cholesky(cov))
    else:
        w = np.ones_like(t) if weights is None else weights
        white = np.diag(np.sqrt(w))
    phi_k = white @ known_design(t, trend, periods, columns)
    yw = white @ y
    base = yw - phi_k @ np.linalg.lstsq(phi_k, yw, rcond=None)[0]
    q0 = base @ base
    out = np.empty(freqs.size)
    for j, f in enumerate(freqs):
        a = np.column_stack(
            [phi_k, white @ np.cos(2 * np.pi * f * t), white @ np.sin(2 * np.pi * f * t)]
        )
        r = yw - a @ np.linalg.lstsq(a, yw, rcond=None)[0]
        out[j] = (q0 - r @ r) / q0
    return out


def welch_hann(
    x: NDArray[np.float64], fs: float, nperseg: int
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Welch PSD with 50 % overlap and a periodic Hann window, by explicit numpy.fft."""
    step = nperseg - nperseg // 2
    nseg = (x.size - nperseg // 2) // step
    w = 0.5 - 0.5 * np.cos(2 * np.pi * np.arange(nperseg) / nperseg)
    acc = np.zeros(nperseg // 2 + 1)
    for s in range(nseg):
        seg = x[s * step : s * step + nperseg]
        acc += np.abs(np.fft.rfft((seg - seg.mean()) * w)) ** 2
    p = acc / (fs * (w**2).sum() * nseg)
    p[1 : (nperseg + 1) // 2] *= 2
    return np.fft.rfftfreq(nperseg, 1 / fs), p
