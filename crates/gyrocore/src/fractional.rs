//! Fractional differencing and integration, ARFIMA(0, d, 0) (SPEC §4, Hosking 1981, \[BP\] eq. 3).
//!
//! The type-II (truncated at the first sample) fractional difference is
//!
//! ```text
//! (Δ^d x)_k = Σ_{i=0}^{k} π_{k−i}(d) x_i,   π_0 = 1,   π_l = π_{l−1}·(l − 1 − d)/l
//! ```
//!
//! (\[BP\] eq. 3 is misprinted; this is the consistent reading, see SPEC §4). Fractional
//! integration is `Δ^{−d}` with weights `ψ_l = π_l(−d)`.

use crate::{Error, Result};

/// The fractional-difference weights `π_0..π_{n−1}` of `(1 − B)^d` by the product recursion.
///
/// The recursion `π_l = π_{l−1}·(l − 1 − d)/l` is stable (no Gamma functions of large
/// arguments) and gives exact zeros for non-negative integer `d` beyond lag `d`.
/// Integration weights are `weights(-d, n)`.
pub fn weights(d: f64, n: usize) -> Result<Vec<f64>> {
    if !d.is_finite() {
        return Err(Error::invalid("d", format!("must be finite, got {d}")));
    }
    let mut w = Vec::with_capacity(n);
    let mut current = 1.0_f64;
    for l in 0..n {
        if l > 0 {
            current *= (l as f64 - 1.0 - d) / l as f64;
        }
        w.push(current);
    }
    Ok(w)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn first_difference_weights() {
        assert_eq!(weights(1.0, 4).unwrap(), vec![1.0, -1.0, 0.0, 0.0]);
    }

    #[test]
    fn half_integration_weights_match_binomial() {
        // ψ_l = Γ(l + ½)/(Γ(½) l!) = (2l choose l)/4^l
        let psi = weights(-0.5, 6).unwrap();
        let exact = [1.0, 0.5, 0.375, 0.3125, 0.2734375, 0.24609375];
        for (a, b) in psi.iter().zip(exact) {
            assert!((a - b).abs() < 1e-15);
        }
    }
}
