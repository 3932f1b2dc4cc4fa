//! Bindings of `gyrocore::validate`: the core's checks that the Python layer needs before it
//! computes with an argument itself (a unit conversion, a report's options checked before any
//! channel is analysed), so that each precondition is written once, in the core.

use std::collections::HashSet;
use std::sync::{Mutex, OnceLock};

use gyrocore::validate;
use pyo3::prelude::*;

use crate::error::core;

/// The sample period `1/fs` of the sample rate `fs` in Hz (`gyrocore::validate::sample_period`):
/// a `ValueError` naming `fs` unless `fs` is finite, > 0 and has a finite period.
#[pyfunction]
#[pyo3(signature = (fs))]
fn sample_period(fs: f64) -> PyResult<f64> {
    core(validate::sample_period(fs))
}

/// The argument name as the `&'static str` the core's errors hold: each distinct name is
/// allocated once and kept (the Python layer passes a handful of fixed names).
fn intern(name: &str) -> &'static str {
    static NAMES: OnceLock<Mutex<HashSet<&'static str>>> = OnceLock::new();
    let mut names = NAMES
        .get_or_init(|| Mutex::new(HashSet::new()))
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner);
    if let Some(&known) = names.get(name) {
        return known;
    }
    let leaked: &'static str = Box::leak(name.to_owned().into_boxed_str());
    names.insert(leaked);
    leaked
}

/// `value` if it is finite and > 0 (`gyrocore::validate::positive`), else a `ValueError`
/// naming `name`.
#[pyfunction]
#[pyo3(signature = (name, value))]
fn positive(name: &str, value: f64) -> PyResult<f64> {
    core(validate::positive(intern(name), value))?;
    Ok(value)
}

/// `value` if it is finite and >= 0 (`gyrocore::validate::non_negative`), else a `ValueError`
/// naming `name`.
#[pyfunction]
#[pyo3(signature = (name, value))]
fn non_negative(name: &str, value: f64) -> PyResult<f64> {
    core(validate::non_negative(intern(name), value))?;
    Ok(value)
}

/// `value` if it lies strictly between 0 and 1 (`gyrocore::validate::probability`), else a
/// `ValueError` naming `name`.
#[pyfunction]
#[pyo3(signature = (name, value))]
fn probability(name: &str, value: f64) -> PyResult<f64> {
    core(validate::probability(intern(name), value))?;
    Ok(value)
}

pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(sample_period, m)?)?;
    m.add_function(wrap_pyfunction!(positive, m)?)?;
    m.add_function(wrap_pyfunction!(non_negative, m)?)?;
    m.add_function(wrap_pyfunction!(probability, m)?)
}
