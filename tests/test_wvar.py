"""gyrobias.noise.wvar: the Haar wavelet variance, classical and robust, with intervals
(issue 26, item 4), against NumPy/SciPy references."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from gyrobias import _core, allan, noise

from .reference_lines import (
    biweight_efficiency,
    haar_coefficients,
    oavar,
    rho,
    robust_variance,
    wvar_classical,
)


def test_classical_matches_numpy_with_eta3_intervals() -> None:
    rate = noise.simulate(5000, 100.0, arw=0.01, rrw=1e-4, seed=2)
    w = noise.wvar(rate, 100.0, confidence=0.9, units="deg/s")
    assert isinstance(w, noise.WaveletVariance)
    levels = int(np.floor(np.log2(rate.size))) - 1  # the R wv package's J
    assert list(w.levels) == list(range(1, levels + 1))
    ref = wvar_classical(rate, levels, 0.9)
    np.testing.assert_allclose(w.variance, ref["variance"], rtol=1e-10)
    np.testing.assert_allclose(w.edf, ref["edf"], rtol=1e-12)
    # The chi-square quantiles: the core's against SciPy's (1e-9 relative).
    np.testing.assert_allclose(w.ci_low, ref["ci_low"], rtol=1e-8)
    np.testing.assert_allclose(w.ci_high, ref["ci_high"], rtol=1e-8)
    np.testing.assert_allclose(w.scales, 2.0 ** np.arange(1, levels + 1) / 100.0)
    assert w.to_dict()["unit"] == "(deg/s)^2"


def test_classical_is_half_the_overlapping_allan_variance() -> None:
    rate = noise.simulate(3000, 50.0, arw=0.02, bias_instability=0.01, seed=5)
    w = noise.wvar(rate, 50.0)
    for j, v in zip(w.levels, w.variance):
        m = 2 ** (int(j) - 1)
        assert 2.0 * v == pytest.approx(oavar(rate, m), rel=1e-9)
    a = allan.adev(rate, 50.0, taus=w.scales / 2.0, confidence=None)
    np.testing.assert_allclose(2.0 * w.variance, a.avar, rtol=1e-9)  # type: ignore[union-attr]


@pytest.mark.parametrize("efficiency", [0.3, 0.6, 0.9])
def test_robust_solves_its_estimating_equation(efficiency: float) -> None:
    rng = np.random.default_rng(11)
    rate = rng.standard_normal(4096)
    rate[::397] += 30.0 * rng.standard_normal(rate[::397].size)
    w = noise.wvar(rate, 1.0, robust=True, efficiency=efficiency, levels=5)
    c = _core.noise.biweight_constant(efficiency)
    # The constant gives the requested efficiency (SciPy quadrature of D²/(2 Var ρ)).
    assert biweight_efficiency(c) == pytest.approx(efficiency, rel=1e-8)
    for j, v in zip(w.levels, w.variance):
        coeffs = haar_coefficients(rate, int(j))
        assert v == pytest.approx(robust_variance(coeffs, c), rel=1e-9)
        # and the equation itself holds at the estimate
        z = np.linspace(-8.0, 8.0, 2_000_001)
        a = float(np.trapezoid(rho(z, c) * np.exp(-z * z / 2), z)) / np.sqrt(2 * np.pi)
        assert float(np.mean(rho(coeffs / np.sqrt(v), c))) == pytest.approx(a, rel=1e-4)
    # Intervals use efficiency × η₃ degrees of freedom.
    classical = noise.wvar(rate, 1.0, levels=5)
    np.testing.assert_allclose(w.edf, efficiency * classical.edf, rtol=1e-12)  # type: ignore[union-attr]


def test_robust_resists_outliers_where_the_classical_does_not() -> None:
    # 100σ spikes on 0.05 % of the samples (one every 2000): the classical estimate is ~5.8×
    # too high at every level; the robust one stays within 5 % up to filter width 32 and 20 %
    # up to 128 (where 6 % of the coefficients contain a spike; its breakdown shows beyond:
    # at one spike per filter width no M-estimator can tell the spikes from the noise).
    clean = noise.simulate(40_000, 100.0, arw=0.05, seed=9)
    spiky = clean.copy()
    spiky[::2000] += 50.0
    c0 = noise.wvar(clean, 100.0, levels=7)
    c1 = noise.wvar(spiky, 100.0, levels=7)
    r1 = noise.wvar(spiky, 100.0, robust=True, levels=7)
    ratio_classical = c1.variance / c0.variance  # type: ignore[union-attr]
    ratio_robust = r1.variance / c0.variance  # type: ignore[union-attr]
    assert np.all(ratio_classical > 4.0)
    assert np.all(np.abs(ratio_robust[:5] - 1.0) < 0.05)
    assert np.all(np.abs(ratio_robust - 1.0) < 0.2)
    # The clean-data value lies inside the robust 95 % interval at every level.
    assert np.all((r1.ci_low <= c0.variance) & (c0.variance <= r1.ci_high))  # type: ignore[union-attr]


@settings(max_examples=25)
@given(
    n=st.integers(16, 600),
    seed=st.integers(0, 2**32 - 1),
    scale=st.floats(1e-3, 1e3),
)
def test_property_classical_equals_numpy_and_robust_is_scale_equivariant(
    n: int, seed: int, scale: float
) -> None:
    x = np.random.default_rng(seed).standard_normal(n)
    w = noise.wvar(x, 1.0)
    ref = wvar_classical(x, int(np.floor(np.log2(n))) - 1, 0.95)
    np.testing.assert_allclose(w.variance, ref["variance"], rtol=1e-9, atol=1e-15)  # type: ignore[union-attr]
    r1 = noise.wvar(x, 1.0, robust=True)
    r2 = noise.wvar(scale * x, 1.0, robust=True)
    np.testing.assert_allclose(r2.variance, scale**2 * r1.variance, rtol=1e-8)  # type: ignore[union-attr]


def test_bad_input_names_the_argument() -> None:
    x = np.random.default_rng(0).standard_normal(100)
    for eff in (0.0, 1.0, -0.5, 1.5):
        with pytest.raises(ValueError, match="efficiency"):
            noise.wvar(x, 1.0, robust=True, efficiency=eff)
    with pytest.raises(ValueError, match="robust"):
        noise.wvar(x[:10], 1.0, robust=True)
    with pytest.raises(ValueError, match="levels"):
        noise.wvar(x, 1.0, levels=10)
    with pytest.raises(ValueError, match="confidence"):
        noise.wvar(x, 1.0, confidence=1.0)
    with pytest.raises(ValueError, match="data"):
        noise.wvar([1.0, np.nan, 2.0, 3.0], 1.0)


def test_plot_draws_the_deviation_and_interval() -> None:
    matplotlib = pytest.importorskip("matplotlib")
    matplotlib.use("Agg")
    w = noise.wvar(noise.simulate(4096, 100.0, arw=0.01, seed=1), 100.0, units="deg/s")
    ax = w.plot()  # type: ignore[union-attr]
    assert ax.get_xscale() == "log" and "deg/s" in ax.get_ylabel()
