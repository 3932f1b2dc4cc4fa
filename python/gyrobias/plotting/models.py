"""Fitted noise models: the model curve, each term's asymptote and the read-off points."""

from __future__ import annotations

import os
from typing import Any

import numpy as np

from gyrobias._validation import instance, optional_instance
from gyrobias.allan._types import AllanResult
from gyrobias.noise._types import NoiseCoefficients, WaveletVariance
from gyrobias.plotting._common import (
    _check_dpi,
    _require_matplotlib,
    _save_atomically,
    check_axes,
    check_output,
    check_texts,
)


def plot_noise_model(
    coefficients: NoiseCoefficients,
    ax: Any = None,
    *,
    allan: AllanResult | None = None,
    show_data: bool = True,
) -> Any:
    """Draw a fitted noise model, each term's asymptote and the labelled read-off points.

    Parameters
    ----------
    coefficients : NoiseCoefficients
        From :func:`gyrobias.noise.fit` (or :func:`gyrobias.noise.gmwm`).
    ax : matplotlib Axes, optional
        Axes to draw on (a new pyplot figure otherwise).
    allan : AllanResult, optional
        The Allan curve to draw beneath (defaults to the one the coefficients came from).
    show_data : bool
        Draw the Allan deviation points (set False when the caller has drawn them).

    Returns
    -------
    matplotlib Axes
    """
    instance("coefficients", coefficients, NoiseCoefficients, "NoiseCoefficients")
    optional_instance("allan", allan, AllanResult, "an AllanResult")
    _require_matplotlib()
    check_axes("ax", ax)
    if ax is None:
        import matplotlib.pyplot as plt

        _, ax = plt.subplots(figsize=(7, 5))
    allan = allan if allan is not None else coefficients.allan
    base = coefficients.to("base") if coefficients.data_unit is not None else coefficients
    if allan is not None:
        taus = np.asarray(allan.taus, dtype=np.float64)
        lo, hi = float(taus[0]), float(taus[-1])
        if show_data:
            ax.loglog(taus, allan.adev, "o", ms=3, color="0.3", label="Allan deviation")
    else:
        lo, hi = coefficients.tau_range
    grid = np.geomspace(lo, hi, 200)
    total, parts = coefficients.model(grid)
    colours = {
        "Q": "tab:purple",
        "N": "tab:blue",
        "B": "tab:green",
        "K": "tab:orange",
        "R": "tab:red",
    }
    ax.loglog(grid, total, "-", color="k", lw=1.5, label=f"{coefficients.method} model")
    unit = coefficients.data_unit or ""
    for t, _b in zip(coefficients.terms, base.terms):
        if t.value is None:
            continue
        curve = parts[t.symbol]
        ax.loglog(grid, curve, "--", color=colours[t.symbol], lw=1, label=f"{t.symbol} asymptote")
        if t.marker is not None:
            mt, ms = t.marker
            ax.loglog([mt], [ms], "s", color=colours[t.symbol], ms=7, mfc="none", mew=1.5)
            value = f"{t.value:.3g} {t.unit or ''}".strip()
            if t.symbol != "B":
                where = f"σ at τ = {mt:.3g} s"
            elif coefficients.method == "ieee":
                where = "min σ / 0.664"
            else:
                where = "plateau σ = 0.664·B"
            ax.annotate(
                f"{t.symbol} = {value}\n({where})",
                (mt, ms),
                textcoords="offset points",
                xytext=(6, 6),
                fontsize=7,
                color=colours[t.symbol],
            )
    for g, colour in zip(coefficients.gauss_markov, ("tab:brown", "tab:pink")):
        if g.present and g.sigma.symbol in parts:
            ax.loglog(
                grid,
                parts[g.sigma.symbol],
                ":",
                color=colour,
                lw=1.2,
                label=f"{g.sigma.symbol} (T = {g.correlation_time.value:.3g} s)",
            )
    if coefficients.diagnostics is not None:
        for k, (a, b, _) in enumerate(coefficients.diagnostics.excluded):
            ax.axvspan(
                a,
                b,
                color="0.85",
                alpha=0.5,
                lw=0,
                label="excluded from the fit" if k == 0 else None,
            )
    # Keep the view on the data and model: asymptotes of negligible terms run far below.
    markers = [
        t.marker[1] for t in coefficients.terms if t.value is not None and t.marker is not None
    ]
    shown = np.concatenate([total, np.asarray(allan.adev) if allan is not None else total, markers])
    shown = shown[np.isfinite(shown) & (shown > 0)]
    if shown.size:
        ax.set_ylim(shown.min() / 5.0, shown.max() * 3.0)
    ax.set_xlabel("τ [s]")
    ax.set_ylabel(f"σ(τ) [{unit}]" if unit else "σ(τ)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7, loc="best")
    return ax


def save_noise_model_plot(
    coefficients: NoiseCoefficients,
    path: str | os.PathLike[str],
    *,
    title: str | None = None,
    dpi: int = 120,
) -> None:
    """Render :func:`plot_noise_model` to an image file through a pyplot-free ``Figure``.

    The file is written atomically (a temporary file renamed over ``path``).
    """
    check_texts(title=title)
    instance("coefficients", coefficients, NoiseCoefficients, "NoiseCoefficients")
    check_output(path)
    _check_dpi(dpi)
    _require_matplotlib()
    from matplotlib.figure import Figure

    fig = Figure(figsize=(7.0, 5.0), layout="constrained")
    ax = fig.add_subplot()
    plot_noise_model(coefficients, ax)
    if title:
        ax.set_title(title)
    _save_atomically(fig, path, dpi)


def plot_wvar(result: WaveletVariance, ax: Any = None) -> Any:
    """Wavelet deviation ν̂_j against the scale τ_j = 2^j/fs (log-log) with its interval.

    Parameters
    ----------
    result : WaveletVariance
        From :func:`gyrobias.noise.wvar`.
    ax : matplotlib Axes, optional
        Axes to draw on (a new figure otherwise).

    Returns
    -------
    matplotlib Axes
    """
    instance("result", result, WaveletVariance, "a WaveletVariance")
    _require_matplotlib()
    check_axes("ax", ax)
    if ax is None:
        import matplotlib.pyplot as plt

        _, ax = plt.subplots(figsize=(6.0, 4.2), layout="constrained")
    scales = np.asarray(result.scales, dtype=np.float64)
    nu = np.sqrt(np.asarray(result.variance, dtype=np.float64))
    low = np.sqrt(np.asarray(result.ci_low, dtype=np.float64))
    high = np.sqrt(np.asarray(result.ci_high, dtype=np.float64))
    kind = "robust" if result.robust else "classical"
    ax.fill_between(scales, low, high, alpha=0.25, label=f"{result.confidence:.0%} interval")
    ax.loglog(scales, nu, "o-", ms=3, label=f"{kind} wavelet deviation")
    ax.set_xlabel("scale τ_j = 2^j/fs (s)")
    unit = f" ({result.unit})" if result.unit else ""
    ax.set_ylabel(f"ν{unit}")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    return ax
