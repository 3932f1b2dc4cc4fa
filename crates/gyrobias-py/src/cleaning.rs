//! Bindings of `gyrocore::cleaning`.

use gyrocore::cleaning;
use numpy::{IntoPyArray, PyArray1, PyReadonlyArray2, PyReadwriteArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;

use crate::array::{c_order, c_order_mut};
use crate::count;
use crate::error::core;

type F64Array<'py> = Bound<'py, PyArray1<f64>>;

/// Outliers of each column of an `(n, k)` array (`gyrocore::cleaning::remove_outliers`):
/// `(data, mask, center, scale, count)`, the first two flat in row-major order.
#[pyfunction]
#[pyo3(signature = (data, threshold))]
#[allow(clippy::needless_pass_by_value, clippy::type_complexity)]
fn remove_outliers<'py>(
    py: Python<'py>,
    data: PyReadonlyArray2<'py, f64>,
    threshold: f64,
) -> PyResult<(
    F64Array<'py>,
    Bound<'py, PyArray1<bool>>,
    F64Array<'py>,
    F64Array<'py>,
    Bound<'py, PyArray1<u64>>,
)> {
    let n_cols = data.shape()[1];
    let x = c_order(&data);
    let r = core(py.detach(|| cleaning::remove_outliers(&x, n_cols, threshold)))?;
    let center: Vec<f64> = r.channels.iter().map(|c| c.center).collect();
    let scale: Vec<f64> = r.channels.iter().map(|c| c.scale).collect();
    let count: Vec<u64> = r.channels.iter().map(|c| c.count as u64).collect();
    Ok((
        r.data.into_pyarray(py),
        r.mask.into_pyarray(py),
        center.into_pyarray(py),
        scale.into_pyarray(py),
        count.into_pyarray(py),
    ))
}

/// `(mask, center, scale, count, gaps)` of a flagged array, the mask flat in row-major order.
type Flagged<'py> = (
    Bound<'py, PyArray1<bool>>,
    F64Array<'py>,
    F64Array<'py>,
    Bound<'py, PyArray1<u64>>,
    u64,
);

fn flagged_arrays(py: Python<'_>, r: cleaning::OutliersFlagged) -> Flagged<'_> {
    let center: Vec<f64> = r.channels.iter().map(|c| c.center).collect();
    let scale: Vec<f64> = r.channels.iter().map(|c| c.scale).collect();
    let count: Vec<u64> = r.channels.iter().map(|c| c.count as u64).collect();
    (
        r.mask.into_pyarray(py),
        center.into_pyarray(py),
        scale.into_pyarray(py),
        count.into_pyarray(py),
        r.gaps as u64,
    )
}

/// Outliers of each column of a writable C-contiguous `(n, k)` array, replaced by NaN in it
/// (`gyrocore::cleaning::remove_outliers_in_place`): `(mask, center, scale, count, gaps)`,
/// the mask flat in row-major order, `gaps` the NaN samples left in the array.
#[pyfunction]
#[pyo3(signature = (data, threshold))]
#[allow(clippy::needless_pass_by_value)]
fn remove_outliers_in_place<'py>(
    py: Python<'py>,
    mut data: PyReadwriteArray2<'py, f64>,
    threshold: f64,
) -> PyResult<Flagged<'py>> {
    let n_cols = data.shape()[1];
    let x = c_order_mut("data", &mut data)?;
    let r = core(py.detach(|| cleaning::remove_outliers_in_place(x, n_cols, threshold)))?;
    Ok(flagged_arrays(py, r))
}

/// Outliers of each column of an `(n, k)` array written with the outliers replaced by NaN into
/// the writable C-contiguous array `out` of its shape (`gyrocore::cleaning::remove_outliers_into`):
/// as `remove_outliers_in_place`.
#[pyfunction]
#[pyo3(signature = (data, out, threshold))]
#[allow(clippy::needless_pass_by_value)]
fn remove_outliers_into<'py>(
    py: Python<'py>,
    data: PyReadonlyArray2<'py, f64>,
    mut out: PyReadwriteArray2<'py, f64>,
    threshold: f64,
) -> PyResult<Flagged<'py>> {
    let n_cols = data.shape()[1];
    let x = c_order(&data);
    let y = c_order_mut("out", &mut out)?;
    let r = core(py.detach(|| cleaning::remove_outliers_into(&x, y, n_cols, threshold)))?;
    Ok(flagged_arrays(py, r))
}

/// Polynomial drift removal of each column of a writable C-contiguous `(n, k)` array, the
/// residual written in it (`gyrocore::cleaning::detrend_in_place_flagged`): `(coefficients,
/// gaps)`, the coefficients flat in row-major order `(k, order + 1)`, `gaps` the NaN samples of
/// the residual.
#[pyfunction]
#[pyo3(signature = (data, fs, order))]
#[allow(clippy::needless_pass_by_value)]
fn detrend_in_place<'py>(
    py: Python<'py>,
    mut data: PyReadwriteArray2<'py, f64>,
    fs: f64,
    #[pyo3(from_py_with = count::order)] order: usize,
) -> PyResult<(F64Array<'py>, u64)> {
    let n_cols = data.shape()[1];
    let x = c_order_mut("data", &mut data)?;
    let r = core(py.detach(|| cleaning::detrend_in_place_flagged(x, n_cols, fs, order)))?;
    Ok((r.coefficients.into_pyarray(py), r.gaps as u64))
}

/// Polynomial drift removal of each column of an `(n, k)` array, the residual written into the
/// writable C-contiguous array `out` of its shape (`gyrocore::cleaning::detrend_into`): as
/// `detrend_in_place`.
#[pyfunction]
#[pyo3(signature = (data, out, fs, order))]
#[allow(clippy::needless_pass_by_value)]
fn detrend_into<'py>(
    py: Python<'py>,
    data: PyReadonlyArray2<'py, f64>,
    mut out: PyReadwriteArray2<'py, f64>,
    fs: f64,
    #[pyo3(from_py_with = count::order)] order: usize,
) -> PyResult<(F64Array<'py>, u64)> {
    let n_cols = data.shape()[1];
    let x = c_order(&data);
    let y = c_order_mut("out", &mut out)?;
    let r = core(py.detach(|| cleaning::detrend_into(&x, y, n_cols, fs, order)))?;
    Ok((r.coefficients.into_pyarray(py), r.gaps as u64))
}

/// Polynomial drift removal of each column (`gyrocore::cleaning::detrend`):
/// `(residual, coefficients)`, flat in row-major order (`(n, k)` and `(k, order + 1)`).
#[pyfunction]
#[pyo3(signature = (data, fs, order))]
#[allow(clippy::needless_pass_by_value)]
fn detrend<'py>(
    py: Python<'py>,
    data: PyReadonlyArray2<'py, f64>,
    fs: f64,
    #[pyo3(from_py_with = count::order)] order: usize,
) -> PyResult<(F64Array<'py>, F64Array<'py>)> {
    let n_cols = data.shape()[1];
    let x = c_order(&data);
    let r = core(py.detach(|| cleaning::detrend(&x, n_cols, fs, order)))?;
    Ok((r.data.into_pyarray(py), r.coefficients.into_pyarray(py)))
}

/// Min/max envelope over bins of rows (`gyrocore::cleaning::minmax_envelope`):
/// `(lower, upper, starts)`, the first two flat in row-major order (`(bins, k)`).
#[pyfunction]
#[pyo3(signature = (data, bins))]
#[allow(clippy::needless_pass_by_value)]
fn minmax_envelope<'py>(
    py: Python<'py>,
    data: PyReadonlyArray2<'py, f64>,
    #[pyo3(from_py_with = count::bins)] bins: usize,
) -> PyResult<(F64Array<'py>, F64Array<'py>, Bound<'py, PyArray1<u64>>)> {
    let n_cols = data.shape()[1];
    let x = c_order(&data);
    let r = core(py.detach(|| cleaning::minmax_envelope(&x, n_cols, bins)))?;
    let starts: Vec<u64> = r.starts.into_iter().map(|s| s as u64).collect();
    Ok((
        r.lower.into_pyarray(py),
        r.upper.into_pyarray(py),
        starts.into_pyarray(py),
    ))
}

pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("MEAN_AD_TO_SD", cleaning::MEAN_AD_TO_SD)?;
    m.add("MIN_OUTLIER_SAMPLES", cleaning::MIN_OUTLIER_SAMPLES)?;
    m.add_function(wrap_pyfunction!(remove_outliers, m)?)?;
    m.add_function(wrap_pyfunction!(detrend, m)?)?;
    m.add_function(wrap_pyfunction!(remove_outliers_in_place, m)?)?;
    m.add_function(wrap_pyfunction!(detrend_in_place, m)?)?;
    m.add_function(wrap_pyfunction!(remove_outliers_into, m)?)?;
    m.add_function(wrap_pyfunction!(detrend_into, m)?)?;
    m.add_function(wrap_pyfunction!(minmax_envelope, m)?)
}
