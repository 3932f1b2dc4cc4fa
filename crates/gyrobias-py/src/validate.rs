//! Bindings of `gyrocore::validate`: the core's checks that the Python layer needs before it
//! computes with an argument itself.

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

pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(sample_period, m)?)
}
