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

pub mod batch;
pub mod confidence;
pub mod dynamic;
pub mod edf;
pub mod family;
mod fused;
pub mod gaps;
pub mod hadamard;
mod modified;
pub mod noise_id;
pub mod progress;
pub mod stream;
pub mod theo;
pub mod total;

use std::borrow::Cow;

use rayon::prelude::*;

pub use progress::Progress;

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
            // m_i = round(10^(i/p)) for i = 0..=p·log10(max_m), deduplicated. Only distinct
            // m (at most max_m of them) are visited: after each new m the index jumps to just
            // below the first i that can round to a larger one, so a huge `per_decade` costs
            // no more than `taus="all"` (instead of p·log10(max_m) steps and as much memory).
            let p = *per_decade as f64;
            if p > 5.0 * max_m as f64 {
                // Grid steps 10^(1/p) − 1 ≈ ln 10/p < 1/(2·max_m): every m is hit.
                return Ok((1..=max_m).collect());
            }
            let count = ((max_m as f64).log10() * p).floor();
            let at = |i: f64| (10f64.powf(i / p).round() as usize).clamp(1, max_m);
            let mut v = Vec::new();
            let mut i = 0.0_f64;
            while i <= count {
                let m = at(i);
                if v.last() != Some(&m) {
                    v.push(m);
                }
                // 10^(i/p) ≥ m + ½ needs i ≥ p·log10(m + ½); step back one for rounding.
                let next = ((m as f64 + 0.5).log10() * p).ceil() - 1.0;
                i = next.max(i + 1.0);
            }
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

    /// Samples `s..e` of this column (`s ≤ e ≤ len`).
    pub(crate) fn sub(&self, s: usize, e: usize) -> Column<'a> {
        let start = self.offset + s * self.stride;
        let end = if e > s {
            self.offset + (e - 1) * self.stride + 1
        } else {
            start
        };
        Column {
            data: &self.data[start..end],
            stride: self.stride,
            offset: 0,
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
    pub(crate) fn get(&self, i: usize) -> f64 {
        self.data[self.offset + i * self.stride]
    }
}

/// Block length of the parallel integration. Fixed (not derived from the thread count), so
/// results are identical however many threads run.
const INTEGRATION_BLOCK: usize = 1 << 16;

/// Sum of `f(i)` for `i in a..b` in 8 independent lanes (vectorisable; error ~√(len/8)·eps).
#[inline]
fn lane_sum(a: usize, b: usize, f: impl Fn(usize) -> f64) -> f64 {
    lane_sum_max(a, b, f).0
}

/// [`lane_sum`] of `f(i)` and, in the same pass, the largest `|f(i)|` (NaN ignored: it shows
/// in the sum).
#[inline]
fn lane_sum_max(a: usize, b: usize, f: impl Fn(usize) -> f64) -> (f64, f64) {
    let mut lanes = [0.0_f64; 8];
    let mut peaks = [0.0_f64; 8];
    let mut i = a;
    while i + 8 <= b {
        for (l, (lane, peak)) in lanes.iter_mut().zip(peaks.iter_mut()).enumerate() {
            let v = f(i + l);
            *lane += v;
            let m = v.abs();
            *peak = if m > *peak { m } else { *peak };
        }
        i += 8;
    }
    let mut tail = 0.0;
    let mut peak = peaks
        .iter()
        .fold(0.0_f64, |p, &q| if q > p { q } else { p });
    while i < b {
        let v = f(i);
        tail += v;
        if v.abs() > peak {
            peak = v.abs();
        }
        i += 1;
    }
    (lanes.iter().sum::<f64>() + tail, peak)
}

/// `(Σ f(i), Σ f(i)²)` for `i in a..b` in 8 independent lanes: [`lane_sum`] with the sum of
/// squares read in the same pass (the data's variance, see [`Moments`]).
#[inline]
fn lane_sum_squares(a: usize, b: usize, f: impl Fn(usize) -> f64) -> (f64, f64) {
    let mut lanes = [0.0_f64; 8];
    let mut squares = [0.0_f64; 8];
    let mut i = a;
    while i + 8 <= b {
        for (l, (lane, square)) in lanes.iter_mut().zip(squares.iter_mut()).enumerate() {
            let v = f(i + l);
            *lane += v;
            *square += v * v;
        }
        i += 8;
    }
    let (mut tail, mut tail_squares) = (0.0, 0.0);
    while i < b {
        let v = f(i);
        tail += v;
        tail_squares += v * v;
        i += 1;
    }
    (
        lanes.iter().sum::<f64>() + tail,
        squares.iter().sum::<f64>() + tail_squares,
    )
}

/// Sample moments of a series — count, mean and `M2 = Σ (v_i − mean)²` — from which the
/// data's variance `M2 / n` (the mean square deviation about the sample mean, NumPy's
/// `var(ddof=0)`) follows.
///
/// The Allan kernels read them off the pass that builds the angle series, with no extra pass
/// over memory: for rate data the block sums of the centred samples `c = v − v̄` (which the
/// integration needs anyway) are accompanied by the block sums of `c²`, and
/// `M2 = Σc² − (Σc)²/n` (the "corrected two-pass" algorithm, Chan, Golub & LeVeque 1983: the
/// correction removes the rounding error of `v̄`; no catastrophic cancellation, unlike
/// `Σv² − n·v̄²`, e.g. for an accelerometer at 9.81 with 1e-4 noise). For angle data they are
/// the moments of the rate `(x_{i+1} − x_i)/t0`, centred on the exact mean rate
/// `(x_{n−1} − x_0)/((n − 1)·t0)`. Pieces (gap-free segments) are combined with the pairwise
/// update of Chan, Golub & LeVeque (1979).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Moments {
    /// Number of samples.
    pub n: usize,
    /// Sample mean.
    pub mean: f64,
    /// Sum of squared deviations from the mean.
    pub m2: f64,
}

impl Moments {
    /// Moments from the sums `s1 = Σc`, `s2 = Σc²` of `n` values centred on `centre`.
    pub(crate) fn from_centred_sums(n: usize, centre: f64, s1: f64, s2: f64) -> Moments {
        if n == 0 {
            return Moments::default();
        }
        let nf = n as f64;
        Moments {
            n,
            mean: centre + s1 / nf,
            m2: (s2 - s1 * s1 / nf).max(0.0),
        }
    }

    /// The moments of the union of two disjoint samples (Chan, Golub & LeVeque 1979).
    #[must_use]
    pub fn combine(self, other: Moments) -> Moments {
        if self.n == 0 {
            return other;
        }
        if other.n == 0 {
            return self;
        }
        let n = self.n + other.n;
        let (a, b, nf) = (self.n as f64, other.n as f64, n as f64);
        let delta = other.mean - self.mean;
        Moments {
            n,
            mean: self.mean + delta * (b / nf),
            m2: self.m2 + other.m2 + delta * delta * (a / nf) * b,
        }
    }

    /// `M2 / n`, the variance about the sample mean (NumPy's `var`); `None` without samples.
    pub fn variance(&self) -> Option<f64> {
        (self.n > 0).then(|| self.m2 / self.n as f64)
    }
}

/// Moments of the rate of an angle column, `(x_{i+1} − x_i)·factor/t0`, together with the
/// column's sum and largest magnitude (unscaled, for the finiteness check and
/// [`scale_exponent`]), in one pass. `factor = 1` reads the data as given.
fn angle_pass(column: Column<'_>, factor: f64, t0: f64) -> (f64, f64, Moments) {
    let n = column.len();
    if n < 2 {
        let (sum, peak) = lane_sum_max(0, n, |i| column.get(i));
        return (sum, peak, Moments::default());
    }
    let slope = (column.get(n - 1) - column.get(0)) * factor / (n - 1) as f64;
    let (mut lanes, mut peaks) = ([0.0_f64; 8], [0.0_f64; 8]);
    let (mut s1, mut s2) = ([0.0_f64; 8], [0.0_f64; 8]);
    let mut i = 0;
    // Differences i = 0..n-1 read x_i and x_{i+1}: the last sample enters the sum separately.
    while i + 8 < n {
        for l in 0..8 {
            let v = column.get(i + l);
            lanes[l] += v;
            let m = v.abs();
            peaks[l] = if m > peaks[l] { m } else { peaks[l] };
            let c = (column.get(i + l + 1) - v) * factor - slope;
            s1[l] += c;
            s2[l] += c * c;
        }
        i += 8;
    }
    let mut sum = lanes.iter().sum::<f64>();
    let mut peak = peaks
        .iter()
        .fold(0.0_f64, |p, &q| if q > p { q } else { p });
    let (mut t1, mut t2) = (s1.iter().sum::<f64>(), s2.iter().sum::<f64>());
    while i < n {
        let v = column.get(i);
        sum += v;
        if v.abs() > peak {
            peak = v.abs();
        }
        if i + 1 < n {
            let c = (column.get(i + 1) - v) * factor - slope;
            t1 += c;
            t2 += c * c;
        }
        i += 1;
    }
    let moments = Moments::from_centred_sums(n - 1, slope, t1, t2);
    let moments = Moments {
        n: moments.n,
        mean: moments.mean / t0,
        m2: moments.m2 / (t0 * t0),
    };
    (sum, peak, moments)
}

/// Data whose largest magnitude lies in `[2^-SAFE_EXPONENT, 2^SAFE_EXPONENT]` are analysed as
/// given; others are first scaled by a power of two (see [`scale_exponent`]).
///
/// With `|Ω| ≤ 2^256` and `N·t0 ≤ 2^200` the angle series stays below `2^460`, so squares of
/// its differences and their sums stay below `2^930` (no overflow), and a nonzero difference
/// of such data (at least about an ulp of a sample, `≥ 2^-256-52`) squares to at least
/// `2^-616` (no underflow to subnormals).
const SAFE_EXPONENT: i32 = 256;

/// `⌊log2 |v|⌋` of a finite nonzero `v` (exact, subnormals included).
fn binary_exponent(v: f64) -> i32 {
    let bits = v.abs().to_bits();
    let biased = ((bits >> 52) & 0x7ff) as i32;
    if biased == 0 {
        let mantissa = bits & ((1_u64 << 52) - 1);
        63 - mantissa.leading_zeros() as i32 - 1074
    } else {
        biased - 1023
    }
}

/// The exponent `k` by which data of largest magnitude `max_abs` are scaled (`data·2^-k`) so
/// that the sums of squares can neither overflow nor underflow: 0 for magnitudes in the safe
/// range (ordinary data are analysed exactly as given), otherwise `⌊log2 max_abs⌋`, which puts
/// the largest sample in `[1, 2)`.
///
/// Scaling by a power of two is exact and commutes with every rounding of the estimators
/// (sums, differences, products with `t0`, divisions by counts), so the variances of the
/// scaled data times `4^k` are the variances of the data bit for bit wherever the latter are
/// representable, and deviations are `2^k·σ` (finite even where σ² over- or underflows).
pub fn scale_exponent(max_abs: f64) -> i32 {
    if max_abs == 0.0 || !max_abs.is_finite() {
        return 0;
    }
    let e = binary_exponent(max_abs);
    // Clamped to ±1022 so that the factor 2^-k is a normal number ([`pow2`]): subnormal data
    // (e < -1022; 2^1074 is not representable, and the bit pattern of 2^-(-1030) wrapped to a
    // tiny negative number, making every deviation 0) are scaled by 2^1022 to at least 2^-52,
    // data in [2^1023, 2^1024) by 2^-1022 to below 4: both well inside the safe range.
    if e.abs() <= SAFE_EXPONENT {
        0
    } else {
        e.clamp(-1022, 1022)
    }
}

/// Sample periods `t0` with `|⌊log2 t0⌋| ≤ PERIOD_EXPONENT` are used as given (every rate from
/// about 5e-20 Hz to 1.8e19 Hz); others are first split by [`split_period`].
const PERIOD_EXPONENT: i32 = 64;

/// `(t0', e)` with `t0 = t0'·2^e` exactly: `(t0, 0)` for ordinary periods, else `t0'` in
/// `[1, 2)`.
///
/// The estimators compute with `t0'` so that neither the angle series `t0·ΣΩ` nor `τ² = (m·t0)²`
/// over- or underflows at an extreme sample rate (fs = 1e286 made every squared difference
/// underflow to 0 and every variance 0/0 = NaN). The variances of rate data do not depend on
/// `t0` (the angle and τ scale together), those of angle data scale with `t0^-2`:
/// [`period_correction`] gives the power-of-two exponent to fold into the data's scale.
pub fn split_period(t0: f64) -> (f64, i32) {
    if !(t0.is_finite() && t0 > 0.0) {
        return (t0, 0);
    }
    let e = binary_exponent(t0);
    if e.abs() <= PERIOD_EXPONENT {
        (t0, 0)
    } else {
        (ldexp(t0, -e), e)
    }
}

/// The deviation exponent (deviations times `2^c`, variances times `4^c`) that brings a
/// variance computed with the period `t0' = t0·2^-e` of [`split_period`] back to `t0`: 0 for
/// rate data, `-e` for angle data (σ² ∝ 1/τ²); a statistic scaled by `τ²` (TVAR) adds `e`.
pub fn period_correction(data_type: DataType, e: i32, times_tau_squared: bool) -> i32 {
    let angle = if data_type == DataType::Angle { -e } else { 0 };
    angle + if times_tau_squared { e } else { 0 }
}

/// `2^k` for `-1022 ≤ k ≤ 1023`.
fn pow2(k: i32) -> f64 {
    debug_assert!((-1022..=1023).contains(&k));
    f64::from_bits(((k + 1023) as u64) << 52)
}

/// `x·2^e`, exact whenever the result is a normal number (the factor is applied in at most two
/// steps, the first as large as possible, so no intermediate over- or underflows needlessly).
pub fn ldexp(x: f64, e: i32) -> f64 {
    let first = e.clamp(-1022, 1023);
    let rest = e - first;
    if rest == 0 {
        x * pow2(first)
    } else {
        x * pow2(first) * pow2(rest.clamp(-1022, 1023))
    }
}

/// Integrated mean-removed rate, `x_0 = 0`, `x_k = t0·Σ_{i<k}(Ω_i·2^-k − Ω̄)`, written into
/// `out` (resized to `n + 1`; a buffer of the right length is reused without being cleared),
/// in three parallel passes over fixed blocks: (1) a copy of the samples into `out[1..]` and
/// their block sums for the mean and the finiteness check, with the largest magnitude,
/// (2) block sums of the centred rate, whose compensated prefix sums give each block's
/// starting angle, (3) the running sum inside each block, written in place, in parallel.
///
/// The data are scaled by `2^-k` with `k = scale` when given, else `k` =
/// [`scale_exponent`] of the largest magnitude (pass 1 is then repeated on the scaled data
/// when `k ≠ 0`, which only extreme data need). Returns `k` and the [`Moments`] of the scaled
/// rate (read off pass 2).
fn integrate_rate_into(
    column: Column<'_>,
    t0: f64,
    out: &mut Vec<f64>,
    progress: &Progress<'_>,
    scale: Option<i32>,
) -> Result<(i32, Moments)> {
    integrate_rate(column, t0, out, progress, scale, false)
}

/// [`integrate_rate_into`]; with `prefilled`, `out` already holds `n + 1` values, the samples
/// in `out[1..]` (copied by [`gather_wave`]), and pass 1 does not copy them again.
fn integrate_rate(
    column: Column<'_>,
    t0: f64,
    out: &mut Vec<f64>,
    progress: &Progress<'_>,
    scale: Option<i32>,
    prefilled: bool,
) -> Result<(i32, Moments)> {
    let n = column.len();
    let blocks: Vec<(usize, usize)> = (0..n)
        .step_by(INTEGRATION_BLOCK)
        .map(|a| (a, (a + INTEGRATION_BLOCK).min(n)))
        .collect();
    let stage = progress.stage(WORK_INTEGRATION * n as f64, 3 * blocks.len());
    let first_factor = pow2(-scale.unwrap_or(0));
    if prefilled {
        debug_assert_eq!(out.len(), n + 1, "a prefilled buffer holds the samples");
    } else if out.capacity() < n + 1 {
        // Zeroed allocation: pages are faulted in by the parallel writers below.
        *out = vec![0.0; n + 1];
    } else {
        // A reused buffer (pages already mapped): every value is overwritten below.
        out.truncate(n + 1);
        out.resize(n + 1, 0.0);
    }
    out[0] = 0.0;
    // Pass 1 copies the samples into `out[1..]`, where the later passes read them contiguous
    // (a column of a row-major matrix is read from memory once, not three times: each pass
    // over it touches every cache line of the matrix) and pass 3 integrates them in place.
    let first: Vec<(f64, f64)> = out[1..]
        .par_chunks_mut(INTEGRATION_BLOCK)
        .zip(blocks.par_iter())
        .map(|(slots, &(a, _))| {
            match column.as_slice() {
                _ if prefilled => {}
                Some(data) => slots.copy_from_slice(&data[a..a + slots.len()]),
                None => {
                    for (k, slot) in slots.iter_mut().enumerate() {
                        *slot = column.get(a + k);
                    }
                }
            }
            let s = lane_sum_max(0, slots.len(), |i| slots[i] * first_factor);
            stage.item_done();
            s
        })
        .collect();
    for (&(a, b), (s, _)) in blocks.iter().zip(&first) {
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
    let k = match scale {
        Some(k) => k,
        None => scale_exponent(first.iter().fold(0.0_f64, |p, &(_, q)| p.max(q))),
    };
    let factor = pow2(-k);
    let sums: Vec<f64> = if scale.is_none() && k != 0 {
        out[1..]
            .par_chunks(INTEGRATION_BLOCK)
            .map(|v| lane_sum(0, v.len(), |i| v[i] * factor))
            .collect()
    } else {
        first.iter().map(|&(s, _)| s).collect()
    };
    let mean = validate::neumaier_sum(sums.iter().copied()) / n as f64;
    if !mean.is_finite() {
        return Err(Error::invalid(
            "data",
            "values too large: their sum overflows float64",
        ));
    }
    progress.check()?;
    // The block sums of the centred rate and, in the same pass, of its squares: the data's
    // variance (see `Moments`) at the cost of one multiply-add per sample.
    let centred: Vec<(f64, f64)> = out[1..]
        .par_chunks(INTEGRATION_BLOCK)
        .map(|v| {
            let s = lane_sum_squares(0, v.len(), |i| v[i] * factor - mean);
            stage.item_done();
            s
        })
        .collect();
    let moments = Moments::from_centred_sums(
        n,
        mean,
        validate::neumaier_sum(centred.iter().map(|c| c.0)),
        validate::neumaier_sum(centred.iter().map(|c| c.1)),
    );
    // Compensated prefix sums: the starting (unscaled) angle of every block.
    let mut starts = Vec::with_capacity(blocks.len());
    let (mut sum, mut comp) = (0.0_f64, 0.0_f64);
    for &(c, _) in &centred {
        starts.push(sum + comp);
        let t = sum + c;
        if sum.abs() >= c.abs() {
            comp += (sum - t) + c;
        } else {
            comp += (c - t) + sum;
        }
        sum = t;
    }
    progress.check()?;
    out[1..]
        .par_chunks_mut(INTEGRATION_BLOCK)
        .zip(starts.par_iter())
        .for_each(|(out, &start)| {
            let mut acc = start;
            for slot in out.iter_mut() {
                acc += *slot * factor - mean;
                *slot = acc * t0;
            }
            stage.item_done();
        });
    progress.check()?;
    Ok((k, moments))
}

/// The angle series of `column`, scaled by `2^-k`, in `scratch` (or borrowed from the column
/// when it already is a contiguous angle series that needs no scaling): SPEC §2's integrated
/// mean-removed rate with `x_0 = 0`, or the angle input itself. `k` is [`scale_exponent`] of
/// the data unless `scale` fixes it. Non-finite input is an error naming its index. Returns
/// the series, `k` and the [`Moments`] of the rate scaled by `2^-k` (for angle input, of the
/// rate differences `(x_{i+1} − x_i)/t0`), read off the same pass.
fn angle_into<'a>(
    column: Column<'a>,
    t0: f64,
    data_type: DataType,
    scratch: &'a mut Vec<f64>,
    progress: &Progress<'_>,
    scale: Option<i32>,
) -> Result<(&'a [f64], i32, Moments)> {
    angle_into_prefilled(column, t0, data_type, scratch, progress, scale, false)
}

/// [`angle_into`]; `prefilled` rate samples already sit in `scratch[1..]` (see
/// [`integrate_rate`]).
fn angle_into_prefilled<'a>(
    column: Column<'a>,
    t0: f64,
    data_type: DataType,
    scratch: &'a mut Vec<f64>,
    progress: &Progress<'_>,
    scale: Option<i32>,
    prefilled: bool,
) -> Result<(&'a [f64], i32, Moments)> {
    validate::positive("fs", 1.0 / t0)?;
    match data_type {
        DataType::Angle => {
            let first_factor = pow2(-scale.unwrap_or(0));
            let (sum, peak, moments) = angle_pass(column, first_factor, t0);
            if !sum.is_finite() {
                if let Some(index) = column.first_non_finite() {
                    return Err(Error::NonFinite {
                        name: "data",
                        index,
                    });
                }
            }
            let k = scale.unwrap_or_else(|| scale_exponent(peak));
            // Extreme data (k ≠ 0 found here): the rate moments again, of the scaled samples
            // (their squares could over- or underflow as given), as for rate data.
            let moments = if scale.is_none() && k != 0 {
                angle_pass(column, pow2(-k), t0).2
            } else {
                moments
            };
            if k == 0 {
                if let Some(s) = column.as_slice() {
                    return Ok((s, 0, moments));
                }
            }
            let factor = pow2(-k);
            scratch.clear();
            scratch.extend(column.iter().map(|v| v * factor));
            Ok((scratch, k, moments))
        }
        DataType::Rate => {
            if column.is_empty() {
                scratch.clear();
                scratch.push(0.0);
                Ok((scratch, 0, Moments::default()))
            } else {
                let (k, moments) = integrate_rate(column, t0, scratch, progress, scale, prefilled)?;
                Ok((scratch, k, moments))
            }
        }
    }
}

/// The angle series the estimators work on (SPEC §2): integrated mean-removed rate with `x_0 = 0`,
/// or the angle input itself (borrowed when contiguous). The data are used as given (see
/// [`scaled_angle_series`] for data of extreme magnitude).
pub fn angle_series(column: Column<'_>, t0: f64, data_type: DataType) -> Result<Cow<'_, [f64]>> {
    Ok(scaled(column, t0, data_type, Some(0))?.0)
}

/// The angle series of the data scaled by `2^-k` and `k` ([`scale_exponent`] of the data: 0
/// for ordinary data, which are used as given). Variances computed from it are the data's
/// times `4^k` ([`ldexp`]`(v, 2k)`), deviations times `2^k`.
pub fn scaled_angle_series(
    column: Column<'_>,
    t0: f64,
    data_type: DataType,
) -> Result<(Cow<'_, [f64]>, i32)> {
    let (x, k, _) = scaled(column, t0, data_type, None)?;
    Ok((x, k))
}

/// [`scaled_angle_series`] with the [`Moments`] of the scaled rate read off the same pass
/// (the data's variance is `ldexp(m2/n, 2k)`, see [`data_variance`]).
pub fn scaled_angle_series_with_moments(
    column: Column<'_>,
    t0: f64,
    data_type: DataType,
) -> Result<(Cow<'_, [f64]>, i32, Moments)> {
    scaled(column, t0, data_type, None)
}

fn scaled(
    column: Column<'_>,
    t0: f64,
    data_type: DataType,
    scale: Option<i32>,
) -> Result<(Cow<'_, [f64]>, i32, Moments)> {
    let mut scratch = Vec::new();
    let (_, k, moments) = angle_into(
        column,
        t0,
        data_type,
        &mut scratch,
        &Progress::none(),
        scale,
    )?;
    if data_type == DataType::Angle && k == 0 {
        if let Some(s) = column.as_slice() {
            return Ok((Cow::Borrowed(s), 0, moments));
        }
    }
    Ok((Cow::Owned(scratch), k, moments))
}

/// The data's variance (unit², the rate's: for angle input the variance of the rate
/// differences) from the [`Moments`] of data scaled by `2^-k`, in the data's own scale
/// (`inf`/0 where it is beyond float64, like the Allan variances of such data); `None` when
/// it cannot be known (fewer than two samples).
pub fn data_variance(moments: &Moments, k: i32) -> Option<f64> {
    if moments.n < 2 {
        return None;
    }
    moments.variance().map(|v| ldexp(v, 2 * k))
}

/// The data's standard deviation `2^k·√(m2/n)` from the same [`Moments`]: computed before the
/// scale is restored, finite where [`data_variance`] over- or underflows (as
/// [`AllanAnalysis::deviation`] next to the variances).
pub fn data_deviation(moments: &Moments, k: i32) -> Option<f64> {
    if moments.n < 2 {
        return None;
    }
    moments.variance().map(|v| unscaled_deviation(v, k))
}

/// `σ = 2^k·√v` for a variance `v` of data scaled by `2^-k`: exactly `√(4^k·v)` wherever that
/// is representable, and finite where `4^k·v` is not.
pub fn unscaled_deviation(v: f64, k: i32) -> f64 {
    ldexp(v.sqrt(), k)
}

/// A result computed on data scaled by `2^-k` ([`scale_exponent`]), in the data's own scale:
/// variances and their bounds times `4^k`, deviations `2^k·√v`.
fn unscale(
    m: Vec<usize>,
    scaled_variance: &[f64],
    n_terms: Vec<usize>,
    confidence: Option<confidence::Intervals>,
    k: i32,
    moments: &Moments,
) -> AllanAnalysis {
    let deviation = scaled_variance
        .iter()
        .map(|&v| unscaled_deviation(v, k))
        .collect();
    let variance = scaled_variance.iter().map(|&v| ldexp(v, 2 * k)).collect();
    let (confidence, deviation_bounds) = match confidence {
        Some(mut ci) => {
            let low = ci.low.iter().map(|&v| unscaled_deviation(v, k)).collect();
            let high = ci.high.iter().map(|&v| unscaled_deviation(v, k)).collect();
            for v in ci.low.iter_mut().chain(ci.high.iter_mut()) {
                *v = ldexp(*v, 2 * k);
            }
            (Some(ci), Some((low, high)))
        }
        None => (None, None),
    };
    AllanAnalysis {
        m,
        variance,
        n_terms,
        confidence,
        deviation,
        deviation_bounds,
        blocks: None,
        data_variance: data_variance(moments, k),
        data_deviation: data_deviation(moments, k),
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

/// Term `k` of the total variance: the second difference at `i = k + 1` of the series
/// reflected at both ends, `x*_{-j} = 2x_0 − x_j` and `x*_{last+j} = 2x_last − x_{last−j}`
/// (`j = 1..n−2`, SP1065 eq. 25).
#[inline]
fn reflected_term(x: &[f64], m: usize, k: usize) -> f64 {
    let last = x.len() - 1;
    let star = |i: isize| -> f64 {
        if i < 0 {
            2.0 * x[0] - x[(-i) as usize]
        } else if (i as usize) > last {
            2.0 * x[last] - x[2 * last - i as usize]
        } else {
            x[i as usize]
        }
    };
    let (i, m) = (k as isize + 1, m as isize);
    star(i - m) - 2.0 * star(i) + star(i + m)
}

/// Total-variance sum on the reflected series (SP1065 eq. 25), without materialising it.
///
/// The terms, lanes and blocks of [`sum_squares`], in the same order (so the same bits): the
/// reflection is only looked up for the `≈ 2m` terms near the ends; a lane chunk wholly
/// inside reads the series directly, without a branch per sample (vectorised).
fn sum_total(x: &[f64], m: usize) -> f64 {
    let n = x.len();
    let last = n - 1;
    let reflected = |k: usize| reflected_term(x, m, k);
    // Term k reads x at k + 1 + {−m, 0, m}: inside for k ∈ [m − 1, last − m − 1].
    let (inside_from, inside_to) = (m - 1, (last + 1).saturating_sub(m + 1));
    let count = n - 2;
    let mut total = 0.0_f64;
    let mut comp = 0.0_f64;
    let mut start = 0;
    while start < count {
        let end = (start + BLOCK).min(count);
        let mut lanes = [0.0_f64; LANES];
        let mut k = start;
        while k + LANES <= end {
            if k >= inside_from && k + LANES <= inside_to {
                let i = k + 1;
                let a: &[f64; LANES] = x[i - m..i - m + LANES].try_into().expect("lanes");
                let b: &[f64; LANES] = x[i..i + LANES].try_into().expect("lanes");
                let c: &[f64; LANES] = x[i + m..i + m + LANES].try_into().expect("lanes");
                for (l, lane) in lanes.iter_mut().enumerate() {
                    let d = a[l] - 2.0 * b[l] + c[l];
                    *lane += d * d;
                }
            } else {
                for (l, lane) in lanes.iter_mut().enumerate() {
                    let d = reflected(k + l);
                    *lane += d * d;
                }
            }
            k += LANES;
        }
        let mut block: f64 = lanes.iter().sum();
        while k < end {
            let d = reflected(k);
            block += d * d;
            k += 1;
        }
        validate::neumaier_add(&mut total, &mut comp, block);
        start = end;
    }
    total + comp
}

/// [`sum_total`] as it was written first: [`sum_squares`] of the reflected terms (the
/// reference of the tests).
#[cfg(test)]
fn sum_total_reference(x: &[f64], m: usize) -> f64 {
    sum_squares(x.len() - 2, |k| reflected_term(x, m, k))
}

/// `variance = sum / (c·τ²·terms)` with the estimator's constant `c` (SP1065 eqs. 7, 11, 14,
/// 18, 25); `sum` is the raw sum of squared differences.
pub(crate) fn normalise(estimator: Estimator, sum: f64, m: usize, t0: f64, terms: usize) -> f64 {
    let tau = m as f64 * t0;
    match estimator {
        Estimator::Overlapping | Estimator::NonOverlapping | Estimator::Total => {
            sum / (2.0 * tau * tau * terms as f64)
        }
        Estimator::Modified => sum / (2.0 * (m * m) as f64 * tau * tau * terms as f64),
        Estimator::Hadamard => sum / (6.0 * tau * tau * terms as f64),
    }
}

/// The `TooShort` error of a factor outside `1..=estimator.max_factor(n_angle)`.
fn factor_too_large(estimator: Estimator, m: usize, n_angle: usize) -> Error {
    Error::TooShort {
        name: "data",
        needed: match estimator {
            Estimator::Overlapping | Estimator::NonOverlapping | Estimator::Total => 2 * m,
            Estimator::Modified => 3 * m - 1,
            Estimator::Hadamard => 3 * m,
        },
        got: n_angle.saturating_sub(1),
    }
}

/// Raw sum of one estimator at one factor by the per-τ kernels (all but the fused ones).
fn single_sum(x: &[f64], m: usize, estimator: Estimator, terms: usize) -> f64 {
    match estimator {
        Estimator::Overlapping => {
            fused::difference_sums(x, &[m], fused::Difference::Second, &Progress::none(), 0.0)[0]
        }
        Estimator::Hadamard => {
            fused::difference_sums(x, &[m], fused::Difference::Third, &Progress::none(), 0.0)[0]
        }
        Estimator::NonOverlapping => sum_squares(terms, |i| {
            let k = i * m;
            x[k + 2 * m] - 2.0 * x[k + m] + x[k]
        }),
        Estimator::Modified => modified::sum_modified(x, m, terms),
        Estimator::Total => sum_total(x, m),
    }
}

/// The variance of one estimator at one averaging factor, from an angle series.
///
/// Returns `(variance, n_terms)`. `m` must satisfy `1 ≤ m ≤ estimator.max_factor(x.len())`.
pub fn variance(x: &[f64], t0: f64, m: usize, estimator: Estimator) -> Result<(f64, usize)> {
    let max_m = estimator.max_factor(x.len());
    if m == 0 || m > max_m {
        return Err(factor_too_large(estimator, m, x.len()));
    }
    let terms = estimator.n_terms(x.len(), m);
    // Same kernels as the many-τ path, so one τ and a τ list give identical numbers.
    let sum = single_sum(x, m, estimator, terms);
    Ok((normalise(estimator, sum, m, t0, terms), terms))
}

/// Raw sums of squared differences at every factor in `ms` (the fused all-τ pass for the
/// overlapping Allan and Hadamard variances, τ in parallel otherwise); `weight` units of
/// progress are reported as the work completes.
pub(crate) fn raw_sums(
    x: &[f64],
    ms: &[usize],
    estimator: Estimator,
    progress: &Progress<'_>,
    weight: f64,
) -> Result<Vec<f64>> {
    let n = x.len();
    if let Some(&bad) = ms.iter().find(|&&m| m == 0 || m > estimator.max_factor(n)) {
        return Err(factor_too_large(estimator, bad, n));
    }
    let sums = match estimator {
        Estimator::Overlapping => {
            fused::difference_sums(x, ms, fused::Difference::Second, progress, weight)
        }
        Estimator::Hadamard => {
            fused::difference_sums(x, ms, fused::Difference::Third, progress, weight)
        }
        _ => {
            let stage = progress.stage(weight, ms.len());
            ms.par_iter()
                .with_max_len(1)
                .map(|&m| {
                    if stage.is_cancelled() {
                        return 0.0;
                    }
                    let s = single_sum(x, m, estimator, estimator.n_terms(n, m));
                    stage.item_done();
                    s
                })
                .collect()
        }
    };
    progress.check()?;
    Ok(sums)
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
    let sums = raw_sums(x, ms, estimator, &Progress::none(), 0.0)?;
    for (i, (&m, s)) in ms.iter().zip(sums).enumerate() {
        let terms = estimator.n_terms(x.len(), m);
        variances[i] = normalise(estimator, s, m, t0, terms);
        n_terms[i] = terms;
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
    /// Confidence intervals of the variance, when asked for.
    pub confidence: Option<confidence::Intervals>,
    /// Deviations `σ = √σ²`, computed before the data's scale is restored (see
    /// [`scale_exponent`]): finite even where the variance over- or underflows float64.
    pub deviation: Vec<f64>,
    /// Confidence bounds `(low, high)` of the deviation, when asked for (as [`Self::deviation`]).
    pub deviation_bounds: Option<(Vec<f64>, Vec<f64>)>,
    /// Block means of the rate for the stationarity check
    /// ([`crate::stationarity::check`]); `None` from the gap-aware and out-of-core kernels.
    pub blocks: Option<crate::stationarity::BlockMeans>,
    /// The data's variance (unit²: of the rate; for angle input of the rate differences
    /// `(x_{i+1} − x_i)/t0`), `Σ(v − v̄)²/n` over the samples used (gaps left out), read off
    /// the pass that builds the angle series ([`Moments`]); `None` for fewer than two samples.
    pub data_variance: Option<f64>,
    /// The data's standard deviation `√data_variance`, computed before the data's scale is
    /// restored: finite where the variance over- or underflows float64.
    pub data_deviation: Option<f64>,
}

/// Where the averaging factors come from.
#[derive(Debug, Clone, PartialEq)]
pub enum Taus {
    /// Generated from a specification, capped to what the data support.
    Spec(TauSpec),
    /// Explicit τ values in seconds (each a multiple of t0; too large is an error).
    Explicit(Vec<f64>),
}

impl Taus {
    /// The τ of a call: the `explicit` τ values (s) if given, else the specification `spec`:
    /// `"octave"`, `"decade"`, `"log"` (`per_decade` points per decade) or `"all"`.
    ///
    /// `per_decade` must be >= 1 whatever the specification: an out-of-range option is refused
    /// even where it is ignored (NumPy/SciPy convention; octave τ with `per_decade = 0` is a
    /// mistake the call that reads it must not be the first to notice).
    pub fn parse(spec: &str, per_decade: usize, explicit: Option<Vec<f64>>) -> Result<Self> {
        if per_decade == 0 {
            return Err(Error::invalid(
                "per_decade",
                "must be >= 1 (also where the τ grid does not use it), got 0",
            ));
        }
        if let Some(t) = explicit {
            return Ok(Taus::Explicit(t));
        }
        Ok(Taus::Spec(match spec {
            "octave" => TauSpec::Octave,
            "decade" => TauSpec::Decade,
            "log" => TauSpec::Log { per_decade },
            "all" => TauSpec::All,
            other => {
                return Err(Error::invalid(
                    "taus",
                    format!(
                        "must be 'octave', 'decade', 'log', 'all' or an array of seconds, \
                         got {other:?}"
                    ),
                ));
            }
        }))
    }
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

/// What to do with NaN samples.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Gaps {
    /// NaN (like inf) is an error naming its index.
    Error,
    /// NaN marks a missing sample: every term whose span touches one is left out (see
    /// [`gaps`]); inf is still an error.
    Omit,
}

impl Gaps {
    /// Parses `"error"` or `"omit"`.
    pub fn parse(name: &str) -> Result<Self> {
        match name {
            "error" => Ok(Gaps::Error),
            "omit" => Ok(Gaps::Omit),
            other => Err(Error::invalid(
                "gaps",
                format!("expected 'error' or 'omit', got {other:?}"),
            )),
        }
    }
}

/// Everything an analysis needs besides the data.
#[derive(Debug, Clone, PartialEq)]
pub struct Config {
    /// Sample period in seconds (1/fs).
    pub t0: f64,
    /// Rate or angle samples.
    pub data_type: DataType,
    /// Which variance.
    pub estimator: Estimator,
    /// Which τ.
    pub taus: Taus,
    /// Two-sided confidence level of the intervals; `None` skips noise identification.
    pub confidence: Option<f64>,
    /// NaN handling.
    pub gaps: Gaps,
}

impl Config {
    /// Checks the parameters that do not depend on the data.
    pub fn validate(&self) -> Result<()> {
        validate::positive("fs", 1.0 / self.t0)?;
        if let Some(level) = self.confidence {
            if !(level > 0.0 && level < 1.0) {
                return Err(Error::invalid(
                    "confidence",
                    format!("must lie strictly between 0 and 1, got {level}"),
                ));
            }
        }
        if self.gaps == Gaps::Omit && self.estimator == Estimator::Total {
            return Err(Error::invalid(
                "gaps",
                "'omit' is not defined for the total deviation: it reflects the record at its \
                 two ends, and a record with gaps has no single pair of ends (use the \
                 overlapping Allan, modified Allan or Hadamard deviation)",
            ));
        }
        Ok(())
    }

    /// Progress units of one column of `n` samples (integration, variances, intervals), in
    /// sample passes. Only proportions matter.
    pub(crate) fn work(&self, n: usize) -> f64 {
        let n = n as f64;
        let integration = match self.data_type {
            DataType::Rate => WORK_INTEGRATION * n,
            DataType::Angle => 0.0,
        };
        let ci = if self.confidence.is_some() {
            WORK_CONFIDENCE * n
        } else {
            0.0
        };
        integration + WORK_VARIANCES * n + ci
    }
}

/// Progress weights per sample of the three stages (their rough cost in memory passes).
const WORK_INTEGRATION: f64 = 3.0;
const WORK_VARIANCES: f64 = 4.0;
const WORK_CONFIDENCE: f64 = 3.0;

/// Reusable scratch memory of one column's analysis (the angle series, N + 1 values). A batch
/// keeps one per concurrently analysed column, so a new unit reuses pages that are already
/// mapped instead of faulting in a fresh N-sized buffer.
#[derive(Debug, Default)]
pub struct Workspace {
    angle: Vec<f64>,
    /// `angle[1..]` holds the next column's rate samples ([`gather_wave`]); reset by the
    /// analysis that uses them.
    prefilled: bool,
}

impl Workspace {
    /// An empty workspace (buffers grow on first use).
    pub fn new() -> Self {
        Self::default()
    }

    /// A workspace whose angle buffer is an idle one from earlier calls when there is one
    /// (see [`SPARE_BYTES`]), else empty.
    fn pooled() -> Self {
        let angle = SPARE
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .pop()
            .unwrap_or_default();
        Workspace {
            angle,
            prefilled: false,
        }
    }

    /// Hands the angle buffer back for later calls, within [`SPARE_BYTES`] in total.
    fn recycle(self) {
        let bytes = |v: &Vec<f64>| v.capacity() * std::mem::size_of::<f64>();
        let mut spare = SPARE
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        let held: usize = spare.iter().map(bytes).sum();
        if self.angle.capacity() > 0 && held + bytes(&self.angle) <= SPARE_BYTES {
            spare.push(self.angle);
        }
    }
}

/// Idle angle buffers kept between calls of [`analyse_matrix`] (at most [`SPARE_BYTES`]).
///
/// On these machines the first-touch page faults of a fresh N-sized buffer cost about as much
/// as the whole kernel, so a second analysis of a long record reuses the pages of the first
/// one instead of mapping new ones. Nothing in a result depends on a buffer's previous
/// contents: every value is written before it is read.
static SPARE: std::sync::Mutex<Vec<Vec<f64>>> = std::sync::Mutex::new(Vec::new());

/// Most memory [`SPARE`] holds between calls (256 MiB: three axes of 10⁷ samples).
const SPARE_BYTES: usize = 1 << 28;

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
    let config = Config {
        t0,
        data_type,
        estimator,
        taus: taus.clone(),
        confidence: confidence_level,
        gaps: Gaps::Error,
    };
    analyse_column(column, &config, &mut Workspace::new(), &Progress::none())
}

/// [`analyse`] with all options, reusing `workspace` and reporting to `progress`.
///
/// The result does not depend on the workspace's previous contents or on `progress`.
pub fn analyse_column(
    column: Column<'_>,
    config: &Config,
    workspace: &mut Workspace,
    progress: &Progress<'_>,
) -> Result<AllanAnalysis> {
    let prefilled = std::mem::replace(&mut workspace.prefilled, false);
    config.validate()?;
    if config.gaps == Gaps::Omit && column.iter().any(f64::is_nan) {
        return gaps::analyse(column, config, workspace, progress);
    }
    let ms = resolve_factors(
        &config.taus,
        column.len(),
        config.t0,
        config.data_type,
        config.estimator,
    )?;
    let estimator = config.estimator;
    // An extreme period is computed with as t0'·2^e (see split_period); τ were resolved above
    // with the period itself.
    let (t0, e) = split_period(config.t0);
    let (x, k, moments) = angle_into_prefilled(
        column,
        t0,
        config.data_type,
        &mut workspace.angle,
        progress,
        None,
        prefilled && config.data_type == DataType::Rate,
    )?;
    let n = column.len() as f64;
    let sums = raw_sums(x, &ms, estimator, progress, WORK_VARIANCES * n)?;
    let n_terms: Vec<usize> = ms.iter().map(|&m| estimator.n_terms(x.len(), m)).collect();
    let variance: Vec<f64> = ms
        .iter()
        .zip(&sums)
        .zip(&n_terms)
        .map(|((&m, &s), &t)| normalise(estimator, s, m, t0, t))
        .collect();
    let confidence = match config.confidence {
        Some(level) => {
            let ci = confidence::intervals(x, estimator, &ms, &variance, level)?;
            progress.advance(WORK_CONFIDENCE * n);
            progress.check()?;
            Some(ci)
        }
        None => None,
    };
    let k = k + period_correction(config.data_type, e, false);
    let mut result = unscale(ms, &variance, n_terms, confidence, k, &moments);
    // The block means of the stationarity check, read off the angle series: O(4096).
    result.blocks = Some(crate::stationarity::block_means_from_angle(x, t0, k));
    Ok(result)
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
    let config = Config {
        t0,
        data_type,
        estimator,
        taus: taus.clone(),
        confidence: confidence_level,
        gaps: Gaps::Error,
    };
    analyse_matrix(data, n_axes, &config, &Progress::none())
}

/// Every column of a row-major (samples × axes) buffer, axes in parallel, with progress.
///
/// Each axis is computed by the same code whatever the number of axes or their order, so a
/// column's result does not depend on its neighbours.
pub fn analyse_matrix(
    data: &[f64],
    n_axes: usize,
    config: &Config,
    progress: &Progress<'_>,
) -> Result<Vec<AllanAnalysis>> {
    config.validate()?;
    let columns = columns_of(data, n_axes)?;
    progress.add_total(columns.iter().map(|c| config.work(c.len())).sum());
    progress.start();
    // The axes run in waves of as many as the pool has threads, each wave's axes in parallel
    // with one workspace each, reused by the next wave: the angle buffers (N + 1 values per
    // axis) then hold `threads` columns at once, not a copy of the whole matrix (six axes on
    // two cores: a third of it). Each axis is computed by the same code either way, so the
    // results do not depend on the wave width; the first failing axis still wins (the axes
    // of earlier waves succeeded).
    let width = rayon::current_num_threads().clamp(1, n_axes.max(1));
    let mut workspaces: Vec<Workspace> = (0..width).map(|_| Workspace::pooled()).collect();
    let mut out = Vec::with_capacity(n_axes);
    let mut failed = None;
    for (wave, chunk) in columns.chunks(width).enumerate() {
        if config.data_type == DataType::Rate
            && config.gaps == Gaps::Error
            && chunk.len() > 1
            && chunk
                .iter()
                .all(|c| c.as_slice().is_none() && !c.is_empty())
        {
            gather_wave(chunk, &mut workspaces[..chunk.len()]);
        }
        match analyse_columns(chunk, config, &mut workspaces[..chunk.len()], progress) {
            Ok(results) => out.extend(results),
            Err((axis, e)) => {
                failed = Some((wave * width + axis, e));
                break;
            }
        }
    }
    for w in workspaces {
        w.recycle();
    }
    if let Some((axis, e)) = failed {
        return Err(locate(e, None, axis, n_axes));
    }
    progress.finish();
    Ok(out)
}

/// Copies the samples of a wave's (equally long, strided) columns into their workspaces'
/// angle buffers (`angle[1..]`), in one pass over the rows: each column read alone touches
/// every cache line of the row-major matrix, so a wave of `w` columns read them `w` times.
/// The analysis then integrates the samples in place ([`integrate_rate`]); the values, and so
/// the results, are those it would read from the columns.
fn gather_wave(columns: &[Column<'_>], workspaces: &mut [Workspace]) {
    let n = columns[0].len();
    let mut slices: Vec<std::slice::ChunksMut<'_, f64>> = Vec::with_capacity(workspaces.len());
    for ws in workspaces.iter_mut() {
        if ws.angle.capacity() < n + 1 {
            // Zeroed allocation: pages are faulted in by the parallel writers below.
            ws.angle = vec![0.0; n + 1];
        } else {
            ws.angle.truncate(n + 1);
            ws.angle.resize(n + 1, 0.0);
        }
        ws.prefilled = true;
        slices.push(ws.angle[1..].chunks_mut(INTEGRATION_BLOCK));
    }
    // Per row block, the chunk of every column's buffer.
    let mut blocks: Vec<Vec<&mut [f64]>> = Vec::with_capacity(n.div_ceil(INTEGRATION_BLOCK));
    'rows: loop {
        let mut block = Vec::with_capacity(slices.len());
        for s in &mut slices {
            match s.next() {
                Some(chunk) => block.push(chunk),
                None => break 'rows,
            }
        }
        blocks.push(block);
    }
    blocks.into_par_iter().enumerate().for_each(|(b, mut out)| {
        let a = b * INTEGRATION_BLOCK;
        for k in 0..out[0].len() {
            for (slot, column) in out.iter_mut().zip(columns) {
                slot[k] = column.get(a + k);
            }
        }
    });
}

fn columns_of(data: &[f64], n_axes: usize) -> Result<Vec<Column<'_>>> {
    (0..n_axes).map(|a| Column::of(data, n_axes, a)).collect()
}

/// Axes in parallel, each with its own workspace; the first failing axis (in axis order) wins.
fn analyse_columns(
    columns: &[Column<'_>],
    config: &Config,
    workspaces: &mut [Workspace],
    progress: &Progress<'_>,
) -> std::result::Result<Vec<AllanAnalysis>, (usize, Error)> {
    let results: Vec<Result<AllanAnalysis>> = columns
        .par_iter()
        .zip(workspaces.par_iter_mut())
        .with_max_len(1)
        .map(|(&c, ws)| analyse_column(c, config, ws, progress))
        .collect();
    results
        .into_iter()
        .enumerate()
        .map(|(axis, r)| r.map_err(|e| (axis, e)))
        .collect()
}

/// Names the unit, row and column of a non-finite value in a multi-axis or batch input.
fn locate(e: Error, unit: Option<usize>, axis: usize, n_axes: usize) -> Error {
    match e {
        Error::NonFinite { name, index } if n_axes > 1 || unit.is_some() => {
            let unit = unit.map_or(String::new(), |u| format!("unit {u}, "));
            let column = if n_axes > 1 {
                format!(", column {axis}")
            } else {
                String::new()
            };
            Error::invalid(
                name,
                format!("non-finite value (NaN or inf) at {unit}row {index}{column}"),
            )
        }
        other => match unit {
            Some(u) => match other {
                Error::TooShort { .. } | Error::Cancelled => other,
                Error::InvalidParameter { name, reason } if name == "data" => {
                    Error::invalid(name, format!("unit {u}: {reason}"))
                }
                other => other,
            },
            None => other,
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const RATE: [f64; 8] = [1.0, 3.0, 2.0, 5.0, 4.0, 6.0, 8.0, 7.0];

    /// Two-pass variance (mean, then the mean square of the deviations): the reference.
    fn two_pass(v: &[f64]) -> f64 {
        let mean = v.iter().sum::<f64>() / v.len() as f64;
        v.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / v.len() as f64
    }

    #[test]
    fn data_variance_is_read_off_every_path() {
        // An accelerometer at 9.81 with 1e-4 noise, 200 001 samples (several integration
        // blocks): no cancellation (Σv² − n v̄² would keep ~1e-8 of the digits).
        let noise = crate::random::normal_vec(200_001, 21);
        let rate: Vec<f64> = noise.iter().map(|v| 9.81 + 1e-4 * v).collect();
        let want = two_pass(&rate);
        for estimator in [
            Estimator::Overlapping,
            Estimator::Modified,
            Estimator::Total,
        ] {
            let a = analyse(
                Column::contiguous(&rate),
                0.01,
                DataType::Rate,
                estimator,
                &Taus::Spec(TauSpec::Octave),
                None,
            )
            .unwrap();
            let got = a.data_variance.unwrap();
            assert!(
                (got - want).abs() <= 1e-10 * want,
                "{estimator:?}: {got} vs {want}"
            );
        }
        // Angle input: the variance of the rate differences.
        let mut angle = vec![3.0];
        for v in &rate {
            angle.push(angle[angle.len() - 1] + v * 0.01);
        }
        let diffs: Vec<f64> = angle.windows(2).map(|w| (w[1] - w[0]) / 0.01).collect();
        let a = analyse(
            Column::contiguous(&angle),
            0.01,
            DataType::Angle,
            Estimator::Overlapping,
            &Taus::Spec(TauSpec::Octave),
            None,
        )
        .unwrap();
        let (got, want) = (a.data_variance.unwrap(), two_pass(&diffs));
        assert!((got - want).abs() <= 1e-9 * want, "angle: {got} vs {want}");
        // Pieces combined (gaps) equal the whole.
        let (x, y) = rate.split_at(70_000);
        let m = |v: &[f64]| {
            let mean = v.iter().sum::<f64>() / v.len() as f64;
            let c: Vec<f64> = v.iter().map(|x| x - mean).collect();
            Moments::from_centred_sums(v.len(), mean, c.iter().sum(), c.iter().map(|c| c * c).sum())
        };
        let whole = m(x).combine(m(y)).variance().unwrap();
        assert!((whole - two_pass(&rate)).abs() <= 1e-10 * whole);
        assert_eq!(data_variance(&Moments::default(), 0), None);
    }

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
    fn total_interior_chunks_give_the_reflected_sum_bits() {
        // The branch-free interior against the reflection looked up for every term: same
        // terms, lanes and blocks, so the same bits; short series (no interior chunk), chunks
        // straddling the ends, several blocks, every factor of a short series.
        for n in [3, 4, 9, 17, 40, 4099, 9000, 20_001] {
            let rate: Vec<f64> = (0..n)
                .map(|i| ((i * 7919 % 1013) as f64) / 101.0 - 5.0 + 1e-3 * i as f64)
                .collect();
            let x = angle_series(Column::contiguous(&rate), 0.01, DataType::Rate).unwrap();
            let max = Estimator::Total.max_factor(x.len());
            let ms: Vec<usize> = if max <= 40 {
                (1..=max).collect()
            } else {
                vec![1, 2, 3, 7, 8, 9, 64, 1000, max / 2, max - 1, max]
            };
            for m in ms.into_iter().filter(|&m| m >= 1 && m <= max) {
                assert_eq!(
                    sum_total(&x, m).to_bits(),
                    sum_total_reference(&x, m).to_bits(),
                    "n = {n}, m = {m}"
                );
            }
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
        // Reference: every index of the log grid, deduplicated.
        for (p, max_m) in [
            (1, 1000),
            (3, 5000),
            (10, 1000),
            (37, 123_457),
            (1000, 2000),
        ] {
            let mut want: Vec<usize> = (0..=((max_m as f64).log10() * p as f64).floor() as usize)
                .map(|i| (10f64.powf(i as f64 / p as f64).round() as usize).clamp(1, max_m))
                .collect();
            want.dedup();
            let got = averaging_factors(&TauSpec::Log { per_decade: p }, max_m).unwrap();
            assert_eq!(got, want, "per_decade {p}, max_m {max_m}");
        }
        // A huge density is every m, computed in O(max_m) (it used to allocate p·log10 m).
        let every = averaging_factors(
            &TauSpec::Log {
                per_decade: 1 << 40,
            },
            5000,
        )
        .unwrap();
        assert_eq!(every, (1..=5000).collect::<Vec<_>>());
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

    /// Normal noise on a slow random walk (cumulative sum of normal steps), from the core's
    /// seeded generator.
    fn walk(n: usize, axes: usize) -> Vec<f64> {
        let noise = crate::random::normal_vec(n * axes, 7);
        let steps = crate::random::normal_vec(n * axes, 8);
        let mut level = 0.0;
        noise
            .iter()
            .zip(&steps)
            .map(|(&u, &s)| {
                level += 1e-3 * s;
                u + level
            })
            .collect()
    }

    fn configs() -> Vec<Config> {
        let mut out = Vec::new();
        for estimator in [
            Estimator::Overlapping,
            Estimator::NonOverlapping,
            Estimator::Modified,
            Estimator::Hadamard,
            Estimator::Total,
        ] {
            out.push(Config {
                t0: 0.01,
                data_type: DataType::Rate,
                estimator,
                taus: Taus::Spec(TauSpec::Log { per_decade: 5 }),
                confidence: Some(0.683),
                gaps: Gaps::Error,
            });
        }
        out
    }

    #[test]
    fn hook_does_not_change_results() {
        let data = walk(200_003, 2);
        for cfg in configs() {
            let plain = analyse_matrix(&data, 2, &cfg, &Progress::none()).unwrap();
            let seen = std::sync::Mutex::new(Vec::new());
            let hook = |f: f64| {
                seen.lock().unwrap().push(f);
                true
            };
            let reported = analyse_matrix(&data, 2, &cfg, &Progress::new(Some(&hook))).unwrap();
            assert_eq!(plain, reported, "{:?}", cfg.estimator);
            let seen = seen.into_inner().unwrap();
            assert_eq!((seen[0], *seen.last().unwrap()), (0.0, 1.0));
            assert!(seen.windows(2).all(|w| w[0] < w[1]));
        }
    }

    #[test]
    fn thread_count_does_not_change_results() {
        let data = walk(300_001, 1);
        for cfg in configs() {
            let run = |threads: usize| {
                rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .unwrap()
                    .install(|| analyse_matrix(&data, 1, &cfg, &Progress::none()).unwrap())
            };
            let one = run(1);
            assert_eq!(one, run(3), "{:?}", cfg.estimator);
            assert_eq!(one, run(8), "{:?}", cfg.estimator);
        }
    }

    #[test]
    fn cancel_stops_with_an_error() {
        let data = walk(300_000, 1);
        let hook = |f: f64| f < 0.3;
        let err = analyse_matrix(&data, 1, &configs()[0], &Progress::new(Some(&hook)));
        assert_eq!(err, Err(Error::Cancelled));
    }

    #[test]
    fn workspace_reuse_does_not_change_results() {
        let a = walk(100_000, 1);
        let b = walk(70_000, 1);
        let cfg = &configs()[0];
        let mut ws = Workspace::new();
        let fresh = analyse_column(
            Column::contiguous(&b),
            cfg,
            &mut Workspace::new(),
            &Progress::none(),
        );
        analyse_column(Column::contiguous(&a), cfg, &mut ws, &Progress::none()).unwrap();
        let reused = analyse_column(Column::contiguous(&b), cfg, &mut ws, &Progress::none());
        assert_eq!(fresh, reused);
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

    #[test]
    fn binary_exponent_and_ldexp() {
        for (v, e) in [
            (1.0, 0),
            (1.5, 0),
            (2.0, 1),
            (0.75, -1),
            (f64::MAX, 1023),
            (f64::MIN_POSITIVE, -1022),
            (5e-324, -1074),
            (1e-310, -1030),
        ] {
            assert_eq!(binary_exponent(v), e, "{v}");
            assert_eq!(binary_exponent(-v), e, "{v}");
        }
        assert_eq!(scale_exponent(3.0), 0);
        assert_eq!(scale_exponent(0.0), 0);
        assert_eq!(scale_exponent(1e300), 996);
        assert_eq!(scale_exponent(1e-300), -997);
        assert_eq!(ldexp(1.5, 2000 - 1000), 1.5 * 2f64.powi(1000));
        assert_eq!(ldexp(3.0 * 2f64.powi(-600), 1500), 3.0 * 2f64.powi(900));
        assert_eq!(ldexp(3.0 * 2f64.powi(600), -1500), 3.0 * 2f64.powi(-900));
        assert_eq!(ldexp(1.0, -1074), 5e-324);
        assert_eq!(ldexp(1.0, 1024), f64::INFINITY);
        assert_eq!(ldexp(1.0, -1076), 0.0);
    }

    /// Noise whose samples all lie in [0.25, 8) in magnitude, so `x·2^k` is exact for every
    /// `k` in [-1000, 1000].
    fn representable_noise(n: usize) -> Vec<f64> {
        crate::random::normal_vec(n, 11)
            .into_iter()
            .map(|z| z.signum() * (0.25 + z.abs()).min(7.9))
            .collect()
    }

    fn assert_scaled(a: &AllanAnalysis, b: &AllanAnalysis, k: i32, what: &str) {
        assert_eq!(a.m, b.m, "{what}");
        assert_eq!(a.n_terms, b.n_terms, "{what}");
        for (&x, &y) in a.deviation.iter().zip(&b.deviation) {
            assert_eq!(x, ldexp(y, k), "{what} k={k}");
        }
        for (&x, &y) in a.variance.iter().zip(&b.variance) {
            assert_eq!(x, ldexp(y, 2 * k), "{what} k={k}");
        }
        match (&a.confidence, &b.confidence) {
            (Some(ca), Some(cb)) => {
                assert_eq!(ca.alpha, cb.alpha, "{what} k={k}");
                assert_eq!(ca.edf, cb.edf, "{what} k={k}");
                for (&x, &y) in ca
                    .low
                    .iter()
                    .zip(&cb.low)
                    .chain(ca.high.iter().zip(&cb.high))
                {
                    assert_eq!(x, ldexp(y, 2 * k), "{what} k={k}");
                }
                let (la, ha) = a.deviation_bounds.as_ref().unwrap();
                let (lb, hb) = b.deviation_bounds.as_ref().unwrap();
                for (&x, &y) in la.iter().zip(lb).chain(ha.iter().zip(hb)) {
                    assert_eq!(x, ldexp(y, k), "{what} k={k}");
                }
            }
            (None, None) => {}
            _ => panic!("{what}: confidence present on one side only"),
        }
    }

    #[test]
    fn extreme_magnitudes_scale_exactly() {
        // σ(x·2^k) = 2^k·σ(x) bit for bit, for every estimator, rate and angle input, with
        // and without gaps, far beyond where the squares used to over- or underflow.
        let base = representable_noise(20_000);
        let mut gapped = base.clone();
        for v in &mut gapped[5000..5100] {
            *v = f64::NAN;
        }
        for k in [-1000, -700, -300, -257, -100, 0, 100, 257, 300, 700, 1000] {
            let f = ldexp(1.0, k);
            let scaled: Vec<f64> = base.iter().map(|v| v * f).collect();
            let scaled_gapped: Vec<f64> = gapped.iter().map(|v| v * f).collect();
            for mut cfg in configs() {
                for data_type in [DataType::Rate, DataType::Angle] {
                    cfg.data_type = data_type;
                    cfg.taus = Taus::Spec(TauSpec::Octave);
                    let run = |d: &[f64], c: &Config| {
                        analyse_column(
                            Column::contiguous(d),
                            c,
                            &mut Workspace::new(),
                            &Progress::none(),
                        )
                        .unwrap()
                    };
                    let what = format!("{:?} {data_type:?}", cfg.estimator);
                    assert_scaled(&run(&scaled, &cfg), &run(&base, &cfg), k, &what);
                    if cfg.estimator != Estimator::Total {
                        let mut omit = cfg.clone();
                        omit.gaps = Gaps::Omit;
                        assert_scaled(
                            &run(&scaled_gapped, &omit),
                            &run(&gapped, &omit),
                            k,
                            &format!("{what} gaps"),
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn huge_and_tiny_data_give_finite_deviations() {
        // The cases of issue 10: ×1e300 used to give NaN, ×1e-300 zeros.
        let x = crate::random::normal_vec(50_000, 4);
        let cfg = &configs()[0];
        let plain = analyse_column(
            Column::contiguous(&x),
            cfg,
            &mut Workspace::new(),
            &Progress::none(),
        )
        .unwrap();
        for factor in [1e300, 1e-300, 1e200, 1e-200] {
            let y: Vec<f64> = x.iter().map(|v| v * factor).collect();
            let r = analyse_column(
                Column::contiguous(&y),
                cfg,
                &mut Workspace::new(),
                &Progress::none(),
            )
            .unwrap();
            let ci = r.confidence.as_ref().unwrap();
            assert_eq!(ci.alpha, plain.confidence.as_ref().unwrap().alpha);
            for (&d, &p) in r.deviation.iter().zip(&plain.deviation) {
                // x·1e300 is not exactly 2^k·x: the products are rounded once each, which
                // moves σ by about one ulp per sample, well below 1e-12.
                assert!(d.is_finite() && d > 0.0, "{factor}: {d}");
                assert!(
                    (d / (p * factor) - 1.0).abs() < 1e-12,
                    "{factor}: {d} vs {p}"
                );
            }
        }
    }

    #[test]
    fn extreme_sample_periods_give_the_ordinary_result() {
        // Issue 27: fs = 1e286 made every squared difference of t0·ΣΩ underflow (NaN σ). Rate
        // deviations do not depend on t0; angle deviations scale with 1/t0.
        let x = crate::random::normal_vec(4000, 9);
        let base = |t0: f64, data_type: DataType, estimator: Estimator| {
            let cfg = Config {
                t0,
                data_type,
                estimator,
                taus: Taus::Spec(TauSpec::Octave),
                confidence: Some(0.683),
                gaps: Gaps::Error,
            };
            analyse_column(
                Column::contiguous(&x),
                &cfg,
                &mut Workspace::new(),
                &Progress::none(),
            )
            .unwrap()
        };
        for estimator in [
            Estimator::Overlapping,
            Estimator::Modified,
            Estimator::Hadamard,
            Estimator::Total,
        ] {
            let rate = base(1.0, DataType::Rate, estimator);
            let angle = base(1.0, DataType::Angle, estimator);
            for t0 in [1e-286, 1e-300, 1e300, 2f64.powi(-1000), 1e-200] {
                let r = base(t0, DataType::Rate, estimator);
                for (&d, &p) in r.deviation.iter().zip(&rate.deviation) {
                    assert!(
                        (d / p - 1.0).abs() < 1e-12,
                        "{estimator:?} t0={t0}: {d} vs {p}"
                    );
                }
                let a = base(t0, DataType::Angle, estimator);
                for (&d, &p) in a.deviation.iter().zip(&angle.deviation) {
                    let want = p / t0;
                    if want.is_finite() && want > f64::MIN_POSITIVE {
                        assert!((d / want - 1.0).abs() < 1e-12, "{estimator:?} t0={t0}");
                    }
                }
            }
        }
        assert_eq!(split_period(0.01), (0.01, 0));
        let (t, e) = split_period(1e-286);
        assert!((1.0..2.0).contains(&t) && ldexp(t, e) == 1e-286);
    }
}
