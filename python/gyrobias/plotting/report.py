"""Figures of the HTML report (``gyrobias report``)."""

from __future__ import annotations

from typing import Any

import numpy as np

from gyrobias._validation import instance, optional_instance
from gyrobias.allan._types import AllanResult
from gyrobias.conservative import ConservativeCoefficients
from gyrobias.noise._types import NoiseCoefficients
from gyrobias.plotting._common import (
    _check_inches,
    _require_matplotlib,
    check_texts,
)
from gyrobias.plotting.deviations import _draw


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
    check_texts(title=title)
    items = [instance("result", result, AllanResult, "an AllanResult")]
    optional_instance("fit", fit, NoiseCoefficients, "NoiseCoefficients")
    optional_instance(
        "conservative", conservative, ConservativeCoefficients, "ConservativeCoefficients"
    )
    width = _check_inches("width", width)
    height = _check_inches("height", height)
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
