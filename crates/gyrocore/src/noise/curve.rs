//! The Allan curve a fit works on, its validation, and the per-term results both
//! identification methods return.

use super::bound::UpperBound;
use super::model::{Term, approximate_edf};
use crate::{Error, Result};

/// An overlapping (or non-overlapping) Allan-variance curve with its estimator bookkeeping.
#[derive(Debug, Clone, Copy)]
pub struct Curve<'a> {
    /// Averaging times τ (s), strictly increasing.
    pub taus: &'a [f64],
    /// Allan variance σ²(τ).
    pub variance: &'a [f64],
    /// Averaging factors m (τ = m·t0).
    pub m: &'a [usize],
    /// Number of terms of each estimate.
    pub n_terms: &'a [usize],
    /// Overlapping (true) or non-overlapping (false) estimator.
    pub overlapping: bool,
    /// Equivalent degrees of freedom of each estimate, when known (from noise identification);
    /// `None` uses [`approximate_edf`] with the locally dominant noise type.
    pub edf: Option<&'a [f64]>,
}

impl Curve<'_> {
    /// Number of points.
    pub fn len(&self) -> usize {
        self.taus.len()
    }

    /// True without points.
    pub fn is_empty(&self) -> bool {
        self.taus.is_empty()
    }

    /// Checks shapes and values; fails on constant data (σ² = 0 everywhere).
    pub fn validate(&self) -> Result<()> {
        let n = self.taus.len();
        for (name, len) in [
            ("variance", self.variance.len()),
            ("m", self.m.len()),
            ("n_terms", self.n_terms.len()),
        ] {
            if len != n {
                return Err(Error::ShapeMismatch {
                    name,
                    reason: format!("{len} values for {n} taus"),
                });
            }
        }
        if let Some(edf) = self.edf {
            if edf.len() != n {
                return Err(Error::ShapeMismatch {
                    name: "edf",
                    reason: format!("{} values for {n} taus", edf.len()),
                });
            }
            if let Some(i) = edf.iter().position(|e| !(e.is_finite() && *e > 0.0)) {
                return Err(Error::invalid(
                    "edf",
                    format!("edf[{i}] = {} is not finite and > 0", edf[i]),
                ));
            }
        }
        if n == 0 {
            return Err(Error::TooShort {
                name: "allan",
                needed: 1,
                got: 0,
            });
        }
        if let Some(i) = self.taus.iter().position(|t| !(t.is_finite() && *t > 0.0)) {
            return Err(Error::invalid(
                "taus",
                format!("taus[{i}] = {} is not finite and > 0", self.taus[i]),
            ));
        }
        if self.taus.windows(2).any(|w| w[1] <= w[0]) {
            return Err(Error::invalid("taus", "must be strictly increasing"));
        }
        if let Some(i) = self
            .variance
            .iter()
            .position(|v| !(v.is_finite() && *v >= 0.0))
        {
            return Err(Error::invalid(
                "variance",
                format!(
                    "variance[{i}] = {} is not finite and >= 0",
                    self.variance[i]
                ),
            ));
        }
        if self.variance.iter().all(|v| *v == 0.0) {
            return Err(Error::invalid(
                "allan",
                "the Allan variance is zero at every τ (constant data): there is no noise to \
                 identify",
            ));
        }
        Ok(())
    }

    /// Number of angle samples behind the estimates (from the first point's bookkeeping).
    pub fn n_phase(&self) -> usize {
        let (m, terms) = (self.m[0], self.n_terms[0]);
        if self.overlapping {
            terms + 2 * m
        } else {
            (terms + 1) * m + 1
        }
    }

    /// EDF of point `i` given the noise term dominating there.
    pub fn edf_at(&self, i: usize, dominant: Term) -> f64 {
        match self.edf {
            Some(e) => e[i],
            None => approximate_edf(self.n_phase(), self.m[i], dominant.alpha()),
        }
    }
}

/// One identified coefficient (or why it is missing).
#[derive(Debug, Clone, PartialEq)]
pub struct TermEstimate {
    /// Which term.
    pub term: Term,
    /// The coefficient in the data's base units; `None` when missing.
    pub value: Option<f64>,
    /// Its standard uncertainty (NaN when missing).
    pub uncertainty: f64,
    /// τ range (s) of the points that determined it.
    pub tau_range: Option<(f64, f64)>,
    /// The point (τ, σ) that marks the read-off on a plot.
    pub marker: Option<(f64, f64)>,
    /// Why the term is missing.
    pub missing: Option<String>,
    /// For a requested term the data do not show (`value` is `None`): the largest value
    /// consistent with them ([`super::bound`]).
    pub upper_bound: Option<UpperBound>,
}

impl TermEstimate {
    pub(crate) fn missing(term: Term, reason: impl Into<String>) -> Self {
        TermEstimate {
            term,
            value: None,
            uncertainty: f64::NAN,
            tau_range: None,
            marker: None,
            missing: Some(reason.into()),
            upper_bound: None,
        }
    }
}

/// Which terms to identify, from their symbols.
pub fn parse_terms(symbols: &[&str]) -> Result<[bool; 5]> {
    let mut enabled = [false; 5];
    for s in symbols {
        enabled[Term::parse(s)?.index()] = true;
    }
    if !enabled.iter().any(|e| *e) {
        return Err(Error::invalid("terms", "no term requested"));
    }
    Ok(enabled)
}
