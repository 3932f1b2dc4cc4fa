//! Dynamic (time-resolved) overlapping Allan variance.
//!
//! The record is cut into windows of `window` samples starting every `step` samples
//! (`start_w = w·step`, `w = 0 … ⌊(N − window)/step⌋`); each window is analysed on its own exactly
//! as [`super::analyse`] would analyse it (rate windows integrated after removing the window's
//! own mean), at one common set of averaging factors resolved for the window length. This is
//! the dynamic Allan variance of L. Galleani and P. Tavella ("The dynamic Allan variance", IEEE
//! UFFC 56 (2009) 450), with the overlapping estimator (SP 1065 eq. 11) inside each window.
//!
//! Windows are independent, so any row depends only on its own samples: the result does not
//! depend on the thread count, and analysing a log in pieces that overlap by `window − step`
//! samples reproduces the rows of the whole log exactly.

use rayon::prelude::*;

use super::{
    Column, DataType, Estimator, Taus, ldexp, period_correction, resolve_factors,
    scaled_angle_series, split_period, variances_into,
};
use crate::{Error, Result};

/// A time × τ dynamic Allan variance.
#[derive(Debug, Clone, PartialEq)]
pub struct DynamicAllan {
    /// First sample of each window.
    pub starts: Vec<usize>,
    /// Averaging factors (τ = m·t0).
    pub m: Vec<usize>,
    /// Terms of each window's sum per factor (the same for every window).
    pub n_terms: Vec<usize>,
    /// Variances, row-major `starts.len() × m.len()`.
    pub variance: Vec<f64>,
}

/// Dynamic overlapping Allan variance of a contiguous series.
pub fn dynamic_avar(
    data: &[f64],
    t0: f64,
    data_type: DataType,
    window: usize,
    step: usize,
    taus: &Taus,
) -> Result<DynamicAllan> {
    crate::validate::positive("fs", 1.0 / t0)?;
    let n = data.len();
    if step == 0 {
        return Err(Error::invalid("step", "must be >= 1 sample"));
    }
    if window > n {
        return Err(Error::invalid(
            "window",
            format!("a window of {window} samples is longer than the log ({n} samples)"),
        ));
    }
    let min_window = match data_type {
        DataType::Rate => 2,
        DataType::Angle => 3,
    };
    if window < min_window {
        return Err(Error::invalid(
            "window",
            format!("must hold at least {min_window} samples for one Allan term, got {window}"),
        ));
    }
    let ms =
        resolve_factors(taus, window, t0, data_type, Estimator::Overlapping).map_err(
            |e| match e {
                Error::TooShort { .. } => Error::invalid("window", "too short for any τ"),
                other => other,
            },
        )?;
    // An extreme period is computed as t0'·2^e (see `split_period`); τ were resolved above with
    // the period itself.
    let (t0, period_exponent) = split_period(t0);
    let correction = period_correction(data_type, period_exponent, false);
    let starts: Vec<usize> = (0..=(n - window) / step).map(|w| w * step).collect();
    let k = ms.len();
    let rows: Vec<Result<(Vec<f64>, Vec<usize>)>> = starts
        .par_iter()
        .with_max_len(1)
        .map(|&s| {
            // A window of extreme magnitude is analysed scaled by 2^-scale (exact) and its
            // variances brought back (see `scale_exponent`).
            let (x, scale) =
                scaled_angle_series(Column::contiguous(&data[s..s + window]), t0, data_type)
                    .map_err(|e| match e {
                        Error::NonFinite { name, index } => Error::NonFinite {
                            name,
                            index: index + s,
                        },
                        other => other,
                    })?;
            let mut v = vec![0.0; k];
            let mut t = vec![0usize; k];
            variances_into(&x, t0, &ms, Estimator::Overlapping, &mut v, &mut t)?;
            for value in &mut v {
                *value = ldexp(*value, 2 * (scale + correction));
            }
            Ok((v, t))
        })
        .collect();
    let mut variance = Vec::with_capacity(starts.len() * k);
    let mut n_terms = Vec::new();
    for r in rows {
        let (v, t) = r?;
        variance.extend_from_slice(&v);
        n_terms = t;
    }
    Ok(DynamicAllan {
        starts,
        m: ms,
        n_terms,
        variance,
    })
}

#[cfg(test)]
mod tests {
    use super::super::{TauSpec, analyse};
    use super::*;

    fn rate(n: usize) -> Vec<f64> {
        (0..n)
            .map(|i| ((i * 7919 % 1013) as f64 * 0.37).sin() + if i > n / 2 { 2.0 } else { 0.0 })
            .collect()
    }

    #[test]
    fn rows_equal_separate_analyses() {
        let r = rate(1000);
        let taus = Taus::Spec(TauSpec::Octave);
        let d = dynamic_avar(&r, 0.1, DataType::Rate, 300, 70, &taus).unwrap();
        assert_eq!(d.starts, (0..=10).map(|w| w * 70).collect::<Vec<_>>());
        for (w, &s) in d.starts.iter().enumerate() {
            let a = analyse(
                Column::contiguous(&r[s..s + 300]),
                0.1,
                DataType::Rate,
                Estimator::Overlapping,
                &taus,
                None,
            )
            .unwrap();
            assert_eq!(a.m, d.m);
            assert_eq!(
                &d.variance[w * d.m.len()..(w + 1) * d.m.len()],
                &a.variance[..]
            );
        }
    }

    #[test]
    fn bad_arguments_name_themselves() {
        let r = rate(100);
        let taus = Taus::Spec(TauSpec::Octave);
        let name = |e: Error| match e {
            Error::InvalidParameter { name, .. } => name,
            other => panic!("{other:?}"),
        };
        assert_eq!(
            name(dynamic_avar(&r, 1.0, DataType::Rate, 101, 1, &taus).unwrap_err()),
            "window"
        );
        assert_eq!(
            name(dynamic_avar(&r, 1.0, DataType::Rate, 50, 0, &taus).unwrap_err()),
            "step"
        );
        assert_eq!(
            name(
                dynamic_avar(&r, 1.0, DataType::Rate, 50, 5, &Taus::Explicit(vec![40.0]))
                    .unwrap_err()
            ),
            "taus"
        );
    }

    #[test]
    fn extreme_periods_give_the_ordinary_result() {
        // t0 = 1.25·2^±950: computed with t0' = 1.25, so rate variances equal those at
        // t0 = 1.25 bit for bit and angle variances (at 2^±300, where
        // they are representable) differ by exactly 4^∓300.
        let r = rate(600);
        let taus = Taus::Spec(TauSpec::Octave);
        let base = dynamic_avar(&r, 1.25, DataType::Rate, 200, 100, &taus).unwrap();
        for e in [-950, 950] {
            let t0 = ldexp(1.25, e);
            let d = dynamic_avar(&r, t0, DataType::Rate, 200, 100, &taus).unwrap();
            assert_eq!(d.variance, base.variance);
        }
        for e in [-300, 300] {
            let t0 = ldexp(1.25, e);
            let a = dynamic_avar(&r, t0, DataType::Angle, 200, 100, &taus).unwrap();
            let b = dynamic_avar(&r, 1.25, DataType::Angle, 200, 100, &taus).unwrap();
            for (x, y) in a.variance.iter().zip(&b.variance) {
                assert!(x.is_finite());
                assert_eq!(*x, ldexp(*y, -2 * e));
            }
        }
    }
}
