//! `gyrobias._core`: the pyo3 binding of gyrocore.
//!
//! One submodule per gyrocore module, with gyrocore's function names: `gyrobias._core.allan`
//! binds `gyrocore::allan`, `gyrobias._core.noise` binds `gyrocore::noise`, and so on. Each
//! submodule is registered in `sys.modules` under its dotted name, so
//! `from gyrobias._core import allan` and `import gyrobias._core.allan` both work (and
//! stubtest checks the stub package `gyrobias/_core/`).
//!
//! This crate only converts arguments (every input array through `array::c_order`: zero-copy
//! for C-contiguous float64 arrays; every integer through `count`, which turns a negative or
//! too large value into a `ValueError` naming the argument), releases the GIL around the
//! numerical work and maps [`gyrocore::Error`] to Python exceptions. It contains no numerics,
//! no checks of its own and no state types: a `#[pyclass]` holding state (`KalmanState`) wraps
//! the core's type, which owns its checks.

mod allan;
mod array;
mod bags;
mod cleaning;
mod codegen;
mod count;
mod discrete;
mod error;
mod evaluate;
mod fir;
mod fleet;
mod fractional;
mod kalman;
mod noise;
mod predict;
mod random;
mod spectral;
mod stationarity;
mod stats;
mod text;
mod thermal;
mod timestamps;
mod validate;

use pyo3::prelude::*;

/// Registers `gyrobias._core.<name>` as a submodule of `parent` and in `sys.modules`.
fn submodule(
    parent: &Bound<'_, PyModule>,
    name: &str,
    register: fn(&Bound<'_, PyModule>) -> PyResult<()>,
) -> PyResult<()> {
    let py = parent.py();
    let full = format!("gyrobias._core.{name}");
    let sub = PyModule::new(py, &full)?;
    register(&sub)?;
    parent.setattr(name, &sub)?;
    py.import("sys")?
        .getattr("modules")?
        .set_item(&full, &sub)?;
    Ok(())
}

/// `gyrobias._core.predict`: `gyrocore::predict` and its `evaluate` submodule.
fn predict_module(m: &Bound<'_, PyModule>) -> PyResult<()> {
    predict::register(m)?;
    evaluate::register(m)
}

/// `gyrobias._core.noise`: `gyrocore::noise` and its `discrete` submodule.
fn noise_module(m: &Bound<'_, PyModule>) -> PyResult<()> {
    noise::register(m)?;
    discrete::register(m)
}

/// The instruction set of the core's vectorised kernels (`gyrocore::simd`): `"x86-64-v3"`
/// (AVX2, FMA), `"neon"`, or `"scalar"` (the baseline, forced by `GYROBIAS_SIMD=scalar`).
#[pyfunction]
fn instruction_set() -> &'static str {
    gyrocore::simd::instruction_set()
}

/// The extension module.
#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    error::register(m)?;
    // The package version, set once in the workspace's Cargo.toml (the wheel's version too).
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    // A misspelt GYROBIAS_SIMD fails the import with the core's message.
    error::core(gyrocore::simd::check())?;
    m.add_function(wrap_pyfunction!(instruction_set, m)?)?;
    submodule(m, "allan", allan::register)?;
    submodule(m, "codegen", codegen::register)?;
    submodule(m, "fir", fir::register)?;
    submodule(m, "spectral", spectral::register)?;
    submodule(m, "thermal", thermal::register)?;
    submodule(m, "fractional", fractional::register)?;
    submodule(m, "predict", predict_module)?;
    submodule(m, "kalman", kalman::register)?;
    submodule(m, "noise", noise_module)?;
    submodule(m, "stats", stats::register)?;
    submodule(m, "fleet", fleet::register)?;
    submodule(m, "timestamps", timestamps::register)?;
    submodule(m, "stationarity", stationarity::register)?;
    submodule(m, "random", random::register)?;
    submodule(m, "validate", validate::register)?;
    submodule(m, "bags", bags::register)?;
    submodule(m, "cleaning", cleaning::register)?;
    submodule(m, "text", text::register)?;
    Ok(())
}
