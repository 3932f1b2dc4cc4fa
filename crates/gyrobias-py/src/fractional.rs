//! Bindings of `gyrocore::fractional` (differencing, ARFIMA simulation, ELW estimation).

use gyrocore::fractional::{self, Method, elw};
use numpy::{
    IntoPyArray, PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2,
    PyUntypedArrayMethods,
};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::array::c_order;
use crate::count;
use crate::error::core;

/// The weights `π_0..π_{n−1}` of `(1 − B)^d`.
#[pyfunction]
fn weights(
    py: Python<'_>,
    d: f64,
    #[pyo3(from_py_with = count::n)] n: usize,
) -> PyResult<Bound<'_, PyArray1<f64>>> {
    Ok(core(fractional::weights(d, n))?.into_pyarray(py))
}

type RowsOp = fn(&[f64], usize, f64, Method) -> gyrocore::Result<Vec<f64>>;

fn rows_op<'py>(
    py: Python<'py>,
    data: &PyReadonlyArray2<'py, f64>,
    d: f64,
    method: &str,
    op: RowsOp,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let (rows, n) = (data.shape()[0], data.shape()[1]);
    let slice = c_order(data);
    let method = core(Method::parse(method))?;
    let out = core(py.detach(|| op(&slice, n, d, method)))?;
    out.into_pyarray(py).reshape([rows, n])
}

/// `Δ^d` along the rows of a (rows × n) float64 array (`gyrocore::fractional::diff_rows`).
#[pyfunction]
#[pyo3(signature = (data, d, method))]
#[allow(clippy::needless_pass_by_value)]
fn diff<'py>(
    py: Python<'py>,
    data: PyReadonlyArray2<'py, f64>,
    d: f64,
    method: &str,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    rows_op(py, &data, d, method, fractional::diff_rows)
}

/// `Δ^{−d}` along the rows of a (rows × n) float64 array
/// (`gyrocore::fractional::integrate_rows`).
#[pyfunction]
#[pyo3(signature = (data, d, method))]
#[allow(clippy::needless_pass_by_value)]
fn integrate<'py>(
    py: Python<'py>,
    data: PyReadonlyArray2<'py, f64>,
    d: f64,
    method: &str,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    rows_op(py, &data, d, method, fractional::integrate_rows)
}

/// `rows` ARFIMA(0, d, 0) series of length `n` as a (rows × n) array.
#[pyfunction]
#[pyo3(signature = (n, d, sigma, rows, seed, kind))]
fn arfima<'py>(
    py: Python<'py>,
    #[pyo3(from_py_with = count::n)] n: usize,
    d: f64,
    sigma: f64,
    #[pyo3(from_py_with = count::rows)] rows: usize,
    #[pyo3(from_py_with = count::seed)] seed: u64,
    kind: &str,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let kind = core(fractional::arfima::Kind::parse(kind))?;
    let out = core(py.detach(|| fractional::arfima::arfima(n, d, sigma, rows, seed, kind)))?;
    out.into_pyarray(py).reshape([rows, n])
}

/// ELW estimates for each row: a dict of per-row arrays `d`, `standard_error`, `objective`,
/// `at_bound` and the scalars `m`, `n`.
#[pyfunction(name = "elw")]
#[pyo3(signature = (data, m, lower, upper, level))]
#[allow(clippy::needless_pass_by_value)]
fn elw_rows<'py>(
    py: Python<'py>,
    data: PyReadonlyArray2<'py, f64>,
    #[pyo3(from_py_with = count::m)] m: Option<usize>,
    lower: f64,
    upper: f64,
    level: &str,
) -> PyResult<Bound<'py, PyDict>> {
    let n = data.shape()[1];
    let slice = c_order(&data);
    let level = core(elw::Level::parse(level))?;
    let est = core(py.detach(|| elw::elw_rows(&slice, n, m, (lower, upper), level)))?;
    let out = PyDict::new(py);
    let col = |f: fn(&elw::Estimate) -> f64| est.iter().map(f).collect::<Vec<f64>>();
    out.set_item("d", col(|e| e.d).into_pyarray(py))?;
    out.set_item("standard_error", col(|e| e.standard_error).into_pyarray(py))?;
    out.set_item("objective", col(|e| e.objective).into_pyarray(py))?;
    let at_bound: Vec<bool> = est.iter().map(|e| e.at_bound).collect();
    out.set_item("at_bound", at_bound.into_pyarray(py))?;
    out.set_item("m", est[0].m)?;
    out.set_item("n", est[0].n)?;
    Ok(out)
}

/// The ELW objective `R(d)` of one series at each of `ds`.
#[pyfunction]
#[pyo3(signature = (x, ds, m, level))]
#[allow(clippy::needless_pass_by_value)]
fn elw_objective<'py>(
    py: Python<'py>,
    x: PyReadonlyArray1<'py, f64>,
    ds: PyReadonlyArray1<'py, f64>,
    #[pyo3(from_py_with = count::m)] m: Option<usize>,
    level: &str,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let x = c_order(&x);
    let ds = c_order(&ds);
    let level = core(elw::Level::parse(level))?;
    Ok(core(py.detach(|| elw::objective(&x, &ds, m, level)))?.into_pyarray(py))
}

/// Two float64 arrays returned to Python (lower and upper bounds).
type ArrayPair<'py> = (Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<f64>>);

/// Asymptotic normal interval of ELW estimates
/// (`gyrocore::fractional::elw::confidence_interval`): `(lower, upper)`.
#[pyfunction]
#[pyo3(signature = (d, standard_error, confidence))]
#[allow(clippy::needless_pass_by_value)]
fn elw_confidence_interval<'py>(
    py: Python<'py>,
    d: PyReadonlyArray1<'py, f64>,
    standard_error: f64,
    confidence: f64,
) -> PyResult<ArrayPair<'py>> {
    let (lo, hi) = core(elw::confidence_interval(
        &c_order(&d),
        standard_error,
        confidence,
    ))?;
    Ok((lo.into_pyarray(py), hi.into_pyarray(py)))
}

pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(elw_confidence_interval, m)?)?;
    m.add_function(wrap_pyfunction!(weights, m)?)?;
    m.add_function(wrap_pyfunction!(diff, m)?)?;
    m.add_function(wrap_pyfunction!(integrate, m)?)?;
    m.add_function(wrap_pyfunction!(arfima, m)?)?;
    m.add_function(wrap_pyfunction!(elw_rows, m)?)?;
    m.add_function(wrap_pyfunction!(elw_objective, m)?)
}
