"""NumPy reference of the Kaiser-window FIR design, written straight from [TS] eqs. 14–20 /
SPEC §7 (independent of the Rust core and of SciPy's firwin)."""

from __future__ import annotations

import math

import numpy as np


def kaiser_design(
    fs: float, fpass: float, fstop: float, apass: float, astop: float
) -> dict[str, object]:
    fc = 0.5 * (fpass + fstop)
    df = fstop - fpass
    dpass = (10 ** (apass / 20) - 1) / (10 ** (apass / 20) + 1)
    dstop = 10 ** (-astop / 20)
    a = -20 * math.log10(min(dpass, dstop))
    if a >= 50:
        alpha = 0.1102 * (a - 8.7)
    elif a > 21:
        alpha = 0.5842 * (a - 21) ** 0.4 + 0.07886 * (a - 21)
    else:
        alpha = 0.0
    d = (a - 7.95) / 14.36 if a > 21 else 0.922
    n = 1 + math.ceil(d * fs / df)
    if n % 2 == 0:
        n += 1
    m = (n - 1) // 2
    k = np.arange(n)
    w = np.i0(alpha * np.sqrt(k * (2 * m - k)) / m) / np.i0(alpha)
    wc = 2 * np.pi * fc / fs
    j = k - m
    with np.errstate(invalid="ignore", divide="ignore"):
        g = np.where(j == 0, wc / np.pi, np.sin(wc * j) / (np.pi * j))
    return {"A": a, "alpha": alpha, "N": n, "taps": w * g}
