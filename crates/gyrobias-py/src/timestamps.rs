//! Bindings of `gyrocore::timestamps`.

use gyrocore::timestamps::{self, Sampling};
use numpy::{IntoPyArray, PyArray1, PyReadonlyArray1, PyReadwriteArray1};
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;

use crate::array::{c_order, c_order_mut};
use crate::count;
use crate::error::core;

/// Raw stamps: an int64 or a float64 1-D array.
enum Stamps<'py> {
    Int(PyReadonlyArray1<'py, i64>),
    Float(PyReadonlyArray1<'py, f64>),
}

impl<'py> Stamps<'py> {
    fn extract(obj: &Bound<'py, PyAny>) -> PyResult<Self> {
        if let Ok(a) = obj.extract::<PyReadonlyArray1<'py, i64>>() {
            return Ok(Self::Int(a));
        }
        obj.extract::<PyReadonlyArray1<'py, f64>>()
            .map(Self::Float)
            .map_err(|_| PyTypeError::new_err("stamps must be a 1-D int64 or float64 array"))
    }
}

fn rows_array(py: Python<'_>, rows: Vec<usize>) -> Bound<'_, PyArray1<i64>> {
    // Rows index an in-memory array, so they fit in i64.
    rows.into_iter()
        .map(|r| i64::try_from(r).unwrap_or(i64::MAX))
        .collect::<Vec<_>>()
        .into_pyarray(py)
}

/// Median of the positive steps of raw stamps (`gyrocore::timestamps::median_positive_step`).
#[pyfunction]
#[pyo3(signature = (stamps))]
fn median_positive_step(py: Python<'_>, stamps: &Bound<'_, PyAny>) -> PyResult<f64> {
    Ok(match Stamps::extract(stamps)? {
        Stamps::Int(a) => {
            let s = c_order(&a);
            py.detach(|| timestamps::median_positive_step(&s))
        }
        Stamps::Float(a) => {
            let s = c_order(&a);
            py.detach(|| timestamps::median_positive_step(&s))
        }
    })
}

/// The unit guessed from a median raw step (`gyrocore::timestamps::guess_unit`).
#[pyfunction]
#[pyo3(signature = (median_step))]
fn guess_unit(median_step: f64) -> &'static str {
    timestamps::guess_unit(median_step)
}

/// Rows whose stamp is earlier than the one before (`gyrocore::timestamps::backward_rows`).
#[pyfunction]
#[pyo3(signature = (stamps))]
fn backward_rows<'py>(
    py: Python<'py>,
    stamps: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyArray1<i64>>> {
    let rows = match Stamps::extract(stamps)? {
        Stamps::Int(a) => {
            let s = c_order(&a);
            py.detach(|| timestamps::backward_rows(&s))
        }
        Stamps::Float(a) => {
            let s = c_order(&a);
            py.detach(|| timestamps::backward_rows(&s))
        }
    };
    Ok(rows_array(py, rows))
}

/// Rows whose stamp repeats the one before (`gyrocore::timestamps::repeated_rows`).
#[pyfunction]
#[pyo3(signature = (stamps))]
fn repeated_rows<'py>(
    py: Python<'py>,
    stamps: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyArray1<i64>>> {
    let rows = match Stamps::extract(stamps)? {
        Stamps::Int(a) => {
            let s = c_order(&a);
            py.detach(|| timestamps::repeated_rows(&s))
        }
        Stamps::Float(a) => {
            let s = c_order(&a);
            py.detach(|| timestamps::repeated_rows(&s))
        }
    };
    Ok(rows_array(py, rows))
}

/// The sampling statistics of a log's intervals (`gyrocore::timestamps::Sampling`), built once
/// by [`analyse`]; read-only.
#[pyclass(name = "Sampling", module = "gyrobias._core.timestamps", frozen)]
struct PySampling {
    inner: Sampling,
}

#[pymethods]
impl PySampling {
    /// Median of the positive intervals, s.
    #[getter]
    fn median_interval(&self) -> f64 {
        self.inner.median_interval
    }
    /// `1/mean(regular intervals)` rounded to 9 significant digits, Hz.
    #[getter]
    fn fs_estimated(&self) -> f64 {
        self.inner.fs_estimated
    }
    /// Relative jitter.
    #[getter]
    fn jitter(&self) -> f64 {
        self.inner.jitter
    }
    /// Row after each gap (int64).
    #[getter]
    fn gap_rows<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<i64>> {
        rows_array(py, self.inner.gap_rows.clone())
    }
    /// Length of each gap, s.
    #[getter]
    fn gap_durations<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.inner.gap_durations.clone().into_pyarray(py)
    }
    /// Samples missing in the gaps.
    #[getter]
    fn missing_samples(&self) -> u64 {
        self.inner.missing_samples
    }
    /// Row of the second sample of each repeated timestamp (int64).
    #[getter]
    fn duplicate_rows<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<i64>> {
        rows_array(py, self.inner.duplicate_rows.clone())
    }
}

/// Rate, jitter, gaps and repeated stamps from the intervals (`gyrocore::timestamps::analyse`).
#[pyfunction]
#[pyo3(signature = (intervals))]
#[allow(clippy::needless_pass_by_value)]
fn analyse(py: Python<'_>, intervals: PyReadonlyArray1<'_, f64>) -> PyResult<PySampling> {
    let iv = c_order(&intervals);
    let inner = core(py.detach(|| timestamps::analyse(&iv)))?;
    Ok(PySampling { inner })
}

/// Rate, jitter, gaps and repeated stamps from raw stamps in time order, the intervals formed
/// on the fly (`gyrocore::timestamps::analyse_stamps`).
#[pyfunction]
#[pyo3(signature = (stamps, per_second))]
fn analyse_stamps(
    py: Python<'_>,
    stamps: &Bound<'_, PyAny>,
    per_second: f64,
) -> PyResult<PySampling> {
    let inner = match Stamps::extract(stamps)? {
        Stamps::Int(a) => {
            let s = c_order(&a);
            core(py.detach(|| timestamps::analyse_stamps(&s, per_second)))?
        }
        Stamps::Float(a) => {
            let s = c_order(&a);
            core(py.detach(|| timestamps::analyse_stamps(&s, per_second)))?
        }
    };
    Ok(PySampling { inner })
}

/// Overwrites raw stamps (int64 or float64, writable) with their seconds since `first`
/// (`gyrocore::timestamps::seconds_in_place_int` / `seconds_in_place_float`); an int64 buffer
/// then holds the bits of float64 values.
#[pyfunction]
#[pyo3(signature = (stamps, first, per_second))]
fn seconds_in_place(
    py: Python<'_>,
    stamps: &Bound<'_, PyAny>,
    first: &Bound<'_, PyAny>,
    per_second: f64,
) -> PyResult<()> {
    if let Ok(mut a) = stamps.extract::<PyReadwriteArray1<'_, i64>>() {
        let first: i64 = first.extract()?;
        let s = c_order_mut("stamps", &mut a)?;
        return core(py.detach(|| timestamps::seconds_in_place_int(s, first, per_second)));
    }
    if let Ok(mut a) = stamps.extract::<PyReadwriteArray1<'_, f64>>() {
        let first: f64 = first.extract()?;
        let s = c_order_mut("stamps", &mut a)?;
        return core(py.detach(|| timestamps::seconds_in_place_float(s, first, per_second)));
    }
    Err(PyTypeError::new_err(
        "stamps must be a writable 1-D int64 or float64 array",
    ))
}

/// Missing samples in a gap (`gyrocore::timestamps::missing_in_gap`).
#[pyfunction]
#[pyo3(signature = (gap, median))]
fn missing_in_gap(gap: f64, median: f64) -> u64 {
    timestamps::missing_in_gap(gap, median)
}

/// Writes the gap-filled time vector into `out` (`gyrocore::timestamps::fill_time_into`).
#[pyfunction]
#[pyo3(signature = (time, gap_rows, counts, out))]
#[allow(clippy::needless_pass_by_value)]
fn fill_time_into(
    py: Python<'_>,
    time: PyReadonlyArray1<'_, f64>,
    #[pyo3(from_py_with = count::gap_rows)] gap_rows: Vec<usize>,
    #[pyo3(from_py_with = count::counts)] counts: Vec<u64>,
    mut out: PyReadwriteArray1<'_, f64>,
) -> PyResult<()> {
    let t = c_order(&time);
    let o = c_order_mut("out", &mut out)?;
    core(py.detach(|| timestamps::fill_time_into(&t, &gap_rows, &counts, o)))
}

pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("GAP_FACTOR", timestamps::GAP_FACTOR)?;
    m.add("NS_THRESHOLD", timestamps::NS_THRESHOLD)?;
    m.add("US_THRESHOLD", timestamps::US_THRESHOLD)?;
    m.add("JITTER_WARN", timestamps::JITTER_WARN)?;
    m.add("FS_TOLERANCE", timestamps::FS_TOLERANCE)?;
    m.add_class::<PySampling>()?;
    m.add_function(wrap_pyfunction!(median_positive_step, m)?)?;
    m.add_function(wrap_pyfunction!(guess_unit, m)?)?;
    m.add_function(wrap_pyfunction!(backward_rows, m)?)?;
    m.add_function(wrap_pyfunction!(repeated_rows, m)?)?;
    m.add_function(wrap_pyfunction!(analyse, m)?)?;
    m.add_function(wrap_pyfunction!(analyse_stamps, m)?)?;
    m.add_function(wrap_pyfunction!(seconds_in_place, m)?)?;
    m.add_function(wrap_pyfunction!(missing_in_gap, m)?)?;
    m.add_function(wrap_pyfunction!(fill_time_into, m)?)
}
