//! IEEE-952 read-off identification (IEEE Std 952-1997 Annex C, SPEC §3).
//!
//! The local log-log slope of the Allan deviation at each point is the central difference
//! `s_i = (ln σ_{i+1} − ln σ_{i−1}) / (ln τ_{i+1} − ln τ_{i−1})` (one-sided at the ends). A
//! term's region is the longest run of consecutive points with `|s_i − s_term| ≤ tolerance`
//! (at least `min_points` points; ties broken by the wider τ span, then the shorter τ), or the
//! points inside a range the caller gives. On that region a line of the term's fixed slope is
//! fitted in log-log by weighted least squares,
//! `ln C = Σ w_i (ln σ_i − s ln τ_i) / Σ w_i`, `w_i = 2·edf_i` (the inverse variance of
//! `ln σ̂_i`), and read off at the term's τ:
//!
//! | term | slope | read at | coefficient |
//! |---|---|---|---|
//! | Q | −1 | τ = √3 s | `σ(√3) = Q` |
//! | N | −½ | τ = 1 s | `σ(1) = N` |
//! | K | +½ | τ = 3 s | `σ(3) = K` |
//! | R | +1 | τ = √2 s | `σ(√2) = R` |
//! | B | 0 | minimum | `B = min σ / 0.664282` |
//!
//! B needs a minimum inside the curve (the flat region); if σ is smallest at the first or
//! last τ the term is missing. The automatic search considers only estimates with EDF ≥ 5
//! ([`MIN_EDF_B`]): the last octaves of a record rest on one or two degrees of freedom, and a
//! low value there is noise, not a plateau. The read-off of B is biased high wherever the N and K
//! asymptotes still contribute at the minimum — the joint fit ([`super::fit`](mod@super::fit)) is the better
//! estimator.
//!
//! **Uncertainty**: the estimates at neighbouring τ come from the same data and are positively
//! correlated, so averaging them does not beat the best single point by much; the read-off
//! reports the relative uncertainty of the most precise point used, `1/√(2·edf)` (from its
//! chi-square interval), which is conservative. For B it is that of the minimum point.

use super::curve::{Curve, TermEstimate};
use super::model::{FLICKER_FACTOR, Term};
use crate::{Error, Result};

/// Smallest EDF of an estimate taken into the automatic search for the minimum (relative
/// standard deviation of σ ≤ 1/√10 ≈ 32 %).
pub const MIN_EDF_B: f64 = 5.0;

/// Options of [`read_off`].
#[derive(Debug, Clone, PartialEq)]
pub struct ReadOffOptions {
    /// Allowed deviation of the local slope from the term's slope (default 0.1).
    pub tolerance: f64,
    /// Minimum number of points in an automatically detected region (default 3).
    pub min_points: usize,
    /// Explicit τ ranges (s) per term in [`Term::ALL`] order, overriding detection.
    pub regions: [Option<(f64, f64)>; 5],
    /// One-sided confidence level of the upper bounds of the terms the read-off does not find
    /// ([`super::bound`]; default [`super::BOUND_CONFIDENCE`]).
    pub bound_confidence: f64,
}

impl Default for ReadOffOptions {
    fn default() -> Self {
        ReadOffOptions {
            tolerance: 0.1,
            min_points: 3,
            regions: [None; 5],
            bound_confidence: super::bound::BOUND_CONFIDENCE,
        }
    }
}

/// Result of [`read_off`].
#[derive(Debug, Clone, PartialEq)]
pub struct ReadOff {
    /// One estimate per term in [`Term::ALL`] order.
    pub terms: Vec<TermEstimate>,
    /// Local log-log slope of σ at each point (NaN where σ = 0).
    pub local_slopes: Vec<f64>,
}

/// Local log-log slopes of the deviation.
pub fn local_slopes(taus: &[f64], variance: &[f64]) -> Vec<f64> {
    let n = taus.len();
    let ls: Vec<f64> = variance.iter().map(|v| 0.5 * v.ln()).collect();
    let lt: Vec<f64> = taus.iter().map(|t| t.ln()).collect();
    (0..n)
        .map(|i| {
            if n < 2 {
                return f64::NAN;
            }
            let (a, b) = if i == 0 {
                (0, 1)
            } else if i == n - 1 {
                (n - 2, n - 1)
            } else {
                (i - 1, i + 1)
            };
            let s = (ls[b] - ls[a]) / (lt[b] - lt[a]);
            if s.is_finite() { s } else { f64::NAN }
        })
        .collect()
}

/// Nearest model term to a local slope (decides the EDF formula when none is given).
fn term_of_slope(s: f64) -> Term {
    if s.is_nan() {
        return Term::AngleRandomWalk;
    }
    Term::ALL
        .into_iter()
        .min_by(|a, b| (a.slope() - s).abs().total_cmp(&(b.slope() - s).abs()))
        .unwrap_or(Term::AngleRandomWalk)
}

/// The longest run of indices satisfying `ok`; ties: wider τ span, then earlier.
fn longest_run(taus: &[f64], ok: impl Fn(usize) -> bool) -> Option<(usize, usize)> {
    let mut best: Option<(usize, usize)> = None;
    let mut start = None;
    for i in 0..=taus.len() {
        let inside = i < taus.len() && ok(i);
        match (inside, start) {
            (true, None) => start = Some(i),
            (false, Some(s)) => {
                let end = i - 1;
                let better = match best {
                    None => true,
                    Some((bs, be)) => {
                        let (len, blen) = (end - s, be - bs);
                        len > blen || (len == blen && taus[end] / taus[s] > taus[be] / taus[bs])
                    }
                };
                if better {
                    best = Some((s, end));
                }
                start = None;
            }
            _ => {}
        }
    }
    best
}

/// IEEE-952 read-off of the requested terms.
pub fn read_off(
    curve: &Curve<'_>,
    enabled: [bool; 5],
    options: &ReadOffOptions,
) -> Result<ReadOff> {
    curve.validate()?;
    if !(options.tolerance.is_finite() && options.tolerance > 0.0) {
        return Err(Error::invalid(
            "slope_tolerance",
            format!("must be finite and > 0, got {}", options.tolerance),
        ));
    }
    if options.min_points == 0 {
        return Err(Error::invalid("min_points", "must be >= 1"));
    }
    crate::validate::probability("bound_confidence", options.bound_confidence)?;
    let min_points = options.min_points;
    for (j, r) in options.regions.iter().enumerate() {
        if let Some((lo, hi)) = r {
            if lo.is_nan() || hi.is_nan() || hi < lo {
                return Err(Error::invalid(
                    "regions",
                    format!(
                        "range of {} must be (low, high) with low <= high, got ({lo}, {hi})",
                        Term::ALL[j].symbol()
                    ),
                ));
            }
        }
    }
    let taus = curve.taus;
    let var = curve.variance;
    let slopes = local_slopes(taus, var);
    let edf: Vec<f64> = (0..curve.len())
        .map(|i| curve.edf_at(i, term_of_slope(slopes[i])))
        .collect();
    let positive = |i: usize| var[i] > 0.0;

    let mut terms = Vec::with_capacity(5);
    for t in Term::ALL {
        let j = t.index();
        if !enabled[j] {
            terms.push(TermEstimate::missing(t, "not requested"));
            continue;
        }
        let region: Option<(usize, usize)> = match options.regions[j] {
            Some((lo, hi)) => {
                let inside: Vec<usize> = (0..curve.len())
                    .filter(|&i| taus[i] >= lo && taus[i] <= hi && positive(i))
                    .collect();
                if inside.is_empty() {
                    return Err(Error::invalid(
                        "regions",
                        format!(
                            "the range {lo}..{hi} s given for {} contains no τ of the curve",
                            t.symbol()
                        ),
                    ));
                }
                Some((inside[0], inside[inside.len() - 1]))
            }
            None => None,
        };
        if t == Term::BiasInstability {
            let (a, b) = region.unwrap_or((0, curve.len() - 1));
            // Automatic search: only estimates with EDF ≥ MIN_EDF_B; the longest-τ points rest
            // on one or two degrees of freedom and their minimum is noise.
            // Without identified EDFs the random-walk formula, the most pessimistic at long τ,
            // decides (a slope-based guess is unreliable exactly where it matters).
            let reliable = |i: usize| {
                let e = match curve.edf {
                    Some(_) => edf[i],
                    None => curve.edf_at(i, Term::RateRandomWalk),
                };
                e >= MIN_EDF_B
            };
            let eligible: Vec<usize> = (a..=b)
                .filter(|&i| positive(i) && (region.is_some() || reliable(i)))
                .collect();
            let i_min = eligible
                .iter()
                .copied()
                .min_by(|&p, &q| var[p].total_cmp(&var[q]));
            let Some(i_min) = i_min else {
                terms.push(TermEstimate::missing(
                    t,
                    if region.is_some() {
                        "σ is zero in the range given".to_string()
                    } else {
                        format!("no Allan estimate with EDF >= {MIN_EDF_B}")
                    },
                ));
                continue;
            };
            let first = eligible[0];
            let last = eligible[eligible.len() - 1];
            if region.is_none() && (i_min == first || i_min == last) {
                let which = if i_min == first {
                    "shortest τ: σ rises from the start"
                } else {
                    "longest reliable τ: σ is still falling"
                };
                terms.push(TermEstimate::missing(
                    t,
                    format!("the minimum of σ is at the {which}; there is no flat region"),
                ));
                continue;
            }
            // The flat region: contiguous points around the minimum with |slope| ≤ tolerance.
            let flat = |i: usize| slopes[i].abs() <= options.tolerance;
            let (mut lo, mut hi) = (i_min, i_min);
            while lo > a && flat(lo - 1) {
                lo -= 1;
            }
            while hi < b && flat(hi + 1) {
                hi += 1;
            }
            let sigma = var[i_min].sqrt();
            let value = sigma / FLICKER_FACTOR;
            terms.push(TermEstimate {
                term: t,
                value: Some(value),
                uncertainty: value / (2.0 * edf[i_min]).sqrt(),
                tau_range: Some((taus[lo], taus[hi])),
                marker: Some((taus[i_min], sigma)),
                missing: None,
                upper_bound: None,
            });
            continue;
        }
        let s = t.slope();
        let region = region.or_else(|| {
            longest_run(taus, |i| {
                positive(i) && (slopes[i] - s).abs() <= options.tolerance
            })
            .filter(|(a, b)| b - a + 1 >= min_points)
        });
        let Some((a, b)) = region else {
            terms.push(TermEstimate::missing(
                t,
                format!(
                    "no region of >= {min_points} consecutive τ with local slope {s:+} ± {}",
                    options.tolerance
                ),
            ));
            continue;
        };
        let idx: Vec<usize> = (a..=b).filter(|&i| positive(i)).collect();
        let w_sum: f64 = idx.iter().map(|&i| 2.0 * edf[i]).sum();
        let ln_c = idx
            .iter()
            .map(|&i| 2.0 * edf[i] * (0.5 * var[i].ln() - s * taus[i].ln()))
            .sum::<f64>()
            / w_sum;
        let rel = idx
            .iter()
            .map(|&i| 1.0 / (2.0 * edf[i]).sqrt())
            .fold(f64::INFINITY, f64::min);
        let read_tau = t.read_off_tau().unwrap_or(1.0);
        let value = (ln_c + s * read_tau.ln()).exp();
        terms.push(TermEstimate {
            term: t,
            value: Some(value),
            uncertainty: value * rel,
            tau_range: Some((taus[a], taus[b])),
            marker: Some((read_tau, value)),
            missing: None,
            upper_bound: None,
        });
    }
    // A requested term the read-off did not find is bounded from above by every point.
    let used: Vec<usize> = (0..curve.len()).filter(|&i| positive(i)).collect();
    let used_edf: Vec<f64> = used.iter().map(|&i| edf[i]).collect();
    super::bound::attach(
        &mut terms,
        enabled,
        curve,
        &used,
        &used_edf,
        options.bound_confidence,
    );
    Ok(ReadOff {
        terms,
        local_slopes: slopes,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::noise::model::model_variance;

    fn curve_of(
        c: &[f64; 5],
        n: usize,
        t0: f64,
        k: u32,
    ) -> (Vec<f64>, Vec<f64>, Vec<usize>, Vec<usize>) {
        let m: Vec<usize> = (0..k).map(|i| 1usize << i).collect();
        let taus: Vec<f64> = m.iter().map(|&m| m as f64 * t0).collect();
        let var = taus.iter().map(|t| model_variance(c, *t)).collect();
        let terms = m.iter().map(|&m| n + 1 - 2 * m).collect();
        (taus, var, m, terms)
    }

    #[test]
    fn pure_power_laws_are_read_exactly() {
        for (j, c) in [(1usize, 4e-6), (3, 1e-9)] {
            let mut sq = [0.0; 5];
            sq[j] = c;
            let (taus, var, m, terms) = curve_of(&sq, 1_000_000, 0.01, 18);
            let curve = Curve {
                taus: &taus,
                variance: &var,
                m: &m,
                n_terms: &terms,
                overlapping: true,
                edf: None,
            };
            let r = read_off(&curve, [true; 5], &ReadOffOptions::default()).unwrap();
            let got = r.terms[j].value.unwrap();
            assert!((got - c.sqrt()).abs() < 1e-12 * c.sqrt(), "{j}: {got}");
            assert!(
                r.terms[2].missing.is_some(),
                "no minimum inside a power law"
            );
        }
    }

    #[test]
    fn zero_min_points_is_a_named_error() {
        let (taus, var, m, terms) = curve_of(&[0.0, 1e-6, 0.0, 0.0, 0.0], 100_000, 0.01, 10);
        let curve = Curve {
            taus: &taus,
            variance: &var,
            m: &m,
            n_terms: &terms,
            overlapping: true,
            edf: None,
        };
        let options = ReadOffOptions {
            min_points: 0,
            ..ReadOffOptions::default()
        };
        let err = read_off(&curve, [true; 5], &options)
            .unwrap_err()
            .to_string();
        assert!(err.contains("min_points"), "{err}");
    }

    #[test]
    fn bias_instability_from_minimum_and_override() {
        let sq = [0.0, 1e-6, 1e-8, 1e-11, 0.0];
        let (taus, var, m, terms) = curve_of(&sq, 10_000_000, 0.01, 22);
        let curve = Curve {
            taus: &taus,
            variance: &var,
            m: &m,
            n_terms: &terms,
            overlapping: true,
            edf: None,
        };
        let r = read_off(&curve, [true; 5], &ReadOffOptions::default()).unwrap();
        let b = r.terms[2].value.unwrap();
        let min = var.iter().copied().fold(f64::INFINITY, f64::min).sqrt();
        assert!((b - min / FLICKER_FACTOR).abs() < 1e-15 * b);
        assert!(b > 1e-4, "read-off B is biased high by the neighbours");
        let mut opts = ReadOffOptions::default();
        opts.regions[1] = Some((0.01, 0.1));
        let r = read_off(&curve, [true; 5], &opts).unwrap();
        assert_eq!(r.terms[1].tau_range, Some((0.01, 0.08)));
        opts.regions[1] = Some((1e6, 1e7));
        assert!(read_off(&curve, [true; 5], &opts).is_err());
    }
}
