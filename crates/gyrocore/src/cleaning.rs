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

/// The output of [`remove_outliers_in_place`] (the data is the caller's buffer).
#[derive(Debug, Clone, PartialEq)]
pub struct OutliersFlagged {
    /// `true` where a sample was flagged, row-major `(n, k)`.
    pub mask: Vec<bool>,
    /// One entry per channel.
    pub channels: Vec<OutlierStats>,
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
    let mut out = data.to_vec();
    let flagged = remove_outliers_in_place(&mut out, n_cols, threshold)?;
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
    let n = rows(data, n_cols)?;
    validate::positive("threshold", threshold)?;
    let view: &[f64] = data;
    validate::min_len("data", n, MIN_OUTLIER_SAMPLES)?;
    // One scratch column per worker, reused for its columns (first-touch page faults of a
    // fresh buffer per column cost more than the selection itself); column j goes to worker
    // j mod workers, and each column's statistics do not depend on the assignment.
    let workers = n_cols.min(rayon::current_num_threads()).max(1);
    let per_worker: Vec<Vec<ColumnStats>> = (0..workers)
        .into_par_iter()
        .map(|w| {
            let mut scratch = Vec::with_capacity(n);
            (w..n_cols)
                .step_by(workers)
                .map(|j| {
                    finite_column_into(view, n_cols, j, &mut scratch);
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
    let channels: Vec<(f64, f64)> = ordered
        .into_iter()
        .map(|(_, stats)| stats)
        .collect::<Result<_>>()?;
    let mut mask = vec![false; data.len()];
    let block_len = BLOCK_ROWS * n_cols;
    let block_counts: Vec<Vec<usize>> = data
        .par_chunks_mut(block_len)
        .zip(mask.par_chunks_mut(block_len))
        .map(|(out_block, mask_block)| {
            let mut counts = vec![0_usize; n_cols];
            for (row, row_mask) in out_block
                .chunks_exact_mut(n_cols)
                .zip(mask_block.chunks_exact_mut(n_cols))
            {
                for (j, (v, flag)) in row.iter_mut().zip(row_mask.iter_mut()).enumerate() {
                    let (center, scale) = channels[j];
                    let deviation = (*v - center).abs();
                    // deviation/scale > threshold, with 0/0 (a constant channel) never an
                    // outlier and an infinite sample always one.
                    let outlier = if scale > 0.0 {
                        deviation / scale > threshold
                    } else {
                        deviation > 0.0
                    };
                    if outlier {
                        *v = f64::NAN;
                        *flag = true;
                        counts[j] += 1;
                    }
                }
            }
            counts
        })
        .collect();
    let mut counts = vec![0_usize; n_cols];
    for block in &block_counts {
        for (total, c) in counts.iter_mut().zip(block) {
            *total += c;
        }
    }
    Ok(OutliersFlagged {
        mask,
        channels: channels
            .into_iter()
            .zip(counts)
            .map(|((center, scale), count)| OutlierStats {
                center,
                scale,
                count,
            })
            .collect(),
    })
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
    let mut out = data.to_vec();
    let coefficients = detrend_in_place(&mut out, n_cols, fs, order)?;
    Ok(Detrended {
        data: out,
        coefficients,
    })
}

/// [`detrend`] writing the residual into `data` itself; returns the coefficients (as
/// [`Detrended::coefficients`]). The residual is that of [`detrend`], bit for bit: the fit
/// reads every sample before the first one is overwritten. A caller that cleans repeatedly
/// reuses one buffer (and the outlier step's output is detrended where it lies: one copy of
/// the data for both steps).
///
/// # Errors
/// As [`detrend`]; `data` is unchanged when an error is returned.
pub fn detrend_in_place(
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
