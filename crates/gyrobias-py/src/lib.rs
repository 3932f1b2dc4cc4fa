//! `gyrobias._core`: the pyo3 binding of gyrocore.
//!
//! One file per gyrocore module, each with a `register` function. This crate converts
//! arguments (zero-copy for contiguous float64 arrays), releases the GIL around the numerical
//! work and maps [`gyrocore::Error`] to Python exceptions. It contains no numerics.

mod allan;
mod error;
mod fir;
mod fractional;
mod kalman;
mod noise;
mod noise_fit;
mod predict;
mod spectral;
mod thermal;

use pyo3::prelude::*;

/// The extension module.
#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    error::register(m)?;
    allan::register(m)?;
    fir::register(m)?;
    spectral::register(m)?;
    thermal::register(m)?;
    fractional::register(m)?;
    predict::register(m)?;
    kalman::register(m)?;
    noise::register(m)?;
    noise_fit::register(m)?;
    Ok(())
}
