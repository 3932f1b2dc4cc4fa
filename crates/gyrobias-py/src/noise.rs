//! Bindings of `gyrocore::noise`.

use gyrocore::noise::{
    self, Ar1, Curve, Diagnostics, FitOptions, GaussMarkovEstimate, GmwmOptions, LineEstimate,
    NoiseSpec, ReadOffOptions, Term, TermEstimate, UpperBound, sinusoid, wavelet,
};
use numpy::{IntoPyArray, PyArray1, PyReadonlyArray1, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::array::{c_order, c_order_opt};
use crate::count;
use crate::error::core;

/// Simulated rate noise, row-major `(n, axes)` flattened (`gyrocore::noise::simulate`).
#[pyfunction]
#[pyo3(signature = (n, fs, quantization, arw, bias_instability, rrw, rate_ramp, ar1, bias, axes, seed))]
fn simulate(
    py: Python<'_>,
    #[pyo3(from_py_with = count::n)] n: usize,
    fs: f64,
    quantization: f64,
    arw: f64,
    bias_instability: f64,
    rrw: f64,
    rate_ramp: f64,
    ar1: Option<(f64, f64)>,
    bias: f64,
    #[pyo3(from_py_with = count::axes)] axes: usize,
    #[pyo3(from_py_with = count::seed)] seed: u64,
) -> PyResult<Bound<'_, PyArray1<f64>>> {
    let spec = NoiseSpec {
        quantization,
        arw,
        bias_instability,
        rrw,
        rate_ramp,
        ar1: ar1.map(|(coefficient, sigma)| Ar1 { coefficient, sigma }),
        bias,
    };
    let out = core(py.detach(|| noise::simulate(n, fs, &spec, axes, seed)))?;
    Ok(out.into_pyarray(py))
}

fn terms_to_py<'py>(py: Python<'py>, terms: &[TermEstimate]) -> PyResult<Vec<Bound<'py, PyDict>>> {
    terms
        .iter()
        .map(|t| {
            let d = PyDict::new(py);
            d.set_item("symbol", t.term.symbol())?;
            d.set_item("value", t.value)?;
            d.set_item("uncertainty", t.value.map(|_| t.uncertainty))?;
            d.set_item("tau_range", t.tau_range)?;
            d.set_item("marker", t.marker)?;
            d.set_item("missing", t.missing.clone())?;
            let bound = t
                .upper_bound
                .as_ref()
                .map(|b| bound_dict(py, b))
                .transpose()?;
            d.set_item("upper_bound", bound)?;
            Ok(d)
        })
        .collect()
}

fn bound_dict<'py>(py: Python<'py>, b: &UpperBound) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("value", b.value)?;
    d.set_item("confidence", b.confidence)?;
    d.set_item("tau", b.tau)?;
    d.set_item("tau_range", b.tau_range)?;
    d.set_item("points", b.points)?;
    d.set_item("reason", b.reason.clone())?;
    Ok(d)
}

/// Upper bound of one term from the curve points `used` with their EDF
/// (`gyrocore::noise::upper_bound`).
#[pyfunction]
#[pyo3(signature = (taus, variance, m, n_terms, overlapping, used, edf, term, confidence))]
#[allow(clippy::needless_pass_by_value, clippy::too_many_arguments)]
fn upper_bound<'py>(
    py: Python<'py>,
    taus: PyReadonlyArray1<'py, f64>,
    variance: PyReadonlyArray1<'py, f64>,
    #[pyo3(from_py_with = count::factors)] m: Vec<usize>,
    #[pyo3(from_py_with = count::n_terms)] n_terms: Vec<usize>,
    overlapping: bool,
    #[pyo3(from_py_with = count::used)] used: Vec<usize>,
    edf: PyReadonlyArray1<'py, f64>,
    term: &str,
    confidence: f64,
) -> PyResult<Bound<'py, PyDict>> {
    let term = core(Term::parse(term))?;
    let taus = c_order(&taus);
    let variance = c_order(&variance);
    let edf = c_order(&edf);
    let curve = Curve {
        taus: &taus,
        variance: &variance,
        m: &m,
        n_terms: &n_terms,
        overlapping,
        edf: None,
    };
    let b = core(noise::upper_bound(&curve, &used, &edf, term, confidence))?;
    bound_dict(py, &b)
}

/// IEEE-952 read-off of the noise terms from an Allan-variance curve
/// (`gyrocore::noise::read_off`).
#[pyfunction]
#[pyo3(signature = (taus, variance, m, n_terms, overlapping, edf, terms, regions, tolerance, min_points, bound_confidence=noise::BOUND_CONFIDENCE))]
#[allow(clippy::needless_pass_by_value, clippy::too_many_arguments)]
fn read_off<'py>(
    py: Python<'py>,
    taus: PyReadonlyArray1<'py, f64>,
    variance: PyReadonlyArray1<'py, f64>,
    #[pyo3(from_py_with = count::factors)] m: Vec<usize>,
    #[pyo3(from_py_with = count::n_terms)] n_terms: Vec<usize>,
    overlapping: bool,
    edf: Option<PyReadonlyArray1<'py, f64>>,
    terms: Vec<String>,
    regions: [Option<(f64, f64)>; 5],
    tolerance: f64,
    #[pyo3(from_py_with = count::min_points)] min_points: usize,
    bound_confidence: f64,
) -> PyResult<Bound<'py, PyDict>> {
    let symbols: Vec<&str> = terms.iter().map(String::as_str).collect();
    let enabled = core(noise::parse_terms(&symbols))?;
    let edf = c_order_opt(edf.as_ref());
    let taus = c_order(&taus);
    let variance = c_order(&variance);
    let curve = Curve {
        taus: &taus,
        variance: &variance,
        m: &m,
        n_terms: &n_terms,
        overlapping,
        edf: edf.as_deref(),
    };
    let options = ReadOffOptions {
        tolerance,
        min_points,
        regions,
        bound_confidence,
    };
    let r = core(noise::read_off(&curve, enabled, &options))?;
    let d = PyDict::new(py);
    d.set_item("terms", terms_to_py(py, &r.terms)?)?;
    d.set_item("local_slopes", r.local_slopes.into_pyarray(py))?;
    Ok(d)
}

/// Total model variance and each term's contribution.
type ModelCurves<'py> = (Bound<'py, PyArray1<f64>>, Vec<Bound<'py, PyArray1<f64>>>);

/// The five-term model (with a sensor filter's correction when `filter_time` > 0): total
/// variance and each term's contribution at `taus` (`gyrocore::noise::model_curves`).
#[pyfunction]
#[pyo3(signature = (squared, taus, filter_time=0.0))]
#[allow(clippy::needless_pass_by_value)]
fn model<'py>(
    py: Python<'py>,
    squared: [f64; 5],
    taus: PyReadonlyArray1<'py, f64>,
    filter_time: f64,
) -> PyResult<ModelCurves<'py>> {
    let (total, parts) = core(noise::model_curves(&squared, filter_time, &c_order(&taus)))?;
    Ok((
        total.into_pyarray(py),
        parts.into_iter().map(|p| p.into_pyarray(py)).collect(),
    ))
}

/// Tightest overbound `A c ≥ b`, `c ≥ floor` (default 0), minimising `Σ (A c)_i / b_i`
/// (`gyrocore::noise::overbound_above`).
#[pyfunction]
#[pyo3(signature = (design, bound, floor=None))]
#[allow(clippy::needless_pass_by_value)]
fn overbound<'py>(
    py: Python<'py>,
    design: PyReadonlyArray2<'py, f64>,
    bound: PyReadonlyArray1<'py, f64>,
    floor: Option<PyReadonlyArray1<'py, f64>>,
) -> PyResult<Bound<'py, PyDict>> {
    let shape = design.shape();
    let (rows, cols) = (shape[0], shape[1]);
    let design = c_order(&design);
    let bound = c_order(&bound);
    let floor = c_order_opt(floor.as_ref());
    let zeros = vec![0.0; cols];
    let floor: &[f64] = floor.as_deref().unwrap_or(&zeros);
    let r = core(py.detach(|| noise::overbound_above(&design, rows, cols, &bound, floor)))?;
    let d = PyDict::new(py);
    d.set_item("coefficients", r.coefficients.into_pyarray(py))?;
    d.set_item("ratio", r.ratio.into_pyarray(py))?;
    d.set_item("objective", r.objective)?;
    d.set_item("pivots", r.pivots)?;
    Ok(d)
}

/// Conservative five-term coefficients overbounding the curve's upper confidence bound
/// (`gyrocore::noise::conservative`).
#[pyfunction]
#[pyo3(signature = (taus, variance, m, n_terms, overlapping, edf, reference, terms, tau_range, confidence))]
#[allow(clippy::needless_pass_by_value, clippy::too_many_arguments)]
fn conservative<'py>(
    py: Python<'py>,
    taus: PyReadonlyArray1<'py, f64>,
    variance: PyReadonlyArray1<'py, f64>,
    #[pyo3(from_py_with = count::factors)] m: Vec<usize>,
    #[pyo3(from_py_with = count::n_terms)] n_terms: Vec<usize>,
    overlapping: bool,
    edf: Option<PyReadonlyArray1<'py, f64>>,
    reference: [f64; 5],
    terms: Vec<String>,
    tau_range: Option<(f64, f64)>,
    confidence: f64,
) -> PyResult<Bound<'py, PyDict>> {
    let symbols: Vec<&str> = terms.iter().map(String::as_str).collect();
    let allowed = core(noise::parse_terms(&symbols))?;
    let edf = c_order_opt(edf.as_ref());
    let taus = c_order(&taus);
    let variance = c_order(&variance);
    let curve = Curve {
        taus: &taus,
        variance: &variance,
        m: &m,
        n_terms: &n_terms,
        overlapping,
        edf: edf.as_deref(),
    };
    let r = core(
        py.detach(|| noise::conservative(&curve, &reference, allowed, tau_range, confidence)),
    )?;
    let d = PyDict::new(py);
    d.set_item("squared", r.squared.to_vec())?;
    d.set_item("inflation", r.inflation.to_vec())?;
    d.set_item("used", r.used.iter().map(|&u| u as u64).collect::<Vec<_>>())?;
    d.set_item("edf", r.edf.into_pyarray(py))?;
    d.set_item("bound", r.bound.into_pyarray(py))?;
    d.set_item("ratio", r.ratio.into_pyarray(py))?;
    d.set_item("tau_range", r.tau_range)?;
    Ok(d)
}

fn gauss_markov_dicts<'py>(
    py: Python<'py>,
    terms: &[GaussMarkovEstimate],
) -> PyResult<Vec<Bound<'py, PyDict>>> {
    terms
        .iter()
        .map(|g| {
            let d = PyDict::new(py);
            d.set_item("sigma", g.sigma)?;
            d.set_item("sigma_uncertainty", g.sigma.map(|_| g.sigma_uncertainty))?;
            d.set_item("correlation_time", g.correlation_time)?;
            d.set_item(
                "correlation_time_uncertainty",
                g.correlation_time.map(|_| g.correlation_time_uncertainty),
            )?;
            d.set_item("tau_range", g.tau_range)?;
            d.set_item("missing", g.missing.clone())?;
            Ok(d)
        })
        .collect()
}

fn line_dicts<'py>(py: Python<'py>, lines: &[LineEstimate]) -> PyResult<Vec<Bound<'py, PyDict>>> {
    lines
        .iter()
        .map(|l| {
            let d = PyDict::new(py);
            d.set_item("frequency", l.frequency)?;
            d.set_item("frequency_uncertainty", l.frequency_uncertainty)?;
            d.set_item("amplitude", l.amplitude)?;
            d.set_item(
                "amplitude_uncertainty",
                l.amplitude.map(|_| l.amplitude_uncertainty),
            )?;
            d.set_item("tau_range", l.tau_range)?;
            d.set_item("missing", l.missing.clone())?;
            Ok(d)
        })
        .collect()
}

/// Spectral lines of a rate series (`gyrocore::noise::sinusoid::detect`): one dict per line.
#[pyfunction]
#[pyo3(signature = (data, t0, false_alarm, half_width, max_lines))]
#[allow(clippy::needless_pass_by_value)]
fn detect_lines<'py>(
    py: Python<'py>,
    data: PyReadonlyArray1<'py, f64>,
    t0: f64,
    false_alarm: f64,
    #[pyo3(from_py_with = count::half_width)] half_width: usize,
    #[pyo3(from_py_with = count::max_lines)] max_lines: usize,
) -> PyResult<Vec<Bound<'py, PyDict>>> {
    let rate = c_order(&data);
    let options = sinusoid::DetectOptions {
        false_alarm,
        half_width,
        max_lines,
    };
    let lines = core(py.detach(|| sinusoid::detect(&rate, t0, &options)))?;
    lines
        .iter()
        .map(|l| {
            let d = PyDict::new(py);
            d.set_item("frequency", l.frequency)?;
            d.set_item("amplitude", l.amplitude)?;
            d.set_item("ratio", l.ratio)?;
            d.set_item("p_value", l.p_value)?;
            d.set_item("resolution", l.resolution)?;
            d.set_item("frequency_uncertainty", l.frequency_uncertainty)?;
            Ok(d)
        })
        .collect()
}

/// Allan variance of a sinusoid at `taus` (`gyrocore::noise::sinusoid::avar`, sampled at
/// period `t0`, or the continuous IEEE form when `t0` is `None`).
#[pyfunction]
#[pyo3(signature = (amplitude, frequency, taus, t0=None))]
#[allow(clippy::needless_pass_by_value)]
fn sinusoid_avar<'py>(
    py: Python<'py>,
    amplitude: f64,
    frequency: f64,
    taus: PyReadonlyArray1<'py, f64>,
    t0: Option<f64>,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let taus = c_order(&taus);
    let out = core(sinusoid::avar_curve(amplitude, frequency, t0, &taus))?;
    Ok(out.into_pyarray(py))
}

/// `data + Σ Ω₀ sin(2π f k t0 + φ)` for sinusoids `(f, Ω₀, φ)` (`gyrocore::noise::sinusoid::add_lines`).
#[pyfunction]
#[allow(clippy::needless_pass_by_value)]
fn add_lines<'py>(
    py: Python<'py>,
    data: PyReadonlyArray1<'py, f64>,
    t0: f64,
    lines: Vec<(f64, f64, f64)>,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let mut rate = c_order(&data).into_owned();
    core(py.detach(|| sinusoid::add_lines(&mut rate, t0, &lines)))?;
    Ok(rate.into_pyarray(py))
}

/// Haar MODWT wavelet variance with intervals (`gyrocore::noise::wavelet::wvar`).
#[pyfunction]
#[pyo3(signature = (data, t0, efficiency, confidence, levels))]
#[allow(clippy::needless_pass_by_value)]
fn wvar<'py>(
    py: Python<'py>,
    data: PyReadonlyArray1<'py, f64>,
    t0: f64,
    efficiency: Option<f64>,
    confidence: f64,
    #[pyo3(from_py_with = count::levels)] levels: Option<usize>,
) -> PyResult<Bound<'py, PyDict>> {
    let rate = c_order(&data);
    let w = core(py.detach(|| wavelet::wvar(&rate, t0, efficiency, confidence, levels)))?;
    let as_u64 = |v: &[usize]| v.iter().map(|&x| x as u64).collect::<Vec<u64>>();
    let d = PyDict::new(py);
    d.set_item("levels", as_u64(&w.levels).into_pyarray(py))?;
    d.set_item("m", as_u64(&w.m).into_pyarray(py))?;
    d.set_item("scales", w.scales.into_pyarray(py))?;
    d.set_item("variance", w.variance.into_pyarray(py))?;
    d.set_item("n_coefficients", as_u64(&w.n_coefficients).into_pyarray(py))?;
    d.set_item("edf", w.edf.into_pyarray(py))?;
    d.set_item("ci_low", w.ci_low.into_pyarray(py))?;
    d.set_item("ci_high", w.ci_high.into_pyarray(py))?;
    d.set_item("tuning", w.tuning)?;
    Ok(d)
}

/// Asymptotic Gaussian efficiency of the biweight wavelet-variance estimator with tuning
/// constant `c`, and the constant for a given efficiency (`gyrocore::noise::wavelet`).
#[pyfunction]
fn biweight_constant(efficiency: f64) -> PyResult<f64> {
    core(wavelet::biweight_constant(efficiency))
}

/// Robust (biweight) variance of zero-mean coefficients with tuning constant `c`
/// (`gyrocore::noise::wavelet::robust_variance`).
#[pyfunction]
#[allow(clippy::needless_pass_by_value)]
fn robust_variance(coefficients: PyReadonlyArray1<'_, f64>, tuning: f64) -> f64 {
    wavelet::robust_variance(&c_order(&coefficients), tuning)
}

fn diagnostics_dict<'py>(
    py: Python<'py>,
    diagnostics: &Diagnostics,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("chi2", diagnostics.chi2)?;
    d.set_item("dof", diagnostics.dof)?;
    d.set_item("p_value", diagnostics.p_value)?;
    d.set_item("residuals", diagnostics.residuals.clone().into_pyarray(py))?;
    d.set_item("tau_range", diagnostics.tau_range)?;
    d.set_item("excluded", diagnostics.excluded.clone())?;
    d.set_item("warnings", diagnostics.warnings.clone())?;
    d.set_item(
        "filter_correlation_time",
        diagnostics.filter_correlation_time,
    )?;
    d.set_item("variance_limit", diagnostics.variance_limit)?;
    Ok(d)
}

/// Joint fit with Gauss–Markov terms, diagnostics and automatic τ-range selection
/// (`gyrocore::noise::fit`).
#[pyfunction]
#[pyo3(signature = (taus, variance, m, n_terms, overlapping, edf, terms, tau_range, correlation_time, automatic_range, lines=Vec::new(), bound_confidence=noise::BOUND_CONFIDENCE, data_variance=None))]
#[allow(clippy::needless_pass_by_value, clippy::too_many_arguments)]
fn fit<'py>(
    py: Python<'py>,
    taus: PyReadonlyArray1<'py, f64>,
    variance: PyReadonlyArray1<'py, f64>,
    #[pyo3(from_py_with = count::factors)] m: Vec<usize>,
    #[pyo3(from_py_with = count::n_terms)] n_terms: Vec<usize>,
    overlapping: bool,
    edf: Option<PyReadonlyArray1<'py, f64>>,
    terms: Vec<String>,
    tau_range: Option<(f64, f64)>,
    correlation_time: Option<(f64, f64)>,
    automatic_range: bool,
    lines: Vec<(f64, f64)>,
    bound_confidence: f64,
    data_variance: Option<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let symbols: Vec<&str> = terms.iter().map(String::as_str).collect();
    let (enabled, gauss_markov) = core(noise::parse_model_terms(&symbols))?;
    let edf = c_order_opt(edf.as_ref());
    let taus = c_order(&taus);
    let variance = c_order(&variance);
    let curve = Curve {
        taus: &taus,
        variance: &variance,
        m: &m,
        n_terms: &n_terms,
        overlapping,
        edf: edf.as_deref(),
    };
    let options = FitOptions {
        enabled,
        gauss_markov,
        tau_range,
        correlation_time,
        automatic_range,
        lines,
        bound_confidence,
        data_variance,
    };
    let fit = core(py.detach(|| noise::fit(&curve, &options)))?;
    let d = PyDict::new(py);
    d.set_item("terms", terms_to_py(py, &fit.terms)?)?;
    d.set_item("squared", fit.squared.to_vec())?;
    d.set_item("gauss_markov", gauss_markov_dicts(py, &fit.gauss_markov)?)?;
    d.set_item("chi2", fit.chi2)?;
    d.set_item("dof", fit.dof)?;
    d.set_item("tau_range", fit.tau_range)?;
    d.set_item("lines", line_dicts(py, &fit.lines)?)?;
    d.set_item(
        "used",
        fit.used.iter().map(|&u| u as u64).collect::<Vec<_>>(),
    )?;
    d.set_item("edf", fit.edf.clone().into_pyarray(py))?;
    d.set_item("diagnostics", diagnostics_dict(py, &fit.diagnostics)?)?;
    Ok(d)
}

/// Goodness-of-fit diagnostics of a given model on an Allan-variance curve
/// (`gyrocore::noise::diagnose`).
#[pyfunction]
#[pyo3(signature = (taus, variance, m, n_terms, overlapping, edf, squared, gauss_markov, n_params))]
#[allow(clippy::needless_pass_by_value)]
fn diagnose<'py>(
    py: Python<'py>,
    taus: PyReadonlyArray1<'py, f64>,
    variance: PyReadonlyArray1<'py, f64>,
    #[pyo3(from_py_with = count::factors)] m: Vec<usize>,
    #[pyo3(from_py_with = count::n_terms)] n_terms: Vec<usize>,
    overlapping: bool,
    edf: Option<PyReadonlyArray1<'py, f64>>,
    squared: [f64; 5],
    gauss_markov: Vec<(f64, f64)>,
    #[pyo3(from_py_with = count::n_params)] n_params: usize,
) -> PyResult<Bound<'py, PyDict>> {
    let edf = c_order_opt(edf.as_ref());
    let taus = c_order(&taus);
    let variance = c_order(&variance);
    let curve = Curve {
        taus: &taus,
        variance: &variance,
        m: &m,
        n_terms: &n_terms,
        overlapping,
        edf: edf.as_deref(),
    };
    let d = core(noise::diagnose(&curve, &squared, &gauss_markov, n_params))?;
    diagnostics_dict(py, &d)
}

/// Allan variance of each Gauss–Markov component `(q², T)` at `taus`
/// (`gyrocore::noise::gauss_markov::allan_variance_curves`).
#[pyfunction]
#[pyo3(signature = (gauss_markov, taus))]
#[allow(clippy::needless_pass_by_value)]
fn gauss_markov_variance<'py>(
    py: Python<'py>,
    gauss_markov: Vec<(f64, f64)>,
    taus: PyReadonlyArray1<'py, f64>,
) -> Vec<Bound<'py, PyArray1<f64>>> {
    noise::gauss_markov::allan_variance_curves(&gauss_markov, &c_order(&taus))
        .into_iter()
        .map(|c| c.into_pyarray(py))
        .collect()
}

/// Allan variance of one Gauss–Markov process of standard deviation `sigma` at `taus`
/// (`gyrocore::noise::gauss_markov::allan_variance_curve`).
#[pyfunction]
#[allow(clippy::needless_pass_by_value)]
fn gauss_markov_avar<'py>(
    py: Python<'py>,
    sigma: f64,
    correlation_time: f64,
    taus: PyReadonlyArray1<'py, f64>,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let taus = c_order(&taus);
    let out = core(noise::gauss_markov::allan_variance_curve(
        sigma,
        correlation_time,
        &taus,
    ))?;
    Ok(out.into_pyarray(py))
}

/// GMWM estimate of the noise model of one rate series (`gyrocore::noise::gmwm`).
#[pyfunction]
#[pyo3(signature = (data, t0, terms, select, bootstrap, seed, min_blocks, automatic_range=false, lines=Vec::new(), bound_confidence=noise::BOUND_CONFIDENCE))]
#[allow(clippy::needless_pass_by_value, clippy::too_many_arguments)]
fn gmwm<'py>(
    py: Python<'py>,
    data: PyReadonlyArray1<'py, f64>,
    t0: f64,
    terms: Vec<String>,
    select: bool,
    #[pyo3(from_py_with = count::bootstrap)] bootstrap: usize,
    #[pyo3(from_py_with = count::seed)] seed: u64,
    #[pyo3(from_py_with = count::min_blocks)] min_blocks: usize,
    automatic_range: bool,
    lines: Vec<(f64, f64)>,
    bound_confidence: f64,
) -> PyResult<Bound<'py, PyDict>> {
    let symbols: Vec<&str> = terms.iter().map(String::as_str).collect();
    let (enabled, gauss_markov) = core(noise::parse_model_terms(&symbols))?;
    let options = GmwmOptions {
        enabled,
        gauss_markov,
        select,
        bootstrap,
        seed,
        min_blocks,
        automatic_range,
        lines,
        bound_confidence,
    };
    let rate = c_order(&data);
    let g = core(py.detach(|| noise::gmwm(&rate, t0, &options)))?;
    let d = PyDict::new(py);
    let fit = &g.fit;
    d.set_item("terms", terms_to_py(py, &fit.terms)?)?;
    d.set_item("squared", fit.squared.to_vec())?;
    d.set_item("gauss_markov", gauss_markov_dicts(py, &fit.gauss_markov)?)?;
    d.set_item("chi2", fit.chi2)?;
    d.set_item("dof", fit.dof)?;
    d.set_item("tau_range", fit.tau_range)?;
    d.set_item("lines", line_dicts(py, &fit.lines)?)?;
    d.set_item("diagnostics", diagnostics_dict(py, &fit.diagnostics)?)?;
    let w = PyDict::new(py);
    w.set_item(
        "m",
        g.wavelet
            .m
            .iter()
            .map(|&x| x as u64)
            .collect::<Vec<u64>>()
            .into_pyarray(py),
    )?;
    w.set_item("scales", g.wavelet.scales.clone().into_pyarray(py))?;
    w.set_item("variance", g.wavelet.variance.clone().into_pyarray(py))?;
    w.set_item(
        "n_coefficients",
        g.wavelet
            .n_coefficients
            .iter()
            .map(|&x| x as u64)
            .collect::<Vec<u64>>()
            .into_pyarray(py),
    )?;
    d.set_item("wavelet", w)?;
    let (sel_enabled, sel_gm) = g.selected;
    let selected = noise::model_term_symbols(&sel_enabled, sel_gm);
    d.set_item("selected", selected)?;
    d.set_item("criterion", g.criterion)?;
    d.set_item("candidates", g.candidates.clone())?;
    d.set_item("bootstrap", g.bootstrap)?;
    Ok(d)
}

pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("FLICKER_FACTOR", noise::FLICKER_FACTOR)?;
    m.add_function(wrap_pyfunction!(simulate, m)?)?;
    m.add_function(wrap_pyfunction!(read_off, m)?)?;
    m.add_function(wrap_pyfunction!(model, m)?)?;
    m.add_function(wrap_pyfunction!(overbound, m)?)?;
    m.add_function(wrap_pyfunction!(conservative, m)?)?;
    m.add_function(wrap_pyfunction!(upper_bound, m)?)?;
    m.add_function(wrap_pyfunction!(fit, m)?)?;
    m.add_function(wrap_pyfunction!(diagnose, m)?)?;
    m.add_function(wrap_pyfunction!(gauss_markov_variance, m)?)?;
    m.add_function(wrap_pyfunction!(gauss_markov_avar, m)?)?;
    m.add_function(wrap_pyfunction!(detect_lines, m)?)?;
    m.add_function(wrap_pyfunction!(sinusoid_avar, m)?)?;
    m.add_function(wrap_pyfunction!(add_lines, m)?)?;
    m.add_function(wrap_pyfunction!(wvar, m)?)?;
    m.add_function(wrap_pyfunction!(biweight_constant, m)?)?;
    m.add_function(wrap_pyfunction!(robust_variance, m)?)?;
    m.add_function(wrap_pyfunction!(gmwm, m)?)
}
