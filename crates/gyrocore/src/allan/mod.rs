//! Allan-family variances of rate or angle data (NIST SP 1065 §4, IEEE Std 952 Annex C).
//!
//! All estimators work on the *angle* (phase) series `x`. Rate input `Ω_0..Ω_{N-1}` sampled at
//! period `t0` is integrated after removing its mean (SPEC §2):
//!
//! ```text
//! x_0 = 0,   x_k = t0 · Σ_{i<k} (Ω_i − Ω̄),   k = 1..N
//! ```
//!
//! so `N` rate samples give `N + 1` angle samples (the AllanTools / Stable32 convention). Removing
//! the mean only subtracts a linear ramp, which every estimator here cancels, and it keeps float64
//! precision on long logs with a large bias. Angle input is used as given.
//!
//! With `τ = m·t0` and `M` angle samples the estimators are
//!
//! | estimator | formula | terms |
//! |---|---|---|
//! | overlapping Allan (SP1065 eq. 11, \[TS\] eq. 1) | `Σ (x_{k+2m} − 2x_{k+m} + x_k)² / (2τ² n)` | `n = M − 2m` |
//! | non-overlapping Allan (\[BP\] eq. 2, SP1065 eq. 7) | same, `k = 0, m, 2m, …` | `n = ⌊(M−1)/m⌋ − 1` |
//! | modified Allan (SP1065 eq. 14) | `Σ_j [Σ_{i=j}^{j+m−1} (x_{i+2m} − 2x_{i+m} + x_i)]² / (2 m² τ² n)` | `n = M − 3m + 1` |
//! | overlapping Hadamard (SP1065 eq. 18) | `Σ (x_{k+3m} − 3x_{k+2m} + 3x_{k+m} − x_k)² / (6τ² n)` | `n = M − 3m` |
//! | total (SP1065 eq. 25) | overlapping Allan on `x` reflected at both ends, `i = 1..M−2` | `n = M − 2` |
//!
//! Each variance is one streaming pass over `x` (O(M) per τ, no per-τ copies); the τ values are
//! computed in parallel. Confidence intervals (noise identification, equivalent degrees of
//! freedom, chi-square bounds) live in [`confidence`].

pub mod confidence;
pub mod dynamic;
pub mod edf;
pub mod family;
mod fused;
pub mod hadamard;
pub mod noise_id;
pub mod theo;
pub mod total;

use std::borrow::Cow;

use rayon::prelude::*;

use crate::validate;
use crate::{Error, Result};

/// What the samples are.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DataType {
    /// Angular rate (gyro output, e.g. deg/s): integrated to angle after removing the mean.
    Rate,
    /// Angle (integrated rate, e.g. deg): used as given.
    Angle,
}

impl DataType {
    /// Parses `"rate"` or `"angle"`.
    pub fn parse(name: &str) -> Result<Self> {
        match name {
            "rate" => Ok(DataType::Rate),
            "angle" => Ok(DataType::Angle),
            other => Err(Error::invalid(
                "data_type",
                format!("expected 'rate' or 'angle', got {other:?}"),
            )),
        }
    }
}

/// Which member of the Allan family to estimate.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Estimator {
    /// Overlapping Allan variance (OAVAR).
    Overlapping,
    /// Non-overlapping Allan variance (AVAR, \[BP\] eq. 2).
    NonOverlapping,
    /// Modified Allan variance (MVAR).
    Modified,
    /// Overlapping Hadamard variance (HVAR).
    Hadamard,
    /// Total variance (TOTVAR).
    Total,
}

impl Estimator {
    /// Parses `"overlapping"`, `"non-overlapping"`, `"modified"`, `"hadamard"` or `"total"`.
    pub fn parse(name: &str) -> Result<Self> {
        match name {
            "overlapping" => Ok(Estimator::Overlapping),
            "non-overlapping" => Ok(Estimator::NonOverlapping),
            "modified" => Ok(Estimator::Modified),
            "hadamard" => Ok(Estimator::Hadamard),
            "total" => Ok(Estimator::Total),
            other => Err(Error::invalid(
                "estimator",
                format!(
                    "expected one of 'overlapping', 'non-overlapping', 'modified', \
                     'hadamard', 'total', got {other:?}"
                ),
            )),
        }
    }

    /// Largest averaging factor `m` with at least one term, for `n_angle` angle samples.
    pub fn max_factor(self, n_angle: usize) -> usize {
        match self {
            // Total: reflection makes every m ≤ M − 1 computable, but TOTVAR is only meaningful
            // up to half the record (SP1065 §5.2.11); cap it there like the Allan estimators.
            Estimator::Overlapping | Estimator::NonOverlapping | Estimator::Total => {
                n_angle.saturating_sub(1) / 2
            }
            Estimator::Modified => n_angle / 3,
            Estimator::Hadamard => n_angle.saturating_sub(1) / 3,
        }
    }

    /// Number of terms in the sum at averaging factor `m` for `n_angle` angle samples.
    pub fn n_terms(self, n_angle: usize, m: usize) -> usize {
        let n = n_angle as isize;
        let m = m as isize;
        let terms = match self {
            Estimator::Overlapping => n - 2 * m,
            Estimator::NonOverlapping => (n - 1) / m - 1,
            Estimator::Modified => n - 3 * m + 1,
            Estimator::Hadamard => n - 3 * m,
            Estimator::Total => n - 2,
        };
        terms.max(0) as usize
    }
}

/// How to choose the averaging factors `m` (τ = m·t0).
#[derive(Debug, Clone, PartialEq)]
pub enum TauSpec {
    /// m = 1, 2, 4, 8, …
    Octave,
    /// m = 1, 2, 4, 10, 20, 40, 100, … (Stable32's decade spacing).
    Decade,
    /// `per_decade` log-spaced points per decade, rounded to distinct integers.
    Log {
        /// Points per decade (≥ 1).
        per_decade: usize,
    },
    /// Every m from 1 to the maximum.
    All,
}

/// Averaging factors for a τ specification, capped at `max_m` (sorted, distinct, ≥ 1).
pub fn averaging_factors(spec: &TauSpec, max_m: usize) -> Result<Vec<usize>> {
    if max_m == 0 {
        return Ok(Vec::new());
    }
    let ms = match spec {
        TauSpec::Octave => {
            let mut v = Vec::new();
            let mut m = 1usize;
            while m <= max_m {
                v.push(m);
                m *= 2;
            }
            v
        }
        TauSpec::Decade => {
            let mut v = Vec::new();
            let mut p = 1usize;
            'outer: loop {
                for f in [1, 2, 4] {
                    let m = f * p;
                    if m > max_m {
                        break 'outer;
                    }
                    v.push(m);
                }
                p *= 10;
            }
            v
        }
        TauSpec::Log { per_decade } => {
            if *per_decade == 0 {
                return Err(Error::invalid("per_decade", "must be >= 1"));
            }
            let decades = (max_m as f64).log10();
            let count = (decades * *per_decade as f64).floor() as usize;
            let mut v: Vec<usize> = (0..=count)
                .map(|i| {
                    let m = 10f64.powf(i as f64 / *per_decade as f64).round() as usize;
                    m.clamp(1, max_m)
                })
                .collect();
            v.dedup();
            v
        }
        TauSpec::All => (1..=max_m).collect(),
    };
    Ok(ms)
}

/// Converts explicit τ values (seconds) to averaging factors.
///
/// Each τ must be a positive multiple of `t0` (relative tolerance 1e-9) with `m ≤ max_m`.
/// The result keeps the caller's order; duplicates are an error.
pub fn factors_from_taus(taus: &[f64], t0: f64, max_m: usize) -> Result<Vec<usize>> {
    validate::positive("fs", 1.0 / t0)?;
    if taus.is_empty() {
        return Err(Error::invalid("taus", "is empty"));
    }
    let mut ms = Vec::with_capacity(taus.len());
    for (i, &tau) in taus.iter().enumerate() {
        if !(tau.is_finite() && tau > 0.0) {
            return Err(Error::invalid(
                "taus",
                format!("taus[{i}] = {tau} is not a finite positive time in seconds"),
            ));
        }
        let ratio = tau / t0;
        let m = ratio.round();
        if m < 1.0 || (ratio - m).abs() > 1e-9 * ratio.max(1.0) {
            return Err(Error::invalid(
                "taus",
                format!(
                    "taus[{i}] = {tau} s is not a positive multiple of the sample period {t0} s"
                ),
            ));
        }
        let m = m as usize;
        if m > max_m {
            return Err(Error::invalid(
                "taus",
                format!(
                    "taus[{i}] = {tau} s needs m = {m} but the data support at most m = {max_m} \
                     (τ ≤ {} s)",
                    max_m as f64 * t0
                ),
            ));
        }
        ms.push(m);
    }
    let mut sorted = ms.clone();
    sorted.sort_unstable();
    if sorted.windows(2).any(|w| w[0] == w[1]) {
        return Err(Error::invalid("taus", "contains duplicate values"));
    }
    Ok(ms)
}

/// One column of a row-major (samples × axes) buffer, read without copying.
#[derive(Debug, Clone, Copy)]
pub struct Column<'a> {
    data: &'a [f64],
    stride: usize,
    offset: usize,
}

impl<'a> Column<'a> {
    /// A contiguous series.
    pub fn contiguous(data: &'a [f64]) -> Self {
        Column {
            data,
            stride: 1,
            offset: 0,
        }
    }

    /// Column `axis` of a row-major buffer with `n_axes` columns.
    pub fn of(data: &'a [f64], n_axes: usize, axis: usize) -> Result<Self> {
        if n_axes == 0 || data.len() % n_axes != 0 {
            return Err(Error::ShapeMismatch {
                name: "data",
                reason: format!("{} values do not form rows of {n_axes} axes", data.len()),
            });
        }
        if axis >= n_axes {
            return Err(Error::invalid(
                "axis",
                format!("{axis} out of range for {n_axes} axes"),
            ));
        }
        Ok(Column {
            data,
            stride: n_axes,
            offset: axis,
        })
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        if self.data.len() <= self.offset {
            0
        } else {
            (self.data.len() - self.offset).div_ceil(self.stride)
        }
    }

    /// True when the column has no samples.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    fn iter(&self) -> impl Iterator<Item = f64> + '_ {
        self.data[self.offset.min(self.data.len())..]
            .iter()
            .step_by(self.stride)
            .copied()
    }

    fn as_slice(&self) -> Option<&'a [f64]> {
        (self.stride == 1 && self.offset == 0).then_some(self.data)
    }

    fn first_non_finite(&self) -> Option<usize> {
        match self.as_slice() {
            Some(s) => match validate::finite("data", s) {
                Ok(()) => None,
                Err(_) => s.iter().position(|v| !v.is_finite()),
            },
            None => self.iter().position(|v| !v.is_finite()),
        }
    }

    /// Sample `i` (no bounds beyond the slice's own).
    #[inline]
    fn get(&self, i: usize) -> f64 {
        self.data[self.offset + i * self.stride]
    }
}

/// Block length of the parallel integration. Fixed (not derived from the thread count), so
/// results are identical however many threads run.
const INTEGRATION_BLOCK: usize = 1 << 16;

/// Sum of `f(i)` for `i in a..b` in 8 independent lanes (vectorisable; error ~√(len/8)·eps).
#[inline]
fn lane_sum(a: usize, b: usize, f: impl Fn(usize) -> f64) -> f64 {
    let mut lanes = [0.0_f64; 8];
    let mut i = a;
    while i + 8 <= b {
        for (l, lane) in lanes.iter_mut().enumerate() {
            *lane += f(i + l);
        }
        i += 8;
    }
    let mut tail = 0.0;
    while i < b {
        tail += f(i);
        i += 1;
    }
    lanes.iter().sum::<f64>() + tail
}

/// Integrated mean-removed rate, `x_0 = 0`, `x_k = t0·Σ_{i<k}(Ω_i − Ω̄)`, in three parallel
/// passes over fixed blocks: (1) block sums for the mean and the finiteness check, (2) block
/// sums of the centred rate, whose compensated prefix sums give each block's starting angle,
/// (3) the running sum inside each block, written in parallel.
fn integrate_rate(column: Column<'_>, t0: f64) -> Result<Vec<f64>> {
    let n = column.len();
    let blocks: Vec<(usize, usize)> = (0..n)
        .step_by(INTEGRATION_BLOCK)
        .map(|a| (a, (a + INTEGRATION_BLOCK).min(n)))
        .collect();
    let sums: Vec<f64> = blocks
        .par_iter()
        .map(|&(a, b)| lane_sum(a, b, |i| column.get(i)))
        .collect();
    for (&(a, b), s) in blocks.iter().zip(&sums) {
        // NaN/inf propagate into the block sum (finite data can only overflow it, which the
        // scan then rules out).
        if !s.is_finite() {
            if let Some(k) = (a..b).find(|&i| !column.get(i).is_finite()) {
                return Err(Error::NonFinite {
                    name: "data",
                    index: k,
                });
            }
        }
    }
    let mean = validate::neumaier_sum(sums.iter().copied()) / n as f64;
    if !mean.is_finite() {
        return Err(Error::invalid(
            "data",
            "values too large: their sum overflows float64",
        ));
    }
    let centred: Vec<f64> = blocks
        .par_iter()
        .map(|&(a, b)| lane_sum(a, b, |i| column.get(i) - mean))
        .collect();
    // Compensated prefix sums: the starting (unscaled) angle of every block.
    let mut starts = Vec::with_capacity(blocks.len());
    let (mut sum, mut comp) = (0.0_f64, 0.0_f64);
    for &c in &centred {
        starts.push(sum + comp);
        let t = sum + c;
        if sum.abs() >= c.abs() {
            comp += (sum - t) + c;
        } else {
            comp += (c - t) + sum;
        }
        sum = t;
    }
    let mut x = vec![0.0; n + 1];
    x[1..]
        .par_chunks_mut(INTEGRATION_BLOCK)
        .zip(blocks.par_iter().zip(starts.par_iter()))
        .for_each(|(out, (&(a, _), &start))| {
            let mut acc = start;
            for (k, slot) in out.iter_mut().enumerate() {
                acc += column.get(a + k) - mean;
                *slot = acc * t0;
            }
        });
    Ok(x)
}

/// The angle series the estimators work on (SPEC §2): integrated mean-removed rate with `x_0 = 0`,
/// or the angle input itself (borrowed when contiguous).
pub fn angle_series(column: Column<'_>, t0: f64, data_type: DataType) -> Result<Cow<'_, [f64]>> {
    validate::positive("fs", 1.0 / t0)?;
    match data_type {
        DataType::Angle => {
            if let Some(index) = column.first_non_finite() {
                return Err(Error::NonFinite {
                    name: "data",
                    index,
                });
            }
            Ok(match column.as_slice() {
                Some(s) => Cow::Borrowed(s),
                None => Cow::Owned(column.iter().collect()),
            })
        }
        DataType::Rate => {
            if column.is_empty() {
                return Ok(Cow::Owned(vec![0.0]));
            }
            Ok(Cow::Owned(integrate_rate(column, t0)?))
        }
    }
}

/// Block size for the compensated summation of squared differences: lanes accumulate within a
/// block, blocks are added with Neumaier compensation, so the rounding error does not grow with
/// the record length.
const BLOCK: usize = 4096;
const LANES: usize = 8;

/// `Σ_k f(k)²` over `k in 0..count` with a SIMD-friendly lane layout and compensated block sums.
#[inline]
fn sum_squares(count: usize, f: impl Fn(usize) -> f64) -> f64 {
    let mut total = 0.0_f64;
    let mut comp = 0.0_f64;
    let mut start = 0;
    while start < count {
        let end = (start + BLOCK).min(count);
        let mut lanes = [0.0_f64; LANES];
        let mut k = start;
        while k + LANES <= end {
            for (l, lane) in lanes.iter_mut().enumerate() {
                let d = f(k + l);
                *lane += d * d;
            }
            k += LANES;
        }
        let mut block: f64 = lanes.iter().sum();
        while k < end {
            let d = f(k);
            block += d * d;
            k += 1;
        }
        let t = total + block;
        if total.abs() >= block.abs() {
            comp += (total - t) + block;
        } else {
            comp += (block - t) + total;
        }
        total = t;
        start = end;
    }
    total + comp
}

/// Modified Allan sum: the inner m-sums of second differences are carried as a running sum,
/// re-seeded exactly every `BLOCK` steps so rounding cannot drift over long records.
fn sum_modified(x: &[f64], m: usize, terms: usize) -> f64 {
    let d = |i: usize| x[i + 2 * m] - 2.0 * x[i + m] + x[i];
    let exact = |j: usize| validate::neumaier_sum((j..j + m).map(d));
    let mut total = 0.0_f64;
    let mut comp = 0.0_f64;
    // Re-seeding costs O(m); doing it every max(BLOCK, 4m) steps bounds that work by a
    // quarter pass per τ while keeping the running sum's drift negligible.
    let reseed = BLOCK.max(4 * m);
    let mut j = 0;
    while j < terms {
        let end = (j + reseed).min(terms);
        let mut s = exact(j);
        let mut block = s * s;
        for jj in j + 1..end {
            s += d(jj + m - 1) - d(jj - 1);
            block += s * s;
        }
        let t = total + block;
        if total.abs() >= block.abs() {
            comp += (total - t) + block;
        } else {
            comp += (block - t) + total;
        }
        total = t;
        j = end;
    }
    total + comp
}

/// Total-variance sum on the reflected series (SP1065 eq. 25), without materialising it.
fn sum_total(x: &[f64], m: usize) -> f64 {
    let n = x.len();
    let last = n - 1;
    // x*_{-j} = 2x_0 − x_j and x*_{last+j} = 2x_last − x_{last−j}  (j = 1..n−2)
    let star = |i: isize| -> f64 {
        if i < 0 {
            2.0 * x[0] - x[(-i) as usize]
        } else if (i as usize) > last {
            2.0 * x[last] - x[2 * last - i as usize]
        } else {
            x[i as usize]
        }
    };
    let m = m as isize;
    sum_squares(n - 2, |k| {
        let i = k as isize + 1;
        star(i - m) - 2.0 * star(i) + star(i + m)
    })
}

/// The variance of one estimator at one averaging factor, from an angle series.
///
/// Returns `(variance, n_terms)`. `m` must satisfy `1 ≤ m ≤ estimator.max_factor(x.len())`.
pub fn variance(x: &[f64], t0: f64, m: usize, estimator: Estimator) -> Result<(f64, usize)> {
    let max_m = estimator.max_factor(x.len());
    if m == 0 || m > max_m {
        return Err(Error::TooShort {
            name: "data",
            needed: match estimator {
                Estimator::Overlapping | Estimator::NonOverlapping | Estimator::Total => 2 * m,
                Estimator::Modified => 3 * m - 1,
                Estimator::Hadamard => 3 * m,
            },
            got: x.len().saturating_sub(1),
        });
    }
    let terms = estimator.n_terms(x.len(), m);
    let tau = m as f64 * t0;
    let var = match estimator {
        // Same kernel as the many-τ path, so one τ and a τ list give identical numbers.
        Estimator::Overlapping => {
            fused::difference_sums(x, &[m], fused::Difference::Second)[0]
                / (2.0 * tau * tau * terms as f64)
        }
        Estimator::NonOverlapping => {
            let s = sum_squares(terms, |i| {
                let k = i * m;
                x[k + 2 * m] - 2.0 * x[k + m] + x[k]
            });
            s / (2.0 * tau * tau * terms as f64)
        }
        Estimator::Modified => {
            sum_modified(x, m, terms) / (2.0 * (m * m) as f64 * tau * tau * terms as f64)
        }
        Estimator::Hadamard => {
            fused::difference_sums(x, &[m], fused::Difference::Third)[0]
                / (6.0 * tau * tau * terms as f64)
        }
        Estimator::Total => sum_total(x, m) / (2.0 * tau * tau * terms as f64),
    };
    Ok((var, terms))
}

/// Variances at several averaging factors, computed in parallel.
///
/// Writes into `variances` and `n_terms` (each `ms.len()` long).
pub fn variances_into(
    x: &[f64],
    t0: f64,
    ms: &[usize],
    estimator: Estimator,
    variances: &mut [f64],
    n_terms: &mut [usize],
) -> Result<()> {
    if variances.len() != ms.len() || n_terms.len() != ms.len() {
        return Err(Error::ShapeMismatch {
            name: "variances",
            reason: "output buffers must have one slot per averaging factor".into(),
        });
    }
    let n = x.len();
    if let Some(&bad) = ms.iter().find(|&&m| m == 0 || m > estimator.max_factor(n)) {
        // Reuse the single-τ path for its error message.
        variance(x, t0, bad, estimator)?;
    }
    let fused = match estimator {
        Estimator::Overlapping => Some((fused::Difference::Second, 2.0)),
        Estimator::Hadamard => Some((fused::Difference::Third, 6.0)),
        _ => None,
    };
    if let Some((diff, scale)) = fused {
        let sums = fused::difference_sums(x, ms, diff);
        for (i, (&m, s)) in ms.iter().zip(sums).enumerate() {
            let terms = estimator.n_terms(n, m);
            let tau = m as f64 * t0;
            variances[i] = s / (scale * tau * tau * terms as f64);
            n_terms[i] = terms;
        }
        return Ok(());
    }
    let results: Vec<Result<(f64, usize)>> = ms
        .par_iter()
        .with_max_len(1)
        .map(|&m| variance(x, t0, m, estimator))
        .collect();
    for (i, r) in results.into_iter().enumerate() {
        let (v, n) = r?;
        variances[i] = v;
        n_terms[i] = n;
    }
    Ok(())
}

/// Everything one Allan analysis of one axis produces.
#[derive(Debug, Clone, PartialEq)]
pub struct AllanAnalysis {
    /// Averaging factors (τ = m·t0).
    pub m: Vec<usize>,
    /// Variance estimates (unit²).
    pub variance: Vec<f64>,
    /// Number of terms in each sum.
    pub n_terms: Vec<usize>,
    /// Confidence intervals, when asked for.
    pub confidence: Option<confidence::Intervals>,
}

/// Where the averaging factors come from.
#[derive(Debug, Clone, PartialEq)]
pub enum Taus {
    /// Generated from a specification, capped to what the data support.
    Spec(TauSpec),
    /// Explicit τ values in seconds (each a multiple of t0; too large is an error).
    Explicit(Vec<f64>),
}

/// Averaging factors for `taus` on `n_samples` input samples.
pub fn resolve_factors(
    taus: &Taus,
    n_samples: usize,
    t0: f64,
    data_type: DataType,
    estimator: Estimator,
) -> Result<Vec<usize>> {
    let n_angle = match data_type {
        DataType::Rate => n_samples + 1,
        DataType::Angle => n_samples,
    };
    let max_m = estimator.max_factor(n_angle);
    let ms = match taus {
        Taus::Spec(spec) => averaging_factors(spec, max_m)?,
        Taus::Explicit(t) => factors_from_taus(t, t0, max_m)?,
    };
    if ms.is_empty() {
        // Smallest record with one term at m = 1: 3 angle samples (4 for Hadamard's third
        // difference); a rate series gives one angle sample more than it has.
        let angle_needed = if estimator == Estimator::Hadamard {
            4
        } else {
            3
        };
        let needed = match data_type {
            DataType::Rate => angle_needed - 1,
            DataType::Angle => angle_needed,
        };
        return Err(Error::TooShort {
            name: "data",
            needed,
            got: n_samples,
        });
    }
    Ok(ms)
}

/// Full analysis of one column: angle series, variances at the requested τ and, when
/// `confidence_level` is given, noise identification, EDF and chi-square intervals.
pub fn analyse(
    column: Column<'_>,
    t0: f64,
    data_type: DataType,
    estimator: Estimator,
    taus: &Taus,
    confidence_level: Option<f64>,
) -> Result<AllanAnalysis> {
    validate::positive("fs", 1.0 / t0)?;
    if let Some(level) = confidence_level {
        if !(level > 0.0 && level < 1.0) {
            return Err(Error::invalid(
                "confidence",
                format!("must lie strictly between 0 and 1, got {level}"),
            ));
        }
    }
    let ms = resolve_factors(taus, column.len(), t0, data_type, estimator)?;
    let x = angle_series(column, t0, data_type)?;
    let mut var = vec![0.0; ms.len()];
    let mut n_terms = vec![0usize; ms.len()];
    variances_into(&x, t0, &ms, estimator, &mut var, &mut n_terms)?;
    let confidence = match confidence_level {
        Some(level) => Some(confidence::intervals(&x, estimator, &ms, &var, level)?),
        None => None,
    };
    Ok(AllanAnalysis {
        m: ms,
        variance: var,
        n_terms,
        confidence,
    })
}

/// [`analyse`] for every column of a row-major (samples × axes) buffer, axes in parallel.
pub fn analyse_axes(
    data: &[f64],
    n_axes: usize,
    t0: f64,
    data_type: DataType,
    estimator: Estimator,
    taus: &Taus,
    confidence_level: Option<f64>,
) -> Result<Vec<AllanAnalysis>> {
    let columns: Vec<Column<'_>> = (0..n_axes)
        .map(|a| Column::of(data, n_axes, a))
        .collect::<Result<_>>()?;
    columns
        .into_par_iter()
        .enumerate()
        .map(|(axis, c)| {
            analyse(c, t0, data_type, estimator, taus, confidence_level).map_err(|e| match e {
                Error::NonFinite { name, index } if n_axes > 1 => Error::invalid(
                    name,
                    format!("non-finite value (NaN or inf) at row {index}, column {axis}"),
                ),
                other => other,
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    const RATE: [f64; 8] = [1.0, 3.0, 2.0, 5.0, 4.0, 6.0, 8.0, 7.0];

    fn close(a: f64, b: f64) {
        assert!((a - b).abs() <= 1e-11 * b.abs().max(1.0), "{a} vs {b}");
    }

    #[test]
    fn spec_check_values_overlapping() {
        let x = angle_series(Column::contiguous(&RATE), 0.5, DataType::Rate).unwrap();
        let expect = [
            (1.714285714286, 7),
            (2.1, 5),
            (4.537037037037, 3),
            (6.125, 1),
        ];
        for (m, (v, n)) in (1..=4).zip(expect) {
            let (var, terms) = variance(&x, 0.5, m, Estimator::Overlapping).unwrap();
            assert!((var - v).abs() < 1e-11, "m={m}: {var}");
            assert_eq!(terms, n);
        }
    }

    #[test]
    fn spec_check_values_non_overlapping() {
        let x = angle_series(Column::contiguous(&RATE), 0.5, DataType::Rate).unwrap();
        let expect = [1.714285714286, 1.791666666667, 4.5, 6.125];
        for (m, v) in (1..=4).zip(expect) {
            let (var, _) = variance(&x, 0.5, m, Estimator::NonOverlapping).unwrap();
            assert!((var - v).abs() < 1e-11, "m={m}: {var}");
        }
    }

    #[test]
    fn non_overlapping_equals_binned_rate_means() {
        // [BP] eq. 2 from bin means of the rate.
        let rate: Vec<f64> = (0..103)
            .map(|i| ((i * 37 % 17) as f64).sin() * 3.0)
            .collect();
        let x = angle_series(Column::contiguous(&rate), 0.01, DataType::Rate).unwrap();
        for m in [1usize, 2, 3, 7, 25, 51] {
            let k = rate.len() / m;
            let means: Vec<f64> = (0..k)
                .map(|i| rate[i * m..(i + 1) * m].iter().sum::<f64>() / m as f64)
                .collect();
            let reference = means.windows(2).map(|w| (w[1] - w[0]).powi(2)).sum::<f64>()
                / (2.0 * (k - 1) as f64);
            let (var, terms) = variance(&x, 0.01, m, Estimator::NonOverlapping).unwrap();
            close(var, reference);
            assert_eq!(terms, k - 1);
        }
    }

    #[test]
    fn modified_equals_direct_double_sum() {
        let rate: Vec<f64> = (0..9000)
            .map(|i| ((i * 7919 % 1013) as f64 * 0.37).sin())
            .collect();
        let x = angle_series(Column::contiguous(&rate), 1.0, DataType::Rate).unwrap();
        for m in [1usize, 2, 5, 33, 1500, 3000] {
            let n = x.len() - 3 * m + 1;
            let mut s = 0.0;
            for j in 0..n {
                let inner: f64 = (j..j + m)
                    .map(|i| x[i + 2 * m] - 2.0 * x[i + m] + x[i])
                    .sum();
                s += inner * inner;
            }
            let reference = s / (2.0 * (m * m) as f64 * (m * m) as f64 * n as f64);
            let (var, terms) = variance(&x, 1.0, m, Estimator::Modified).unwrap();
            assert_eq!(terms, n);
            assert!(
                (var - reference).abs() <= 1e-10 * reference,
                "m={m} {var} {reference}"
            );
        }
    }

    #[test]
    fn total_equals_explicit_reflection() {
        let rate: Vec<f64> = (0..50).map(|i| ((i * 13 % 11) as f64) - 5.0).collect();
        let x = angle_series(Column::contiguous(&rate), 1.0, DataType::Rate).unwrap();
        let n = x.len();
        let mut star = Vec::new();
        for j in (1..=n - 2).rev() {
            star.push(2.0 * x[0] - x[j]);
        }
        star.extend_from_slice(&x);
        for j in 1..=n - 2 {
            star.push(2.0 * x[n - 1] - x[n - 1 - j]);
        }
        let mid = n - 2;
        for m in 1..=Estimator::Total.max_factor(n) {
            let s: f64 = (1..n - 1)
                .map(|i| {
                    let c = mid + i;
                    (star[c - m] - 2.0 * star[c] + star[c + m]).powi(2)
                })
                .sum();
            let reference = s / (2.0 * (m * m) as f64 * (n - 2) as f64);
            let (var, _) = variance(&x, 1.0, m, Estimator::Total).unwrap();
            close(var, reference);
        }
    }

    #[test]
    fn tau_sets() {
        assert_eq!(
            averaging_factors(&TauSpec::Octave, 10).unwrap(),
            vec![1, 2, 4, 8]
        );
        assert_eq!(
            averaging_factors(&TauSpec::Decade, 500).unwrap(),
            vec![1, 2, 4, 10, 20, 40, 100, 200, 400]
        );
        let log = averaging_factors(&TauSpec::Log { per_decade: 10 }, 1000).unwrap();
        assert_eq!(log.first(), Some(&1));
        assert_eq!(log.last(), Some(&1000));
        assert!(log.windows(2).all(|w| w[0] < w[1]));
        assert_eq!(averaging_factors(&TauSpec::All, 3).unwrap(), vec![1, 2, 3]);
    }

    #[test]
    fn explicit_taus_are_checked() {
        assert_eq!(factors_from_taus(&[0.5, 1.0], 0.5, 4).unwrap(), vec![1, 2]);
        assert!(factors_from_taus(&[0.75], 0.5, 4).is_err());
        assert!(factors_from_taus(&[3.0], 0.5, 4).is_err());
        assert!(factors_from_taus(&[0.5, 0.5], 0.5, 4).is_err());
        assert!(factors_from_taus(&[f64::NAN], 0.5, 4).is_err());
    }

    #[test]
    fn strided_column_equals_contiguous() {
        let data: Vec<f64> = (0..300).map(|i| (i as f64 * 0.1).sin()).collect();
        let col1: Vec<f64> = data.iter().skip(1).step_by(3).copied().collect();
        let a = analyse(
            Column::of(&data, 3, 1).unwrap(),
            0.1,
            DataType::Rate,
            Estimator::Overlapping,
            &Taus::Spec(TauSpec::All),
            None,
        )
        .unwrap();
        let b = analyse(
            Column::contiguous(&col1),
            0.1,
            DataType::Rate,
            Estimator::Overlapping,
            &Taus::Spec(TauSpec::All),
            None,
        )
        .unwrap();
        assert_eq!(a, b);
    }

    #[test]
    fn non_finite_is_located() {
        let mut data = vec![0.0; 20];
        data[13] = f64::NAN;
        let err = angle_series(Column::contiguous(&data), 1.0, DataType::Rate).unwrap_err();
        assert_eq!(
            err,
            Error::NonFinite {
                name: "data",
                index: 13
            }
        );
    }
}
