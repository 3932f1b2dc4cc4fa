"""Shared by the plotting modules: statistic names, the matplotlib import, atomic saving."""

from __future__ import annotations

import os
from typing import Any

from gyrobias._files import atomic_binary
from gyrobias._validation import (
    checked_path,
    instance,
    integer,
    optional_text,
    positive_float,
    sequence,
    text,
)

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


def _sensor_title(unit: str | None) -> str:
    """Panel title of a unit's results: ``"gyroscope [rad/s]"``, ``"accelerometer [m/s^2]"``."""
    from gyrobias.units import sensor_kind

    try:
        kind = sensor_kind(unit or "")
    except ValueError:
        return f"[{unit}]" if unit else "no unit"
    return f"{'gyroscope' if kind == 'gyro' else 'accelerometer'} [{unit}]"


def check_axes(name: str, ax: Any) -> Any:
    """``ax`` if it is ``None`` or a matplotlib ``Axes``, else ``TypeError`` naming ``name``
    (checked before drawing, not as ``'str' object has no attribute 'errorbar'``)."""
    if ax is None:
        return None
    from matplotlib.axes import Axes

    return instance(name, ax, Axes, "a matplotlib Axes or None")


def check_figure(name: str, fig: Any) -> Any:
    """``fig`` if it is ``None`` or a matplotlib ``Figure`` (or ``SubFigure``), else ``TypeError``."""
    if fig is None:
        return None
    from matplotlib.figure import FigureBase

    return instance(name, fig, FigureBase, "a matplotlib Figure or None")


def check_output(path: Any) -> Any:
    """The image file ``path`` (:func:`gyrobias._validation.checked_path`), checked before
    anything is drawn."""
    return checked_path("path", path)


#: Largest figure side (inches) and resolution (dots per inch) drawn: beyond them matplotlib's
#: font rasteriser fails (``invalid ppem value``) or the image cannot be allocated.
_MAX_INCHES = 200.0
_MAX_DPI = 10_000
#: Smallest resolution drawn: below it the smallest labels (7 pt) are under one pixel per em
#: and matplotlib's font rasteriser fails (``FT_Set_Char_Size … invalid ppem value``).
_MIN_DPI = 12


def _check_dpi(dpi: Any) -> int:
    d = integer("dpi", dpi)
    if not _MIN_DPI <= d <= _MAX_DPI:
        raise ValueError(f"dpi must be an integer from {_MIN_DPI} to {_MAX_DPI}, got {d}")
    return d


def _check_inches(name: str, value: Any) -> float:
    v = positive_float(name, value)
    if v > _MAX_INCHES:
        raise ValueError(f"{name} must be finite, > 0 and at most {_MAX_INCHES:g} inches, got {v}")
    return v


def _save_atomically(fig: Any, path: str | os.PathLike[str], dpi: int) -> None:
    """``fig.savefig`` through :func:`gyrobias._files.atomic_binary` (a temporary file beside
    ``path``, renamed over it); the image format comes from the suffix, as ``savefig(path)``."""
    _check_dpi(dpi)
    suffix = os.path.splitext(os.fspath(path))[1][1:].lower()
    with atomic_binary(path) as fh:
        fig.savefig(fh, dpi=dpi, format=suffix or None)


def check_texts(title: object = None, labels: object = None, label: object = None) -> None:
    """The free text a plot shows (``title``, ``labels``, ``label``): one printable line each
    (:func:`gyrobias._validation.text`), checked before anything is drawn."""
    optional_text("title", title)
    optional_text("label", label)
    if labels is not None:
        for i, item in enumerate(sequence("labels", labels)):
            text(f"labels[{i}]", item)
