//! Bindings of `gyrocore::predict`.

use gyrocore::predict::{self, Algorithm, MeanPrior, Model, batch::Compiled};
use numpy::{
    IntoPyArray, PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray2, PyUntypedArrayMethods,
};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::array::c_order;
use crate::count;
use crate::error::core;

/// A pair of float64 arrays returned to Python.
type ArrayPair<'py> = (Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<f64>>);

fn model(d: f64, q: f64, r: f64, mean: &str, mu0: f64, p0: f64) -> PyResult<Model> {
    let prior = core(MeanPrior::parse(mean, mu0, p0))?;
    core(Model::new(d, q, r, prior))
}

/// Checks a model and an algorithm name with the core's preconditions (`gyrocore::predict::Model::new`,
/// `Algorithm::parse`): the Python predictor calls it when it is constructed.
#[pyfunction]
#[pyo3(signature = (d, q, r, mean, mu0, p0, algorithm))]
fn validate_model(
    d: f64,
    q: f64,
    r: f64,
    mean: &str,
    mu0: f64,
    p0: f64,
    algorithm: &str,
) -> PyResult<()> {
    model(d, q, r, mean, mu0, p0)?;
    core(Algorithm::parse(algorithm))?;
    Ok(())
}

/// The model variances `(q, r)` from noise coefficients (`gyrocore::predict::noise_parameters`).
#[pyfunction]
#[pyo3(signature = (arw, bias_instability, fs))]
fn noise_parameters(arw: f64, bias_instability: f64, fs: f64) -> PyResult<(f64, f64)> {
    core(predict::noise_parameters(arw, bias_instability, fs))
}

/// Fractional Kalman prediction of each row of a (windows × k) float64 array
/// (`gyrocore::predict::fractional_kalman_rows`).
///
/// Returns a dict with `bias` (flat windows·h), `std`, `std_observation` (h), `mean` (windows)
/// and `mean_std`.
#[pyfunction]
#[pyo3(signature = (calibration, horizon, d, q, r, mean, mu0, p0, algorithm, n_threads))]
#[allow(clippy::needless_pass_by_value)]
fn fractional_kalman<'py>(
    py: Python<'py>,
    calibration: PyReadonlyArray2<'py, f64>,
    #[pyo3(from_py_with = count::horizon)] horizon: usize,
    d: f64,
    q: f64,
    r: f64,
    mean: &str,
    mu0: f64,
    p0: f64,
    algorithm: &str,
    #[pyo3(from_py_with = count::n_threads)] n_threads: usize,
) -> PyResult<Bound<'py, PyDict>> {
    let k = calibration.shape()[1];
    let data = c_order(&calibration);
    let model = model(d, q, r, mean, mu0, p0)?;
    let algorithm = core(Algorithm::parse(algorithm))?;
    let p = core(py.detach(|| {
        predict::fractional_kalman_rows(&model, &data, k, horizon, algorithm, n_threads)
    }))?;
    let out = PyDict::new(py);
    out.set_item("bias", p.bias.into_pyarray(py))?;
    out.set_item("std", p.std.into_pyarray(py))?;
    out.set_item("std_observation", p.std_observation.into_pyarray(py))?;
    out.set_item("mean", p.mean.into_pyarray(py))?;
    out.set_item("mean_std", p.mean_std)?;
    Ok(out)
}

/// Calibration-mean forecast of each row (flat windows·h).
#[pyfunction]
#[allow(clippy::needless_pass_by_value)]
fn calibration_mean<'py>(
    py: Python<'py>,
    calibration: PyReadonlyArray2<'py, f64>,
    #[pyo3(from_py_with = count::horizon)] horizon: usize,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let k = calibration.shape()[1];
    let data = c_order(&calibration);
    let out = core(py.detach(|| predict::calibration_mean(&data, k, horizon)))?;
    Ok(out.into_pyarray(py))
}

/// Moving-average forecast of each row (flat windows·h).
#[pyfunction]
#[allow(clippy::needless_pass_by_value)]
fn moving_average<'py>(
    py: Python<'py>,
    calibration: PyReadonlyArray2<'py, f64>,
    #[pyo3(from_py_with = count::horizon)] horizon: usize,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let k = calibration.shape()[1];
    let data = c_order(&calibration);
    let out = core(py.detach(|| predict::moving_average(&data, k, horizon)))?;
    Ok(out.into_pyarray(py))
}

/// A compiled linear fractional Kalman predictor `ŷ = W·y + w0` (immutable, thread-safe).
#[pyclass(frozen, module = "gyrobias._core.predict")]
struct CompiledPredictor {
    inner: Compiled,
}

#[pymethods]
impl CompiledPredictor {
    #[new]
    #[pyo3(signature = (calibration_length, horizon, d, q, r, mean, mu0, p0, n_threads))]
    fn new(
        py: Python<'_>,
        #[pyo3(from_py_with = count::calibration_length)] calibration_length: usize,
        #[pyo3(from_py_with = count::horizon)] horizon: usize,
        d: f64,
        q: f64,
        r: f64,
        mean: &str,
        mu0: f64,
        p0: f64,
        #[pyo3(from_py_with = count::n_threads)] n_threads: usize,
    ) -> PyResult<Self> {
        let model = model(d, q, r, mean, mu0, p0)?;
        let inner =
            core(py.detach(|| Compiled::new(&model, calibration_length, horizon, n_threads)))?;
        Ok(Self { inner })
    }

    /// Predicts each row of a (windows × k) batch: `(bias (flat windows·h), mean)`.
    #[allow(clippy::needless_pass_by_value)]
    fn predict<'py>(
        &self,
        py: Python<'py>,
        batch: PyReadonlyArray2<'py, f64>,
        #[pyo3(from_py_with = count::n_threads)] n_threads: usize,
    ) -> PyResult<ArrayPair<'py>> {
        let k = batch.shape()[1];
        let data = c_order(&batch);
        let p = core(py.detach(|| self.inner.apply_rows(&data, k, n_threads)))?;
        Ok((p.bias.into_pyarray(py), p.mean.into_pyarray(py)))
    }

    /// Each row of a (windows × k) batch in the generated C's order, float64
    /// (`gyrocore::predict::batch::Compiled::apply_sequential::<f64>`): `(bias, mean)`.
    #[allow(clippy::needless_pass_by_value)]
    fn predict_sequential<'py>(
        &self,
        py: Python<'py>,
        batch: PyReadonlyArray2<'py, f64>,
    ) -> PyResult<ArrayPair<'py>> {
        let k = batch.shape()[1];
        let data = c_order(&batch);
        let (bias, mean) = core(py.detach(|| self.inner.apply_sequential::<f64>(&data, k)))?;
        Ok((bias.into_pyarray(py), mean.into_pyarray(py)))
    }

    /// [`predict_sequential`](Self::predict_sequential) in float32
    /// (`gyrocore::predict::batch::Compiled::apply_sequential::<f32>`).
    #[allow(clippy::needless_pass_by_value, clippy::type_complexity)]
    fn predict_sequential_f32<'py>(
        &self,
        py: Python<'py>,
        batch: PyReadonlyArray2<'py, f32>,
    ) -> PyResult<(Bound<'py, PyArray1<f32>>, Bound<'py, PyArray1<f32>>)> {
        let k = batch.shape()[1];
        let data = c_order(&batch);
        let (bias, mean) = core(py.detach(|| self.inner.apply_sequential::<f32>(&data, k)))?;
        Ok((bias.into_pyarray(py), mean.into_pyarray(py)))
    }

    #[getter]
    fn calibration_length(&self) -> usize {
        self.inner.calibration_length
    }

    #[getter]
    fn horizon(&self) -> usize {
        self.inner.horizon
    }

    /// `W` (h × k).
    #[getter]
    fn weights<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        self.inner
            .weights
            .clone()
            .into_pyarray(py)
            .reshape([self.inner.horizon, self.inner.calibration_length])
    }

    #[getter]
    fn offset<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.inner.offset.clone().into_pyarray(py)
    }

    #[getter]
    fn std<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.inner.std.clone().into_pyarray(py)
    }

    #[getter]
    fn std_observation<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.inner.std_observation.clone().into_pyarray(py)
    }

    #[getter]
    fn mean_std(&self) -> f64 {
        self.inner.mean_std
    }
}

pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(validate_model, m)?)?;
    m.add_function(wrap_pyfunction!(noise_parameters, m)?)?;
    m.add_function(wrap_pyfunction!(fractional_kalman, m)?)?;
    m.add_function(wrap_pyfunction!(calibration_mean, m)?)?;
    m.add_function(wrap_pyfunction!(moving_average, m)?)?;
    m.add_class::<CompiledPredictor>()
}
