//! Out-of-core overlapping Allan analysis: a record larger than memory, read in pieces.
//!
//! A [`Source`] hands out consecutive samples on request (a memory-mapped `.npy` read with
//! `readinto`, a bag read message by message). [`analyse_stream`] computes the overlapping Allan
//! variance (SP1065 eq. 11) and, when asked, the noise identification, EDF and chi-square
//! intervals, with memory bounded by a few windows of `fused::CHUNK` samples per pass,
//! however long the record. It reads the source several times:
//!
//! 1. the integration constants (rate input): block sums for the mean, then block sums of the
//!    centred rate, whose compensated prefix sums are the starting angle of every integration
//!    block — the very numbers [`super::angle_series`] computes in memory;
//! 2. the all-τ pass: the angle series is regenerated block by block by *cursors* (one at the
//!    start of the record and one per large lag `m`, `2m`), and every τ's chunk sums are formed
//!    from the three windows `x[c..]`, `x[c+m..]`, `x[c+2m..]` by the kernel the in-memory
//!    pass uses; τ with many distinct lags are split into several passes (at most
//!    [`MAX_CURSORS`] cursors each);
//! 3. noise identification: the joint lag-1 sweep of the small factors fed window by window
//!    ([`noise_id::JointSweep`]), and the decimated series `x_{k·m}` of the large factors
//!    (collected in passes of at most `N/16` values).
//!
//! Every sum is formed over the same blocks, in the same order, as in memory, so the result
//! equals [`super::analyse_column`] on the whole record bit for bit, whatever the read size
//! (`block`).

use rayon::prelude::*;

use super::{
    AllanAnalysis, Config, DataType, Estimator, Gaps, INTEGRATION_BLOCK, Moments, Progress,
    Workspace, analyse_column, angle_pass, confidence, edf, fused, lane_sum, lane_sum_max,
    lane_sum_squares, noise_id, normalise, pow2, resolve_factors, scale_exponent, unscale,
};
use crate::validate;
use crate::{Error, Result};

/// Largest number of lag cursors (besides the one at the start) in one all-τ pass.
pub const MAX_CURSORS: usize = 12;

/// Records up to this many samples are read whole and analysed in memory.
const SMALL: usize = 1 << 14;

/// Consecutive samples of one series, read on request.
pub trait Source {
    /// Number of samples.
    fn len(&self) -> usize;
    /// True when there are no samples.
    fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// Copies samples `start..start + out.len()` into `out`.
    fn read(&mut self, start: usize, out: &mut [f64]) -> Result<()>;
}

/// A [`Source`] over a slice (for tests and for in-memory data).
#[derive(Debug, Clone, Copy)]
pub struct SliceSource<'a>(pub &'a [f64]);

impl Source for SliceSource<'_> {
    fn len(&self) -> usize {
        self.0.len()
    }

    fn read(&mut self, start: usize, out: &mut [f64]) -> Result<()> {
        let end = start + out.len();
        if end > self.0.len() {
            return Err(Error::invalid("start", "read beyond the end of the source"));
        }
        out.copy_from_slice(&self.0[start..end]);
        Ok(())
    }
}

/// Reads `out.len()` samples from `start` in pieces of at most `block`.
fn read_into(src: &mut dyn Source, start: usize, out: &mut [f64], block: usize) -> Result<()> {
    for (i, piece) in out.chunks_mut(block).enumerate() {
        src.read(start + i * block, piece)?;
    }
    Ok(())
}

/// Moments of the rate differences `(x_{i+1} − x_i)·factor/t0` of one piece of an angle
/// series, including the difference from the previous piece's last sample `last`.
fn piece_moments(last: Option<f64>, piece: &[f64], factor: f64, t0: f64) -> Moments {
    let inner = angle_pass(super::Column::contiguous(piece), factor, t0).2;
    match (last, piece.first()) {
        (Some(l), Some(&f)) => {
            let d = (f - l) * factor / t0;
            Moments {
                n: 1,
                mean: d,
                m2: 0.0,
            }
            .combine(inner)
        }
        _ => inner,
    }
}

/// What regenerates the angle series from the source.
struct Integration {
    data_type: DataType,
    t0: f64,
    mean: f64,
    /// The data are scaled by `factor = 2^-scale` ([`scale_exponent`]) as in memory.
    scale: i32,
    factor: f64,
    starts: Vec<f64>,
    n_samples: usize,
    block: usize,
    /// Moments of the scaled rate (of the rate differences for angle input), as in memory.
    moments: Moments,
}

impl Integration {
    fn n_angle(&self) -> usize {
        match self.data_type {
            DataType::Rate => self.n_samples + 1,
            DataType::Angle => self.n_samples,
        }
    }

    /// Pass 1 (and 2 for rate): finiteness, mean and block starts, as `integrate_rate_into`.
    fn new(
        src: &mut dyn Source,
        data_type: DataType,
        t0: f64,
        block: usize,
        progress: &Progress<'_>,
    ) -> Result<Integration> {
        let n = src.len();
        let mut buf = vec![0.0; INTEGRATION_BLOCK.min(n)];
        let mut sums = Vec::with_capacity(n.div_ceil(INTEGRATION_BLOCK));
        let mut peak = 0.0_f64;
        // Angle input: the rate differences' moments in the same pass (`angle_pass` per piece,
        // plus the difference that straddles two pieces).
        let angle = data_type == DataType::Angle;
        let mut moments = Moments::default();
        let mut last: Option<f64> = None;
        for a in (0..n).step_by(INTEGRATION_BLOCK) {
            let len = INTEGRATION_BLOCK.min(n - a);
            let piece = &mut buf[..len];
            read_into(src, a, piece, block)?;
            let (s, p) = lane_sum_max(0, len, |i| piece[i]);
            if angle {
                moments = moments.combine(piece_moments(last, piece, 1.0, t0));
                last = piece.last().copied();
            }
            peak = peak.max(p);
            if !s.is_finite() {
                if let Some(k) = piece.iter().position(|v| !v.is_finite()) {
                    return Err(Error::NonFinite {
                        name: "data",
                        index: a + k,
                    });
                }
            }
            sums.push(s);
            progress.advance(len as f64);
            progress.check()?;
        }
        let scale = scale_exponent(peak);
        let factor = pow2(-scale);
        let mut integration = Integration {
            data_type,
            t0,
            mean: 0.0,
            scale,
            factor,
            starts: Vec::new(),
            n_samples: n,
            block,
            moments,
        };
        if data_type == DataType::Angle {
            if scale != 0 {
                // Extreme data: the moments again, of the scaled samples (as in memory).
                let mut moments = Moments::default();
                let mut last = None;
                for a in (0..n).step_by(INTEGRATION_BLOCK) {
                    let len = INTEGRATION_BLOCK.min(n - a);
                    let piece = &mut buf[..len];
                    read_into(src, a, piece, block)?;
                    moments = moments.combine(piece_moments(last, piece, factor, t0));
                    last = piece.last().copied();
                    progress.check()?;
                }
                integration.moments = moments;
            }
            return Ok(integration);
        }
        if scale != 0 {
            // Extreme data: the block sums again, of the scaled samples (as in memory).
            sums.clear();
            for a in (0..n).step_by(INTEGRATION_BLOCK) {
                let len = INTEGRATION_BLOCK.min(n - a);
                let piece = &mut buf[..len];
                read_into(src, a, piece, block)?;
                sums.push(lane_sum(0, len, |i| piece[i] * factor));
                progress.check()?;
            }
        }
        let mean = validate::neumaier_sum(sums.iter().copied()) / n as f64;
        if !mean.is_finite() {
            return Err(Error::invalid(
                "data",
                "values too large: their sum overflows float64",
            ));
        }
        let (mut sum, mut comp) = (0.0_f64, 0.0_f64);
        let (mut s1, mut s2) = (Vec::new(), Vec::new());
        for a in (0..n).step_by(INTEGRATION_BLOCK) {
            let len = INTEGRATION_BLOCK.min(n - a);
            let piece = &mut buf[..len];
            read_into(src, a, piece, block)?;
            let (c, c2) = lane_sum_squares(0, len, |i| piece[i] * factor - mean);
            s1.push(c);
            s2.push(c2);
            integration.starts.push(sum + comp);
            let t = sum + c;
            if sum.abs() >= c.abs() {
                comp += (sum - t) + c;
            } else {
                comp += (c - t) + sum;
            }
            sum = t;
            progress.advance(len as f64);
            progress.check()?;
        }
        integration.mean = mean;
        // The same block sums, combined in the same order, as `integrate_rate_into`: the
        // in-memory kernel's moments bit for bit.
        integration.moments = Moments::from_centred_sums(
            n,
            mean,
            validate::neumaier_sum(s1.iter().copied()),
            validate::neumaier_sum(s2.iter().copied()),
        );
        Ok(integration)
    }
}

/// Produces the angle series `x_j, x_{j+1}, …` from a starting index, window by window.
struct Cursor {
    next: usize,
    acc: f64,
    rate: Vec<f64>,
}

impl Cursor {
    /// A cursor whose first value is `x_start`.
    fn new(src: &mut dyn Source, integ: &Integration, start: usize) -> Result<Cursor> {
        let mut cursor = Cursor {
            next: start,
            acc: 0.0,
            rate: Vec::new(),
        };
        if integ.data_type == DataType::Rate && start >= 1 && start <= integ.n_samples {
            // Warm up: accumulate from the start of the integration block holding sample
            // start − 1 exactly as the in-memory pass does.
            let i0 = start - 1;
            let b0 = i0 - i0 % INTEGRATION_BLOCK;
            if i0 > b0 {
                cursor.acc = integ.starts[b0 / INTEGRATION_BLOCK];
                cursor.rate.resize(i0 - b0, 0.0);
                read_into(src, b0, &mut cursor.rate, integ.block)?;
                for &r in &cursor.rate {
                    cursor.acc += r * integ.factor - integ.mean;
                }
            }
        }
        Ok(cursor)
    }

    /// Writes the next `out.len()` angle samples (zeros beyond the end of the series).
    fn fill(&mut self, src: &mut dyn Source, integ: &Integration, out: &mut [f64]) -> Result<()> {
        let n_angle = integ.n_angle();
        let first = self.next;
        let last = (first + out.len()).min(n_angle);
        out.fill(0.0);
        if first < last {
            match integ.data_type {
                DataType::Angle => {
                    read_into(src, first, &mut out[..last - first], integ.block)?;
                    if integ.scale != 0 {
                        for v in &mut out[..last - first] {
                            *v *= integ.factor;
                        }
                    }
                }
                DataType::Rate => {
                    // Rate samples behind x_first..x_last: i = j − 1.
                    let i_lo = first.max(1) - 1;
                    let i_hi = last - 1;
                    self.rate.resize(i_hi.saturating_sub(i_lo), 0.0);
                    if i_hi > i_lo {
                        read_into(src, i_lo, &mut self.rate, integ.block)?;
                    }
                    let (mean, t0, factor) = (integ.mean, integ.t0, integ.factor);
                    for j in first..last {
                        if j == 0 {
                            out[0] = 0.0;
                            continue;
                        }
                        let i = j - 1;
                        if i % INTEGRATION_BLOCK == 0 {
                            self.acc = integ.starts[i / INTEGRATION_BLOCK];
                        }
                        self.acc += self.rate[i - i_lo] * factor - mean;
                        out[j - first] = self.acc * t0;
                    }
                }
            }
        }
        self.next = first + out.len();
        Ok(())
    }
}

/// The all-τ overlapping Allan sums by cursors (module docs, step 2).
fn overlapping_sums(
    src: &mut dyn Source,
    integ: &Integration,
    ms: &[usize],
    progress: &Progress<'_>,
) -> Result<Vec<f64>> {
    const CHUNK: usize = fused::CHUNK;
    let ext = CHUNK;
    let n = integ.n_angle();
    // Groups of τ with at most MAX_CURSORS distinct lags beyond the base window.
    let mut groups: Vec<(Vec<usize>, Vec<usize>)> = Vec::new();
    for (j, &m) in ms.iter().enumerate() {
        let new: Vec<usize> = [m, 2 * m].into_iter().filter(|&o| o > ext).collect();
        let fits = groups.last().is_some_and(|(_, offs)| {
            offs.len() + new.iter().filter(|o| !offs.contains(o)).count() <= MAX_CURSORS
        });
        if !fits {
            groups.push((Vec::new(), Vec::new()));
        }
        let (taus, offs) = groups.last_mut().expect("a group was just pushed");
        taus.push(j);
        for o in new {
            if !offs.contains(&o) {
                offs.push(o);
            }
        }
    }
    let mut chunk_sums: Vec<Vec<f64>> = vec![Vec::new(); ms.len()];
    let mut base = vec![0.0; CHUNK + ext];
    for (taus, offs) in &groups {
        let terms: Vec<usize> = taus.iter().map(|&j| n - 2 * ms[j]).collect();
        let longest = terms.iter().copied().max().unwrap_or(0);
        let mut base_cursor = Cursor::new(src, integ, 0)?;
        let mut cursors = Vec::with_capacity(offs.len());
        for &o in offs {
            cursors.push((Cursor::new(src, integ, o)?, vec![0.0; CHUNK]));
        }
        for (ci, c0) in (0..longest).step_by(CHUNK).enumerate() {
            if ci == 0 {
                base_cursor.fill(src, integ, &mut base)?;
            } else {
                base.copy_within(CHUNK.., 0);
                base_cursor.fill(src, integ, &mut base[ext..])?;
            }
            for (cursor, window) in &mut cursors {
                cursor.fill(src, integ, window)?;
            }
            progress.advance(((1 + cursors.len()) * CHUNK) as f64);
            progress.check()?;
            let window = |o: usize, len: usize| -> &[f64] {
                if o <= ext {
                    &base[o..o + len]
                } else {
                    let k = offs.iter().position(|&x| x == o).unwrap_or(0);
                    &cursors[k].1[..len]
                }
            };
            let sums: Vec<Option<f64>> = taus
                .par_iter()
                .zip(terms.par_iter())
                .with_max_len(1)
                .map(|(&j, &t)| {
                    (c0 < t).then(|| {
                        let len = (c0 + CHUNK).min(t) - c0;
                        let m = ms[j];
                        fused::second_chunk_sum(&base[..len], window(m, len), window(2 * m, len))
                    })
                })
                .collect();
            for (&j, s) in taus.iter().zip(sums) {
                if let Some(s) = s {
                    chunk_sums[j].push(s);
                }
            }
        }
    }
    Ok(chunk_sums
        .iter()
        .map(|c| validate::neumaier_sum(c.iter().copied()))
        .collect())
}

/// Noise identification from the source (module docs, step 3), equal to
/// [`noise_id::identify`] on the whole angle series.
fn identify(
    src: &mut dyn Source,
    integ: &Integration,
    ms: &[usize],
    dmax: u32,
    progress: &Progress<'_>,
) -> Result<Vec<i32>> {
    const WINDOW: usize = fused::CHUNK; // a multiple of JointSweep::SWEEP
    let n = integ.n_angle();
    let (small, large) = noise_id::split_factors(ms);
    let mut window = vec![0.0; WINDOW];
    // Small factors: the joint sweep, two passes.
    let small_ids = if small.is_empty() {
        Vec::new()
    } else {
        let mut sweep = noise_id::JointSweep::new(n, &small, dmax);
        for pass in 0..2 {
            let mut cursor = Cursor::new(src, integ, 0)?;
            for w0 in (0..n).step_by(WINDOW) {
                let len = WINDOW.min(n - w0);
                cursor.fill(src, integ, &mut window[..len])?;
                for s in (0..len).step_by(noise_id::JointSweep::SWEEP) {
                    let e = (s + noise_id::JointSweep::SWEEP).min(len);
                    if pass == 0 {
                        sweep.trend_block(&window[s..e], w0 + s);
                    } else {
                        sweep.acf_block(&window[s..e], w0 + s);
                    }
                }
                progress.advance(len as f64);
                progress.check()?;
            }
        }
        sweep.finish()
    };
    // Large factors and the fallback factor: decimated series, in passes of bounded memory.
    let m_c = noise_id::fallback_factor(n);
    let mut wanted = large.clone();
    if m_c >= 1 && !wanted.contains(&m_c) {
        wanted.push(m_c);
    }
    let budget = (n / 16).max(1 << 16);
    let mut ids: Vec<Option<noise_id::Identification>> = vec![None; wanted.len()];
    // Factors with fewer than 100 decimated points (B1 / R(n)): gathered during the first
    // decimation pass (it always runs: `wanted` holds m_c for every streamed record).
    let mut few = noise_id::FewPoints::new(n, &noise_id::few_point_factors(n, ms));
    let mut next = 0;
    while next < wanted.len() {
        let mut end = next;
        let mut used = 0;
        while end < wanted.len() && (end == next || used + n.div_ceil(wanted[end]) <= budget) {
            used += n.div_ceil(wanted[end]);
            end += 1;
        }
        let group = &wanted[next..end];
        let mut z: Vec<Vec<f64>> = group
            .iter()
            .map(|&m| Vec::with_capacity(n.div_ceil(m)))
            .collect();
        let mut cursor = Cursor::new(src, integ, 0)?;
        for w0 in (0..n).step_by(WINDOW) {
            let len = WINDOW.min(n - w0);
            cursor.fill(src, integ, &mut window[..len])?;
            if next == 0 {
                few.feed(&window[..len], w0);
            }
            for (zm, &m) in z.iter_mut().zip(group) {
                let mut k = w0.div_ceil(m) * m;
                while k < w0 + len {
                    zm.push(window[k - w0]);
                    k += m;
                }
            }
            progress.advance(len as f64);
            progress.check()?;
        }
        let found: Vec<Option<noise_id::Identification>> = z
            .par_iter()
            .with_max_len(1)
            .map(|zm| noise_id::lag1_acf(zm, 1, dmax))
            .collect();
        ids[next..end].copy_from_slice(&found);
        next = end;
    }
    let lookup = |m: usize| wanted.iter().position(|&w| w == m).and_then(|i| ids[i]);
    let large_ids: Vec<Option<noise_id::Identification>> =
        large.iter().map(|&m| lookup(m)).collect();
    Ok(noise_id::identify_with(
        n,
        ms,
        |_, _| (small_ids, large_ids),
        lookup,
        |m, acf| few.resolve(m, acf),
    ))
}

/// Overlapping Allan analysis of a streamed record (see the module docs); `block` is the
/// largest number of samples asked from the source at once.
///
/// Equals [`analyse_column`] on the whole record bit for bit. Only the overlapping Allan
/// variance without gaps is streamed (`estimator`/`gaps` errors otherwise).
pub fn analyse_stream(
    source: &mut dyn Source,
    config: &Config,
    block: usize,
    progress: &Progress<'_>,
) -> Result<AllanAnalysis> {
    config.validate()?;
    if config.estimator != Estimator::Overlapping {
        return Err(Error::invalid(
            "estimator",
            "only the overlapping Allan variance is computed out of core",
        ));
    }
    if config.gaps != Gaps::Error {
        return Err(Error::invalid(
            "gaps",
            "gap-aware analysis is not computed out of core",
        ));
    }
    if block == 0 {
        return Err(Error::invalid("block", "must be >= 1"));
    }
    let n = source.len();
    let t0 = config.t0;
    let ms = resolve_factors(&config.taus, n, t0, config.data_type, config.estimator)?;
    if n <= SMALL {
        let mut data = vec![0.0; n];
        read_into(source, 0, &mut data, block)?;
        progress.start();
        let out = analyse_column(
            super::Column::contiguous(&data),
            config,
            &mut Workspace::new(),
            progress,
        );
        progress.finish();
        return out;
    }
    let passes = match config.data_type {
        DataType::Rate => 2.0,
        DataType::Angle => 1.0,
    } + 4.0
        + if config.confidence.is_some() {
            4.0
        } else {
            0.0
        };
    progress.add_total(passes * n as f64);
    progress.start();
    let integ = Integration::new(source, config.data_type, t0, block, progress)?;
    let n_angle = integ.n_angle();
    let sums = overlapping_sums(source, &integ, &ms, progress)?;
    let estimator = config.estimator;
    let n_terms: Vec<usize> = ms.iter().map(|&m| estimator.n_terms(n_angle, m)).collect();
    let variance: Vec<f64> = ms
        .iter()
        .zip(&sums)
        .zip(&n_terms)
        .map(|((&m, &s), &t)| normalise(estimator, s, m, t0, t))
        .collect();
    let confidence = match config.confidence {
        Some(level) => {
            let raw = identify(source, &integ, &ms, edf::differences(estimator), progress)?;
            let alpha = confidence::clamp_alphas(raw, estimator);
            Some(confidence::intervals_from_alphas(
                alpha, estimator, &ms, &variance, level, n_angle,
            )?)
        }
        None => None,
    };
    progress.finish();
    Ok(unscale(
        ms,
        &variance,
        n_terms,
        confidence,
        integ.scale,
        &integ.moments,
    ))
}

#[cfg(test)]
mod tests {
    use super::super::{Column, TauSpec, Taus};
    use super::*;

    /// Normal noise on a slow random walk (cumulative sum of normal steps) around 5, from the
    /// core's seeded generator.
    fn walk(n: usize) -> Vec<f64> {
        let noise = crate::random::normal_vec(n, 3);
        let steps = crate::random::normal_vec(n, 4);
        let mut level = 0.0;
        noise
            .iter()
            .zip(&steps)
            .map(|(&u, &s)| {
                level += 2e-3 * s;
                u + level + 5.0
            })
            .collect()
    }

    /// The streamed result equals the in-memory one bit for bit, except the data variance of
    /// angle input: the rate differences' moments are summed piece by piece (combined with
    /// Chan's update) instead of over the whole column, which changes the last bits only.
    fn same(memory: &AllanAnalysis, mut streamed: AllanAnalysis, data_type: DataType, what: &str) {
        if data_type == DataType::Angle {
            let (a, b) = (
                memory.data_variance.unwrap(),
                streamed.data_variance.unwrap(),
            );
            assert!(
                a == b || (a - b).abs() <= 1e-12 * a.abs(),
                "{what}: {a} vs {b}"
            );
            streamed.data_variance = memory.data_variance;
            let (a, b) = (
                memory.data_deviation.unwrap(),
                streamed.data_deviation.unwrap(),
            );
            assert!(
                a == b || (a - b).abs() <= 1e-12 * a.abs(),
                "{what}: {a} vs {b}"
            );
            streamed.data_deviation = memory.data_deviation;
        }
        assert_eq!(*memory, streamed, "{data_type:?} {what}");
    }

    #[test]
    fn stream_equals_in_memory_bit_for_bit() {
        // 600 001 samples: several integration blocks (65 536), chunks (262 144) and lags
        // beyond the base window; reads of 1 000 and 70 000 samples do not line up with either.
        let data = walk(600_001);
        for data_type in [DataType::Rate, DataType::Angle] {
            for taus in [
                Taus::Spec(TauSpec::Octave),
                Taus::Spec(TauSpec::Log { per_decade: 20 }),
            ] {
                let cfg = Config {
                    t0: 0.01,
                    data_type,
                    estimator: Estimator::Overlapping,
                    taus,
                    confidence: Some(0.683),
                    gaps: Gaps::Error,
                };
                let mut memory = analyse_column(
                    Column::contiguous(&data),
                    &cfg,
                    &mut Workspace::new(),
                    &Progress::none(),
                )
                .unwrap();
                // the stationarity check's block means come from the in-memory kernel only
                memory.blocks = None;
                for block in [1000, 70_000] {
                    let streamed =
                        analyse_stream(&mut SliceSource(&data), &cfg, block, &Progress::none())
                            .unwrap();
                    same(&memory, streamed, data_type, &format!("block {block}"));
                }
            }
        }
    }

    #[test]
    fn extreme_magnitudes_stream_like_in_memory() {
        // Data scaled internally by a power of two (scale_exponent) give the in-memory bits.
        let base = walk(300_001);
        for factor in [1e300, 1e-300, super::super::ldexp(1.0, -900)] {
            let data: Vec<f64> = base.iter().map(|v| v * factor).collect();
            for data_type in [DataType::Rate, DataType::Angle] {
                let cfg = Config {
                    t0: 0.01,
                    data_type,
                    estimator: Estimator::Overlapping,
                    taus: Taus::Spec(TauSpec::Octave),
                    confidence: Some(0.683),
                    gaps: Gaps::Error,
                };
                let mut memory = analyse_column(
                    Column::contiguous(&data),
                    &cfg,
                    &mut Workspace::new(),
                    &Progress::none(),
                )
                .unwrap();
                // the stationarity check's block means come from the in-memory kernel only
                memory.blocks = None;
                assert!(memory.deviation.iter().all(|d| d.is_finite() && *d > 0.0));
                let streamed =
                    analyse_stream(&mut SliceSource(&data), &cfg, 50_000, &Progress::none())
                        .unwrap();
                same(&memory, streamed, data_type, &format!("×{factor:e}"));
            }
        }
    }

    #[test]
    fn stream_errors() {
        let mut data = walk(100_000);
        data[77_777] = f64::NAN;
        let cfg = Config {
            t0: 1.0,
            data_type: DataType::Rate,
            estimator: Estimator::Overlapping,
            taus: Taus::Spec(TauSpec::Octave),
            confidence: None,
            gaps: Gaps::Error,
        };
        let err = analyse_stream(&mut SliceSource(&data), &cfg, 4096, &Progress::none());
        assert_eq!(
            err,
            Err(Error::NonFinite {
                name: "data",
                index: 77_777
            })
        );
        let mut hadamard = cfg.clone();
        hadamard.estimator = Estimator::Hadamard;
        assert!(
            analyse_stream(&mut SliceSource(&data), &hadamard, 4096, &Progress::none()).is_err()
        );
        assert!(analyse_stream(&mut SliceSource(&data), &cfg, 0, &Progress::none()).is_err());
    }
}
