//! Is a log static? Rate steps, motion segments and warm-up trends, found in block means at
//! several scales and judged against the record's own noise at each scale.
//!
//! An Allan analysis assumes a stationary record: a static sensor whose rate is noise about a
//! constant bias. A rotation in the middle of the log, a step in the rate (a knock, a mode
//! change) or a warm-up drift over the first minutes is not noise, and the Allan curve and the
//! noise terms fitted to it describe that event instead of the sensor. This module finds the
//! common cases cheaply (O(N) for the block means, O(K log K) for the rest with K ≤ 4096
//! blocks) and says where they are, so the user can select around them.
//!
//! # The statistic
//!
//! The record of `n` samples is cut into `K₀ ≈ 4096` blocks of `L₀ = max(16, ⌈n/4096⌉)`
//! samples ([`block_length`]); coarser scales average pairs of blocks (`L_s = 2^s·L₀`) down to
//! [`MIN_BLOCKS`] blocks. At each scale the differences of consecutive block means
//! `d_j = m_{j+1} − m_j` are what the Allan variance is made of: for any stationary noise,
//! `E[d_j²] = 2σ²_A(τ_s)` with `τ_s = L_s/fs` — quantisation, white noise, bias instability,
//! rate random walk, Gauss–Markov and filtered noise alike, whatever the shape of the Allan
//! curve. So the record's own scale of `d` at that τ, `ŝ = 1.4826·MAD(d)` (robust: a few
//! disturbed blocks do not inflate it), is the noise yardstick, and a difference is a change
//! the noise cannot explain when `|d_j − median(d)| > t_K·ŝ`.
//!
//! # The threshold
//!
//! Under the null (a Gaussian stationary record: every noise the simulator and the IEEE-952
//! model know is Gaussian, and at `L ≥ 16` samples block means of quantised data are nearly so)
//! `d_j/σ_d` is standard normal. With `K'` differences at a scale, Bonferroni gives the per-scale
//! false-alarm level [`FALSE_ALARM`] (10⁻⁶) for `z_K = Φ⁻¹(1 − α/(2K'))` (5.3 at K' = 31, 6.4 at
//! 4095). `ŝ` is itself estimated from `K'` values: the MAD of a normal sample has a relative
//! standard deviation of about `1.166/√K'` (Hampel 1974), so the threshold divides `z_K` by
//! `1 − 3·1.166/√K'`, the value of `ŝ/σ_d` three standard deviations low: `t_K` is 6.8 at 4095
//! differences, 9.8 at 63 and 14 at 31. The per-scale false-alarm rate is therefore ≤ 10⁻⁶ plus
//! the chance that ŝ is more than three standard deviations low (≈ 10⁻³ by itself, but then
//! the largest `|d|` must also exceed the lowered threshold). Random walk and bias instability
//! make `d` larger at long τ, and `ŝ` grows with them: the test compares each scale with
//! itself, so long logs with strong random walk do not trigger it (`tests/test_stationarity.py`
//! checks many seeds of the simulated logs the documentation uses).
//!
//! # From flagged differences to disturbances
//!
//! Flagged boundaries closer than three blocks form one region. Each region is classified by
//! the median block means just before and after it (up to 8 blocks each side, not crossing
//! another region): a region at the very start whose flagged differences all have one sign is
//! a [`Kind::Trend`] (warm-up); a region whose levels before and after agree is a
//! [`Kind::Segment`] (the rate went away and came back: a motion); else a [`Kind::Step`]. Two
//! consecutive steps of opposite sign and equal size (within a quarter) are one segment. The
//! finest scale that sees an event locates it; coarser scales add only events no finer scale
//! saw (a start trend is extended to the latest end any scale sees).
//!
//! A warm-up is a smooth drift: its differences are largest at the start and, over a long
//! first part of the record, inflate the whole record's spread. So each scale also tests the
//! differences of its first quarter against the spread of its *second half* alone (Bonferroni
//! over the positions tested): a run of at least two same-sign differences from the first block
//! on is a trend. Sensitivity, measured on simulated 100 Hz logs of the documentation's MEMS
//! gyro: a 10-minute exponential warm-up of 0.5 deg/s is found on 1 h, one of 0.2 deg/s on
//! 2.8 h (not on 1 h: the coarsest scale of a 1 h log is 56 s).
//!
//! Records shorter than `2·MIN_BLOCKS·MIN_BLOCK` samples are not checked ([`Report::checked`]).

use crate::allan::{Column, ldexp};
use crate::error::{Error, Result};
use crate::stats;

/// Blocks at the finest scale (at most; fewer for short records).
pub const TARGET_BLOCKS: usize = 4096;
/// Fewest samples per block (block means of quantised data are then close to Gaussian).
pub const MIN_BLOCK: usize = 16;
/// Fewest blocks at a scale (coarser scales are not tested).
pub const MIN_BLOCKS: usize = 32;
/// Family-wise false-alarm level of one scale (Bonferroni over its differences).
pub const FALSE_ALARM: f64 = 1e-6;
/// Relative standard deviation of the normal-sample MAD, times √K (Hampel 1974).
const MAD_RSD: f64 = 1.166;
/// MAD to standard deviation for normal data.
const MAD_TO_SD: f64 = 1.482_602_218_505_602;
/// Blocks each side of a region whose median is its level.
const LEVEL_BLOCKS: usize = 8;

/// Samples per block at the finest scale for a record of `n` samples.
pub fn block_length(n: usize) -> usize {
    MIN_BLOCK.max(n.div_ceil(TARGET_BLOCKS))
}

/// Block means of a rate record at the finest scale.
#[derive(Debug, Clone, PartialEq)]
pub struct BlockMeans {
    /// Mean of each block (NaN for a block without a finite sample). Only differences matter:
    /// a constant may have been removed.
    pub means: Vec<f64>,
    /// Samples per block.
    pub length: usize,
    /// Samples of the record (the last `n mod length` are in no block).
    pub n: usize,
}

/// Block means of a rate column (non-finite samples skipped; one pass).
pub fn block_means(column: Column<'_>) -> BlockMeans {
    let n = column.len();
    let length = block_length(n);
    let k = n / length;
    let means = (0..k)
        .map(|j| {
            let (mut sum, mut count) = (0.0_f64, 0_usize);
            for i in j * length..(j + 1) * length {
                let v = column.get(i);
                if v.is_finite() {
                    sum += v;
                    count += 1;
                }
            }
            if count == 0 {
                f64::NAN
            } else {
                sum / count as f64
            }
        })
        .collect();
    BlockMeans { means, length, n }
}

/// Block means read off an angle series `x` (`x_i − x_0 = t0·Σ_{k<i} Ω_k·2^-scale` up to a
/// removed constant rate): `(x_{(j+1)L} − x_{jL})/(L·t0)`, restored by `2^scale`. O(K): the
/// Allan analysis calls it on the series it has already built.
pub fn block_means_from_angle(x: &[f64], t0: f64, scale: i32) -> BlockMeans {
    let n = x.len().saturating_sub(1);
    let length = block_length(n);
    let k = n / length;
    let width = length as f64 * t0;
    let means = (0..k)
        .map(|j| ldexp((x[(j + 1) * length] - x[j * length]) / width, scale))
        .collect();
    BlockMeans { means, length, n }
}

/// What kind of disturbance.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// The rate changes level and stays there.
    Step,
    /// The rate leaves its level and comes back (a motion, a knock).
    Segment,
    /// A monotone drift over the first part of the record (warm-up).
    Trend,
}

impl Kind {
    /// `"step"`, `"segment"` or `"trend"`.
    pub fn name(self) -> &'static str {
        match self {
            Kind::Step => "step",
            Kind::Segment => "segment",
            Kind::Trend => "trend",
        }
    }
}

/// One disturbance, in samples of the record.
#[derive(Debug, Clone, PartialEq)]
pub struct Disturbance {
    /// Its kind.
    pub kind: Kind,
    /// First sample of the blocks it affects.
    pub start: usize,
    /// End (exclusive) of the blocks it affects.
    pub stop: usize,
    /// Sample at the largest change (a step's position).
    pub at: usize,
    /// Step: level after − level before; segment: the largest excursion from the level before
    /// (signed); trend: the level at the start − the level after it. In the data's unit.
    pub size: f64,
    /// Largest `|d − median(d)|/ŝ` of its differences.
    pub z: f64,
    /// Samples per block of the scale that located it.
    pub block: usize,
    /// The threshold `t_K` of that scale.
    pub threshold: f64,
}

/// The result of [`check`].
#[derive(Debug, Clone, PartialEq)]
pub struct Report {
    /// Disturbances in order of their start.
    pub disturbances: Vec<Disturbance>,
    /// Whether the record was long enough to be checked.
    pub checked: bool,
    /// Samples of the record.
    pub n: usize,
    /// Samples per block at the finest scale.
    pub block: usize,
    /// The longest stretch `[start, stop)` free of disturbances (the whole record when none).
    pub quiet: (usize, usize),
}

/// A region of flagged boundaries at one scale, in blocks of that scale.
struct Region {
    first: usize, // first block affected
    last: usize,  // last block affected (inclusive)
    peak: usize,  // boundary with the largest |d|: between blocks peak and peak + 1
    z: f64,
    monotone: bool,
    peak_d: f64,
}

fn pairwise(means: &[f64]) -> Vec<f64> {
    means
        .chunks_exact(2)
        .map(|p| match (p[0].is_finite(), p[1].is_finite()) {
            (true, true) => 0.5 * (p[0] + p[1]),
            (true, false) => p[0],
            (false, true) => p[1],
            _ => f64::NAN,
        })
        .collect()
}

fn median_of(values: impl Iterator<Item = f64>) -> Option<f64> {
    let mut v: Vec<f64> = values.filter(|x| x.is_finite()).collect();
    if v.is_empty() {
        None
    } else {
        Some(stats::median_in_place(&mut v))
    }
}

/// The threshold `t_K` for `k` differences (module docs).
pub fn threshold(k: usize) -> Result<f64> {
    tested_threshold(k, k)
}

/// The threshold for `tests` differences judged against a spread estimated from `k`.
fn tested_threshold(tests: usize, k: usize) -> Result<f64> {
    if k < 2 || tests == 0 {
        return Err(Error::invalid("k", "at least 2 differences are needed"));
    }
    let z = stats::chi2_isf(FALSE_ALARM / tests as f64, 1.0)?.sqrt();
    let low = 1.0 - 3.0 * MAD_RSD / (k as f64).sqrt();
    Ok(if low > 0.05 { z / low } else { f64::INFINITY })
}

/// Robust centre and spread of values (the RMS about the median for lattice data).
fn centre_spread(values: &[f64]) -> Option<(f64, f64)> {
    let centre = median_of(values.iter().copied())?;
    let mut scale = MAD_TO_SD * median_of(values.iter().map(|v| (v - centre).abs()))?;
    if scale.is_nan() || scale <= 0.0 {
        let ss: f64 = values.iter().map(|v| (v - centre).powi(2)).sum();
        scale = (ss / values.len() as f64).sqrt();
    }
    (scale > 0.0 && scale.is_finite()).then_some((centre, scale))
}

/// A warm-up at one scale: a run of same-sign differences from the first block on, each
/// beyond the spread of the *second half's* differences (a trend over the first part of a
/// log inflates the whole record's spread, not the second half's). Tested positions: the first
/// quarter (Bonferroni over them).
fn start_trend(means: &[f64], length: usize) -> Result<Option<Disturbance>> {
    let k = means.len();
    let d: Vec<f64> = means.windows(2).map(|w| w[1] - w[0]).collect();
    let late: Vec<f64> = d[d.len() / 2..]
        .iter()
        .copied()
        .filter(|v| v.is_finite())
        .collect();
    if late.len() < MIN_BLOCKS / 2 - 1 {
        return Ok(None);
    }
    let Some((centre, scale)) = centre_spread(&late) else {
        return Ok(None);
    };
    let tests = (d.len() / 4).max(1);
    let t = tested_threshold(tests, late.len())?;
    let mut run = 0;
    let mut z_max = 0.0_f64;
    let mut sign = 0.0_f64;
    for &v in &d[..tests] {
        let z = (v - centre).abs() / scale;
        let s = (v - centre).signum();
        if z.is_nan() || z <= t || (sign != 0.0 && s != sign) {
            break;
        }
        sign = s;
        z_max = z_max.max(z);
        run += 1;
    }
    if run < 2 {
        return Ok(None);
    }
    let after = median_of(
        means[run + 1..k.min(run + 1 + LEVEL_BLOCKS)]
            .iter()
            .copied(),
    );
    let first = means.iter().copied().find(|v| v.is_finite());
    let (Some(after), Some(first)) = (after, first) else {
        return Ok(None);
    };
    Ok(Some(Disturbance {
        kind: Kind::Trend,
        start: 0,
        stop: (run + 1) * length,
        at: length,
        size: first - after,
        z: z_max,
        block: length,
        threshold: t,
    }))
}

/// Adds `d` to `events`: the finest scale that sees an event keeps it; a start trend absorbs
/// what overlaps it at the start and extends to the latest end any scale sees.
fn add_event(events: &mut Vec<Disturbance>, d: Disturbance) {
    let (start, stop) = (d.start, d.stop);
    let overlaps = |e: &Disturbance| start < e.stop && e.start < stop;
    if d.kind == Kind::Trend {
        let mut merged = d;
        events.retain(|e| {
            if overlaps(e) && (e.kind == Kind::Trend || e.start == 0) {
                if e.stop > merged.stop {
                    merged.stop = e.stop;
                }
                merged.z = merged.z.max(e.z);
                false
            } else {
                true
            }
        });
        events.push(merged);
    } else if !events.iter().any(overlaps) {
        events.push(d);
    }
}

/// The regions of one scale and the scale's yardstick.
fn regions(means: &[f64]) -> Result<Option<(Vec<Region>, f64, f64)>> {
    let d: Vec<(usize, f64)> = means
        .windows(2)
        .enumerate()
        .filter(|(_, w)| w[0].is_finite() && w[1].is_finite())
        .map(|(j, w)| (j, w[1] - w[0]))
        .collect();
    if d.len() < MIN_BLOCKS - 1 {
        return Ok(None);
    }
    let values: Vec<f64> = d.iter().map(|p| p.1).collect();
    // None: a constant record, nothing to find (lattice data: the RMS, see centre_spread)
    let Some((centre, scale)) = centre_spread(&values) else {
        return Ok(None);
    };
    let t = threshold(d.len())?;
    let mut out: Vec<Region> = Vec::new();
    for &(j, v) in &d {
        let z = (v - centre).abs() / scale;
        if z <= t {
            continue;
        }
        let sign = v > centre;
        match out.last_mut() {
            Some(r) if j <= r.last + 2 => {
                r.last = j + 1;
                if z > r.z {
                    r.z = z;
                    r.peak = j;
                    r.peak_d = v - centre;
                }
                r.monotone &= sign == (r.peak_d > 0.0);
            }
            _ => out.push(Region {
                first: j,
                last: j + 1,
                peak: j,
                z,
                monotone: true,
                peak_d: v - centre,
            }),
        }
    }
    Ok(Some((out, scale, t)))
}

/// The disturbances one scale sees (samples per block `length`).
fn classify(
    means: &[f64],
    length: usize,
    regions: &[Region],
    t: f64,
    scale: f64,
) -> Vec<Disturbance> {
    let k = means.len();
    let mut found: Vec<Disturbance> = Vec::new();
    for (i, r) in regions.iter().enumerate() {
        let lo = if i == 0 { 0 } else { regions[i - 1].last + 1 };
        let hi = if i + 1 < regions.len() {
            regions[i + 1].first
        } else {
            k
        };
        let before = median_of(
            means[lo.max(r.first.saturating_sub(LEVEL_BLOCKS))..r.first]
                .iter()
                .copied(),
        );
        let after_end = hi.min(r.last + 1 + LEVEL_BLOCKS);
        let after = if r.last + 1 < after_end {
            median_of(means[r.last + 1..after_end].iter().copied())
        } else {
            None
        };
        let inside = &means[r.first..=r.last];
        let excursion = |level: f64| {
            inside
                .iter()
                .filter(|v| v.is_finite())
                .map(|v| v - level)
                .fold(0.0_f64, |a, v| if v.abs() > a.abs() { v } else { a })
        };
        let (kind, size) = match (before, after) {
            (None, Some(a)) if r.monotone && r.last > r.first + 1 => {
                let start = means[r.first..=r.last]
                    .iter()
                    .copied()
                    .find(|v| v.is_finite());
                (Kind::Trend, start.unwrap_or(a) - a)
            }
            (Some(b), Some(a)) => {
                let e = excursion(b);
                if (a - b).abs() <= (t * scale).max(0.25 * e.abs()) && r.last > r.first + 1 {
                    (Kind::Segment, e)
                } else {
                    (Kind::Step, a - b)
                }
            }
            _ => (Kind::Step, r.peak_d),
        };
        found.push(Disturbance {
            kind,
            start: r.first * length,
            stop: (r.last + 1) * length,
            at: (r.peak + 1) * length,
            size,
            z: r.z,
            block: length,
            threshold: t,
        });
    }
    // A step and its return: one segment.
    let mut merged: Vec<Disturbance> = Vec::new();
    for dist in found {
        if let Some(prev) = merged.last_mut() {
            if prev.kind == Kind::Step
                && dist.kind == Kind::Step
                && prev.size * dist.size < 0.0
                && (prev.size + dist.size).abs() <= 0.25 * prev.size.abs().max(dist.size.abs())
            {
                prev.kind = Kind::Segment;
                prev.stop = dist.stop;
                prev.z = prev.z.max(dist.z);
                continue;
            }
        }
        merged.push(dist);
    }
    merged
}

/// Steps, segments and trends in a record's block means (module docs).
pub fn check(blocks: &BlockMeans) -> Result<Report> {
    let n = blocks.n;
    let mut report = Report {
        disturbances: Vec::new(),
        checked: false,
        n,
        block: blocks.length,
        quiet: (0, n),
    };
    if blocks.length == 0 || blocks.means.len() < 2 * MIN_BLOCKS {
        return Ok(report);
    }
    report.checked = true;
    let mut means = blocks.means.clone();
    let mut length = blocks.length;
    let mut events: Vec<Disturbance> = Vec::new();
    while means.len() >= MIN_BLOCKS {
        if let Some((found, scale, t)) = regions(&means)? {
            for d in classify(&means, length, &found, t, scale) {
                add_event(&mut events, d);
            }
        }
        if let Some(d) = start_trend(&means, length)? {
            add_event(&mut events, d);
        }
        means = pairwise(&means);
        length *= 2;
    }
    events.sort_by_key(|e| e.start);
    // The longest quiet stretch between disturbances (and the record's ends); the first of
    // equally long ones.
    let mut best = (0, 0);
    let mut free_from = 0;
    for e in events
        .iter()
        .map(|e| (e.start, e.stop.min(n)))
        .chain([(n, n)])
    {
        if e.0 > free_from && e.0 - free_from > best.1 - best.0 {
            best = (free_from, e.0);
        }
        free_from = free_from.max(e.1);
    }
    report.quiet = best;
    report.disturbances = events;
    Ok(report)
}

/// [`check`] of each column of a row-major (samples × axes) buffer.
pub fn check_matrix(data: &[f64], n_axes: usize) -> Result<Vec<Report>> {
    (0..n_axes)
        .map(|axis| check(&block_means(Column::of(data, n_axes, axis)?)))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn noise(n: usize, seed: u64) -> Vec<f64> {
        crate::random::normal_vec(n, seed)
    }

    #[test]
    fn white_noise_is_static() {
        for seed in 0..20 {
            let x = noise(200_000, seed);
            let r = check(&block_means(Column::contiguous(&x))).unwrap();
            assert!(r.checked && r.disturbances.is_empty(), "{seed}: {r:?}");
            assert_eq!(r.quiet, (0, 200_000));
        }
    }

    #[test]
    fn a_step_is_found_where_it_is() {
        let mut x = noise(200_000, 1);
        for v in &mut x[123_456..] {
            *v += 1.0;
        }
        let r = check(&block_means(Column::contiguous(&x))).unwrap();
        assert_eq!(r.disturbances.len(), 1, "{r:?}");
        let d = &r.disturbances[0];
        assert_eq!(d.kind, Kind::Step);
        assert!(d.start <= 123_456 && 123_456 <= d.stop && d.stop - d.start <= 4 * d.block);
        assert!(d.at.abs_diff(123_456) <= d.block);
        assert!((d.size - 1.0).abs() < 0.1, "{}", d.size);
        assert_eq!(r.quiet, (0, d.start));
    }

    #[test]
    fn a_segment_and_a_trend_are_told_apart() {
        let mut x = noise(400_000, 2);
        for v in &mut x[200_000..203_000] {
            *v += 5.0;
        }
        for (i, v) in x.iter_mut().enumerate() {
            *v += 3.0 * (-(i as f64) / 30_000.0).exp();
        }
        let r = check(&block_means(Column::contiguous(&x))).unwrap();
        let kinds: Vec<Kind> = r.disturbances.iter().map(|d| d.kind).collect();
        assert_eq!(kinds, vec![Kind::Trend, Kind::Segment], "{r:?}");
        let seg = &r.disturbances[1];
        assert!(seg.start <= 200_000 && seg.stop >= 203_000 && seg.stop - seg.start < 4000);
        assert!((seg.size - 5.0).abs() < 0.5);
        assert_eq!(r.disturbances[0].start, 0);
        assert!(r.disturbances[0].size > 1.0);
    }

    #[test]
    fn block_means_from_the_angle_series_agree() {
        let x = noise(100_000, 3);
        let t0 = 0.01;
        let mut angle = vec![0.0];
        for v in &x {
            let last = *angle.last().unwrap();
            angle.push(last + t0 * v);
        }
        let direct = block_means(Column::contiguous(&x));
        let read = block_means_from_angle(&angle, t0, 0);
        assert_eq!(direct.length, read.length);
        for (a, b) in direct.means.iter().zip(&read.means) {
            assert!((a - b).abs() < 1e-9, "{a} {b}");
        }
    }

    #[test]
    fn short_and_constant_records() {
        let r = check(&block_means(Column::contiguous(&[1.0; 100]))).unwrap();
        assert!(!r.checked && r.disturbances.is_empty());
        let flat = vec![1.0; 100_000];
        let r = check(&block_means(Column::contiguous(&flat))).unwrap();
        assert!(r.checked && r.disturbances.is_empty());
        let mut step = vec![1.0; 100_000];
        step[60_000..].fill(2.0);
        let r = check(&block_means(Column::contiguous(&step))).unwrap();
        assert_eq!(r.disturbances.len(), 1);
        assert_eq!(r.disturbances[0].kind, Kind::Step);
        assert!(threshold(1).is_err());
        assert!((threshold(4095).unwrap() - 6.8).abs() < 0.2);
    }
}
