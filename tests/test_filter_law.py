"""A sensor's anti-alias/decimation filter at short τ (issue 26: GMWM and the joint fit on
filtered logs within their uncertainty of the truth).

The law ``σ²(τ) = N²/τ·(1 − 3τ_c/τ)`` for white noise through a filter (``gyrocore::noise::fit``,
"Sensor filter") is checked against the exact Allan variance computed here from the filter's
autocovariance (independent of the core); the fits are checked on simulated filtered logs.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import signal

import gyrobias
from gyrobias import noise

FS = 100.0
ARW = 0.2 / 60
BIAS = 3 / 3600
RRW = 10 / 216000


def exact_filtered_white_avar(taps: np.ndarray, m: int) -> float:
    """Allan variance of unit white noise through the FIR ``taps`` at averaging factor m, from
    its autocovariance r(k) = Σ_i h_i h_{i+k}: [Var S_m − Cov(S_m, S'_m)]/m² with S_m a sum of
    m consecutive samples and S'_m the next one (no approximation)."""
    r = np.correlate(taps, taps, "full")
    lag = np.arange(-(taps.size - 1), taps.size)

    def acov(j: np.ndarray) -> np.ndarray:
        return np.interp(j, lag, r, left=0.0, right=0.0)

    j = np.arange(-m + 1, m)
    var = np.sum((m - np.abs(j)) * acov(j))
    k = np.arange(1, 2 * m)
    cov = np.sum((m - np.abs(k - m)) * acov(k))
    return float((var - cov) / m**2)


def correlation_time(taps: np.ndarray, t0: float) -> float:
    """τ_c = t0·Σ_{k≥1} k·r(k)/Σ_k r(k) of the filtered white noise."""
    r = np.correlate(taps, taps, "full")[taps.size - 1 :]
    s0 = r[0] + 2.0 * r[1:].sum()
    return float(t0 * np.sum(np.arange(r.size) * r) / s0)


def _log(seed: int, taps: np.ndarray | None, n: int = 360_000) -> np.ndarray:
    rate = np.asarray(noise.simulate(n, FS, arw=ARW, bias_instability=BIAS, rrw=RRW, seed=seed))
    return rate if taps is None else signal.lfilter(taps, 1.0, rate)


FIR31 = signal.firwin(31, 40.0, fs=FS)
MA4 = np.ones(4) / 4


@pytest.mark.parametrize("taps", [FIR31, MA4], ids=["fir31", "ma4"])
def test_the_law_is_exact_beyond_the_filter_length(taps: np.ndarray) -> None:
    # Unit white noise at t0 = 1 has N² = (Σh)² = 1.
    tc = correlation_time(taps, 1.0)
    for m in range(taps.size, 4 * taps.size):
        law = (1.0 / m) * (1.0 - 3.0 * tc / m)
        assert exact_filtered_white_avar(taps, m) == pytest.approx(law, rel=1e-12)
    # ... and not inside it: there the filter's curve departs from the law (MA4 at m = 2: 3×).
    assert exact_filtered_white_avar(MA4, 2) == pytest.approx(3 * 0.5 * (1 - 3 * 0.625 / 2))


@settings(max_examples=25, deadline=None)
@given(taps=st.lists(st.floats(0.05, 1.0), min_size=2, max_size=12))
def test_the_law_holds_for_any_fir(taps: list[float]) -> None:
    # Property: for any FIR with positive DC gain, normalised to unity, the exact Allan variance
    # beyond its length is (1/m)(1 − 3τ_c/m); a low-pass (positive taps) has τ_c > 0.
    h = np.asarray(taps) / np.sum(taps)
    tc = correlation_time(h, 1.0)
    assert tc > 0.0
    for m in (h.size, h.size + 1, 2 * h.size + 3):
        assert exact_filtered_white_avar(h, m) == pytest.approx((1 - 3 * tc / m) / m, rel=1e-10)


@pytest.mark.parametrize("taps", [FIR31, MA4], ids=["fir31", "ma4"])
@pytest.mark.parametrize("estimator", ["fit", "gmwm"])
def test_n_within_its_uncertainty_on_filtered_logs(taps: np.ndarray, estimator: str) -> None:
    # 1 h at 100 Hz through a 31-tap FIR (cut-off 0.8 Nyquist) or a 4-tap moving average (the
    # case where GMWM used to collapse to B alone). Six logs each: N within 3 standard
    # uncertainties of the truth in every one (a 3σ bound fails a correct estimator with
    # probability 0.3 % per log; measured over 30 logs: |z| < 2 in 93–97 %, all < 3), the
    # filter reported with its correlation time within 3σ of the filter's own, Q not invented.
    true_tc = correlation_time(taps, 1 / FS)
    for seed in range(6):
        rate = _log(2000 + seed, taps)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            c = (
                noise.gmwm(rate, FS, terms=("N", "B", "K"), units="deg/s")
                if estimator == "gmwm"
                else noise.fit(gyrobias.allan.avar(rate, FS, units="deg/s"), terms=("N", "B", "K"))
            )
        assert c.N.value is not None and c.N.uncertainty is not None
        assert abs(c.N.value - ARW) < 3 * c.N.uncertainty, (seed, c.N)
        assert c.B.value is not None
        d = c.diagnostics
        assert d is not None and d.filter_correlation_time is not None
        tc = d.filter_correlation_time
        assert tc.unit == "s" and tc.value is not None and tc.uncertainty is not None
        assert abs(tc.value - true_tc) < 3 * tc.uncertainty + 0.1 * true_tc, (seed, tc, true_tc)
        assert any("filter" in e[2] for e in d.excluded)


def test_unfiltered_logs_see_no_filter() -> None:
    for seed in range(4):
        rate = _log(3000 + seed, None)
        c = noise.fit(gyrobias.allan.avar(rate, FS, units="deg/s"), terms=("N", "B", "K"))
        assert c.diagnostics is not None and c.diagnostics.filter_correlation_time is None
        assert c.N.value is not None and c.N.uncertainty is not None
        assert abs(c.N.value - ARW) < 3 * c.N.uncertainty


def test_without_the_filter_term_n_is_biased() -> None:
    # What the term is for: on the same filtered logs, a fit on the points beyond the filter's
    # visible bend (τ ≥ 0.04 s) but without the term is biased low by ≈ 3τ_c/(2τ) at its first
    # points, beyond its uncertainty on average.
    z = []
    for seed in range(6):
        rate = _log(2000 + seed, FIR31)
        a = gyrobias.allan.avar(rate, FS, units="deg/s")
        c = noise.fit(a, terms=("N", "B", "K"), tau_range=(0.04, 700.0))
        assert c.N.value is not None and c.N.uncertainty is not None
        z.append((c.N.value - ARW) / c.N.uncertainty)
    assert np.mean(z) < -1.0


def test_the_model_curve_includes_the_filter() -> None:
    rate = _log(2001, MA4)
    c = noise.fit(gyrobias.allan.avar(rate, FS, units="deg/s"), terms=("N", "B", "K"))
    tc = c.diagnostics.filter_correlation_time  # type: ignore[union-attr]
    assert tc is not None and tc.value is not None
    t = np.array([0.05, 0.1, 1.0])
    total, parts = c.model(t)
    n2 = c.to("base").N.value ** 2  # type: ignore[operator]
    expected = parts["N"] ** 2 + parts["B"] ** 2 + parts["K"] ** 2 - 3 * n2 * tc.value / t**2
    np.testing.assert_allclose(total**2, expected, rtol=1e-12)
    assert c.Q.value is None and c.Q.missing == "not requested"
