//! Bindings of `gyrocore::text`.

use gyrocore::text::{self, Format, Parsed, Stamps, Stop};
use numpy::{PyReadonlyArray1, PyReadwriteArray1, PyReadwriteArray2};
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;

use crate::array::c_order_mut;
use crate::count;
use crate::error::core;

/// What the parser reads (`gyrocore::text::Format`).
#[pyclass(name = "Format", module = "gyrobias._core.text", frozen)]
struct PyFormat {
    inner: Format,
}

#[pymethods]
impl PyFormat {
    #[new]
    #[pyo3(signature = (delimiter, comment, usecols, stamps))]
    #[allow(clippy::needless_pass_by_value)]
    fn new(
        delimiter: Option<&str>,
        comment: &str,
        #[pyo3(from_py_with = count::usecols)] usecols: Vec<usize>,
        stamps: bool,
    ) -> PyResult<Self> {
        let delimiter = match delimiter {
            None => None,
            Some(d) if d.len() == 1 => Some(d.as_bytes()[0]),
            Some(d) => {
                return Err(pyo3::exceptions::PyValueError::new_err(format!(
                    "delimiter must be one ASCII character or None, got {d:?}"
                )));
            }
        };
        let inner = core(Format::new(delimiter, comment.as_bytes(), &usecols, stamps))?;
        Ok(Self { inner })
    }

    /// Values per row of the samples array.
    #[getter]
    fn width(&self) -> usize {
        self.inner.width()
    }
}

/// The outcome of [`parse_into`] (`gyrocore::text::Parsed`); read-only.
#[pyclass(name = "Parsed", module = "gyrobias._core.text", frozen)]
struct PyParsed {
    inner: Parsed,
}

#[pymethods]
impl PyParsed {
    /// Rows written.
    #[getter]
    fn rows(&self) -> usize {
        self.inner.rows
    }
    /// Bytes read (whole lines), for `stop` "done" and "full".
    #[getter]
    fn consumed(&self) -> usize {
        self.inner.consumed
    }
    /// Why the parse ended: "done", "full", "bad_cell", "too_few_fields" or "unsupported".
    #[getter]
    fn stop(&self) -> &'static str {
        match self.inner.stop {
            Stop::Done => "done",
            Stop::Full => "full",
            Stop::BadCell { .. } => "bad_cell",
            Stop::TooFewFields { .. } => "too_few_fields",
            Stop::Unsupported { .. } => "unsupported",
        }
    }
    /// Data row of the stop (loadtxt's count), or -1.
    #[getter]
    fn row(&self) -> i64 {
        match self.inner.stop {
            Stop::BadCell { row, .. }
            | Stop::TooFewFields { row, .. }
            | Stop::Unsupported { row, .. } => i64::try_from(row).unwrap_or(i64::MAX),
            _ => -1,
        }
    }
    /// 0-based file column of a bad cell, or the number of fields of a short row, or -1.
    #[getter]
    fn column(&self) -> i64 {
        match self.inner.stop {
            Stop::BadCell { column, .. } => i64::try_from(column).unwrap_or(i64::MAX),
            Stop::TooFewFields { fields, .. } => i64::try_from(fields).unwrap_or(i64::MAX),
            _ => -1,
        }
    }
    /// The raw text of a bad cell, or the reason of "unsupported", else "".
    #[getter]
    fn text(&self) -> String {
        match &self.inner.stop {
            Stop::BadCell { text, .. } => text.clone(),
            Stop::Unsupported { reason, .. } => (*reason).to_owned(),
            _ => String::new(),
        }
    }
}

/// Raw stamps output: an int64 or a float64 1-D array.
enum StampsOut<'py> {
    Int(PyReadwriteArray1<'py, i64>),
    Float(PyReadwriteArray1<'py, f64>),
}

/// Parses the whole lines of `text` (a uint8 array) into `values` and `stamps`
/// (`gyrocore::text::parse_into`).
#[pyfunction]
#[pyo3(signature = (text, format, values, stamps=None))]
#[allow(clippy::needless_pass_by_value)]
fn parse_into<'py>(
    py: Python<'py>,
    text: PyReadonlyArray1<'py, u8>,
    format: &PyFormat,
    mut values: PyReadwriteArray2<'py, f64>,
    stamps: Option<&Bound<'py, PyAny>>,
) -> PyResult<PyParsed> {
    let bytes = text
        .as_slice()
        .map_err(|_| PyTypeError::new_err("text must be a contiguous uint8 array"))?;
    let v = c_order_mut("values", &mut values)?;
    let mut out = match stamps {
        None => None,
        Some(obj) => Some(
            if let Ok(a) = obj.extract::<PyReadwriteArray1<'py, i64>>() {
                StampsOut::Int(a)
            } else {
                StampsOut::Float(obj.extract::<PyReadwriteArray1<'py, f64>>().map_err(|_| {
                    PyTypeError::new_err("stamps must be a writable 1-D int64 or float64 array")
                })?)
            },
        ),
    };
    let st = match &mut out {
        None => Stamps::None,
        Some(StampsOut::Int(a)) => Stamps::Int(c_order_mut("stamps", a)?),
        Some(StampsOut::Float(a)) => Stamps::Float(c_order_mut("stamps", a)?),
    };
    let f = &format.inner;
    let inner = core(py.detach(|| text::parse_into(bytes, f, v, st)))?;
    Ok(PyParsed { inner })
}

/// Lines in `text` (a uint8 array), the last one without its newline included
/// (`gyrocore::text::lines_in`).
#[pyfunction]
#[pyo3(signature = (text))]
#[allow(clippy::needless_pass_by_value)]
fn lines_in(py: Python<'_>, text: PyReadonlyArray1<'_, u8>) -> PyResult<usize> {
    let bytes = text
        .as_slice()
        .map_err(|_| PyTypeError::new_err("text must be a contiguous uint8 array"))?;
    Ok(py.detach(|| text::lines_in(bytes)))
}

/// A cell as a number, as the parser reads it (`gyrocore::text::parse_float`); None if not one.
#[pyfunction]
#[pyo3(signature = (cell))]
fn parse_float(cell: &[u8]) -> Option<f64> {
    text::parse_float(cell)
}

/// A cell as an int64, as the parser reads a time column (`gyrocore::text::parse_int`).
#[pyfunction]
#[pyo3(signature = (cell))]
fn parse_int(cell: &[u8]) -> Option<i64> {
    text::parse_int(cell)
}

pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyFormat>()?;
    m.add_class::<PyParsed>()?;
    m.add_function(wrap_pyfunction!(parse_into, m)?)?;
    m.add_function(wrap_pyfunction!(lines_in, m)?)?;
    m.add_function(wrap_pyfunction!(parse_float, m)?)?;
    m.add_function(wrap_pyfunction!(parse_int, m)?)
}
