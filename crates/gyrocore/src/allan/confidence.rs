//! Confidence intervals for Allan-family variances (SP1065 §5). (scaffold: being written)

use super::Estimator;
use crate::{Error, Result};

/// Per-τ noise type, equivalent degrees of freedom and chi-square interval of the variance.
#[derive(Debug, Clone, PartialEq)]
pub struct Intervals {
    /// Identified power-law exponent α of the fractional-frequency (rate) PSD, S ∝ f^α.
    pub alpha: Vec<i32>,
    /// Equivalent degrees of freedom.
    pub edf: Vec<f64>,
    /// Lower bound of the variance.
    pub low: Vec<f64>,
    /// Upper bound of the variance.
    pub high: Vec<f64>,
}

/// Confidence intervals at `level` for `variances` estimated at factors `ms` from angle series `x`.
pub fn intervals(
    _x: &[f64],
    _estimator: Estimator,
    _ms: &[usize],
    _variances: &[f64],
    _level: f64,
) -> Result<Intervals> {
    Err(Error::invalid("confidence", "scaffold"))
}
