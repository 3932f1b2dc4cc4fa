//! Modified total (MTOTVAR) and Hadamard total (HTOTVAR) variances without reflection copies.
//!
//! Both statistics (NIST SP 1065 §5.2.12–5.2.13; D. A. Howe and F. Vernotte, "Generalization of
//! the total variance approach to the modified Allan variance", PTTI 1999; D. A. Howe et al.,
//! "A total estimator of the Hadamard function used for GPS operations", PTTI 2000) run the same
//! recipe on every sub-sequence of `3m` consecutive samples `z_i, …, z_{i+3m−1}`:
//!
//! 1. remove a linear trend whose slope is the difference of the means of the first and last
//!    `⌊3m/2⌋` samples divided by their distance `⌈3m/2⌉` (samples);
//! 2. extend the detrended sub-sequence `z⁰` to `9m` samples by uninverted even reflection at
//!    both ends, `z* = [rev(z⁰), z⁰, rev(z⁰)]`;
//! 3. sum the squared second differences of `m`-sample averages over the `6m` positions:
//!    `Σ_{j<6m} ((S_j − 2S_{j+m} + S_{j+2m})/m)²`, `S_j = Σ_{t=j}^{j+m−1} z*_t`.
//!
//! MTOTVAR applies it to the angle (phase) series `x` (`M` samples, `M − 3m + 1` windows) and
//! scales like the modified Allan variance (SP 1065 eq. 27):
//!
//! ```text
//! Mod σ²_total(τ) = 1/(2τ²(M − 3m + 1)) · Σ_i 1/(6m) · Σ_j ((S_j − 2S_{j+m} + S_{j+2m})/m)²
//! ```
//!
//! HTOTVAR applies it to the rate (frequency) series `y_k = (x_{k+1} − x_k)/t0` (`M − 1`
//! samples) and scales like the Hadamard variance (SP 1065 eq. 29): `Σ_i 1/(6·6m) · Σ_j (…)²`
//! over the `M − 3m` windows; at `m = 1` it is the overlapping Hadamard variance (Riley's
//! recommendation for consistency, as Stable32 and AllanTools do).
//!
//! **No copies.** The literal recipe builds a `9m` array per window: O(N·m) memory traffic per
//! τ. Here nothing is copied. With `P` the prefix sums of `z` (kept as a double-double pair, so
//! range sums are accurate to the rounding of the range itself), every window sum is
//! `R_i(r) = P_{i+r} − P_i`, the detrended sum is `X_i(r) = R_i(r) − s_i·r(r−1)/2`, and the
//! running sum of the reflected sequence at position `p` is
//!
//! ```text
//! C(p) = X(3m) − X(3m − p)        (p ≤ 3m)
//!        X(3m) + X(p − 3m)        (3m ≤ p ≤ 6m)
//!        3X(3m) − X(9m − p)       (p ≥ 6m)
//! ```
//!
//! so each term `d_j = C(j+3m) − 3C(j+2m) + 3C(j+m) − C(j)` is O(1). The reflected sequence is
//! 6m-periodic and mirror-symmetric, hence `d_j = d_{3m−j} = d_{9m−j}`: only about `3m` of the
//! `6m` terms are evaluated. The loop runs over windows innermost (contiguous, vectorised) for
//! each `j`. Work per τ is O(N·m) arithmetic on data that stays in cache, with O(N) memory.

use rayon::prelude::*;

use crate::validate;
use crate::{Error, Result};

/// Prefix sums `P_r = Σ_{l<r} z_l` as an unevaluated sum `hi + lo` (error-free TwoSum steps).
struct Prefix {
    hi: Vec<f64>,
    lo: Vec<f64>,
}

impl Prefix {
    fn new(z: impl Iterator<Item = f64>, n: usize) -> Self {
        let mut hi = Vec::with_capacity(n + 1);
        let mut lo = Vec::with_capacity(n + 1);
        hi.push(0.0);
        lo.push(0.0);
        let (mut s, mut c) = (0.0_f64, 0.0_f64);
        for v in z {
            // Neumaier step: s + c carries the exact running sum to ~eps² relative.
            let t = s + v;
            if s.abs() >= v.abs() {
                c += (s - t) + v;
            } else {
                c += (v - t) + s;
            }
            s = t;
            let h = s + c;
            hi.push(h);
            lo.push(c - (h - s));
        }
        Prefix { hi, lo }
    }

    /// Number of samples covered.
    fn len(&self) -> usize {
        self.hi.len() - 1
    }
}

/// Which total statistic's scaling to apply.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    Modified,
    Hadamard,
}

#[inline]
fn tri(r: usize) -> f64 {
    (r as f64) * (r as f64 - 1.0) / 2.0
}

/// `Σ_i Σ_{j<6m} d_j(i)²` over all `n − 3m + 1` windows of the series behind `p`.
fn reflected_sum(p: &Prefix, m: usize) -> f64 {
    let n = p.len();
    let w = 3 * m;
    let windows = n + 1 - w;
    let half = w / 2; // ⌊3m/2⌋ samples in each half
    let dist = w.div_ceil(2) as f64; // ⌈3m/2⌉ between the half means
    let (hi, lo) = (&p.hi, &p.lo);
    let range = |i: usize, r: usize| (hi[i + r] - hi[i]) + (lo[i + r] - lo[i]);
    // Per window: slope (per sample) and the full-window sum.
    let slope: Vec<f64> = (0..windows)
        .map(|i| {
            let mean1 = range(i, half) / half as f64;
            let mean2 = range(i + w - half, half) / half as f64;
            (mean2 - mean1) / dist
        })
        .collect();
    let full: Vec<f64> = (0..windows).map(|i| range(i, w)).collect();
    let t_full = tri(w);

    // Reflected running sum C(p) = a·X(3m) + b·X(r).
    let piece = |pos: usize| -> (f64, f64, usize) {
        if pos <= w {
            (1.0, -1.0, w - pos)
        } else if pos <= 2 * w {
            (1.0, 1.0, pos - w)
        } else {
            (3.0, -1.0, 3 * w - pos)
        }
    };
    // Distinct terms with their multiplicities (mirror symmetry d_j = d_{3m−j} = d_{9m−j}).
    let mut terms: Vec<(usize, f64)> = Vec::with_capacity(w + 2);
    for j in 0..=w / 2 {
        let weight = if 2 * j == w { 1.0 } else { 2.0 };
        terms.push((j, weight));
    }
    for j in w + 1..=(3 * w) / 2 {
        let weight = if 2 * j == 3 * w { 1.0 } else { 2.0 };
        terms.push((j, weight));
    }

    let partial: Vec<f64> = terms
        .par_iter()
        .with_min_len(16)
        .map(|&(j, weight)| {
            let mut a_total = 0.0;
            let mut coef = [0.0_f64; 4];
            let mut rr = [0usize; 4];
            let mut ramp = 0.0;
            for (t, (wt, pos)) in [(1.0, j + 3 * m), (-3.0, j + 2 * m), (3.0, j + m), (-1.0, j)]
                .into_iter()
                .enumerate()
            {
                let (a, b, r) = piece(pos);
                a_total += wt * a;
                coef[t] = wt * b;
                rr[t] = r;
                ramp += wt * b * tri(r);
            }
            ramp += a_total * t_full;
            let mut lanes = [0.0_f64; 4];
            let mut i = 0;
            let term = |i: usize| {
                let mut d = a_total * full[i] - slope[i] * ramp;
                for t in 0..4 {
                    d += coef[t] * range(i, rr[t]);
                }
                d * d
            };
            while i + 4 <= windows {
                for (l, lane) in lanes.iter_mut().enumerate() {
                    *lane += term(i + l);
                }
                i += 4;
            }
            let mut tail = 0.0;
            while i < windows {
                tail += term(i);
                i += 1;
            }
            weight * (lanes.iter().sum::<f64>() + tail)
        })
        .collect();
    validate::neumaier_sum(partial)
}

fn check_factor(name_needed: usize, got: usize, m: usize, max_m: usize) -> Result<()> {
    if m == 0 || m > max_m {
        return Err(Error::TooShort {
            name: "data",
            needed: name_needed,
            got,
        });
    }
    Ok(())
}

/// Largest `m` of MTOTVAR on `n_angle` angle samples (`3m ≤ M`).
pub fn max_factor_modified(n_angle: usize) -> usize {
    n_angle / 3
}

/// Largest `m` of HTOTVAR on `n_angle` angle samples (`3m ≤ M − 1` rate samples).
pub fn max_factor_hadamard(n_angle: usize) -> usize {
    n_angle.saturating_sub(1) / 3
}

/// Modified total variance at averaging factor `m` from the angle series `x` (SP 1065 eq. 27).
///
/// Returns `(variance, n_windows)` with `n_windows = M − 3m + 1`.
pub fn mtotvar(x: &[f64], t0: f64, m: usize) -> Result<(f64, usize)> {
    let prefix = modified_prefix(x);
    mtotvar_with(&prefix, t0, m)
}

fn modified_prefix(x: &[f64]) -> Prefix {
    // Removing the mean changes no term (every d_j has zero total weight on a constant) and
    // keeps the prefix sums small.
    let mean = validate::neumaier_sum(x.iter().copied()) / x.len().max(1) as f64;
    Prefix::new(x.iter().map(|&v| v - mean), x.len())
}

fn hadamard_prefix(x: &[f64], t0: f64) -> Prefix {
    // Prefix sums of the rate y_k = (x_{k+1} − x_k)/t0 are (x_r − x_0)/t0: no summation needed.
    let n = x.len().saturating_sub(1);
    let hi: Vec<f64> = (0..=n).map(|r| (x[r] - x[0]) / t0).collect();
    Prefix {
        hi,
        lo: vec![0.0; n + 1],
    }
}

fn mtotvar_with(prefix: &Prefix, t0: f64, m: usize) -> Result<(f64, usize)> {
    let n = prefix.len();
    check_factor(3 * m, n, m, max_factor_modified(n))?;
    let windows = n + 1 - 3 * m;
    let s = reflected_sum(prefix, m);
    let mf = m as f64;
    Ok((s / (12.0 * mf.powi(5) * t0 * t0 * windows as f64), windows))
}

/// Hadamard total variance at averaging factor `m` from the angle series `x` (SP 1065 eq. 29).
///
/// Returns `(variance, n_terms)`: `M − 3m` windows of the rate series for `m ≥ 2`; at `m = 1`
/// the overlapping Hadamard variance and its `M − 3` terms.
pub fn htotvar(x: &[f64], t0: f64, m: usize) -> Result<(f64, usize)> {
    let prefix = hadamard_prefix(x, t0);
    htotvar_with(x, &prefix, t0, m)
}

fn htotvar_with(x: &[f64], prefix: &Prefix, t0: f64, m: usize) -> Result<(f64, usize)> {
    let n_rate = prefix.len();
    check_factor(3 * m, n_rate, m, max_factor_hadamard(x.len()))?;
    if m == 1 {
        return super::variance(x, t0, 1, super::Estimator::Hadamard);
    }
    let windows = n_rate + 1 - 3 * m;
    let s = reflected_sum(prefix, m);
    let mf = m as f64;
    Ok((s / (36.0 * mf.powi(3) * windows as f64), windows))
}

/// Which total statistic [`variances`] computes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Total {
    /// MTOTVAR.
    Modified,
    /// HTOTVAR.
    Hadamard,
}

/// Variances at several averaging factors (τ in parallel, prefix sums shared).
pub fn variances(x: &[f64], t0: f64, ms: &[usize], which: Total) -> Result<Vec<(f64, usize)>> {
    let kind = match which {
        Total::Modified => Kind::Modified,
        Total::Hadamard => Kind::Hadamard,
    };
    let prefix = match kind {
        Kind::Modified => modified_prefix(x),
        Kind::Hadamard => hadamard_prefix(x, t0),
    };
    ms.par_iter()
        .with_max_len(1)
        .map(|&m| match kind {
            Kind::Modified => mtotvar_with(&prefix, t0, m),
            Kind::Hadamard => htotvar_with(x, &prefix, t0, m),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The literal recipe (reflection copies), as in SP 1065 and AllanTools.
    fn naive(z: &[f64], m: usize) -> f64 {
        let w = 3 * m;
        let half = w / 2;
        let dist = w.div_ceil(2) as f64;
        let mut total = 0.0;
        for i in 0..=z.len() - w {
            let xs = &z[i..i + w];
            let mean1: f64 = xs[..half].iter().sum::<f64>() / half as f64;
            let mean2: f64 = xs[w - half..].iter().sum::<f64>() / half as f64;
            let s = (mean2 - mean1) / dist;
            let x0: Vec<f64> = xs
                .iter()
                .enumerate()
                .map(|(k, v)| v - s * k as f64)
                .collect();
            let mut star: Vec<f64> = x0.iter().rev().copied().collect();
            star.extend_from_slice(&x0);
            star.extend(x0.iter().rev());
            for j in 0..6 * m {
                let s1: f64 = star[j..j + m].iter().sum();
                let s2: f64 = star[j + m..j + 2 * m].iter().sum();
                let s3: f64 = star[j + 2 * m..j + 3 * m].iter().sum();
                total += (s1 - 2.0 * s2 + s3).powi(2);
            }
        }
        total
    }

    /// A random walk (cumulative sum of seeded normal deviates, scaled to the step size the
    /// tolerances were set with) on a small ramp.
    fn series(n: usize) -> Vec<f64> {
        let mut acc = 0.0;
        crate::random::normal_vec(n, 7)
            .into_iter()
            .enumerate()
            .map(|(k, d)| {
                acc += 0.29 * d;
                acc + 0.01 * k as f64
            })
            .collect()
    }

    #[test]
    fn reflected_sum_equals_literal_recipe() {
        let z = series(97);
        let p = Prefix::new(z.iter().copied(), z.len());
        for m in [1usize, 2, 3, 4, 5, 7, 10, 16, 32] {
            let fast = reflected_sum(&p, m);
            let slow = naive(&z, m);
            // 1e-11: same sums, different association (prefix differences vs direct sums).
            assert!(
                (fast - slow).abs() <= 1e-11 * slow,
                "m={m}: {fast} vs {slow}"
            );
        }
    }

    #[test]
    fn invariant_to_offset_and_ramp() {
        let x = series(200);
        let shifted: Vec<f64> = x
            .iter()
            .enumerate()
            .map(|(k, v)| v + 1e3 + 2.5 * k as f64)
            .collect();
        for m in [1usize, 3, 8, 21] {
            let (a, _) = mtotvar(&x, 0.1, m).unwrap();
            let (b, _) = mtotvar(&shifted, 0.1, m).unwrap();
            assert!((a - b).abs() <= 1e-8 * a, "m={m} {a} {b}");
        }
    }

    #[test]
    fn factor_limits() {
        let x = series(30);
        assert!(mtotvar(&x, 1.0, 10).is_ok());
        assert!(mtotvar(&x, 1.0, 11).is_err());
        assert!(htotvar(&x, 1.0, 9).is_ok());
        assert!(htotvar(&x, 1.0, 10).is_err());
        assert!(mtotvar(&x, 1.0, 0).is_err());
    }
}
