"""Every plot of gyrobias: Allan-family deviations with their confidence bars, fitted noise
models, fleets, dynamic Allan maps, bias predictions and filter comparisons.

The science modules never import this module: their results' ``.plot()`` methods delegate to
:func:`gyrobias._generics.plot`, whose methods this module registers (at the end), so the
dependency points one way (plotting → result types). matplotlib is optional (``pip install "gyrobias[plot]"``) and imported only when a plot is made.
:func:`plot_allan` draws into a given or a new pyplot ``Axes``; :func:`save_allan_plot` renders
straight to a file through a pyplot-free ``Figure`` (Agg canvas), so it works headless and does
not touch pyplot's global state — the command line uses it.
"""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gyrobias import _generics
from gyrobias._files import atomic_binary
from gyrobias._fleet_table import term_columns
from gyrobias.allan._types import AllanResult, DynamicAllanResult
from gyrobias.noise._types import NoiseCoefficients, WaveletVariance
from gyrobias.noise.fitting import fit as fit_noise

__all__ = [
    "allan_report_svg",
    "plot_allan",
    "plot_dynamic_allan",
    "plot_fleet",
    "plot_noise_model",
    "save_allan_plot",
    "save_comparison_plot",
    "save_fleet_plot",
    "save_noise_model_plot",
    "save_prediction_plot",
]

_SYMBOL = {"adev": "σ(τ)", "mdev": "Mod σ(τ)", "hdev": "Hadamard σ(τ)", "totdev": "Tot σ(τ)"}
_NAME = {"adev": "Allan", "mdev": "modified Allan", "hdev": "Hadamard", "totdev": "total"}
# The rest of the Allan family (issue 15).
_SYMBOL.update(
    {
        "tdev": "σ_x(τ)",
        "mtotdev": "Mod σ_total(τ)",
        "htotdev": "Hadamard σ_total(τ)",
        "theo1": "Théo1 σ(τ)",
        "theobr": "ThéoBR σ(τ)",
        "theoh": "ThéoH σ(τ)",
    }
)
_NAME.update(
    {
        "tdev": "time",
        "mtotdev": "modified total",
        "htotdev": "Hadamard total",
        "theo1": "Théo1",
        "theobr": "bias-removed Théo1",
        "theoh": "hybrid ThéoH",
    }
)


def _require_matplotlib() -> Any:
    try:
        import matplotlib
    except ImportError as exc:
        raise ImportError(
            "plotting needs matplotlib, which is not installed; install it with "
            'pip install "gyrobias[plot]" (or pip install matplotlib)'
        ) from exc
    return matplotlib


def _as_list(results: AllanResult | Sequence[AllanResult]) -> list[AllanResult]:
    items = [results] if isinstance(results, AllanResult) else list(results)
    if not items:
        raise ValueError("results is empty: nothing to plot")
    for r in items:
        if not isinstance(r, AllanResult):
            raise TypeError(f"results must be AllanResult objects, got {type(r).__name__}")
    return items


def plot_allan(
    results: AllanResult | Sequence[AllanResult],
    ax: Any = None,
    labels: Sequence[str] | None = None,
    *,
    title: str | None = None,
    confidence_bars: bool = True,
    fits: Sequence[Any] | None = None,
    **kwargs: Any,
) -> Any:
    """Log-log plot of one or more Allan-family deviations σ(τ) against τ.

    Parameters
    ----------
    results : AllanResult or sequence of AllanResult
        E.g. the tuple returned by :func:`gyrobias.allan.adev` for a multi-axis log.
    ax : matplotlib Axes, optional
        Where to draw; default a new figure from :func:`matplotlib.pyplot.subplots`.
    labels : sequence of str, optional
        Legend entries, one per result; default the axis names (``result.axis``), else the
        estimator names when several kinds are shown.
    title : str, optional
        Axes title.
    confidence_bars : bool
        Draw the asymmetric confidence bars ``[ci_low, ci_high]`` of results that have them.
    fits : sequence of NoiseCoefficients, optional
        One fitted noise model per result (:func:`gyrobias.noise.fit`): overlays the model
        curve, each term's asymptote and the labelled read-off points
        (:meth:`gyrobias.noise.NoiseCoefficients.plot`).
    **kwargs
        Passed to :meth:`~matplotlib.axes.Axes.errorbar` (e.g. ``fmt``, ``color``, ``ms``).

    Returns
    -------
    matplotlib.axes.Axes

    Raises
    ------
    ImportError
        matplotlib is not installed (the message names the ``gyrobias[plot]`` extra).
    ValueError
        Empty ``results`` or ``labels`` of the wrong length.

    Notes
    -----
    The y label carries the deviation's unit (``σ(τ) [deg/s]``) when all results share it,
    the x label is ``τ [s]``; the legend title states the confidence level of the bars.
    """
    items = _as_list(results)
    _require_matplotlib()
    if labels is not None and len(labels) != len(items):
        raise ValueError(f"labels has {len(labels)} entries for {len(items)} results")
    if ax is None:
        import matplotlib.pyplot as plt

        _, ax = plt.subplots(figsize=(7.5, 5.0), layout="constrained")
    _draw(ax, items, labels, title, confidence_bars, kwargs)
    _overlay_fits(ax, items, fits)
    return ax


def save_allan_plot(
    results: AllanResult | Sequence[AllanResult],
    path: str | os.PathLike[str],
    labels: Sequence[str] | None = None,
    *,
    title: str | None = None,
    dpi: int = 150,
    fits: Sequence[Any] | None = None,
    **kwargs: Any,
) -> None:
    """Render :func:`plot_allan` to an image file (format from the suffix: png, pdf, svg, …).

    Uses a standalone ``matplotlib.figure.Figure`` (Agg canvas for raster formats), so no
    display and no pyplot state are involved.
    """
    items = _as_list(results)
    _require_matplotlib()
    from matplotlib.figure import Figure

    if labels is not None and len(labels) != len(items):
        raise ValueError(f"labels has {len(labels)} entries for {len(items)} results")
    bars = kwargs.pop("confidence_bars", True)
    units = list(dict.fromkeys(r.unit for r in items))
    if len(units) > 1:  # e.g. a 6-axis IMU: one panel per unit (gyro rad/s, accel m/s²)
        fig = Figure(figsize=(7.0 * len(units), 5.0), layout="constrained")
        if title:
            fig.suptitle(title)
        for k, unit in enumerate(units):
            pick = [i for i, r in enumerate(items) if r.unit == unit]
            ax = fig.add_subplot(1, len(units), k + 1)
            _draw(
                ax,
                [items[i] for i in pick],
                None if labels is None else [labels[i] for i in pick],
                _sensor_title(unit),
                bars,
                dict(kwargs),
            )
            _overlay_fits(
                ax, [items[i] for i in pick], None if fits is None else [fits[i] for i in pick]
            )
        _save_atomically(fig, path, dpi)
        return
    fig = Figure(figsize=(7.5, 5.0), layout="constrained")
    ax = fig.add_subplot()
    _draw(ax, items, labels, title, bars, kwargs)
    _overlay_fits(ax, items, fits)
    _save_atomically(fig, path, dpi)


def _overlay_fits(ax: Any, items: list[AllanResult], fits: Sequence[Any] | None) -> None:
    if fits is None:
        return
    if len(fits) != len(items):
        raise ValueError(f"fits has {len(fits)} entries for {len(items)} results")
    for fit, item in zip(fits, items):
        plot_noise_model(fit, ax, allan=item, show_data=False)


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
    _require_matplotlib()
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
    _require_matplotlib()
    from matplotlib.figure import Figure

    fig = Figure(figsize=(7.0, 5.0), layout="constrained")
    ax = fig.add_subplot()
    plot_noise_model(coefficients, ax)
    if title:
        ax.set_title(title)
    _save_atomically(fig, path, dpi)


def save_prediction_plot(
    section: NDArray[np.float64],
    calibration: int,
    fs: float,
    forecasts: Mapping[str, NDArray[np.float64]],
    path: str | os.PathLike[str],
    *,
    std: NDArray[np.float64] | None = None,
    title: str = "",
    dpi: int = 120,
) -> None:
    """Draw one bias-prediction section ([BP] Figs. 2–3) to an image file.

    Parameters
    ----------
    section : ndarray, shape (k + h,)
        The calibration window (first ``calibration`` samples) and the data it predicts.
    calibration : int
        k, the calibration length in samples.
    fs : float
        Sample rate in Hz (the time axis is in seconds).
    forecasts : mapping of label → ndarray of shape (h,)
        The forecasts to draw after the calibration window; the first one is drawn with the
        ``±2·std`` band.
    path : path
        Output image (format from the suffix), written atomically.
    std : ndarray of shape (h,), optional
        Standard deviation of the first forecast.
    """
    _require_matplotlib()
    from matplotlib.figure import Figure

    t = np.arange(section.size) / fs
    tf = t[calibration:]
    fig = Figure(figsize=(8.0, 4.0), layout="constrained")
    ax = fig.add_subplot()
    ax.plot(t, section, color="0.6", lw=0.6, label="data")
    ax.axvline(t[calibration], color="k", lw=0.8, ls=":")
    for i, (label, forecast) in enumerate(forecasts.items()):
        ax.plot(tf, forecast, color=f"C{i}", ls="--" if i == 2 else "-", label=label)
        if i == 0 and std is not None:
            ax.fill_between(
                tf,
                forecast - 2 * std,
                forecast + 2 * std,
                color="C0",
                alpha=0.2,
                label="±2σ (bias)",
            )
    ax.set_xlabel("time (s)")
    ax.set_ylabel("rate")
    ax.set_title(title or "bias prediction")
    ax.legend(loc="best", fontsize=8)
    _save_atomically(fig, path, dpi)


def save_comparison_plot(
    before: Sequence[AllanResult],
    after: Sequence[AllanResult],
    path: str | os.PathLike[str],
    *,
    labels: tuple[str, str] = ("raw", "filtered"),
    title: str | None = None,
    dpi: int = 120,
) -> None:
    """Allan deviations of each axis before (solid) and after (dashed) a filter, to a file.

    ``before[i]`` and ``after[i]`` share a colour; the file is written atomically.
    """
    _require_matplotlib()
    from matplotlib.figure import Figure

    if len(before) != len(after):
        raise ValueError(f"after has {len(after)} results for {len(before)} in before")
    fig = Figure(figsize=(6.4, 4.8), layout="constrained")
    ax = fig.add_subplot()
    unit = None
    for axis, (r, f) in enumerate(zip(before, after)):
        name = r.axis or str(axis)
        (line,) = ax.loglog(r.taus, r.adev, label=f"axis {name} {labels[0]}")
        ax.loglog(f.taus, f.adev, "--", color=line.get_color(), label=f"axis {name} {labels[1]}")
        unit = unit or r.unit
    ax.set_xlabel("τ [s]")
    ax.set_ylabel(f"Allan deviation [{unit}]" if unit else "Allan deviation")
    if title:
        ax.set_title(title)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize="small")
    _save_atomically(fig, path, dpi)


def _draw(
    ax: Any,
    items: list[AllanResult],
    labels: Sequence[str] | None,
    title: str | None,
    confidence_bars: bool,
    kwargs: dict[str, Any],
) -> None:
    kinds = {r.kind for r in items}
    if labels is None:
        auto: list[str | None] = []
        for i, r in enumerate(items):
            name = r.axis or (f"series {i + 1}" if len(items) > 1 and len(kinds) == 1 else None)
            if len(kinds) > 1:
                name = f"{name} {r.kind.upper()}" if name else r.kind.upper()
            auto.append(name)
        labels = None if all(a is None for a in auto) else [a or "" for a in auto]
    style = {"fmt": "o-", "ms": 3.5, "lw": 1.2, "capsize": 2.5, "elinewidth": 0.9}
    style.update(kwargs)
    levels = set()
    for i, r in enumerate(items):
        label = labels[i] if labels is not None else None
        yerr = None
        if confidence_bars and r.ci_low is not None and r.ci_high is not None:
            dev = r.adev
            yerr = np.vstack(
                [np.clip(dev - r.ci_low, 0.0, None), np.clip(r.ci_high - dev, 0.0, None)]
            )
            if r.confidence is not None:
                levels.add(r.confidence)
        ax.errorbar(r.taus, r.adev, yerr=yerr, label=label, **style)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("τ [s]")
    units = {r.unit for r in items}
    symbol = _SYMBOL[items[0].kind] if len(kinds) == 1 else "deviation"
    unit = f" [{units.pop()}]" if len(units) == 1 and None not in units else ""
    ax.set_ylabel(f"{symbol}{unit}")
    ax.grid(True, which="major", alpha=0.6)
    ax.grid(True, which="minor", alpha=0.2)
    if title is None and len(kinds) == 1:
        kind = items[0].kind
        title = f"{'Overlapping ' if items[0].overlapping else 'Non-overlapping '}{_NAME[kind]} deviation"
        if kind != "adev":
            title = f"{_NAME[kind][0].upper()}{_NAME[kind][1:]} deviation"
        if kind == "hdev":  # overlapping = Stable32 OHDEV, non-overlapping = Stable32 HDEV
            title = (
                f"{'Overlapping' if items[0].overlapping else 'Non-overlapping'} Hadamard deviation"
            )
    if title:
        ax.set_title(title)
    if labels is not None or levels:
        legend_title = None
        if len(levels) == 1:
            legend_title = f"bars: {100 * levels.pop():.3g} % confidence"
        if labels is not None:
            ax.legend(title=legend_title)
        elif legend_title:
            ax.text(
                0.98, 0.98, legend_title, transform=ax.transAxes, ha="right", va="top", fontsize=9
            )


def _sensor_title(unit: str | None) -> str:
    """Panel title of a unit's results: ``"gyroscope [rad/s]"``, ``"accelerometer [m/s^2]"``."""
    from gyrobias.units import sensor_kind

    try:
        kind = sensor_kind(unit or "")
    except ValueError:
        return f"[{unit}]" if unit else "no unit"
    return f"{'gyroscope' if kind == 'gyro' else 'accelerometer'} [{unit}]"


# --- fleets (gyrobias.fleet) ---------------------------------------------------------------------


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
    _require_matplotlib()
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
    _require_matplotlib()
    from matplotlib.figure import Figure

    ok = table[table["error"].isna()]
    if ok.empty:
        raise ValueError("table has no analysed unit (every row has an error): nothing to plot")
    fig = Figure(figsize=(11.0, 7.5), layout="constrained")
    _draw_fleet(fig, ok, title)
    _save_atomically(fig, path, dpi)


def _save_atomically(fig: Any, path: str | os.PathLike[str], dpi: int) -> None:
    """``fig.savefig`` through :func:`gyrobias.exports.atomic_binary` (a temporary file beside
    ``path``, renamed over it); the image format comes from the suffix, as ``savefig(path)``."""
    suffix = os.path.splitext(os.fspath(path))[1][1:].lower()
    with atomic_binary(path) as fh:
        fig.savefig(fh, dpi=dpi, format=suffix or None)


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
    rng = np.random.default_rng(0)  # fixed jitter: the same table always gives the same figure
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
            x = k + rng.uniform(-0.18, 0.18, size=values.size)
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


def plot_dynamic_allan(
    result: Any,
    ax: Any = None,
    *,
    title: str | None = None,
    cmap: str = "viridis",
    colorbar: bool = True,
) -> Any:
    """Heat map of a dynamic Allan deviation: time on x, τ on a log y axis, σ in colour.

    Parameters
    ----------
    result : DynamicAllanResult
        From :func:`gyrobias.allan.dynamic_adev`.
    ax : matplotlib Axes, optional
        Where to draw; default a new figure.
    title : str, optional
        Axes title (default names the window and step).
    cmap : str
        Colour map.
    colorbar : bool
        Add a colour bar labelled with σ in the result's unit (log colour scale).

    Returns the matplotlib ``Axes``.

    Examples
    --------
    >>> import numpy as np, gyrobias
    >>> rate = np.random.default_rng(0).normal(0.0, 0.1, 4_000)
    >>> d = gyrobias.allan.dynamic_adev(rate, 10.0, window=1_000, step=500, units="deg/s")
    >>> from matplotlib.figure import Figure
    >>> from gyrobias.plotting import plot_dynamic_allan
    >>> ax = plot_dynamic_allan(d, ax=Figure().add_subplot())
    >>> ax.get_ylabel()
    'τ [s]'
    """
    _require_matplotlib()
    from matplotlib.colors import LogNorm

    if ax is None:
        import matplotlib.pyplot as plt

        _, ax = plt.subplots(figsize=(7, 4.5))
    dev = np.asarray(result.adev, dtype=float)
    times = np.asarray(result.times, dtype=float)
    taus = np.asarray(result.taus, dtype=float)

    def edges(c: np.ndarray, log: bool) -> np.ndarray:
        v = np.log(c) if log else c
        if v.size == 1:
            mid = (
                np.array([v[0] - 0.5, v[0] + 0.5])
                if not log
                else np.array([v[0] - 0.35, v[0] + 0.35])
            )
        else:
            inner = (v[1:] + v[:-1]) / 2
            mid = np.concatenate(([2 * v[0] - inner[0]], inner, [2 * v[-1] - inner[-1]]))
        return np.exp(mid) if log else mid

    positive = dev[dev > 0]
    norm = LogNorm(vmin=positive.min(), vmax=positive.max()) if positive.size else None
    mesh = ax.pcolormesh(
        edges(times, False), edges(taus, True), dev.T, cmap=cmap, norm=norm, shading="flat"
    )
    ax.set_yscale("log")
    ax.set_xlabel("time (window centre) [s]")
    ax.set_ylabel("τ [s]")
    if title is None:
        title = f"Dynamic Allan deviation (window {result.window / result.fs:g} s, step {result.step / result.fs:g} s)"
    ax.set_title(title)
    if colorbar:
        unit = f" [{result.unit}]" if result.unit else ""
        ax.figure.colorbar(mesh, ax=ax, label=f"σ(τ){unit}")
    return ax


# --- report figures (issue 13) --------------------------------------------------------------------


def allan_report_svg(
    result: AllanResult,
    fit: Any = None,
    conservative: Any = None,
    *,
    title: str | None = None,
    width: float = 6.6,
    height: float = 4.0,
) -> str:
    """One axis' Allan deviation with its intervals, fitted and conservative models, as SVG text.

    Parameters
    ----------
    result : AllanResult
        The curve (drawn with its confidence bars when it has them).
    fit : NoiseCoefficients, optional
        Best-fit coefficients: their model is drawn as a solid line.
    conservative : ConservativeCoefficients, optional
        Conservative set: its model (dashed) and the upper confidence bounds it overbounds.
    title : str, optional
        Axes title.
    width, height : float
        Figure size in inches.

    Returns
    -------
    str
        A standalone ``<svg>`` element; text is drawn as paths (no font files needed) and ids
        are deterministic.
    """
    items = _as_list(result)
    matplotlib = _require_matplotlib()
    import io

    from matplotlib.figure import Figure

    with matplotlib.rc_context({"svg.fonttype": "path", "svg.hashsalt": "gyrobias"}):
        fig = Figure(figsize=(width, height), layout="constrained")
        ax = fig.add_subplot()
        r = items[0]
        bars = (
            f" ({100 * r.confidence:.3g} % intervals)"
            if r.confidence is not None and r.ci_low is not None
            else ""
        )
        _draw(ax, items, [f"measured{bars}"], title, True, {"color": "0.25"})
        lo, hi = float(r.taus[0]), float(r.taus[-1])
        grid = np.geomspace(lo, hi, 200)
        if fit is not None:
            total, _ = fit.model(grid)
            ax.loglog(grid, total, "-", color="tab:blue", lw=1.6, label=f"{fit.method} fit")
        if conservative is not None:
            total, _ = conservative.coefficients.model(grid)
            level = f"{100 * conservative.confidence:.3g} %"
            ax.loglog(grid, total, "--", color="tab:red", lw=1.6, label=f"conservative ({level})")
            ax.loglog(
                conservative.taus,
                conservative.upper_bound,
                "v",
                color="tab:red",
                ms=4,
                mfc="none",
                label=f"{level} upper bound",
            )
        ax.legend(fontsize=8, loc="best")
        buf = io.StringIO()
        fig.savefig(buf, format="svg", metadata={"Date": None, "Creator": None})
    text = buf.getvalue()
    return text[text.index("<svg") :]


# --- the result objects' ``.plot()`` methods ------------------------------------------------------


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
    _require_matplotlib()
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


@_generics.plot.register(WaveletVariance)
def _plot_wvar(result: WaveletVariance, ax: Any = None, **kwargs: Any) -> Any:
    return plot_wvar(result, ax=ax, **kwargs)


@_generics.plot.register(AllanResult)
def _plot_allan_result(
    result: AllanResult, ax: Any = None, *, label: str | None = None, fit: Any = None, **kwargs: Any
) -> Any:
    if fit is True:
        fit = fit_noise(result)
    fits = None if fit is None or fit is False else [fit]
    return plot_allan([result], ax=ax, labels=[label] if label else None, fits=fits, **kwargs)


@_generics.plot.register(DynamicAllanResult)
def _plot_dynamic_result(result: DynamicAllanResult, ax: Any = None, **kwargs: Any) -> Any:
    return plot_dynamic_allan(result, ax=ax, **kwargs)


@_generics.plot.register(NoiseCoefficients)
def _plot_coefficients(
    coefficients: NoiseCoefficients,
    ax: Any = None,
    *,
    allan: AllanResult | None = None,
    show_data: bool = True,
) -> Any:
    return plot_noise_model(coefficients, ax, allan=allan, show_data=show_data)
