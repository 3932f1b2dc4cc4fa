//! Bindings of `gyrocore::allan`.

use gyrocore::allan::{self, DataType, Estimator, TauSpec, Taus};
use numpy::{IntoPyArray, PyArray1, PyReadonlyArray1, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::array::c_order;
use crate::error::core;

fn taus_from(spec: &str, per_decade: usize, explicit: Option<Vec<f64>>) -> PyResult<Taus> {
    if let Some(t) = explicit {
        return Ok(Taus::Explicit(t));
    }
    let spec = match spec {
        "octave" => TauSpec::Octave,
        "decade" => TauSpec::Decade,
        "log" => TauSpec::Log { per_decade },
        "all" => TauSpec::All,
        other => {
            return Err(pyo3::exceptions::PyValueError::new_err(format!(
                "taus must be 'octave', 'decade', 'log', 'all' or an array of seconds, got {other:?}"
            )));
        }
    };
    Ok(Taus::Spec(spec))
}

/// Allan-family analysis of each column of a (samples × axes) float64 array
/// (`gyrocore::allan::analyse_axes`).
///
/// Returns one dict per axis with keys `m`, `variance`, `n_terms` and, when `confidence` is
/// given, `alpha`, `edf`, `low`, `high`.
#[pyfunction]
#[pyo3(signature = (data, t0, data_type, estimator, tau_spec, per_decade, taus, confidence))]
#[allow(clippy::needless_pass_by_value)]
fn analyse<'py>(
    py: Python<'py>,
    data: PyReadonlyArray2<'py, f64>,
    t0: f64,
    data_type: &str,
    estimator: &str,
    tau_spec: &str,
    per_decade: usize,
    taus: Option<PyReadonlyArray1<'py, f64>>,
    confidence: Option<f64>,
) -> PyResult<Vec<Bound<'py, PyDict>>> {
    let n_axes = data.shape()[1];
    let slice = c_order(&data);
    let data_type = core(DataType::parse(data_type))?;
    let estimator = core(Estimator::parse(estimator))?;
    let explicit = taus.map(|t| c_order(&t).into_owned());
    let taus = taus_from(tau_spec, per_decade, explicit)?;
    let results = core(py.detach(|| {
        allan::analyse_axes(&slice, n_axes, t0, data_type, estimator, &taus, confidence)
    }))?;
    results
        .into_iter()
        .map(|r| {
            let d = PyDict::new(py);
            let m: Vec<u64> = r.m.iter().map(|&m| m as u64).collect();
            let n: Vec<u64> = r.n_terms.iter().map(|&n| n as u64).collect();
            d.set_item("m", m.into_pyarray(py))?;
            d.set_item("variance", r.variance.into_pyarray(py))?;
            d.set_item("n_terms", n.into_pyarray(py))?;
            if let Some(c) = r.confidence {
                d.set_item("alpha", c.alpha.into_pyarray(py))?;
                d.set_item("edf", c.edf.into_pyarray(py))?;
                d.set_item("low", c.low.into_pyarray(py))?;
                d.set_item("high", c.high.into_pyarray(py))?;
            }
            Ok(d)
        })
        .collect()
}

/// The averaging factors an analysis of `n_samples` samples would use
/// (`gyrocore::allan::resolve_factors`).
#[pyfunction]
#[pyo3(signature = (n_samples, t0, data_type, estimator, tau_spec, per_decade, taus))]
#[allow(clippy::needless_pass_by_value)]
fn factors<'py>(
    py: Python<'py>,
    n_samples: usize,
    t0: f64,
    data_type: &str,
    estimator: &str,
    tau_spec: &str,
    per_decade: usize,
    taus: Option<PyReadonlyArray1<'py, f64>>,
) -> PyResult<Bound<'py, PyArray1<u64>>> {
    let data_type = core(DataType::parse(data_type))?;
    let estimator = core(Estimator::parse(estimator))?;
    let explicit = taus.map(|t| c_order(&t).into_owned());
    let taus = taus_from(tau_spec, per_decade, explicit)?;
    let ms = core(allan::resolve_factors(
        &taus, n_samples, t0, data_type, estimator,
    ))?;
    Ok(ms
        .into_iter()
        .map(|m| m as u64)
        .collect::<Vec<_>>()
        .into_pyarray(py))
}

pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(analyse, m)?)?;
    m.add_function(wrap_pyfunction!(factors, m)?)
}
