"""Bias predictions and filter comparisons."""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence

import numpy as np
from numpy.typing import NDArray

from gyrobias._validation import as_float_array, integer, sample_rate, sequence
from gyrobias.allan._types import AllanResult
from gyrobias.plotting._common import (
    _check_dpi,
    _require_matplotlib,
    _save_atomically,
    check_output,
    check_texts,
)
from gyrobias.plotting.deviations import _as_list


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
    check_texts(title=title)
    section = as_float_array("section", section)
    fs = sample_rate(fs)
    calibration = integer("calibration", calibration)
    if not 1 <= calibration < section.size:
        raise ValueError(
            f"calibration must be an integer from 1 to len(section) - 1 = {section.size - 1}, "
            f"got {calibration}"
        )
    h = section.size - calibration
    if not isinstance(forecasts, Mapping):
        raise TypeError(
            f"forecasts must be a mapping label → array, got {type(forecasts).__name__}"
        )
    curves = {str(k): as_float_array(f"forecasts[{k!r}]", v) for k, v in forecasts.items()}
    for k, v in curves.items():
        if v.size != h:
            raise ValueError(f"forecasts[{k!r}] must have {h} values, got {v.size}")
    if std is not None:
        std = as_float_array("std", std)
        if std.size != h:
            raise ValueError(f"std must have {h} values, got {std.size}")
    check_output(path)
    _check_dpi(dpi)
    _require_matplotlib()
    from matplotlib.figure import Figure

    t = np.arange(section.size) / fs
    tf = t[calibration:]
    fig = Figure(figsize=(8.0, 4.0), layout="constrained")
    ax = fig.add_subplot()
    ax.plot(t, section, color="0.6", lw=0.6, label="data")
    ax.axvline(t[calibration], color="k", lw=0.8, ls=":")
    for i, (label, forecast) in enumerate(curves.items()):
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
    check_texts(title=title, labels=labels)
    pair_of = sequence("labels", labels)
    if len(pair_of) != 2:
        raise ValueError(f"labels must be two labels (before, after), got {len(pair_of)}")
    before = _as_list(before, "before")
    after = _as_list(after, "after")
    check_output(path)
    _check_dpi(dpi)
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
