"""Issue 11: goodness-of-fit diagnostics, automatic τ-range selection, Gauss–Markov terms."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from gyrobias import noise
from gyrobias.allan import AllanResult, adev
from tests.reference_noise import gauss_markov_avar_reference, sensor_like_log

FS = 100.0


# --- Gauss–Markov closed form ---------------------------------------------------------------------


@pytest.mark.parametrize(
    ("t", "tau"), [(1.0, 0.01), (1.0, 0.5), (1.0, 1.89), (1.0, 7.0), (30.0, 2000.0)]
)
def test_gauss_markov_avar_matches_psd_integral(t: float, tau: float) -> None:
    got = float(noise.gauss_markov_avar(1.5, t, [tau])[0])
    expect = gauss_markov_avar_reference(1.5**2, t, tau)
    # quad at 1e-10 per decade plus the analytic tail: agreement to 1e-7 relative.
    assert got == pytest.approx(expect, rel=1e-7)


@given(
    sigma=st.floats(1e-3, 1e3),
    t=st.floats(1e-2, 1e4),
    x=st.floats(1e-4, 1e4),
)
def test_gauss_markov_avar_bounded_by_its_asymptotes(sigma: float, t: float, x: float) -> None:
    # The Allan variance lies below both the white (2σ²T/τ) and the random-walk (2σ²τ/(3T))
    # asymptotes and is positive; checked across eight decades of τ/T, through the switch
    # between the power series and the direct formula.
    tau = x * t
    v = float(noise.gauss_markov_avar(sigma, t, [tau])[0])
    assert v > 0.0
    assert v <= 2.0 * sigma**2 * t / tau * (1 + 1e-12)
    assert v <= 2.0 * sigma**2 * tau / (3.0 * t) * (1 + 1e-12)


def test_gauss_markov_avar_matches_monte_carlo() -> None:
    # AR(1) sampled exactly (T = 2 s at 100 Hz): overlapping AVAR of 4e5 samples vs closed form
    # at τ = T (EDF ≈ 2000 → 3 % s.d. of σ²; 12 % is 4σ).
    sigma, t = 0.3, 2.0
    phi = math.exp(-1.0 / (FS * t))
    rate = noise.simulate(400_000, FS, ar1=(phi, sigma * math.sqrt(1 - phi * phi)), seed=4)
    r = adev(rate, FS, taus=np.array([0.5, 2.0, 8.0]), confidence=None)
    assert isinstance(r, AllanResult)
    expect = noise.gauss_markov_avar(sigma, t, r.taus)
    np.testing.assert_allclose(r.avar, expect, rtol=0.12)


# --- diagnostics ---------------------------------------------------------------------------------


def _white_plus_gm(seed: int, n: int = 720_000) -> np.ndarray:
    t = 20.0
    phi = math.exp(-1.0 / (FS * t))
    return noise.simulate(n, FS, arw=0.01, ar1=(phi, 0.004 * math.sqrt(1 - phi * phi)), seed=seed)


def test_diagnostics_always_present_and_serialisable() -> None:
    rate = noise.simulate(200_000, FS, arw=0.2 / 60, rrw=10 / 216000, seed=2)
    r = adev(rate, FS, units="deg/s")
    assert isinstance(r, AllanResult)
    for method in ("joint", "ieee"):
        c = noise.fit(r, method=method)
        d = c.diagnostics
        assert d is not None
        assert d.dof > 0 and np.isfinite(d.chi2) and 0.0 <= d.p_value <= 1.0
        assert d.residuals.shape == d.taus.shape and np.isin(d.taus, r.taus).all()
        assert np.isfinite(d.residuals).all()  # unused points are omitted, not NaN
        assert d.tau_range[0] >= r.taus[0] and d.tau_range[1] <= r.taus[-1]
        assert isinstance(d.warnings, tuple) and isinstance(d.excluded, tuple)
        text = json.dumps(c.to_dict())
        assert '"diagnostics"' in text and '"p_value"' in text
        assert "goodness of fit" in str(c)


def test_clean_model_passes_and_misfit_warns() -> None:
    rate = _white_plus_gm(seed=1)
    r = adev(rate, FS, units="deg/s")
    assert isinstance(r, AllanResult)
    good = noise.fit(r, terms=("N", "GM"))
    assert good.diagnostics is not None and good.diagnostics.passed
    assert not good.diagnostics.warnings
    # White noise alone cannot follow the Gauss–Markov bump: rejected, and said so everywhere.
    bad = noise.fit(r, terms=("N",), auto_range=False)
    assert bad.diagnostics is not None
    assert bad.diagnostics.p_value < 1e-3 and not bad.diagnostics.passed
    assert any("does not fit" in w for w in bad.diagnostics.warnings)
    assert "REJECTED" in str(bad) and "WARNING" in str(bad)
    # Uncertainties are inflated when the model is rejected.
    assert bad.N.uncertainty is not None and bad.N.uncertainty > 0


def test_p_values_are_not_extreme_under_the_model() -> None:
    # 12 clean white + flicker + RRW logs: the test must not reject a correct model (each
    # p < 0.001 has probability 0.001; allow at most one p < 0.01 among 12).
    small = 0
    for seed in range(12):
        rate = noise.simulate(
            100_000, FS, arw=0.2 / 60, bias_instability=3 / 3600, rrw=10 / 216000, seed=seed
        )
        c = noise.fit(adev(rate, FS), terms=("N", "B", "K"))
        assert c.diagnostics is not None
        assert c.diagnostics.p_value > 1e-3, seed
        small += c.diagnostics.p_value < 0.01
    assert small <= 1


def test_dense_tau_grid_fit_is_unchanged() -> None:
    # Every τ of a 2050-sample record (1025 points, where the n × n correlation of the
    # estimates dominates the cost): the fit must give what the pair-by-pair correlation
    # integrals gave before they were blocked and shared (values printed by commit 8d06cac,
    # whose fit code is that of the old path). The kernel reproduces every integral bit for bit
    # (gyrocore's covariance_equals_the_pair_by_pair_integrals_bit_for_bit), so here the values
    # agree exactly; rel 1e-10 only leaves room for a libm whose sin differs in the last bit,
    # amplified by the near-singular correlation of neighbouring τ (ridge 1e-9).
    rate = noise.simulate(2050, FS, arw=0.2 / 60, bias_instability=3 / 3600, seed=1)
    r = adev(rate, FS, taus="all", confidence=None, units="deg/s")
    assert isinstance(r, AllanResult) and len(r.taus) == 1025
    pinned = {
        # auto_range: the range selection tests the model, then the report and the sandwich
        # covariance reuse its correlation matrix.
        True: (
            "0x1.ada16dc38c76ap+4",  # diagnostics.chi2
            "0x1.603841c702d14p+6",  # weighted least-squares chi2
            ("0x1.685ff123995c4p-17", "0x1.0a16e50699afcp-17"),  # N², B²
            ("0x1.185358c5c728cp-13", "0x1.521ef2d2342e4p-10"),  # u(N), u(B)
        ),
        False: (
            "0x1.2130a09a0aa95p+5",
            "0x1.7324f723e77bcp+8",
            ("0x1.7e2c827826969p-17", "0x1.265aa364d0adap-18"),
            ("0x1.37dfe48f2a324p-13", "0x1.4d5b999086d40p-10"),
        ),
    }
    for auto, (gof, chi2, squared, uncertainty) in pinned.items():
        c = noise.fit(r, auto_range=auto)
        assert c.diagnostics is not None
        got = [c.diagnostics.chi2, c.chi2, c.squared[1], c.squared[2], c.N.uncertainty]
        got.append(c.B.uncertainty)
        want = [float.fromhex(v) for v in (gof, chi2, *squared, *uncertainty)]
        assert got == pytest.approx(want, rel=1e-10), auto


# --- Gauss–Markov fit -------------------------------------------------------------------------------


def test_gauss_markov_term_is_recovered() -> None:
    rate = _white_plus_gm(seed=3)
    c = noise.fit(adev(rate, FS, units="deg/s"), terms=("N", "GM"))
    assert len(c.gauss_markov) == 1
    g = c.gauss_markov[0]
    assert g.present and g.sigma.unit == "deg/s" and g.correlation_time.unit == "s"
    # Truth σ = 0.004 deg/s, T = 20 s on a 2 h log: within 3 standard uncertainties.
    assert abs(g.sigma.value - 0.004) < 3 * g.sigma.uncertainty
    assert abs(g.correlation_time.value - 20.0) < 3 * g.correlation_time.uncertainty
    assert g.correlation_time.uncertainty < 0.5 * 20.0
    assert c.N.value == pytest.approx(0.01, rel=0.02)
    # Units: σ converts with B's unit; T stays in seconds; the model includes the term.
    ieee = c.to("ieee")
    assert ieee.gauss_markov[0].sigma.unit == "deg/h"
    assert ieee.gauss_markov[0].sigma.value == pytest.approx(g.sigma.value * 3600)
    total, parts = c.model(np.array([1.0, 40.0]))
    assert "GM" in parts and np.all(total >= parts["GM"])
    assert "GM" in str(c) and "T =" in str(c)


def test_two_gauss_markov_terms_are_sorted_and_reported() -> None:
    rate = _white_plus_gm(seed=5)
    c = noise.fit(adev(rate, FS), terms=("N", "GM", "GM2"))
    assert len(c.gauss_markov) == 2
    times = [g.correlation_time.value for g in c.gauss_markov if g.present]
    assert times == sorted(times)
    assert [g.sigma.symbol for g in c.gauss_markov] == ["GM", "GM2"]


# --- automatic region selection ----------------------------------------------------------------------


def test_sensor_like_log_excludes_the_filter_bend() -> None:
    """The README example: an ADIS16405-like static log (100 Hz, 2.8 h)."""
    rate = sensor_like_log(
        1_000_000, FS, arw=0.044, gm_sigma=0.005, gm_time=100.0, lsb=0.05, cutoff=6.0, seed=0
    )
    r = adev(rate, FS, units="deg/s")
    assert isinstance(r, AllanResult)
    c = noise.fit(r, terms=("N", "K", "GM"))
    d = c.diagnostics
    assert d is not None and d.passed
    # The bend is excluded (the last τ, 4 decimated points with EDF < 3, may be too).
    bend = [e for e in d.excluded if "filter" in e[2]]
    assert bend and bend[0][0] == pytest.approx(0.01)
    # Default N within 5 % of σ(τ)·√τ in the clean −½ region (0.5–5 s).
    clean = (r.taus > 0.5) & (r.taus < 5.0)
    read = float(np.mean(r.adev[clean] * np.sqrt(r.taus[clean])))
    assert c.N.value == pytest.approx(read, rel=0.05)
    assert c.gauss_markov[0].present
    # Without the selection the bent region drags the fit and the test says so.
    every = noise.fit(r, terms=("N", "K", "GM"), auto_range=False)
    assert every.diagnostics is not None and not every.diagnostics.passed


def test_tau_range_overrides_the_selection() -> None:
    rate = noise.simulate(100_000, FS, arw=0.01, seed=8)
    r = adev(rate, FS)
    c = noise.fit(r, terms=("N",), tau_range=(0.05, 10.0))
    assert c.diagnostics is not None and not c.diagnostics.excluded
    assert c.diagnostics.tau_range[0] >= 0.05 and c.diagnostics.tau_range[1] <= 10.0
    assert c.diagnostics.taus[0] >= 0.05  # the points below tau_range have no residual


# --- bad input ---------------------------------------------------------------------------------------


def test_bad_input_is_a_clear_value_error() -> None:
    rate = _white_plus_gm(seed=0, n=50_000)
    r = adev(rate, FS)
    with pytest.raises(ValueError, match="terms"):
        noise.fit(r, terms=("N", "GM3"))
    with pytest.raises(ValueError, match="correlation_time"):
        noise.fit(r, terms=("N", "GM"), correlation_time=(1e-4, 10.0))
    with pytest.raises(ValueError, match="correlation_time"):
        noise.fit(r, terms=("N", "GM"), correlation_time=(10.0, 1.0))
    with pytest.raises(ValueError, match="method='joint'"):
        noise.fit(r, method="ieee", terms=("N", "GM"))
    with pytest.raises(ValueError, match="correlation_time"):
        noise.gauss_markov_avar(1.0, 0.0, [1.0])
    with pytest.raises(TypeError, match="auto_range"):
        noise.fit(r, auto_range="yes")  # type: ignore[arg-type]


# --- command line ----------------------------------------------------------------------------------


def test_cli_prints_diagnostics_and_rejection(tmp_path, capsys) -> None:  # type: ignore[no-untyped-def]
    from gyrobias.cli import main

    np.save(tmp_path / "g.npy", _white_plus_gm(seed=2, n=200_000))
    assert (
        main(
            [
                "allan",
                str(tmp_path / "g.npy"),
                "--fs",
                "100",
                "--units",
                "deg/s",
                "--fit",
                "--fit-terms",
                "N,GM",
            ]
        )
        == 0
    )
    captured = capsys.readouterr()
    assert "goodness of fit" in captured.out and "Gauss–Markov" in captured.out
    # Quantisation noise lifts the shortest τ above a white-noise-only model: no range selection
    # can remove that (it only trims σ *below* the model at short τ), so the fit is rejected.
    np.save(tmp_path / "q.npy", noise.simulate(200_000, FS, arw=0.01, quantization=0.002, seed=2))
    assert (
        main(
            [
                "allan",
                str(tmp_path / "q.npy"),
                "--fs",
                "100",
                "--units",
                "deg/s",
                "--fit",
                "--fit-terms",
                "N",
            ]
        )
        == 0
    )
    captured = capsys.readouterr()
    assert "REJECTED" in captured.out and "does not fit" in captured.err
    assert (
        main(["allan", str(tmp_path / "g.npy"), "--fs", "100", "--fit", "--fit-terms", "N,X"]) == 2
    )
    assert capsys.readouterr().err.startswith("gyrobias: error: --fit-terms must be")


def test_a_single_excluded_tau_prints_as_one_value() -> None:
    # On a 6.4 s real log the summary said "excluded τ 2.56–2.56 s" (a range of one point).
    d = noise.FitDiagnostics(
        chi2=1.0,
        dof=1,
        p_value=0.3,
        residuals=np.zeros(1),
        taus=np.ones(1),
        tau_range=(0.02, 1.28),
        excluded=((2.56, 2.56, "fewer than 3 equivalent degrees of freedom"), (0.01, 0.0101, "x")),
    )
    text = d.summary()
    assert "excluded τ 2.56 s: fewer than 3" in text
    assert "excluded τ 0.01–0.0101 s: x" in text
