"""Issue 33 point 4, the fit's edges: the shortest-τ exclusion says on which side of the model the
dropped points lay; a fitted line's τ band keeps the line's reason; a model with a sensor filter
has no value (NaN, a gap in plots) below 3τ_c instead of a plunge to zero."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from scipy import signal

import gyrobias
from gyrobias import noise

FS = 100.0
ARW = 0.2 / 60
BIAS = 3 / 3600
RRW = 10 / 216000
MA4 = np.ones(4) / 4
# A long FIR at 0.3 Nyquist: its ringing leaves the first scales above and below the model.
FIR41 = signal.firwin(41, 0.3 * FS / 2, fs=FS)


def _log(seed: int, taps: np.ndarray) -> np.ndarray:
    rate = np.asarray(
        noise.simulate(360_000, FS, arw=ARW, bias_instability=BIAS, rrw=RRW, seed=seed)
    )
    return signal.lfilter(taps, 1.0, rate)


def _short(c: noise.NoiseCoefficients) -> tuple[float, float, str]:
    assert c.diagnostics is not None
    short = [e for e in c.diagnostics.excluded if "shortest τ" in e[2]]
    assert len(short) == 1, c.diagnostics.excluded
    return short[0]


def _sides(c: noise.NoiseCoefficients, a: gyrobias.allan.AllanResult, band: tuple[float, float]):
    # Independent of the core's residuals: the measured σ² against the fitted terms' sum (the
    # filter's −3N²τ_c/τ² law has no meaning at these τ), on the excluded points.
    t = np.asarray(a.taus)
    inside = (t >= band[0] * (1 - 1e-9)) & (t <= band[1] * (1 + 1e-9))
    _, parts = c.model(t[inside])
    plain = sum(p**2 for p in parts.values())
    ratio = np.asarray(a.avar)[inside] / plain
    return ratio


def test_points_below_the_model_are_said_to_be_below() -> None:
    # A 4-tap moving average: the first scales fall below the white-noise line.
    a = gyrobias.allan.avar(_log(1, MA4), FS, units="deg/s")
    c = noise.fit(a, terms=("N", "B", "K"))
    lo, hi, reason = _short(c)
    assert reason.startswith("σ below the model at the shortest τ"), reason
    assert np.all(_sides(c, a, (lo, hi)) < 1.0)


@pytest.mark.parametrize("estimator", ["fit", "gmwm"])
def test_points_above_and_below_are_said_to_be_both(estimator: str) -> None:
    # Before the fix this read "σ below the model" although the FIR's ringing put excluded
    # points above it too.
    rate = _log(1, FIR41)
    a = gyrobias.allan.avar(rate, FS, units="deg/s")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        c = (
            noise.gmwm(rate, FS, terms=("N", "B", "K"), units="deg/s")
            if estimator == "gmwm"
            else noise.fit(a, terms=("N", "B", "K"))
        )
    lo, hi, reason = _short(c)
    assert reason.startswith("σ above and below the model at the shortest τ"), reason
    ratio = _sides(c, a, (lo, hi))
    assert np.any(ratio > 1.0) and np.any(ratio < 1.0), ratio


def test_the_model_has_no_value_below_three_filter_times() -> None:
    a = gyrobias.allan.avar(_log(2001, MA4), FS, units="deg/s")
    c = noise.fit(a, terms=("N", "B", "K"))
    assert c.diagnostics is not None
    tc = c.diagnostics.filter_correlation_time
    assert tc is not None and tc.value is not None
    t = np.asarray(a.taus)
    total, parts = c.model(t)
    below = t < 3 * tc.value
    assert below.any() and (~below).any()
    # NaN (a gap in a plot) where the filter law has no meaning, never 0 (a plunge) ...
    assert np.all(np.isnan(total[below]))
    # ... and the model's value everywhere else; the terms' asymptotes are defined everywhere.
    assert np.all(np.isfinite(total[~below])) and np.all(total[~below] > 0)
    assert all(np.all(np.isfinite(p)) for p in parts.values())


def _model_lines(ax: object) -> list[tuple[np.ndarray, np.ndarray]]:
    return [
        (np.asarray(ln.get_xdata(), float), np.asarray(ln.get_ydata(), float))
        for ln in ax.get_lines()  # type: ignore[attr-defined]
        if str(ln.get_label()).endswith(" model")
    ]


def test_a_plotted_model_stops_at_three_filter_times() -> None:
    pytest.importorskip("matplotlib")
    from matplotlib.figure import Figure

    a = gyrobias.allan.adev(_log(2001, MA4), FS, units="deg/s")
    c = noise.fit(a, terms=("N", "B", "K"))
    assert c.diagnostics is not None and c.diagnostics.filter_correlation_time is not None
    tc = c.diagnostics.filter_correlation_time.value
    assert tc is not None
    ax = c.plot(Figure().add_subplot())
    (x, y), *_ = _model_lines(ax)
    drawn = np.isfinite(y)
    # A gap, not a plunge: nothing drawn below 3τ_c, everything drawn beyond, nothing at 0.
    assert x[0] < 3 * tc and not drawn[x < 3 * tc].any()
    assert drawn[x >= 3 * tc].all() and np.all(y[drawn] > 0)


def test_the_gallery_fit_figure_does_not_plunge(monkeypatch: pytest.MonkeyPatch) -> None:
    # docs/examples' "Noise fit with diagnostics": its accepted fit models the 41-tap FIR; the
    # drawn model lines end at 3τ_c instead of falling to 0 (before: 0, a plunge off the axes).
    pytest.importorskip("matplotlib")
    import runpy
    from pathlib import Path

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    script = Path(__file__).parents[1] / "docs" / "examples" / "plot_noise_fit_diagnostics.py"
    monkeypatch.setattr(plt, "show", lambda *a, **k: None)
    ns = runpy.run_path(str(script), run_name="gallery")
    try:
        fits = [ns["good"], ns["bad"]]
        for ax, fit in zip(ns["axes"], fits):
            tc = fit.diagnostics.filter_correlation_time
            lines = _model_lines(ax)
            assert lines
            for x, y in lines:
                drawn = np.isfinite(y)
                assert drawn.any() and np.all(y[drawn] > 0), fit.method
                if tc is not None:
                    assert not drawn[x < 3 * tc.value].any()
        assert ns["good"].diagnostics.filter_correlation_time is not None
    finally:
        plt.close("all")


def _with_line(f: float) -> np.ndarray:
    rate = _log(1, MA4)
    return rate + 0.01 * np.sin(2 * np.pi * f * np.arange(rate.size) / FS)


def _check_line_band(c: noise.NoiseCoefficients, taus: np.ndarray, f: float) -> None:
    # Band where the line's Allan bump A²/2·sin⁴(πfτ)/(πfτ)² is above half its peak, solved here.
    x = np.linspace(0.01, 0.99, 200_001)
    g = np.sin(np.pi * x) ** 4 / (np.pi * x) ** 2
    inside = x[g >= g.max() / 2]
    lo_band, hi_band = inside[0] / f, inside[-1] / f
    assert c.diagnostics is not None
    ex = c.diagnostics.excluded
    line = [e for e in ex if e[2].startswith(f"σ shaped by the spectral line at {f:.4g} Hz")]
    assert len(line) == 1, ex
    assert lo_band * 0.999 <= line[0][0] <= line[0][1] <= hi_band * 1.001, (line, lo_band, hi_band)
    # No other reason covers a τ point of the band (the filter's run used to swallow it).
    band_pts = taus[(taus >= lo_band) & (taus <= hi_band)]
    for a, b, r in ex:
        if r != line[0][2]:
            assert not np.any((band_pts >= a) & (band_pts <= b)), (a, b, r)


@pytest.mark.parametrize("lines", ["auto", None, "explicit"])
def test_a_line_band_is_excluded_under_the_line_reason(lines: str | None) -> None:
    # A 5 Hz line (bump at τ ≈ 0.074 s) on a log through a 4-tap moving average: the automatic
    # range drops the short τ as the filter's transition, and the line's band with them.
    f = 5.0
    a = gyrobias.allan.avar(_with_line(f), FS, units="deg/s")
    assert [round(x.frequency, 3) for x in a.lines] == [f]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        c = noise.fit(a, terms=("N", "B", "K"), lines=[f] if lines == "explicit" else lines)
    _check_line_band(c, np.asarray(a.taus), f)


def test_gmwm_excludes_a_line_band_under_the_line_reason() -> None:
    f = 10.0
    rate = _with_line(f)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        c = noise.gmwm(rate, FS, terms=("N", "B", "K"), units="deg/s")
    assert c.diagnostics is not None
    taus = np.asarray(gyrobias.allan.avar(rate, FS, units="deg/s").taus)
    _check_line_band(c, taus, f)
