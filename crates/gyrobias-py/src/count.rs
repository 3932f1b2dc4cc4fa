//! The one place where Python integers become counts, sizes and seeds.
//!
//! pyo3's own extraction of `usize`/`u64` fails on a negative value or one of 2**64 or more
//! with an `OverflowError` whose message does not say which argument it was. Every integer
//! argument of the binding is therefore extracted by the function of its name below
//! (`#[pyo3(from_py_with = count::n)] n: usize`), which raises a `ValueError` naming the
//! argument instead. A value of the wrong type (a float, a string) stays pyo3's `TypeError`.
//! Only representability is decided here; what a count must be (≥ 1, below the data length, …)
//! is the core's check.

use pyo3::exceptions::{PyOverflowError, PyValueError};
use pyo3::prelude::*;

fn out_of_range(obj: &Bound<'_, PyAny>, name: &str, bits: u32) -> PyErr {
    PyValueError::new_err(format!(
        "invalid {name}: must be an integer from 0 to 2**{bits} - 1, got {obj}"
    ))
}

/// `obj` as a `u64`; a negative or too large integer is a `ValueError` naming `name`.
fn unsigned(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<u64> {
    match obj.extract::<u64>() {
        Ok(v) => Ok(v),
        Err(e) if e.is_instance_of::<PyOverflowError>(obj.py()) => {
            Err(out_of_range(obj, name, u64::BITS))
        }
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
    axes, block, bootstrap, calibration_length, degree, horizon, iterations, min_blocks,
    min_points, n, n_known, n_params, n_samples, n_threads, noverlap, nperseg, padlen,
    per_decade, rows, step, window,
);
extractors!(unsigned -> u64: samples, seed);
extractors!(optional_size -> Option<usize>: m);
