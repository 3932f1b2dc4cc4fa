//! Bindings of `gyrocore::predict::evaluate` (registered in `gyrobias._core.predict`).

use gyrocore::predict::evaluate::{self as batch_test, Method, Scores, Statistic};
use gyrocore::predict::{MeanPrior, Model};
use numpy::{IntoPyArray, PyArray1, PyReadonlyArray1, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;

use crate::array::c_order;
use crate::count;
use crate::error::core;

/// Per-section scores of one method (`gyrocore::predict::evaluate::Scores`), built once by
/// [`evaluate`]; read-only.
#[pyclass(name = "Scores", module = "gyrobias._core.predict", frozen)]
struct PyScores {
    inner: Scores,
}

#[pymethods]
impl PyScores {
    /// Integrated error of every section.
    #[getter]
    fn integrated_error<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.inner.integrated_error.clone().into_pyarray(py)
    }
    /// RSSE of every section.
    #[getter]
    fn rsse<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.inner.rsse.clone().into_pyarray(py)
    }
}

/// \[BP\]'s batch test (`gyrocore::predict::evaluate::evaluate`): `log` flat, `row_width` the
/// section width of a 2-D log or `None` for a long 1-D log.
#[pyfunction]
#[pyo3(signature = (log, row_width, calibration, horizon, methods, d, q, r, mean, mu0, p0, n_threads))]
#[allow(clippy::needless_pass_by_value, clippy::too_many_arguments)]
fn evaluate(
    py: Python<'_>,
    log: PyReadonlyArray1<'_, f64>,
    #[pyo3(from_py_with = count::row_width)] row_width: Option<usize>,
    #[pyo3(from_py_with = count::calibration)] calibration: usize,
    #[pyo3(from_py_with = count::horizon)] horizon: usize,
    methods: Vec<String>,
    d: f64,
    q: f64,
    r: f64,
    mean: &str,
    mu0: f64,
    p0: f64,
    #[pyo3(from_py_with = count::n_threads)] n_threads: usize,
) -> PyResult<Vec<PyScores>> {
    let data = c_order(&log);
    let methods = methods
        .iter()
        .map(|m| core(Method::parse(m)))
        .collect::<PyResult<Vec<_>>>()?;
    let model = core(Model::new(d, q, r, core(MeanPrior::parse(mean, mu0, p0))?))?;
    let scores = core(py.detach(|| {
        batch_test::evaluate(
            &data,
            row_width,
            calibration,
            horizon,
            &methods,
            &model,
            n_threads,
        )
    }))?;
    Ok(scores.into_iter().map(|inner| PyScores { inner }).collect())
}

/// Integrated error of every row (`gyrocore::predict::evaluate::integrated_error`).
#[pyfunction]
#[pyo3(signature = (y, yhat))]
#[allow(clippy::needless_pass_by_value)]
fn integrated_error<'py>(
    py: Python<'py>,
    y: PyReadonlyArray2<'py, f64>,
    yhat: PyReadonlyArray2<'py, f64>,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let (w, wh) = (y.shape()[1], yhat.shape()[1]);
    let (a, b) = (c_order(&y), c_order(&yhat));
    let out = core(py.detach(|| batch_test::integrated_error(&a, &b, w, wh)))?;
    Ok(out.into_pyarray(py))
}

/// RSSE of every row (`gyrocore::predict::evaluate::rsse`).
#[pyfunction]
#[pyo3(signature = (y, yhat))]
#[allow(clippy::needless_pass_by_value)]
fn rsse<'py>(
    py: Python<'py>,
    y: PyReadonlyArray2<'py, f64>,
    yhat: PyReadonlyArray2<'py, f64>,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let (w, wh) = (y.shape()[1], yhat.shape()[1]);
    let (a, b) = (c_order(&y), c_order(&yhat));
    let out = core(py.detach(|| batch_test::rsse(&a, &b, w, wh)))?;
    Ok(out.into_pyarray(py))
}

/// Mean and sample standard deviation (`gyrocore::predict::evaluate::mean_std`).
#[pyfunction]
#[pyo3(signature = (values))]
#[allow(clippy::needless_pass_by_value)]
fn mean_std(values: PyReadonlyArray1<'_, f64>) -> (f64, f64) {
    batch_test::mean_std(&c_order(&values))
}

/// A ratio of statistics with its paired bootstrap standard error
/// (`gyrocore::predict::evaluate::bootstrap_ratio`).
#[pyfunction]
#[pyo3(signature = (a, b, statistic, resamples, seed))]
#[allow(clippy::needless_pass_by_value)]
fn bootstrap_ratio(
    py: Python<'_>,
    a: PyReadonlyArray1<'_, f64>,
    b: PyReadonlyArray1<'_, f64>,
    statistic: &str,
    #[pyo3(from_py_with = count::resamples)] resamples: usize,
    #[pyo3(from_py_with = count::seed)] seed: u64,
) -> PyResult<(f64, f64)> {
    let statistic = core(Statistic::parse(statistic))?;
    let (a, b) = (c_order(&a), c_order(&b));
    core(py.detach(|| batch_test::bootstrap_ratio(&a, &b, statistic, resamples, seed)))
}

pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("MIN_BOOTSTRAP_SECTIONS", batch_test::MIN_BOOTSTRAP_SECTIONS)?;
    m.add_class::<PyScores>()?;
    m.add_function(wrap_pyfunction!(evaluate, m)?)?;
    m.add_function(wrap_pyfunction!(integrated_error, m)?)?;
    m.add_function(wrap_pyfunction!(rsse, m)?)?;
    m.add_function(wrap_pyfunction!(mean_std, m)?)?;
    m.add_function(wrap_pyfunction!(bootstrap_ratio, m)?)
}
