//! Bindings of `gyrocore::codegen` (Q31 designs for the generated C).

use gyrocore::codegen::{self, Scaled};
use numpy::{PyReadonlyArray1, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::array::c_order;
use crate::error::core;

fn scaled<'py>(py: Python<'py>, s: &Scaled) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("value", s.value)?;
    d.set_item("shift", s.shift)?;
    d.set_item("represented", s.represented)?;
    d.set_item("error", s.error)?;
    Ok(d)
}

/// Q31 realisation of the fixed-gain Kalman recursion (`gyrocore::codegen::kalman_q31`).
#[pyfunction]
#[pyo3(signature = (pole, one_minus_pole, g1, g2, amplitude))]
fn kalman_q31(
    py: Python<'_>,
    pole: f64,
    one_minus_pole: f64,
    g1: f64,
    g2: f64,
    amplitude: f64,
) -> PyResult<Bound<'_, PyDict>> {
    let k = core(codegen::kalman_q31(pole, one_minus_pole, g1, g2, amplitude))?;
    let d = PyDict::new(py);
    d.set_item("a", scaled(py, &k.a)?)?;
    d.set_item("rate_gain", scaled(py, &k.rate_gain)?)?;
    d.set_item("bias_gain", scaled(py, &k.bias_gain)?)?;
    d.set_item("error_bound", (k.error_bound[0], k.error_bound[1]))?;
    d.set_item("noise_rms", (k.noise_rms[0], k.noise_rms[1]))?;
    Ok(d)
}

/// Q31 realisation of the dot products `W·x + w0` (rows × k) (`gyrocore::codegen::dot_q31`).
#[pyfunction]
#[pyo3(signature = (weights, offsets, amplitude))]
#[allow(clippy::needless_pass_by_value)]
fn dot_q31<'py>(
    py: Python<'py>,
    weights: PyReadonlyArray2<'py, f64>,
    offsets: PyReadonlyArray1<'py, f64>,
    amplitude: f64,
) -> PyResult<Bound<'py, PyDict>> {
    let rows = weights.shape()[0];
    let w = c_order(&weights);
    let o = c_order(&offsets);
    let q = core(codegen::dot_q31(&w, rows, &o, amplitude))?;
    let d = PyDict::new(py);
    d.set_item("values", q.values)?;
    d.set_item("shift", q.shift)?;
    d.set_item("offsets", q.offsets)?;
    d.set_item("error_bound", q.error_bound)?;
    d.set_item("coefficient_error", q.coefficient_error)?;
    d.set_item("noise_rms", q.noise_rms)?;
    Ok(d)
}

pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(kalman_q31, m)?)?;
    m.add_function(wrap_pyfunction!(dot_q31, m)?)
}
