//! Frozen copy of [`super::analyse`] as it was before the one-buffer rewrite (issue 35,
//! commit 9b2f450; the concatenated segments buffer is passed in instead of living in the
//! workspace): the reference of the randomized old-versus-new equality test of the gap-aware
//! analysis. Compiled for the tests only; do not change it.

use super::super::{
    AllanAnalysis, Column, Config, DataType, Estimator, Moments, Progress, Taus, WORK_CONFIDENCE,
    WORK_VARIANCES, Workspace, angle_pass, confidence, edf, integrate_rate_into, normalise,
    period_correction, pow2, raw_sums, resolve_factors, scale_exponent, split_period, unscale,
};
use super::non_overlapping_sum;
use crate::{Error, Result};

/// Gap-aware analysis of a column that contains NaN (see the module docs).
pub(super) fn analyse(
    column: Column<'_>,
    config: &Config,
    workspace: &mut Workspace,
    segments_buffer: &mut Vec<f64>,
    progress: &Progress<'_>,
) -> Result<AllanAnalysis> {
    if let Some(index) = column.iter().position(f64::is_infinite) {
        return Err(Error::NonFinite {
            name: "data",
            index,
        });
    }
    let estimator = config.estimator;
    let segs = super::segments(column);
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
    let peak = column
        .iter()
        .filter(|v| !v.is_nan())
        .fold(0.0_f64, |p, v| p.max(v.abs()));
    let k = scale_exponent(peak);
    let factor = pow2(-k);
    // An extreme period is computed as t0'·2^e (see `split_period`); τ were resolved above with
    // the period itself.
    let (t0, period_exponent) = split_period(config.t0);
    // Angle series of every segment (data scaled by 2^-k), concatenated in the workspace.
    let buffer = segments_buffer;
    buffer.clear();
    let mut ranges = Vec::with_capacity(segs.len());
    // The data's variance over the samples present: each segment's moments (of the rate; of
    // the rate differences inside the segment for angle input), combined.
    let mut moments = Moments::default();
    for &(s, e) in &segs {
        let start = buffer.len();
        let part = column.sub(s, e);
        match config.data_type {
            DataType::Rate => {
                let (_, m) = integrate_rate_into(
                    part,
                    t0,
                    &mut workspace.angle,
                    &Progress::none(),
                    Some(k),
                )?;
                moments = moments.combine(m);
                buffer.extend_from_slice(&workspace.angle);
            }
            DataType::Angle => {
                moments = moments.combine(angle_pass(part, factor, t0).2);
                buffer.extend(part.iter().map(|v| v * factor));
            }
        }
        ranges.push((start, buffer.len()));
    }
    let n_total = column.len() as f64;

    // Raw sums and term counts per segment and factor.
    let mut sums: Vec<Vec<f64>> = vec![Vec::with_capacity(segs.len()); ms.len()];
    let mut terms: Vec<Vec<usize>> = vec![Vec::with_capacity(segs.len()); ms.len()];
    for (&(a, b), &(s, _)) in ranges.iter().zip(&segs) {
        let x = &buffer[a..b];
        let weight = WORK_VARIANCES * x.len() as f64;
        if estimator == Estimator::NonOverlapping {
            for (j, &m) in ms.iter().enumerate() {
                let (sum, count) = non_overlapping_sum(x, m, s);
                sums[j].push(sum);
                terms[j].push(count);
            }
            progress.advance(weight);
            continue;
        }
        let max_m = estimator.max_factor(x.len());
        let fit: Vec<usize> = ms.iter().copied().filter(|&m| m <= max_m).collect();
        let seg_sums = if fit.is_empty() {
            progress.advance(weight);
            Vec::new()
        } else {
            raw_sums(x, &fit, estimator, progress, weight)?
        };
        let mut it = seg_sums.into_iter();
        for (j, &m) in ms.iter().enumerate() {
            if m <= max_m {
                sums[j].push(it.next().unwrap_or(0.0));
                terms[j].push(estimator.n_terms(x.len(), m));
            } else {
                sums[j].push(0.0);
                terms[j].push(0);
            }
        }
    }
    progress.check()?;
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
        sums.retain(|_| *it.next().unwrap_or(&false));
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
    let variance: Vec<f64> = ms
        .iter()
        .zip(&sums)
        .zip(&n_terms)
        .map(|((&m, s), &t)| {
            let total = crate::validate::neumaier_sum(s.iter().copied());
            normalise(estimator, total, m, t0, t)
        })
        .collect();

    let confidence = match config.confidence {
        Some(level) => {
            let (a, b) = ranges[longest];
            let alpha = confidence::alphas(&buffer[a..b], estimator, &ms);
            let mut out = confidence::Intervals {
                alpha,
                edf: Vec::with_capacity(ms.len()),
                low: Vec::with_capacity(ms.len()),
                high: Vec::with_capacity(ms.len()),
            };
            for (j, &m) in ms.iter().enumerate() {
                let mut denominator = 0.0;
                for (k, &t) in terms[j].iter().enumerate() {
                    if t > 0 {
                        let (a, b) = ranges[k];
                        let nu = edf::edf(estimator, out.alpha[j], m, b - a)?;
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
        None => None,
    };
    let k = k + period_correction(config.data_type, period_exponent, false);
    Ok(unscale(ms, &variance, n_terms, confidence, k, &moments))
}
