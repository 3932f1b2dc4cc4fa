//! The one place where NumPy arrays become Rust slices.
//!
//! `PyReadonlyArray::as_slice` succeeds for any contiguous array, C *or Fortran* order, so a
//! Fortran-ordered (samples × axes) array would be read with its axes scrambled. Every input
//! array of the binding goes through [`c_order`] instead: C-contiguous arrays are borrowed
//! without a copy, every other layout (Fortran order, strided views) is copied once into C
//! (row-major) order. Output arrays the core writes into must already be C-contiguous
//! ([`c_order_mut`]); they are rejected otherwise, naming the argument.

use std::borrow::Cow;

use numpy::ndarray::Dimension;
use numpy::{Element, PyReadonlyArray, PyReadwriteArray, PyUntypedArrayMethods};
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;

/// The elements of `a` in C (row-major) order: borrowed if `a` is C-contiguous, else copied.
pub(crate) fn c_order<'a, T, D>(a: &'a PyReadonlyArray<'_, T, D>) -> Cow<'a, [T]>
where
    T: Element + Copy,
    D: Dimension,
{
    if a.is_c_contiguous() {
        if let Ok(slice) = a.as_slice() {
            return Cow::Borrowed(slice);
        }
    }
    Cow::Owned(a.as_array().iter().copied().collect())
}

/// [`c_order`] of an optional array.
pub(crate) fn c_order_opt<'a, T, D>(
    a: Option<&'a PyReadonlyArray<'_, T, D>>,
) -> Option<Cow<'a, [T]>>
where
    T: Element + Copy,
    D: Dimension,
{
    a.map(c_order)
}

/// The elements of the writable output array `a` (argument `name`), which must be
/// C-contiguous: the core writes them in row-major order.
pub(crate) fn c_order_mut<'a, T, D>(
    name: &str,
    a: &'a mut PyReadwriteArray<'_, T, D>,
) -> PyResult<&'a mut [T]>
where
    T: Element,
    D: Dimension,
{
    if !a.is_c_contiguous() {
        return Err(PyTypeError::new_err(format!(
            "{name} must be a C-contiguous float64 array"
        )));
    }
    a.as_slice_mut()
        .map_err(|_| PyTypeError::new_err(format!("{name} must be a C-contiguous float64 array")))
}
