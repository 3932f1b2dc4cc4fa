//! Bindings of `gyrocore::spectral`.

use gyrocore::spectral::{self, LssaOptions, Window};
use numpy::{IntoPyArray, PyArray1, PyReadonlyArray1, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::array::{c_order, c_order_opt};
use crate::count;
use crate::error::core;

/// Least-squares spectrum (`gyrocore::spectral::lssa`): dict with `spectrum`, `n_known`, `known_params`, `t_ref`,
/// `residual_norm`.
#[pyfunction]
#[pyo3(signature = (t, y, freqs, weights, cov, trend, known_periods, columns))]
#[allow(clippy::needless_pass_by_value)]
fn lssa<'py>(
    py: Python<'py>,
    t: PyReadonlyArray1<'py, f64>,
    y: PyReadonlyArray1<'py, f64>,
    freqs: PyReadonlyArray1<'py, f64>,
    weights: Option<PyReadonlyArray1<'py, f64>>,
    cov: Option<PyReadonlyArray2<'py, f64>>,
    trend: bool,
    known_periods: PyReadonlyArray1<'py, f64>,
    columns: Option<PyReadonlyArray2<'py, f64>>,
) -> PyResult<Bound<'py, PyDict>> {
    let t = c_order(&t);
    let y = c_order(&y);
    let freqs = c_order(&freqs);
    let weights = c_order_opt(weights.as_ref());
    let cov = c_order_opt(cov.as_ref());
    let periods = c_order(&known_periods);
    let n_columns = columns.as_ref().map_or(0, |c| c.shape()[1]);
    let columns = c_order_opt(columns.as_ref());
    let opts = LssaOptions {
        weights: weights.as_deref(),
        cov: cov.as_deref(),
        trend,
        known_periods: &periods,
        columns: columns.as_deref().map(|c| (c, n_columns)),
    };
    let r = core(py.detach(|| spectral::lssa(&t, &y, &freqs, &opts)))?;
    let d = PyDict::new(py);
    d.set_item("spectrum", r.spectrum.into_pyarray(py))?;
    d.set_item("n_known", r.n_known)?;
    d.set_item("known_params", r.known_params.into_pyarray(py))?;
    d.set_item("t_ref", r.t_ref)?;
    d.set_item("residual_norm", r.residual_norm)?;
    Ok(d)
}

/// Pagiatakis' critical spectral value `1 − alpha^(2/(n − u − 2))`
/// (`gyrocore::spectral::critical_value`).
#[pyfunction]
#[pyo3(signature = (n, n_known, alpha))]
fn critical_value(
    #[pyo3(from_py_with = count::n)] n: usize,
    #[pyo3(from_py_with = count::n_known)] n_known: usize,
    alpha: f64,
) -> PyResult<f64> {
    core(spectral::critical_value(n, n_known, alpha))
}

/// Default LSSA frequency grid of the times `t` (`gyrocore::spectral::default_frequencies`).
#[pyfunction]
#[pyo3(signature = (t,))]
#[allow(clippy::needless_pass_by_value)]
fn default_frequencies<'py>(
    py: Python<'py>,
    t: PyReadonlyArray1<'py, f64>,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let t = c_order(&t);
    Ok(core(spectral::default_frequencies(&t))?.into_pyarray(py))
}

/// Welch one-sided PSD: (freqs, psd) (`gyrocore::spectral::welch`).
#[pyfunction]
#[pyo3(signature = (x, fs, nperseg, noverlap, window))]
#[allow(clippy::needless_pass_by_value, clippy::type_complexity)]
fn welch<'py>(
    py: Python<'py>,
    x: PyReadonlyArray1<'py, f64>,
    fs: f64,
    #[pyo3(from_py_with = count::nperseg)] nperseg: usize,
    #[pyo3(from_py_with = count::noverlap)] noverlap: usize,
    window: &str,
) -> PyResult<(Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<f64>>)> {
    let x = c_order(&x);
    let window = core(Window::parse(window))?;
    let (f, p) = core(py.detach(|| spectral::welch(&x, fs, nperseg, noverlap, window)))?;
    Ok((f.into_pyarray(py), p.into_pyarray(py)))
}

pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(lssa, m)?)?;
    m.add_function(wrap_pyfunction!(critical_value, m)?)?;
    m.add_function(wrap_pyfunction!(default_frequencies, m)?)?;
    m.add_function(wrap_pyfunction!(welch, m)?)
}
