//! What a log's timestamps say about its sampling: rate, jitter, gaps, repeated and
//! out-of-order stamps, and the times of the samples missing in the gaps.
//!
//! Allan analysis assumes uniform sampling; these routines measure how far a log is from it.
//! With `Δt_i = t_i − t_{i−1}` the intervals and `m = median(Δt > 0)`:
//!
//! ```text
//! gap:        Δt_i > 1.5·m                          (GAP_FACTOR)
//! repeated:   Δt_i = 0
//! regular:    0 < Δt_i ≤ 1.5·m
//! fs  = 1 / mean(regular Δt),   rounded to 9 significant digits
//! jitter = std(regular Δt) / m  (population s.d.)
//! missing samples in a gap of length g:  round(g/m) − 1  (ties to even)
//! ```
//!
//! The mean of the regular intervals is unaffected by gaps like the median, but not stuck on one
//! quantised interval value; the 9 significant digits drop the decimal-rounding noise of
//! timestamps written as text (`0.0100` s → 100.00000000000213 Hz without it). A time unit not
//! stated is guessed from the median positive step of the raw stamps: nanoseconds from
//! [`NS_THRESHOLD`] = 10⁵ up (rates up to 10 kHz; no gyro log has samples 10⁵ s apart),
//! microseconds from [`US_THRESHOLD`] = 10³ up to it (rates 10 Hz – 1 kHz: `micros()` clocks,
//! x-io and YEI logs, which read as nanoseconds gave 1000× the rate), seconds below. A gap of `c` missing samples between `t_a` and `t_b` is
//! filled with `t_a + (t_b − t_a)·j/(c + 1)`, `j = 1..c`.
//!
//! Raw stamps may be integers (`i64`, exact epoch nanoseconds) or floats; intervals are
//! floats in seconds. Every scan is one pass without full-length temporaries; the median too:
//! it is selected exactly from the IEEE-754 bits of the positive intervals (a positive double's
//! bits order like its value), 16 bits per pass over the data with a 2¹⁶-bin histogram
//! (five passes in all), so a log of any length is analysed in O(1) extra memory. The
//! intervals can be formed on the fly from the raw stamps ([`analyse_stamps`]): the loader
//! never holds a full-length array of them.

use rayon::prelude::*;

use crate::validate;
use crate::{Error, Result};

/// Intervals longer than this multiple of the median interval count as gaps.
pub const GAP_FACTOR: f64 = 1.5;
/// A median raw step at least this large means the stamps are nanoseconds (unit guess): as
/// nanoseconds, a smaller step would be a rate above 10 kHz.
pub const NS_THRESHOLD: f64 = 1e5;
/// A median raw step at least this large, and below [`NS_THRESHOLD`], means microseconds
/// (10 Hz – 1 kHz; as seconds it would be a sample every 17 minutes or more).
pub const US_THRESHOLD: f64 = 1e3;
/// Relative jitter (s.d. of the regular intervals / median interval) above which the sampling
/// is called irregular.
pub const JITTER_WARN: f64 = 0.01;
/// A given sample rate differing from the timestamps' estimate by more than this (relative)
/// disagrees with them.
pub const FS_TOLERANCE: f64 = 0.01;

/// A raw timestamp type: integer nanoseconds or floating-point values.
pub trait Stamp: Copy + PartialOrd {
    /// `self − earlier` as a float (exact for integer stamps whose difference is below 2⁵³).
    fn step_from(self, earlier: Self) -> f64;
}

impl Stamp for i64 {
    #[allow(clippy::cast_precision_loss)]
    fn step_from(self, earlier: Self) -> f64 {
        // i128 keeps the difference exact even across the whole i64 range.
        (i128::from(self) - i128::from(earlier)) as f64
    }
}

impl Stamp for f64 {
    fn step_from(self, earlier: Self) -> f64 {
        self - earlier
    }
}

/// Median of the positive steps `t_i − t_{i−1}` of raw stamps (0 if none is positive), in
/// O(1) extra memory (module docs).
pub fn median_positive_step<T: Stamp + Sync>(stamps: &[T]) -> f64 {
    let n = stamps.len().saturating_sub(1);
    median_positive(n, |i| stamps[i + 1].step_from(stamps[i])).unwrap_or(0.0)
}

/// Bins of one radix-selection pass (16 bits of a double's bit pattern).
const RADIX_BINS: usize = 1 << 16;
/// Values per parallel task of a selection pass (each task has its own histogram).
const RADIX_TASK: usize = 1 << 18;

/// Histogram of the 16 bits below `shift + 16` of every positive value `value(i)`, `i < n`,
/// whose bits above `shift + 16` equal `prefix`.
fn radix_histogram(
    n: usize,
    value: &(impl Fn(usize) -> f64 + Sync),
    shift: u32,
    prefix: u64,
) -> Vec<u64> {
    let tasks = n.div_ceil(RADIX_TASK);
    (0..tasks)
        .into_par_iter()
        .fold(
            || vec![0_u64; RADIX_BINS],
            |mut hist, t| {
                for i in t * RADIX_TASK..((t + 1) * RADIX_TASK).min(n) {
                    let v = value(i);
                    if v > 0.0 {
                        let bits = v.to_bits();
                        let high = bits.checked_shr(shift + 16).unwrap_or(0);
                        if high == prefix {
                            hist[((bits >> shift) & 0xFFFF) as usize] += 1;
                        }
                    }
                }
                hist
            },
        )
        .reduce(
            || vec![0_u64; RADIX_BINS],
            |mut a, b| {
                for (x, y) in a.iter_mut().zip(b) {
                    *x += y;
                }
                a
            },
        )
}

/// The `k`-th smallest (0-based) positive value of `value(0..n)`, exactly, by radix selection
/// on the bit patterns (four 16-bit passes); `first` is the histogram of the first pass.
fn kth_positive(n: usize, value: &(impl Fn(usize) -> f64 + Sync), first: &[u64], k: u64) -> f64 {
    let mut prefix = 0_u64;
    let mut rank = k;
    let mut owned;
    let mut hist = first;
    for shift in [48_u32, 32, 16, 0] {
        if shift != 48 {
            owned = radix_histogram(n, value, shift, prefix);
            hist = &owned;
        }
        let mut bin = 0;
        for (b, &c) in hist.iter().enumerate() {
            if rank < c {
                bin = b;
                break;
            }
            rank -= c;
        }
        prefix = (prefix << 16) | bin as u64;
    }
    f64::from_bits(prefix)
}

/// Median of the positive values among `value(0..n)` (`None` if there is none): the middle
/// one, or the mean of the two middle ones (`f64::midpoint`, NumPy's `median`), selected
/// exactly in O(1) extra memory (module docs).
fn median_positive(n: usize, value: impl Fn(usize) -> f64 + Sync) -> Option<f64> {
    let first = radix_histogram(n, &value, 48, 0);
    let count: u64 = first.iter().sum();
    if count == 0 {
        return None;
    }
    let mid = count / 2;
    let upper = kth_positive(n, &value, &first, mid);
    if count % 2 == 1 {
        return Some(upper);
    }
    // The value just below the middle: `upper` itself when fewer than `mid` values are smaller.
    let (smaller, largest_below) = (0..n)
        .into_par_iter()
        .with_min_len(RADIX_TASK)
        .map(&value)
        .filter(|v| *v > 0.0 && *v < upper)
        .fold(|| (0_u64, 0.0_f64), |(c, m), v| (c + 1, m.max(v)))
        .reduce(|| (0, 0.0), |a, b| (a.0 + b.0, a.1.max(b.1)));
    let lower = if smaller >= mid { largest_below } else { upper };
    Some(f64::midpoint(lower, upper))
}

/// The unit of stamps whose median positive step is `median_step` when no unit is stated:
/// `"ns"` from [`NS_THRESHOLD`] up, `"us"` from [`US_THRESHOLD`] up to it, else `"s"`
/// (module docs).
pub fn guess_unit(median_step: f64) -> &'static str {
    if median_step >= NS_THRESHOLD {
        "ns"
    } else if median_step >= US_THRESHOLD {
        "us"
    } else {
        "s"
    }
}

/// Rows `i ≥ 1` whose stamp is earlier than the one before (`t_i < t_{i−1}`).
pub fn backward_rows<T: Stamp>(stamps: &[T]) -> Vec<usize> {
    rows_where(stamps, |a, b| b < a)
}

/// Rows `i ≥ 1` whose stamp repeats the one before (`t_i = t_{i−1}`).
pub fn repeated_rows<T: Stamp>(stamps: &[T]) -> Vec<usize> {
    #[allow(clippy::float_cmp)] // exact repetition is what is asked
    rows_where(stamps, |a, b| b == a)
}

fn rows_where<T: Stamp>(stamps: &[T], test: impl Fn(T, T) -> bool) -> Vec<usize> {
    stamps
        .windows(2)
        .enumerate()
        .filter(|(_, w)| test(w[0], w[1]))
        .map(|(i, _)| i + 1)
        .collect()
}

/// The sampling statistics of a log's intervals (see [`analyse`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Sampling {
    /// Median of the positive intervals, s.
    pub median_interval: f64,
    /// `1/mean(regular intervals)` rounded to 9 significant digits, Hz.
    pub fs_estimated: f64,
    /// Population s.d. of the regular intervals over the median (0 with fewer than two).
    pub jitter: f64,
    /// Row (index of the sample after the interval) of every gap.
    pub gap_rows: Vec<usize>,
    /// Length of every gap interval, s.
    pub gap_durations: Vec<f64>,
    /// `Σ round(gap/median) − 1` over the gaps.
    pub missing_samples: u64,
    /// Row of the second sample of every repeated timestamp.
    pub duplicate_rows: Vec<usize>,
}

/// Rounds to 9 significant decimal digits (correctly rounded, as Python's `f"{x:.9g}"`).
fn nine_digits(x: f64) -> f64 {
    format!("{x:.8e}").parse().unwrap_or(x)
}

/// Missing samples in a gap of length `gap` at median interval `median`: `round(gap/median) − 1`
/// (ties to even), at least 0.
#[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
pub fn missing_in_gap(gap: f64, median: f64) -> u64 {
    let r = (gap / median).round_ties_even() - 1.0;
    if r > 0.0 { r as u64 } else { 0 }
}

/// Rate, jitter, gaps and repeated stamps from the intervals `Δt_i = t_i − t_{i−1}` (s) of a
/// log in time order (module docs). Interval `i` (0-based) ends at row `i + 1`.
///
/// # Errors
/// A non-finite or negative interval ([`Error::NonFinite`] / [`Error::InvalidParameter`], named
/// `intervals`: the stamps must be finite and sorted first); no positive interval (the time
/// does not advance).
pub fn analyse(intervals: &[f64]) -> Result<Sampling> {
    validate::finite("intervals", intervals)?;
    analyse_by(intervals.len(), |i| intervals[i])
}

/// [`analyse`] of the intervals `(t_{i+1} − t_i)/per_second` of raw stamps in time order,
/// formed on the fly (the same values, bit for bit, as dividing the differences
/// [`Stamp::step_from`] by `per_second`): no full-length array of intervals is made.
///
/// # Errors
/// As [`analyse`]; `per_second` not finite and positive.
pub fn analyse_stamps<T: Stamp + Sync>(stamps: &[T], per_second: f64) -> Result<Sampling> {
    validate::positive("per_second", per_second)?;
    let n = stamps.len().saturating_sub(1);
    let interval = |i: usize| stamps[i + 1].step_from(stamps[i]) / per_second;
    if let Some(index) = (0..n).find(|&i| !interval(i).is_finite()) {
        return Err(Error::NonFinite {
            name: "intervals",
            index,
        });
    }
    analyse_by(n, interval)
}

/// [`analyse`] of the finite intervals `interval(0..n)`.
#[allow(clippy::cast_precision_loss)]
fn analyse_by(n: usize, interval: impl Fn(usize) -> f64 + Sync) -> Result<Sampling> {
    if let Some(i) = (0..n).find(|&i| interval(i) < 0.0) {
        return Err(Error::invalid(
            "intervals",
            format!(
                "must be >= 0 (timestamps in order), got {} at row {}",
                interval(i),
                i + 1
            ),
        ));
    }
    let Some(median) = median_positive(n, &interval) else {
        return Err(Error::invalid(
            "time",
            format!(
                "the time column does not advance ({} samples, all with the same timestamp)",
                n + 1
            ),
        ));
    };
    let limit = GAP_FACTOR * median;
    let mut gap_rows = Vec::new();
    let mut gap_durations = Vec::new();
    let mut duplicate_rows = Vec::new();
    let (mut sum, mut comp, mut n_regular) = (0.0, 0.0, 0_usize);
    for i in 0..n {
        let v = interval(i);
        if v > limit {
            gap_rows.push(i + 1);
            gap_durations.push(v);
        } else if v > 0.0 {
            validate::neumaier_add(&mut sum, &mut comp, v);
            n_regular += 1;
        } else {
            duplicate_rows.push(i + 1);
        }
    }
    // The median is a regular interval (or the midpoint of two positive ones, the lower of
    // which is ≤ it ≤ 1.5·it), so there is at least one.
    debug_assert!(n_regular > 0);
    let regular = |v: f64| v > 0.0 && v <= limit;
    let mean = (sum + comp) / n_regular as f64;
    let jitter = if n_regular > 1 {
        let ss = validate::neumaier_sum(
            (0..n)
                .map(&interval)
                .filter(|v| regular(*v))
                .map(|v| (v - mean) * (v - mean)),
        );
        (ss / n_regular as f64).sqrt() / median
    } else {
        0.0
    };
    let fs_estimated = nine_digits(1.0 / mean);
    let missing_samples = gap_durations
        .iter()
        .map(|g| missing_in_gap(*g, median))
        .sum();
    Ok(Sampling {
        median_interval: median,
        fs_estimated,
        jitter,
        gap_rows,
        gap_durations,
        missing_samples,
        duplicate_rows,
    })
}

/// Overwrites integer stamps with their times in seconds since `first`:
/// `((t − first) as f64) / per_second`, the difference wrapping like NumPy's `int64`
/// subtraction, stored as the bits of the `f64` (the caller views the buffer as `float64`).
/// The loader's own copy of the stamps becomes the time vector, with no second column.
///
/// # Errors
/// `per_second` not finite and positive.
#[allow(clippy::cast_precision_loss)]
pub fn seconds_in_place_int(stamps: &mut [i64], first: i64, per_second: f64) -> Result<()> {
    validate::positive("per_second", per_second)?;
    stamps.par_chunks_mut(RADIX_TASK).for_each(|chunk| {
        for t in chunk {
            let seconds = (t.wrapping_sub(first) as f64) / per_second;
            *t = i64::from_ne_bytes(seconds.to_ne_bytes());
        }
    });
    Ok(())
}

/// Overwrites float stamps with their times in seconds since `first`: `(t − first)/per_second`.
///
/// # Errors
/// `per_second` not finite and positive.
pub fn seconds_in_place_float(stamps: &mut [f64], first: f64, per_second: f64) -> Result<()> {
    validate::positive("per_second", per_second)?;
    stamps.par_chunks_mut(RADIX_TASK).for_each(|chunk| {
        for t in chunk {
            *t = (*t - first) / per_second;
        }
    });
    Ok(())
}

/// Writes the time vector with the gaps filled: the `n` times of `time` moved to their new
/// rows and `counts[g]` evenly spaced times inserted before row `gap_rows[g]` (module docs).
/// `out` must hold `n + Σ counts` values.
///
/// # Errors
/// `gap_rows` and `counts` of different lengths, a gap row outside `1..n` or not increasing,
/// or `out` of the wrong length ([`Error::ShapeMismatch`] / [`Error::InvalidParameter`]).
pub fn fill_time_into(
    time: &[f64],
    gap_rows: &[usize],
    counts: &[u64],
    out: &mut [f64],
) -> Result<()> {
    if gap_rows.len() != counts.len() {
        return Err(Error::ShapeMismatch {
            name: "counts",
            reason: format!("{} counts for {} gaps", counts.len(), gap_rows.len()),
        });
    }
    let n = time.len();
    let mut previous = 0;
    for &r in gap_rows {
        if r == 0 || r >= n || r <= previous {
            return Err(Error::invalid(
                "gap_rows",
                format!("must be increasing rows in 1..{n}, got {r}"),
            ));
        }
        previous = r;
    }
    let total = counts
        .iter()
        .try_fold(n as u64, |acc, c| acc.checked_add(*c));
    if total != Some(out.len() as u64) {
        return Err(Error::ShapeMismatch {
            name: "out",
            reason: format!(
                "{} values for {n} times and {} filled",
                out.len(),
                counts.iter().map(|c| u128::from(*c)).sum::<u128>()
            ),
        });
    }
    let mut dest = 0;
    let mut start = 0;
    for (&row, &count) in gap_rows.iter().zip(counts) {
        let len = row - start;
        out[dest..dest + len].copy_from_slice(&time[start..row]);
        dest += len;
        let (t0, t1) = (time[row - 1], time[row]);
        #[allow(clippy::cast_possible_truncation)]
        let c = count as usize; // fits: the total was checked against out.len()
        let denom = (c + 1) as f64;
        for (j, o) in out[dest..dest + c].iter_mut().enumerate() {
            *o = t0 + (t1 - t0) * (j + 1) as f64 / denom;
        }
        dest += c;
        start = row;
    }
    out[dest..].copy_from_slice(&time[start..]);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unit_guess_and_step_rows() {
        let ns: [i64; 5] = [0, 10_000_000, 20_000_000, 20_000_000, 30_000_000];
        assert_eq!(median_positive_step(&ns), 1e7);
        assert_eq!(guess_unit(median_positive_step(&ns)), "ns");
        assert_eq!(guess_unit(median_positive_step(&[0.0, 0.01, 0.02])), "s");
        // Microsecond stamps of a 110 Hz YEI log (scikit-kinematics data_yei.txt) and of a
        // 50 Hz x-IMU3 log; nanoseconds at 10 kHz; the boundaries themselves.
        assert_eq!(
            guess_unit(median_positive_step(&[90198.0, 99285.0, 108380.0])),
            "us"
        );
        assert_eq!(guess_unit(20_034.0), "us");
        assert_eq!(guess_unit(1e5), "ns");
        assert_eq!(guess_unit(99_999.0), "us");
        assert_eq!(guess_unit(1e3), "us");
        assert_eq!(guess_unit(999.0), "s");
        assert_eq!(median_positive_step(&[1.0, 1.0]), 0.0);
        assert_eq!(repeated_rows(&ns), vec![3]);
        assert_eq!(backward_rows(&[0.0, 2.0, 1.0, 3.0, 2.5]), vec![2, 4]);
        // Extreme integer stamps: the difference is formed without overflow.
        assert_eq!(i64::MAX.step_from(i64::MIN), 2f64.powi(64));
    }

    #[test]
    fn analyse_by_hand() {
        // 100 Hz with one 3-interval gap (2 missing samples) and one repeated stamp.
        let mut t = vec![0.0, 0.01, 0.02, 0.05, 0.06, 0.06, 0.07];
        let iv: Vec<f64> = t.windows(2).map(|w| w[1] - w[0]).collect();
        let s = analyse(&iv).unwrap();
        assert!((s.median_interval - 0.01).abs() < 1e-15);
        assert_eq!(s.gap_rows, vec![3]);
        assert_eq!(s.duplicate_rows, vec![5]);
        assert_eq!(s.missing_samples, 2);
        assert_eq!(s.fs_estimated, 100.0);
        assert!(s.jitter < 1e-12);
        // Filling the gap gives evenly spaced times.
        t.remove(5);
        let mut out = vec![0.0; t.len() + 2];
        fill_time_into(&t, &[3], &[2], &mut out).unwrap();
        let want = [0.0, 0.01, 0.02, 0.03, 0.04, 0.05, 0.06, 0.07];
        for (a, b) in out.iter().zip(want) {
            assert!((a - b).abs() < 1e-15, "{out:?}");
        }
        assert!(fill_time_into(&t, &[3], &[2], &mut [0.0; 3]).is_err());
        assert!(fill_time_into(&t, &[0], &[2], &mut out).is_err());
        assert!(
            analyse(&[0.0, 0.0])
                .unwrap_err()
                .to_string()
                .contains("does not advance")
        );
        assert!(analyse(&[0.1, -0.1]).is_err());
    }

    #[test]
    fn jitter_and_rate() {
        // Alternating 9 and 11 ms: median 10 ms (even count: mean of the middles), jitter 10 %.
        let iv: Vec<f64> = (0..100)
            .map(|i| if i % 2 == 0 { 0.009 } else { 0.011 })
            .collect();
        let s = analyse(&iv).unwrap();
        assert!((s.median_interval - 0.01).abs() < 1e-15);
        assert!((s.jitter - 0.1).abs() < 1e-12);
        assert_eq!(s.fs_estimated, 100.0);
        assert!(s.gap_rows.is_empty());
        assert_eq!(nine_digits(100.000_000_000_002_13), 100.0);
        assert_eq!(missing_in_gap(0.025, 0.01), 1); // 2.5 rounds to 2 (ties to even)
    }

    /// The sort-based median the radix selection replaces (NumPy's `median` of the positives).
    fn median_by_sorting(values: &[f64]) -> Option<f64> {
        let mut p: Vec<f64> = values.iter().copied().filter(|v| *v > 0.0).collect();
        if p.is_empty() {
            return None;
        }
        p.sort_by(f64::total_cmp);
        let m = p.len() / 2;
        Some(if p.len() % 2 == 1 {
            p[m]
        } else {
            f64::midpoint(p[m - 1], p[m])
        })
    }

    #[test]
    fn radix_median_is_the_sorted_median() {
        // xorshift: deterministic values with ties, zeros, negatives, subnormals and a wide range.
        let mut state = 0x9E37_79B9_7F4A_7C15_u64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        for len in [0_usize, 1, 2, 3, 4, 5, 10, 101, 1000, 300_001] {
            for kind in 0..5 {
                let v: Vec<f64> = (0..len)
                    .map(|_| {
                        let r = next();
                        match kind {
                            0 => (r % 7) as f64 * 0.01,                     // ties and zeros
                            1 => f64::from_bits(r >> 2) - 1e-300,           // any positive double
                            2 => 0.01 + (r % 1000) as f64 * 1e-9,           // jittered 100 Hz
                            3 => (r as i64 as f64) * 1e-12,                 // half negative
                            _ => f64::from_bits(r % 1000) * (r % 3) as f64, // subnormals
                        }
                    })
                    .collect();
                let want = median_by_sorting(&v);
                let got = median_positive(v.len(), |i| v[i]);
                assert_eq!(
                    got.map(f64::to_bits),
                    want.map(f64::to_bits),
                    "len {len} kind {kind}"
                );
            }
        }
    }

    #[test]
    fn stamps_analysed_like_their_intervals() {
        // Integer nanoseconds at 200 Hz with jitter, a gap and a repeated stamp.
        let mut t: Vec<i64> = Vec::new();
        let mut now = 1_700_000_000_000_000_000_i64;
        for i in 0..20_000_i64 {
            now += 5_000_000 + (i * 7919 % 2001) - 1000;
            if i == 9000 {
                now += 40_000_000;
            }
            t.push(now);
            if i == 12_000 {
                t.push(now);
            }
        }
        let iv: Vec<f64> = t.windows(2).map(|w| w[1].step_from(w[0]) / 1e9).collect();
        assert_eq!(analyse_stamps(&t, 1e9).unwrap(), analyse(&iv).unwrap());
        let f: Vec<f64> = t.iter().map(|v| (v - t[0]) as f64 * 1e-6).collect();
        let ivf: Vec<f64> = f.windows(2).map(|w| (w[1] - w[0]) / 1e3).collect();
        assert_eq!(analyse_stamps(&f, 1e3).unwrap(), analyse(&ivf).unwrap());
        assert_eq!(
            median_positive_step(&t),
            median_by_sorting(
                &t.windows(2)
                    .map(|w| w[1].step_from(w[0]))
                    .collect::<Vec<_>>()
            )
            .unwrap()
        );
        assert!(analyse_stamps(&[1.0, -f64::MAX, f64::MAX], 1.0).is_err());
        assert!(analyse_stamps(&t, 0.0).is_err());
        // Seconds in place, as NumPy computes them.
        let mut s = t.clone();
        seconds_in_place_int(&mut s, t[0], 1e9).unwrap();
        for (a, b) in s.iter().zip(&t) {
            assert_eq!(f64::from_bits(*a as u64), ((b - t[0]) as f64) / 1e9);
        }
        let mut g = f.clone();
        seconds_in_place_float(&mut g, 2.5, 1e3).unwrap();
        for (a, b) in g.iter().zip(&f) {
            assert_eq!(*a, (b - 2.5) / 1e3);
        }
    }
}
