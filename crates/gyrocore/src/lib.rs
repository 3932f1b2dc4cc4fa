//! # gyrocore — the numerical core of gyrobias
//!
//! Pure Rust (no Python types) implementations of the science gyrobias offers, one module per
//! piece of it. Every routine validates its numerical preconditions and reports violations as
//! [`Error`] values; nothing here panics on user input.
//!
//! | module | science | source |
//! |---|---|---|
//! | [`allan`] | overlapping / non-overlapping Allan, modified, Hadamard and total variance, noise identification, EDF and confidence intervals | NIST SP 1065, IEEE 952, \[BP\] eq. 2, \[TS\] eq. 1 |
//! | [`fractional`] | fractional differencing and integration, ARFIMA(0, d, 0) | SPEC §4, Hosking (1981), [BP] eq. 3 |
//! | [`noise`] | IEEE-952 noise terms: simulation with known coefficients, joint weighted fit and read-off identification | IEEE 952 Annex C, SPEC §3 |
//! | [`stats`] | chi-square quantiles and the special functions behind them | — |
//!
//! Units: time in seconds; rates and angles in the caller's unit (the core is unit-agnostic).
#![forbid(unsafe_code)]

pub mod allan;
pub mod error;
pub mod fractional;
pub mod noise;
pub mod stats;
pub mod validate;

pub use error::{Error, Result};
