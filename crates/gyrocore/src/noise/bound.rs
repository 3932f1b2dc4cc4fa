//! Upper bounds of noise terms the Allan curve does not show (SPEC "Third wave").
//!
//! When the non-negative fit sets a term to zero ("not visible above the others"), zero is not
//! what the data say: they say the term is *at most* so large. With the one-sided upper
//! confidence bound of each Allan-variance estimate used by the fit,
//!
//! ```text
//! u²_i = σ̂²_i · edf_i / χ²_{edf_i}(α),      α = 1 − confidence,
//! ```
//!
//! (the true variance lies below `u²_i` with probability `1 − α`: σ̂²·edf/σ² ~ χ²_edf, the same
//! bound as [`mod@super::overbound`]) the bound of term `j` is the largest `c_j` whose asymptote stays
//! under `u²` at every τ used,
//!
//! ```text
//! c_j,max = min_i (u²_i − O_i) / g_j(τ_i),      bound = √c_j,max,
//! ```
//!
//! with `g_j` the term's basis ([`Term::basis`]: `K²τ/3` for K, `3Q²/τ²`, `N²/τ`,
//! `(0.664282·B)²`, `R²τ²/2`) and `O_i` the other terms' model variance at `τ_i`.
//!
//! **The other terms are held at zero** — their lower bound under non-negativity — and not at
//! their fit. The fit that set the term to zero has let the other terms absorb its share
//! (an invisible rate random walk is taken up by the bias-instability plateau, the rate ramp or a
//! Gauss–Markov term), so subtracting the fitted others removes part of the very signal being
//! bounded; and with `O_i` close to the truth the bound would need the true curve under `u²` at
//! *every* τ at once, a simultaneous event far less likely than `1 − α` (on simulated logs with a
//! known, invisible K, holding the others at their fit put the bound above the truth in only
//! 60–75 % of runs). With `O_i = 0` every term's Allan variance is non-negative, so
//! `c_j g_j(τ) = s_i σ²_true(τ_i)` with `s_i ≤ 1` the term's share of the true variance, and the
//! bound falls below the truth only if at some τ used `u²_i < s_i σ²_true(τ_i)`. At one τ that
//! has probability `P(χ²_edf < s_i · χ²_edf(α)) ≤ α` — equality only where the term is
//! all of the variance, far less where its share is small, which is what "invisible" means; the
//! points are correlated, and the union over them stays near α (the Monte Carlo check in the
//! tests and `benches/python/bench_coverage.py` measures it). The price is a looser bound
//! where the others are large at the binding τ; the bound is reported with the τ that binds it.

use super::curve::{Curve, TermEstimate};
use super::fit::sig;
use super::model::Term;
use crate::stats::chi2_ppf;
use crate::{Error, Result};

/// Default one-sided confidence level of the upper bounds the fits report (their
/// `bound_confidence` option).
pub const BOUND_CONFIDENCE: f64 = 0.95;

/// The largest value of a term consistent with the data (module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct UpperBound {
    /// Upper bound of the coefficient (amplitude, the data's base units).
    pub value: f64,
    /// One-sided confidence level `1 − α`.
    pub confidence: f64,
    /// τ (s) of the point that binds the bound.
    pub tau: f64,
    /// τ range (s) of the points used.
    pub tau_range: (f64, f64),
    /// Number of points used.
    pub points: usize,
    /// Plain sentence: what the bound is and how it was obtained.
    pub reason: String,
}

/// Upper bound of `term` from the Allan-curve points `used` with their EDF `edf` at one-sided
/// `confidence` (module docs; the other terms are held at zero).
///
/// # Errors
/// Invalid curve ([`Curve::validate`]); `confidence` outside (0, 1); `used` empty, out of range
/// or pointing at σ² = 0; `edf` of another length than `used` or not finite and > 0.
pub fn upper_bound(
    curve: &Curve<'_>,
    used: &[usize],
    edf: &[f64],
    term: Term,
    confidence: f64,
) -> Result<UpperBound> {
    let u2 = upper_variances(curve, used, edf, confidence)?;
    Ok(bound_of(curve, used, &u2, term, confidence))
}

/// The upper confidence bounds `u²_i` of the points `used` (module docs): the part of
/// [`upper_bound`] that does not depend on the term (one χ² quantile per point, computed once
/// for all the terms of a fit by [`attach`]).
fn upper_variances(
    curve: &Curve<'_>,
    used: &[usize],
    edf: &[f64],
    confidence: f64,
) -> Result<Vec<f64>> {
    curve.validate()?;
    crate::validate::probability("confidence", confidence)?;
    if used.is_empty() {
        return Err(Error::TooShort {
            name: "used",
            needed: 1,
            got: 0,
        });
    }
    if edf.len() != used.len() {
        return Err(Error::ShapeMismatch {
            name: "edf",
            reason: format!("{} values for {} points", edf.len(), used.len()),
        });
    }
    if let Some(k) = used
        .iter()
        .position(|&i| i >= curve.len() || curve.variance[i] <= 0.0)
    {
        return Err(Error::invalid(
            "used",
            format!(
                "used[{k}] = {} is not the index of a point with σ² > 0 (the curve has {} points)",
                used[k],
                curve.len()
            ),
        ));
    }
    if let Some(k) = edf.iter().position(|e| !(e.is_finite() && *e > 0.0)) {
        return Err(Error::invalid(
            "edf",
            format!("edf[{k}] = {} is not finite and > 0", edf[k]),
        ));
    }
    let alpha = 1.0 - confidence;
    used.iter()
        .zip(edf)
        .map(|(&i, &e)| Ok(curve.variance[i] * e / chi2_ppf(alpha, e)?))
        .collect()
}

/// [`upper_bound`] of `term` from the points' upper bounds `u2` ([`upper_variances`]).
fn bound_of(
    curve: &Curve<'_>,
    used: &[usize],
    u2: &[f64],
    term: Term,
    confidence: f64,
) -> UpperBound {
    let mut best = (f64::INFINITY, 0usize);
    for (k, (&i, &u2)) in used.iter().zip(u2).enumerate() {
        let tau = curve.taus[i];
        let c = u2 / term.basis(tau);
        if c < best.0 {
            best = (c, k);
        }
    }
    let value = best.0.sqrt();
    let tau = curve.taus[used[best.1]];
    let tau_range = (curve.taus[used[0]], curve.taus[used[used.len() - 1]]);
    let reason = format!(
        "upper bound at {} % one-sided confidence: the largest {} whose Allan-variance asymptote \
         stays under the upper confidence bound of the curve at every τ used ({} points, \
         τ {}–{} s; binding at τ = {} s; the other terms held at zero)",
        percent(confidence),
        term.symbol(),
        used.len(),
        sig(tau_range.0, 3),
        sig(tau_range.1, 3),
        sig(tau, 3)
    );
    UpperBound {
        value,
        confidence,
        tau,
        tau_range,
        points: used.len(),
        reason,
    }
}

/// `confidence` as a percentage with up to 4 significant digits and no trailing zeros
/// (0.95 → "95", 0.9973 → "99.73").
fn percent(confidence: f64) -> String {
    let s = sig(100.0 * confidence, 4);
    if s.contains('.') && !s.contains('e') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// Sets [`TermEstimate::upper_bound`] (at one-sided `confidence`, which the fits check on
/// entry with [`crate::validate::probability`]) on every requested term that has no value,
/// from the points `used` with their EDF `edf`. A bound that cannot be formed (no usable point)
/// is left unset: the term stays missing with its reason.
pub(crate) fn attach(
    terms: &mut [TermEstimate],
    enabled: [bool; 5],
    curve: &Curve<'_>,
    used: &[usize],
    edf: &[f64],
    confidence: f64,
) {
    // The points' bounds are the same for every term: computed once, when a term needs them.
    let mut u2: Option<Option<Vec<f64>>> = None;
    for t in terms.iter_mut() {
        if enabled[t.term.index()] && t.value.is_none() {
            let u2 = u2.get_or_insert_with(|| upper_variances(curve, used, edf, confidence).ok());
            t.upper_bound = u2
                .as_deref()
                .map(|u2| bound_of(curve, used, u2, t.term, confidence));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::noise::model::model_variance;

    fn curve_of<'a>(
        taus: &'a [f64],
        var: &'a [f64],
        m: &'a [usize],
        terms: &'a [usize],
    ) -> Curve<'a> {
        Curve {
            taus,
            variance: var,
            m,
            n_terms: terms,
            overlapping: true,
            edf: None,
        }
    }

    #[test]
    fn bound_touches_the_upper_confidence_bound_once() {
        let m: Vec<usize> = (0..12).map(|k| 1usize << k).collect();
        let taus: Vec<f64> = m.iter().map(|&m| m as f64 * 0.01).collect();
        let var: Vec<f64> = taus
            .iter()
            .map(|t| model_variance(&[0.0, 1e-4, 1e-6, 0.0, 0.0], *t))
            .collect();
        let n_terms: Vec<usize> = m.iter().map(|&m| 100_001 - 2 * m).collect();
        let curve = curve_of(&taus, &var, &m, &n_terms);
        let used: Vec<usize> = (0..taus.len()).collect();
        let edf: Vec<f64> = m.iter().map(|&m| 1e5 / m as f64).collect();
        for term in Term::ALL {
            let b = upper_bound(&curve, &used, &edf, term, 0.95).unwrap();
            let c = b.value * b.value;
            let mut ratios = Vec::new();
            for (&i, &e) in used.iter().zip(&edf) {
                let u2 = var[i] * e / chi2_ppf(0.05, e).unwrap();
                ratios.push(c * term.basis(taus[i]) / u2);
            }
            let max = ratios.iter().copied().fold(0.0, f64::max);
            assert!((max - 1.0).abs() < 1e-12, "{term:?}: {max}");
            assert!(b.reason.contains("95 %"));
            assert_eq!(b.points, used.len());
        }
        // K binds at the longest τ on a flat-then-falling curve; Q at the shortest.
        let k = upper_bound(&curve, &used, &edf, Term::RateRandomWalk, 0.95).unwrap();
        assert_eq!(k.tau, taus[taus.len() - 1]);
        let q = upper_bound(&curve, &used, &edf, Term::Quantization, 0.95).unwrap();
        assert_eq!(q.tau, taus[0]);
        // A higher confidence gives a higher bound.
        let k99 = upper_bound(&curve, &used, &edf, Term::RateRandomWalk, 0.99).unwrap();
        assert!(k99.value > k.value);
    }

    #[test]
    fn the_fits_bound_at_the_callers_confidence_and_refuse_a_bad_one() {
        use crate::noise::fit::{FitOptions, fit};
        use crate::noise::ieee::{ReadOffOptions, read_off};
        // White + flicker only: K and R are not visible, so the fits bound them.
        let m: Vec<usize> = (0..14).map(|k| 1usize << k).collect();
        let taus: Vec<f64> = m.iter().map(|&m| m as f64 * 0.01).collect();
        let var: Vec<f64> = taus
            .iter()
            .map(|t| model_variance(&[0.0, 1e-6, 1e-8, 0.0, 0.0], *t))
            .collect();
        let n_terms: Vec<usize> = m.iter().map(|&m| 400_001 - 2 * m).collect();
        let curve = curve_of(&taus, &var, &m, &n_terms);
        let k = Term::RateRandomWalk.index();
        let at = |level: f64| {
            let options = FitOptions {
                bound_confidence: level,
                ..FitOptions::default()
            };
            fit(&curve, &options).map(|f| f.terms[k].upper_bound.clone())
        };
        let b80 = at(0.8).unwrap().expect("K bounded");
        let b95 = at(0.95).unwrap().expect("K bounded");
        assert_eq!((b80.confidence, b95.confidence), (0.8, 0.95));
        assert!(b80.value < b95.value);
        assert!(b80.reason.contains("80 %"));
        let ieee = read_off(
            &curve,
            [true; 5],
            &ReadOffOptions {
                bound_confidence: 0.8,
                ..ReadOffOptions::default()
            },
        )
        .unwrap();
        assert!(
            ieee.terms
                .iter()
                .filter_map(|t| t.upper_bound.as_ref())
                .all(|b| b.confidence == 0.8)
        );
        for bad in [0.0, 1.0, -0.5, 1.5, f64::NAN, f64::INFINITY] {
            assert!(
                matches!(
                    at(bad),
                    Err(Error::InvalidParameter {
                        name: "bound_confidence",
                        ..
                    })
                ),
                "{bad}"
            );
            let r = read_off(
                &curve,
                [true; 5],
                &ReadOffOptions {
                    bound_confidence: bad,
                    ..ReadOffOptions::default()
                },
            );
            assert!(
                matches!(
                    r,
                    Err(Error::InvalidParameter {
                        name: "bound_confidence",
                        ..
                    })
                ),
                "{bad}"
            );
        }
    }

    #[test]
    fn bad_input_names_the_argument() {
        let m = [1usize, 2, 4];
        let taus = [1.0, 2.0, 4.0];
        let var = [1.0, 0.5, 0.0];
        let terms = [99usize, 97, 93];
        let curve = curve_of(&taus, &var, &m, &terms);
        let k = Term::RateRandomWalk;
        let name = |r: Result<UpperBound>| match r {
            Err(
                Error::InvalidParameter { name, .. }
                | Error::ShapeMismatch { name, .. }
                | Error::TooShort { name, .. },
            ) => name,
            other => panic!("{other:?}"),
        };
        assert_eq!(
            name(upper_bound(&curve, &[0, 1], &[3.0, 3.0], k, 1.0)),
            "confidence"
        );
        assert_eq!(
            name(upper_bound(&curve, &[0, 1], &[3.0, 3.0], k, f64::NAN)),
            "confidence"
        );
        assert_eq!(name(upper_bound(&curve, &[], &[], k, 0.9)), "used");
        assert_eq!(
            name(upper_bound(&curve, &[0, 2], &[3.0, 3.0], k, 0.9)),
            "used"
        );
        assert_eq!(
            name(upper_bound(&curve, &[0, 7], &[3.0, 3.0], k, 0.9)),
            "used"
        );
        assert_eq!(name(upper_bound(&curve, &[0, 1], &[3.0], k, 0.9)), "edf");
        assert_eq!(
            name(upper_bound(&curve, &[0, 1], &[3.0, -1.0], k, 0.9)),
            "edf"
        );
    }
}
