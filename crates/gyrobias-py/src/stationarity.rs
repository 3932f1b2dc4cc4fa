//! Bindings of `gyrocore::stationarity`.

use gyrocore::stationarity::{self, BlockMeans, Report};
use numpy::PyReadonlyArray1;
use numpy::{PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::array::c_order;
use crate::count;
use crate::error::core;

fn to_dict(py: Python<'_>, r: Report) -> PyResult<Bound<'_, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("checked", r.checked)?;
    d.set_item("n", r.n)?;
    d.set_item("block", r.block)?;
    d.set_item("quiet", r.quiet)?;
    let events = r
        .disturbances
        .into_iter()
        .map(|e| {
            let x = PyDict::new(py);
            x.set_item("kind", e.kind.name())?;
            x.set_item("start", e.start)?;
            x.set_item("stop", e.stop)?;
            x.set_item("at", e.at)?;
            x.set_item("size", e.size)?;
            x.set_item("z", e.z)?;
            x.set_item("block", e.block)?;
            x.set_item("threshold", e.threshold)?;
            Ok(x)
        })
        .collect::<PyResult<Vec<_>>>()?;
    d.set_item("disturbances", events)?;
    Ok(d)
}

/// Steps, segments and trends in block means (`gyrocore::stationarity::check`): a dict with
/// `checked`, `n`, `block`, `quiet` (start, stop) and `disturbances` (dicts with `kind`,
/// `start`, `stop`, `at`, `size`, `z`, `block`, `threshold`; samples).
#[pyfunction]
#[pyo3(signature = (means, block, n))]
#[allow(clippy::needless_pass_by_value)]
fn check<'py>(
    py: Python<'py>,
    means: PyReadonlyArray1<'py, f64>,
    #[pyo3(from_py_with = count::block)] block: usize,
    #[pyo3(from_py_with = count::n)] n: usize,
) -> PyResult<Bound<'py, PyDict>> {
    let blocks = BlockMeans {
        means: c_order(&means).into_owned(),
        length: block,
        n,
    };
    let r = core(py.detach(|| stationarity::check(&blocks)))?;
    to_dict(py, r)
}

/// [`check`] of every column of a (samples × axes) float64 array, from its samples
/// (`gyrocore::stationarity::check_matrix`).
#[pyfunction]
#[pyo3(signature = (data,))]
#[allow(clippy::needless_pass_by_value)]
fn check_matrix<'py>(
    py: Python<'py>,
    data: PyReadonlyArray2<'py, f64>,
) -> PyResult<Vec<Bound<'py, PyDict>>> {
    let n_axes = data.shape()[1];
    let slice = c_order(&data);
    let reports = core(py.detach(|| stationarity::check_matrix(&slice, n_axes)))?;
    reports.into_iter().map(|r| to_dict(py, r)).collect()
}

/// Samples per block at the finest scale (`gyrocore::stationarity::block_length`).
#[pyfunction]
#[pyo3(signature = (n,))]
fn block_length(#[pyo3(from_py_with = count::n)] n: usize) -> usize {
    stationarity::block_length(n)
}

pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("FALSE_ALARM", stationarity::FALSE_ALARM)?;
    m.add("MIN_BLOCKS", stationarity::MIN_BLOCKS)?;
    m.add("MIN_BLOCK", stationarity::MIN_BLOCK)?;
    m.add("TARGET_BLOCKS", stationarity::TARGET_BLOCKS)?;
    m.add_function(wrap_pyfunction!(check, m)?)?;
    m.add_function(wrap_pyfunction!(check_matrix, m)?)?;
    m.add_function(wrap_pyfunction!(block_length, m)?)
}
