//! Bindings of `gyrocore::random`: the library's one generator, for the Python code that needs
//! random numbers (CLI experiments, plot jitter, seeds per axis).

use gyrocore::random;
use numpy::{IntoPyArray, PyArray1};
use pyo3::prelude::*;

use crate::count;

/// `n` standard normal deviates from `seed` (`gyrocore::random::normal_vec`).
#[pyfunction]
#[pyo3(signature = (n, seed))]
fn normal(
    py: Python<'_>,
    #[pyo3(from_py_with = count::n)] n: usize,
    #[pyo3(from_py_with = count::seed)] seed: u64,
) -> Bound<'_, PyArray1<f64>> {
    py.detach(|| random::normal_vec(n, seed)).into_pyarray(py)
}

/// `n` uniform deviates in `[0, 1)` from `seed` (`gyrocore::random::uniform_vec`).
#[pyfunction]
#[pyo3(signature = (n, seed))]
fn uniform(
    py: Python<'_>,
    #[pyo3(from_py_with = count::n)] n: usize,
    #[pyo3(from_py_with = count::seed)] seed: u64,
) -> Bound<'_, PyArray1<f64>> {
    py.detach(|| random::uniform_vec(n, seed)).into_pyarray(py)
}

/// `k` seeds for independent streams from `seed` (`gyrocore::random::seeds`).
#[pyfunction]
#[pyo3(signature = (n, seed))]
fn seeds(
    #[pyo3(from_py_with = count::n)] n: usize,
    #[pyo3(from_py_with = count::seed)] seed: u64,
) -> Vec<u64> {
    random::seeds(n, seed)
}

pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(normal, m)?)?;
    m.add_function(wrap_pyfunction!(uniform, m)?)?;
    m.add_function(wrap_pyfunction!(seeds, m)?)
}
