//! Precondition checks shared by all modules.

use crate::{Error, Result};

/// Fails with [`Error::NonFinite`] at the first NaN or infinity in `data`.
pub fn finite(name: &'static str, data: &[f64]) -> Result<()> {
    // Fast path: a sum of finite numbers scaled down cannot overflow, NaN/inf propagate.
    // Fall back to a scan to locate the index only when something is wrong.
    let mut acc = 0.0_f64;
    for chunk in data.chunks(4096) {
        acc += chunk.iter().map(|v| v * 0.0).sum::<f64>();
        if !acc.is_finite() {
            break;
        }
    }
    if acc.is_finite() {
        return Ok(());
    }
    let index = data.iter().position(|v| !v.is_finite()).unwrap_or(0);
    Err(Error::NonFinite { name, index })
}

/// Fails unless `value` is finite and strictly positive.
pub fn positive(name: &'static str, value: f64) -> Result<()> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(Error::invalid(
            name,
            format!("must be finite and > 0, got {value}"),
        ))
    }
}

/// Fails unless `value` is finite and non-negative.
pub fn non_negative(name: &'static str, value: f64) -> Result<()> {
    if value.is_finite() && value >= 0.0 {
        Ok(())
    } else {
        Err(Error::invalid(
            name,
            format!("must be finite and >= 0, got {value}"),
        ))
    }
}

/// Fails unless `data.len() >= needed`.
pub fn min_len(name: &'static str, data_len: usize, needed: usize) -> Result<()> {
    if data_len >= needed {
        Ok(())
    } else {
        Err(Error::TooShort {
            name,
            needed,
            got: data_len,
        })
    }
}

/// Compensated (Neumaier) sum: error independent of the length for well-scaled data.
pub fn neumaier_sum(values: impl IntoIterator<Item = f64>) -> f64 {
    let mut sum = 0.0_f64;
    let mut comp = 0.0_f64;
    for v in values {
        let t = sum + v;
        if sum.abs() >= v.abs() {
            comp += (sum - t) + v;
        } else {
            comp += (v - t) + sum;
        }
        sum = t;
    }
    sum + comp
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finite_reports_first_bad_index() {
        let mut x = vec![1.0; 10_000];
        x[7000] = f64::NAN;
        x[9000] = f64::INFINITY;
        assert_eq!(
            finite("data", &x),
            Err(Error::NonFinite {
                name: "data",
                index: 7000
            })
        );
        assert!(finite("data", &[1e308, 1e308]).is_ok());
    }

    #[test]
    fn neumaier_is_exact_on_cancellation() {
        assert_eq!(neumaier_sum([1e16, 1.0, -1e16]), 1.0);
    }
}
