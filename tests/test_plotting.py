"""Tests of gyrobias.plotting: what is drawn, labels with units, confidence bars, file output."""

from __future__ import annotations

import sys
from collections.abc import Iterator
from dataclasses import replace
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # headless; must precede pyplot

import matplotlib.pyplot as plt
import numpy as np
import pytest

import gyrobias
from gyrobias.allan import AllanResult
from gyrobias.plotting import plot_allan, save_allan_plot

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


@pytest.fixture(autouse=True)
def _close_figures() -> Iterator[None]:
    yield
    plt.close("all")


def _results(k: int = 3, *, ci: bool = True) -> tuple[AllanResult, ...]:
    rate = np.random.default_rng(7).normal(0.0, 0.05, (20_000, k))
    res = gyrobias.allan.adev(
        rate, 100.0, confidence=None, units="deg/s", axis_names=["x", "y", "z"][:k]
    )
    assert isinstance(res, tuple)
    if not ci:
        return res
    # the plot only reads ci_low/ci_high: hand-made asymmetric bounds (−20 %, +50 %) make the
    # bar geometry checkable independently of how the intervals are computed
    return tuple(
        replace(
            r,
            confidence=0.683,
            edf=np.full(len(r.taus), 10.0),
            alpha=np.zeros(len(r.taus), dtype=np.int64),
            ci_low=0.8 * r.adev,
            ci_high=1.5 * r.adev,
            noise_type=("white rate (angle random walk)",) * len(r.taus),
        )
        for r in res
    )


def test_log_log_with_units_grid_and_legend() -> None:
    res = _results()
    ax = plot_allan(res)
    assert ax.get_xscale() == "log" and ax.get_yscale() == "log"
    assert ax.get_xlabel() == "τ [s]"
    assert ax.get_ylabel() == "σ(τ) [deg/s]"
    legend = ax.get_legend()
    assert [t.get_text() for t in legend.get_texts()] == ["x", "y", "z"]
    assert legend.get_title().get_text() == "bars: 68.3 % confidence"
    assert ax.xaxis.get_gridlines()[0].get_visible()
    assert len(ax.lines) >= 3
    line = ax.containers[0].lines[0]
    np.testing.assert_array_equal(line.get_xdata(), res[0].taus)
    np.testing.assert_array_equal(line.get_ydata(), res[0].adev)


def test_asymmetric_confidence_bars_span_ci_low_to_ci_high() -> None:
    (r,) = _results(1)
    ax = plot_allan(r)
    container = ax.containers[0]
    assert container.has_yerr
    assert r.ci_low is not None and r.ci_high is not None
    segments = container.lines[2][0].get_segments()
    lows = np.array([s[0][1] for s in segments])
    highs = np.array([s[1][1] for s in segments])
    np.testing.assert_allclose(np.minimum(lows, highs), r.ci_low, rtol=1e-12)
    np.testing.assert_allclose(np.maximum(lows, highs), r.ci_high, rtol=1e-12)


def test_no_bars_without_confidence_or_when_disabled() -> None:
    ax = plot_allan(_results(2, ci=False))
    assert not any(c.has_yerr for c in ax.containers)
    ax2 = plot_allan(_results(2), confidence_bars=False)
    assert not any(c.has_yerr for c in ax2.containers)


def test_labels_title_kwargs_and_given_axes() -> None:
    fig, ax = plt.subplots()
    out = plot_allan(_results(2), ax=ax, labels=["roll", "pitch"], title="bench", color="k")
    assert out is ax
    assert [t.get_text() for t in ax.get_legend().get_texts()] == ["roll", "pitch"]
    assert ax.get_title() == "bench"
    assert matplotlib.colors.to_hex(ax.containers[0].lines[0].get_color()) == "#000000"
    with pytest.raises(ValueError, match="labels has 1 entries for 2 results"):
        plot_allan(_results(2), labels=["one"])


def test_mixed_kinds_and_units() -> None:
    rate = np.random.default_rng(1).normal(size=5000)
    a = gyrobias.allan.adev(rate, 10.0, confidence=None, units="deg/s")
    m = gyrobias.allan.mdev(rate, 10.0, confidence=None, units="rad/s")
    assert isinstance(a, AllanResult) and isinstance(m, AllanResult)
    ax = plot_allan([a, m])
    assert ax.get_ylabel() == "deviation"  # neither one symbol nor one unit applies
    assert [t.get_text() for t in ax.get_legend().get_texts()] == ["ADEV", "MDEV"]
    ax2 = plot_allan(m)
    assert ax2.get_ylabel() == "Mod σ(τ) [rad/s]"
    assert ax2.get_legend() is None  # a single unnamed series needs no legend


def test_result_plot_method() -> None:
    (r,) = _results(1)
    ax = r.plot(label="gyro")
    assert [t.get_text() for t in ax.get_legend().get_texts()] == ["gyro"]


def test_save_png(tmp_path: Path) -> None:
    path = tmp_path / "adev.png"
    save_allan_plot(_results(), path, title="t")
    data = path.read_bytes()
    assert data.startswith(PNG_SIGNATURE)
    assert len(data) > 20_000  # a 1125×750 plot with three series and bars, not an empty canvas


def test_bad_results() -> None:
    with pytest.raises(ValueError, match="^results is empty"):
        plot_allan([])
    with pytest.raises(TypeError, match="AllanResult"):
        plot_allan([np.ones(3)])  # type: ignore[list-item]


def test_missing_matplotlib_names_the_extra(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setitem(sys.modules, "matplotlib", None)  # makes `import matplotlib` fail
    with pytest.raises(ImportError, match=r"gyrobias\[plot\]"):
        plot_allan(_results(1, ci=False))
