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
