"""Hostile input, class by class, over the whole public API (issue 27).

The registry (``tests/hostile_registry.py``) classifies every parameter of every public function
and method by kind; each test below takes one class of hostile input and throws it at every
member of the class, so a new function joins every test of its parameters' kinds as soon as it
is registered — and the first test fails until it is. The accepted outcomes are a valid result
or a ``ValueError``/``TypeError`` whose message names the argument (``<arg> must be …, got …``);
anything else (``KeyError``, NumPy's "setting an array element with a sequence", a result with
NaN/inf the caller did not put in, a traceback on the command line) fails.

``BASE`` gives each function a valid call; a hostile value replaces one argument of it.
"""

from __future__ import annotations

import bz2
import contextlib
import functools
import gzip
import io as _io
import json
import lzma
import math
import os
import re
import subprocess
import sys
import warnings
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import gyrobias
from gyrobias import (
    allan,
    cleaning,
    datasheet,
    exports,
    fir,
    fractional,
    kalman,
    noise,
    predict,
    spectral,
    thermal,
    units,
)
from gyrobias import io as gio
from gyrobias.cli import main as cli_main
from tests.hostile_registry import KINDS, REGISTRY, entries, kinds_of, parameters, public_api

# --- fixtures: small valid inputs ---------------------------------------------------------------


class _Fixtures:
    """Valid inputs built once (lazily): the base of every hostile call."""

    @functools.cached_property
    def rate(self) -> np.ndarray:
        return noise.simulate(4000, 100.0, arw=0.01, rrw=1e-3, seed=2)

    @functools.cached_property
    def allan(self) -> Any:
        return allan.adev(self.rate, 100.0, units="deg/s")

    @functools.cached_property
    def coefficients(self) -> Any:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return noise.fit(self.allan)

    @functools.cached_property
    def datasheet(self) -> Any:
        return datasheet.from_datasheet(
            arw="0.2 deg/√h", bias_instability="5 deg/h", rrw="0.5 deg/h/√h", rate=200.0
        )

    @functools.cached_property
    def gyro(self) -> Any:
        """Coefficients with every term an estimator file needs."""
        return self.datasheet.gyro

    @functools.cached_property
    def lowpass(self) -> Any:
        return fir.kaiser_lowpass(100.0, 10.0, 20.0, astop_db=40.0)

    @functools.cached_property
    def kalman(self) -> Any:
        return kalman.FixedGainKalman(100.0, arw=0.01, rrw=1e-4, q_omega=1e-6)

    @functools.cached_property
    def predictor(self) -> Any:
        return predict.FractionalKalmanPredictor(d=0.4)

    @functools.cached_property
    def evaluation(self) -> Any:
        # 10 sections: enough for the bootstrap of Evaluation.ratio to run
        return predict.evaluate(self.rate[:1500], calibration=100, horizon=50)

    @functools.cached_property
    def elw(self) -> Any:
        return fractional.elw(fractional.arfima(500, 0.3, seed=1))

    @functools.cached_property
    def model(self) -> Any:
        return thermal.TemperatureModel(
            temperatures=np.array([0.0, 20.0, 40.0]),
            parameters={"arw": np.array([1.0, 2.0, 3.0])},
        )

    @functools.cached_property
    def log(self) -> Any:
        path = _tmp() / "log.npy"
        np.save(path, self.rate[:, None])
        return gio.load(path, fs=100.0, units="deg/s")


_TMP: list[Path] = []


def _tmp() -> Path:
    return _TMP[0]


@pytest.fixture(autouse=True, scope="module")
def _module_tmp(tmp_path_factory: pytest.TempPathFactory) -> Any:
    _TMP.insert(0, tmp_path_factory.mktemp("hostile"))
    yield
    _TMP.pop(0)


FX = _Fixtures()


def _bound(attr: str, factory: Callable[[], Any]) -> Callable[..., Any]:
    return lambda **kw: getattr(factory(), attr)(**kw)


#: A valid call of every registered function whose parameters a class test exercises:
#: ``key: (callable, base keyword arguments)`` (built lazily).
BASE: dict[str, Callable[[], tuple[Callable[..., Any], dict[str, Any]]]] = {
    **{
        f"allan.{k}": (lambda k=k: (getattr(allan, k), {"data": FX.rate[:1000], "fs": 100.0}))
        for k in ("adev avar hdev mdev totdev tdev mtotdev htotdev theo1 theobr theoh".split())
    },
    "allan.adev_batch": lambda: (
        allan.adev_batch,
        {"data": FX.rate[:1000].reshape(2, 500), "fs": 100.0},
    ),
    "allan.dynamic_adev": lambda: (
        allan.dynamic_adev,
        {"data": FX.rate, "fs": 100.0, "window": 1000, "step": 500},
    ),
    "allan.stationarity": lambda: (allan.stationarity, {"data": FX.rate, "fs": 100.0}),
    "allan.Disturbance.shifted": lambda: (
        allan.Disturbance("step", 1.0, 2.0, 1.5, 0.8, "deg/s", 100.0, 7.0, 0.5).shifted,
        {"offset_s": 10.0},
    ),
    "allan.AllanResult.in_log_time": lambda: (
        allan.adev(FX.rate, 100.0).in_log_time,
        {"offset_s": 10.0},
    ),
    "allan.Stationarity.shifted": lambda: (
        allan.stationarity(FX.rate, 100.0).shifted,
        {"offset_s": 10.0},
    ),
    "codegen.emit_fir": lambda: (
        gyrobias.codegen.emit_fir,
        {"f": FX.lowpass, "path": _tmp() / "cfir"},
    ),
    "codegen.emit_kalman": lambda: (
        gyrobias.codegen.emit_kalman,
        {"kf": FX.kalman, "path": _tmp() / "ckf"},
    ),
    "codegen.emit_predictor": lambda: (
        gyrobias.codegen.emit_predictor,
        {"cp": FX.predictor.compile(50, 5), "path": _tmp() / "cpred"},
    ),
    "fir.KaiserLowpass.to_c": lambda: (FX.lowpass.to_c, {"path": _tmp() / "cfir2"}),
    "kalman.FixedGainKalman.to_c": lambda: (FX.kalman.to_c, {"path": _tmp() / "ckf2"}),
    "predict.CompiledPredictor.to_c": lambda: (
        FX.predictor.compile(50, 5).to_c,
        {"path": _tmp() / "cpred2"},
    ),
    "conservative.ConservativeCoefficients.export": lambda: (
        FX.coefficients.conservative().export,
        {"fmt": "json"},
    ),
    "conservative.conservative": lambda: (
        gyrobias.conservative.conservative,
        {"coefficients": FX.coefficients},
    ),
    "datasheet.Datasheet.discrete": lambda: (FX.datasheet.discrete, {}),
    "datasheet.Datasheet.export": lambda: (FX.datasheet.export, {"fmt": "kalibr"}),
    "datasheet.Datasheet.export_all": lambda: (FX.datasheet.export_all, {}),
    "datasheet.from_datasheet": lambda: (
        datasheet.from_datasheet,
        {"arw": "0.2 deg/√h", "rate": 200.0},
    ),
    "exports.atomic_write": lambda: (exports.atomic_write, {"path": _tmp() / "a.txt", "text": "x"}),
    "exports.discrete": lambda: (exports.discrete, {"coefficients": FX.gyro, "rate": 200.0}),
    "exports.export": lambda: (exports.export, {"gyro": FX.gyro, "fmt": "kalibr"}),
    "exports.export_all": lambda: (exports.export_all, {"gyro": FX.gyro}),
    "fir.KaiserLowpass.apply": lambda: (FX.lowpass.apply, {"x": FX.rate[:500]}),
    "fir.KaiserLowpass.frequency_response": lambda: (FX.lowpass.frequency_response, {}),
    "fir.apply": lambda: (fir.apply, {"taps": FX.lowpass.taps, "x": FX.rate[:500]}),
    "cleaning.remove_outliers": lambda: (cleaning.remove_outliers, {"data": FX.rate[:500]}),
    "cleaning.detrend": lambda: (cleaning.detrend, {"data": FX.rate[:500], "fs": 100.0}),
    "cleaning.minmax_envelope": lambda: (
        cleaning.minmax_envelope,
        {"data": FX.rate[:500], "bins": 10},
    ),
    "cleaning.clean": lambda: (
        cleaning.clean,
        {"data": FX.rate[:500], "fs": 100.0, "outliers": 5.0, "detrend": "linear"},
    ),
    "fir.kaiser_lowpass": lambda: (
        fir.kaiser_lowpass,
        {"fs": 100.0, "fpass": 10.0, "fstop": 20.0, "astop_db": 40.0},
    ),
    "fir.stream": lambda: (fir.stream, {"taps": FX.lowpass.taps, "x": FX.rate[:500]}),
    "fleet.analyse": lambda: (
        gyrobias.fleet.analyse,
        {"sources": np.stack([FX.rate[:2000], FX.rate[2000:]]), "fs": 100.0, "num_workers": 1},
    ),
    "fleet.summary": lambda: (gyrobias.fleet.summary, {"table": _fleet_table()}),
    "fleet.write_table": lambda: (
        gyrobias.fleet.write_table,
        {"table": _fleet_table(), "path": _tmp() / "fleet.csv"},
    ),
    "fractional.ElwResult.confidence_interval": lambda: (FX.elw.confidence_interval, {}),
    "fractional.arfima": lambda: (fractional.arfima, {"n": 100, "d": 0.3, "seed": 1}),
    "fractional.diff": lambda: (fractional.diff, {"x": FX.rate[:300], "d": 0.3}),
    "fractional.elw": lambda: (fractional.elw, {"x": FX.rate[:300]}),
    "fractional.elw_objective": lambda: (
        fractional.elw_objective,
        {"x": FX.rate[:300], "d": [0.1, 0.2]},
    ),
    "fractional.integrate": lambda: (fractional.integrate, {"w": FX.rate[:300], "d": 0.3}),
    "fractional.weights": lambda: (fractional.weights, {"d": 0.3, "n": 10}),
    "io.GyroLog.__getitem__": lambda: (lambda name: FX.log[name], {"name": "col0"}),
    "io.load": lambda: (gio.load, {"path": FX.log.path, "fs": 100.0}),
    "io.resolve_selection": lambda: (
        gio.resolve_selection,
        {"n_samples": 1000, "fs": 100.0, "start": "1s", "time": np.arange(1000) / 100.0},
    ),
    "kalman.FixedGainKalman.__init__": lambda: (
        kalman.FixedGainKalman,
        {"fs": 100.0, "arw": 0.01, "rrw": 1e-4, "q_omega": 1e-6},
    ),
    "kalman.FixedGainKalman.filter": lambda: (FX.kalman.filter, {"z": FX.rate[:300]}),
    "kalman.FixedGainKalman.frequency_response": lambda: (
        FX.kalman.frequency_response,
        {"freqs": [1.0, 2.0]},
    ),
    "kalman.FixedGainKalman.initial_state": lambda: (FX.kalman.initial_state, {"z": FX.rate[:300]}),
    **{
        f"kalman.{k}": (lambda k=k, a=a: (getattr(kalman, k), {a: 1.0}))
        for k, a in (
            ("arw_from_deg_per_sqrt_hour", "arw"),
            ("q_omega_from_deg_per_hour", "q_omega"),
            ("q_omega_to_deg_per_hour", "q_omega"),
            ("rrw_from_deg_per_hour_1p5", "rrw"),
        )
    },
    "kalman.bandwidth_for_qomega": lambda: (
        kalman.bandwidth_for_qomega,
        {"q_omega": 1e-6, "fs": 100.0, "arw": 0.01, "rrw": 1e-4},
    ),
    "kalman.qomega_for_bandwidth": lambda: (
        kalman.qomega_for_bandwidth,
        {"bandwidth": 5.0, "fs": 100.0, "arw": 0.01, "rrw": 1e-4},
    ),
    "kalman.riccati_gain": lambda: (
        kalman.riccati_gain,
        {"q_omega": 1.0, "q_b": 0.1, "r_d": 1.0},
    ),
    "kalman.steady_state_gain": lambda: (
        kalman.steady_state_gain,
        {"q_omega": 1.0, "q_b": 0.1, "r_d": 1.0},
    ),
    "noise.NoiseCoefficients.__getitem__": lambda: (
        lambda symbol: FX.gyro[symbol],
        {"symbol": "N"},
    ),
    "noise.NoiseCoefficients.conservative": lambda: (FX.coefficients.conservative, {}),
    "noise.NoiseCoefficients.discrete": lambda: (FX.gyro.discrete, {"rate": 200.0}),
    "noise.NoiseCoefficients.export": lambda: (FX.gyro.export, {"fmt": "kalibr"}),
    "noise.NoiseCoefficients.model": lambda: (FX.coefficients.model, {"taus": [0.1, 1.0]}),
    "noise.NoiseCoefficients.to_json": lambda: (FX.coefficients.to_json, {}),
    "noise.NoiseCoefficients.to_kalibr": lambda: (
        FX.gyro.to_kalibr,
        {"path": _tmp() / "k.yaml"},
    ),
    "noise.Term.to": lambda: (FX.gyro.N.to, {"unit": "deg/√h"}),
    "noise.fit": lambda: (noise.fit, {"allan": FX.allan}),
    "noise.gauss_markov_avar": lambda: (
        noise.gauss_markov_avar,
        {"sigma": 1.0, "correlation_time": 10.0, "taus": [1.0]},
    ),
    "noise.gmwm": lambda: (noise.gmwm, {"data": FX.rate[:2000], "fs": 100.0, "seed": 1}),
    "noise.simulate": lambda: (noise.simulate, {"n": 100, "fs": 100.0, "arw": 0.1, "seed": 1}),
    "noise.detect_lines": lambda: (noise.detect_lines, {"data": FX.rate[:2000], "fs": 100.0}),
    "noise.sinusoid_avar": lambda: (
        noise.sinusoid_avar,
        {"amplitude": 0.1, "frequency": 23.0, "taus": [0.01, 0.02], "fs": 100.0},
    ),
    "noise.wvar": lambda: (noise.wvar, {"data": FX.rate[:2000], "fs": 100.0, "robust": True}),
    "exports.write_kalibr": lambda: (
        gyrobias.exports.write_kalibr,
        {"path": _tmp() / "w.yaml", "gyro": [FX.gyro]},
    ),
    "plotting.allan_report_svg": lambda: (gyrobias.plotting.allan_report_svg, {"result": FX.allan}),
    "plotting.plot_dynamic_allan": lambda: (
        gyrobias.plotting.plot_dynamic_allan,
        {"result": allan.dynamic_adev(FX.rate, 100.0, window=1000, step=1000)},
    ),
    "plotting.save_allan_plot": lambda: (
        gyrobias.plotting.save_allan_plot,
        {"results": FX.allan, "path": _tmp() / "a.png"},
    ),
    "plotting.save_comparison_plot": lambda: (
        gyrobias.plotting.save_comparison_plot,
        {"before": [FX.allan], "after": [FX.allan], "path": _tmp() / "c.png"},
    ),
    "plotting.save_fleet_plot": lambda: (
        gyrobias.plotting.save_fleet_plot,
        {"table": _fleet_table(), "path": _tmp() / "f.png"},
    ),
    "plotting.save_noise_model_plot": lambda: (
        gyrobias.plotting.save_noise_model_plot,
        {"coefficients": FX.coefficients, "path": _tmp() / "n.png"},
    ),
    "plotting.save_prediction_plot": lambda: (
        gyrobias.plotting.save_prediction_plot,
        {
            "section": FX.rate[:150],
            "calibration": 100,
            "fs": 100.0,
            "forecasts": {"cm": np.zeros(50)},
            "path": _tmp() / "p.png",
        },
    ),
    "predict.CompiledPredictor.predict": lambda: (
        FX.predictor.compile(50, 5).predict,
        {"batch": FX.rate[:50]},
    ),
    "predict.Evaluation.ratio": lambda: (FX.evaluation.ratio, {"method": "kf"}),
    "predict.FractionalKalmanPredictor.__init__": lambda: (predict.FractionalKalmanPredictor, {}),
    "predict.FractionalKalmanPredictor.compile": lambda: (
        FX.predictor.compile,
        {"calibration_length": 50, "horizon": 5},
    ),
    "predict.FractionalKalmanPredictor.from_noise": lambda: (
        predict.FractionalKalmanPredictor.from_noise,
        {"fs": 100.0, "arw": 0.01, "bias_instability": 1e-3},
    ),
    "predict.FractionalKalmanPredictor.predict": lambda: (
        FX.predictor.predict,
        {"calibration": FX.rate[:50], "horizon": 5},
    ),
    "predict.calibration_mean": lambda: (
        predict.calibration_mean,
        {"y": FX.rate[:50], "horizon": 5},
    ),
    "predict.evaluate": lambda: (
        predict.evaluate,
        {"log": FX.rate[:600], "calibration": 100, "horizon": 50},
    ),
    "predict.integrated_error": lambda: (
        predict.integrated_error,
        {"y": FX.rate[:50], "yhat": FX.rate[50:100]},
    ),
    "predict.moving_average": lambda: (predict.moving_average, {"y": FX.rate[:50], "horizon": 5}),
    "predict.rsse": lambda: (predict.rsse, {"y": FX.rate[:50], "yhat": FX.rate[50:100]}),
    "report.build_report": lambda: (gyrobias.report.build_report, {"log": FX.log}),
    "report.write_report": lambda: (
        gyrobias.report.write_report,
        {"path": _tmp() / "r.html", "log": FX.log},
    ),
    "spectral.lssa": lambda: (
        spectral.lssa,
        {"t": np.arange(80.0), "y": np.sin(np.arange(80.0))},
    ),
    "spectral.noise_density": lambda: (spectral.noise_density, {"x": FX.rate, "fs": 100.0}),
    "spectral.psd": lambda: (spectral.psd, {"x": FX.rate, "fs": 100.0}),
    "thermal.TemperatureModel.__call__": lambda: (FX.model, {"name": "arw", "temperature": 10.0}),
    "thermal.TemperatureModel.__init__": lambda: (
        thermal.TemperatureModel,
        {"temperatures": np.array([0.0, 20.0, 40.0]), "parameters": {"arw": [1.0, 2.0, 3.0]}},
    ),
    "thermal.TemperatureModel.evaluate": lambda: (FX.model.evaluate, {"temperature": 10.0}),
    "thermal.TemperatureModel.from_analyses": lambda: (
        thermal.TemperatureModel.from_analyses,
        {"analyses": [_thermal_analysis(0.0), _thermal_analysis(20.0)]},
    ),
    "thermal.TemperatureModel.from_json": lambda: (
        thermal.TemperatureModel.from_json,
        {"text": FX.model.to_json()},
    ),
    "thermal.analyse_log": lambda: (
        thermal.analyse_log,
        {"x": FX.rate, "fs": 100.0, "temperature": 25.0},
    ),
    "thermal.analyse_logs": lambda: (
        thermal.analyse_logs,
        {"logs": {20.0: FX.rate, 40.0: FX.rate}, "fs": 100.0},
    ),
    "thermal.build_temperature_model": lambda: (
        thermal.build_temperature_model,
        {"logs": {20.0: FX.rate, 40.0: FX.rate}, "fs": 100.0},
    ),
    "thermal.fit_ar1": lambda: (thermal.fit_ar1, {"x": FX.rate}),
    "units.base_unit": lambda: (units.base_unit, {"data_unit": "deg/s", "symbol": "N"}),
    "units.conversion_factor": lambda: (
        units.conversion_factor,
        {"from_unit": "deg/s", "to_unit": "rad/s"},
    ),
    "units.parse_unit": lambda: (units.parse_unit, {"text": "deg/s"}),
    "units.sensor_kind": lambda: (units.sensor_kind, {"data_unit": "deg/s"}),
}


@functools.cache
def _fleet_table() -> Any:
    pytest.importorskip("pandas")
    return gyrobias.fleet.analyse(
        np.stack([FX.rate[:2000], FX.rate[2000:], 1.1 * FX.rate[:2000]]), fs=100.0, num_workers=1
    )


def _thermal_analysis(temperature: float) -> Any:
    return thermal.analyse_log(FX.rate, 100.0, temperature)


# --- classification -----------------------------------------------------------------------------

#: (registry key, parameter) pairs a class test leaves out, with the reason.
UNCHECKED: dict[tuple[str, str], str] = {
    ("thermal.TemperatureModel.__call__", "temperature"): "an array of temperatures (kind array)",
    ("fractional.elw_objective", "d"): "a grid of d values to evaluate (kind array)",
}


def _outcome(call: Callable[[], Any], name: str) -> str:
    """``"ok"``, or the refusal's class after checking that its message names ``name``."""
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            result = call()
    except (ValueError, TypeError) as exc:
        message = str(exc)
        assert re.search(rf"(?<![A-Za-z0-9]){re.escape(name)}(?![A-Za-z0-9])", message), (
            f"{type(exc).__name__} does not name {name!r}: {message}"
        )
        assert "setting an array element with a sequence" not in message, message
        return "ValueError" if isinstance(exc, ValueError) else "TypeError"
    _assert_no_garbage(result)
    return "ok"


def _assert_no_garbage(result: Any) -> None:
    """A result holds no NaN/inf (the callers here never put one in)."""
    values = []
    if isinstance(result, (float, np.floating)):
        values = [float(result)]
    elif isinstance(result, np.ndarray) and result.dtype.kind == "f":
        values = list(result.ravel()[:100000])
    assert all(math.isfinite(v) for v in values), f"non-finite result: {result!r}"


def _call(key: str, name: str, value: Any) -> str:
    assert key in BASE, f"{key}: add a valid call to BASE so its {name!r} can be tested"
    func, kwargs = BASE[key]()
    return _outcome(lambda: func(**{**kwargs, name: value}), name)


def _cases(kinds: tuple[str, ...], values: dict[str, list[Any]]) -> list[Any]:
    out = []
    for kind in kinds:
        for key, name, _ in entries(kind):
            if (key, name) in UNCHECKED or key.startswith("cli."):
                continue
            for value in values[kind]:
                out.append(pytest.param(key, name, value, id=f"{key}-{name}-{value!r}"))
    return out


# --- the registry -------------------------------------------------------------------------------


def test_registry_knows_every_public_function() -> None:
    """A public function or method unknown to the registry fails here: classify its
    parameters in ``tests/hostile_registry.py`` (one line) and it joins the class tests."""
    api = public_api()
    unknown = sorted(set(api) - set(REGISTRY))
    assert not unknown, f"public functions missing from the hostile registry: {unknown}"
    stale = sorted(set(REGISTRY) - set(api))
    assert not stale, f"registry entries for functions that are gone: {stale}"


def test_registry_knows_every_parameter() -> None:
    api = public_api()
    for key, func in api.items():
        assert set(parameters(func)) == set(kinds_of(key)), (
            f"{key}: parameters {parameters(func)} vs registry {list(kinds_of(key))}"
        )
        for name, (kind, _) in kinds_of(key).items():
            assert kind in KINDS, f"{key}: unknown kind {kind!r} of {name!r}"


# --- physical scalars ---------------------------------------------------------------------------

_SCALARS = {
    "pos": [math.nan, math.inf, -math.inf, 0.0, -1.0],
    "nonneg": [math.nan, math.inf, -math.inf, -1.0],
    "real": [math.nan, math.inf, -math.inf],
    "level": [math.nan, 0.0, 1.0, 1.5, -0.5],
}


@pytest.mark.parametrize(("key", "name", "value"), _cases(tuple(_SCALARS), _SCALARS))
def test_physical_scalars_refuse_nan_inf_and_out_of_domain(key: str, name: str, value: Any) -> None:
    """NaN, ±inf (and 0/negative where the physics says so) are a ValueError naming the
    argument — the unit helpers of ``kalman`` included."""
    outcome = _call(key, name, value)
    assert outcome == "ValueError", f"{key}({name}={value!r}) gave {outcome}"


_WRONG_TYPES = {k: [True, "1", [1.0, 2.0]] for k in _SCALARS}


@pytest.mark.parametrize(("key", "name", "value"), _cases(tuple(_SCALARS), _WRONG_TYPES))
def test_physical_scalars_refuse_wrong_types(key: str, name: str, value: Any) -> None:
    """``True`` (not 1.0), a numeric string, a list: TypeError or ValueError naming it.

    Datasheet values are strings with units by design: there a string is parsed, and an
    unparsable one is a ValueError naming the argument."""
    outcome = _call(key, name, value)
    assert outcome in ("TypeError", "ValueError"), f"{key}({name}={value!r}) gave {outcome}"


# --- counts, options, units, keys -----------------------------------------------------------------


@pytest.mark.parametrize(
    ("key", "name", "value"),
    _cases(("count", "axis"), {"count": [-1, 2.5, True, 2**70], "axis": [2.5, 99, -99, True]}),
)
def test_counts_and_axes(key: str, name: str, value: Any) -> None:
    outcome = _call(key, name, value)
    assert outcome in ("ValueError", "TypeError"), f"{key}({name}={value!r}) gave {outcome}"


@pytest.mark.parametrize(("key", "name", "value"), _cases(("option",), {"option": ["bogus", 3]}))
def test_options_refuse_unknown_names_and_list_the_valid_ones(
    key: str, name: str, value: Any
) -> None:
    func, kwargs = BASE[key]()
    with pytest.raises((ValueError, TypeError)) as info:
        func(**{**kwargs, name: value})
    message = str(info.value)
    assert name in message, message
    if isinstance(value, str):  # the valid names are listed after "must be" / "one of"
        rest = message.replace(repr(value), "")
        assert "one of" in rest or "'" in rest or " or " in rest, f"no valid names: {message}"


@pytest.mark.parametrize(
    ("key", "name", "value"), _cases(("unit",), {"unit": ["furlong", 3, "deg/s/s/s/"]})
)
def test_units_refuse_unknown_units(key: str, name: str, value: Any) -> None:
    outcome = _call(key, name, value)
    assert outcome in ("ValueError", "TypeError"), f"{key}({name}={value!r}) gave {outcome}"


@pytest.mark.parametrize(("key", "name", "value"), _cases(("key",), {"key": ["bogus", 3]}))
def test_lookups_by_name_are_value_errors_listing_the_names(
    key: str, name: str, value: Any
) -> None:
    """``Evaluation.ratio``, term symbols, parameter names: never KeyError/IndexError.

    (``GyroLog["name"]`` follows the mapping protocol: its ``KeyError`` lists the channels; a
    key that is not a string is a ``TypeError`` naming ``name``.)"""
    func, kwargs = BASE[key]()
    mapping_miss = key == "io.GyroLog.__getitem__" and isinstance(value, str)
    expected: Any = (KeyError,) if mapping_miss else (ValueError, TypeError)
    with pytest.raises(expected) as info:
        func(**{**kwargs, name: value})
    message = str(info.value)
    assert name in message or mapping_miss, message
    if isinstance(kwargs.get(name), str) and (mapping_miss or key != "io.GyroLog.__getitem__"):
        # a valid name is listed (GyroLog's TypeError for a non-string key says what a key is)
        assert kwargs[name] in message, f"no valid names listed: {message}"


# --- arrays, pairs, callables ---------------------------------------------------------------------


@pytest.mark.parametrize(
    ("key", "name", "value"),
    _cases(("array",), {"array": [[[1.0, 2.0], [3.0]], "abc", [1 + 2j, 3.0]]}),
)
def test_arrays_refuse_ragged_and_non_numeric_input(key: str, name: str, value: Any) -> None:
    """A ragged list or a string: an error naming the argument, not NumPy's message."""
    outcome = _call(key, name, value)
    assert outcome in ("ValueError", "TypeError"), f"{key}({name}={value!r}) gave {outcome}"


@pytest.mark.parametrize(
    ("key", "name", "value"), _cases(("pair",), {"pair": [(1.0, 2.0, 3.0), 5.0, "ab"]})
)
def test_pairs_are_exactly_two_numbers(key: str, name: str, value: Any) -> None:
    outcome = _call(key, name, value)
    assert outcome in ("ValueError", "TypeError"), f"{key}({name}={value!r}) gave {outcome}"


@pytest.mark.parametrize(
    ("key", "name", "value"), _cases(("callable",), {"callable": [5, "print"]})
)
def test_callbacks_are_checked_up_front(key: str, name: str, value: Any) -> None:
    func, kwargs = BASE[key]()
    with pytest.raises(TypeError, match=rf"^{name} must be callable"):
        func(**{**kwargs, name: value})


# --- files ------------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("key", "name", "value"),
    _cases(("json",), {"json": ["{bad", '{"a": 1', "[1, 2]", "\udcff", 5]}),
)
def test_json_loaders_name_the_position(key: str, name: str, value: Any) -> None:
    func, kwargs = BASE[key]()
    with pytest.raises((ValueError, TypeError)) as info:
        func(**{**kwargs, name: value})
    assert name in str(info.value) or "line" in str(info.value), str(info.value)


@pytest.mark.parametrize(("key", "name", "value"), _cases(("path_out",), {"path_out": ["x"]}))
def test_writers_name_the_callers_path(key: str, name: str, value: Any) -> None:
    """A path in a directory that does not exist: the error names that path, never the hidden
    temporary file written beside it."""
    func, kwargs = BASE[key]()
    target = _tmp() / "no" / "such" / "dir" / "out.txt"
    try:
        func(**{**kwargs, name: target})
    except (OSError, ValueError) as exc:
        message = str(exc)
        assert ".tmp" not in message, message
        assert "no/such/dir" in message or "no" in message, message
    else:
        # writers that create their directory must have written the file there
        assert target.exists() or target.parent.exists()


def test_writers_never_replace_a_device_or_a_directory() -> None:
    """Output to /dev/null is written in place (renaming a temporary file over it, as root,
    replaced the device node with a regular file); a directory is refused naming it."""
    import stat

    from gyrobias._files import atomic_write

    atomic_write("/dev/null", "x")
    assert stat.S_ISCHR(os.stat("/dev/null").st_mode)
    with pytest.raises(IsADirectoryError, match=re.escape(str(_tmp()))):
        atomic_write(_tmp(), "x")


_CORRUPT = {
    "gz": b"\x1f\x8b\x08\x00garbage-not-deflate",
    "bz2": b"BZh91AY&SYgarbage",
    "xz": b"\xfd7zXZ\x00garbage",
    "npy": b"\x93NUMPY\x01\x00garbage",
    "csv": b"\x00\xff\xfe\x00binary",
    "bag": b"#ROSBAG V2.0\ngarbage",
    "mcap": b"\x89MCAP0\r\ngarbage",
}


@pytest.mark.parametrize("suffix", list(_CORRUPT))
def test_corrupt_files_are_one_value_error_naming_the_file(suffix: str) -> None:
    path = _tmp() / f"corrupt.{'csv.' if suffix in ('gz', 'bz2', 'xz') else ''}{suffix}"
    path.write_bytes(_CORRUPT[suffix])
    with pytest.raises((ValueError, ImportError)) as info:
        gio.load(path, fs=100.0)
    assert path.name in str(info.value), str(info.value)


def test_valid_compressed_logs_still_load() -> None:
    text = "t,gx\n" + "".join(f"{i / 100},{v}\n" for i, v in enumerate(FX.rate[:200]))
    for suffix, opener in (("gz", gzip.open), ("bz2", bz2.open), ("xz", lzma.open)):
        path = _tmp() / f"ok.csv.{suffix}"
        with opener(path, "wt") as f:
            f.write(text)
        assert gio.load(path).data.shape == (200, 1)


@pytest.mark.parametrize("kind", ["directory", "null", "zero", "fifo"])
def test_special_files_are_refused(kind: str) -> None:
    """Directories (that are not ROS2 bags), devices and FIFOs: a ValueError/OSError naming
    the path, in a subprocess with a timeout (a FIFO must not block, /dev/zero not be read)."""
    if kind == "fifo" and not hasattr(os, "mkfifo"):
        pytest.skip("no FIFOs here")
    target = {
        "directory": str(_tmp()),
        "null": "/dev/null",
        "zero": "/dev/zero",
        "fifo": str(_tmp() / "fifo.csv"),
    }[kind]
    if kind == "fifo" and not os.path.exists(target):
        os.mkfifo(target)
    script = (
        "import gyrobias.io as g, sys\n"
        "try:\n"
        f"    g.load({target!r}, fs=100.0)\n"
        "except (ValueError, OSError) as e:\n"
        "    print(type(e).__name__, e)\n"
    )
    proc = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, timeout=60
    )
    assert proc.returncode == 0 and "Traceback" not in proc.stderr, proc.stderr[-2000:]
    assert os.path.basename(target) in proc.stdout, proc.stdout


def test_temperature_model_json_errors() -> None:
    with pytest.raises(ValueError, match=r"line 1, column 2"):
        thermal.TemperatureModel.from_json("{bad")
    with pytest.raises(ValueError, match="parameters"):
        thermal.TemperatureModel.from_json('{"temperatures": [0, 1], "parameters": [1, 2]}')
    with pytest.raises(ValueError, match="temperatures"):
        thermal.TemperatureModel.from_json('{"parameters": {}}')


# --- strings written into files ---------------------------------------------------------------------

_INJECTIONS = ["a\nb: c", "x: [1", "'; rm -rf /", "a\x00b", "</script><b>", "#comment"]


@pytest.mark.parametrize("value", _INJECTIONS)
def test_rostopic_cannot_inject_into_estimator_files(value: str) -> None:
    """``export_all(c, rostopic="a\\nb: c")`` must not add a key: refused, or quoted so that the
    file parses back to exactly the given topic."""
    yaml = pytest.importorskip("yaml")
    out = _tmp() / f"inject{abs(hash(value))}"
    try:
        exports.export_all(FX.gyro, out, rostopic=value)
    except ValueError as exc:
        assert "rostopic" in str(exc)
        return
    for path in out.iterdir():
        text = path.read_text()
        if path.suffix == ".yaml":
            doc = yaml.safe_load(text.replace("%YAML:1.0", "", 1))
            flat = json.dumps(doc)
            assert '"b"' not in flat, (path.name, doc)
        elif path.suffix == ".json":
            json.loads(text)


def test_kalibr_writer_topic_is_quoted_or_refused() -> None:
    yaml = pytest.importorskip("yaml")
    path = _tmp() / "kal.yaml"
    for value in _INJECTIONS:
        try:
            noise.write_kalibr(path, gyro=[FX.gyro], rostopic=value)
        except ValueError as exc:
            assert "rostopic" in str(exc)
            continue
        doc = yaml.safe_load(path.read_text())
        assert doc["rostopic"] == value and "b" not in doc


@pytest.mark.parametrize("value", [*_INJECTIONS, "x; system", "__reserved", "a b", "1abc"])
def test_c_names_cannot_inject_into_generated_c(value: str) -> None:
    """A name written into generated C is a C identifier, or refused naming ``name``."""
    for emit in (FX.lowpass.to_c, FX.kalman.to_c):
        with pytest.raises(ValueError, match=r"^name must"):
            emit(_tmp() / "inject_c", name=value)


def test_report_title_is_escaped() -> None:
    page = gyrobias.report.build_report(FX.log, title="</title><script>alert(1)</script>")
    assert "<script>alert(1)" not in page


# --- extremes: computed or refused, never NaN ------------------------------------------------------

_X = np.random.default_rng(1).normal(size=2000)

EXTREMES: dict[str, Callable[[], Any]] = {
    **{
        f"{k} fs={fs:g}": (lambda k=k, fs=fs: getattr(allan, k)(_X[:600], fs, confidence=None).adev)
        for k in "adev mdev hdev totdev tdev mtotdev htotdev theo1 theobr theoh".split()
        for fs in (1e286, 1e235, 1e-300, 1e300, 1e-200)
    },
    "adev angle fs=1e-300": lambda: allan.adev(np.cumsum(_X), 1e-300, data_type="angle").adev,
    "adev angle fs=1e300": lambda: allan.adev(np.cumsum(_X), 1e300, data_type="angle").adev,
    "gauss_markov_avar tau=1e-300": lambda: noise.gauss_markov_avar(1.0, 10.0, [1e-300]),
    "gauss_markov_avar tau=1e300": lambda: noise.gauss_markov_avar(1.0, 10.0, [1e300]),
    "simulate bias_instability=1e155": lambda: noise.simulate(
        1000, 100.0, bias_instability=1e155, seed=1
    ),
    "simulate arw=1e150": lambda: noise.simulate(1000, 100.0, arw=1e150, seed=1),
    "model tau=1e-300": lambda: FX.coefficients.model([1e-300])[0],
    "model tau=1e300": lambda: FX.coefficients.model([1e300])[0],
    "rsse 1e200": lambda: predict.rsse(np.full(4, 1e200), np.zeros(4)),
    "kalman unit 1e308": lambda: kalman.q_omega_to_deg_per_hour(1e308),
    "fractional.diff d=3e16": lambda: fractional.diff(_X[:300], 3e16),
    "fractional.weights d=3e16": lambda: fractional.weights(3e16, 10),
    "psd fs=1e286": lambda: spectral.psd(_X, 1e286).psd,
    "fit_ar1 fs=1e286": lambda: thermal.fit_ar1(_X, 1e286).sigma_e,
}


@pytest.mark.parametrize("case", list(EXTREMES))
def test_extremes_are_computed_or_refused(case: str) -> None:
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            result = np.asarray(EXTREMES[case](), dtype=np.float64)
    except ValueError as exc:
        assert str(exc)
        return
    assert np.isfinite(result).all(), f"{case}: {result}"


def test_extreme_sample_rate_gives_the_ordinary_rate_data_result() -> None:
    """For rate data the deviations do not depend on fs: fs = 1e286 gives the fs = 1 values."""
    for k in ("adev", "mdev", "hdev", "totdev", "mtotdev", "htotdev", "theo1"):
        ref = getattr(allan, k)(_X[:600], 1.0, confidence=None).adev
        for fs in (1e286, 2.0**-900):
            got = getattr(allan, k)(_X[:600], fs, confidence=None).adev
            np.testing.assert_allclose(got, ref, rtol=1e-12, err_msg=f"{k} fs={fs}")


def test_extreme_sample_rate_with_gaps_and_windows_gives_the_ordinary_result() -> None:
    """Gap-aware and dynamic ADEV split an extreme period like the other statistics do."""
    gapped = _X[:600].copy()
    gapped[[100, 257]] = np.nan
    ref = allan.adev(gapped, 1.0, gaps="omit", confidence=None).adev
    ref_dyn = allan.dynamic_adev(_X[:600], 1.0, window=200, step=100).avar
    for fs in (1e286, 2.0**-900):
        got = allan.adev(gapped, fs, gaps="omit", confidence=None).adev
        np.testing.assert_allclose(got, ref, rtol=1e-12, err_msg=f"gaps fs={fs}")
        dyn = allan.dynamic_adev(_X[:600], fs, window=200, step=100).avar
        np.testing.assert_allclose(dyn, ref_dyn, rtol=1e-12, err_msg=f"dynamic fs={fs}")


def test_model_curves_refuse_tau_without_value() -> None:
    for taus in (None, [0.0], [-1.0], [math.nan]):
        with pytest.raises((ValueError, TypeError), match="taus"):
            FX.coefficients.model(taus)


def test_fit_diagnostics_hold_no_nan() -> None:
    d = FX.coefficients.diagnostics
    if d is not None:
        assert np.isfinite(d.residuals).all(), d.residuals


# --- options that do not apply: refused all the same (NumPy/SciPy convention) --------------------

IGNORED_OPTIONS: dict[str, Callable[[], Any]] = {
    "adev per_decade=0 with octave": lambda: allan.adev(_X, 100.0, taus="octave", per_decade=0),
    "psd noverlap=-1 with default": lambda: spectral.psd(_X, 100.0, noverlap=-1),
    "fir.apply padlen=-1 causal": lambda: fir.apply(
        FX.lowpass.taps, _X, zero_phase=False, padlen=-1
    ),
    "analyse_log fpass=nan without prefilter": lambda: thermal.analyse_log(
        _X, 100.0, 25.0, prefilter=False, fpass=math.nan
    ),
    "kalman bandwidth=nan with q_omega": lambda: kalman.FixedGainKalman(
        100.0, arw=0.01, rrw=1e-4, q_omega=1e-6, bandwidth=math.nan
    ),
    "predict q=-1 with r=0": lambda: predict.FractionalKalmanPredictor(d=0.4, q=-1.0),
    "evaluate n_threads=-1": lambda: predict.evaluate(
        _X[:600], calibration=100, horizon=50, methods=("cm",), n_threads=-1
    ),
    "fleet.summary alpha=1.5": lambda: gyrobias.fleet.summary(_fleet_table(), alpha=1.5),
    "fleet.summary min_ratio=nan": lambda: gyrobias.fleet.summary(
        _fleet_table(), min_ratio=math.nan
    ),
    "noise_density band=(1,2,3)": lambda: spectral.noise_density(_X, 100.0, band=(1, 2, 3)),
    "report method": lambda: gyrobias.report.build_report(FX.log, method="bogus"),
    "report conservative_confidence=0": lambda: gyrobias.report.build_report(
        FX.log, conservative_confidence=0
    ),
    "report conservative_confidence=1.5": lambda: gyrobias.report.build_report(
        FX.log, conservative_confidence=1.5
    ),
    "report rate=-1": lambda: gyrobias.report.build_report(FX.log, rate=-1),
}


@pytest.mark.parametrize("case", list(IGNORED_OPTIONS))
def test_out_of_range_options_are_refused_even_when_ignored(case: str) -> None:
    with pytest.raises((ValueError, TypeError)):
        IGNORED_OPTIONS[case]()


def test_named_messages() -> None:
    """The messages the issue quoted as unclear, now naming the argument."""
    with pytest.raises(ValueError, match=r"axis=0"):
        FX.lowpass.apply(np.ones((5, 3)), axis=0)
    with pytest.raises(TypeError, match=r"^progress must be callable or None, got int"):
        allan.adev(_X, 100.0, progress=5)
    with pytest.raises(ValueError, match=r"^data "):
        allan.adev([[1.0, 2.0], [3.0]], 100.0)
    with pytest.raises(ValueError, match=r"^method must be one of 'kf', 'ma', 'cm'"):
        FX.evaluation.ratio("bogus")
    with pytest.raises((ValueError, TypeError), match=r"^system"):
        FX.coefficients.to(None)
    with pytest.raises((ValueError, TypeError), match=r"table"):
        gyrobias.fleet.write_table("abc", _tmp() / "t.csv")
    with pytest.raises(ValueError, match=r"^data is too short: 2 samples needed, 1 given"):
        allan.theo1(_X[:1], 100.0)  # rate samples, as given (not the angle series' count)


# --- the command line -------------------------------------------------------------------------------

_HOSTILE_NUMBERS = ["nan", "inf", "-inf", "xx", "", "1e999", "0x10"]
_HOSTILE_TEXT = ["", "a\nb", "\x00"]
#: Hostile values per argparse converter of gyrobias.cli._types (numbers for the others).
_HOSTILE_BY_TYPE = {
    "path": ["", "a\nb", "\x00"],
    "c_identifier": ["", "a b", "x;y", "1a", "a\nb"],
    "text": _HOSTILE_TEXT,
    "delimiter": ["xx", "", "1", "\n", "."],
    "column_list": ["", ",", "a,,b", "-1", "a\nb"],
    "unit_spec": ["furlong", "", "deg/s,", "gx=furlong"],
    "repair_spec": ["sort,", "bogus", "sort,sort,x"],
    "term_list": ["X", "", "N,N", "N,,B"],
    "export_spec": ["bogus=x", "kalibr", "=x", "kalibr="],
}


def _run(argv: list[str]) -> tuple[int, str]:
    out, err = _io.StringIO(), _io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = cli_main(argv)
    return code, err.getvalue()


def _subcommands() -> dict[str, Any]:
    from gyrobias.cli import build_parser

    parser = build_parser()
    found: dict[str, Any] = {}

    def walk(p: Any, prefix: list[str]) -> None:
        for action in p._actions:
            if action.__class__.__name__ == "_SubParsersAction":
                for name, sub in action.choices.items():
                    walk(sub, [*prefix, name])
        if prefix:
            found[" ".join(prefix)] = p

    walk(parser, [])
    return found


def _option_cases() -> list[Any]:
    cases = []
    for command, parser in _subcommands().items():
        for action in parser._actions:
            if not action.option_strings or action.nargs == 0 or action.dest == "help":
                continue
            option = max(action.option_strings, key=len)
            kind = getattr(action.type, "__name__", "")
            if action.choices is not None:
                values = ["bogus"]
            elif action.type is None:
                values = []  # free text the command interprets (none left: see the next test)
            else:
                values = _HOSTILE_BY_TYPE.get(kind, _HOSTILE_NUMBERS)
            if kind != "path":
                # a byte that is not UTF-8 in argv arrives as a lone surrogate (surrogateescape)
                values = [*values, "\udcff"]
            for value in values:
                cases.append(
                    pytest.param(command, option, value, id=f"{command} {option}={value!r}")
                )
    return cases


def _cli_log() -> Path:
    path = _tmp() / "cli.csv"
    if not path.exists():
        path.write_text(
            "t,gx,gy\n" + "".join(f"{i / 100},{v},{-v}\n" for i, v in enumerate(FX.rate[:400]))
        )
    return path


def _positionals(command: str) -> list[str]:
    log = str(_cli_log())
    return {
        "allan": [log],
        "predict": [log],
        "filter": [log, "--arw", "0.01"],
        "thermal": [f"{log}@20"],
        "fleet": [log],
        "report": [log],
    }.get(command.split()[0], [])


def test_every_cli_option_value_has_a_converter() -> None:
    """No option takes free text past the argument layer unchecked (argparse ``type=``)."""
    loose = [
        f"{command} {max(a.option_strings, key=len)}"
        for command, parser in _subcommands().items()
        for a in parser._actions
        if a.option_strings
        and a.nargs != 0
        and a.type is None
        and a.choices is None
        and a.dest not in ("help", "version")
    ]
    assert not loose, loose


@pytest.mark.parametrize(("command", "option", "value"), _option_cases())
def test_cli_option_values_are_one_line_exit_2(command: str, option: str, value: str) -> None:
    """Every option value of every subcommand: checked by the argument layer, one line
    ``gyrobias: error: …``, exit code 2, no traceback."""
    argv = [*command.split(), *_positionals(command), f"{option}={value}"]
    code, err = _run(argv)
    assert code == 2, (argv, code, err)
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("gyrobias: error: "), err
    assert "Traceback" not in err


def test_cli_delimiter_xx_is_an_option_error() -> None:
    code, err = _run(["allan", str(_cli_log()), "--delimiter", "xx"])
    assert code == 2 and err.startswith("gyrobias: error: --delimiter must be one character"), err


@pytest.mark.parametrize("kind", ["directory", "null", "zero", "fifo", "gz", "bz2", "xz", "npy"])
@pytest.mark.parametrize("command", ["allan", "predict", "filter", "report"])
def test_cli_hostile_files_give_one_line(command: str, kind: str) -> None:
    """Corrupt compressed files, directories, devices and FIFOs: exit 2 with one line (in a
    subprocess with a timeout: a FIFO must not block the command)."""
    tmp = _tmp()
    if kind in _CORRUPT:
        path = tmp / f"bad.{'csv.' if kind != 'npy' else ''}{kind}"
        path.write_bytes(_CORRUPT[kind])
    elif kind == "fifo":
        if not hasattr(os, "mkfifo"):
            pytest.skip("no FIFOs here")
        path = tmp / "cli_fifo.csv"
        if not path.exists():
            os.mkfifo(path)
    else:
        path = Path(
            {"directory": str(tmp / "emptydir"), "null": "/dev/null", "zero": "/dev/zero"}[kind]
        )
        if kind == "directory":
            path.mkdir(exist_ok=True)
    argv = [command, str(path), "--fs", "100"]
    if command == "filter":
        argv += ["--arw", "0.01"]
    if command == "report":
        argv += ["-o", str(tmp / "rep.html")]
    proc = subprocess.run(
        [sys.executable, "-m", "gyrobias", *argv], capture_output=True, text=True, timeout=60
    )
    assert proc.returncode == 2, (argv, proc.returncode, proc.stderr[-2000:])
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("gyrobias: error: "), proc.stderr[-2000:]


def test_cli_fit_and_export_failures_exit_2(tmp_path: Path) -> None:
    log = str(_cli_log())
    code, err = _run(["allan", log, "--export", "bogus=x.yaml"])
    assert code == 2 and err.startswith("gyrobias: error: --export must be FMT=PATH"), err
    code, err = _run(["allan", log, "--fs", "100", "--kalibr", str(tmp_path / "k.yaml")])
    assert code == 2 and err.startswith("gyrobias: error: --kalibr needs the data unit"), err
    code, err = _run(
        ["allan", log, "--units", "deg/s", "--export", f"vins={tmp_path}/no/such/dir/v.yaml"]
    )
    assert code == 2 and err.startswith("gyrobias: error: "), err
    assert err.count("\n") == 1 and ".tmp" not in err, err


def test_report_cli_refuses_bad_levels() -> None:
    for option, value in (("--conservative", "0"), ("--conservative", "1.5"), ("--rate", "-1")):
        code, err = _run(["report", str(_cli_log()), option, value])
        assert code == 2 and err.startswith(f"gyrobias: error: {option} must"), err
