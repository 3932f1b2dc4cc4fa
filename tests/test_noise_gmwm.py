"""GMWM (issue 11 item 4): wavelet variance, estimates, selection, uncertainties, bad input."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from gyrobias import noise
from gyrobias.allan import AllanResult, adev

FS = 100.0
TRUE = {"arw": 0.2 / 60.0, "bias_instability": 3.0 / 3600.0, "rrw": 10.0 / 216000.0}


def _haar_wavelet_variance(y: np.ndarray, half: int) -> float:
    """NumPy reference: MODWT Haar coefficients (ȳ_after − ȳ_before)/2 over all positions."""
    c = np.concatenate([[0.0], np.cumsum(y - y.mean())])
    w = (c[2 * half :] - 2.0 * c[half:-half] + c[: -2 * half]) / (2.0 * half)
    return float(np.mean(w**2))


def test_wavelet_variance_matches_numpy_and_is_half_the_allan_variance() -> None:
    rate = noise.simulate(50_000, FS, arw=0.01, rrw=1e-4, seed=1)
    c = noise.gmwm(rate, FS, terms=("N", "K"))
    assert isinstance(c, noise.NoiseCoefficients) and c.allan is not None
    for tau, avar in zip(c.allan.taus, c.allan.avar):
        half = int(round(tau * FS))
        assert avar / 2.0 == pytest.approx(_haar_wavelet_variance(rate, half), rel=1e-9)
    r = adev(rate, FS, taus=c.allan.taus, confidence=None)
    assert isinstance(r, AllanResult)
    np.testing.assert_allclose(c.allan.avar, r.avar, rtol=1e-9)
    # Every scale wvar gives (filter width 2m ≤ n/2, the R wv package's levels); the automatic
    # selection then decides which the estimate uses.
    assert c.allan.taus[-1] * FS <= 50_000 / 4


def test_gmwm_agrees_with_the_joint_fit_on_clean_logs() -> None:
    rate = noise.simulate(1_000_000, FS, seed=2, **TRUE)
    g = noise.gmwm(rate, FS, terms=("N", "B", "K"), units="deg/s")
    j = noise.fit(adev(rate, FS, units="deg/s"), terms=("N", "B", "K"))
    assert isinstance(g, noise.NoiseCoefficients)
    assert g.method == "gmwm" and g.diagnostics is not None and g.diagnostics.passed
    for s in ("N", "B", "K"):
        a, b = g[s], j[s]
        assert a.value is not None and b.value is not None
        # Same data: the two estimates differ by less than their combined uncertainty × 3.
        assert abs(a.value - b.value) < 3 * math.hypot(a.uncertainty or 0, b.uncertainty or 0), s
    truth = {"N": TRUE["arw"], "B": TRUE["bias_instability"], "K": TRUE["rrw"]}
    for s, v in truth.items():
        t = g[s]
        assert t.value is not None and abs(t.value - v) < 4 * (t.uncertainty or 0), s


def test_gmwm_gauss_markov_and_selection() -> None:
    t = 10.0
    phi = math.exp(-1.0 / (FS * t))
    rate = noise.simulate(
        400_000, FS, arw=0.01, ar1=(phi, 0.003 * math.sqrt(1 - phi * phi)), seed=3
    )
    c = noise.gmwm(rate, FS, terms=("N", "GM"), units="deg/s")
    assert isinstance(c, noise.NoiseCoefficients)
    gm = c.gauss_markov[0]
    assert gm.present
    assert abs(gm.sigma.value - 0.003) < 3 * gm.sigma.uncertainty
    assert abs(gm.correlation_time.value - t) < 3 * gm.correlation_time.uncertainty
    # Selection among sub-models of (N, B, K, GM): white + GM is what the data are; B and K
    # either drop out or come out insignificant.
    s = noise.gmwm(rate, FS, terms=("N", "B", "K", "GM"), units="deg/s", select=True)
    assert isinstance(s, noise.NoiseCoefficients)
    assert s.N.present and s.gauss_markov[0].present
    for sym in ("B", "K"):
        term = s[sym]
        assert not term.present or term.value < 2.5 * (term.uncertainty or 0)


def test_gmwm_bootstrap_uncertainty_is_close_to_asymptotic() -> None:
    rate = noise.simulate(100_000, FS, arw=0.01, rrw=2e-4, seed=4)
    a = noise.gmwm(rate, FS, terms=("N", "K"))
    b = noise.gmwm(rate, FS, terms=("N", "K"), bootstrap=40, seed=1)
    assert isinstance(a, noise.NoiseCoefficients) and isinstance(b, noise.NoiseCoefficients)
    assert a.N.value == b.N.value  # the estimate itself does not change
    # 40 replicates estimate a standard deviation to ±11 % (1σ); a factor 1.5 is ~4σ.
    for s in ("N", "K"):
        ua, ub = a[s].uncertainty, b[s].uncertainty
        assert ua is not None and ub is not None
        assert 1 / 1.5 < ub / ua < 1.5, (s, ua, ub)
    again = noise.gmwm(rate, FS, terms=("N", "K"), bootstrap=40, seed=1)
    assert isinstance(again, noise.NoiseCoefficients)
    assert again.N.uncertainty == b.N.uncertainty


@settings(max_examples=10)
@given(arw=st.floats(1e-3, 1.0), seed=st.integers(0, 2**32))
def test_gmwm_white_noise_property(arw: float, seed: int) -> None:
    rate = noise.simulate(20_000, FS, arw=arw, seed=seed)
    c = noise.gmwm(rate, FS, terms=("N",))
    assert isinstance(c, noise.NoiseCoefficients)
    # m = 1 alone carries EDF ≈ 30 000: 3 % is many standard deviations.
    assert c.N.value == pytest.approx(arw, rel=0.03)


def test_gmwm_multi_axis_and_bad_input() -> None:
    rate = noise.simulate(20_000, FS, arw=0.01, axes=2, seed=5)
    out = noise.gmwm(rate, FS, terms=("N",), axis_names=["x", "y"], units="deg/s")
    assert isinstance(out, tuple) and [c.axis for c in out] == ["x", "y"]
    with pytest.raises(ValueError, match="constant"):
        noise.gmwm(np.ones(1000), FS)
    with pytest.raises(ValueError, match="scales"):
        noise.gmwm(rate[:40, 0], FS, terms=("Q", "N", "B", "K"))
    with pytest.raises(ValueError, match="terms"):
        noise.gmwm(rate[:, 0], FS, terms=("N", "X"))
    with pytest.raises(ValueError, match="data"):
        noise.gmwm(np.array([1.0, np.nan] * 100), FS)
    with pytest.raises(ValueError, match="bootstrap"):
        noise.gmwm(rate[:, 0], FS, bootstrap=-1)
    original = rate.copy()
    noise.gmwm(rate, FS, terms=("N",))
    np.testing.assert_array_equal(rate, original)


def test_gmwm_selection_labels_dropped_terms() -> None:
    """A requested term that the model selection leaves out is reported as dropped by the
    selection (with the chosen sub-model), not as set to zero by the non-negative fit."""
    rate = noise.simulate(200_000, FS, arw=0.01, seed=11)  # white noise only
    s = noise.gmwm(rate, FS, terms=("N", "K", "GM"), units="deg/s", select=True)
    assert isinstance(s, noise.NoiseCoefficients)
    assert s.N.present
    reasons = [s["K"].missing] if not s["K"].present else []
    if not s.gauss_markov[0].present:
        reasons.append(s.gauss_markov[0].missing)
    assert reasons, "white noise alone: the selection must drop K or GM"
    for why in reasons:
        assert why is not None and "model selection" in why and "non-negative" not in why, why
