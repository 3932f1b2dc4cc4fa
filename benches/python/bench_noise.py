"""Timing of gyrobias.noise: simulation of an 8 h, 100 Hz, 3-axis log and the coefficient fits.

Baseline: the same white + flicker + random-walk series built with NumPy (white and random walk)
and allantools' pink-noise generator (``allantools.noise.pink``, 1/f by FFT shaping). The issue
sets no speed target; the ratios are printed for information.

Run: ``PYTHONPATH=python python benches/python/bench_noise.py``
"""

from __future__ import annotations

import numpy as np
from _timing import best_of

import gyrobias

FS = 100.0
N = 8 * 3600 * 100
TRUE = {"arw": 0.2 / 60.0, "bias_instability": 3.0 / 3600.0, "rrw": 10.0 / 216000.0}


def best(fn, repeats: int = 3) -> float:
    return best_of(fn, repeats)


def baseline() -> np.ndarray:
    import allantools

    rng = np.random.default_rng(0)
    out = np.empty((N, 3))
    for a in range(3):
        white = TRUE["arw"] * np.sqrt(FS) * rng.standard_normal(N)
        walk = np.cumsum(TRUE["rrw"] / np.sqrt(FS) * rng.standard_normal(N))
        pink = np.asarray(allantools.noise.pink(N)) * TRUE["bias_instability"]  # unscaled PSD level
        out[:, a] = white + walk + pink
    return out


def main() -> None:
    t_sim = best(lambda: gyrobias.noise.simulate(N, FS, axes=3, seed=1, **TRUE))
    try:
        t_base = best(baseline, repeats=1)
    except ImportError:
        t_base = float("nan")
    rate = gyrobias.noise.simulate(N, FS, axes=3, seed=1, **TRUE)
    results = gyrobias.allan.adev(rate, FS, confidence=None, units="deg/s")
    t_joint = best(lambda: gyrobias.noise.fit(results))
    t_ieee = best(lambda: gyrobias.noise.fit(results, method="ieee"))
    print(
        f"simulate 8 h × 3 axes @ 100 Hz: gyrobias {t_sim:.2f} s, NumPy+allantools {t_base:.2f} s "
        f"(ratio {t_base / t_sim:.1f}x; no target in the issue)"
    )
    print(
        f"joint fit, 3 axes: {t_joint * 1e3:.1f} ms; IEEE read-off, 3 axes: {t_ieee * 1e3:.1f} ms"
    )
    # A dense τ grid: every τ of a 2050-sample record (1025 points; the fit's cost is the
    # n × n correlation of the estimates, O(n²) spectral integrals) against the octave grid of
    # the same record as the same-run baseline. Before the blocked kernel and the shared
    # correlation matrix (commit 8d06cac) the dense fit took 3.3–4.1 s, 8.4–9.8 s with
    # auto_range=False (0.24 s and 0.8 s after; alternating runs, 2 cores at load ≈ 3.5).
    short = np.ascontiguousarray(rate[:2050, 0])
    dense = gyrobias.allan.adev(short, FS, taus="all", confidence=None, units="deg/s")
    octave = gyrobias.allan.adev(short, FS, confidence=None, units="deg/s")
    t_dense = best(lambda: gyrobias.noise.fit(dense))
    t_all_points = best(lambda: gyrobias.noise.fit(dense, auto_range=False))
    t_octave = best(lambda: gyrobias.noise.fit(octave))
    print(
        f"joint fit, all {len(dense.taus)} τ of 2050 samples: {t_dense * 1e3:.0f} ms "
        f"({t_all_points * 1e3:.0f} ms with auto_range=False) = {t_dense / t_octave:.0f}x the "
        f"octave grid's {t_octave * 1e3:.1f} ms ({len(octave.taus)} τ)"
    )
    explorer_fit()


def explorer_fit() -> None:
    """The explorer's fit of a 10⁶ × 6 log (``explore/state.py``: octave ADEV with 68.3 %
    intervals, the joint fit of the six curves, their conservative sets), against the ADEV
    computation it follows, measured in the same run (printed for information, like the rest of
    this file: the ADEV kernels change too). Before the variance limit cached its χ² quantiles
    (issue 35) the six fits took 54-79 ms where they take 22-37 ms after (same-run A/B, 2 cores
    at load ≈ 4)."""
    x = np.random.default_rng(0).standard_normal((1_000_000, 6))
    units = ["deg/s"] * 3 + ["m/s^2"] * 3

    def curves() -> tuple:
        return gyrobias.allan.adev(x, FS, taus="octave", confidence=0.683, units=units)

    results = list(curves())
    kw = {"method": "joint", "terms": ["Q", "N", "B", "K", "R"], "lines": "auto"}
    t_adev = best(curves, 5)
    t_fit = best(lambda: gyrobias.noise.fit(results, **kw), 7)
    fits = gyrobias.noise.fit(results, **kw)
    t_cons = best(lambda: [c.conservative(0.95) for c in fits], 7)
    print(
        f"explorer fit of 6 octave curves (10⁶ × 6): {t_fit * 1e3:.1f} ms = "
        f"{t_fit / t_adev:.2f}x the ADEV's {t_adev * 1e3:.0f} ms; "
        f"conservative() of the six {t_cons * 1e3:.1f} ms"
    )


if __name__ == "__main__":
    main()
