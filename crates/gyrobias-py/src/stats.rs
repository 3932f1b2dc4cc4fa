//! Bindings of `gyrocore::stats`.

use gyrocore::stats;
use pyo3::prelude::*;

use crate::error::core;

/// Chi-square survival function `P(χ²_dof > x)` (`gyrocore::stats::chi2_sf`), exact to ~1e-13.
#[pyfunction]
#[pyo3(signature = (x, dof))]
fn chi2_sf(x: f64, dof: f64) -> PyResult<f64> {
    core(stats::chi2_sf(x, dof))
}

pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(chi2_sf, m)?)
}
