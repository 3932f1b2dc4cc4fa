"""Upper bounds of noise terms the Allan curve does not show (issue 26 item 2).

Reference: the bound recomputed in SciPy from the fit's own points and EDF,
``√min_i (σ̂²_i·edf_i/χ²_{edf_i}(α) / g(τ_i))``; a hypothesis property of the core function;
and a Monte Carlo check of its coverage on simulated logs whose K is known but invisible.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy import stats

import gyrobias
from gyrobias import _core

FS = 100.0
FLICKER = gyrobias.noise.FLICKER_FACTOR
BASIS = {
    "Q": lambda t: 3.0 / t**2,
    "N": lambda t: 1.0 / t,
    "B": lambda t: FLICKER**2 + 0.0 * t,
    "K": lambda t: t / 3.0,
    "R": lambda t: t**2 / 2.0,
}


def _short_log(seed: int, rrw: float = 1e-5, n: int = 60_000) -> gyrobias.allan.AllanResult:
    rate = gyrobias.noise.simulate(
        n, FS, arw=0.2 / 60, bias_instability=3 / 3600, rrw=rrw, seed=seed
    )
    r = gyrobias.allan.adev(rate, FS, units="deg/s")
    assert isinstance(r, gyrobias.allan.AllanResult)
    return r


def test_bound_matches_a_scipy_recomputation() -> None:
    r = _short_log(4)
    c = gyrobias.noise.fit(r)
    raw = _core.noise.fit(
        r.taus, r.avar, r.m, r.n_terms, r.overlapping, r.edf, list("QNBKR"), None, None, True
    )
    used = np.asarray(raw["used"], dtype=np.int64)
    edf = np.asarray(raw["edf"], dtype=np.float64)
    taus = r.taus[used]
    u2 = r.avar[used] * edf / stats.chi2.ppf(0.05, edf)
    bounded = [t for t in c.terms if t.bounded]
    assert {t.symbol for t in bounded} >= {"K"}, c.summary()
    for t in bounded:
        expect = math.sqrt(float(np.min(u2 / BASIS[t.symbol](taus))))
        # SciPy's and the core's chi-square quantiles agree to ~1e-13 relative.
        assert t.upper_bound == pytest.approx(expect, rel=1e-10), t.symbol
        assert t.bound_confidence == 0.95
        assert t.bound_reason is not None and "held at zero" in t.bound_reason
    # Identified terms carry no bound; unit conversion scales the bound like a value.
    assert c.N.upper_bound is None and not c.N.bounded
    k = c.K.to("deg/h^1.5")
    assert k.upper_bound == pytest.approx(c.K.upper_bound * 3600**1.5, rel=1e-12)
    assert "≤" in str(c.K) and "95 % upper bound" in str(c.K)
    assert "upper bound" in c.summary()
    assert c.K.to_dict()["upper_bound"] == c.K.upper_bound


def test_read_off_bounds_what_it_does_not_find() -> None:
    r = _short_log(5)
    c = gyrobias.noise.fit(r, method="ieee")
    missing = [t for t in c.terms if t.value is None]
    assert missing and all(t.bounded for t in missing), c.summary()


def test_terms_not_requested_are_not_bounded() -> None:
    c = gyrobias.noise.fit(_short_log(6), terms=("N", "B"))
    assert c.K.value is None and c.K.upper_bound is None and not c.K.bounded


@given(
    variance=st.lists(st.floats(1e-6, 1e3), min_size=3, max_size=12),
    edf=st.floats(1.0, 5e3),
    confidence=st.floats(0.5, 0.995),
    term=st.sampled_from("QNBKR"),
)
def test_bound_touches_the_upper_confidence_bound(
    variance: list[float], edf: float, confidence: float, term: str
) -> None:
    n = len(variance)
    m = 2 ** np.arange(n)
    taus = m / FS
    var = np.asarray(variance, dtype=np.float64)
    edfs = np.full(n, edf) / np.sqrt(m)
    edfs = np.maximum(edfs, 1.0)
    used = np.arange(n)
    n_terms = 10 * 2**n - 2 * m + 1
    b = _core.noise.upper_bound(taus, var, m, n_terms, True, used, edfs, term, confidence)
    u2 = var * edfs / stats.chi2.ppf(1.0 - confidence, edfs)
    ratio = b["value"] ** 2 * BASIS[term](taus) / u2
    # The asymptote stays under every upper bound and touches the binding one.
    assert np.max(ratio) == pytest.approx(1.0, rel=1e-9)
    assert b["tau"] == taus[int(np.argmax(ratio))]
    higher = _core.noise.upper_bound(
        taus, var, m, n_terms, True, used, edfs, term, min(0.999, confidence + 0.004)
    )
    assert higher["value"] >= b["value"]


def test_bad_input_names_the_argument() -> None:
    taus = np.array([0.01, 0.02, 0.04])
    var = np.array([1.0, 0.5, 0.25])
    m, n_terms = np.array([1, 2, 4]), np.array([99, 97, 93])
    edf = np.array([50.0, 20.0, 5.0])
    with pytest.raises(ValueError, match="confidence"):
        _core.noise.upper_bound(taus, var, m, n_terms, True, [0, 1, 2], edf, "K", 1.0)
    with pytest.raises(ValueError, match="edf"):
        _core.noise.upper_bound(taus, var, m, n_terms, True, [0, 1], edf, "K", 0.9)
    with pytest.raises(ValueError, match="used"):
        _core.noise.upper_bound(taus, var, m, n_terms, True, [0, 5, 1], edf, "K", 0.9)
    with pytest.raises(ValueError, match="terms"):
        _core.noise.upper_bound(taus, var, m, n_terms, True, [0, 1, 2], edf, "X", 0.9)


#: Monte Carlo regime: 20 min at 100 Hz with N = 0.2 deg/√h, B = 3 deg/h and K = 2e-5 deg/s^1.5
#: (4.32 deg/h^1.5), which the default fit does not see in about three runs of five. Measured
#: (seeds 1000–1059, this regime): K bounded in 37 of 60 runs; the 95 % bound is above the true
#: K in 100 % of them (smallest ratio 2.3) and below 10× it in 95 % (35 of 37), median 6.0×,
#: largest 11.7×; the 80 % bound is lower in every run (median 4.3×, smallest 1.4×) and above
#: the true K in 100 % too (200 logs, seeds 1000–1199: 138 bounded, coverage 100 % at both
#: levels; medians 4.5× and 6.2×, smallest 1.31× and 2.09×). The bound of an invisible term covers more often than its level (the
#: other terms are held at zero: module docs of ``gyrocore::noise::bound``); the level itself is
#: calibrated where the term is the whole variance (next test). The larger run is in
#: benches/python/bench_coverage.py.
MC_RUNS = 60
MC_RRW = 2e-5


def _binomial_floor(level: float, runs: int) -> float:
    """``level`` minus three binomial standard errors ``√(level(1 − level)/runs)``: a coverage
    below it has probability < 0.14 % if the true coverage is ``level``."""
    return level - 3.0 * math.sqrt(level * (1.0 - level) / runs)


def test_bound_covers_an_invisible_rrw() -> None:
    ratios: dict[float, list[float]] = {0.95: [], 0.8: []}
    for seed in range(1000, 1000 + MC_RUNS):
        r = _short_log(seed, rrw=MC_RRW, n=120_000)
        k = {level: gyrobias.noise.fit(r, bound_confidence=level).K for level in ratios}
        assert k[0.95].bounded == k[0.8].bounded  # the level changes the bound, not the fit
        if k[0.95].bounded:
            assert k[0.95].upper_bound is not None and k[0.8].upper_bound is not None
            assert k[0.8].upper_bound < k[0.95].upper_bound
            assert (k[0.8].bound_confidence, k[0.95].bound_confidence) == (0.8, 0.95)
            for level, kk in k.items():
                ratios[level].append(float(kk.upper_bound or 0.0) / MC_RRW)
    for level, values in ratios.items():
        ratios_a = np.asarray(values)
        assert ratios_a.size >= MC_RUNS // 3, ratios_a.size
        above = float(np.mean(ratios_a >= 1.0))
        # At least the level, within three binomial s.e. of the bounded runs (37 here: 0.8 -
        # 3 × 0.066 = 0.60); the 95 % bound's coverage was required at >= 95 % outright.
        floor = 0.95 if level == 0.95 else _binomial_floor(level, ratios_a.size)
        assert above >= floor, (level, above, ratios_a)
        assert float(np.mean(ratios_a < 10.0)) > 0.5, (level, ratios_a)


#: Calibration runs: 400 white-noise records of 4000 samples; the bound of N from one Allan
#: point (τ = 0.08 s, EDF ≈ 670), where N is the whole variance, covers the true N with
#: probability exactly ``level`` if the χ² law with the Allan result's EDF holds. Measured
#: (seeds 50000–51999): 81.2 % at 0.80 and 94.95 % at 0.95 over 2000 runs (s.e. 0.9 % and 0.5 %).
CAL_RUNS = 400


@pytest.mark.parametrize("level", [0.8, 0.95])
def test_bound_level_is_calibrated_where_the_term_is_the_whole_variance(level: float) -> None:
    arw = 0.2 / 60
    hits = 0
    for k in range(CAL_RUNS):
        rate = gyrobias.noise.simulate(4000, FS, arw=arw, seed=50_000 + k)
        r = gyrobias.allan.adev(rate, FS, units="deg/s", taus="octave")
        assert isinstance(r, gyrobias.allan.AllanResult) and r.edf is not None
        i = 3
        b = _core.noise.upper_bound(
            r.taus, r.avar, r.m, r.n_terms, True, np.array([i]), r.edf[i : i + 1], "N", level
        )
        hits += b["value"] >= arw
    coverage = hits / CAL_RUNS
    # Three binomial s.e. either side: ±0.060 at 0.80, ±0.033 at 0.95 (400 runs).
    se = math.sqrt(level * (1.0 - level) / CAL_RUNS)
    assert abs(coverage - level) <= 3.0 * se, (level, coverage)


def test_bound_confidence_reaches_every_fit() -> None:
    r = _short_log(4)
    raw = _core.noise.fit(
        r.taus, r.avar, r.m, r.n_terms, r.overlapping, r.edf, list("QNBKR"), None, None, True
    )
    used = np.asarray(raw["used"], dtype=np.int64)
    edf = np.asarray(raw["edf"], dtype=np.float64)
    u2 = r.avar[used] * edf / stats.chi2.ppf(1.0 - 0.8, edf)
    c = gyrobias.noise.fit(r, bound_confidence=0.8)
    assert c.K.bounded and c.K.bound_confidence == 0.8
    expect = math.sqrt(float(np.min(u2 / BASIS["K"](r.taus[used]))))
    assert c.K.upper_bound == pytest.approx(expect, rel=1e-10)
    assert "80 % upper bound" in str(c.K) and "80 %" in (c.K.bound_reason or "")
    assert c.K.upper_bound < (gyrobias.noise.fit(r).K.upper_bound or 0.0)
    ieee = gyrobias.noise.fit(r, method="ieee", bound_confidence=0.8)
    assert all(t.bound_confidence == 0.8 for t in ieee.terms if t.bounded)
    assert any(t.bounded for t in ieee.terms)
    # A sequence of results passes the level to each.
    assert all(
        x.K.bound_confidence == 0.8 for x in gyrobias.noise.fit([r, r], bound_confidence=0.8)
    )


@pytest.mark.parametrize("bad", [0.0, 1.0, -0.1, 1.5, math.nan, math.inf])
def test_bad_bound_confidence_names_it(bad: float) -> None:
    r = _short_log(4)
    rate = gyrobias.noise.simulate(20_000, FS, arw=0.2 / 60, seed=1)
    with pytest.raises(ValueError, match="bound_confidence"):
        gyrobias.noise.fit(r, bound_confidence=bad)
    with pytest.raises(ValueError, match="bound_confidence"):
        gyrobias.noise.fit(r, method="ieee", bound_confidence=bad)
    with pytest.raises(ValueError, match="bound_confidence"):
        gyrobias.noise.gmwm(rate, FS, bound_confidence=bad)
    with pytest.raises(TypeError, match="bound_confidence"):
        gyrobias.noise.fit(r, bound_confidence="0.9")  # type: ignore[arg-type]


def _gmwm_log(seed: int) -> np.ndarray:
    return np.asarray(
        gyrobias.noise.simulate(
            120_000, FS, arw=0.2 / 60, bias_instability=3 / 3600, rrw=MC_RRW, seed=seed
        )
    )


def test_gmwm_selection_keeps_the_bound_of_a_dropped_term() -> None:
    # Seed 1006: the full model's non-negative fit sets K to zero and the selection drops it;
    # the chosen sub-model {N, B} is then the full model's solution, so the dropped K must carry
    # exactly the bound the full model gives its zero K.
    rate = _gmwm_log(1006)
    full = gyrobias.noise.gmwm(rate, FS, terms=("N", "B", "K"), units="deg/s")
    chosen = gyrobias.noise.gmwm(rate, FS, terms=("N", "B", "K"), units="deg/s", select=True)
    assert full.K.value is None and full.K.bounded
    assert chosen.K.value is None and chosen.K.bounded, str(chosen.K)
    assert (chosen.K.missing or "").startswith("dropped by the model selection")
    assert chosen.K.upper_bound == pytest.approx(full.K.upper_bound, rel=1e-12)
    assert chosen.K.bound_confidence == 0.95
    assert "upper bound" in str(chosen.K) and "dropped by the model selection" in str(chosen.K)
    # The level is the caller's; terms not requested stay unbounded.
    low = gyrobias.noise.gmwm(
        rate, FS, terms=("N", "B", "K"), units="deg/s", select=True, bound_confidence=0.8
    )
    assert low.K.bound_confidence == 0.8 and (low.K.upper_bound or 0.0) < chosen.K.upper_bound
    assert chosen.R.upper_bound is None and chosen.Q.upper_bound is None


def test_gmwm_dropped_bounds_cover_the_true_rrw() -> None:
    # K = 2e-5 deg/s^1.5 on 20 min logs: the selection drops it in 10 of seeds 1000–1011
    # (measured); every dropped K's bound lies above the true K (smallest ratio 5.4).
    dropped = 0
    for seed in range(1000, 1012):
        c = gyrobias.noise.gmwm(
            _gmwm_log(seed), FS, terms=("N", "B", "K"), units="deg/s", select=True
        )
        if (c.K.missing or "").startswith("dropped"):
            dropped += 1
            assert c.K.bounded and (c.K.upper_bound or 0.0) >= MC_RRW, (seed, str(c.K))
    assert dropped >= 6, dropped


def test_conservative_set_carries_a_bounded_rrw_at_its_bound() -> None:
    c = gyrobias.noise.fit(_short_log(4))
    assert c.K.bounded and c.K.upper_bound is not None
    cons = c.conservative(0.95)
    k = cons.coefficients.K
    assert k.value is not None and k.value >= c.K.upper_bound * (1 - 1e-12)
    inflation = cons.inflation["K"]
    assert inflation is not None and inflation >= 1.0
    assert "≤" in cons.summary()
    # ... and it exports without any bound mark (the conservative value is a value).
    text = cons.export("kalibr")
    assert "UPPER BOUND" not in text and "gyroscope_random_walk: " in text
