"""Allan-family deviation plots (with confidence bars and fitted models) and dynamic Allan maps."""

from __future__ import annotations

import os
from collections.abc import Sequence
from typing import Any

import numpy as np

from gyrobias._validation import instance, instances, sequence, string
from gyrobias.allan._types import AllanResult, DynamicAllanResult
from gyrobias.noise._types import NoiseCoefficients
from gyrobias.plotting._common import (
    _NAME,
    _SYMBOL,
    _check_dpi,
    _require_matplotlib,
    _save_atomically,
    _sensor_title,
    check_axes,
    check_output,
    check_texts,
)
from gyrobias.plotting.models import plot_noise_model


def _as_list(
    results: AllanResult | Sequence[AllanResult], name: str = "results"
) -> list[AllanResult]:
    """One AllanResult or a non-empty sequence of them (:func:`gyrobias._validation.instances`)."""
    return instances(name, results, AllanResult, "an AllanResult")


def _fits(fits: Any) -> list[NoiseCoefficients] | None:
    """``fits``: ``None`` or a sequence of NoiseCoefficients (one per result)."""
    if fits is None:
        return None
    items = sequence("fits", fits)
    for i, f in enumerate(items):
        instance(f"fits[{i}]", f, NoiseCoefficients, "NoiseCoefficients")
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
    check_texts(title=title, labels=labels)
    items = _as_list(results)
    _require_matplotlib()
    check_axes("ax", ax)
    fits = _fits(fits)
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
    check_texts(title=title, labels=labels)
    items = _as_list(results)
    check_output(path)
    _check_dpi(dpi)
    fits = _fits(fits)
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
    check_texts(title=title)
    instance("result", result, DynamicAllanResult, "a DynamicAllanResult")
    string("cmap", cmap)
    _require_matplotlib()
    check_axes("ax", ax)
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
