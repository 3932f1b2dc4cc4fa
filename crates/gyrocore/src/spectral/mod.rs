//! Spectral analysis: the least-squares spectrum of unequally spaced, weighted series
//! ([`lssa()`]) and the FFT power spectral density of regularly sampled series ([`psd`]).
//!
//! See the submodules for the formulas and references (\[TS\] §2.2, Vaníček 1969, Pagiatakis
//! 1999; Welch 1967).

pub mod lssa;
pub mod psd;

pub use lssa::{LssaOptions, LssaResult, critical_value, default_frequencies, lssa};
pub use psd::{Window, welch};
