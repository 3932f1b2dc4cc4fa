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

from typing import Any

from gyrobias import _generics
from gyrobias._validation import optional_instance, optional_text
from gyrobias.allan._types import AllanResult, DynamicAllanResult
from gyrobias.noise._types import NoiseCoefficients, WaveletVariance
from gyrobias.noise.fitting import fit as fit_noise
from gyrobias.plotting.deviations import plot_allan, plot_dynamic_allan, save_allan_plot
from gyrobias.plotting.fleets import plot_fleet, save_fleet_plot
from gyrobias.plotting.models import plot_noise_model, plot_wvar, save_noise_model_plot
from gyrobias.plotting.predictions import save_comparison_plot, save_prediction_plot
from gyrobias.plotting.report import allan_report_svg

__all__ = [
    # Allan-family deviations
    "plot_allan",
    "plot_dynamic_allan",
    "save_allan_plot",
    # noise models
    "plot_noise_model",
    "plot_wvar",
    "save_noise_model_plot",
    # fleets
    "plot_fleet",
    "save_fleet_plot",
    # predictions and filters
    "save_comparison_plot",
    "save_prediction_plot",
    # the report
    "allan_report_svg",
]

# --- the result objects' ``.plot()`` methods ------------------------------------------------------


@_generics.plot.register(AllanResult)
def _plot_allan_result(
    result: AllanResult, ax: Any = None, *, label: str | None = None, fit: Any = None, **kwargs: Any
) -> Any:
    optional_text("label", label)
    if fit is True:
        fit = fit_noise(result)
    elif fit is not False:
        optional_instance("fit", fit, NoiseCoefficients, "NoiseCoefficients, True")
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


@_generics.plot.register(WaveletVariance)
def _plot_wvar(result: WaveletVariance, ax: Any = None, **kwargs: Any) -> Any:
    return plot_wvar(result, ax=ax, **kwargs)
