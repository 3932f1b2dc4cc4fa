//! Bindings of `gyrocore::noise::{fit, diagnose, gauss_markov}` (issue 11: diagnostics, region
//! selection, Gauss–Markov terms).

use gyrocore::noise::{
    self, Curve, Diagnostics, FitOptions, GaussMarkovEstimate, GmwmOptions, TermEstimate,
};
use numpy::{IntoPyArray, PyArray1, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::error::core;

fn as_usize(v: &[u64]) -> Vec<usize> {
    v.iter().map(|&x| x as usize).collect()
}

pub(crate) fn term_dicts<'py>(
    py: Python<'py>,
    terms: &[TermEstimate],
) -> PyResult<Vec<Bound<'py, PyDict>>> {
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
            Ok(d)
        })
        .collect()
}

pub(crate) fn gauss_markov_dicts<'py>(
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

pub(crate) fn diagnostics_dict<'py>(
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
    Ok(d)
}

/// Joint fit with Gauss–Markov terms, diagnostics and automatic τ-range selection.
#[pyfunction]
#[pyo3(signature = (taus, variance, m, n_terms, overlapping, edf, terms, tau_range, correlation_time, automatic_range))]
#[allow(clippy::needless_pass_by_value)]
fn noise_fit<'py>(
    py: Python<'py>,
    taus: PyReadonlyArray1<'py, f64>,
    variance: PyReadonlyArray1<'py, f64>,
    m: PyReadonlyArray1<'py, u64>,
    n_terms: PyReadonlyArray1<'py, u64>,
    overlapping: bool,
    edf: Option<PyReadonlyArray1<'py, f64>>,
    terms: Vec<String>,
    tau_range: Option<(f64, f64)>,
    correlation_time: Option<(f64, f64)>,
    automatic_range: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let symbols: Vec<&str> = terms.iter().map(String::as_str).collect();
    let (enabled, gauss_markov) = core(noise::parse_model_terms(&symbols))?;
    let m = as_usize(m.as_slice()?);
    let n_terms = as_usize(n_terms.as_slice()?);
    let edf_slice = match &edf {
        Some(e) => Some(e.as_slice()?),
        None => None,
    };
    let curve = Curve {
        taus: taus.as_slice()?,
        variance: variance.as_slice()?,
        m: &m,
        n_terms: &n_terms,
        overlapping,
        edf: edf_slice,
    };
    let options = FitOptions {
        enabled,
        gauss_markov,
        tau_range,
        correlation_time,
        automatic_range,
    };
    let fit = core(py.detach(|| noise::fit(&curve, &options)))?;
    let d = PyDict::new(py);
    d.set_item("terms", term_dicts(py, &fit.terms)?)?;
    d.set_item("squared", fit.squared.to_vec())?;
    d.set_item("gauss_markov", gauss_markov_dicts(py, &fit.gauss_markov)?)?;
    d.set_item("gauss_markov_squared", fit.gauss_markov_squared.clone())?;
    d.set_item("chi2", fit.chi2)?;
    d.set_item("dof", fit.dof)?;
    d.set_item("tau_range", fit.tau_range)?;
    d.set_item("diagnostics", diagnostics_dict(py, &fit.diagnostics)?)?;
    Ok(d)
}

/// Goodness-of-fit diagnostics of a given model on an Allan-variance curve.
#[pyfunction]
#[pyo3(signature = (taus, variance, m, n_terms, overlapping, edf, squared, gauss_markov, n_params))]
#[allow(clippy::needless_pass_by_value)]
fn noise_diagnose<'py>(
    py: Python<'py>,
    taus: PyReadonlyArray1<'py, f64>,
    variance: PyReadonlyArray1<'py, f64>,
    m: PyReadonlyArray1<'py, u64>,
    n_terms: PyReadonlyArray1<'py, u64>,
    overlapping: bool,
    edf: Option<PyReadonlyArray1<'py, f64>>,
    squared: [f64; 5],
    gauss_markov: Vec<(f64, f64)>,
    n_params: usize,
) -> PyResult<Bound<'py, PyDict>> {
    let m = as_usize(m.as_slice()?);
    let n_terms = as_usize(n_terms.as_slice()?);
    let edf_slice = match &edf {
        Some(e) => Some(e.as_slice()?),
        None => None,
    };
    let curve = Curve {
        taus: taus.as_slice()?,
        variance: variance.as_slice()?,
        m: &m,
        n_terms: &n_terms,
        overlapping,
        edf: edf_slice,
    };
    let d = core(noise::diagnose(&curve, &squared, &gauss_markov, n_params))?;
    diagnostics_dict(py, &d)
}

/// Allan variance of each Gauss–Markov component `(q², T)` at `taus`.
#[pyfunction]
#[pyo3(signature = (gauss_markov, taus))]
#[allow(clippy::needless_pass_by_value)]
fn noise_gauss_markov_variance<'py>(
    py: Python<'py>,
    gauss_markov: Vec<(f64, f64)>,
    taus: PyReadonlyArray1<'py, f64>,
) -> PyResult<Vec<Bound<'py, PyArray1<f64>>>> {
    let taus = taus.as_slice()?;
    Ok(gauss_markov
        .iter()
        .map(|&(q2, t)| {
            taus.iter()
                .map(|&tau| noise::gauss_markov::allan_variance(q2, t, tau))
                .collect::<Vec<f64>>()
                .into_pyarray(py)
        })
        .collect())
}

/// GMWM estimate of the noise model of one rate series.
#[pyfunction]
#[pyo3(signature = (data, t0, terms, select, bootstrap, seed, min_blocks))]
#[allow(clippy::needless_pass_by_value)]
fn noise_gmwm<'py>(
    py: Python<'py>,
    data: PyReadonlyArray1<'py, f64>,
    t0: f64,
    terms: Vec<String>,
    select: bool,
    bootstrap: usize,
    seed: u64,
    min_blocks: usize,
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
    };
    let rate = data.as_slice()?;
    let g = core(py.detach(|| noise::gmwm(rate, t0, &options)))?;
    let d = PyDict::new(py);
    let fit = &g.fit;
    d.set_item("terms", term_dicts(py, &fit.terms)?)?;
    d.set_item("squared", fit.squared.to_vec())?;
    d.set_item("gauss_markov", gauss_markov_dicts(py, &fit.gauss_markov)?)?;
    d.set_item("gauss_markov_squared", fit.gauss_markov_squared.clone())?;
    d.set_item("chi2", fit.chi2)?;
    d.set_item("dof", fit.dof)?;
    d.set_item("tau_range", fit.tau_range)?;
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
    let mut selected: Vec<&str> = noise::Term::ALL
        .iter()
        .filter(|t| sel_enabled[t.index()])
        .map(|t| t.symbol())
        .collect();
    if sel_gm >= 1 {
        selected.push("GM");
    }
    if sel_gm >= 2 {
        selected.push("GM2");
    }
    d.set_item("selected", selected)?;
    d.set_item("criterion", g.criterion)?;
    d.set_item("candidates", g.candidates.clone())?;
    d.set_item("bootstrap", g.bootstrap)?;
    Ok(d)
}

pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(noise_fit, m)?)?;
    m.add_function(wrap_pyfunction!(noise_diagnose, m)?)?;
    m.add_function(wrap_pyfunction!(noise_gauss_markov_variance, m)?)?;
    m.add_function(wrap_pyfunction!(noise_gmwm, m)?)
}
