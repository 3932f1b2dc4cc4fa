//! Non-overlapping Hadamard variance (Stable32's "HDEV"; NIST SP 1065 eq. 17).
//!
//! On `M` angle samples at averaging factor `m` (τ = m·t0), with the third difference taken only
//! at the disjoint starting points `k = 0, m, 2m, …`:
//!
//! ```text
//! Hσ²(τ) = Σ_{j=0}^{n−1} (x_{jm+3m} − 3x_{jm+2m} + 3x_{jm+m} − x_{jm})² / (6 τ² n),
//! n = ⌊(M − 1)/m⌋ − 2
//! ```
//!
//! It differs from the overlapping Hadamard variance ([`super::Estimator::Hadamard`], Stable32's
//! "OHDEV") only in which differences enter the average; for white angle noise the two differ
//! by a factor that grows with m, so results must not be compared across the two.

use crate::validate;
use crate::{Error, Result};

/// Largest `m` with at least one term (`3m ≤ M − 1`).
pub fn max_factor(n_angle: usize) -> usize {
    n_angle.saturating_sub(1) / 3
}

/// Number of terms at factor `m` on `n_angle` samples.
pub fn n_terms(n_angle: usize, m: usize) -> usize {
    (n_angle.saturating_sub(1) / m).saturating_sub(2)
}

/// Non-overlapping Hadamard variance at factor `m`; returns `(variance, n_terms)`.
pub fn variance(x: &[f64], t0: f64, m: usize) -> Result<(f64, usize)> {
    if m == 0 || m > max_factor(x.len()) {
        return Err(Error::TooShort {
            name: "data",
            needed: 3 * m.max(1) + 1,
            got: x.len(),
        });
    }
    let n = n_terms(x.len(), m);
    let s = validate::neumaier_sum((0..n).map(|j| {
        let k = j * m;
        let d = x[k + 3 * m] - 3.0 * x[k + 2 * m] + 3.0 * x[k + m] - x[k];
        d * d
    }));
    let tau = m as f64 * t0;
    Ok((s / (6.0 * tau * tau * n as f64), n))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn binned_rate_means() {
        // Third difference of x at stride m = second difference of the m-bin rate means × τ.
        let rate: Vec<f64> = (0..61).map(|i| ((i * 31 % 17) as f64).cos()).collect();
        let mut x = vec![0.0];
        for r in &rate {
            x.push(x.last().unwrap() + r * 0.1);
        }
        for m in [1usize, 2, 5, 20] {
            let k = rate.len() / m;
            let means: Vec<f64> = (0..k)
                .map(|i| rate[i * m..(i + 1) * m].iter().sum::<f64>() / m as f64)
                .collect();
            let refv = means
                .windows(3)
                .map(|w| (w[2] - 2.0 * w[1] + w[0]).powi(2))
                .sum::<f64>()
                / (6.0 * (k - 2) as f64);
            let (v, n) = variance(&x, 0.1, m).unwrap();
            assert_eq!(n, k - 2);
            assert!((v - refv).abs() <= 1e-12 * refv, "m={m} {v} {refv}");
        }
        assert!(variance(&x, 0.1, 21).is_err());
    }
}
