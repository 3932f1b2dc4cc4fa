//! Bindings of `gyrocore::noise::overbound` (conservative noise coefficients).

use gyrocore::noise::{self, Curve};
use numpy::{IntoPyArray, PyReadonlyArray1, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::error::core;

/// Tightest overbound `A c ≥ b`, `c ≥ floor` (default 0), minimising `Σ (A c)_i / b_i`.
#[pyfunction]
#[pyo3(signature = (design, bound, floor=None))]
#[allow(clippy::needless_pass_by_value)]
fn noise_overbound<'py>(
    py: Python<'py>,
    design: PyReadonlyArray2<'py, f64>,
    bound: PyReadonlyArray1<'py, f64>,
    floor: Option<PyReadonlyArray1<'py, f64>>,
) -> PyResult<Bound<'py, PyDict>> {
    if !design.is_c_contiguous() {
        return Err(pyo3::exceptions::PyValueError::new_err(
            "design must be a C-contiguous float64 array",
        ));
    }
    let shape = design.shape();
    let (rows, cols) = (shape[0], shape[1]);
    let design = design.as_slice()?;
    let bound = bound.as_slice()?;
    let zeros = vec![0.0; cols];
    let floor = match &floor {
        Some(f) => f.as_slice()?,
        None => &zeros,
    };
    let r = core(py.detach(|| noise::overbound_above(design, rows, cols, bound, floor)))?;
    let d = PyDict::new(py);
    d.set_item("coefficients", r.coefficients.into_pyarray(py))?;
    d.set_item("ratio", r.ratio.into_pyarray(py))?;
    d.set_item("objective", r.objective)?;
    d.set_item("pivots", r.pivots)?;
    Ok(d)
}

/// Conservative five-term coefficients overbounding the curve's upper confidence bound.
#[pyfunction]
#[pyo3(signature = (taus, variance, m, n_terms, overlapping, edf, reference, terms, tau_range, confidence))]
#[allow(clippy::needless_pass_by_value, clippy::too_many_arguments)]
fn noise_conservative<'py>(
    py: Python<'py>,
    taus: PyReadonlyArray1<'py, f64>,
    variance: PyReadonlyArray1<'py, f64>,
    m: PyReadonlyArray1<'py, u64>,
    n_terms: PyReadonlyArray1<'py, u64>,
    overlapping: bool,
    edf: Option<PyReadonlyArray1<'py, f64>>,
    reference: [f64; 5],
    terms: Vec<String>,
    tau_range: Option<(f64, f64)>,
    confidence: f64,
) -> PyResult<Bound<'py, PyDict>> {
    let symbols: Vec<&str> = terms.iter().map(String::as_str).collect();
    let allowed = core(noise::parse_terms(&symbols))?;
    let m: Vec<usize> = m.as_slice()?.iter().map(|&x| x as usize).collect();
    let n_terms: Vec<usize> = n_terms.as_slice()?.iter().map(|&x| x as usize).collect();
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

pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(noise_overbound, m)?)?;
    m.add_function(wrap_pyfunction!(noise_conservative, m)?)
}
