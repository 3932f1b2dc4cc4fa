"""Conservative (overbounding) coefficients: the LP against SciPy, the bound against SciPy's χ²,
and the overbound on simulated logs (Lethander & Taylor 2023)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import optimize, stats

import gyrobias
from gyrobias import _core

FLICKER = math.sqrt(2 * math.log(2) / math.pi)


def basis(taus: np.ndarray) -> np.ndarray:
    """The five-term model's basis g_j(τ) (NumPy, independent of the core)."""
    return np.column_stack(
        [3 / taus**2, 1 / taus, np.full_like(taus, FLICKER**2), taus / 3, taus**2 / 2]
    )


def linprog_reference(design: np.ndarray, bound: np.ndarray, floor: np.ndarray) -> float:
    """min Σ (A c)_i/b_i s.t. A c ≥ b, c ≥ floor with SciPy's HiGHS; returns the mean ratio."""
    a = design / bound[:, None]
    bounds = [(f, None) for f in floor]
    res = optimize.linprog(
        a.sum(axis=0), A_ub=-a, b_ub=-np.ones(len(bound)), bounds=bounds, method="highs"
    )
    assert res.status == 0
    return float(res.fun) / len(bound)


def test_lp_matches_scipy_linprog() -> None:
    rng = np.random.default_rng(7)
    for _ in range(60):
        n = int(rng.integers(3, 40))
        cols = sorted(rng.choice(5, size=int(rng.integers(1, 6)), replace=False))
        taus = np.sort(rng.uniform(-2, 4, size=n))
        taus = 10.0**taus
        design = np.ascontiguousarray(basis(taus)[:, cols])
        truth = 10.0 ** rng.uniform(-3, 1, size=len(cols))
        bound = design @ truth * rng.uniform(0.5, 2.0, size=n)
        floor = truth * rng.uniform(0.0, 1.0, size=len(cols)) * rng.integers(0, 2)
        got = _core.noise.overbound(design, bound, floor)
        # HiGHS solves to ~1e-9 relative; our simplex is exact up to rounding.
        assert got["objective"] == pytest.approx(linprog_reference(design, bound, floor), rel=1e-7)
        assert np.all(got["ratio"] >= 1.0)
        assert np.all(got["coefficients"] >= floor)


@settings(derandomize=True, max_examples=60, deadline=None)
@given(
    st.lists(st.floats(0.3, 3.0), min_size=4, max_size=25),
    st.sets(st.integers(0, 4), min_size=1, max_size=5),
)
def test_overbound_is_feasible_and_tighter_than_scaling(
    scales: list[float], cols: set[int]
) -> None:
    taus = np.geomspace(0.01, 1000.0, len(scales))
    design = np.ascontiguousarray(basis(taus)[:, sorted(cols)])
    bound = design.sum(axis=1) * np.asarray(scales)
    got = _core.noise.overbound(design, bound)
    model = design @ got["coefficients"]
    assert np.all(model >= bound)  # exact: the core rescales away rounding
    # Any feasible model, e.g. the all-ones model scaled up to touch the bound, is no tighter.
    ones = design.sum(axis=1)
    scaled = ones * np.max(bound / ones)
    assert got["objective"] <= np.mean(scaled / bound) * (1 + 1e-12)


def test_bad_lp_input_names_the_argument() -> None:
    with pytest.raises(ValueError, match="bound"):
        _core.noise.overbound(np.ones((2, 1)), np.array([1.0, -1.0]))
    with pytest.raises(ValueError, match="design"):
        _core.noise.overbound(np.array([[1.0], [0.0]]), np.ones(2))
    # A Fortran-ordered design is read in the right order (the binding copies it to C order).
    design = np.array([[1.0, 2.0], [0.5, 1.0], [0.25, 3.0]])
    c_order = _core.noise.overbound(design, np.ones(3))
    f_order = _core.noise.overbound(np.asfortranarray(design), np.ones(3))
    np.testing.assert_array_equal(c_order["coefficients"], f_order["coefficients"])


def _log(seed: int, n: int = 100_000) -> gyrobias.NoiseCoefficients:
    rate = gyrobias.noise.simulate(
        n, 100.0, arw=0.2 / 60, bias_instability=3 / 3600, rrw=30 / 216000, seed=seed
    )
    r = gyrobias.allan.adev(rate, 100.0, units="deg/s")
    return gyrobias.noise.fit(r, terms=("N", "B", "K"))


def test_upper_bound_is_the_one_sided_chi_square_bound() -> None:
    c = _log(3)
    cc = c.conservative(0.9)
    r = c.allan
    assert r is not None
    idx = np.searchsorted(r.taus, cc.taus)
    # Reference: U = σ² · edf / χ²_edf(1 − p) with SciPy's quantile and the analysis' own EDF.
    expect = r.avar[idx] * cc.edf / stats.chi2.ppf(0.1, cc.edf)
    np.testing.assert_allclose(cc.upper_bound**2, expect, rtol=1e-9)
    np.testing.assert_allclose(cc.edf, np.asarray(r.edf)[idx])


def test_conservative_overbounds_the_measured_bound_and_the_truth() -> None:
    true = [0.0, (0.2 / 60) ** 2, (3 / 3600) ** 2, (30 / 216000) ** 2, 0.0]
    covered = 0
    for seed in range(20):
        cc = _log(seed).conservative(0.95)
        model, _ = cc.coefficients.model(cc.taus)
        assert np.all(model >= cc.upper_bound)  # the defining property, at every τ used
        assert cc.margin >= 1.0
        assert all(f is None or f >= 1.0 for f in cc.inflation.values())
        truth, _ = _core.noise.model(true, np.ascontiguousarray(cc.taus))
        covered += bool(np.all(model**2 >= truth))
    # Each point's bound holds with probability 0.95; with these fixed seeds 19 of 20 sets lie
    # above the true curve at every τ (one falls below where the fit dropped K).
    assert covered >= 18


def test_conservative_on_real_sensor_like_data() -> None:
    """AR(1) (Gauss–Markov) drift that the five-term model does not contain: still overbounded."""
    rate = gyrobias.noise.simulate(150_000, 100.0, arw=0.3 / 60, ar1=(0.999, 2e-4), seed=11)
    r = gyrobias.allan.adev(rate, 100.0, units="deg/s")
    cc = gyrobias.noise.fit(r).conservative(0.95)
    model, _ = cc.coefficients.model(cc.taus)
    assert np.all(model >= cc.upper_bound)
    assert np.all(cc.upper_bound >= np.sqrt(r.avar[np.searchsorted(r.taus, cc.taus)]))
    text = cc.export("kalibr") if cc.coefficients.K.present else cc.export("matlab")
    assert "gyrobias" in text


def test_conservative_errors() -> None:
    ds = gyrobias.noise.from_datasheet(arw="0.3 deg/sqrt(h)")
    assert ds.gyro is not None
    with pytest.raises(ValueError, match="Allan curve"):
        ds.gyro.conservative()
    c = _log(1, 20_000)
    with pytest.raises(ValueError, match="confidence"):
        c.conservative(1.5)
    with pytest.raises(ValueError, match="terms"):
        c.conservative(terms=("X",))
    cc = c.conservative(terms=("N",))
    assert cc.coefficients.N.present and not cc.coefficients.B.present
    with pytest.raises(ValueError, match="floor"):
        _core.noise.overbound(np.ones((2, 1)), np.ones(2), np.array([-1.0]))
    assert "inflation" in cc.summary() and cc.to_dict()["confidence"] == 0.95
