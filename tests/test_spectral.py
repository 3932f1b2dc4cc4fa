"""Tests of gyrobias.spectral: LSSA ([TS] §2.2, SPEC §8) against astropy and a dense NumPy
reference, significance, known constituents, Welch PSD and noise density against SciPy."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.signal as ss
from astropy.timeseries import LombScargle
from hypothesis import example, given
from hypothesis import strategies as st
from numpy.testing import assert_allclose

import gyrobias
from gyrobias import spectral
from tests.reference_spectral import lssa as lssa_ref
from tests.reference_spectral import welch_hann


def irregular(n: int, seed: int, gap: bool = True) -> tuple[np.ndarray, np.ndarray]:
    """Unequally spaced times with a gap in the middle, two sinusoids plus noise."""
    rng = np.random.default_rng(seed)
    t = np.cumsum(rng.uniform(0.2, 1.8, n))
    if gap:
        t[n // 2 :] += 50.0
    y = 1.5 * np.sin(2 * np.pi * 0.1 * t) + 0.8 * np.cos(2 * np.pi * (1 / 3.7) * t + 0.3)
    return t, y + rng.normal(0.0, 1.0, n) + 4.0


# Tolerance for the agreement with astropy/the dense reference: a uniform grid uses a rotation
# recurrence re-seeded every 32 frequencies (≤ 32 roundings of cos/sin, ~1e-14), and the sums
# are accumulated in a different order (~n·ε relative to the largest terms).
ATOL = 1e-12


def conditioning_tolerance(t: np.ndarray, f: np.ndarray) -> np.ndarray:
    """Forward-error allowance of a normal-equation least-squares fit at each frequency.

    Both gyrobias and astropy solve the [1, cos, sin] fit through its normal equations, whose
    forward error grows like κ(A)²·ε. At frequencies with only a fraction of a cycle over the
    record, cos and sin are nearly collinear with the mean (κ ≈ 160 for 20 points over 0.13
    cycles: κ²ε ≈ 6e-12), and the two implementations are then each ~7e-13 from the exact
    value (checked at 50 digits with mpmath), in opposite directions.
    """
    kappa = np.array(
        [
            np.linalg.cond(
                np.c_[np.ones_like(t), np.cos(2 * np.pi * fk * t), np.sin(2 * np.pi * fk * t)]
            )
            for fk in f
        ]
    )
    return ATOL + kappa**2 * np.finfo(float).eps


@given(seed=st.integers(0, 2**32 - 1), n=st.integers(20, 400))
@example(seed=38894, n=20)  # issue 19 explore run: 1.4e-12 apart at f = 0.002 (κ = 160)
def test_equals_astropy_unequal_spacing(seed: int, n: int) -> None:
    t, y = irregular(n, seed)
    f = np.linspace(0.002, 0.5, 300)
    r = spectral.lssa(t, y, f)
    ref = LombScargle(t, y, fit_mean=True, center_data=True, normalization="standard").power(
        f, method="cython"
    )
    tolerance = conditioning_tolerance(t, f)
    worst = np.max(np.abs(r.spectrum - ref) / tolerance)
    assert worst <= 1.0, (
        f"gyrobias and astropy differ by {worst:.3g} times the conditioning allowance"
    )


def test_equals_astropy_weighted_and_irregular_grid() -> None:
    t, y = irregular(500, 11)
    dy = np.random.default_rng(2).uniform(0.5, 2.0, t.size)
    f = np.sort(
        np.random.default_rng(3).uniform(0.001, 0.4, 200)
    )  # non-uniform grid: direct sin/cos
    r = spectral.lssa(t, y, f, weights=1 / dy**2)
    ref = LombScargle(t, y, dy, fit_mean=True, center_data=True).power(f, method="cython")
    assert_allclose(r.spectrum, ref, rtol=0, atol=ATOL)


@pytest.mark.parametrize("trend", [False, True])
@pytest.mark.parametrize("periods", [(), (10.0,), (10.0, 37.0)])
@pytest.mark.parametrize("weighting", ["none", "weights", "cov"])
def test_equals_dense_reference(trend: bool, periods: tuple[float, ...], weighting: str) -> None:
    t, y = irregular(120, 5)
    y = y + 0.05 * t  # a trend to remove
    f = np.linspace(0.003, 0.45, 97)
    rng = np.random.default_rng(9)
    kw: dict[str, np.ndarray] = {}
    if weighting == "weights":
        kw["weights"] = rng.uniform(0.2, 3.0, t.size)
    elif weighting == "cov":
        # Exponentially correlated noise (Gauss–Markov), a common full covariance.
        d = np.abs(t[:, None] - t[None, :])
        kw["cov"] = 0.5 * np.exp(-d / 2.0) + 0.5 * np.eye(t.size)
    r = spectral.lssa(t, y, f, trend=trend, known_periods=periods, **kw)
    ref = lssa_ref(t, y, f, trend=trend, periods=periods, **kw)
    assert r.n_known == 1 + trend + 2 * len(periods)
    # Dense lstsq per frequency vs normal equations: conditioning of the design (trend and
    # low frequencies) costs a few digits; 1e-9 absolute on s ∈ [0, 1].
    assert_allclose(r.spectrum, ref, rtol=0, atol=1e-9)


def test_user_columns() -> None:
    t, y = irregular(150, 12)
    step = (t > t[70]).astype(float)  # a bias jump at a known epoch
    y = y + 3.0 * step
    cols = np.column_stack([step, np.cos(t / 40.0)])
    f = np.linspace(0.004, 0.45, 80)
    r = spectral.lssa(t, y, f, columns=cols, known_periods=[10.0])
    ref = lssa_ref(t, y, f, periods=(10.0,), columns=cols)
    assert r.n_known == 5
    assert_allclose(r.spectrum, ref, rtol=0, atol=1e-9)  # as test_equals_dense_reference
    assert r.known_params[3] == pytest.approx(3.0, abs=0.5)  # the step's height
    one = spectral.lssa(t, y, f, columns=step)
    assert_allclose(one.spectrum, lssa_ref(t, y, f, columns=step), rtol=0, atol=1e-9)
    with pytest.raises(ValueError, match="columns"):
        spectral.lssa(t, y, f, columns=np.ones(10))
    with pytest.raises(gyrobias.GyroLinAlgError, match="linearly dependent"):
        spectral.lssa(t, y, f, columns=np.ones(t.size))  # duplicates the bias


def test_diagonal_cov_equals_weights() -> None:
    t, y = irregular(80, 6)
    w = np.random.default_rng(1).uniform(0.5, 2.0, t.size)
    f = np.linspace(0.01, 0.4, 50)
    a = spectral.lssa(t, y, f, weights=w).spectrum
    b = spectral.lssa(t, y, f, cov=np.diag(1 / w)).spectrum
    assert_allclose(a, b, rtol=0, atol=1e-12)


def test_known_constituent_suppressed_without_shifting_peaks() -> None:
    t, y = irregular(600, 7)
    f = np.linspace(0.005, 0.45, 900)
    plain = spectral.lssa(t, y, f)
    known = spectral.lssa(t, y, f, known_periods=[10.0])
    near = np.abs(f - 0.1) < 0.003
    assert plain.spectrum[near].max() > 0.3
    # The 0.1 Hz constituent is fitted: nothing significant is left around it.
    assert known.spectrum[near].max() < known.critical_value
    # The 1/3.7 Hz peak is still significant, at the same frequency bin.
    other = np.abs(f - 1 / 3.7) < 0.01
    assert (
        plain.frequencies[other][np.argmax(plain.spectrum[other])]
        == known.frequencies[other][np.argmax(known.spectrum[other])]
    )
    assert known.spectrum[other].max() > plain.spectrum[other].max()  # larger share of the residual
    assert known.n_known == 3
    # The fitted known amplitude (cos, sin at t_ref) has the injected magnitude 1.5.
    assert np.hypot(*known.known_params[1:3]) == pytest.approx(1.5, abs=0.15)
    peaks = known.peaks()
    assert abs(f[peaks[0]] - 1 / 3.7) < 0.002


def test_critical_value_and_significance() -> None:
    assert gyrobias._core.spectral.critical_value(600, 1, 0.01) == pytest.approx(
        0.01530931, abs=5e-9
    )
    rng = np.random.default_rng(8)
    t = np.sort(rng.uniform(0, 500, 600))
    r = spectral.lssa(t, rng.normal(size=600), alpha=0.01)
    assert r.critical_value == pytest.approx(0.01530931, abs=5e-9)
    assert r.critical_db == pytest.approx(10 * np.log10(0.01530931 / (1 - 0.01530931)), abs=1e-6)
    # Pure noise: each spectral value exceeds s_crit with probability α = 1 % (Beta law);
    # ~300 frequencies → expect 3, allow up to 15 (binomial tail < 1e-6).
    assert r.significant.sum() <= 15
    assert_allclose(r.db, 10 * np.log10(r.spectrum / (1 - r.spectrum)))


def test_default_frequency_grid_and_regular_sampling() -> None:
    n, dt = 256, 0.01
    t = np.arange(n) * dt
    y = np.sin(2 * np.pi * 12.5 * t) + 0.1 * np.random.default_rng(0).normal(size=n)
    r = spectral.lssa(t, y)
    assert_allclose(r.frequencies, np.arange(1, (n - 1) // 2 + 1) / (n * dt))
    assert r.frequencies[np.argmax(r.spectrum)] == pytest.approx(12.5)
    # Regular sampling, Fourier frequencies: s equals the periodogram share of the variance.
    p = np.abs(np.fft.rfft(y - y.mean())) ** 2
    share = 2 * p[1 : (n - 1) // 2 + 1] / (n * np.sum((y - y.mean()) ** 2))
    assert_allclose(r.spectrum, share, atol=1e-12)


def test_nyquist_frequency_is_handled() -> None:
    t = np.arange(64.0)
    y = np.cos(np.pi * t) + np.random.default_rng(0).normal(size=64) * 0.01
    r = spectral.lssa(t, y, [0.25, 0.5])  # 0.5 = Nyquist: sin column vanishes
    assert 0.99 < r.spectrum[1] <= 1.0
    assert np.all(np.isfinite(r.spectrum))


def test_result_to_dict() -> None:
    t, y = irregular(100, 1)
    d = spectral.lssa(t, y, np.linspace(0.01, 0.4, 20)).to_dict()
    assert d["n"] == 100 and len(d["spectrum"]) == 20


def test_bad_lssa_input() -> None:
    t, y = irregular(50, 2)
    f = np.linspace(0.01, 0.4, 10)
    bad = t.copy()
    bad[[3, 4]] = bad[[4, 3]]
    with pytest.raises(ValueError, match="t.*unsorted"):
        spectral.lssa(bad, y, f)
    bad = t.copy()
    bad[4] = bad[3]
    with pytest.raises(ValueError, match="t.*duplicate"):
        spectral.lssa(bad, y, f)
    with pytest.raises(ValueError, match="freqs.*known period"):
        spectral.lssa(t, y, [0.05, 0.1], known_periods=[10.0])
    with pytest.raises(ValueError, match="t is too short"):
        spectral.lssa(t[:6], y[:6], f, trend=True, known_periods=[10.0])
    with pytest.raises(ValueError, match="freqs"):
        spectral.lssa(t, y, [0.0, 0.1])
    with pytest.raises(ValueError, match="weights"):
        spectral.lssa(t, y, f, weights=np.r_[0.0, np.ones(49)])
    with pytest.raises(ValueError, match="cov"):
        spectral.lssa(t, y, f, weights=np.ones(50), cov=np.eye(50))
    with pytest.raises(ValueError, match="cov"):
        spectral.lssa(t, y, f, cov=np.eye(49))
    with pytest.raises(gyrobias.GyroLinAlgError, match="positive definite"):
        spectral.lssa(t, y, f, cov=-np.eye(50))
    with pytest.raises(ValueError, match="y has"):
        spectral.lssa(t, y[:-1], f)
    with pytest.raises(ValueError, match="alpha"):
        spectral.lssa(t, y, f, alpha=1.5)
    with pytest.raises(ValueError, match="known_periods"):
        spectral.lssa(t, y, f, known_periods=[-3.0])
    ynan = y.copy()
    ynan[2] = np.nan
    with pytest.raises(ValueError, match="y .*index 2"):
        spectral.lssa(t, ynan, f)
    with pytest.raises(gyrobias.GyroLinAlgError, match="explained exactly"):
        spectral.lssa(t, np.full(50, 3.0), f)
    with pytest.raises(TypeError, match="t"):
        spectral.lssa(["a"] * 50, y, f)
    big = 4001
    with pytest.raises(ValueError, match="cov.*4000"):
        spectral.lssa(
            np.arange(big, dtype=float),
            np.random.default_rng(0).normal(size=big),
            [0.1],
            cov=np.zeros((big, big)),
        )


# --- PSD ---------------------------------------------------------------------------------------


@pytest.mark.parametrize("nperseg", [256, 255, 1024])
def test_psd_equals_scipy_welch(nperseg: int) -> None:
    x = np.random.default_rng(0).normal(size=10_000) + np.sin(np.arange(10_000) * 0.3)
    r = spectral.psd(x, 100.0, nperseg=nperseg)
    f, p = ss.welch(x, 100.0, window="hann", nperseg=nperseg, detrend="constant", scaling="density")
    assert_allclose(r.frequencies, f)
    assert_allclose(r.psd, p, rtol=1e-10, atol=1e-14)
    fr, pr = welch_hann(x, 100.0, nperseg)
    assert_allclose(r.psd, pr, rtol=1e-10, atol=1e-14)


def test_periodogram_boxcar() -> None:
    x = np.random.default_rng(1).normal(size=1000)
    r = spectral.psd(x, 50.0, nperseg=1000, noverlap=0, window="boxcar", units="deg/s")
    f, p = ss.periodogram(x, 50.0, detrend="constant")
    assert_allclose(r.psd, p, rtol=1e-10, atol=1e-15)
    # Parseval: the one-sided PSD integrates to the variance.
    assert np.sum(r.psd) * (f[1] - f[0]) == pytest.approx(np.var(x), rel=1e-12)
    assert r.to_dict()["unit"] == "deg/s"


def test_noise_density_of_white_noise() -> None:
    sigma, fs = 0.02, 100.0
    x = np.random.default_rng(2).normal(0.0, sigma, 400_000)
    nd = spectral.noise_density(x, fs, units="deg/s")
    # One-sided density σ√(2/fs); ~100 segments × ~800 bins averaged: relative error < 1 %.
    assert nd.density == pytest.approx(sigma * np.sqrt(2 / fs), rel=0.01)
    assert nd.arw == pytest.approx(sigma / np.sqrt(fs), rel=0.01)
    # The Allan deviation at τ = 1 s of white noise is N = σ/√fs (IEEE 952): same number.
    adev1 = gyrobias.adev(x, fs, taus=[1.0], confidence=None)
    assert nd.arw == pytest.approx(float(adev1.adev[0]), rel=0.05)


def test_bad_psd_input() -> None:
    x = np.ones(100)
    with pytest.raises(ValueError, match="x is too short"):
        spectral.psd(x, 10.0, nperseg=200)
    with pytest.raises(ValueError, match="noverlap"):
        spectral.psd(x, 10.0, nperseg=50, noverlap=50)
    with pytest.raises(ValueError, match="fs"):
        spectral.psd(x, -1.0)
    with pytest.raises(ValueError, match="window"):
        spectral.psd(x, 10.0, window="hamming")
    with pytest.raises(ValueError, match="band"):
        spectral.noise_density(np.random.default_rng(0).normal(size=1000), 10.0, band=(3.0, 9.0))
