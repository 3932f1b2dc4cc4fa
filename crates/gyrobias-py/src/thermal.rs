//! Bindings of `gyrocore::thermal`.

use gyrocore::thermal::{self, Method};
use numpy::{IntoPyArray, PyArray1, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::array::c_order;
use crate::count;
use crate::error::core;

/// AR(1) fit (`gyrocore::thermal::fit_ar1`): dict with `c`, `c_std_error`, `sigma_e`, `mean`, `n`, `beta`, `process_std`.
#[pyfunction]
#[pyo3(signature = (x, dt, demean))]
#[allow(clippy::needless_pass_by_value)]
fn fit_ar1<'py>(
    py: Python<'py>,
    x: PyReadonlyArray1<'py, f64>,
    dt: f64,
    demean: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let x = c_order(&x);
    let f = core(py.detach(|| thermal::fit_ar1(&x, dt, demean)))?;
    let d = PyDict::new(py);
    d.set_item("c", f.c)?;
    d.set_item("c_std_error", f.c_std_error)?;
    d.set_item("sigma_e", f.sigma_e)?;
    d.set_item("mean", f.mean)?;
    d.set_item("n", f.n)?;
    d.set_item("beta", f.beta)?;
    d.set_item("process_std", f.process_std)?;
    Ok(d)
}

/// Interpolates `values` given at `temperatures` at `at` (`method`: linear, pchip, polynomial)
/// (`gyrocore::thermal::interpolate`).
#[pyfunction]
#[pyo3(signature = (temperatures, values, method, degree, at, extrapolate))]
#[allow(clippy::needless_pass_by_value)]
fn interpolate<'py>(
    py: Python<'py>,
    temperatures: PyReadonlyArray1<'py, f64>,
    values: PyReadonlyArray1<'py, f64>,
    method: &str,
    #[pyo3(from_py_with = count::degree)] degree: usize,
    at: PyReadonlyArray1<'py, f64>,
    extrapolate: bool,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let method = core(Method::parse(method, degree))?;
    let x = c_order(&temperatures);
    let y = c_order(&values);
    let at = c_order(&at);
    Ok(core(thermal::interpolate(&x, &y, method, &at, extrapolate))?.into_pyarray(py))
}

/// Checks calibration temperatures: finite and distinct (`gyrocore::thermal::check_temperatures`).
#[pyfunction]
#[pyo3(signature = (temperatures))]
#[allow(clippy::needless_pass_by_value)]
fn check_temperatures(temperatures: PyReadonlyArray1<'_, f64>) -> PyResult<()> {
    core(thermal::check_temperatures(&c_order(&temperatures)))
}

pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(check_temperatures, m)?)?;
    m.add_function(wrap_pyfunction!(fit_ar1, m)?)?;
    m.add_function(wrap_pyfunction!(interpolate, m)?)
}
