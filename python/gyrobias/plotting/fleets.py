"""Fleets (:mod:`gyrobias.fleet`): every unit's Allan curve in a band, and the terms per unit."""

from __future__ import annotations

import os
from typing import Any

import numpy as np

from gyrobias import _core
from gyrobias.fleet.table import check_table, term_columns
from gyrobias.plotting._common import (
    _check_dpi,
    _require_matplotlib,
    _save_atomically,
    check_figure,
    check_output,
    check_texts,
)


def _fleet_band(curves: list[tuple[Any, Any]]) -> tuple[Any, Any, Any, Any]:
    """Fleet median and 16–84 % band of Allan curves on the τ grid of the longest curve.

    Each curve is interpolated linearly in log τ – log σ inside its own τ range; the statistics
    are taken where at least 3 curves are defined.
    """
    grid = np.asarray(max(curves, key=lambda c: len(c[0]))[0], dtype=np.float64)
    stack = np.full((len(curves), grid.size), np.nan)
    for i, (tau, dev) in enumerate(curves):
        tau = np.asarray(tau, dtype=np.float64)
        dev = np.asarray(dev, dtype=np.float64)
        good = (tau > 0) & (dev > 0)
        if good.sum() < 2:
            continue
        lt, ld = np.log(tau[good]), np.log(dev[good])
        inside = (np.log(grid) >= lt[0] - 1e-12) & (np.log(grid) <= lt[-1] + 1e-12)
        stack[i, inside] = np.exp(np.interp(np.log(grid[inside]), lt, ld))
    enough = np.sum(np.isfinite(stack), axis=0) >= 3
    if not enough.any():
        return grid[:0], grid[:0], grid[:0], grid[:0]
    sub = stack[:, enough]
    return (
        grid[enough],
        np.nanmedian(sub, axis=0),
        np.nanpercentile(sub, 16.0, axis=0),
        np.nanpercentile(sub, 84.0, axis=0),
    )


def plot_fleet(table: Any, fig: Any = None, *, title: str | None = None) -> Any:
    """Fleet figure: every unit's ADEV with the fleet median and band, and each term's spread.

    Parameters
    ----------
    table : pandas.DataFrame
        The result of :func:`gyrobias.fleet.analyse`.
    fig : matplotlib Figure, optional
        Where to draw; default a new pyplot figure.
    title : str, optional
        Figure title.

    Returns
    -------
    matplotlib.figure.Figure

    Notes
    -----
    Top row, one panel per axis: all units' Allan deviations (grey; out-of-family units red),
    the fleet median (black) and its 16–84 % band, interpolated in log–log on the τ grid of the
    longest record where at least 3 units have data. Bottom row, one panel per noise term
    (Q, N, B, K, R and, when fitted, the Gauss–Markov σ and correlation time): the
    value of each unit with its 1σ uncertainty, per axis; outliers (``out_of_family_terms``
    names the term) are red crosses labelled with their source file.
    """
    check_texts(title=title)
    check_table(table)
    _require_matplotlib()
    check_figure("fig", fig)
    ok = table[table["error"].isna()]
    if ok.empty:
        raise ValueError("table has no analysed unit (every row has an error): nothing to plot")
    if fig is None:
        import matplotlib.pyplot as plt

        fig = plt.figure(figsize=(11.0, 7.5), layout="constrained")
    _draw_fleet(fig, ok, title)
    return fig


def save_fleet_plot(
    table: Any, path: str | os.PathLike[str], *, title: str | None = None, dpi: int = 150
) -> None:
    """Render :func:`plot_fleet` to an image file through a pyplot-free ``Figure`` (headless)."""
    check_texts(title=title)
    check_table(table)
    check_output(path)
    _check_dpi(dpi)
    _require_matplotlib()
    from matplotlib.figure import Figure

    ok = table[table["error"].isna()]
    if ok.empty:
        raise ValueError("table has no analysed unit (every row has an error): nothing to plot")
    fig = Figure(figsize=(11.0, 7.5), layout="constrained")
    _draw_fleet(fig, ok, title)
    _save_atomically(fig, path, dpi)


def _draw_fleet(fig: Any, ok: Any, title: str | None) -> None:
    axes_names = list(dict.fromkeys(str(a) for a in ok["axis"]))
    terms = [t for t in term_columns(ok) if np.isfinite(ok[t].to_numpy(dtype=np.float64)).any()]
    top, bottom = fig.subfigures(2, 1, height_ratios=[1.15, 1.0]) if terms else (fig, None)
    adev_axes = np.atleast_1d(top.subplots(1, len(axes_names), sharey=True, squeeze=False)[0])
    for ax, name in zip(adev_axes, axes_names):
        rows = ok[ok["axis"].astype(str) == name]
        curves = []
        flagged = rows["out_of_family"].astype("boolean").fillna(False).to_numpy(dtype=bool)
        for tau_list, dev_list, bad in zip(rows["adev_tau"], rows["adev"], flagged):
            tau, dev = (
                np.asarray(tau_list, dtype=np.float64),
                np.asarray(dev_list, dtype=np.float64),
            )
            curves.append((tau, dev))
            ax.loglog(
                tau,
                dev,
                color="tab:red" if bad else "0.55",
                lw=1.1 if bad else 0.7,
                alpha=0.9 if bad else 0.45,
                zorder=3 if bad else 1,
            )
        grid, med, lo, hi = _fleet_band(curves)
        if grid.size:
            ax.fill_between(
                grid, lo, hi, color="tab:blue", alpha=0.25, lw=0, label="fleet 16–84 %", zorder=2
            )
            ax.loglog(grid, med, color="black", lw=1.8, label="fleet median", zorder=4)
        unit = next((u for u in rows["data_unit"] if isinstance(u, str)), None)
        ax.set_title(f"axis {name} ({len(rows)} units)", fontsize=10)
        ax.set_xlabel("τ [s]")
        ax.grid(True, which="major", alpha=0.5)
    adev_axes[0].set_ylabel(f"σ(τ) [{unit}]" if unit else "σ(τ)")
    handles, labels = adev_axes[0].get_legend_handles_labels()
    if handles:
        from matplotlib.lines import Line2D

        handles.append(Line2D([], [], color="tab:red", lw=1.1))
        labels.append("out of family")
        adev_axes[0].legend(handles, labels, fontsize=8, loc="best")
    if title:
        fig.suptitle(title)
    if bottom is None:
        return
    term_axes = np.atleast_1d(bottom.subplots(1, len(terms), squeeze=False)[0])
    # Fixed jitter from the core's generator (seeded by the axis' position): the same table
    # always gives the same figure, and a unit keeps its offset in every term's panel.
    for ax, t in zip(term_axes, terms):
        unit = next((u for u in ok[f"{t}_unit"] if isinstance(u, str)), None)
        for k, name in enumerate(axes_names):
            rows = ok[ok["axis"].astype(str) == name]
            values = rows[t].to_numpy(dtype=np.float64)
            unc = rows[f"{t}_uncertainty"].to_numpy(dtype=np.float64)
            have = np.isfinite(values)
            if not have.any():
                continue
            flags = rows["out_of_family_terms"].map(
                lambda s, t=t: isinstance(s, str) and t in s.split(",")
            )
            out = flags.to_numpy(dtype=bool) & have
            x = k - 0.18 + 0.36 * _core.random.uniform(values.size, k)
            ax.errorbar(
                x[have & ~out],
                values[have & ~out],
                yerr=np.nan_to_num(unc[have & ~out]),
                fmt="o",
                ms=3,
                color="tab:blue",
                alpha=0.6,
                elinewidth=0.6,
                capsize=0,
            )
            ax.hlines(np.median(values[have]), k - 0.3, k + 0.3, color="black", lw=1.5)
            if out.any():
                ax.errorbar(
                    x[out],
                    values[out],
                    yerr=np.nan_to_num(unc[out]),
                    fmt="x",
                    ms=7,
                    mew=1.8,
                    color="tab:red",
                    elinewidth=0.8,
                    capsize=0,
                )
                for xi, yi, src in zip(x[out], values[out], rows["source"].to_numpy()[out]):
                    ax.annotate(
                        os.path.basename(str(src)),
                        (xi, yi),
                        textcoords="offset points",
                        xytext=(4, 3),
                        fontsize=7,
                        color="tab:red",
                    )
        ax.set_xticks(range(len(axes_names)), axes_names)
        ax.set_xlim(-0.6, len(axes_names) - 0.4)
        label = t.replace("_sigma", " σ").replace("_correlation_time", " T")  # GM1 σ, GM1 T
        ax.set_title(label, fontsize=10)
        ax.set_ylabel(f"{label} [{unit}]" if unit else label)
        ax.grid(True, axis="y", alpha=0.4)
        shown = ok[t].to_numpy(dtype=np.float64)
        shown = shown[np.isfinite(shown) & (shown > 0)]
        if shown.size and shown.max() > 20.0 * shown.min():
            ax.set_yscale("log")  # an outlier decades away would flatten the fleet into one line
        else:
            ax.ticklabel_format(axis="y", style="sci", scilimits=(-3, 4))
