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
#: (seeds 1000–1059, this regime): K bounded in 37 of 60 runs; the bound is above the true K in
#: 100 % of them (smallest ratio 2.3) and below 10× it in 95 % (35 of 37), median 6.0×, largest
#: 11.7×. The larger run is in benches/python/bench_coverage.py.
MC_RUNS = 60
MC_RRW = 2e-5


def test_bound_covers_an_invisible_rrw() -> None:
    ratios = []
    for seed in range(1000, 1000 + MC_RUNS):
        c = gyrobias.noise.fit(_short_log(seed, rrw=MC_RRW, n=120_000))
        if c.K.bounded:
            assert c.K.upper_bound is not None
            ratios.append(c.K.upper_bound / MC_RRW)
    ratios_a = np.asarray(ratios)
    assert ratios_a.size >= MC_RUNS // 3, ratios_a.size
    above = float(np.mean(ratios_a >= 1.0))
    below10 = float(np.mean(ratios_a < 10.0))
    assert above >= 0.95, (above, ratios_a)
    assert below10 > 0.5, (below10, ratios_a)


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
