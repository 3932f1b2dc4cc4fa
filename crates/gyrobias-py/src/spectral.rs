//! Bindings of `gyrocore::spectral`.

use gyrocore::spectral::{self, LssaOptions, Window};
use numpy::{IntoPyArray, PyArray1, PyReadonlyArray1, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::error::core;

/// Least-squares spectrum: dict with `spectrum`, `n_known`, `known_params`, `t_ref`,
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
    let t = t.as_slice()?;
    let y = y.as_slice()?;
    let freqs = freqs.as_slice()?;
    let weights = match &weights {
        Some(w) => Some(w.as_slice()?),
        None => None,
    };
    let cov = match &cov {
        Some(c) => Some(c.as_slice()?),
        None => None,
    };
    let periods = known_periods.as_slice()?;
    let columns = match &columns {
        Some(c) => Some((c.as_slice()?, c.shape()[1])),
        None => None,
    };
    let opts = LssaOptions {
        weights,
        cov,
        trend,
        known_periods: periods,
        columns,
    };
    let r = core(py.detach(|| spectral::lssa(t, y, freqs, &opts)))?;
    let d = PyDict::new(py);
    d.set_item("spectrum", r.spectrum.into_pyarray(py))?;
    d.set_item("n_known", r.n_known)?;
    d.set_item("known_params", r.known_params.into_pyarray(py))?;
    d.set_item("t_ref", r.t_ref)?;
    d.set_item("residual_norm", r.residual_norm)?;
    Ok(d)
}

/// Pagiatakis' critical spectral value `1 − alpha^(2/(n − u − 2))`.
#[pyfunction]
#[pyo3(signature = (n, n_known, alpha))]
fn lssa_critical(n: usize, n_known: usize, alpha: f64) -> PyResult<f64> {
    core(spectral::critical_value(n, n_known, alpha))
}

/// Default LSSA frequency grid of the times `t`.
#[pyfunction]
#[pyo3(signature = (t,))]
#[allow(clippy::needless_pass_by_value)]
fn lssa_frequencies<'py>(
    py: Python<'py>,
    t: PyReadonlyArray1<'py, f64>,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let t = t.as_slice()?;
    Ok(core(spectral::default_frequencies(t))?.into_pyarray(py))
}

/// Welch one-sided PSD: (freqs, psd).
#[pyfunction]
#[pyo3(signature = (x, fs, nperseg, noverlap, window))]
#[allow(clippy::needless_pass_by_value, clippy::type_complexity)]
fn welch_psd<'py>(
    py: Python<'py>,
    x: PyReadonlyArray1<'py, f64>,
    fs: f64,
    nperseg: usize,
    noverlap: usize,
    window: &str,
) -> PyResult<(Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<f64>>)> {
    let x = x.as_slice()?;
    let window = core(Window::parse(window))?;
    let (f, p) = core(py.detach(|| spectral::welch(x, fs, nperseg, noverlap, window)))?;
    Ok((f.into_pyarray(py), p.into_pyarray(py)))
}

pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(lssa, m)?)?;
    m.add_function(wrap_pyfunction!(lssa_critical, m)?)?;
    m.add_function(wrap_pyfunction!(lssa_frequencies, m)?)?;
    m.add_function(wrap_pyfunction!(welch_psd, m)?)
}
