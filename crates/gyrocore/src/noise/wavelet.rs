//! Haar wavelet variance at dyadic scales (MODWT; Percival & Walden, *Wavelet Methods for Time
//! Series Analysis*, 2000, §8.1).
//!
//! The level-j Haar MODWT coefficient of a rate series `y` (scale `τ_j = 2^j t0`, half-width
//! `m = 2^{j−1}` samples) is the difference of two adjacent means of `m` samples, halved:
//!
//! ```text
//! W_{j,t} = (ȳ_{t+m..t+2m} − ȳ_{t..t+m}) / 2,   t = 0 … n − 2m,   M_j = n − 2m + 1
//! ν̂²_j = (1/M_j) Σ_t W_{j,t}²
//! ```
//!
//! (sign and time alignment do not matter for the variance). Hence `E ν̂²_j = σ²_A(m·t0)/2`:
//! the Haar wavelet variance is half the overlapping Allan variance at `τ = m·t0` with the same
//! number of terms (Percival & Guttorp 1994). The sums use prefix sums of the mean-removed
//! series, one pass per scale, scales in parallel.

use rayon::prelude::*;

use crate::validate;
use crate::{Error, Result};

/// Haar wavelet variance of a rate series.
#[derive(Debug, Clone, PartialEq)]
pub struct WaveletVariance {
    /// Half-widths `m = 2^{j−1}` (samples), j = 1 … J.
    pub m: Vec<usize>,
    /// Wavelet scales `τ_j = 2m·t0` (s).
    pub scales: Vec<f64>,
    /// `ν̂²_j` (rate unit²).
    pub variance: Vec<f64>,
    /// Number of coefficients `M_j = n − 2m + 1`.
    pub n_coefficients: Vec<usize>,
}

/// Haar wavelet variance of `rate` (period `t0`) at every dyadic scale with
/// `n / m ≥ min_blocks` (`m` the half-width), at least two scales.
pub fn haar(rate: &[f64], t0: f64, min_blocks: usize) -> Result<WaveletVariance> {
    validate::positive("fs", 1.0 / t0)?;
    validate::finite("data", rate)?;
    let n = rate.len();
    let min_blocks = min_blocks.max(2);
    let mut m = Vec::new();
    let mut half = 1usize;
    while half.saturating_mul(min_blocks) <= n {
        m.push(half);
        half *= 2;
    }
    if m.len() < 2 {
        return Err(Error::TooShort {
            name: "data",
            needed: 2 * min_blocks,
            got: n,
        });
    }
    let mean = rate.iter().sum::<f64>() / n as f64;
    let mut prefix = Vec::with_capacity(n + 1);
    prefix.push(0.0);
    let mut acc = 0.0;
    for v in rate {
        acc += v - mean;
        prefix.push(acc);
    }
    let variance: Vec<f64> = m
        .par_iter()
        .map(|&h| {
            let count = n - 2 * h + 1;
            let scale = 1.0 / (2.0 * h as f64);
            let mut sum = 0.0;
            for t in 0..count {
                let w = (prefix[t + 2 * h] - 2.0 * prefix[t + h] + prefix[t]) * scale;
                sum += w * w;
            }
            sum / count as f64
        })
        .collect();
    if variance.iter().all(|v| *v == 0.0) {
        return Err(Error::invalid(
            "data",
            "the wavelet variance is zero at every scale (constant data): there is no noise to \
             identify",
        ));
    }
    Ok(WaveletVariance {
        scales: m.iter().map(|&h| 2.0 * h as f64 * t0).collect(),
        n_coefficients: m.iter().map(|&h| n - 2 * h + 1).collect(),
        m,
        variance,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::allan::{Column, DataType, Estimator, angle_series, variance};

    #[test]
    fn half_the_overlapping_allan_variance() {
        let rate: Vec<f64> = (0..1000)
            .map(|k| ((k * 7919) % 113) as f64 * 0.01 + (k as f64 * 0.001).sin())
            .collect();
        let t0 = 0.1;
        let wv = haar(&rate, t0, 4).unwrap();
        let x = angle_series(Column::contiguous(&rate), t0, DataType::Rate).unwrap();
        for (i, &h) in wv.m.iter().enumerate() {
            let (avar, terms) = variance(&x, t0, h, Estimator::Overlapping).unwrap();
            assert_eq!(terms, wv.n_coefficients[i]);
            assert!(
                (2.0 * wv.variance[i] / avar - 1.0).abs() < 1e-10,
                "m={h}: {} vs {avar}",
                2.0 * wv.variance[i]
            );
        }
        assert_eq!(wv.m.last(), Some(&128));
    }

    #[test]
    fn constant_and_short_data_are_errors() {
        assert!(haar(&[1.0; 100], 1.0, 4).is_err());
        assert!(matches!(
            haar(&[1.0, 2.0, 3.0], 1.0, 4),
            Err(Error::TooShort { .. })
        ));
    }
}
