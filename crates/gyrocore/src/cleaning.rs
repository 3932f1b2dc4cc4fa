//! Cleaning a log before its stability analysis: Stable32's *Outliers* and *Drift* steps, and
//! the min/max envelope that draws a long log.
//!
//! Every routine takes a row-major `(n, k)` matrix (`n` samples of `k` channels, the layout of
//! a NumPy `(n, k)` C-order array) and treats each channel on its own. **NaN marks a missing
//! sample** (a gap, e.g. from `io.load(fill_gaps=True)` or from an earlier outlier removal): it
//! is skipped by every statistic here and stays NaN in every output.
//!
//! **Outliers** ([`remove_outliers`]): per channel, with `m` the median and `s` the scaled
//! median absolute deviation of the finite samples,
//!
//! ```text
//! m = median(x),   s = 1.482602·median|x − m|            (MAD scaled to a normal s.d.)
//! z_i = |x_i − m| / s,   sample i is an outlier when z_i > threshold
//! ```
//!
//! the robust z-score of Stable32's outlier recognition (W. Riley, *Handbook of Frequency
//! Stability Analysis*, NIST SP 1065 (2008), §6.2 "Data Preprocessing"/"Outlier recognition":
//! "a robust way to identify outliers is by the median absolute deviation (MAD)"). When more
//! than half of a channel's finite samples equal the median (coarse quantisation), the MAD is
//! 0; `s` then falls back to `1.253314·mean|x − m|` (the mean absolute deviation scaled to a
//! normal s.d., Iglewicz & Hoaglin 1993), and when that is 0 too (a constant channel) nothing
//! is flagged. An infinite sample has an infinite z-score (always flagged). Flagged samples become NaN in the
//! output, which the Allan functions skip with `gaps = omit`.
//!
//! **Drift** ([`detrend`]): per channel, the least-squares polynomial of degree `order` (1 or
//! 2) in time `t_i = i·t0` (seconds from the first sample) over the finite samples is removed.
//! For numerical stability the fit is made in the Legendre basis of the scaled time
//! `u = 2i/(n − 1) − 1 ∈ [−1, 1]` (`P0 = 1, P1 = u, P2 = (3u² − 1)/2`; the Gram matrix of a
//! uniform grid is close to `diag(1, 1/3, 1/5)·n`, condition number ≈ 5 whatever `n` and `t0`),
//! with each channel's values taken relative to its first finite sample and the sums formed
//! in fixed blocks of rows (so the result is the same for any number of threads). The
//! coefficients are reported in the monomial form `c0 + c1·t + c2·t²` (units: rate, rate/s,
//! rate/s²).
//!
//! **Envelope** ([`minmax_envelope`]): the rows are cut into `bins` consecutive bins, bin `b`
//! holding rows `⌊b·n/bins⌋ .. ⌊(b + 1)·n/bins⌋`, and each bin's minimum and maximum of each
//! channel (NaN ignored; NaN for a bin without a value) are returned: one pass over the data,
//! the bins in parallel.

use rayon::prelude::*;

use crate::fleet::MAD_TO_SD;
use crate::stats;
use crate::validate;
use crate::{Error, Result};

/// `√(π/2)`: the mean absolute deviation of a normal sample times this estimates its s.d.
pub const MEAN_AD_TO_SD: f64 = 1.253_314_137_315_500_3;

/// A column's index and its (center, scale), or why it has none.
type ColumnStats = (usize, Result<(f64, f64)>);

/// Fewest finite samples per channel for an outlier test.
pub const MIN_OUTLIER_SAMPLES: usize = 3;

/// Rows summed together before the block sums are added (fixed, so the sums do not depend
/// on the number of threads).
const BLOCK_ROWS: usize = 8192;

/// The outlier statistics of one channel (see [`remove_outliers`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OutlierStats {
    /// Median of the channel's finite samples.
    pub center: f64,
    /// Scale `s` of the robust z-score (module docs).
    pub scale: f64,
    /// Samples flagged as outliers.
    pub count: usize,
}

/// The output of [`remove_outliers`].
#[derive(Debug, Clone, PartialEq)]
pub struct Outliers {
    /// The data with every outlier replaced by NaN, row-major `(n, k)`.
    pub data: Vec<f64>,
    /// `true` where a sample was flagged, row-major `(n, k)`.
    pub mask: Vec<bool>,
    /// One entry per channel.
    pub channels: Vec<OutlierStats>,
}

/// The output of [`remove_outliers_in_place`] and [`remove_outliers_into`] (the data is the
/// caller's buffer).
#[derive(Debug, Clone, PartialEq)]
pub struct OutliersFlagged {
    /// `true` where a sample was flagged, row-major `(n, k)`.
    pub mask: Vec<bool>,
    /// One entry per channel.
    pub channels: Vec<OutlierStats>,
    /// NaN samples in the output (the gaps given plus the outliers flagged): whether the
    /// Allan functions need `gaps = omit`, without a scan of the data.
    pub gaps: usize,
}

/// The output of [`detrend`].
#[derive(Debug, Clone, PartialEq)]
pub struct Detrended {
    /// The residual after removing each channel's polynomial, row-major `(n, k)`.
    pub data: Vec<f64>,
    /// Per channel, `order + 1` monomial coefficients `c0, c1[, c2]` of `t` in seconds from the
    /// first sample, row-major `(k, order + 1)`.
    pub coefficients: Vec<f64>,
}

/// The output of [`minmax_envelope`].
#[derive(Debug, Clone, PartialEq)]
pub struct Envelope {
    /// Per bin, the minimum of each channel, row-major `(bins, k)`.
    pub lower: Vec<f64>,
    /// Per bin, the maximum of each channel, row-major `(bins, k)`.
    pub upper: Vec<f64>,
    /// First row of each bin and, last, `n`: `bins + 1` entries.
    pub starts: Vec<usize>,
}

/// Checks `(n, k)` and returns `n`.
fn rows(data: &[f64], n_cols: usize) -> Result<usize> {
    if n_cols == 0 {
        return Err(Error::invalid(
            "data",
            "must have at least one column, got 0",
        ));
    }
    if data.len() % n_cols != 0 {
        return Err(Error::ShapeMismatch {
            name: "data",
            reason: format!("{} values are not rows of {n_cols} columns", data.len()),
        });
    }
    Ok(data.len() / n_cols)
}

/// The finite samples of column `j` (rows of `n_cols`), copied into `out` (reused).
fn finite_column_into(data: &[f64], n_cols: usize, j: usize, out: &mut Vec<f64>) {
    out.clear();
    out.extend(
        data.iter()
            .skip(j)
            .step_by(n_cols)
            .copied()
            .filter(|v| v.is_finite()),
    );
}

/// Median and robust scale of the finite values in `values` (reordered; module docs).
fn robust_center_scale(values: &mut [f64]) -> (f64, f64) {
    let center = stats::median_in_place(values);
    for v in values.iter_mut() {
        *v = (*v - center).abs();
    }
    let mean_ad = validate::neumaier_sum(values.iter().copied()) / values.len() as f64;
    let mad = stats::median_in_place(values);
    let scale = if mad > 0.0 {
        MAD_TO_SD * mad
    } else {
        MEAN_AD_TO_SD * mean_ad
    };
    (center, scale)
}

/// Flags and removes the outliers of every channel by their robust z-score (module docs).
///
/// `data` is row-major `(n, n_cols)`; NaN samples are gaps (skipped, kept, never flagged);
/// `threshold` is finite and > 0.
///
/// # Errors
/// `n_cols` of 0 or not dividing `data.len()`; `threshold` not finite and > 0 ([`Error::InvalidParameter`]
/// naming `threshold`); fewer than [`MIN_OUTLIER_SAMPLES`] rows ([`Error::TooShort`]) or a
/// channel with fewer finite samples ([`Error::InvalidParameter`] naming `data` and the column).
/// An infinite sample is not an error: it is flagged.
pub fn remove_outliers(data: &[f64], n_cols: usize, threshold: f64) -> Result<Outliers> {
    let mut out = vec![0.0; data.len()];
    let flagged = remove_outliers_into(data, &mut out, n_cols, threshold)?;
    Ok(Outliers {
        data: out,
        mask: flagged.mask,
        channels: flagged.channels,
    })
}

/// [`remove_outliers`] writing into `data` itself: the statistics are taken from `data` as
/// given, then every outlier is replaced by NaN there (the values are those of
/// [`remove_outliers`], bit for bit). A caller that cleans repeatedly reuses one buffer
/// instead of mapping a new copy of its data each time.
///
/// # Errors
/// As [`remove_outliers`]; `data` is unchanged when an error is returned.
pub fn remove_outliers_in_place(
    data: &mut [f64],
    n_cols: usize,
    threshold: f64,
) -> Result<OutliersFlagged> {
    outliers(None, data, n_cols, threshold)
}

/// [`remove_outliers`] writing into the caller's buffer `out` (of `data`'s length): `out`
/// receives `data` with every outlier replaced by NaN, in the pass that flags them (no
/// separate copy of the data). The values are those of [`remove_outliers`], bit for bit.
///
/// # Errors
/// As [`remove_outliers`]; `out` not of `data`'s length ([`Error::ShapeMismatch`]). `out` is
/// unchanged when an error is returned.
pub fn remove_outliers_into(
    data: &[f64],
    out: &mut [f64],
    n_cols: usize,
    threshold: f64,
) -> Result<OutliersFlagged> {
    same_length(data, out)?;
    outliers(Some(data), out, n_cols, threshold)
}

fn same_length(data: &[f64], out: &[f64]) -> Result<()> {
    if out.len() == data.len() {
        Ok(())
    } else {
        Err(Error::ShapeMismatch {
            name: "out",
            reason: format!("{} values for data of {}", out.len(), data.len()),
        })
    }
}

/// Whether a sample at `deviation = |x − center|` is an outlier: `deviation/scale >
/// threshold`, with 0/0 (a constant channel) never one and an infinite sample always one.
#[inline]
fn is_outlier(deviation: f64, scale: f64, threshold: f64) -> bool {
    if scale > 0.0 {
        deviation / scale > threshold
    } else {
        deviation > 0.0
    }
}

/// Columns at least this long take their statistics from sampled brackets (module docs of
/// [`outliers`]); shorter ones are copied and selected whole (cheap at that size).
const SAMPLED_MIN_ROWS: usize = 1 << 15;

/// Rows drawn (with replacement, by a fixed hash: deterministic) to bracket a median.
const SAMPLE_ROWS: usize = 1 << 13;

/// Rows per block of the outlier passes, which walk each block column by column: small
/// enough for a block (input, output and mask) to stay in the core's cache meanwhile. The
/// results do not depend on it.
const OUTLIER_BLOCK_ROWS: usize = 2048;

/// The key of `v` in [`f64::total_cmp`]'s order, as an integer (the same bit trick).
#[inline]
fn order_key(v: f64) -> i64 {
    let bits = v.to_bits() as i64;
    bits ^ ((((bits >> 63) as u64) >> 1) as i64)
}

/// The inverse of [`order_key`].
#[inline]
fn from_order_key(k: i64) -> f64 {
    f64::from_bits((k ^ ((((k >> 63) as u64) >> 1) as i64)) as u64)
}

/// SplitMix64's finaliser (Steele, Lea & Flood 2014): the sampled rows.
#[inline]
fn mix64(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// Per channel, the key range `[lo, hi]` that holds the median of the values `value(j, x)` of
/// the finite samples `x` with overwhelming probability: the order statistics of a sample of
/// rows 5 standard deviations of the sample median's rank either side (`i64::MIN` / `MAX`:
/// unbounded). A miss is detected afterwards and only costs the exact path.
fn brackets<F: Fn(usize, f64) -> f64>(data: &[f64], n_cols: usize, value: F) -> Vec<(i64, i64)> {
    let n = data.len() / n_cols;
    let mut samples: Vec<Vec<i64>> = vec![Vec::with_capacity(SAMPLE_ROWS); n_cols];
    for s in 0..SAMPLE_ROWS as u64 {
        let row = (mix64(s) % n as u64) as usize;
        for (j, sample) in samples.iter_mut().enumerate() {
            let x = data[row * n_cols + j];
            if x.is_finite() {
                sample.push(order_key(value(j, x)));
            }
        }
    }
    samples
        .iter_mut()
        .map(|sample| {
            sample.sort_unstable();
            let m = sample.len();
            let h = (2.5 * (m as f64).sqrt()).ceil() as usize + 2;
            let lo = if m / 2 > h {
                sample[m / 2 - h]
            } else {
                i64::MIN
            };
            let hi = if m / 2 + h < m {
                sample[m / 2 + h]
            } else {
                i64::MAX
            };
            (lo, hi)
        })
        .collect()
}

/// One column of one block's share of a bracketed selection: finite values, keys below the
/// bracket, and the keys inside it.
#[derive(Default)]
struct Tally {
    count: usize,
    below: usize,
    inside: Vec<i64>,
}

/// The median (as [`stats::median_in_place`]) of a column from its blocks' tallies; `None`
/// when a middle rank fell outside the bracket. Also returns the finite count (`total`, or
/// the tallies' when `None`).
fn median_of_tallies(
    tallies: &mut [Vec<Tally>],
    j: usize,
    total: Option<usize>,
) -> (Option<f64>, usize) {
    let total = total.unwrap_or_else(|| tallies.iter().map(|t| t[j].count).sum());
    let below: usize = tallies.iter().map(|t| t[j].below).sum();
    let mut inside: Vec<i64> = Vec::with_capacity(tallies.iter().map(|t| t[j].inside.len()).sum());
    for t in tallies.iter_mut() {
        inside.append(&mut t[j].inside);
    }
    (median_of_keys(&mut inside, below, total), total)
}

/// The median of `total` values of which `below` lie under the keys `inside` (the rest above
/// them), as [`stats::median_in_place`] of all of them; `None` when a middle rank is not
/// among `inside`.
fn median_of_keys(inside: &mut [i64], below: usize, total: usize) -> Option<f64> {
    if total == 0 {
        return None;
    }
    let mid = total / 2;
    // Both middle ranks (one for an odd count) must fall inside.
    let first = if total % 2 == 1 { mid } else { mid - 1 };
    if first < below || mid >= below + inside.len() {
        return None;
    }
    let (left, upper, _) = inside.select_nth_unstable(mid - below);
    let upper = from_order_key(*upper);
    if total % 2 == 1 {
        return Some(upper);
    }
    // The largest value under the upper middle one, as median_in_place folds it.
    let lower = left
        .iter()
        .map(|&k| from_order_key(k))
        .fold(f64::NEG_INFINITY, f64::max);
    Some(f64::midpoint(lower, upper))
}

/// What the fused pass of one column knows before the MAD: the median and the thresholds on
/// `|x − m|` that decide a sample whatever the MAD inside its bracket turns out to be.
#[derive(Clone, Copy)]
struct Cut {
    center: f64,
    /// `|x − m| > surely`: an outlier for every scale in the bracket.
    surely: f64,
    /// `|x − m| < maybe`: not an outlier for every scale in the bracket; in between: decided
    /// after the pass.
    maybe: f64,
    /// Flag in the pass at all (otherwise the column is only copied and flagged afterwards).
    decide: bool,
}

/// One block's share of the fused MAD-and-flag pass, per column.
struct FusedBlock {
    tallies: Vec<Tally>,
    flagged: Vec<usize>,
    gaps: usize,
    /// Per column, the (block-relative) indices left undecided.
    undecided: Vec<Vec<usize>>,
    /// Per column, the (block-relative index, value) of the samples flagged in the pass (to
    /// restore if the column's bracket turns out to have missed).
    removed: Vec<Vec<(usize, f64)>>,
}

/// The outlier step (module docs), reading `data` (or `out` itself when `None`) and writing
/// `out`.
///
/// On a long log the statistics come from two passes over the rows instead of a sort of each
/// column. A deterministic sample of rows brackets each median (and then each MAD); a pass
/// counts, per column, the values below the bracket and keeps those inside it, and the median
/// is selected among those: the same order statistic, bit for bit. The second pass does the
/// same for the deviations `|x − m|` and, at the same time, writes the output: a sample whose
/// deviation exceeds the threshold times the bracket's largest scale is an outlier whatever
/// the MAD, one below the threshold times its smallest scale is not, and the few in between
/// are decided once the MAD is known. A bracket that missed, or a MAD of 0 (then the mean
/// absolute deviation is needed, in the exact path's summation order), sends the column to the
/// exact path (its flagged samples restored first): the results do not depend on the sample.
fn outliers(
    data: Option<&[f64]>,
    out: &mut [f64],
    n_cols: usize,
    threshold: f64,
) -> Result<OutliersFlagged> {
    let view: &[f64] = data.unwrap_or(out);
    let n = rows(view, n_cols)?;
    validate::positive("threshold", threshold)?;
    validate::min_len("data", n, MIN_OUTLIER_SAMPLES)?;
    let all: Vec<usize> = (0..n_cols).collect();
    if n < SAMPLED_MIN_ROWS {
        let channels = exact_statistics(view, n_cols, &all)?;
        let mut mask = vec![false; out.len()];
        let (counts, gaps) = flag_rows(data, out, &mut mask, n_cols, &channels, threshold, &all);
        return Ok(flagged(mask, &channels, &counts, gaps));
    }
    let block_len = OUTLIER_BLOCK_ROWS * n_cols;
    // Pass 1: the medians.
    let median_brackets = brackets(view, n_cols, |_, x| x);
    let mut tallies: Vec<Vec<Tally>> = view
        .par_chunks(block_len)
        .map_init(
            || scratch(n_cols),
            |keep, block| {
                let mut tallies = Vec::with_capacity(n_cols);
                for (j0, k) in groups(n_cols) {
                    let b = &median_brackets[j0..j0 + k];
                    let keep = &mut keep[j0..j0 + k];
                    match k {
                        1 => tally_group::<1>(block, n_cols, j0, b, keep, &mut tallies),
                        2 => tally_group::<2>(block, n_cols, j0, b, keep, &mut tallies),
                        3 => tally_group::<3>(block, n_cols, j0, b, keep, &mut tallies),
                        4 => tally_group::<4>(block, n_cols, j0, b, keep, &mut tallies),
                        5 => tally_group::<5>(block, n_cols, j0, b, keep, &mut tallies),
                        6 => tally_group::<6>(block, n_cols, j0, b, keep, &mut tallies),
                        7 => tally_group::<7>(block, n_cols, j0, b, keep, &mut tallies),
                        _ => tally_group::<8>(block, n_cols, j0, b, keep, &mut tallies),
                    }
                }
                tallies
            },
        )
        .collect();
    let mut centers = Vec::with_capacity(n_cols);
    let mut finite = Vec::with_capacity(n_cols);
    for j in 0..n_cols {
        let (center, count) = median_of_tallies(&mut tallies, j, None);
        if count < MIN_OUTLIER_SAMPLES {
            return Err(too_few_finite(j, count, MIN_OUTLIER_SAMPLES));
        }
        centers.push(center);
        finite.push(count);
    }
    drop(tallies);
    // Pass 2: the MADs, and the output.
    let center_of: Vec<f64> = centers.iter().map(|c| c.unwrap_or(0.0)).collect();
    let mad_brackets = brackets(view, n_cols, |j, x| (x - center_of[j]).abs());
    let cuts: Vec<Cut> = (0..n_cols)
        .map(|j| {
            let (lo, hi) = mad_brackets[j];
            // The MAD lies in [lo, hi] when the bracket holds (checked after the pass); the
            // scale then in MAD_TO_SD·[lo, hi], and |x − m|/s > threshold is decided for
            // |x − m| outside threshold·MAD_TO_SD·[lo, hi] (widened by 1e-9 relative, far
            // beyond the rounding of the division).
            let small = if lo == i64::MIN {
                0.0
            } else {
                from_order_key(lo)
            };
            let large = if hi == i64::MAX {
                f64::INFINITY
            } else {
                from_order_key(hi)
            };
            let maybe = threshold * MAD_TO_SD * small * (1.0 - 1e-9);
            let surely = threshold * MAD_TO_SD * large * (1.0 + 1e-9);
            Cut {
                center: center_of[j],
                surely,
                maybe,
                // A bracket reaching a MAD of 0 (the mean-deviation fallback) or a missing
                // median: flagged after the statistics.
                decide: centers[j].is_some() && maybe > 0.0,
            }
        })
        .collect();
    let mut mask = vec![false; out.len()];
    let fused =
        |keep: &mut Vec<Vec<i64>>, src: Option<&[f64]>, out: &mut [f64], mask: &mut [bool]| {
            let mut block = FusedBlock {
                tallies: Vec::with_capacity(n_cols),
                flagged: Vec::with_capacity(n_cols),
                gaps: 0,
                undecided: vec![Vec::new(); n_cols],
                removed: vec![Vec::new(); n_cols],
            };
            for (j0, k) in groups(n_cols) {
                let g = Group {
                    j0,
                    n_cols,
                    brackets: &mad_brackets[j0..j0 + k],
                    cuts: &cuts[j0..j0 + k],
                };
                let keep = &mut keep[j0..j0 + k];
                match k {
                    1 => fused_group::<1>(&g, src, out, mask, keep, &mut block),
                    2 => fused_group::<2>(&g, src, out, mask, keep, &mut block),
                    3 => fused_group::<3>(&g, src, out, mask, keep, &mut block),
                    4 => fused_group::<4>(&g, src, out, mask, keep, &mut block),
                    5 => fused_group::<5>(&g, src, out, mask, keep, &mut block),
                    6 => fused_group::<6>(&g, src, out, mask, keep, &mut block),
                    7 => fused_group::<7>(&g, src, out, mask, keep, &mut block),
                    _ => fused_group::<8>(&g, src, out, mask, keep, &mut block),
                }
            }
            block
        };
    let mut blocks: Vec<FusedBlock> = match data {
        Some(src) => out
            .par_chunks_mut(block_len)
            .zip(mask.par_chunks_mut(block_len))
            .zip(src.par_chunks(block_len))
            .map_init(
                || scratch(n_cols),
                |keep, ((o, f), s)| fused(keep, Some(s), o, f),
            )
            .collect(),
        None => out
            .par_chunks_mut(block_len)
            .zip(mask.par_chunks_mut(block_len))
            .map_init(|| scratch(n_cols), |keep, (o, f)| fused(keep, None, o, f))
            .collect(),
    };
    let mut channels = vec![(0.0, 0.0); n_cols];
    let mut counts = vec![0_usize; n_cols];
    let mut gaps: usize = blocks.iter().map(|b| b.gaps).sum();
    let mut redo = vec![false; n_cols];
    let mut tallies: Vec<Vec<Tally>> = blocks
        .iter_mut()
        .map(|b| std::mem::take(&mut b.tallies))
        .collect();
    for j in 0..n_cols {
        let (mad, _) = median_of_tallies(&mut tallies, j, Some(finite[j]));
        match (centers[j], mad) {
            (Some(center), Some(mad)) if mad > 0.0 => {
                let scale = MAD_TO_SD * mad;
                channels[j] = (center, scale);
                if !cuts[j].decide {
                    redo[j] = true;
                    continue;
                }
                counts[j] = blocks.iter().map(|b| b.flagged[j]).sum();
                for (b, block) in blocks.iter().enumerate() {
                    for &i in &block.undecided[j] {
                        let at = b * block_len + i;
                        if is_outlier((out[at] - center).abs(), scale, threshold) {
                            out[at] = f64::NAN;
                            mask[at] = true;
                            counts[j] += 1;
                            gaps += 1;
                        }
                    }
                }
            }
            _ => {
                // Undo the pass's flags of this column: it is redone whole.
                for (b, block) in blocks.iter().enumerate() {
                    for &(i, v) in &block.removed[j] {
                        out[b * block_len + i] = v;
                        mask[b * block_len + i] = false;
                    }
                    gaps -= block.flagged[j];
                }
                redo[j] = true;
                channels[j] = (f64::NAN, f64::NAN);
            }
        }
    }
    drop(blocks);
    let exact: Vec<usize> = (0..n_cols)
        .filter(|&j| redo[j] && channels[j].0.is_nan())
        .collect();
    if !exact.is_empty() {
        // `out` holds the data unflagged in these columns.
        for (&j, s) in exact.iter().zip(exact_statistics(out, n_cols, &exact)?) {
            channels[j] = s;
        }
    }
    let later: Vec<usize> = (0..n_cols).filter(|&j| redo[j]).collect();
    if !later.is_empty() {
        // These columns were copied unflagged: flag them in place. Their NaN (gaps given) were
        // counted by the pass already.
        let (c, _) = flag_rows(None, out, &mut mask, n_cols, &channels, threshold, &later);
        for &j in &later {
            counts[j] = c[j];
            gaps += c[j];
        }
    }
    Ok(flagged(mask, &channels, &counts, gaps))
}

/// Per worker, one buffer of [`OUTLIER_BLOCK_ROWS`] keys per column: the keys inside a
/// bracket are written at the next free slot whether kept or not (no branch on the data).
fn scratch(n_cols: usize) -> Vec<Vec<i64>> {
    vec![vec![0_i64; OUTLIER_BLOCK_ROWS]; n_cols]
}

/// The columns in groups of at most 8 consecutive ones, `(first, width)`: each group is
/// walked row by row with its state in registers (a kernel per width).
fn groups(n_cols: usize) -> impl Iterator<Item = (usize, usize)> {
    (0..n_cols)
        .step_by(8)
        .map(move |j0| (j0, (n_cols - j0).min(8)))
}

/// Pass 1 of [`outliers`] over one block for the columns `j0 .. j0 + K`: pushes their tallies
/// of the samples against the median brackets.
// `&` on booleans on purpose: both sides are cheap and a branch on the data would be
// mispredicted half the time.
#[allow(clippy::needless_bitwise_bool)]
fn tally_group<const K: usize>(
    block: &[f64],
    n_cols: usize,
    j0: usize,
    brackets: &[(i64, i64)],
    keep: &mut [Vec<i64>],
    tallies: &mut Vec<Tally>,
) {
    let lo: [i64; K] = std::array::from_fn(|j| brackets[j].0);
    let width: [u64; K] = std::array::from_fn(|j| brackets[j].1.wrapping_sub(brackets[j].0) as u64);
    let mut count = [0_usize; K];
    let mut below = [0_usize; K];
    let mut kept = [0_usize; K];
    for row in block.chunks_exact(n_cols) {
        let row = &row[j0..j0 + K];
        for j in 0..K {
            let x = row[j];
            let key = order_key(x);
            let finite = x.is_finite();
            count[j] += usize::from(finite);
            below[j] += usize::from(finite & (key < lo[j]));
            keep[j][kept[j]] = key;
            kept[j] += usize::from(finite & ((key.wrapping_sub(lo[j]) as u64) <= width[j]));
        }
    }
    for j in 0..K {
        tallies.push(Tally {
            count: count[j],
            below: below[j],
            inside: keep[j][..kept[j]].to_vec(),
        });
    }
}

/// A group of columns of the fused pass: the first column, the row width and the group's
/// MAD brackets and cuts.
struct Group<'a> {
    j0: usize,
    n_cols: usize,
    brackets: &'a [(i64, i64)],
    cuts: &'a [Cut],
}

/// Pass 2 of [`outliers`] over one block for the columns of `g`: tallies the deviations
/// against the MAD brackets and writes the output, flagging what is decided.
// `&` on booleans on purpose: both sides are cheap and a branch on the data would be
// mispredicted half the time.
#[allow(clippy::needless_bitwise_bool)]
fn fused_group<const K: usize>(
    g: &Group<'_>,
    src: Option<&[f64]>,
    out: &mut [f64],
    mask: &mut [bool],
    keep: &mut [Vec<i64>],
    block: &mut FusedBlock,
) {
    let (j0, n_cols) = (g.j0, g.n_cols);
    let lo: [i64; K] = std::array::from_fn(|j| g.brackets[j].0);
    let width: [u64; K] =
        std::array::from_fn(|j| g.brackets[j].1.wrapping_sub(g.brackets[j].0) as u64);
    let center: [f64; K] = std::array::from_fn(|j| g.cuts[j].center);
    // A column not decided in the pass has cuts no deviation passes (NaN compares false).
    let surely: [f64; K] = std::array::from_fn(|j| {
        if g.cuts[j].decide {
            g.cuts[j].surely
        } else {
            f64::NAN
        }
    });
    let maybe: [f64; K] = std::array::from_fn(|j| {
        if g.cuts[j].decide {
            g.cuts[j].maybe
        } else {
            f64::NAN
        }
    });
    let mut below = [0_usize; K];
    let mut kept = [0_usize; K];
    let mut flagged = [0_usize; K];
    let mut nan = [0_usize; K];
    for (r, (o, f)) in out
        .chunks_exact_mut(n_cols)
        .zip(mask.chunks_exact_mut(n_cols))
        .enumerate()
    {
        let o = &mut o[j0..j0 + K];
        let f = &mut f[j0..j0 + K];
        let x: [f64; K] = match src {
            Some(s) => std::array::from_fn(|j| s[r * n_cols + j0 + j]),
            None => std::array::from_fn(|j| o[j]),
        };
        for j in 0..K {
            let v = x[j];
            let d = (v - center[j]).abs();
            // d ≥ +0 for a finite sample: its order key is its bits.
            let key = d.to_bits() as i64;
            let finite = v.is_finite();
            below[j] += usize::from(finite & (key < lo[j]));
            keep[j][kept[j]] = key;
            kept[j] += usize::from(finite & ((key.wrapping_sub(lo[j]) as u64) <= width[j]));
            nan[j] += usize::from(v.is_nan());
            let outlier = d > surely[j];
            o[j] = if outlier { f64::NAN } else { v };
            f[j] = outlier;
            flagged[j] += usize::from(outlier);
            if d >= maybe[j] {
                // Rare: a deviation near the threshold, or an outlier to restore if the
                // column's bracket turns out to have missed.
                let i = r * n_cols + j0 + j;
                if outlier {
                    block.removed[j0 + j].push((i, v));
                } else {
                    block.undecided[j0 + j].push(i);
                }
            }
        }
    }
    for j in 0..K {
        block.tallies.push(Tally {
            count: 0,
            below: below[j],
            inside: keep[j][..kept[j]].to_vec(),
        });
        block.flagged.push(flagged[j]);
        block.gaps += flagged[j] + nan[j];
    }
}

fn flagged(
    mask: Vec<bool>,
    channels: &[(f64, f64)],
    counts: &[usize],
    gaps: usize,
) -> OutliersFlagged {
    OutliersFlagged {
        mask,
        channels: channels
            .iter()
            .zip(counts)
            .map(|(&(center, scale), &count)| OutlierStats {
                center,
                scale,
                count,
            })
            .collect(),
        gaps,
    }
}

/// Writes the flagged data of the columns `columns` into `out` (from `data`, or from `out`
/// itself when `data` is `None`) and `mask`: per row block in parallel. Returns the count per
/// channel (0 for the others) and the number of NaN samples written in those columns (gaps
/// given and outliers flagged).
fn flag_rows(
    data: Option<&[f64]>,
    out: &mut [f64],
    mask: &mut [bool],
    n_cols: usize,
    channels: &[(f64, f64)],
    threshold: f64,
    columns: &[usize],
) -> (Vec<usize>, usize) {
    let block_len = OUTLIER_BLOCK_ROWS * n_cols;
    let block_counts: Vec<(Vec<usize>, usize)> = out
        .par_chunks_mut(block_len)
        .zip(mask.par_chunks_mut(block_len))
        .enumerate()
        .map(|(b, (out_block, mask_block))| {
            let mut counts = vec![0_usize; n_cols];
            let mut gaps = 0_usize;
            let source = data.map(|d| &d[b * block_len..b * block_len + out_block.len()]);
            // Column by column within the block (it stays in cache): the column's statistics
            // and counts live in registers.
            for &j in columns {
                let (center, scale) = channels[j];
                let (mut flagged, mut nan) = (0_usize, 0_usize);
                let mut flag = |v: f64, o: &mut f64, f: &mut bool| {
                    let outlier = is_outlier((v - center).abs(), scale, threshold);
                    *o = if outlier { f64::NAN } else { v };
                    *f = outlier;
                    flagged += usize::from(outlier);
                    nan += usize::from(v.is_nan());
                };
                let outs = out_block[j..].iter_mut().step_by(n_cols);
                let flags = mask_block[j..].iter_mut().step_by(n_cols);
                match source {
                    Some(src) => {
                        for ((o, f), &v) in outs.zip(flags).zip(src[j..].iter().step_by(n_cols)) {
                            flag(v, o, f);
                        }
                    }
                    None => {
                        for (o, f) in outs.zip(flags) {
                            let v = *o;
                            flag(v, o, f);
                        }
                    }
                }
                counts[j] = flagged;
                // NaN given are never flagged: the output's NaN are both kinds.
                gaps += flagged + nan;
            }
            (counts, gaps)
        })
        .collect();
    let mut counts = vec![0_usize; n_cols];
    let mut gaps = 0;
    for (block, g) in &block_counts {
        for (total, c) in counts.iter_mut().zip(block) {
            *total += c;
        }
        gaps += g;
    }
    (counts, gaps)
}

/// `(center, scale)` of the columns `columns` (in order), each copied out and selected whole
/// ([`robust_center_scale`]); the first error in column order.
fn exact_statistics(data: &[f64], n_cols: usize, columns: &[usize]) -> Result<Vec<(f64, f64)>> {
    let n = data.len() / n_cols;
    // One scratch column per worker, reused for its columns (first-touch page faults of a
    // fresh buffer per column cost more than the selection itself); column j goes to worker
    // j mod workers, and each column's statistics do not depend on the assignment.
    let workers = columns.len().min(rayon::current_num_threads()).max(1);
    let per_worker: Vec<Vec<ColumnStats>> = (0..workers)
        .into_par_iter()
        .map(|w| {
            let mut scratch = Vec::with_capacity(n);
            columns
                .iter()
                .skip(w)
                .step_by(workers)
                .map(|&j| {
                    finite_column_into(data, n_cols, j, &mut scratch);
                    let stats = if scratch.len() < MIN_OUTLIER_SAMPLES {
                        Err(too_few_finite(j, scratch.len(), MIN_OUTLIER_SAMPLES))
                    } else {
                        Ok(robust_center_scale(&mut scratch))
                    };
                    (j, stats)
                })
                .collect()
        })
        .collect();
    let mut ordered: Vec<ColumnStats> = per_worker.into_iter().flatten().collect();
    ordered.sort_by_key(|(j, _)| *j);
    ordered.into_iter().map(|(_, stats)| stats).collect()
}

fn too_few_finite(column: usize, got: usize, needed: usize) -> Error {
    Error::invalid(
        "data",
        format!("column {column} has {got} finite samples, at least {needed} are needed"),
    )
}

/// Legendre basis `[P0, P1, P2]` at the scaled time of row `i` of `n`.
#[inline]
fn legendre(i: usize, n: usize) -> [f64; 3] {
    let u = if n > 1 {
        2.0 * i as f64 / (n - 1) as f64 - 1.0
    } else {
        0.0
    };
    [1.0, u, 1.5 * u * u - 0.5]
}

/// Per channel: Gram matrix (upper triangle, 6 entries) and right-hand side (3 entries).
type Normal = [f64; 9];

fn add_normal(a: &mut [Normal], b: &[Normal]) {
    for (x, y) in a.iter_mut().zip(b) {
        for (p, q) in x.iter_mut().zip(y) {
            *p += q;
        }
    }
}

/// Solves the symmetric positive definite `dim × dim` system (Cholesky); `None` if singular.
fn solve_spd(normal: &Normal, dim: usize) -> Option<[f64; 3]> {
    let g = |r: usize, c: usize| {
        let (r, c) = if r <= c { (r, c) } else { (c, r) };
        // Upper triangle, row-major: (0,0) (0,1) (0,2) (1,1) (1,2) (2,2).
        normal[[0, 1, 2, 0, 3, 4, 0, 0, 5][r * 3 + c]]
    };
    let mut l = [[0.0_f64; 3]; 3];
    for i in 0..dim {
        for j in 0..=i {
            let mut s = g(i, j);
            for p in 0..j {
                s -= l[i][p] * l[j][p];
            }
            if i == j {
                // Relative pivot test: the basis is well conditioned, so a tiny pivot means
                // too few distinct times.
                if s.partial_cmp(&(1e-12 * g(i, i))) != Some(std::cmp::Ordering::Greater) {
                    return None;
                }
                l[i][i] = s.sqrt();
            } else {
                l[i][j] = s / l[j][j];
            }
        }
    }
    let mut y = [0.0_f64; 3];
    for i in 0..dim {
        let mut s = normal[6 + i];
        for p in 0..i {
            s -= l[i][p] * y[p];
        }
        y[i] = s / l[i][i];
    }
    let mut x = [0.0_f64; 3];
    for i in (0..dim).rev() {
        let mut s = y[i];
        for p in i + 1..dim {
            s -= l[p][i] * x[p];
        }
        x[i] = s / l[i][i];
    }
    Some(x)
}

/// Removes each channel's least-squares polynomial of degree `order` in time (module docs).
///
/// `data` is row-major `(n, n_cols)` sampled at `fs` Hz; NaN samples are gaps (not fitted,
/// kept NaN). Returns the residual and the monomial coefficients of `t` in seconds from the
/// first sample.
///
/// # Errors
/// `fs` not finite and > 0; `order` not 1 or 2; `n_cols` of 0 or not dividing `data.len()`;
/// an infinite sample ([`Error::NonFinite`]); a channel with fewer than `order + 2` finite
/// samples (naming `data` and the column).
pub fn detrend(data: &[f64], n_cols: usize, fs: f64, order: usize) -> Result<Detrended> {
    let mut out = vec![0.0; data.len()];
    let drift = detrend_into(data, &mut out, n_cols, fs, order)?;
    Ok(Detrended {
        data: out,
        coefficients: drift.coefficients,
    })
}

/// The output of [`detrend_in_place`] and [`detrend_into`] (the residual is the caller's
/// buffer).
#[derive(Debug, Clone, PartialEq)]
pub struct DetrendFlagged {
    /// As [`Detrended::coefficients`].
    pub coefficients: Vec<f64>,
    /// NaN samples in the residual (the gaps): whether the Allan functions need
    /// `gaps = omit`, without a scan of the data.
    pub gaps: usize,
}

/// [`detrend`] writing the residual into `data` itself. The residual is that of [`detrend`],
/// bit for bit: the fit reads every sample before the first one is overwritten. A caller that
/// cleans repeatedly reuses one buffer (and the outlier step's output is detrended where it
/// lies: one copy of the data for both steps).
///
/// # Errors
/// As [`detrend`]; `data` is unchanged when an error is returned.
pub fn detrend_in_place(
    data: &mut [f64],
    n_cols: usize,
    fs: f64,
    order: usize,
) -> Result<Vec<f64>> {
    detrend_in_place_flagged(data, n_cols, fs, order).map(|d| d.coefficients)
}

/// [`detrend_in_place`] that also counts the residual's NaN samples ([`DetrendFlagged`]).
///
/// # Errors
/// As [`detrend`]; `data` is unchanged when an error is returned.
pub fn detrend_in_place_flagged(
    data: &mut [f64],
    n_cols: usize,
    fs: f64,
    order: usize,
) -> Result<DetrendFlagged> {
    let fitted = fit_drift(data, n_cols, fs, order)?;
    let gaps = remove_drift(None, data, n_cols, &fitted);
    Ok(DetrendFlagged {
        coefficients: fitted.coefficients,
        gaps,
    })
}

/// [`detrend`] writing the residual into the caller's buffer `out` (of `data`'s length), in
/// the pass that computes it (no separate copy of the data). The residual is that of
/// [`detrend`], bit for bit.
///
/// # Errors
/// As [`detrend`]; `out` not of `data`'s length ([`Error::ShapeMismatch`]). `out` is unchanged
/// when an error is returned.
pub fn detrend_into(
    data: &[f64],
    out: &mut [f64],
    n_cols: usize,
    fs: f64,
    order: usize,
) -> Result<DetrendFlagged> {
    same_length(data, out)?;
    let fitted = fit_drift(data, n_cols, fs, order)?;
    let gaps = remove_drift(Some(data), out, n_cols, &fitted);
    Ok(DetrendFlagged {
        coefficients: fitted.coefficients,
        gaps,
    })
}

/// The drift fitted by [`fit_drift`]: what [`remove_drift`] subtracts, and the coefficients.
struct Drift {
    n: usize,
    reference: Vec<f64>,
    legendre: Vec<[f64; 3]>,
    coefficients: Vec<f64>,
}

/// One block of rows' share of the normal equations: per channel the sums and the finite
/// count, and the block-relative index of its first infinite sample.
struct BlockNormal {
    sums: Vec<Normal>,
    counts: Vec<usize>,
    first_infinite: Option<usize>,
}

/// The sums of one block of rows (rows `first_row ..`). The basis sums (entries 0-5) are
/// accumulated once for the block and shared by every channel without a gap in it (the same
/// additions in the same order as a channel's own); a channel with a gap in the block sums
/// its basis over its finite rows.
fn block_normal(
    block: &[f64],
    n_cols: usize,
    first_row: usize,
    n: usize,
    reference: &[f64],
) -> BlockNormal {
    let mut basis = [0.0_f64; 6];
    let mut sums = vec![[0.0_f64; 9]; n_cols];
    let mut counts = vec![0_usize; n_cols];
    let mut gap = vec![false; n_cols];
    let mut infinite = false;
    for (j0, k) in groups(n_cols) {
        let mut g = NormalGroup {
            block,
            n_cols,
            j0,
            first_row,
            n,
            reference: &reference[j0..j0 + k],
            sums: &mut sums[j0..j0 + k],
            counts: &mut counts[j0..j0 + k],
            gap: &mut gap[j0..j0 + k],
            infinite: false,
            // The first group also sums the basis (one Legendre evaluation per row).
            basis: (j0 == 0).then_some(&mut basis),
        };
        match k {
            1 => g.run::<1>(),
            2 => g.run::<2>(),
            3 => g.run::<3>(),
            4 => g.run::<4>(),
            5 => g.run::<5>(),
            6 => g.run::<6>(),
            7 => g.run::<7>(),
            _ => g.run::<8>(),
        }
        infinite |= g.infinite;
    }
    for j in 0..n_cols {
        if !gap[j] {
            sums[j][..6].copy_from_slice(&basis);
            continue;
        }
        let s = &mut sums[j];
        for (r, row) in block.chunks_exact(n_cols).enumerate() {
            if row[j].is_nan() {
                continue;
            }
            let p = legendre(first_row + r, n);
            s[0] += 1.0;
            s[1] += p[1];
            s[2] += p[2];
            s[3] += p[1] * p[1];
            s[4] += p[1] * p[2];
            s[5] += p[2] * p[2];
        }
    }
    BlockNormal {
        sums,
        counts,
        first_infinite: if infinite {
            block.iter().position(|v| v.is_infinite())
        } else {
            None
        },
    }
}

/// The right-hand sides (entries 6-8) of a group of columns `j0 ..` of one block, walked row
/// by row with the group's sums in registers.
struct NormalGroup<'a> {
    block: &'a [f64],
    n_cols: usize,
    j0: usize,
    first_row: usize,
    n: usize,
    reference: &'a [f64],
    sums: &'a mut [Normal],
    counts: &'a mut [usize],
    gap: &'a mut [bool],
    infinite: bool,
    /// The block's basis sums (entries 0-5), accumulated row by row when given.
    basis: Option<&'a mut [f64; 6]>,
}

impl NormalGroup<'_> {
    fn run<const K: usize>(&mut self) {
        let reference: [f64; K] = std::array::from_fn(|j| self.reference[j]);
        let mut s6 = [0.0_f64; K];
        let mut s7 = [0.0_f64; K];
        let mut s8 = [0.0_f64; K];
        let mut count = [0_usize; K];
        let mut gap = [false; K];
        let mut infinite = false;
        let mut basis = [0.0_f64; 6];
        let with_basis = self.basis.is_some();
        for (r, row) in self.block.chunks_exact(self.n_cols).enumerate() {
            let p = legendre(self.first_row + r, self.n);
            if with_basis {
                basis[0] += 1.0;
                basis[1] += p[1];
                basis[2] += p[2];
                basis[3] += p[1] * p[1];
                basis[4] += p[1] * p[2];
                basis[5] += p[2] * p[2];
            }
            let row = &row[self.j0..self.j0 + K];
            for j in 0..K {
                let v = row[j];
                let nan = v.is_nan();
                gap[j] |= nan;
                infinite |= v.is_infinite();
                // A gap adds +0 (the sums start at +0 and can never become −0, so adding ±0
                // leaves them bit for bit as skipping the sample does).
                let y = if nan { 0.0 } else { v - reference[j] };
                s6[j] += y;
                s7[j] += y * p[1];
                s8[j] += y * p[2];
                count[j] += usize::from(!nan);
            }
        }
        for j in 0..K {
            self.sums[j][6] = s6[j];
            self.sums[j][7] = s7[j];
            self.sums[j][8] = s8[j];
            self.counts[j] = count[j];
            self.gap[j] = gap[j];
        }
        self.infinite = infinite;
        if let Some(b) = self.basis.as_deref_mut() {
            *b = basis;
        }
    }
}

/// Checks the arguments and fits each channel's polynomial (module docs), reading `data` only.
fn fit_drift(data: &[f64], n_cols: usize, fs: f64, order: usize) -> Result<Drift> {
    let n = rows(data, n_cols)?;
    let t0 = validate::sample_period(fs)?;
    if !(1..=2).contains(&order) {
        return Err(Error::invalid(
            "order",
            format!("must be 1 (linear) or 2 (quadratic), got {order}"),
        ));
    }
    let dim = order + 1;
    let needed = order + 2;
    // Each channel relative to its first finite sample (the sums then hold deviations only).
    let reference: Vec<f64> = (0..n_cols)
        .map(|j| {
            data.iter()
                .skip(j)
                .step_by(n_cols)
                .copied()
                .find(|v| v.is_finite())
                .unwrap_or(0.0)
        })
        .collect();
    let block_len = BLOCK_ROWS * n_cols;
    // One pass: the sums and the search for an infinite sample (an error, checked before the
    // length so that its message wins as it did when it was a pass of its own).
    let partial: Vec<BlockNormal> = data
        .par_chunks(block_len)
        .enumerate()
        .map(|(b, block)| block_normal(block, n_cols, b * BLOCK_ROWS, n, &reference))
        .collect();
    if let Some((b, i)) = partial
        .iter()
        .enumerate()
        .find_map(|(b, p)| p.first_infinite.map(|i| (b, i)))
    {
        return Err(Error::NonFinite {
            name: "data",
            index: b * block_len + i,
        });
    }
    validate::min_len("data", n, needed)?;
    let mut sums = vec![[0.0_f64; 9]; n_cols];
    let mut counts = vec![0_usize; n_cols];
    for p in &partial {
        add_normal(&mut sums, &p.sums);
        for (a, b) in counts.iter_mut().zip(&p.counts) {
            *a += b;
        }
    }
    drop(partial);
    let mut legendre_coefficients = Vec::with_capacity(n_cols);
    for j in 0..n_cols {
        if counts[j] < needed {
            return Err(too_few_finite(j, counts[j], needed));
        }
        let beta = solve_spd(&sums[j], dim).ok_or_else(|| Error::Singular {
            reason: format!("detrend of data column {j}: too few distinct sample times"),
        })?;
        legendre_coefficients.push(beta);
    }
    // P(u) with u = a·t − 1, a = 2/((n − 1)·t0):
    //   β0 + β1(a t − 1) + β2(1.5 (a t − 1)² − 0.5)
    //   = (β0 − β1 + β2) + (β1 − 3β2)·a·t + 1.5·β2·a²·t².
    let a = if n > 1 {
        2.0 / ((n - 1) as f64 * t0)
    } else {
        0.0
    };
    let mut coefficients = Vec::with_capacity(n_cols * dim);
    for (beta, reference) in legendre_coefficients.iter().zip(&reference) {
        coefficients.push(reference + beta[0] - beta[1] + beta[2]);
        coefficients.push((beta[1] - 3.0 * beta[2]) * a);
        if order == 2 {
            coefficients.push(1.5 * beta[2] * a * a);
        }
    }
    Ok(Drift {
        n,
        reference,
        legendre: legendre_coefficients,
        coefficients,
    })
}

/// Writes the residual into `out` (of `data`, or of `out` itself when `data` is `None`);
/// returns its number of NaN samples.
fn remove_drift(data: Option<&[f64]>, out: &mut [f64], n_cols: usize, drift: &Drift) -> usize {
    let block_len = BLOCK_ROWS * n_cols;
    out.par_chunks_mut(block_len)
        .enumerate()
        .map(|(b, block)| {
            let source = data.map(|d| &d[b * block_len..b * block_len + block.len()]);
            groups(n_cols)
                .map(|(j0, k)| {
                    let g = DriftGroup {
                        src: source,
                        n_cols,
                        j0,
                        first_row: b * BLOCK_ROWS,
                        drift,
                    };
                    match k {
                        1 => g.run::<1>(block),
                        2 => g.run::<2>(block),
                        3 => g.run::<3>(block),
                        4 => g.run::<4>(block),
                        5 => g.run::<5>(block),
                        6 => g.run::<6>(block),
                        7 => g.run::<7>(block),
                        _ => g.run::<8>(block),
                    }
                })
                .sum::<usize>()
        })
        .sum()
}

/// The residual of a group of columns `j0 ..` of one block (rows from `first_row`), written
/// row by row; returns its NaN count.
struct DriftGroup<'a> {
    src: Option<&'a [f64]>,
    n_cols: usize,
    j0: usize,
    first_row: usize,
    drift: &'a Drift,
}

impl DriftGroup<'_> {
    fn run<const K: usize>(&self, out: &mut [f64]) -> usize {
        let (n_cols, j0) = (self.n_cols, self.j0);
        let reference: [f64; K] = std::array::from_fn(|j| self.drift.reference[j0 + j]);
        let beta: [[f64; 3]; K] = std::array::from_fn(|j| self.drift.legendre[j0 + j]);
        let mut gaps = 0_usize;
        for (r, row) in out.chunks_exact_mut(n_cols).enumerate() {
            let p = legendre(self.first_row + r, self.drift.n);
            let row = &mut row[j0..j0 + K];
            let x: [f64; K] = match self.src {
                Some(s) => std::array::from_fn(|j| s[r * n_cols + j0 + j]),
                None => std::array::from_fn(|j| row[j]),
            };
            for j in 0..K {
                let model = beta[j][0] + beta[j][1] * p[1] + beta[j][2] * p[2];
                row[j] = (x[j] - reference[j]) - model;
                gaps += usize::from(row[j].is_nan());
            }
        }
        gaps
    }
}

/// First row of bin `b` of `bins` over `n` rows: `⌊b·n/bins⌋`.
#[inline]
fn bin_start(b: usize, n: usize, bins: usize) -> usize {
    // u128: b·n cannot overflow.
    ((b as u128 * n as u128) / bins as u128) as usize
}

/// Min/max envelope of each channel over `bins` consecutive bins of rows (module docs).
///
/// `bins` larger than the number of rows `n` gives `n` bins of one row.
///
/// # Errors
/// `bins` of 0; `n_cols` of 0 or not dividing `data.len()`; no row.
pub fn minmax_envelope(data: &[f64], n_cols: usize, bins: usize) -> Result<Envelope> {
    let n = rows(data, n_cols)?;
    if bins == 0 {
        return Err(Error::invalid("bins", "must be >= 1, got 0"));
    }
    validate::min_len("data", n, 1)?;
    let bins = bins.min(n);
    let size = validate::product("bins", bins, n_cols)?;
    validate::allocatable::<f64>("bins", size)?;
    let mut lower = vec![f64::NAN; size];
    let mut upper = vec![f64::NAN; size];
    // Enough bins per task to amortise rayon's overhead, few enough to balance two cores.
    let per_task = bins.div_ceil(64).max(1);
    lower
        .par_chunks_mut(per_task * n_cols)
        .zip(upper.par_chunks_mut(per_task * n_cols))
        .enumerate()
        .for_each(|(task, (lo_task, hi_task))| {
            let first_bin = task * per_task;
            for (i, (lo, hi)) in lo_task
                .chunks_exact_mut(n_cols)
                .zip(hi_task.chunks_exact_mut(n_cols))
                .enumerate()
            {
                let b = first_bin + i;
                let rows =
                    &data[bin_start(b, n, bins) * n_cols..bin_start(b + 1, n, bins) * n_cols];
                envelope_bin(rows, lo, hi);
            }
        });
    let starts = (0..=bins).map(|b| bin_start(b, n, bins)).collect();
    Ok(Envelope {
        lower,
        upper,
        starts,
    })
}

/// Min and max of each column of `rows` (NaN skipped; NaN when the column has no value).
#[inline]
fn envelope_bin(rows: &[f64], lo: &mut [f64], hi: &mut [f64]) {
    // The usual channel counts get a kernel whose row fits in registers (unrolled by the
    // compiler); the others the general loop. Same comparisons, same results.
    match lo.len() {
        1 => envelope_fixed::<1>(rows, lo, hi),
        2 => envelope_fixed::<2>(rows, lo, hi),
        3 => envelope_fixed::<3>(rows, lo, hi),
        4 => envelope_fixed::<4>(rows, lo, hi),
        6 => envelope_fixed::<6>(rows, lo, hi),
        7 => envelope_fixed::<7>(rows, lo, hi),
        _ => envelope_any(rows, lo, hi),
    }
    for (l, h) in lo.iter_mut().zip(hi.iter_mut()) {
        if *l > *h {
            // Nothing but NaN (an infinite value keeps l ≤ h).
            *l = f64::NAN;
            *h = f64::NAN;
        }
    }
}

/// `l = min(l, v)`, `h = max(h, v)` with NaN skipped (it compares false both ways).
#[inline]
fn widen(l: &mut f64, h: &mut f64, v: f64) {
    if v < *l {
        *l = v;
    }
    if v > *h {
        *h = v;
    }
}

fn envelope_fixed<const K: usize>(rows: &[f64], lo: &mut [f64], hi: &mut [f64]) {
    let mut l = [f64::INFINITY; K];
    let mut h = [f64::NEG_INFINITY; K];
    for row in rows.chunks_exact(K) {
        for j in 0..K {
            widen(&mut l[j], &mut h[j], row[j]);
        }
    }
    lo.copy_from_slice(&l);
    hi.copy_from_slice(&h);
}

fn envelope_any(rows: &[f64], lo: &mut [f64], hi: &mut [f64]) {
    lo.fill(f64::INFINITY);
    hi.fill(f64::NEG_INFINITY);
    for row in rows.chunks_exact(lo.len()) {
        for ((l, h), &v) in lo.iter_mut().zip(hi.iter_mut()).zip(row) {
            widen(l, h, v);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 3-channel series with a drift, a gap and spikes (rows of 3).
    fn messy(n: usize) -> Vec<f64> {
        let noise = crate::random::normal_vec(3 * n, 5);
        let mut x: Vec<f64> = noise
            .iter()
            .enumerate()
            .map(|(i, v)| v + 1e-3 * (i / 3) as f64 + (i % 3) as f64)
            .collect();
        x[3 * 10] = f64::NAN;
        x[3 * 20 + 1] = 50.0;
        x[3 * 40 + 2] = -70.0;
        x
    }

    #[test]
    fn in_place_equals_copy_bit_for_bit() {
        let x = messy(5_000);
        let copy = remove_outliers(&x, 3, 5.0).unwrap();
        let mut buf = x.clone();
        let flagged = remove_outliers_in_place(&mut buf, 3, 5.0).unwrap();
        assert_eq!(flagged.mask, copy.mask);
        assert_eq!(flagged.channels, copy.channels);
        let bits = |v: &[f64]| v.iter().map(|f| f.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&buf), bits(&copy.data));
        for order in [1, 2] {
            let d = detrend(&copy.data, 3, 100.0, order).unwrap();
            let mut again = copy.data.clone();
            let coefficients = detrend_in_place(&mut again, 3, 100.0, order).unwrap();
            assert_eq!(bits(&again), bits(&d.data));
            assert_eq!(bits(&coefficients), bits(&d.coefficients));
        }
    }

    #[test]
    fn in_place_errors_leave_the_buffer_alone() {
        let mut x = messy(100);
        x[7] = f64::INFINITY;
        let before = x.clone();
        assert!(detrend_in_place(&mut x, 3, 100.0, 3).is_err());
        assert!(detrend_in_place(&mut x, 3, 100.0, 1).is_err()); // the infinite sample
        assert!(remove_outliers_in_place(&mut x, 3, f64::NAN).is_err());
        assert!(remove_outliers_in_place(&mut x[..6], 3, 5.0).is_err()); // 2 rows
        let bits = |v: &[f64]| v.iter().map(|f| f.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&x), bits(&before));
    }

    /// The exact path for every column (each column copied out and selected whole, the
    /// implementation before the sampled statistics): the reference of the long-log path.
    fn exact_reference(data: &[f64], n_cols: usize, threshold: f64) -> (Vec<f64>, OutliersFlagged) {
        let all: Vec<usize> = (0..n_cols).collect();
        let channels = exact_statistics(data, n_cols, &all).unwrap();
        let mut out = vec![0.0; data.len()];
        let mut mask = vec![false; data.len()];
        let (counts, gaps) = flag_rows(
            Some(data),
            &mut out,
            &mut mask,
            n_cols,
            &channels,
            threshold,
            &all,
        );
        (out, flagged(mask, &channels, &counts, gaps))
    }

    fn bits(v: &[f64]) -> Vec<u64> {
        v.iter().map(|f| f.to_bits()).collect()
    }

    /// Columns that exercise every path of the long-log statistics: normal with spikes, a
    /// quantised one (MAD 0: the mean-deviation fallback), gaps and infinities, heavy tails
    /// with 2 % contamination, a constant, a ramp, signed zeros, and a column whose sampled
    /// rows (the fixed hash) differ from the rest so that both of its brackets miss.
    fn hostile(n: usize, n_cols: usize) -> Vec<f64> {
        let z = crate::random::normal_vec(n * n_cols, 11);
        let sampled: std::collections::HashSet<usize> = (0..SAMPLE_ROWS as u64)
            .map(|s| (mix64(s) % n as u64) as usize)
            .collect();
        let mut x = vec![0.0; n * n_cols];
        for i in 0..n {
            for j in 0..n_cols {
                let g = z[i * n_cols + j];
                x[i * n_cols + j] = match j % 9 {
                    0 => g + if i % 997 == 0 { 40.0 } else { 0.0 },
                    1 => f64::from(u8::from(i % 10 == 0)),
                    2 => match i % 7 {
                        0 => f64::NAN,
                        3 if i % 1001 == 3 => f64::INFINITY,
                        5 if i % 1003 == 5 => f64::NEG_INFINITY,
                        _ => 0.5 + g,
                    },
                    3 => {
                        g / z[(i * n_cols + j + 1) % z.len()].abs().max(1e-3)
                            + if i % 50 == 0 { 1e3 } else { 0.0 }
                    }
                    4 => 3.25,
                    5 => i as f64 * 1e-3,
                    6 => [0.0, -0.0, 1.0, -1.0, -0.0][i % 5],
                    7 => {
                        if sampled.contains(&i) {
                            100.0 + g
                        } else {
                            g
                        }
                    }
                    _ => (g * 8.0).round() / 8.0,
                };
            }
        }
        x
    }

    #[test]
    fn long_log_statistics_equal_the_exact_path_bit_for_bit() {
        for (n, n_cols) in [
            (SAMPLED_MIN_ROWS + 1001, 9),
            (SAMPLED_MIN_ROWS * 2, 9),
            (SAMPLED_MIN_ROWS + 2, 11),
        ] {
            let x = hostile(n, n_cols);
            for threshold in [2.0, 5.0] {
                let (want, reference) = exact_reference(&x, n_cols, threshold);
                let got = remove_outliers(&x, n_cols, threshold).unwrap();
                assert_eq!(bits(&got.data), bits(&want), "n={n} t={threshold}");
                assert_eq!(got.mask, reference.mask);
                for (g, r) in got.channels.iter().zip(&reference.channels) {
                    assert_eq!(g.center.to_bits(), r.center.to_bits(), "{g:?} {r:?}");
                    assert_eq!(g.scale.to_bits(), r.scale.to_bits(), "{g:?} {r:?}");
                    assert_eq!(g.count, r.count);
                }
                let mut buf = x.clone();
                let flagged = remove_outliers_in_place(&mut buf, n_cols, threshold).unwrap();
                assert_eq!(bits(&buf), bits(&want));
                assert_eq!(flagged.mask, reference.mask);
                assert_eq!(flagged.channels, got.channels);
                let nan = want.iter().filter(|v| v.is_nan()).count();
                assert_eq!((flagged.gaps, reference.gaps), (nan, nan));
                let mut into = vec![7.0; x.len()];
                assert_eq!(
                    remove_outliers_into(&x, &mut into, n_cols, threshold).unwrap(),
                    flagged
                );
                assert_eq!(bits(&into), bits(&want));
            }
        }
    }

    #[test]
    fn into_and_in_place_errors_leave_the_output_alone() {
        let mut x = hostile(SAMPLED_MIN_ROWS + 5, 3);
        for i in (0..x.len()).skip(1).step_by(3) {
            x[i] = f64::NAN; // column 1 has no finite sample
        }
        let mut out = vec![7.0; x.len()];
        let e = remove_outliers_into(&x, &mut out, 3, 5.0)
            .unwrap_err()
            .to_string();
        assert!(e.contains("column 1 has 0 finite"), "{e}");
        assert!(out.iter().all(|&v| v == 7.0));
        let before = bits(&x);
        assert!(remove_outliers_in_place(&mut x, 3, 5.0).is_err());
        assert_eq!(bits(&x), before);
        assert!(remove_outliers_into(&x, &mut out[1..], 3, 5.0).is_err());
        x[5] = f64::INFINITY;
        assert!(detrend_into(&x, &mut out, 3, 100.0, 1).is_err());
        assert!(out.iter().all(|&v| v == 7.0));
    }

    /// The implementation before the grouped kernels (copied verbatim): the bit-for-bit
    /// reference of the residual and the coefficients.
    #[allow(clippy::needless_range_loop)]
    fn detrend_reference(
        data: &mut [f64],
        n_cols: usize,
        fs: f64,
        order: usize,
    ) -> Result<Vec<f64>> {
        let n = rows(data, n_cols)?;
        let t0 = validate::sample_period(fs)?;
        if !(1..=2).contains(&order) {
            return Err(Error::invalid(
                "order",
                format!("must be 1 (linear) or 2 (quadratic), got {order}"),
            ));
        }
        if let Some(index) = data.iter().position(|v| v.is_infinite()) {
            return Err(Error::NonFinite {
                name: "data",
                index,
            });
        }
        let dim = order + 1;
        let needed = order + 2;
        validate::min_len("data", n, needed)?;
        // Each channel relative to its first finite sample (the sums then hold deviations only).
        let reference: Vec<f64> = (0..n_cols)
            .map(|j| {
                data.iter()
                    .skip(j)
                    .step_by(n_cols)
                    .copied()
                    .find(|v| v.is_finite())
                    .unwrap_or(0.0)
            })
            .collect();
        let block_len = BLOCK_ROWS * n_cols;
        let partial: Vec<(Vec<Normal>, Vec<usize>)> = data
            .par_chunks(block_len)
            .enumerate()
            .map(|(b, block)| {
                let mut sums = vec![[0.0_f64; 9]; n_cols];
                let mut counts = vec![0_usize; n_cols];
                for (r, row) in block.chunks_exact(n_cols).enumerate() {
                    let p = legendre(b * BLOCK_ROWS + r, n);
                    for (j, &v) in row.iter().enumerate() {
                        if v.is_nan() {
                            continue;
                        }
                        let y = v - reference[j];
                        let s = &mut sums[j];
                        s[0] += 1.0;
                        s[1] += p[1];
                        s[2] += p[2];
                        s[3] += p[1] * p[1];
                        s[4] += p[1] * p[2];
                        s[5] += p[2] * p[2];
                        s[6] += y;
                        s[7] += y * p[1];
                        s[8] += y * p[2];
                        counts[j] += 1;
                    }
                }
                (sums, counts)
            })
            .collect();
        let mut sums = vec![[0.0_f64; 9]; n_cols];
        let mut counts = vec![0_usize; n_cols];
        for (s, c) in &partial {
            add_normal(&mut sums, s);
            for (a, b) in counts.iter_mut().zip(c) {
                *a += b;
            }
        }
        drop(partial);
        let mut legendre_coefficients = Vec::with_capacity(n_cols);
        for j in 0..n_cols {
            if counts[j] < needed {
                return Err(too_few_finite(j, counts[j], needed));
            }
            let beta = solve_spd(&sums[j], dim).ok_or_else(|| Error::Singular {
                reason: format!("detrend of data column {j}: too few distinct sample times"),
            })?;
            legendre_coefficients.push(beta);
        }
        data.par_chunks_mut(block_len)
            .enumerate()
            .for_each(|(b, block)| {
                for (r, row) in block.chunks_exact_mut(n_cols).enumerate() {
                    let p = legendre(b * BLOCK_ROWS + r, n);
                    for (j, v) in row.iter_mut().enumerate() {
                        let beta = &legendre_coefficients[j];
                        let model = beta[0] + beta[1] * p[1] + beta[2] * p[2];
                        *v = (*v - reference[j]) - model;
                    }
                }
            });
        // P(u) with u = a·t − 1, a = 2/((n − 1)·t0):
        //   β0 + β1(a t − 1) + β2(1.5 (a t − 1)² − 0.5)
        //   = (β0 − β1 + β2) + (β1 − 3β2)·a·t + 1.5·β2·a²·t².
        let a = if n > 1 {
            2.0 / ((n - 1) as f64 * t0)
        } else {
            0.0
        };
        let mut coefficients = Vec::with_capacity(n_cols * dim);
        for (beta, reference) in legendre_coefficients.iter().zip(&reference) {
            coefficients.push(reference + beta[0] - beta[1] + beta[2]);
            coefficients.push((beta[1] - 3.0 * beta[2]) * a);
            if order == 2 {
                coefficients.push(1.5 * beta[2] * a * a);
            }
        }
        Ok(coefficients)
    }

    #[test]
    fn detrend_equals_the_reference_bit_for_bit() {
        // Gaps in some blocks only, a gap-free column, 11 columns (groups of 8 and 3).
        let n = 3 * BLOCK_ROWS + 101;
        let z = crate::random::normal_vec(n * 11, 21);
        let x: Vec<f64> = z
            .iter()
            .enumerate()
            .map(|(i, v)| {
                let (r, j) = (i / 11, i % 11);
                if j % 3 == 1 && (r % 977 == 5 || r / BLOCK_ROWS == 1 && r % 13 == 0) {
                    f64::NAN
                } else {
                    v + 1e-3 * r as f64 * j as f64 + 5.0
                }
            })
            .collect();
        for n_cols in [11, 1] {
            let x = if n_cols == 1 { &x[..n] } else { &x[..] };
            for order in [1, 2] {
                let mut want = x.to_vec();
                let c = detrend_reference(&mut want, n_cols, 100.0, order).unwrap();
                let got = detrend(x, n_cols, 100.0, order).unwrap();
                assert_eq!(bits(&got.data), bits(&want));
                assert_eq!(bits(&got.coefficients), bits(&c));
            }
        }
    }

    #[test]
    fn detrend_variants_agree_and_count_the_gaps() {
        let x = messy(3 * BLOCK_ROWS + 17);
        for order in [1, 2] {
            let d = detrend(&x, 3, 100.0, order).unwrap();
            let mut into = vec![0.0; x.len()];
            let a = detrend_into(&x, &mut into, 3, 100.0, order).unwrap();
            let mut again = x.clone();
            let b = detrend_in_place_flagged(&mut again, 3, 100.0, order).unwrap();
            assert_eq!(bits(&into), bits(&d.data));
            assert_eq!(bits(&again), bits(&d.data));
            assert_eq!(bits(&a.coefficients), bits(&d.coefficients));
            assert_eq!(a, b);
            assert_eq!(a.gaps, 1);
        }
    }

    #[test]
    fn outliers_flag_a_spike_and_keep_gaps() {
        let mut x: Vec<f64> = (0..101).map(|i| ((i * 37) % 11) as f64 - 5.0).collect();
        x[50] = 1e6;
        x[7] = f64::NAN;
        let r = remove_outliers(&x, 1, 5.0).unwrap();
        assert_eq!(r.channels[0].count, 1);
        assert!(r.mask[50] && !r.mask[7]);
        assert!(r.data[50].is_nan() && r.data[7].is_nan());
        assert_eq!(r.data[0], x[0]);
        let none = remove_outliers(&x, 1, 1e300).unwrap();
        assert_eq!(none.channels[0].count, 0);
    }

    #[test]
    fn outliers_of_a_quantised_channel_use_the_mean_deviation() {
        // 90 % zeros: the MAD is 0, the mean absolute deviation is not.
        let mut x = vec![0.0; 100];
        for v in x.iter_mut().take(10) {
            *v = 1.0;
        }
        let r = remove_outliers(&x, 1, 5.0).unwrap();
        assert!((r.channels[0].scale - MEAN_AD_TO_SD * 0.1).abs() < 1e-15);
        assert_eq!(r.channels[0].count, 10); // 1/0.125 = 8 > 5
        let constant = remove_outliers(&[2.0; 10], 1, 1e-9).unwrap();
        assert_eq!(constant.channels[0].count, 0);
    }

    #[test]
    fn outlier_errors_name_the_argument() {
        let x = [1.0, 2.0, 3.0, 4.0];
        for t in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            let e = remove_outliers(&x, 1, t).unwrap_err().to_string();
            assert!(e.contains("threshold"), "{e}");
        }
        let e = remove_outliers(&[1.0, f64::NAN, f64::NAN, 2.0], 1, 5.0).unwrap_err();
        assert!(e.to_string().contains("column 0 has 2 finite"), "{e}");
        assert!(remove_outliers(&x, 3, 5.0).is_err());
        assert!(remove_outliers(&x, 0, 5.0).is_err());
    }

    #[test]
    fn detrend_removes_an_exact_polynomial() {
        let fs = 10.0;
        let n = 20_001;
        let x: Vec<f64> = (0..n)
            .flat_map(|i| {
                let t = i as f64 / fs;
                [3.0 + 0.5 * t, -1.0 + 0.01 * t - 2e-4 * t * t]
            })
            .collect();
        let r = detrend(&x, 2, fs, 2).unwrap();
        assert!(r.data.iter().all(|v| v.abs() < 1e-9), "residual");
        let c = &r.coefficients;
        assert!((c[0] - 3.0).abs() < 1e-9 && (c[1] - 0.5).abs() < 1e-12 && c[2].abs() < 1e-14);
        assert!((c[3] + 1.0).abs() < 1e-9 && (c[4] - 0.01).abs() < 1e-12);
        assert!((c[5] + 2e-4).abs() < 1e-15);
    }

    #[test]
    fn detrend_skips_gaps_and_checks_its_arguments() {
        let mut x: Vec<f64> = (0..100).map(|i| 2.0 * i as f64).collect();
        x[10] = f64::NAN;
        let r = detrend(&x, 1, 1.0, 1).unwrap();
        assert!(r.data[10].is_nan());
        assert!((r.coefficients[1] - 2.0).abs() < 1e-12);
        assert!(
            detrend(&x, 1, 1.0, 3)
                .unwrap_err()
                .to_string()
                .contains("order")
        );
        assert!(
            detrend(&x, 1, 0.0, 1)
                .unwrap_err()
                .to_string()
                .contains("fs")
        );
        let mut inf = x.clone();
        inf[3] = f64::INFINITY;
        assert!(matches!(
            detrend(&inf, 1, 1.0, 1),
            Err(Error::NonFinite { index: 3, .. })
        ));
        let e = detrend(&[f64::NAN; 10], 1, 1.0, 1).unwrap_err().to_string();
        assert!(e.contains("column 0 has 0 finite"), "{e}");
    }

    #[test]
    fn envelope_bins_are_min_and_max() {
        let x = [
            1.0,
            10.0,
            f64::NAN,
            20.0,
            3.0,
            30.0,
            4.0,
            f64::NAN,
            0.5,
            f64::NAN,
        ];
        // 5 rows × 2 columns, 2 bins: rows 0..2 and 2..5.
        let e = minmax_envelope(&x, 2, 2).unwrap();
        assert_eq!(e.starts, vec![0, 2, 5]);
        assert_eq!(e.lower[..2], [1.0, 10.0]);
        assert_eq!(e.upper[..2], [1.0, 20.0]);
        assert_eq!(e.lower[2..], [0.5, 30.0]);
        assert_eq!(e.upper[2..], [4.0, 30.0]);
        let all_nan = minmax_envelope(&[f64::NAN, 1.0], 1, 2).unwrap();
        assert!(all_nan.lower[0].is_nan() && all_nan.upper[1] == 1.0);
        assert_eq!(minmax_envelope(&x, 2, 100).unwrap().starts.len(), 6);
        assert!(
            minmax_envelope(&x, 2, 0)
                .unwrap_err()
                .to_string()
                .contains("bins")
        );
    }
}
