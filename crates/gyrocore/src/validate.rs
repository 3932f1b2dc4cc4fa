//! Precondition checks shared by all modules.

use crate::{Error, Result};

/// Fails with [`Error::NonFinite`] at the first NaN or infinity in `data`.
pub fn finite(name: &'static str, data: &[f64]) -> Result<()> {
    // Fast path: a sum of finite numbers scaled down cannot overflow, NaN/inf propagate.
    // Fall back to a scan to locate the index only when something is wrong.
    let mut acc = 0.0_f64;
    for chunk in data.chunks(4096) {
        acc += chunk.iter().map(|v| v * 0.0).sum::<f64>();
        if !acc.is_finite() {
            break;
        }
    }
    if acc.is_finite() {
        return Ok(());
    }
    let index = data.iter().position(|v| !v.is_finite()).unwrap_or(0);
    Err(Error::NonFinite { name, index })
}

/// Fails unless `value` is finite and strictly positive.
pub fn positive(name: &'static str, value: f64) -> Result<()> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(Error::invalid(
            name,
            format!("must be finite and > 0, got {value}"),
        ))
    }
}

/// The sample period `t0 = 1/fs` of the sample rate `fs` (Hz): the one check of `fs` for every
/// caller that works with the period (the Allan family, wavelet variances, AR(1) fits, …).
///
/// `fs` must be finite and > 0 ([`positive`]'s message, naming `fs`) and have a finite period:
/// a subnormal `fs` (below `2^-1022` Hz) overflows `1/fs` and is refused too, so a caller never
/// divides by a rate this function has not accepted.
pub fn sample_period(fs: f64) -> Result<f64> {
    positive("fs", fs)?;
    let t0 = 1.0 / fs;
    if t0.is_finite() {
        Ok(t0)
    } else {
        Err(Error::invalid(
            "fs",
            format!("must be finite and > 0 with a finite period 1/fs, got {fs:e}"),
        ))
    }
}

/// Fails unless `value` is finite and non-negative.
pub fn non_negative(name: &'static str, value: f64) -> Result<()> {
    if value.is_finite() && value >= 0.0 {
        Ok(())
    } else {
        Err(Error::invalid(
            name,
            format!("must be finite and >= 0, got {value}"),
        ))
    }
}

/// Fails unless `value` is a level strictly between 0 and 1 (a confidence or probability).
pub fn probability(name: &'static str, value: f64) -> Result<()> {
    if value > 0.0 && value < 1.0 {
        Ok(())
    } else {
        Err(Error::invalid(
            name,
            format!("must lie strictly between 0 and 1, got {value}"),
        ))
    }
}

/// Fails with [`Error::Allocation`] (naming the argument `name` the size comes from) unless
/// `count` values of type `T` can be allocated now.
///
/// The check reserves the memory and releases it at once: large requests are `mmap`ed without
/// touching a page, so this costs two system calls, and callers keep allocating with
/// `vec![0.0; n]` (calloc's lazily zeroed pages). Call it before every allocation whose size
/// comes from a parameter rather than from data that already exists.
pub fn allocatable<T>(name: &'static str, count: usize) -> Result<()> {
    let bytes = count as u128 * std::mem::size_of::<T>() as u128;
    let too_large = Error::Allocation { name, bytes };
    if bytes > isize::MAX as u128 {
        return Err(too_large);
    }
    let mut probe: Vec<T> = Vec::new();
    let reserved = probe.try_reserve_exact(count);
    // Without the black box an optimised build may elide the unused allocation and its free
    // as a pair and report success (observed with `cargo test --release`): the probe must
    // really reach the allocator.
    std::hint::black_box(&mut probe);
    reserved.map_err(|_| too_large)
}

/// `value²` if it is finite, else an error naming `name`: a standard deviation or amplitude
/// above `sqrt(f64::MAX)` ≈ 1.34e154 has a variance float64 cannot hold (the Allan variance
/// of such a term would be `inf` at every τ), which no rescaling of the result can represent.
pub fn finite_square(name: &'static str, value: f64) -> Result<f64> {
    let square = value * value;
    if square.is_finite() {
        Ok(square)
    } else {
        Err(Error::invalid(
            name,
            format!(
                "must be at most {:.4e} (its square, a variance, must be finite in float64), \
                 got {value}",
                f64::MAX.sqrt()
            ),
        ))
    }
}

/// The exponent `e` with `max |x| · 2^−e` in `[1, 2)` (0 for all-zero data): dividing the data
/// by `2^e` is exact and brings it to the scale where squares and sums of squares neither
/// overflow (data near 1e155) nor underflow (subnormal data); a variance computed from the
/// scaled data is multiplied back by `2^2e` ([`times_pow2`]).
pub fn pow2_exponent(x: &[f64]) -> i32 {
    let peak = x.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    if peak == 0.0 || !peak.is_finite() {
        return 0;
    }
    // log2 of a finite non-zero f64 lies in [-1074, 1024): the floor fits an i32.
    #[allow(clippy::cast_possible_truncation)]
    let e = peak.log2().floor() as i32;
    // log2 may round up across a power of two: settle the exponent exactly.
    if times_pow2(peak, -e) < 1.0 { e - 1 } else { e }
}

/// `v · 2^e`, exact unless the result over- or underflows (in two steps, so that `2^e` itself
/// need not be representable: `e` may reach ±2148 for a variance of scaled data).
pub fn times_pow2(v: f64, e: i32) -> f64 {
    let mut out = v;
    let mut rest = e;
    while rest != 0 {
        let step = rest.clamp(-1000, 1000);
        out *= 2.0_f64.powi(step);
        rest -= step;
    }
    out
}

/// Most worker threads a caller may ask for (`n_threads`): far beyond any machine's cores,
/// far below what would exhaust the operating system's thread limit.
pub const MAX_THREADS: usize = 1024;

/// Fails unless `n_threads` (0 = every core) is at most [`MAX_THREADS`]: a thread pool of
/// 2^40 threads is a request for resources that cannot exist, refused before any is spawned.
pub fn threads(n_threads: usize) -> Result<()> {
    if n_threads <= MAX_THREADS {
        Ok(())
    } else {
        Err(Error::invalid(
            "n_threads",
            format!("must be from 0 (every core) to {MAX_THREADS}, got {n_threads}"),
        ))
    }
}

/// `a·b` element count for the argument `name`, or [`Error::Allocation`] when the product
/// overflows `usize` (then it cannot be allocated either).
pub fn product(name: &'static str, a: usize, b: usize) -> Result<usize> {
    a.checked_mul(b).ok_or(Error::Allocation {
        name,
        bytes: (a as u128).saturating_mul(b as u128).saturating_mul(8),
    })
}

/// Fails unless `data.len() >= needed`.
pub fn min_len(name: &'static str, data_len: usize, needed: usize) -> Result<()> {
    if data_len >= needed {
        Ok(())
    } else {
        Err(Error::TooShort {
            name,
            needed,
            got: data_len,
        })
    }
}

/// Compensated (Neumaier) sum: error independent of the length for well-scaled data.
pub fn neumaier_sum(values: impl IntoIterator<Item = f64>) -> f64 {
    let mut sum = 0.0_f64;
    let mut comp = 0.0_f64;
    for v in values {
        neumaier_add(&mut sum, &mut comp, v);
    }
    sum + comp
}

/// One step of [`neumaier_sum`]: adds `v` to the running `sum` and its compensation `comp`
/// (the total is `sum + comp`), for callers that keep several running sums.
#[inline]
pub fn neumaier_add(sum: &mut f64, comp: &mut f64, v: f64) {
    let t = *sum + v;
    if sum.abs() >= v.abs() {
        *comp += (*sum - t) + v;
    } else {
        *comp += (v - t) + *sum;
    }
    *sum = t;
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn impossible_sizes_are_errors_not_aborts() {
        assert!(allocatable::<f64>("n", 1000).is_ok());
        for count in [usize::MAX, 1 << 61, 1 << 50] {
            match allocatable::<f64>("n", count) {
                Err(Error::Allocation { name: "n", bytes }) => {
                    assert_eq!(bytes, count as u128 * 8);
                }
                other => panic!("expected an allocation error, got {other:?}"),
            }
        }
        assert!(matches!(
            product("size", usize::MAX, 2),
            Err(Error::Allocation { name: "size", .. })
        ));
    }

    #[test]
    fn sample_period_accepts_exactly_the_rates_with_a_period() {
        assert_eq!(sample_period(100.0), Ok(0.01));
        assert_eq!(sample_period(f64::MAX), Ok(1.0 / f64::MAX));
        for fs in [
            0.0,
            -0.0,
            -5.0,
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            1e-310,
        ] {
            match sample_period(fs) {
                Err(Error::InvalidParameter { name: "fs", reason }) => {
                    assert!(reason.starts_with("must be finite and > 0"), "{reason}");
                }
                other => panic!("fs = {fs}: expected an fs error, got {other:?}"),
            }
        }
    }

    #[test]
    fn probability_is_open_unit_interval() {
        assert!(probability("p", 0.5).is_ok());
        for p in [0.0, 1.0, -0.1, 1.5, f64::NAN, f64::INFINITY] {
            assert!(matches!(
                probability("p", p),
                Err(Error::InvalidParameter { name: "p", .. })
            ));
        }
    }

    #[test]
    fn finite_reports_first_bad_index() {
        let mut x = vec![1.0; 10_000];
        x[7000] = f64::NAN;
        x[9000] = f64::INFINITY;
        assert_eq!(
            finite("data", &x),
            Err(Error::NonFinite {
                name: "data",
                index: 7000
            })
        );
        assert!(finite("data", &[1e308, 1e308]).is_ok());
    }

    #[test]
    fn neumaier_is_exact_on_cancellation() {
        assert_eq!(neumaier_sum([1e16, 1.0, -1e16]), 1.0);
    }
}
