//! The one place where Python integers become counts, sizes and seeds.
//!
//! pyo3's own extraction of `usize`/`u64` fails on a negative value or one of 2**64 or more
//! with an `OverflowError` whose message does not say which argument it was. Every integer
//! argument of the binding is therefore extracted by the function of its name below
//! (`#[pyo3(from_py_with = count::n)] n: usize`), which raises a `ValueError` naming the
//! argument instead, and a value of the wrong type (a float, a string, `None`, a bool) a
//! `TypeError` naming it instead of pyo3's generic "cannot be interpreted as an integer".
//! Python ints and NumPy integer scalars (anything with `__index__` but `bool`) are accepted.
//! Integer *arrays* (the averaging factors `m` and term counts `n_terms` of an Allan curve) go
//! through [`sizes`], element by element with the same rules. Only representability is decided
//! here; what a count must be (≥ 1, below the data length, …) is the core's check.

use numpy::PyReadonlyArray1;
use pyo3::exceptions::{PyOverflowError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyBool;

fn out_of_range(obj: &Bound<'_, PyAny>, name: &str, bits: u32) -> PyErr {
    PyValueError::new_err(format!(
        "{name} must be an integer from 0 to 2**{bits} - 1, got {obj}"
    ))
}

fn not_integer(obj: &Bound<'_, PyAny>, name: &str) -> PyErr {
    let kind = obj
        .get_type()
        .name()
        .map_or_else(|_| "?".to_owned(), |n| n.to_string());
    PyTypeError::new_err(format!("{name} must be an integer, got {kind}"))
}

/// `obj` as a `u64`; a negative or too large integer is a `ValueError` naming `name`, a
/// non-integer (bools included) a `TypeError` naming it.
fn unsigned(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<u64> {
    if obj.is_instance_of::<PyBool>() {
        return Err(not_integer(obj, name));
    }
    match obj.extract::<u64>() {
        Ok(v) => Ok(v),
        Err(e) if e.is_instance_of::<PyOverflowError>(obj.py()) => {
            Err(out_of_range(obj, name, u64::BITS))
        }
        Err(e) if e.is_instance_of::<PyTypeError>(obj.py()) => Err(not_integer(obj, name)),
        Err(e) => Err(e),
    }
}

/// `obj` as a `usize`; a negative or too large integer is a `ValueError` naming `name`.
fn size(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<usize> {
    usize::try_from(unsigned(obj, name)?).map_err(|_| out_of_range(obj, name, usize::BITS))
}

/// `None`, or `obj` as a `usize` as in [`size`].
fn optional_size(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Option<usize>> {
    if obj.is_none() {
        Ok(None)
    } else {
        size(obj, name).map(Some)
    }
}

fn element_out_of_range(name: &str, index: usize, value: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(format!(
        "{name} must hold integers from 0 to 2**64 - 1, got {value} at index {index}"
    ))
}

/// The 1-D integer array `obj` (any integer dtype and layout, or a sequence of ints) as
/// `usize`s: a negative or too large element is a `ValueError` naming `name` and the index, a
/// non-integer array (float, bool, strings) a `TypeError` naming `name`.
fn sizes(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Vec<usize>> {
    let py = obj.py();
    let arr = py.import("numpy")?.call_method1("asarray", (obj,))?;
    let ndim: usize = arr.getattr("ndim")?.extract()?;
    if ndim != 1 {
        return Err(PyValueError::new_err(format!(
            "{name} must be a 1-D integer array, got a {ndim}-D array"
        )));
    }
    let dtype = arr.getattr("dtype")?;
    let kind: String = dtype.getattr("kind")?.extract()?;
    let to_size =
        |index: usize, v: u64| usize::try_from(v).map_err(|_| element_out_of_range(name, index, v));
    match kind.as_str() {
        "u" => {
            let a = arr.call_method1("astype", ("uint64",))?;
            let a: PyReadonlyArray1<'_, u64> = a.extract()?;
            let values = a.as_array();
            values
                .iter()
                .enumerate()
                .map(|(i, &v)| to_size(i, v))
                .collect()
        }
        "i" => {
            let a = arr.call_method1("astype", ("int64",))?;
            let a: PyReadonlyArray1<'_, i64> = a.extract()?;
            let values = a.as_array();
            values
                .iter()
                .enumerate()
                .map(|(i, &v)| {
                    u64::try_from(v)
                        .map_err(|_| element_out_of_range(name, i, v))
                        .and_then(|v| to_size(i, v))
                })
                .collect()
        }
        // Python ints beyond int64 make an object array: each element as a scalar count.
        "O" => arr
            .try_iter()?
            .enumerate()
            .map(|(i, item)| {
                let item = item?;
                if item.is_instance_of::<PyBool>() {
                    return Err(PyTypeError::new_err(format!(
                        "{name} must be an integer array, got a bool at index {i}"
                    )));
                }
                match item.extract::<u64>() {
                    Ok(v) => to_size(i, v),
                    Err(e) if e.is_instance_of::<PyOverflowError>(py) => {
                        Err(element_out_of_range(name, i, &item))
                    }
                    Err(_) => Err(PyTypeError::new_err(format!(
                        "{name} must be an integer array, got {} at index {i}",
                        item.get_type()
                            .name()
                            .map_or_else(|_| "?".to_owned(), |n| n.to_string())
                    ))),
                }
            })
            .collect(),
        _ => Err(PyTypeError::new_err(format!(
            "{name} must be an integer array, got dtype {dtype}"
        ))),
    }
}

/// The averaging factors `m` of an Allan curve (see [`sizes`]).
pub(crate) fn factors(obj: &Bound<'_, PyAny>) -> PyResult<Vec<usize>> {
    sizes(obj, "m")
}

/// The gap rows `gap_rows` of a sampling report (see [`sizes`]).
pub(crate) fn gap_rows(obj: &Bound<'_, PyAny>) -> PyResult<Vec<usize>> {
    sizes(obj, "gap_rows")
}

/// The per-gap counts `counts` of missing samples (see [`sizes`]).
pub(crate) fn counts(obj: &Bound<'_, PyAny>) -> PyResult<Vec<u64>> {
    Ok(sizes(obj, "counts")?
        .into_iter()
        .map(|c| c as u64)
        .collect())
}

/// The term counts `n_terms` of an Allan curve (see [`sizes`]).
pub(crate) fn n_terms(obj: &Bound<'_, PyAny>) -> PyResult<Vec<usize>> {
    sizes(obj, "n_terms")
}

/// Indices of curve points `used` (see [`sizes`]).
pub(crate) fn used(obj: &Bound<'_, PyAny>) -> PyResult<Vec<usize>> {
    sizes(obj, "used")
}

macro_rules! extractors {
    ($kind:ident -> $ty:ty: $($name:ident),+ $(,)?) => {
        $(
            #[doc = concat!("The argument `", stringify!($name), "` (see the module docs).")]
            pub(crate) fn $name(obj: &Bound<'_, PyAny>) -> PyResult<$ty> {
                $kind(obj, stringify!($name))
            }
        )+
    };
}

extractors!(size -> usize:
    axes, block, bootstrap, calibration, calibration_length, degree, half_width, horizon,
    iterations, max_lines, min_blocks, min_points, n, n_known, n_params, n_samples, n_threads,
    noverlap, nperseg, padlen, per_decade, resamples, rows, step, window,
);
extractors!(unsigned -> u64: samples, seed);
extractors!(unsigned -> u64: channel, conn);
extractors!(size -> usize: start);
extractors!(size -> usize: bins, order);
extractors!(optional_size -> Option<usize>: levels, m, row_width);

/// The columns `usecols` of a text format (see [`sizes`]).
pub(crate) fn usecols(obj: &Bound<'_, PyAny>) -> PyResult<Vec<usize>> {
    sizes(obj, "usecols")
}
