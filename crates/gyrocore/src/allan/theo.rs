//! Théo1, bias-removed ThéoBR and the hybrid ThéoH (NIST SP 1065 §5.2.14–5.2.16).
//!
//! **Théo1** (D. A. Howe and T. K. Peppler, "Very long-term frequency stability: estimation
//! using a special-purpose statistic", IFCS 2003; SP 1065 eq. 30) on `N` angle samples at even
//! `m` (`2 ≤ m ≤ N − 1`) estimates the Allan variance at `τ = 0.75·m·t0`:
//!
//! ```text
//! Théo1(m) = 1/(0.75 (N − m)(m t0)²) · Σ_{i=0}^{N−m−1} Σ_{δ=0}^{m/2−1} 1/(m/2 − δ)
//!            · [(x_i − x_{i−δ+m/2}) + (x_{i+m} − x_{i+δ+m/2})]²
//! ```
//!
//! With `k = m/2 − δ` the bracket is `(x_i − x_{i+k}) − (x_{i+m−k} − x_{i+m})`, the difference of
//! two `k`-lag increments `m − k` apart. It is summed directly from differences of `x` (no
//! expansion into products, which loses digits on drifting data): for each `k` one contiguous,
//! vectorised pass over `i`, the `k` in parallel and combined in a fixed order. Cost
//! `(N − m)·m/2` per τ — about `m/2` overlapping-Allan passes.
//!
//! **ThéoBR** (Howe & Tasset, "ThêoH: a hybrid, high-confidence statistic that improves on the
//! Allan deviation", Metrologia 43 (2006) S322; SP 1065 eq. 31) removes Théo1's bias for the
//! noise at hand using the AVAR/Théo1 ratio at the same τ over the short-τ region:
//!
//! ```text
//! ThéoBR(m) = [1/(n+1) · Σ_{i=0}^{n} AVAR(9 + 3i) / Théo1(12 + 4i)] · Théo1(m),   n = ⌊N/30 − 3⌋
//! ```
//!
//! (AVAR the overlapping Allan variance at `m = 9 + 3i`, the same τ as Théo1 at `12 + 4i`).
//! **ThéoH** joins AVAR below and ThéoBR above the break τ `k`, the largest τ ≤ 10 % of the
//! record `T = (N − 1)·t0` (SP 1065 eq. 32).

use rayon::prelude::*;

use crate::validate;
use crate::{Error, Result};

/// `Σ_{k=1}^{m/2} (1/k) Σ_i [(x_i − x_{i+k}) − (x_{i+m−k} − x_{i+m})]²` (the Théo1 double sum).
fn theo1_sum(x: &[f64], m: usize) -> f64 {
    let n = x.len();
    let count = n - m;
    let h = m / 2;
    let per_k: Vec<f64> = (1..h + 1)
        .into_par_iter()
        .with_min_len(if count < 4096 { 64 } else { 1 })
        .map(|k| {
            let a = &x[..count];
            let b = &x[k..k + count];
            let c = &x[m - k..m - k + count];
            let d = &x[m..m + count];
            let mut lanes = [0.0_f64; 8];
            let whole = count - count % 8;
            for (((ca, cb), cc), cd) in a[..whole]
                .chunks_exact(8)
                .zip(b[..whole].chunks_exact(8))
                .zip(c[..whole].chunks_exact(8))
                .zip(d[..whole].chunks_exact(8))
            {
                for l in 0..8 {
                    let t = (ca[l] - cb[l]) - (cc[l] - cd[l]);
                    lanes[l] += t * t;
                }
            }
            let mut tail = 0.0;
            for i in whole..count {
                let t = (a[i] - b[i]) - (c[i] - d[i]);
                tail += t * t;
            }
            (lanes.iter().sum::<f64>() + tail) / k as f64
        })
        .collect();
    validate::neumaier_sum(per_k)
}

/// Largest even `m` of Théo1 on `n_angle` samples (`m ≤ N − 1`).
pub fn max_factor(n_angle: usize) -> usize {
    let m = n_angle.saturating_sub(1);
    m - m % 2
}

/// Théo1 variance at even averaging factor `m` (τ = 0.75·m·t0) from the angle series `x`.
///
/// Returns `(variance, n_terms)` with `n_terms = N − m` outer terms.
pub fn theo1(x: &[f64], t0: f64, m: usize) -> Result<(f64, usize)> {
    let n = x.len();
    if m < 2 || m % 2 != 0 {
        return Err(Error::invalid(
            "taus",
            format!("Théo1 needs an even averaging factor m >= 2 (τ = 0.75·m·t0), got m = {m}"),
        ));
    }
    if m > max_factor(n) {
        return Err(Error::TooShort {
            name: "data",
            needed: m + 1,
            got: n,
        });
    }
    let tau = m as f64 * t0;
    let count = n - m;
    Ok((theo1_sum(x, m) / (0.75 * count as f64 * tau * tau), count))
}

/// Number of terms `n + 1` of the ThéoBR bias ratio on `n_angle` samples (`n = ⌊N/30 − 3⌋`),
/// or `None` when the record is too short (N < 90).
pub fn bias_terms(n_angle: usize) -> Option<usize> {
    let n = (n_angle as f64 / 30.0 - 3.0).floor();
    if n < 0.0 { None } else { Some(n as usize + 1) }
}

/// Smallest record for ThéoBR / ThéoH.
pub const MIN_SAMPLES_BR: usize = 90;

/// ThéoBR bias ratio `1/(n+1) Σ_i AVAR(9 + 3i)/Théo1(12 + 4i)` of the angle series `x`.
pub fn bias_ratio(x: &[f64], t0: f64) -> Result<f64> {
    let terms = bias_terms(x.len()).ok_or(Error::TooShort {
        name: "data",
        needed: MIN_SAMPLES_BR,
        got: x.len(),
    })?;
    let ratios: Vec<Result<f64>> = (0..terms)
        .into_par_iter()
        .with_max_len(1)
        .map(|i| {
            let (avar, _) = super::variance(x, t0, 9 + 3 * i, super::Estimator::Overlapping)?;
            let (th, _) = theo1(x, t0, 12 + 4 * i)?;
            Ok(avar / th)
        })
        .collect();
    let mut vals = Vec::with_capacity(terms);
    for r in ratios {
        vals.push(r?);
    }
    let ratio = validate::neumaier_sum(vals) / terms as f64;
    if ratio.is_finite() {
        Ok(ratio)
    } else {
        Err(Error::invalid(
            "data",
            "ThéoBR bias ratio undefined: Théo1 is zero at short τ (constant or linear data)",
        ))
    }
}

/// Break point of ThéoH in units of t0: the largest τ/t0 ≤ 10 % of the record `(N − 1)`.
pub fn theoh_break(n_angle: usize) -> f64 {
    (0.1 * n_angle.saturating_sub(1) as f64).floor().max(1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn series(n: usize, seed: u64) -> Vec<f64> {
        let mut s = seed;
        let mut acc = 0.0;
        (0..n)
            .map(|_| {
                s = s
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                acc += (s >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
                acc
            })
            .collect()
    }

    /// SP 1065 eq. 30 literally.
    fn naive(x: &[f64], t0: f64, m: usize) -> f64 {
        let n = x.len();
        let h = m / 2;
        let mut s = 0.0;
        for i in 0..n - m {
            for d in 0..h {
                let t = x[i] - x[i + h - d] + x[i + m] - x[i + d + h];
                s += t * t / (h - d) as f64;
            }
        }
        s / (0.75 * (n - m) as f64 * (m as f64 * t0).powi(2))
    }

    #[test]
    fn theo1_equals_definition() {
        let x = series(301, 3);
        for m in [2usize, 4, 10, 64, 150, 300] {
            let (v, n) = theo1(&x, 0.5, m).unwrap();
            let r = naive(&x, 0.5, m);
            assert_eq!(n, 301 - m);
            // 1e-12: same terms, summed in a different order.
            assert!((v - r).abs() <= 1e-12 * r, "m={m} {v} {r}");
        }
    }

    #[test]
    fn theo1_rejects_odd_and_long() {
        let x = series(50, 1);
        assert!(theo1(&x, 1.0, 3).is_err());
        assert!(theo1(&x, 1.0, 0).is_err());
        assert!(theo1(&x, 1.0, 48).is_ok());
        assert!(theo1(&x, 1.0, 50).is_err());
    }

    #[test]
    fn bias_ratio_needs_record() {
        assert!(bias_ratio(&series(89, 2), 1.0).is_err());
        assert!(bias_ratio(&series(90, 2), 1.0).is_ok());
        let r = bias_ratio(&series(2000, 2), 1.0).unwrap();
        assert!(r > 0.3 && r < 3.0, "{r}");
    }
}
