//! Joint identification: weighted non-negative least squares of the five-term model (SPEC §3).
//!
//! The model `σ²(τ) = Σ_j c_j g_j(τ)` is linear in `c = (Q², N², B², K², R²) ≥ 0`. Each
//! estimate `σ̂²_i` has relative standard deviation `√(2/edf_i)` (chi-square with `edf_i`
//! degrees of freedom), so the weights are `w_i = edf_i / (2 σ²_i²)`. Weighting by the *observed*
//! `σ̂²_i` favours low estimates (a known downward bias), so the weights use the fitted model
//! instead, by iteratively reweighted least squares (first pass: observed values; then the
//! previous model, floored at 1 % of the observation; ≤ 50 passes, stop when the coefficients
//! change by < 1e-10 relative).
//!
//! **Non-negativity** is exact: with at most five unknowns every subset of the requested terms
//! is solved unconstrained (Householder QR of the column-scaled weighted design) and the
//! feasible subset with the smallest χ² is the NNLS solution (its KKT point is the unconstrained
//! optimum on its passive set). Subsets that leave no degree of freedom are not used.
//!
//! **Uncertainties**: the estimates at neighbouring τ are strongly correlated, so the
//! covariance of `c` is the sandwich `(AᵀWA)⁻¹ AᵀW V W A (AᵀWA)⁻¹` with `V_ij = ρ_ij s_i s_j`,
//! `s_i = σ²_i √(2/edf_i)` and the correlation ρ of the fitted model's estimates
//! ([`super::covariance`]); it is inflated by `max(1, χ²/ν)` when the model does not explain the
//! scatter. For the amplitude `√c_j` the delta method gives `u = u(c_j) / (2√c_j)`.
//!
//! **EDF**: from noise identification when the caller has it (`Curve::edf`), else SP1065's
//! simple approximations ([`super::model::approximate_edf`]) for the noise type of the term that
//! dominates the current model at each τ (white rate in the first pass).

use super::covariance::correlation;
use super::curve::{Curve, TermEstimate};
use super::model::{FLICKER_FACTOR, Term, model_variance};
use crate::{Error, Result};

/// Result of [`joint`].
#[derive(Debug, Clone, PartialEq)]
pub struct JointFit {
    /// One estimate per term in [`Term::ALL`] order.
    pub terms: Vec<TermEstimate>,
    /// Squared coefficients `c` (zero for terms not in the solution).
    pub squared: [f64; 5],
    /// Covariance of `c` (after the χ² inflation).
    pub covariance: [[f64; 5]; 5],
    /// Weighted residual sum of squares.
    pub chi2: f64,
    /// Degrees of freedom `points − fitted terms`.
    pub dof: usize,
    /// τ range of the points used (s).
    pub tau_range: (f64, f64),
    /// Indices of the curve points used.
    pub used: Vec<usize>,
    /// EDF used for each point of `used`.
    pub edf: Vec<f64>,
    /// IRLS passes made.
    pub iterations: usize,
}

/// A solved subset: its terms, coefficients, unscaled covariance and χ².
type SubsetFit = (Vec<Term>, Vec<f64>, Vec<Vec<f64>>, f64);

/// Minimum share of the model variance at which a point counts towards a term's τ range.
const SHARE: f64 = 0.1;

/// Weighted least squares on the columns in `subset`; `None` if singular or dof < 1.
/// Returns (coefficients, unscaled covariance of the subset, chi2).
fn solve_subset(
    taus: &[f64],
    y: &[f64],
    sqrt_w: &[f64],
    subset: &[Term],
) -> Option<(Vec<f64>, Vec<Vec<f64>>, f64)> {
    let n = taus.len();
    let p = subset.len();
    if p == 0 || n <= p {
        return None;
    }
    // Column-major weighted design, columns scaled to unit norm.
    let mut a: Vec<Vec<f64>> = subset
        .iter()
        .map(|t| (0..n).map(|i| sqrt_w[i] * t.basis(taus[i])).collect())
        .collect();
    let scale: Vec<f64> = a
        .iter()
        .map(|col| col.iter().map(|v| v * v).sum::<f64>().sqrt())
        .collect();
    if scale.iter().any(|s| !(s.is_finite() && *s > 0.0)) {
        return None;
    }
    for (col, s) in a.iter_mut().zip(&scale) {
        for v in col.iter_mut() {
            *v /= s;
        }
    }
    let mut b: Vec<f64> = (0..n).map(|i| sqrt_w[i] * y[i]).collect();
    let b_norm2: f64 = b.iter().map(|v| v * v).sum();
    // Householder QR, applied to b on the fly.
    let mut r = vec![vec![0.0; p]; p];
    for j in 0..p {
        let norm = a[j][j..].iter().map(|v| v * v).sum::<f64>().sqrt();
        if norm == 0.0 {
            return None;
        }
        let alpha = if a[j][j] > 0.0 { -norm } else { norm };
        let mut v: Vec<f64> = a[j][j..].to_vec();
        v[0] -= alpha;
        let vnorm2: f64 = v.iter().map(|x| x * x).sum();
        if vnorm2 > 0.0 {
            for col in a.iter_mut().skip(j) {
                let dot: f64 = v.iter().zip(&col[j..]).map(|(x, y)| x * y).sum();
                let f = 2.0 * dot / vnorm2;
                for (c, x) in col[j..].iter_mut().zip(&v) {
                    *c -= f * x;
                }
            }
            let dot: f64 = v.iter().zip(&b[j..]).map(|(x, y)| x * y).sum();
            let f = 2.0 * dot / vnorm2;
            for (c, x) in b[j..].iter_mut().zip(&v) {
                *c -= f * x;
            }
        }
        for i in 0..=j {
            r[i][j] = a[j][i];
        }
    }
    // Columns have unit norm, so |r_jj| is a direct measure of the loss of rank.
    if r.iter().enumerate().any(|(j, row)| row[j].abs() < 1e-10) {
        return None;
    }
    // Back substitution R z = (Qᵀ b)[..p].
    let mut z = vec![0.0; p];
    for j in (0..p).rev() {
        let s: f64 = (j + 1..p).map(|k| r[j][k] * z[k]).sum();
        z[j] = (b[j] - s) / r[j][j];
    }
    let chi2 = b[p..].iter().map(|v| v * v).sum::<f64>().max(0.0);
    if !chi2.is_finite() || !b_norm2.is_finite() {
        return None;
    }
    // R⁻¹ (upper triangular), covariance = R⁻¹ R⁻ᵀ, unscaled.
    let mut rinv = vec![vec![0.0; p]; p];
    for j in 0..p {
        rinv[j][j] = 1.0 / r[j][j];
        for i in (0..j).rev() {
            let s: f64 = (i + 1..=j).map(|k| r[i][k] * rinv[k][j]).sum();
            rinv[i][j] = -s / r[i][i];
        }
    }
    let mut cov = vec![vec![0.0; p]; p];
    for i in 0..p {
        for j in 0..p {
            let s: f64 = (i.max(j)..p).map(|k| rinv[i][k] * rinv[j][k]).sum();
            cov[i][j] = s / (scale[i] * scale[j]);
        }
    }
    let c: Vec<f64> = z.iter().zip(&scale).map(|(z, s)| z / s).collect();
    Some((c, cov, chi2))
}

/// The term contributing most to the model at `tau` (white rate if the model is empty).
fn dominant(c: &[f64; 5], tau: f64) -> Term {
    let mut best = Term::AngleRandomWalk;
    let mut best_value = 0.0;
    for t in Term::ALL {
        let v = c[t.index()] * t.basis(tau);
        if v > best_value {
            best_value = v;
            best = t;
        }
    }
    best
}

/// Covariance of the WLS estimate when the estimates are correlated:
/// `(AᵀWA)⁻¹ · AᵀW V W A · (AᵀWA)⁻¹` with `V_ij = ρ_ij s_i s_j`, `s_i = σ²_model,i √(2/edf_i)` and
/// ρ from [`super::covariance::correlation`].
fn sandwich(
    curve: &Curve<'_>,
    used: &[usize],
    taus: &[f64],
    y: &[f64],
    subset: &[Term],
    c: &[f64; 5],
    edf: &[f64],
    sqrt_w: &[f64],
    bread: &[Vec<f64>],
) -> Vec<Vec<f64>> {
    let n = used.len();
    let p = subset.len();
    let m: Vec<usize> = used.iter().map(|&i| curve.m[i]).collect();
    let terms: Vec<usize> = used.iter().map(|&i| curve.n_terms[i]).collect();
    let t0 = taus[0] / m[0] as f64;
    let rho = correlation(&m, &terms, t0, c);
    let s: Vec<f64> = taus
        .iter()
        .zip(y)
        .zip(edf)
        .map(|((t, obs), e)| model_variance(c, *t).max(0.01 * obs) * (2.0 / e).sqrt())
        .collect();
    // u_i = w_i · A_i (row i of the design on the subset).
    let u: Vec<Vec<f64>> = (0..n)
        .map(|i| {
            let w = sqrt_w[i] * sqrt_w[i];
            subset.iter().map(|t| w * t.basis(taus[i])).collect()
        })
        .collect();
    let mut meat = vec![vec![0.0; p]; p];
    for i in 0..n {
        for j in 0..n {
            let v = rho[i * n + j] * s[i] * s[j];
            for a in 0..p {
                for b in 0..p {
                    meat[a][b] += u[i][a] * v * u[j][b];
                }
            }
        }
    }
    let mut tmp = vec![vec![0.0; p]; p];
    for a in 0..p {
        for b in 0..p {
            tmp[a][b] = (0..p).map(|k| bread[a][k] * meat[k][b]).sum();
        }
    }
    let mut out = vec![vec![0.0; p]; p];
    for a in 0..p {
        for b in 0..p {
            out[a][b] = (0..p).map(|k| tmp[a][k] * bread[k][b]).sum();
        }
    }
    out
}

/// Joint weighted NNLS fit of the requested terms over the points with τ in `tau_range`.
pub fn joint(
    curve: &Curve<'_>,
    enabled: [bool; 5],
    tau_range: Option<(f64, f64)>,
) -> Result<JointFit> {
    curve.validate()?;
    if !enabled.iter().any(|e| *e) {
        return Err(Error::invalid("terms", "no term requested"));
    }
    let (lo, hi) = tau_range.unwrap_or((0.0, f64::INFINITY));
    if !(lo.is_finite() || lo == 0.0) || lo.is_nan() || hi.is_nan() || hi <= lo {
        return Err(Error::invalid(
            "tau_range",
            format!("must be (low, high) with low < high, got ({lo}, {hi})"),
        ));
    }
    // Points with σ² = 0 carry no usable weight (their relative error is undefined).
    let used: Vec<usize> = (0..curve.len())
        .filter(|&i| curve.taus[i] >= lo && curve.taus[i] <= hi && curve.variance[i] > 0.0)
        .collect();
    if used.len() < 3 {
        return Err(Error::TooShort {
            name: "allan",
            needed: 3,
            got: used.len(),
        });
    }
    let taus: Vec<f64> = used.iter().map(|&i| curve.taus[i]).collect();
    let y: Vec<f64> = used.iter().map(|&i| curve.variance[i]).collect();
    let requested: Vec<Term> = Term::ALL
        .into_iter()
        .filter(|t| enabled[t.index()])
        .collect();

    let mut c = [0.0_f64; 5];
    let mut reference = y.clone();
    let mut edf: Vec<f64> = used
        .iter()
        .map(|&i| curve.edf_at(i, Term::AngleRandomWalk))
        .collect();
    let mut best: Option<SubsetFit> = None;
    let mut last_sqrt_w: Vec<f64> = Vec::new();
    let mut iterations = 0;
    for pass in 0..50 {
        iterations = pass + 1;
        let sqrt_w: Vec<f64> = reference
            .iter()
            .zip(&edf)
            .map(|(r, e)| (e / 2.0).sqrt() / r)
            .collect();
        let mut pass_best: Option<SubsetFit> = None;
        for mask in 1u32..(1 << requested.len()) {
            let subset: Vec<Term> = requested
                .iter()
                .enumerate()
                .filter(|(k, _)| mask & (1 << k) != 0)
                .map(|(_, t)| *t)
                .collect();
            let Some((coef, cov, chi2)) = solve_subset(&taus, &y, &sqrt_w, &subset) else {
                continue;
            };
            if coef.iter().any(|v| *v < 0.0) {
                continue;
            }
            if pass_best.as_ref().is_none_or(|b| chi2 < b.3) {
                pass_best = Some((subset, coef, cov, chi2));
            }
        }
        let Some(found) = pass_best else {
            return Err(Error::Singular {
                reason: "no subset of the requested terms gives a non-negative weighted \
                         least-squares solution with a degree of freedom left"
                    .into(),
            });
        };
        let mut next = [0.0_f64; 5];
        for (t, v) in found.0.iter().zip(&found.1) {
            next[t.index()] = *v;
        }
        let change = (0..5)
            .map(|j| (next[j] - c[j]).abs() / next[j].abs().max(c[j].abs()).max(f64::MIN_POSITIVE))
            .fold(0.0_f64, f64::max);
        c = next;
        best = Some(found);
        last_sqrt_w = sqrt_w;
        if pass > 0 && change < 1e-10 {
            break;
        }
        reference = taus
            .iter()
            .zip(&y)
            .map(|(t, obs)| model_variance(&c, *t).max(0.01 * obs))
            .collect();
        if curve.edf.is_none() {
            edf = used
                .iter()
                .zip(&taus)
                .map(|(&i, t)| curve.edf_at(i, dominant(&c, *t)))
                .collect();
        }
    }
    let (subset, _, cov_sub, chi2) = best.expect("at least one pass ran");
    let dof = taus.len() - subset.len();
    let inflation = (chi2 / dof as f64).max(1.0);
    let cov_sub = sandwich(
        curve,
        &used,
        &taus,
        &y,
        &subset,
        &c,
        &edf,
        &last_sqrt_w,
        &cov_sub,
    );
    let mut covariance = [[0.0_f64; 5]; 5];
    for (a, ta) in subset.iter().enumerate() {
        for (b, tb) in subset.iter().enumerate() {
            covariance[ta.index()][tb.index()] = cov_sub[a][b] * inflation;
        }
    }
    let model: Vec<f64> = taus.iter().map(|t| model_variance(&c, *t)).collect();
    // τ of the model minimum among the used points (marker of B).
    let tau_min = taus
        .iter()
        .zip(&model)
        .min_by(|a, b| a.1.total_cmp(b.1))
        .map_or(taus[0], |p| *p.0);
    let terms = Term::ALL
        .into_iter()
        .map(|t| {
            let j = t.index();
            if !enabled[j] {
                return TermEstimate::missing(t, "not requested");
            }
            if c[j] <= 0.0 {
                return TermEstimate::missing(
                    t,
                    format!(
                        "the non-negative fit set it to zero: no τ in {}..{} s where this \
                         term is visible above the others",
                        taus[0],
                        taus[taus.len() - 1]
                    ),
                );
            }
            let value = c[j].sqrt();
            let uncertainty = covariance[j][j].sqrt() / (2.0 * value);
            let visible: Vec<f64> = taus
                .iter()
                .zip(&model)
                .filter(|(tau, m)| c[j] * t.basis(**tau) >= SHARE * **m)
                .map(|(tau, _)| *tau)
                .collect();
            let tau_range = visible.first().map(|a| (*a, *visible.last().unwrap_or(a)));
            let marker = match t.read_off_tau() {
                Some(tau) => Some((tau, value)),
                None => Some((tau_min, FLICKER_FACTOR * value)),
            };
            TermEstimate {
                term: t,
                value: Some(value),
                uncertainty,
                tau_range,
                marker,
                missing: None,
            }
        })
        .collect();
    Ok(JointFit {
        terms,
        squared: c,
        covariance,
        chi2,
        dof,
        tau_range: (taus[0], taus[taus.len() - 1]),
        used,
        edf,
        iterations,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Exact model curve on octave τ (no noise): the fit must return the coefficients.
    #[test]
    fn exact_model_is_recovered() {
        let t0 = 0.01;
        let n = 2_880_000usize;
        let m: Vec<usize> = (0..21).map(|k| 1usize << k).collect();
        let taus: Vec<f64> = m.iter().map(|&m| m as f64 * t0).collect();
        let truth = [1e-6, 1e-5, 4e-8, 1e-9, 1e-13];
        let var: Vec<f64> = taus.iter().map(|t| model_variance(&truth, *t)).collect();
        let terms: Vec<usize> = m.iter().map(|&m| n + 1 - 2 * m).collect();
        let curve = Curve {
            taus: &taus,
            variance: &var,
            m: &m,
            n_terms: &terms,
            overlapping: true,
            edf: None,
        };
        let fit = joint(&curve, [true; 5], None).unwrap();
        for (j, t) in truth.iter().enumerate() {
            assert!(
                (fit.squared[j] - t).abs() <= 1e-8 * t,
                "{j}: {} vs {t}",
                fit.squared[j]
            );
        }
        assert!(fit.chi2 < 1e-12);
    }

    #[test]
    fn absent_term_is_missing_with_reason() {
        let m: Vec<usize> = (0..12).map(|k| 1usize << k).collect();
        let taus: Vec<f64> = m.iter().map(|&m| m as f64).collect();
        // Pure white rate noise: Q, B, K, R must come out missing or tiny; N exact.
        let var: Vec<f64> = taus.iter().map(|t| 4.0 / t).collect();
        let terms: Vec<usize> = m.iter().map(|&m| 100_001 - 2 * m).collect();
        let curve = Curve {
            taus: &taus,
            variance: &var,
            m: &m,
            n_terms: &terms,
            overlapping: true,
            edf: None,
        };
        let fit = joint(&curve, [true; 5], None).unwrap();
        let n = &fit.terms[1];
        assert!((n.value.unwrap() - 2.0).abs() < 1e-9);
        for j in [0, 2, 3, 4] {
            let t = &fit.terms[j];
            assert!(t.value.is_none() || t.value.unwrap() < 1e-6, "{t:?}");
        }
        let missing = fit.terms.iter().filter(|t| t.missing.is_some()).count();
        assert!(missing >= 1);
    }

    #[test]
    fn constant_and_short_curves_are_errors() {
        let m = [1usize, 2, 4];
        let taus = [1.0, 2.0, 4.0];
        let zero = [0.0; 3];
        let terms = [99usize, 97, 93];
        let curve = Curve {
            taus: &taus,
            variance: &zero,
            m: &m,
            n_terms: &terms,
            overlapping: true,
            edf: None,
        };
        assert!(joint(&curve, [true; 5], None).is_err());
        let var = [1.0, 0.5, 0.25];
        let curve = Curve {
            variance: &var,
            ..curve
        };
        assert!(matches!(
            joint(&curve, [true; 5], Some((1.5, 10.0))),
            Err(Error::TooShort { .. })
        ));
        assert!(joint(&curve, [false; 5], None).is_err());
    }
}
