//! The two IEEE-754 binary formats the streaming kernels run in.
//!
//! The fixed-gain Kalman filter ([`crate::kalman`]) and the FIR stream ([`crate::fir`]) are
//! generic over [`Float`] so that their float32 variants perform *the same operations in the
//! same order* as the float64 ones (and as the C that `gyrobias.codegen` generates from them):
//! one rounding per `+`, `−`, `×`, `÷`, never a fused multiply-add (Rust does not contract
//! floating-point expressions).

use std::fmt::Debug;
use std::ops::{Add, AddAssign, Div, Mul, Sub};

/// `f32` or `f64`.
pub trait Float:
    Copy
    + Send
    + Sync
    + Debug
    + PartialEq
    + PartialOrd
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + AddAssign
    + 'static
{
    /// `0.0`.
    const ZERO: Self;
    /// Round-to-nearest conversion from `f64` (exact for `f64`).
    fn from_f64(x: f64) -> Self;
    /// Exact widening to `f64`.
    fn to_f64(self) -> f64;
    /// Neither NaN nor ±∞.
    fn is_finite(self) -> bool;
}

impl Float for f64 {
    const ZERO: Self = 0.0;
    fn from_f64(x: f64) -> Self {
        x
    }
    fn to_f64(self) -> f64 {
        self
    }
    fn is_finite(self) -> bool {
        f64::is_finite(self)
    }
}

impl Float for f32 {
    const ZERO: Self = 0.0;
    #[allow(clippy::cast_possible_truncation)] // rounding to nearest is the point
    fn from_f64(x: f64) -> Self {
        x as f32
    }
    fn to_f64(self) -> f64 {
        f64::from(self)
    }
    fn is_finite(self) -> bool {
        f32::is_finite(self)
    }
}

/// Index of the first non-finite value of `x`.
pub fn first_non_finite<T: Float>(x: &[T]) -> Option<usize> {
    x.iter().position(|v| !v.is_finite())
}
