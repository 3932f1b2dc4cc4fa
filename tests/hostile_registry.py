"""The registry of gyrobias' public API for the hostile-input suite (``tests/test_hostile.py``).

Every public function and method — everything a public module lists in ``__all__``, and the
public methods (plus ``__init__``, ``__call__``, ``__getitem__``) of the public classes — has an
entry here that classifies each of its parameters by *kind*. The suite iterates over the kinds:
every parameter of kind ``pos`` gets NaN, ±inf, 0 and −1; every ``option`` an unknown name; every
``callable`` an int; and so on. A new public function (or a new parameter) that is not classified
here fails :func:`test_hostile.test_registry_knows_every_public_function` — classify it with one
line and it joins every class test of its kinds automatically.

Entries are one string ``"name:kind name:kind …"``; a kind ending in ``?`` also accepts
``None`` (its default). ``UNCHECKED`` lists (function, parameter) pairs deliberately left out of
a class test, each with its reason.
"""

from __future__ import annotations

import importlib
import inspect
import pkgutil
from collections.abc import Callable, Iterator
from typing import Any

import gyrobias

#: The kinds of parameters, and what the suite does with each.
KINDS: dict[str, str] = {
    "pos": "physical scalar, finite and > 0 (rate, frequency, time, attenuation): NaN, ±inf, 0, "
    "-1 → ValueError naming it; True, '1' → TypeError",
    "nonneg": "physical scalar, finite and >= 0 (noise density, variance, amplitude): NaN, ±inf, "
    "-1 → ValueError naming it",
    "real": "finite real number (bias, temperature, memory parameter d): NaN, ±inf → ValueError",
    "level": "probability / confidence level in (0, 1): 0, 1, 1.5, NaN → ValueError naming it",
    "count": "integer count, size, seed or index: -1 → ValueError, 2.5 → TypeError naming it",
    "axis": "an axis of an array (negative counts from the end): 2.5 → TypeError, 99 → "
    "ValueError naming it",
    "option": "a name from a fixed set: an unknown name → ValueError naming it and the valid names",
    "unit": "a unit string of gyrobias.units: 'furlong' → ValueError naming it",
    "array": "numeric array: a ragged list → ValueError naming it (never NumPy's own message)",
    "callable": "callback: an int → TypeError 'progress must be callable …'",
    "flag": "bool",
    "path_in": "a file read by a loader: corrupt content → one ValueError naming the file",
    "path_out": "a file or directory written atomically: errors name this path, not the temp file",
    "text": "a string written into a file (YAML, XML, MATLAB, HTML, C, plot labels): quoted, "
    "escaped or refused, checked by parsing the output back",
    "key": "a lookup key (term symbol, parameter name, channel, method): unknown → ValueError "
    "listing the valid names",
    "pair": "two numbers (low, high): three numbers or a scalar → error naming it",
    "json": "JSON text: invalid → ValueError naming line and column",
    "spec": "a structured option (term list, regions, load options, repair list, ar1 tuple, "
    "shape, taus list, temperature logs) checked by the function's own parser",
    "object": "a gyrobias object (result, log, coefficients, table, Axes, client)",
    "forwarded": "**kwargs passed on to a function that has its own entry here",
    "field": "field of a result record (constructed by gyrobias; stored as given, not validated)",
    "cli": "command-line internals (argparse parser / Namespace): driven by the CLI tests",
}

_ALLAN = (
    "data:array fs:pos taus:spec per_decade:count data_type:option confidence:level? "
    "units:unit? axis_names:text? progress:callable?"
)

#: Every public function and method, with the kind of each parameter.
REGISTRY: dict[str, str] = {
    # --- allan ----------------------------------------------------------------------------------
    "allan.AllanResult.__init__": "taus:field avar:field n_terms:field fs:field data_type:field "
    "kind:field overlapping:field unit:field confidence:field edf:field alpha:field "
    "ci_low:field ci_high:field axis:field noise_type:field factors:field deviation:field "
    "lines:field stationarity:field data_variance:field data_deviation:field",
    "allan.Disturbance.__init__": "kind:field start_s:field stop_s:field at_s:field size:field "
    "unit:field z:field threshold:field block_s:field",
    "allan.Disturbance.describe": "",
    "allan.Disturbance.shifted": "offset_s:real",
    "allan.Disturbance.to_dict": "",
    "allan.Stationarity.__init__": "disturbances:field checked:field n_samples:field fs:field "
    "quiet_s:field axis:field unit:field total_s:field",
    "allan.Stationarity.advice": "",
    "allan.Stationarity.shifted": "offset_s:real",
    "allan.Stationarity.to_dict": "",
    "allan.stationarity": "data:array fs:pos units:unit? axis_names:text?",
    "allan.AllanResult.plot": "ax:object? label:text? fit:object? kwargs:forwarded",
    "allan.AllanResult.in_log_time": "offset_s:real",
    "allan.AllanResult.table": "",
    "allan.AllanResult.to_dict": "",
    "allan.AllanResult.to_json": "kwargs:forwarded",
    "allan.DynamicAllanResult.__init__": "times:field starts:field taus:field avar:field "
    "n_terms:field window:field step:field fs:field data_type:field unit:field",
    "allan.DynamicAllanResult.plot": "ax:object? kwargs:forwarded",
    "allan.DynamicAllanResult.to_dict": "",
    "allan.adev": _ALLAN + " overlapping:flag gaps:option",
    "allan.avar": _ALLAN + " overlapping:flag gaps:option",
    "allan.hdev": _ALLAN + " overlapping:flag gaps:option",
    "allan.mdev": _ALLAN + " gaps:option",
    "allan.totdev": _ALLAN + " gaps:option",
    "allan.tdev": _ALLAN,
    "allan.mtotdev": _ALLAN,
    "allan.htotdev": _ALLAN,
    "allan.theo1": _ALLAN,
    "allan.theobr": _ALLAN,
    "allan.theoh": _ALLAN,
    "allan.adev_batch": _ALLAN + " overlapping:flag gaps:option",
    "allan.dynamic_adev": "data:array fs:pos window:count step:count taus:spec per_decade:count "
    "data_type:option units:unit?",
    # --- codegen ---------------------------------------------------------------------------------
    "codegen.GeneratedC.__init__": "header:field source:field name:field dtype:field "
    "state_bytes:field q31:field",
    "codegen.emit_fir": "f:object path:path_out name:text dtype:option full_scale:pos?",
    "codegen.emit_kalman": "kf:object path:path_out name:text dtype:option full_scale:pos?",
    "codegen.emit_predictor": "cp:object path:path_out name:text dtype:option full_scale:pos?",
    # --- conservative, datasheet, exports -------------------------------------------------------
    "conservative.ConservativeCoefficients.__init__": "coefficients:field best:field "
    "inflation:field confidence:field taus:field upper_bound:field edf:field ratio:field",
    "conservative.ConservativeCoefficients.export": "fmt:option path:path_out? kwargs:forwarded",
    "conservative.ConservativeCoefficients.summary": "",
    "conservative.ConservativeCoefficients.to_dict": "",
    "conservative.conservative": "coefficients:object confidence:level terms:spec?",
    "datasheet.Datasheet.__init__": "gyro:field accel:field rate:field conventions:field",
    "datasheet.Datasheet.discrete": "rate:pos?",
    "datasheet.Datasheet.export": "fmt:option path:path_out? rate:pos? rostopic:text",
    "datasheet.Datasheet.export_all": "directory:path_out? rate:pos? rostopic:text",
    "datasheet.Datasheet.summary": "",
    "datasheet.from_datasheet": "arw:nonneg? bias_instability:nonneg? rrw:nonneg? "
    "quantization:nonneg? rate_ramp:nonneg? noise_density:nonneg? vrw:nonneg? "
    "accel_bias_instability:nonneg? accel_random_walk:nonneg? accel_quantization:nonneg? "
    "accel_ramp:nonneg? accel_noise_density:nonneg? rate:pos? units:spec? density:option "
    "bias_instability_is:option gyro_unit:unit accel_unit:unit axis:text?",
    "exports.DiscreteNoise.__init__": "rate:field white:field bias_walk:field "
    "gauss_markov:field axis:field",
    "exports.DiscreteNoise.to_dict": "",
    "exports.DiscreteValue.__init__": "name:field value:field uncertainty:field unit:field "
    "formula:field",
    "exports.DiscreteValue.to_dict": "",
    "exports.atomic_write": "path:path_out text:text",
    "exports.discrete": "coefficients:object rate:pos",
    "exports.export": "gyro:object? fmt:option path:path_out? accel:object? rate:pos? "
    "rostopic:text strict:flag",
    "exports.export_all": "gyro:object? directory:path_out? accel:object? rate:pos? rostopic:text "
    "strict:flag",
    "exports.write_kalibr": "path:path_out gyro:spec accel:spec update_rate:pos? rostopic:text "
    "strict:flag",
    # --- fir --------------------------------------------------------------------------------------
    "fir.FrequencyResponse.__init__": "frequencies:field response:field zero_phase:field",
    "fir.KaiserLowpass.__init__": "fs:field fpass:field fstop:field apass_db:field "
    "astop_db:field cutoff:field delta_pass:field delta_stop:field attenuation_db:field "
    "alpha:field taps:field",
    "fir.KaiserLowpass.apply": "x:array zero_phase:flag axis:axis padtype:option padlen:count?",
    "fir.KaiserLowpass.frequency_response": "frequencies:array? n:count zero_phase:flag",
    "fir.KaiserLowpass.to_c": "path:path_out name:text dtype:option options:forwarded",
    "fir.KaiserLowpass.to_dict": "",
    "fir.apply": "taps:array x:array zero_phase:flag axis:axis padtype:option padlen:count?",
    "fir.kaiser_lowpass": "fs:pos fpass:pos fstop:pos apass_db:pos astop_db:pos",
    "fir.stream": "taps:array x:array state:array? axis:axis dtype:option",
    # --- cleaning ---------------------------------------------------------------------------------
    "cleaning.remove_outliers": "data:array threshold:pos method:option units:unit? out:spec?",
    "cleaning.detrend": "data:array fs:pos order:count units:unit? out:spec?",
    "cleaning.minmax_envelope": "data:array bins:count",
    "cleaning.clean": "data:array fs:pos outliers:pos? detrend:option? units:unit? out:spec?",
    "cleaning.OutlierResult.__init__": "data:field mask:field count:field threshold:field "
    "center:field scale:field units:field method:field",
    "cleaning.OutlierResult.to_dict": "",
    "cleaning.DetrendResult.__init__": "data:field coefficients:field order:field fs:field "
    "units:field",
    "cleaning.DetrendResult.to_dict": "",
    "cleaning.CleaningResult.__init__": "data:field outliers:field drift:field gaps:field",
    "cleaning.CleaningResult.describe": "",
    # The explorer (issue 35): an application over the public API above. Its settings and
    # sessions are checked by the functions they reach (every value goes through the library's
    # own checks; tests/test_explore.py drives the refusals), its server by the browser tests.
    "cli.explore.register": "subparsers:cli",
    "cli.explore.run": "args:cli",
    "explore.explore": "obj:object fs:spec units:spec options:forwarded",
    "explore.load_sessions": "paths:spec start:spec stop:spec options:forwarded",
    "explore.Session.__init__": "log:object source:object allan:object settings:object",
    "explore.Session.allan": "",
    "explore.Session.cleaned": "",
    "explore.Session.cli_command": "export:spec output:spec",
    "explore.Session.coefficients": "",
    "explore.Session.conservative": "confidence:spec",
    "explore.Session.export": "fmt:spec",
    "explore.Session.fit_options": "",
    "explore.Session.python_code": "export:spec",
    "explore.Session.report_html": "",
    "explore.Session.selection": "",
    "explore.Session.stability": "",
    "explore.Session.undo": "",
    "explore.Session.unit_groups": "",
    "explore.Session.update": "changes:forwarded",
    "explore.Settings.__init__": "start:spec stop:spec outliers:spec detrend:spec "
    "deviation:spec method:spec terms:spec tau_range:spec lines:spec",
    "explore.Settings.replace": "changes:forwarded",
    "explore.Settings.steps": "",
    "explore.Source.__init__": "path:field options:field label:field",
    "explore.Source.from_options": "path:spec options:spec",
    "explore.state.Cleaned.__init__": "data:field outliers:field outlier_mask:field trend:field "
    "has_gaps:field",
    "explore.app.ExploreApp.__init__": "sessions:object errors:spec",
    "explore.app.ExploreApp.apply": "changes:forwarded",
    "explore.app.ExploreApp.refresh": "",
    "explore.app.ExploreApp.sampling_html": "session:object",
    "explore.app.ExploreApp.schedule": "",
    "explore.app.ExploreApp.servable": "",
    "explore.app.ExploreApp.show_error": "exc:object prefix:spec",
    "explore.app.ExploreApp.sync_widgets": "",
    "explore.server.Served.__init__": "server:field url:field port:field thread:field",
    "explore.server.Served.stop": "",
    "explore.server.configure": "",
    "explore.server.serve": "sessions:object errors:spec host:spec port:spec show:flag "
    "background:flag",
    "cleaning.CleaningResult.to_dict": "",
    "cleaning.Envelope.__init__": "lower:field upper:field starts:field",
    # --- fleet ------------------------------------------------------------------------------------
    "fleet.analyse": "sources:spec fs:pos? units:spec? fit:option terms:spec? client:object? "
    "columns:spec? time_column:spec? load_options:spec? axis_names:text? taus:spec "
    "confidence:level? gaps:option threshold:pos num_workers:count? progress:callable? "
    "start:spec? stop:spec? bound_confidence:level outliers:pos? detrend:option? "
    "tau_range:pair? lines:spec",
    "fleet.summary": "table:object alpha:level min_ratio:pos",
    "fleet.term_columns": "table:object",
    "fleet.write_table": "table:object path:path_out",
    # --- fractional -------------------------------------------------------------------------------
    "fractional.ElwResult.__init__": "d:field standard_error:field m:field n:field level:field "
    "bounds:field objective:field at_bound:field",
    "fractional.ElwResult.confidence_interval": "confidence:level",
    "fractional.ElwResult.to_dict": "",
    "fractional.arfima": "n:count d:real sigma:nonneg size:spec? seed:count? kind:option",
    "fractional.diff": "x:array d:real axis:axis method:option",
    "fractional.elw": "x:array m:count? bounds:pair level:option axis:axis",
    "fractional.elw_objective": "x:array d:array m:count? level:option",
    "fractional.integrate": "w:array d:real axis:axis method:option",
    "fractional.weights": "d:real n:count",
    # --- io ---------------------------------------------------------------------------------------
    "io.GyroLog.__getitem__": "name:key",
    "io.GyroLog.__init__": "data:field columns:field fs:field time:field time_start:field "
    "time_column:field path:field sampling:field units:field topic:field "
    "selection:field",
    "io.GyroLog.unit_groups": "",
    "io.GyroLog.select": "start:spec? stop:spec? names:spec",
    "io.Selection.__init__": "start_s:field stop_s:field start_index:field stop_index:field "
    "total_s:field total_samples:field",
    "io.Selection.describe": "",
    "io.Selection.to_dict": "",
    "io.TimeBound.__init__": "seconds:field index:field text:field",
    "io.parse_time_bound": "value:spec? name:spec",
    "io.resolve_selection": "n_samples:count fs:pos? start:spec? stop:spec? time:array? names:spec",
    "io.SamplingReport.__init__": "n_samples:field fs:field fs_source:field fs_estimated:field "
    "median_interval:field jitter:field time_unit:field duration:field n_gaps:field "
    "gap_rows:field gap_durations:field missing_samples:field n_duplicates:field "
    "duplicate_rows:field warnings:field n_out_of_order:field out_of_order_rows:field "
    "n_exact_duplicates:field repairs:field filled_samples:field source_format:field",
    "io.SamplingReport.to_dict": "",
    "io.load": "path:path_in columns:spec? time_column:spec? time_unit:option fs:pos? "
    "delimiter:spec? skip_rows:count comments:spec units:spec? topic:key? stamp:option "
    "repair:spec fill_gaps:flag spill:flag? spill_dir:path_out? progress:callable?",
    "io.topics": "path:path_in",
    # --- kalman -----------------------------------------------------------------------------------
    "kalman.FilterResult.__init__": "rate:field bias:field state:field",
    "kalman.FixedGainKalman.__init__": "fs:pos arw:pos rrw:nonneg q_omega:nonneg? "
    "bandwidth:pos? form:option x0:array?",
    "kalman.FixedGainKalman.estimates": "state:object",
    "kalman.FixedGainKalman.filter": "z:array state:object? out:spec? dtype:option",
    "kalman.FixedGainKalman.to_c": "path:path_out name:text dtype:option options:forwarded",
    "kalman.FixedGainKalman.frequency_response": "freqs:array",
    "kalman.FixedGainKalman.initial_state": "z:array",
    "kalman.arw_from_deg_per_sqrt_hour": "arw:nonneg",
    "kalman.bandwidth_for_qomega": "q_omega:nonneg fs:pos arw:pos rrw:nonneg form:option",
    "kalman.q_omega_from_deg_per_hour": "q_omega:nonneg",
    "kalman.q_omega_to_deg_per_hour": "q_omega:nonneg",
    "kalman.qomega_for_bandwidth": "bandwidth:pos fs:pos arw:pos rrw:nonneg form:option",
    "kalman.riccati_gain": "q_omega:nonneg q_b:nonneg r_d:pos iterations:count",
    "kalman.rrw_from_deg_per_hour_1p5": "rrw:nonneg",
    "kalman.steady_state_gain": "q_omega:nonneg q_b:nonneg r_d:pos",
    # --- noise ------------------------------------------------------------------------------------
    "noise.FitDiagnostics.__init__": "chi2:field dof:field p_value:field residuals:field "
    "taus:field tau_range:field excluded:field warnings:field lines:field filter_correlation_time:field "
    "data_variance:field variance_claimed:field",
    "noise.FitDiagnostics.summary": "",
    "noise.FitDiagnostics.to_dict": "",
    "noise.GaussMarkovTerm.__init__": "sigma:field correlation_time:field tau_range:field "
    "missing:field",
    "noise.GaussMarkovTerm.to_dict": "",
    "noise.NoiseCoefficients.__getitem__": "symbol:key",
    "noise.NoiseCoefficients.__init__": "Q:field N:field B:field K:field R:field method:field "
    "data_unit:field sensor:field fs:field tau_range:field edf_source:field axis:field "
    "chi2:field dof:field squared:field gauss_markov:field diagnostics:field allan:field "
    "sinusoids:field",
    "noise.NoiseCoefficients.conservative": "confidence:level terms:spec?",
    "noise.NoiseCoefficients.discrete": "rate:pos",
    "noise.NoiseCoefficients.export": "fmt:option path:path_out? accel:object? rate:pos? "
    "rostopic:text",
    "noise.NoiseCoefficients.model": "taus:array",
    "noise.NoiseCoefficients.plot": "ax:object? allan:object? show_data:flag",
    "noise.NoiseCoefficients.summary": "",
    "noise.NoiseCoefficients.to": "system:spec",
    "noise.NoiseCoefficients.to_dict": "",
    "noise.NoiseCoefficients.to_json": "path:path_out? kwargs:forwarded",
    "noise.NoiseCoefficients.to_kalibr": "path:path_out update_rate:pos? rostopic:text",
    "noise.Term.__init__": "symbol:field name:field value:field uncertainty:field unit:field "
    "tau_range:field marker:field missing:field upper_bound:field bound_confidence:field "
    "bound_reason:field",
    "noise.Term.to": "unit:unit",
    "noise.Term.to_dict": "",
    "noise.fit": "allan:object method:option terms:spec tau_range:pair? regions:spec? "
    "slope_tolerance:pos min_points:count unit:unit? correlation_time:pair? auto_range:flag "
    "lines:spec bound_confidence:level",
    "noise.gauss_markov_avar": "sigma:nonneg correlation_time:pos taus:array",
    "noise.gmwm": "data:array fs:pos terms:spec units:unit? axis_names:text? select:flag "
    "bootstrap:count seed:count? auto_range:flag lines:spec bound_confidence:level",
    "noise.detect_lines": "data:array fs:pos false_alarm:level units:unit? max_lines:count "
    "axis_names:text?",
    "noise.sinusoid_avar": "amplitude:nonneg frequency:pos taus:array fs:pos?",
    "noise.wvar": "data:array fs:pos robust:flag efficiency:level confidence:level levels:count? "
    "units:unit? axis_names:text?",
    "noise.SinusoidTerm.__init__": "frequency:field amplitude:field tau_range:field missing:field",
    "noise.SinusoidTerm.to_dict": "",
    "noise.SpectralLine.__init__": "frequency:field amplitude:field unit:field ratio:field "
    "p_value:field resolution:field frequency_uncertainty:field",
    "noise.SpectralLine.to_dict": "",
    "noise.WaveletVariance.__init__": "levels:field scales:field variance:field ci_low:field "
    "ci_high:field edf:field n_coefficients:field robust:field efficiency:field "
    "confidence:field fs:field unit:field axis:field",
    "noise.WaveletVariance.plot": "ax:object?",
    "noise.WaveletVariance.to_dict": "",
    "noise.simulate": "n:count fs:pos quantization:nonneg arw:nonneg bias_instability:nonneg "
    "rrw:nonneg rate_ramp:real ar1:spec? bias:real axes:count seed:count? sinusoids:spec",
    # --- plotting ---------------------------------------------------------------------------------
    "plotting.allan_report_svg": "result:object fit:object? conservative:object? title:text? "
    "width:pos height:pos",
    "plotting.plot_allan": "results:object ax:object? labels:text? title:text? "
    "confidence_bars:flag fits:spec? kwargs:forwarded",
    "plotting.plot_dynamic_allan": "result:object ax:object? title:text? cmap:option colorbar:flag",
    "plotting.plot_fleet": "table:object fig:object? title:text?",
    "plotting.plot_noise_model": "coefficients:object ax:object? allan:object? show_data:flag",
    "plotting.plot_wvar": "result:object ax:object?",
    "plotting.save_allan_plot": "results:object path:path_out labels:text? title:text? "
    "dpi:count fits:spec? kwargs:forwarded",
    "plotting.save_comparison_plot": "before:object after:object path:path_out labels:text "
    "title:text? dpi:count",
    "plotting.save_fleet_plot": "table:object path:path_out title:text? dpi:count",
    "plotting.save_noise_model_plot": "coefficients:object path:path_out title:text? dpi:count",
    "plotting.save_prediction_plot": "section:array calibration:count fs:pos forecasts:spec "
    "path:path_out std:array? title:text dpi:count",
    # --- predict ----------------------------------------------------------------------------------
    "predict.CompiledPredictor.__init__": "inner:field predictor:field",
    "predict.CompiledPredictor.predict": "batch:array n_threads:count? dtype:option?",
    "predict.CompiledPredictor.to_c": "path:path_out name:text dtype:option options:forwarded",
    "predict.Evaluation.__init__": "calibration:field horizon:field sections:field methods:field",
    "predict.Evaluation.ratio": "method:key reference:key statistic:option resamples:count "
    "seed:count?",
    "predict.Evaluation.table": "",
    "predict.Evaluation.to_dict": "",
    "predict.FractionalKalmanPredictor.__init__": "d:real q:nonneg r:nonneg mean:spec "
    "algorithm:option",
    "predict.FractionalKalmanPredictor.compile": "calibration_length:count horizon:count "
    "n_threads:count?",
    "predict.FractionalKalmanPredictor.from_noise": "coefficients:object? fs:pos? d:real "
    "arw:nonneg? bias_instability:nonneg? mean:spec",
    "predict.FractionalKalmanPredictor.predict": "calibration:array horizon:count n_threads:count?",
    "predict.MethodStats.__init__": "method:field ie:field rsse:field",
    "predict.MethodStats.to_dict": "",
    "predict.Prediction.__init__": "bias:field std:field std_observation:field mean:field "
    "mean_std:field",
    "predict.Prediction.to_dict": "",
    "predict.calibration_mean": "y:array horizon:count",
    "predict.evaluate": "log:array calibration:count horizon:count methods:spec "
    "predictor:object? n_threads:count?",
    "predict.integrated_error": "y:array yhat:array",
    "predict.moving_average": "y:array horizon:count",
    "predict.rsse": "y:array yhat:array",
    # --- report -----------------------------------------------------------------------------------
    "report.ChannelReport.__init__": "name:field unit:field allan:field fit:field "
    "conservative:field errors:field",
    "report.build_report": "log:object units:spec? confidence:level? method:option "
    "conservative_confidence:level rate:pos? title:text? bound_confidence:level outliers:pos? "
    "detrend:option? tau_range:pair? lines:spec",
    "report.write_report": "path:path_out log:object kwargs:forwarded",
    # --- spectral ---------------------------------------------------------------------------------
    "spectral.LSSAResult.__init__": "frequencies:field spectrum:field alpha:field "
    "critical_value:field n:field n_known:field trend:field known_periods:field "
    "known_params:field t_ref:field residual_norm:field",
    "spectral.LSSAResult.peaks": "",
    "spectral.LSSAResult.to_dict": "",
    "spectral.NoiseDensity.__init__": "density:field band:field unit:field spectrum:field",
    "spectral.NoiseDensity.to_dict": "",
    "spectral.PSDResult.__init__": "frequencies:field psd:field fs:field nperseg:field "
    "noverlap:field window:field unit:field",
    "spectral.PSDResult.to_dict": "",
    "spectral.lssa": "t:array y:array freqs:array? weights:array? cov:array? trend:flag "
    "known_periods:array columns:array? alpha:level",
    "spectral.noise_density": "x:array fs:pos band:pair? nperseg:count? units:unit?",
    "spectral.psd": "x:array fs:pos nperseg:count? noverlap:count? window:option units:unit?",
    # --- thermal ----------------------------------------------------------------------------------
    "thermal.AR1Fit.__init__": "c:field c_std_error:field sigma_e:field mean:field n:field "
    "dt:field beta:field process_std:field",
    "thermal.AR1Fit.to_dict": "",
    "thermal.TemperatureModel.__call__": "name:key temperature:array extrapolate:flag",
    "thermal.TemperatureModel.__init__": "temperatures:array parameters:spec units:spec "
    "method:option degree:count",
    "thermal.TemperatureModel.evaluate": "temperature:real extrapolate:flag",
    "thermal.TemperatureModel.from_analyses": "analyses:spec method:option degree:count",
    "thermal.TemperatureModel.from_dict": "data:spec",
    "thermal.TemperatureModel.from_json": "text:json",
    "thermal.TemperatureModel.table": "",
    "thermal.TemperatureModel.to_dict": "",
    "thermal.TemperatureModel.to_json": "kwargs:forwarded",
    "thermal.ThermalAnalysis.__init__": "temperature:field fs:field n:field arw:field "
    "bias_instability:field noise_density:field ar1:field filter_cutoff:field unit:field",
    "thermal.ThermalAnalysis.parameter_units": "",
    "thermal.ThermalAnalysis.parameters": "",
    "thermal.ThermalAnalysis.to_dict": "",
    "thermal.analyse_log": "x:array fs:pos temperature:real prefilter:flag zero_phase:flag "
    "fpass:pos? fstop:pos? apass_db:pos astop_db:pos units:unit?",
    "thermal.analyse_logs": "logs:spec fs:pos kwargs:forwarded",
    "thermal.build_temperature_model": "logs:spec fs:pos method:option degree:count "
    "kwargs:forwarded",
    "thermal.fit_ar1": "x:array fs:pos demean:flag",
    # --- units ------------------------------------------------------------------------------------
    "units.Unit.__init__": "factor:field dims:field",
    "units.base_unit": "data_unit:unit symbol:key",
    "units.conversion_factor": "from_unit:unit to_unit:unit",
    "units.parse_unit": "text:unit",
    "units.sensor_kind": "data_unit:unit",
    # --- the command line (driven by the CLI tests) ----------------------------------------------
    "cli.build_parser": "",
    "cli.main": "argv:cli",
    "cli.allan.ProgressBar.__init__": "label:text stream:object?",
    "cli.allan.ProgressBar.__call__": "fraction:real",
    "cli.allan.ProgressBar.close": "",
    "cli.allan.register": "subparsers:cli",
    "cli.allan.run": "args:cli",
    "cli.demo.register": "subparsers:cli",
    "cli.demo.run": "args:cli",
    "cli.experiment_table1.register_experiment": "exp_subparsers:cli",
    "cli.experiment_table1.run": "args:cli",
    "cli.experiment_table1.simulate": "runs:count n:count sigma:pos seed:count bias:real",
    "cli.fleet.register": "subparsers:cli",
    "cli.fleet.run": "args:cli",
    "cli.noise.add_fit_arguments": "parser:cli",
    "cli.noise.add_fit_range_arguments": "group:cli",
    "cli.noise.fit_range_options": "args:cli method:cli",
    "cli.noise.demo_section": "rate:array fs:pos outdir:path_out true_coefficients:spec? unit:unit",
    "cli.noise.run_fit": "args:cli results:object",
    "cli.predict.demo_section": "rate:array fs:pos outdir:path_out",
    "cli.predict.register": "subparsers:cli",
    "cli.predict.run": "args:cli",
    "cli.report.register": "subparsers:cli",
    "cli.report.run": "args:cli",
    "cli.thermal.register": "subparsers:cli",
    "cli.thermal.run": "args:cli",
}


def kinds_of(key: str) -> dict[str, tuple[str, bool]]:
    """``{parameter: (kind, accepts_none)}`` of a registry entry."""
    out = {}
    for item in REGISTRY[key].split():
        name, _, kind = item.partition(":")
        out[name] = (kind.rstrip("?"), kind.endswith("?"))
    return out


def _public_modules() -> dict[str, Any]:
    modules: dict[str, Any] = {"gyrobias": gyrobias}
    for info in pkgutil.walk_packages(gyrobias.__path__, "gyrobias."):
        if any(part.startswith("_") for part in info.name.split(".")[1:]):
            continue
        modules[info.name] = importlib.import_module(info.name)
    return modules


_PROTOCOL = ("__init__", "__call__", "__getitem__")


def public_api() -> dict[str, Callable[..., Any]]:
    """Every public function and method: ``{"module.name" or "module.Class.method": callable}``.

    A public name is one a public module (no ``_`` in its path) lists in ``__all__``; an object
    exported by several modules is named after its package's public module
    (``gyrobias.allan.adev``, not ``gyrobias.adev`` or ``gyrobias.allan.classic.adev``). Methods are those a public class defines
    itself (properties excluded), plus ``__init__``, ``__call__`` and ``__getitem__``.
    """
    best: dict[int, tuple[int, str, str, Any]] = {}
    for modname, module in _public_modules().items():
        for attr in getattr(module, "__all__", ()):
            obj = getattr(module, attr)
            if inspect.ismodule(obj) or not callable(obj):
                continue
            if inspect.isclass(obj) and issubclass(obj, BaseException):
                continue
            home = getattr(obj, "__module__", "") or ""
            # the public module of the package (gyrobias.exports, not .exports.formats) if it
            # exports the object, else the exporting module nearest the definition
            depth = modname.count(".")
            if not home.startswith(modname):
                score = -1
            elif depth == 1:
                score = 1000
            else:
                score = len(modname)
            if id(obj) not in best or score > best[id(obj)][0]:
                best[id(obj)] = (score, modname, attr, obj)
    api: dict[str, Callable[..., Any]] = {}
    for _, modname, attr, obj in best.values():
        prefix = modname.removeprefix("gyrobias").lstrip(".")
        name = f"{prefix}.{attr}" if prefix else attr
        if inspect.isclass(obj):
            for member, value in vars(obj).items():
                if member.startswith("_") and member not in _PROTOCOL:
                    continue
                func = value.__func__ if isinstance(value, (staticmethod, classmethod)) else value
                if isinstance(value, property) or not callable(func):
                    continue
                api[f"{name}.{member}"] = func
        else:
            api[name] = obj
    return api


def parameters(func: Callable[..., Any]) -> list[str]:
    """Parameter names of ``func`` without ``self``/``cls`` (``**kwargs`` as ``kwargs``)."""
    return [p for p in inspect.signature(func).parameters if p not in ("self", "cls")]


def entries(kind: str) -> Iterator[tuple[str, str, bool]]:
    """``(key, parameter, accepts_none)`` of every registered parameter of ``kind``."""
    for key in REGISTRY:
        for name, (k, none_ok) in kinds_of(key).items():
            if k == kind:
                yield key, name, none_ok
