//! Bindings of `gyrocore::fir`.

use gyrocore::fir::{self, Mode};
use numpy::{
    IntoPyArray, PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2,
    PyUntypedArrayMethods,
};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::array::c_order;
use crate::count;
use crate::error::core;

/// Kaiser-window low-pass design (`gyrocore::fir::kaiser_lowpass`): dict with the design
/// quantities and `taps`.
#[pyfunction]
#[pyo3(signature = (fs, fpass, fstop, apass_db, astop_db))]
fn kaiser_lowpass(
    py: Python<'_>,
    fs: f64,
    fpass: f64,
    fstop: f64,
    apass_db: f64,
    astop_db: f64,
) -> PyResult<Bound<'_, PyDict>> {
    let f = core(fir::kaiser_lowpass(fs, fpass, fstop, apass_db, astop_db))?;
    let d = PyDict::new(py);
    d.set_item("cutoff", f.cutoff)?;
    d.set_item("delta_pass", f.delta_pass)?;
    d.set_item("delta_stop", f.delta_stop)?;
    d.set_item("attenuation_db", f.attenuation_db)?;
    d.set_item("alpha", f.alpha)?;
    d.set_item("d", f.d)?;
    d.set_item("taps", f.taps.into_pyarray(py))?;
    Ok(d)
}

/// Filters every row of a (rows × n) float64 array with FIR `taps` (`gyrocore::fir::filter_rows`).
#[pyfunction]
#[pyo3(signature = (taps, x, zero_phase, padtype, padlen))]
#[allow(clippy::needless_pass_by_value)]
fn filter_rows<'py>(
    py: Python<'py>,
    taps: PyReadonlyArray1<'py, f64>,
    x: PyReadonlyArray2<'py, f64>,
    zero_phase: bool,
    padtype: &str,
    #[pyo3(from_py_with = count::padlen)] padlen: usize,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let shape = [x.shape()[0], x.shape()[1]];
    let h = c_order(&taps);
    let data = c_order(&x);
    let mode = core(Mode::new(zero_phase, padtype, padlen))?;
    let out = core(py.detach(|| fir::filter_rows(&h, &data, shape[0], mode)))?;
    out.into_pyarray(py).reshape(shape)
}

/// Complex frequency response of `taps` at `freqs` (Hz): (real, imag)
/// (`gyrocore::fir::frequency_response`).
#[pyfunction]
#[pyo3(signature = (taps, fs, freqs))]
#[allow(clippy::needless_pass_by_value, clippy::type_complexity)]
fn frequency_response<'py>(
    py: Python<'py>,
    taps: PyReadonlyArray1<'py, f64>,
    fs: f64,
    freqs: PyReadonlyArray1<'py, f64>,
) -> PyResult<(Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<f64>>)> {
    let h = c_order(&taps);
    let f = c_order(&freqs);
    let (re, im) = core(py.detach(|| fir::frequency_response(&h, fs, &f)))?;
    Ok((re.into_pyarray(py), im.into_pyarray(py)))
}

/// Causal filtering of one stream chunk per row: returns (output rows, new state rows)
/// (`gyrocore::fir::filter_stream_rows`).
#[pyfunction]
#[pyo3(signature = (taps, x, state))]
#[allow(clippy::needless_pass_by_value, clippy::type_complexity)]
fn filter_stream_rows<'py>(
    py: Python<'py>,
    taps: PyReadonlyArray1<'py, f64>,
    x: PyReadonlyArray2<'py, f64>,
    state: PyReadonlyArray2<'py, f64>,
) -> PyResult<(Bound<'py, PyArray2<f64>>, Bound<'py, PyArray2<f64>>)> {
    let (rows, n) = (x.shape()[0], x.shape()[1]);
    let width = state.shape()[1];
    let h = c_order(&taps);
    let data = c_order(&x);
    let mut hist = c_order(&state).into_owned();
    let out = core(py.detach(|| fir::filter_stream_rows(&h, &data, rows, &mut hist)))?;
    Ok((
        out.into_pyarray(py).reshape([rows, n])?,
        hist.into_pyarray(py).reshape([rows, width])?,
    ))
}

/// Float32 causal filtering of one stream chunk per row: returns (output rows, new state
/// rows) (`gyrocore::fir::filter_stream_rows_f32`).
#[pyfunction]
#[pyo3(signature = (taps, x, state))]
#[allow(clippy::needless_pass_by_value, clippy::type_complexity)]
fn filter_stream_rows_f32<'py>(
    py: Python<'py>,
    taps: PyReadonlyArray1<'py, f32>,
    x: PyReadonlyArray2<'py, f32>,
    state: PyReadonlyArray2<'py, f32>,
) -> PyResult<(Bound<'py, PyArray2<f32>>, Bound<'py, PyArray2<f32>>)> {
    let (rows, n) = (x.shape()[0], x.shape()[1]);
    let width = state.shape()[1];
    let h = c_order(&taps);
    let data = c_order(&x);
    let mut hist = c_order(&state).into_owned();
    let out = core(py.detach(|| fir::filter_stream_rows_f32(&h, &data, rows, &mut hist)))?;
    Ok((
        out.into_pyarray(py).reshape([rows, n])?,
        hist.into_pyarray(py).reshape([rows, width])?,
    ))
}

pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(kaiser_lowpass, m)?)?;
    m.add_function(wrap_pyfunction!(filter_rows, m)?)?;
    m.add_function(wrap_pyfunction!(frequency_response, m)?)?;
    m.add_function(wrap_pyfunction!(filter_stream_rows, m)?)?;
    m.add_function(wrap_pyfunction!(filter_stream_rows_f32, m)?)
}
