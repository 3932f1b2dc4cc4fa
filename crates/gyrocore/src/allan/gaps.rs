//! Gap-aware Allan-family variances: NaN marks a missing sample.
//!
//! Missing samples are not contiguous samples: joining the pieces of a record as if nothing
//! had been lost puts a step (the drift of the missing stretch) into the data. Here the record
//! is cut at every NaN into gap-free **segments** and every term of an estimator whose span
//! touches a gap is left out:
//!
//! * rate input `Ω`: a segment of rate samples `[s, e)` gives the angle samples `x_s..x_e`
//!   (integrated mean-removed rate, SPEC §2, per segment — the second and third differences
//!   cancel the segment's own mean exactly); a term is kept when every rate sample it spans
//!   lies in one segment;
//! * angle input `x`: a segment is a run of finite phase samples, and a term is kept when
//!   every phase sample it spans lies in one segment.
//!
//! With `S_j(m)` and `n_j(m)` the raw sum of squared differences and the number of terms of
//! segment `j`,
//!
//! ```text
//! σ²(τ) = Σ_j S_j(m) / (c · τ² · Σ_j n_j(m)),   n_terms = Σ_j n_j(m)
//! ```
//!
//! (`c` = 2 for the Allan variances, `2m²` modified, 6 Hadamard). This is the overlapping,
//! modified and Hadamard estimator restricted to the terms that do not touch a gap (NIST
//! SP1065 §5.2 defines the terms; this only removes some). The non-overlapping Allan variance
//! keeps its global grid `k = 0, m, 2m, …` and drops the grid terms that touch a gap. The
//! **total variance is not defined** here: it extends the record by reflection at its two ends,
//! and a record with gaps has no single pair of ends ([`super::Config::validate`] says so).
//!
//! **Confidence intervals.** Segments are treated as independent records of the same noise:
//! segment `j` has the EDF `ν_j` of its own length (Greenhall's algorithm, [`super::edf`]), and
//! the pooled estimate `Σ n_j σ̂_j² / Σ n_j` gets Satterthwaite's EDF
//!
//! ```text
//! ν = (Σ_j n_j)² / Σ_j (n_j² / ν_j)
//! ```
//!
//! (F. E. Satterthwaite, "An approximate distribution of estimates of variance components",
//! Biometrics Bulletin 2 (1946), for a weighted sum of independent scaled chi-squares). The
//! noise type is identified on the longest segment (lag-1 autocorrelation, [`super::noise_id`]).
//! τ is limited by the longest segment: a factor with no term in any segment is beyond the data.
//!
//! **Memory.** The segments are analysed one after the other in one buffer (the workspace's
//! angle buffer, sized for the longest segment): a record with gaps costs at most one working
//! copy of its longest gap-free stretch per column being analysed, never a copy of the column.

use super::{
    AllanAnalysis, Column, Config, DataType, Estimator, Moments, Progress, Taus, WORK_CONFIDENCE,
    WORK_VARIANCES, Workspace, angle_pass, confidence, edf, integrate_rate_into, normalise,
    period_correction, pow2, raw_sums, resolve_factors, scale_exponent, split_period, sum_squares,
    unscale,
};
use crate::{Error, Result};

/// Maximal runs `[s, e)` of non-NaN samples.
pub fn segments(column: Column<'_>) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut start: Option<usize> = None;
    for (i, v) in column.iter().enumerate() {
        match (v.is_nan(), start) {
            (true, Some(s)) => {
                out.push((s, i));
                start = None;
            }
            (false, None) => start = Some(i),
            _ => {}
        }
    }
    if let Some(s) = start {
        out.push((s, column.len()));
    }
    out
}

/// Number of non-overlapping terms on the global grid (see [`non_overlapping_sum`]) in a
/// segment of `len` angle samples whose first one has global index `first_global`.
fn non_overlapping_count(len: usize, m: usize, first_global: usize) -> usize {
    let first = first_global.div_ceil(m) * m - first_global;
    if len < first + 2 * m + 1 {
        0
    } else {
        (len - 1 - first - 2 * m) / m + 1
    }
}

/// Non-overlapping sum on the global grid: terms at global angle index `k ≡ 0 (mod m)` inside
/// the segment whose first angle sample has global index `first_global`.
fn non_overlapping_sum(x: &[f64], m: usize, first_global: usize) -> (f64, usize) {
    let first = first_global.div_ceil(m) * m - first_global;
    let len = x.len();
    let count = non_overlapping_count(len, m, first_global);
    if count == 0 {
        return (0.0, 0);
    }
    let sum = sum_squares(count, |i| {
        let k = first + i * m;
        x[k + 2 * m] - 2.0 * x[k + m] + x[k]
    });
    (sum, count)
}

/// One pass over the column: the gap-free segments (as [`segments`]), the largest finite
/// magnitude, and an error at the first infinite value.
///
/// Blocks of [`SCAN_BLOCK`] samples are read once for their magnitudes (in lanes; NaN never
/// wins a comparison, so it is skipped) and whether all are finite; only a block that holds a
/// NaN or an infinity is walked sample by sample for the segment ends.
fn scan(column: Column<'_>) -> Result<(Vec<(usize, usize)>, f64)> {
    const LANES: usize = 8;
    let n = column.len();
    let mut out = Vec::new();
    let mut start: Option<usize> = Some(0);
    let mut peaks = [0.0_f64; LANES];
    let mut b0 = 0;
    while b0 < n {
        let b1 = (b0 + SCAN_BLOCK).min(n);
        let mut finite = [true; LANES];
        let mut i = b0;
        while i + LANES <= b1 {
            for l in 0..LANES {
                let a = column.get(i + l).abs();
                peaks[l] = if a > peaks[l] { a } else { peaks[l] };
                finite[l] &= a < f64::INFINITY;
            }
            i += LANES;
        }
        for j in i..b1 {
            let a = column.get(j).abs();
            peaks[0] = if a > peaks[0] { a } else { peaks[0] };
            finite[0] &= a < f64::INFINITY;
        }
        if finite.iter().any(|&f| !f) {
            for j in b0..b1 {
                let v = column.get(j);
                if v.is_nan() {
                    if let Some(s) = start.take() {
                        if s < j {
                            out.push((s, j));
                        }
                    }
                } else if v.is_infinite() {
                    return Err(Error::NonFinite {
                        name: "data",
                        index: j,
                    });
                } else if start.is_none() {
                    start = Some(j);
                }
            }
            // A segment may start with the next (unwalked) block; an empty one is dropped.
            start.get_or_insert(b1);
        }
        b0 = b1;
    }
    if let Some(s) = start {
        if s < n {
            out.push((s, n));
        }
    }
    Ok((out, peaks.iter().fold(0.0_f64, |p, &q| p.max(q))))
}

/// Samples per block of [`scan`].
const SCAN_BLOCK: usize = 256;

/// Gap-aware analysis of a column that contains NaN (see the module docs).
///
/// The segments are processed one at a time in the workspace's angle buffer (one segment's
/// angle series, at most the longest segment plus one sample): the raw sums of each, and the
/// noise identification on the longest one while it is in the buffer. The term counts, hence
/// the factors kept, are known from the segments' lengths before any data are read.
pub(crate) fn analyse(
    column: Column<'_>,
    config: &Config,
    workspace: &mut Workspace,
    progress: &Progress<'_>,
) -> Result<AllanAnalysis> {
    let estimator = config.estimator;
    let (segs, peak) = scan(column)?;
    let longest = segs
        .iter()
        .enumerate()
        .max_by_key(|&(i, &(s, e))| (e - s, std::cmp::Reverse(i)))
        .map(|(i, _)| i);
    let Some(longest) = longest else {
        return Err(Error::invalid("data", "every sample is NaN (a gap)"));
    };
    let (ls, le) = segs[longest];
    let mut ms = resolve_factors(
        &config.taus,
        le - ls,
        config.t0,
        config.data_type,
        estimator,
    )
    .map_err(|e| match e {
        Error::TooShort { needed, got, .. } => Error::invalid(
            "data",
            format!(
                "the longest gap-free stretch has {got} samples (rows {ls}..{le}), \
                     {needed} needed"
            ),
        ),
        other => other,
    })?;

    // One scale for the whole record (segments' sums are added): the largest finite magnitude.
    let k = scale_exponent(peak);
    let factor = pow2(-k);
    // An extreme period is computed as t0'·2^e (see `split_period`); τ were resolved above with
    // the period itself.
    let (t0, period_exponent) = split_period(config.t0);
    // Length of each segment's angle series: N + 1 integrated rate samples, or the N angles.
    let extra = usize::from(config.data_type == DataType::Rate);
    let lens: Vec<usize> = segs.iter().map(|&(s, e)| e - s + extra).collect();

    // Term counts per factor and segment (from the lengths alone).
    let fits = |len: usize, m: usize| {
        estimator == Estimator::NonOverlapping || m <= estimator.max_factor(len)
    };
    let count = |m: usize, len: usize, s: usize| -> usize {
        if estimator == Estimator::NonOverlapping {
            non_overlapping_count(len, m, s)
        } else if fits(len, m) {
            estimator.n_terms(len, m)
        } else {
            0
        }
    };
    let mut terms: Vec<Vec<usize>> = ms
        .iter()
        .map(|&m| {
            lens.iter()
                .zip(&segs)
                .map(|(&len, &(s, _))| count(m, len, s))
                .collect()
        })
        .collect();
    let mut n_terms: Vec<usize> = terms.iter().map(|t| t.iter().sum()).collect();
    if let Some(j) = n_terms.iter().position(|&t| t == 0) {
        // Only the non-overlapping grid can miss every segment below the longest one's limit.
        if matches!(config.taus, Taus::Explicit(_)) {
            return Err(Error::invalid(
                "taus",
                format!(
                    "τ = {} s has no term that avoids the gaps",
                    ms[j] as f64 * config.t0
                ),
            ));
        }
        let keep: Vec<bool> = n_terms.iter().map(|&t| t > 0).collect();
        let mut it = keep.iter();
        ms.retain(|_| *it.next().unwrap_or(&false));
        let mut it = keep.iter();
        terms.retain(|_| *it.next().unwrap_or(&false));
        n_terms.retain(|&t| t > 0);
        if ms.is_empty() {
            return Err(Error::invalid(
                "data",
                "no τ has a term that avoids the gaps",
            ));
        }
    }

    // Raw sums per segment and factor, one segment's angle series at a time.
    let buffer = &mut workspace.angle;
    if buffer.capacity() < lens[longest] {
        // Sized once for the longest segment (not grown segment by segment).
        *buffer = Vec::with_capacity(lens[longest]);
    }
    let mut sums: Vec<Vec<f64>> = vec![Vec::with_capacity(segs.len()); ms.len()];
    // The data's variance over the samples present: each segment's moments (of the rate; of
    // the rate differences inside the segment for angle input), combined.
    let mut moments = Moments::default();
    let mut alpha = None;
    for (i, &(s, e)) in segs.iter().enumerate() {
        let part = column.sub(s, e);
        match config.data_type {
            DataType::Rate => {
                let (_, m) = integrate_rate_into(part, t0, buffer, &Progress::none(), Some(k))?;
                moments = moments.combine(m);
            }
            DataType::Angle => {
                moments = moments.combine(angle_pass(part, factor, t0).2);
                buffer.clear();
                buffer.extend(part.iter().map(|v| v * factor));
            }
        }
        let x = &buffer[..];
        let weight = WORK_VARIANCES * x.len() as f64;
        if estimator == Estimator::NonOverlapping {
            for (j, &m) in ms.iter().enumerate() {
                sums[j].push(non_overlapping_sum(x, m, s).0);
            }
            progress.advance(weight);
        } else {
            let fit: Vec<usize> = ms.iter().copied().filter(|&m| fits(x.len(), m)).collect();
            let seg_sums = if fit.is_empty() {
                progress.advance(weight);
                Vec::new()
            } else {
                raw_sums(x, &fit, estimator, progress, weight)?
            };
            let mut it = seg_sums.into_iter();
            for (j, &m) in ms.iter().enumerate() {
                sums[j].push(if fits(x.len(), m) {
                    it.next().unwrap_or(0.0)
                } else {
                    0.0
                });
            }
        }
        if i == longest && config.confidence.is_some() {
            // The noise type, identified on the longest segment (module docs).
            alpha = Some(confidence::alphas(x, estimator, &ms));
        }
    }
    progress.check()?;
    let variance: Vec<f64> = ms
        .iter()
        .zip(&sums)
        .zip(&n_terms)
        .map(|((&m, s), &t)| {
            let total = crate::validate::neumaier_sum(s.iter().copied());
            normalise(estimator, total, m, t0, t)
        })
        .collect();

    let n_total = column.len() as f64;
    let confidence = match (config.confidence, alpha) {
        (Some(level), Some(alpha)) => {
            let mut out = confidence::Intervals {
                alpha,
                edf: Vec::with_capacity(ms.len()),
                low: Vec::with_capacity(ms.len()),
                high: Vec::with_capacity(ms.len()),
            };
            // Segments of equal length have equal EDF: each computed once per τ.
            let mut nus: std::collections::HashMap<usize, f64> = std::collections::HashMap::new();
            for (j, &m) in ms.iter().enumerate() {
                nus.clear();
                let mut denominator = 0.0;
                for (&t, &len) in terms[j].iter().zip(&lens) {
                    if t > 0 {
                        let nu = if let Some(&nu) = nus.get(&len) {
                            nu
                        } else {
                            let nu = edf::edf(estimator, out.alpha[j], m, len)?;
                            nus.insert(len, nu);
                            nu
                        };
                        let t = t as f64;
                        denominator += t * t / nu;
                    }
                }
                let count = n_terms[j] as f64;
                let nu = count * count / denominator;
                let (lo, hi) = confidence::chi2_bounds(variance[j], nu, level)?;
                out.edf.push(nu);
                out.low.push(lo);
                out.high.push(hi);
            }
            progress.advance(WORK_CONFIDENCE * n_total);
            Some(out)
        }
        _ => None,
    };
    let k = k + period_correction(config.data_type, period_exponent, false);
    Ok(unscale(ms, &variance, n_terms, confidence, k, &moments))
}

#[cfg(test)]
mod tests {
    use super::super::{Gaps, TauSpec, analyse_column};
    use super::*;

    fn noise(n: usize, seed: u64) -> Vec<f64> {
        // Normal noise from the core's seeded generator (one PRNG for every test).
        crate::random::normal_vec(n, seed)
    }

    fn config(estimator: Estimator, data_type: DataType) -> Config {
        Config {
            t0: 0.5,
            data_type,
            estimator,
            taus: Taus::Spec(TauSpec::All),
            confidence: Some(0.683),
            gaps: Gaps::Omit,
        }
    }

    /// Direct definition: every term whose span is gap-free, from the rate.
    fn direct_rate(rate: &[f64], m: usize, t0: f64, estimator: Estimator) -> (f64, usize) {
        let n = rate.len();
        let ok = |a: usize, b: usize| rate[a..b].iter().all(|v| !v.is_nan());
        let mean = |a: usize| rate[a..a + m].iter().sum::<f64>() / m as f64;
        let (mut s, mut count) = (0.0, 0usize);
        let tau = m as f64 * t0;
        match estimator {
            Estimator::Overlapping | Estimator::NonOverlapping => {
                let step = if estimator == Estimator::Overlapping {
                    1
                } else {
                    m
                };
                let mut k = 0;
                while k + 2 * m <= n {
                    if ok(k, k + 2 * m) {
                        s += (mean(k + m) - mean(k)).powi(2) * tau * tau;
                        count += 1;
                    }
                    k += step;
                }
                (s / (2.0 * tau * tau * count as f64), count)
            }
            Estimator::Hadamard => {
                for k in 0..=(n.saturating_sub(3 * m)) {
                    if k + 3 * m <= n && ok(k, k + 3 * m) {
                        let d = mean(k + 2 * m) - 2.0 * mean(k + m) + mean(k);
                        s += d * d * tau * tau;
                        count += 1;
                    }
                }
                (s / (6.0 * tau * tau * count as f64), count)
            }
            _ => unreachable!(),
        }
    }

    #[test]
    fn gapped_rate_equals_direct_definition() {
        let mut rate = noise(400, 9);
        for i in (57..63).chain(200..201).chain(330..345) {
            rate[i] = f64::NAN;
        }
        for estimator in [
            Estimator::Overlapping,
            Estimator::NonOverlapping,
            Estimator::Hadamard,
        ] {
            let cfg = config(estimator, DataType::Rate);
            let r = analyse_column(
                Column::contiguous(&rate),
                &cfg,
                &mut Workspace::new(),
                &Progress::none(),
            )
            .unwrap();
            for (j, &m) in r.m.iter().enumerate() {
                let (v, count) = direct_rate(&rate, m, 0.5, estimator);
                assert_eq!(r.n_terms[j], count, "{estimator:?} m={m}");
                assert!(
                    (r.variance[j] - v).abs() <= 1e-12 * v,
                    "{estimator:?} m={m}: {} vs {v}",
                    r.variance[j]
                );
                let ci = r.confidence.as_ref().unwrap();
                assert!(ci.low[j] <= r.variance[j] && r.variance[j] <= ci.high[j]);
            }
        }
    }

    #[test]
    fn scan_equals_segments_and_peak() {
        let mut x = noise(2_000, 4);
        for i in [0usize, 1, 7, 255, 256, 257, 511, 1_000, 1_001, 1_999] {
            x[i] = f64::NAN;
        }
        x[600] = -9.5;
        let (segs, peak) = scan(Column::contiguous(&x)).unwrap();
        assert_eq!(segs, segments(Column::contiguous(&x)));
        assert_eq!(peak, 9.5);
        // A strided column (the matrix path) and an infinity after a NaN.
        let matrix: Vec<f64> = x.iter().flat_map(|&v| [v, 1.0, 2.0]).collect();
        let column = Column::of(&matrix, 3, 0).unwrap();
        assert_eq!(scan(column).unwrap().0, segs);
        x[1_500] = f64::NEG_INFINITY;
        assert_eq!(
            scan(Column::contiguous(&x)).unwrap_err(),
            Error::NonFinite {
                name: "data",
                index: 1_500
            }
        );
    }

    #[test]
    fn one_segment_edf_is_the_plain_edf() {
        // A NaN at the very end leaves one segment: Satterthwaite's EDF reduces to ν.
        let mut rate = noise(3000, 2);
        let plain = analyse_column(
            Column::contiguous(&rate[..2999]),
            &config(Estimator::Overlapping, DataType::Rate),
            &mut Workspace::new(),
            &Progress::none(),
        )
        .unwrap();
        rate[2999] = f64::NAN;
        let gapped = analyse_column(
            Column::contiguous(&rate),
            &config(Estimator::Overlapping, DataType::Rate),
            &mut Workspace::new(),
            &Progress::none(),
        )
        .unwrap();
        assert_eq!(plain.m, gapped.m);
        assert_eq!(plain.n_terms, gapped.n_terms);
        let (a, b) = (plain.confidence.unwrap(), gapped.confidence.unwrap());
        assert_eq!(a.alpha, b.alpha);
        for j in 0..plain.m.len() {
            assert!((a.edf[j] / b.edf[j] - 1.0).abs() < 1e-12);
            assert!((plain.variance[j] / gapped.variance[j] - 1.0).abs() < 1e-12);
        }
    }

    #[test]
    fn bad_gaps() {
        let mut rate = noise(100, 1);
        rate[5] = f64::INFINITY;
        rate[3] = f64::NAN;
        let cfg = config(Estimator::Overlapping, DataType::Rate);
        let err = analyse_column(
            Column::contiguous(&rate),
            &cfg,
            &mut Workspace::new(),
            &Progress::none(),
        )
        .unwrap_err();
        assert_eq!(
            err,
            Error::NonFinite {
                name: "data",
                index: 5
            }
        );
        let all_nan = vec![f64::NAN; 10];
        assert!(
            analyse_column(
                Column::contiguous(&all_nan),
                &cfg,
                &mut Workspace::new(),
                &Progress::none()
            )
            .is_err()
        );
        let mut total = config(Estimator::Total, DataType::Rate);
        total.gaps = Gaps::Omit;
        assert!(total.validate().is_err());
    }

    #[test]
    fn extreme_periods_give_the_ordinary_result() {
        // t0 = 1.25·2^±950 is computed with t0' = 1.25: rate variances (and their intervals)
        // equal those at t0 = 1.25 bit for bit; angle variances (at 2^±300, where
        // they are representable) differ by exactly 4^∓300.
        let mut rate = noise(400, 7);
        rate[100] = f64::NAN;
        rate[257] = f64::NAN;
        let run = |t0: f64, data_type: DataType| {
            let cfg = Config {
                t0,
                ..config(Estimator::Overlapping, data_type)
            };
            analyse_column(
                Column::contiguous(&rate),
                &cfg,
                &mut Workspace::new(),
                &Progress::none(),
            )
            .unwrap()
        };
        let base = run(1.25, DataType::Rate);
        let base_angle = run(1.25, DataType::Angle);
        for e in [-950, 950] {
            let t0 = super::super::ldexp(1.25, e);
            let r = run(t0, DataType::Rate);
            assert_eq!(r.variance, base.variance);
            assert_eq!(
                r.confidence.unwrap().high,
                base.confidence.as_ref().unwrap().high
            );
        }
        for e in [-300, 300] {
            let t0 = super::super::ldexp(1.25, e);
            let a = run(t0, DataType::Angle);
            for (x, y) in a.variance.iter().zip(&base_angle.variance) {
                assert!(x.is_finite() && *x > 0.0);
                assert_eq!(*x, super::super::ldexp(*y, -2 * e));
            }
        }
    }
}
