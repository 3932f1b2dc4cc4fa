//! Bindings of `gyrocore::allan`.

use std::sync::Mutex;

use gyrocore::allan::{self, Config, DataType, Estimator, Gaps, Progress, Taus, dynamic, family};
use numpy::{
    IntoPyArray, PyArray1, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2, PyReadonlyArray3,
    PyUntypedArrayMethods,
};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::array::c_order;
use crate::count;
use crate::error::core;

/// The analysis options, parsed by the core.
#[allow(clippy::too_many_arguments)]
fn config(
    t0: f64,
    data_type: &str,
    estimator: &str,
    tau_spec: &str,
    per_decade: usize,
    taus: Option<&PyReadonlyArray1<'_, f64>>,
    confidence: Option<f64>,
    gaps: &str,
) -> PyResult<Config> {
    let explicit = taus.map(|t| c_order(t).into_owned());
    Ok(Config {
        t0,
        data_type: core(DataType::parse(data_type))?,
        estimator: core(Estimator::parse(estimator))?,
        taus: core(Taus::parse(tau_spec, per_decade, explicit))?,
        confidence,
        gaps: core(Gaps::parse(gaps))?,
    })
}

/// A Python callable as the core's progress hook: called with the GIL re-attached (from
/// whichever worker thread finished the work); an exception it raises cancels the analysis
/// and is re-raised to the caller.
pub(crate) struct PyHook {
    callback: Option<Py<PyAny>>,
    error: Mutex<Option<PyErr>>,
}

impl PyHook {
    pub(crate) fn new(callback: Option<Py<PyAny>>) -> Self {
        PyHook {
            callback,
            error: Mutex::new(None),
        }
    }

    fn call(&self, fraction: f64) -> bool {
        let Some(callback) = &self.callback else {
            return true;
        };
        Python::attach(|py| match callback.call1(py, (fraction,)) {
            Ok(_) => true,
            Err(e) => {
                *self
                    .error
                    .lock()
                    .unwrap_or_else(std::sync::PoisonError::into_inner) = Some(e);
                false
            }
        })
    }

    /// Runs `work` without the GIL with this hook as its progress; the callback's exception
    /// (if any) takes precedence over the core's `Cancelled`.
    pub(crate) fn run<T: Send>(
        &self,
        py: Python<'_>,
        work: impl FnOnce(&Progress<'_>) -> gyrocore::Result<T> + Send,
    ) -> PyResult<T> {
        let hook = |f: f64| self.call(f);
        let result = py.detach(|| {
            let progress = if self.callback.is_some() {
                Progress::new(Some(&hook))
            } else {
                Progress::new(None)
            };
            work(&progress)
        });
        if let Some(e) = self
            .error
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .take()
        {
            return Err(e);
        }
        core(result)
    }
}

/// A Python callable `read(start, count) -> float64 array` as the core's sample source; an
/// exception it raises stops the analysis and is re-raised to the caller.
struct PySource<'h> {
    read: Py<PyAny>,
    len: usize,
    error: &'h Mutex<Option<PyErr>>,
}

impl allan::stream::Source for PySource<'_> {
    fn len(&self) -> usize {
        self.len
    }

    fn read(&mut self, start: usize, out: &mut [f64]) -> gyrocore::Result<()> {
        Python::attach(|py| -> PyResult<()> {
            let values = self.read.call1(py, (start, out.len()))?;
            let values: PyReadonlyArray1<'_, f64> = values.extract(py)?;
            let values = c_order(&values);
            if values.len() != out.len() {
                return Err(pyo3::exceptions::PyValueError::new_err(format!(
                    "read({start}, {}) returned {} values",
                    out.len(),
                    values.len()
                )));
            }
            out.copy_from_slice(&values);
            Ok(())
        })
        .map_err(|e| {
            *self
                .error
                .lock()
                .unwrap_or_else(std::sync::PoisonError::into_inner) = Some(e);
            gyrocore::Error::Cancelled
        })
    }
}

fn to_dict(py: Python<'_>, r: allan::AllanAnalysis) -> PyResult<Bound<'_, PyDict>> {
    let d = PyDict::new(py);
    let m: Vec<u64> = r.m.iter().map(|&m| m as u64).collect();
    let n: Vec<u64> = r.n_terms.iter().map(|&n| n as u64).collect();
    d.set_item("m", m.into_pyarray(py))?;
    d.set_item("variance", r.variance.into_pyarray(py))?;
    d.set_item("deviation", r.deviation.into_pyarray(py))?;
    d.set_item("n_terms", n.into_pyarray(py))?;
    if let Some(c) = r.confidence {
        d.set_item("alpha", c.alpha.into_pyarray(py))?;
        d.set_item("edf", c.edf.into_pyarray(py))?;
        d.set_item("low", c.low.into_pyarray(py))?;
        d.set_item("high", c.high.into_pyarray(py))?;
    }
    if let Some((low, high)) = r.deviation_bounds {
        d.set_item("deviation_low", low.into_pyarray(py))?;
        d.set_item("deviation_high", high.into_pyarray(py))?;
    }
    if let Some(b) = r.blocks {
        d.set_item("block_means", b.means.into_pyarray(py))?;
        d.set_item("block_length", b.length)?;
        d.set_item("block_samples", b.n)?;
    }
    if let Some(v) = r.data_variance {
        d.set_item("data_variance", v)?;
    }
    if let Some(v) = r.data_deviation {
        d.set_item("data_deviation", v)?;
    }
    Ok(d)
}

/// Allan-family analysis of each column of a (samples × axes) float64 array
/// (`gyrocore::allan::analyse_matrix`).
///
/// Returns one dict per axis with keys `m`, `variance`, `deviation`, `n_terms` and, when
/// `confidence` is given, `alpha`, `edf`, `low`, `high` (variance bounds), `deviation_low`,
/// `deviation_high`. `progress(fraction)` is called from the kernel.
#[pyfunction]
#[pyo3(signature = (data, t0, data_type, estimator, tau_spec, per_decade, taus, confidence, gaps="error", progress=None))]
#[allow(clippy::needless_pass_by_value, clippy::too_many_arguments)]
fn analyse<'py>(
    py: Python<'py>,
    data: PyReadonlyArray2<'py, f64>,
    t0: f64,
    data_type: &str,
    estimator: &str,
    tau_spec: &str,
    #[pyo3(from_py_with = count::per_decade)] per_decade: usize,
    taus: Option<PyReadonlyArray1<'py, f64>>,
    confidence: Option<f64>,
    gaps: &str,
    progress: Option<Py<PyAny>>,
) -> PyResult<Vec<Bound<'py, PyDict>>> {
    let n_axes = data.shape()[1];
    let slice = c_order(&data);
    let cfg = config(
        t0,
        data_type,
        estimator,
        tau_spec,
        per_decade,
        taus.as_ref(),
        confidence,
        gaps,
    )?;
    let results =
        PyHook::new(progress).run(py, |p| allan::analyse_matrix(&slice, n_axes, &cfg, p))?;
    results.into_iter().map(|r| to_dict(py, r)).collect()
}

/// Allan-family analysis of a (units × samples × axes) float64 batch in one call
/// (`gyrocore::allan::batch::analyse_batch`: GIL released for the whole batch, scratch buffers
/// reused across units).
///
/// Returns `[unit][axis]` dicts as [`allan_analysis`].
#[pyfunction]
#[pyo3(signature = (data, t0, data_type, estimator, tau_spec, per_decade, taus, confidence, gaps="error", progress=None))]
#[allow(clippy::needless_pass_by_value, clippy::too_many_arguments)]
fn analyse_batch<'py>(
    py: Python<'py>,
    data: PyReadonlyArray3<'py, f64>,
    t0: f64,
    data_type: &str,
    estimator: &str,
    tau_spec: &str,
    #[pyo3(from_py_with = count::per_decade)] per_decade: usize,
    taus: Option<PyReadonlyArray1<'py, f64>>,
    confidence: Option<f64>,
    gaps: &str,
    progress: Option<Py<PyAny>>,
) -> PyResult<Vec<Vec<Bound<'py, PyDict>>>> {
    let shape = data.shape();
    let (n_units, n_axes) = (shape[0], shape[2]);
    let slice = c_order(&data);
    let cfg = config(
        t0,
        data_type,
        estimator,
        tau_spec,
        per_decade,
        taus.as_ref(),
        confidence,
        gaps,
    )?;
    let results = PyHook::new(progress).run(py, |p| {
        allan::batch::analyse_batch(&slice, n_units, n_axes, &cfg, p)
    })?;
    results
        .into_iter()
        .map(|unit| unit.into_iter().map(|r| to_dict(py, r)).collect())
        .collect()
}

/// Overlapping Allan analysis of a series read in pieces by `read(start, count)`
/// (`gyrocore::allan::stream::analyse_stream`: memory bounded by a few windows, results equal
/// to [`analyse`] on the whole series). Returns one dict as [`analyse`].
#[pyfunction]
#[pyo3(signature = (read, n_samples, t0, data_type, tau_spec, per_decade, taus, confidence, block, progress=None))]
#[allow(clippy::needless_pass_by_value, clippy::too_many_arguments)]
fn analyse_stream<'py>(
    py: Python<'py>,
    read: Py<PyAny>,
    #[pyo3(from_py_with = count::n_samples)] n_samples: usize,
    t0: f64,
    data_type: &str,
    tau_spec: &str,
    #[pyo3(from_py_with = count::per_decade)] per_decade: usize,
    taus: Option<PyReadonlyArray1<'py, f64>>,
    confidence: Option<f64>,
    #[pyo3(from_py_with = count::block)] block: usize,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let cfg = config(
        t0,
        data_type,
        "overlapping",
        tau_spec,
        per_decade,
        taus.as_ref(),
        confidence,
        "error",
    )?;
    let hook = PyHook::new(progress);
    let mut source = PySource {
        read,
        len: n_samples,
        error: &hook.error,
    };
    let result = hook.run(py, |p| {
        allan::stream::analyse_stream(&mut source, &cfg, block, p)
    })?;
    to_dict(py, result)
}

/// The averaging factors an analysis of `n_samples` samples would use
/// (`gyrocore::allan::resolve_factors`).
#[pyfunction]
#[pyo3(signature = (n_samples, t0, data_type, estimator, tau_spec, per_decade, taus))]
#[allow(clippy::needless_pass_by_value)]
fn factors<'py>(
    py: Python<'py>,
    #[pyo3(from_py_with = count::n_samples)] n_samples: usize,
    t0: f64,
    data_type: &str,
    estimator: &str,
    tau_spec: &str,
    #[pyo3(from_py_with = count::per_decade)] per_decade: usize,
    taus: Option<PyReadonlyArray1<'py, f64>>,
) -> PyResult<Bound<'py, PyArray1<u64>>> {
    let data_type = core(DataType::parse(data_type))?;
    let estimator = core(Estimator::parse(estimator))?;
    let explicit = taus.map(|t| c_order(&t).into_owned());
    let taus = core(Taus::parse(tau_spec, per_decade, explicit))?;
    let ms = core(allan::resolve_factors(
        &taus, n_samples, t0, data_type, estimator,
    ))?;
    Ok(ms
        .into_iter()
        .map(|m| m as u64)
        .collect::<Vec<_>>()
        .into_pyarray(py))
}

/// Non-overlapping Hadamard, time, total and Théo statistics of each column
/// (`gyrocore::allan::family::analyse_axes`).
///
/// Returns one dict per axis with keys `m`, `tau_factor` (τ/t0), `theo`, `variance`,
/// `deviation`, `n_terms` and, when `confidence` is given, `alpha`, `edf`, `low`, `high`,
/// `deviation_low`, `deviation_high`.
#[pyfunction]
#[pyo3(signature = (data, t0, data_type, statistic, tau_spec, per_decade, taus, confidence))]
#[allow(clippy::needless_pass_by_value, clippy::too_many_arguments)]
fn family_analyse<'py>(
    py: Python<'py>,
    data: PyReadonlyArray2<'py, f64>,
    t0: f64,
    data_type: &str,
    statistic: &str,
    tau_spec: &str,
    #[pyo3(from_py_with = count::per_decade)] per_decade: usize,
    taus: Option<PyReadonlyArray1<'py, f64>>,
    confidence: Option<f64>,
) -> PyResult<Vec<Bound<'py, PyDict>>> {
    let n_axes = data.shape()[1];
    let slice = c_order(&data);
    let data_type = core(DataType::parse(data_type))?;
    let statistic = core(family::Statistic::parse(statistic))?;
    let explicit = taus.map(|t| c_order(&t).into_owned());
    let taus = core(Taus::parse(tau_spec, per_decade, explicit))?;
    let results = core(py.detach(|| {
        family::analyse_axes(&slice, n_axes, t0, data_type, statistic, &taus, confidence)
    }))?;
    results
        .into_iter()
        .map(|r| {
            let d = PyDict::new(py);
            let m: Vec<u64> = r.points.iter().map(|p| p.m as u64).collect();
            let f: Vec<f64> = r.points.iter().map(|p| p.tau_factor).collect();
            let theo: Vec<bool> = r.points.iter().map(|p| p.theo).collect();
            let n: Vec<u64> = r.n_terms.iter().map(|&n| n as u64).collect();
            d.set_item("m", m.into_pyarray(py))?;
            d.set_item("tau_factor", f.into_pyarray(py))?;
            d.set_item("theo", theo)?;
            d.set_item("variance", r.variance.into_pyarray(py))?;
            d.set_item("deviation", r.deviation.into_pyarray(py))?;
            d.set_item("n_terms", n.into_pyarray(py))?;
            if let Some(c) = r.confidence {
                d.set_item("alpha", c.alpha.into_pyarray(py))?;
                d.set_item("edf", c.edf.into_pyarray(py))?;
                d.set_item("low", c.low.into_pyarray(py))?;
                d.set_item("high", c.high.into_pyarray(py))?;
            }
            if let Some((low, high)) = r.deviation_bounds {
                d.set_item("deviation_low", low.into_pyarray(py))?;
                d.set_item("deviation_high", high.into_pyarray(py))?;
            }
            if let Some(v) = r.data_variance {
                d.set_item("data_variance", v)?;
            }
            if let Some(v) = r.data_deviation {
                d.set_item("data_deviation", v)?;
            }
            Ok(d)
        })
        .collect()
}

/// Dynamic overlapping Allan variance of a 1-D float64 series
/// (`gyrocore::allan::dynamic::dynamic_avar`).
///
/// Returns a dict with `starts` (first sample of each window), `m`, `n_terms` and `variance`
/// (windows × factors).
#[pyfunction]
#[pyo3(signature = (data, t0, data_type, window, step, tau_spec, per_decade, taus))]
#[allow(clippy::needless_pass_by_value, clippy::too_many_arguments)]
fn dynamic_avar<'py>(
    py: Python<'py>,
    data: PyReadonlyArray1<'py, f64>,
    t0: f64,
    data_type: &str,
    #[pyo3(from_py_with = count::window)] window: usize,
    #[pyo3(from_py_with = count::step)] step: usize,
    tau_spec: &str,
    #[pyo3(from_py_with = count::per_decade)] per_decade: usize,
    taus: Option<PyReadonlyArray1<'py, f64>>,
) -> PyResult<Bound<'py, PyDict>> {
    let slice = c_order(&data);
    let data_type = core(DataType::parse(data_type))?;
    let explicit = taus.map(|t| c_order(&t).into_owned());
    let taus = core(Taus::parse(tau_spec, per_decade, explicit))?;
    let r = core(py.detach(|| dynamic::dynamic_avar(&slice, t0, data_type, window, step, &taus)))?;
    let d = PyDict::new(py);
    let k = r.m.len();
    let rows = r.starts.len();
    let starts: Vec<u64> = r.starts.iter().map(|&s| s as u64).collect();
    let m: Vec<u64> = r.m.iter().map(|&m| m as u64).collect();
    let n: Vec<u64> = r.n_terms.iter().map(|&n| n as u64).collect();
    d.set_item("starts", starts.into_pyarray(py))?;
    d.set_item("m", m.into_pyarray(py))?;
    d.set_item("n_terms", n.into_pyarray(py))?;
    d.set_item("variance", r.variance.into_pyarray(py).reshape([rows, k])?)?;
    Ok(d)
}

pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(analyse, m)?)?;
    m.add_function(wrap_pyfunction!(analyse_batch, m)?)?;
    m.add_function(wrap_pyfunction!(analyse_stream, m)?)?;
    m.add_function(wrap_pyfunction!(factors, m)?)?;
    m.add_function(wrap_pyfunction!(family_analyse, m)?)?;
    m.add_function(wrap_pyfunction!(dynamic_avar, m)?)
}
