//! # gyrocore — the numerical core of gyrobias
//!
//! Pure Rust (no Python types) implementations of the science gyrobias offers, one module per
//! piece of it. Every routine validates its numerical preconditions and reports violations as
//! [`Error`] values; nothing here panics on user input.
//!
//! | module | science | source |
//! |---|---|---|
//! | [`allan`] | overlapping / non-overlapping Allan, modified, Hadamard and total variance, noise identification, EDF and confidence intervals | NIST SP 1065, IEEE 952, \[BP\] eq. 2, \[TS\] eq. 1 |
//! | [`fir`] | Kaiser-window FIR low-pass design, causal and zero-phase filtering | \[TS\] eqs. 14–20, Orfanidis §10.2 |
//! | [`spectral`] | least-squares spectral analysis with significance, Welch PSD | \[TS\] §2.2, Vaníček 1969, Pagiatakis 1999, Welch 1967 |
//! | [`thermal`] | AR(1) drift fits, temperature interpolation of noise parameters | \[TS\] §4 |
//! | [`fractional`] | fractional differencing and integration (direct / FFT), ARFIMA(0, d, 0) simulation (type II, Davies–Harte), exact local Whittle estimation of d | SPEC §4, Hosking (1981), \[BP\] eq. 3, Shimotsu & Phillips (2005), Shimotsu (2010) |
//! | [`noise`] | IEEE-952 noise terms: simulation with known coefficients, joint weighted fit and read-off identification | IEEE 952 Annex C, SPEC §3 |
//! | [`optimize`] | Brent's derivative-free 1-D minimisation | Brent (1973) |
//! | [`random`] | the one seeded generator: normal deviates (xoshiro256++, polar method), unbiased integers (Lemire) | Blackman & Vigna (2019), Lemire (2019) |
//! | [`predict`] | bias prediction: calibration mean, moving average, fractional (1/f) Kalman predictor (literal and generalized-Schur O(n·k)), compiled batch predictor | \[BP\] §IV–V, SPEC §5 |
//! | [`kalman`] | fixed-gain 2-state [rate, bias] Kalman filter: steady-state gain, discrete fixed-gain form, bandwidth design, streaming | \[NR\] eqs. 4–18, SPEC §6 |
//! | [`stats`] | chi-square quantiles and the special functions behind them | — |
//! | [`fleet`] | robust z-scores of a unit within its fleet, weighted χ² homogeneity test and Birge ratio | Rousseeuw & Croux (1993), Birge (1932) |
//! | [`stationarity`] | is a log static: rate steps, motion segments and warm-up trends against the record's own noise at several scales | Hampel (1974) |
//! | [`timestamps`] | sampling analysis of a log's timestamps: rate, jitter, gaps, repeated and out-of-order stamps, gap filling | — |
//! | [`bags`] | bulk decoding of `sensor_msgs/Imu` from ROS1 bag chunks, MCAP chunks and CDR messages | REP 103, ROS bag format 2.0, MCAP spec, OMG CDR |
//! | [`cleaning`] | outlier removal by the robust (MAD) z-score, least-squares drift removal (Legendre basis), min/max envelope of long logs | NIST SP 1065 §6.2, Stable32 |
//! | [`text`] | delimited text logs parsed into the samples array, as `numpy.loadtxt` reads them (correctly rounded, in parallel) | — |
//! | [`simd`] | run-time choice of the kernels' vector instruction set (`GYROBIAS_SIMD=scalar` forces the baseline) | — |
//!
//! Units: time in seconds; rates and angles in the caller's unit (the core is unit-agnostic).
#![forbid(unsafe_code)]

pub mod allan;
pub mod bags;
pub mod cleaning;
pub mod codegen;
pub mod error;
pub mod fir;
pub mod fleet;
pub mod float;
pub mod fractional;
pub mod kalman;
pub mod noise;
pub mod optimize;
pub mod predict;
pub mod random;
pub mod simd;
pub mod spectral;
pub mod stationarity;
pub mod stats;
pub mod text;
pub mod thermal;
pub mod timestamps;
pub mod validate;

pub use error::{Error, Result};
