//! Mapping of [`gyrocore::Error`] to Python exceptions.
//!
//! Invalid arguments, non-finite or too-short data and shape mismatches become `ValueError`;
//! a numerically singular problem becomes `gyrobias.GyroLinAlgError`, a `ValueError` subclass;
//! a size that cannot be allocated becomes `MemoryError` (checked before allocating).

use pyo3::exceptions::{PyMemoryError, PyValueError};
use pyo3::prelude::*;

pyo3::create_exception!(
    _core,
    GyroLinAlgError,
    PyValueError,
    "A numerically singular or ill-conditioned problem (a ValueError subclass)."
);

/// Converts a gyrocore result into a Python result (the orphan rule forbids a `From` impl).
pub(crate) fn core<T>(result: gyrocore::Result<T>) -> PyResult<T> {
    result.map_err(to_pyerr)
}

fn to_pyerr(err: gyrocore::Error) -> PyErr {
    match err {
        gyrocore::Error::Singular { .. } => GyroLinAlgError::new_err(err.to_string()),
        gyrocore::Error::Allocation { .. } => PyMemoryError::new_err(err.to_string()),
        other => PyValueError::new_err(other.to_string()),
    }
}

pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("GyroLinAlgError", m.py().get_type::<GyroLinAlgError>())
}
