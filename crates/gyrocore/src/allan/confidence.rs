//! Confidence intervals for Allan-family variances (NIST SP1065 §5.3–5.5).
//!
//! For each averaging factor: identify the power-law noise ([`super::noise_id`]: lag-1 ACF
//! where the decimated series has ≥ 30 points, B1 ratio and R(n) where it has fewer — SP1065
//! §5.6, Stable32's rule), compute the equivalent degrees of freedom ([`super::edf`], Greenhall /
//! SP1065 Table 11; never more than the number of terms summed) and form the chi-square interval
//! of the variance (SP1065 eq. 45):
//!
//! ```text
//! σ̂² · edf / χ²_{edf, (1+c)/2}  ≤  σ²  ≤  σ̂² · edf / χ²_{edf, (1−c)/2}
//! ```
//!
//! (`c` the two-sided confidence level, χ²_{ν,p} the p-quantile). The identified α is clamped to
//! the range where the estimator converges and Greenhall's algorithm is defined (α ≥ −2 for
//! the Allan-type variances, α ≥ −4 for the Hadamard variance, α ≤ 2 always); the reported α
//! is the clamped value the EDF was computed with. Noise identification, EDF and quantiles run
//! in parallel over τ.

use rayon::prelude::*;

use super::{Estimator, edf, noise_id};
use crate::{Error, Result, stats};

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

/// Chi-square interval `(low, high)` of a variance with `edf` degrees of freedom at two-sided
/// confidence `level`.
pub fn chi2_bounds(variance: f64, edf: f64, level: f64) -> Result<(f64, f64)> {
    let tail = (1.0 - level) / 2.0;
    let upper_quantile = stats::chi2_isf(tail, edf)?;
    let lower_quantile = stats::chi2_ppf(tail, edf)?;
    Ok((
        variance * edf / upper_quantile,
        variance * edf / lower_quantile,
    ))
}

/// Identified noise exponent α per factor, clamped to the estimator's convergent range (the
/// value the EDF is computed with).
pub fn alphas(x: &[f64], estimator: Estimator, ms: &[usize]) -> Vec<i32> {
    clamp_alphas(
        noise_id::identify(x, ms, edf::differences(estimator)),
        estimator,
    )
}

/// Identified α clamped to the estimator's convergent range (α ≤ 2, α ≥ [`edf::min_alpha`]).
pub fn clamp_alphas(raw: Vec<i32>, estimator: Estimator) -> Vec<i32> {
    let alpha_min = edf::min_alpha(estimator);
    raw.into_iter().map(|a| a.clamp(alpha_min, 2)).collect()
}

/// Confidence intervals at `level` for `variances` estimated at factors `ms` from angle series `x`.
pub fn intervals(
    x: &[f64],
    estimator: Estimator,
    ms: &[usize],
    variances: &[f64],
    level: f64,
) -> Result<Intervals> {
    if !(level > 0.0 && level < 1.0) {
        return Err(Error::invalid(
            "confidence",
            format!("must lie strictly between 0 and 1, got {level}"),
        ));
    }
    if ms.len() != variances.len() {
        return Err(Error::ShapeMismatch {
            name: "variances",
            reason: format!(
                "{} variances for {} averaging factors",
                variances.len(),
                ms.len()
            ),
        });
    }
    intervals_from_alphas(
        alphas(x, estimator, ms),
        estimator,
        ms,
        variances,
        level,
        x.len(),
    )
}

/// [`intervals`] for already identified (clamped) α, on a record of `n_phase` angle samples.
pub fn intervals_from_alphas(
    alpha: Vec<i32>,
    estimator: Estimator,
    ms: &[usize],
    variances: &[f64],
    level: f64,
    n_phase: usize,
) -> Result<Intervals> {
    let rows: Vec<Result<(f64, f64, f64)>> = ms
        .par_iter()
        .zip(variances.par_iter())
        .zip(alpha.par_iter())
        .with_max_len(1)
        .map(|((&m, &var), &a)| {
            let e = edf::edf(estimator, a, m, n_phase)?;
            let (lo, hi) = chi2_bounds(var, e, level)?;
            Ok((e, lo, hi))
        })
        .collect();
    let mut out = Intervals {
        alpha,
        edf: Vec::with_capacity(ms.len()),
        low: Vec::with_capacity(ms.len()),
        high: Vec::with_capacity(ms.len()),
    };
    for r in rows {
        let (e, lo, hi) = r?;
        out.edf.push(e);
        out.low.push(lo);
        out.high.push(hi);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::super::{Column, DataType, TauSpec, Taus, analyse};
    use super::*;

    fn rate(n: usize, seed: u64) -> Vec<f64> {
        crate::random::normal_vec(n, seed)
    }

    #[test]
    fn interval_contains_estimate_and_scales() {
        let r = rate(4000, 1);
        for est in [
            Estimator::Overlapping,
            Estimator::NonOverlapping,
            Estimator::Modified,
            Estimator::Hadamard,
            Estimator::Total,
        ] {
            let a = analyse(
                Column::contiguous(&r),
                0.01,
                DataType::Rate,
                est,
                &Taus::Spec(TauSpec::Octave),
                Some(0.683),
            )
            .unwrap();
            let ci = a.confidence.unwrap();
            for i in 0..a.m.len() {
                assert!(
                    ci.low[i] <= a.variance[i] && a.variance[i] <= ci.high[i],
                    "{est:?} {i}"
                );
                assert!(ci.edf[i] > 0.0);
                // White rate noise in the well-populated τ.
                if a.m[i] <= 16 {
                    assert_eq!(ci.alpha[i], 0, "{est:?} m={}", a.m[i]);
                }
            }
            let scaled: Vec<f64> = r.iter().map(|v| 3.0 * v).collect();
            let b = analyse(
                Column::contiguous(&scaled),
                0.01,
                DataType::Rate,
                est,
                &Taus::Spec(TauSpec::Octave),
                Some(0.683),
            )
            .unwrap();
            let cb = b.confidence.unwrap();
            assert_eq!(ci.alpha, cb.alpha);
            for i in 0..a.m.len() {
                // 1e-12: scaling by 3 is exact in the noise id (scale-free ACF) and EDF; the
                // variances themselves agree to rounding.
                assert!((cb.low[i] / (9.0 * ci.low[i]) - 1.0).abs() < 1e-12);
                assert!((cb.high[i] / (9.0 * ci.high[i]) - 1.0).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn chi2_bounds_white_fm_example() {
        // edf 10 at 68.3 %: 10/χ²_{10,0.8415} and 10/χ²_{10,0.1585} from scipy.stats.chi2
        // (0.6978775507845881, 1.760979788295106); 1e-12 = the quantiles' accuracy.
        let (lo, hi) = chi2_bounds(1.0, 10.0, 0.683).unwrap();
        assert!((lo / 0.6978775507845881 - 1.0).abs() < 1e-12, "{lo}");
        assert!((hi / 1.760979788295106 - 1.0).abs() < 1e-12, "{hi}");
    }

    #[test]
    fn edf_never_exceeds_the_terms() {
        // White angle noise makes Greenhall's EDF largest; every estimator, every octave τ.
        let x = crate::random::normal_vec(3001, 3);
        for est in [
            Estimator::Overlapping,
            Estimator::NonOverlapping,
            Estimator::Modified,
            Estimator::Hadamard,
            Estimator::Total,
        ] {
            let ms: Vec<usize> = (0..12)
                .map(|k| 1usize << k)
                .filter(|&m| m <= est.max_factor(x.len()))
                .collect();
            for alpha in edf::min_alpha(est)..=2 {
                for &m in &ms {
                    let e = edf::edf(est, alpha, m, x.len()).unwrap();
                    let terms = est.n_terms(x.len(), m) as f64;
                    assert!(e <= terms, "{est:?} alpha={alpha} m={m}: {e} > {terms}");
                }
            }
        }
    }

    #[test]
    fn bad_level() {
        let x: Vec<f64> = (0..100).map(f64::from).collect();
        for level in [0.0, 1.0, -0.5, f64::NAN] {
            assert!(intervals(&x, Estimator::Overlapping, &[1], &[1.0], level).is_err());
        }
    }
}
