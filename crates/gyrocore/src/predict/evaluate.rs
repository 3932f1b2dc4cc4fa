//! \[BP\]'s batch test (§V-C, Table I): a long static log cut into disjoint sections of
//! `k + h` samples, each predicted from its first `k` samples, scored over the last `h`.
//!
//! Per section and method (SPEC §5, "Metrics"):
//!
//! ```text
//! IE   = Σ_j (y_j − ŷ_j)            (data minus prediction)
//! RSSE = √(Σ_j (y_j − ŷ_j)²)        (the root: [BP]'s text omits it, its numbers need it)
//! ```
//!
//! summarised over the sections by their mean and sample standard deviation (`n − 1`), and
//! compared between two methods by a ratio of mean RSSEs or of IE standard deviations with a
//! paired bootstrap standard error (Efron & Tibshirani 1993, §6.2: `B` resamples of the section
//! indices with replacement, the same indices for both methods; the s.e. is the sample standard
//! deviation of the `B` ratios, resamples whose ratio is not finite left out). The resampling
//! indices come from the core's one generator ([`crate::random`]), seeded by the caller.
//!
//! Sums are compensated (Neumaier), so a score does not depend on the order of summation to
//! more than a few ulps; the RSSE is scaled by the largest error (squares beyond float64 give the
//! same root), and a difference or sum beyond float64 is an error, never ∞.

use crate::predict::batch::Compiled;
use crate::predict::{self, Model};
use crate::random::NormalStream;
use crate::validate;
use crate::{Error, Result};

/// Fewest sections for which [`bootstrap_ratio`] reports a standard error (below, NaN): with
/// fewer, the resampling distribution has too few distinct values to mean anything.
pub const MIN_BOOTSTRAP_SECTIONS: usize = 10;

/// A forecasting method of the batch test.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Method {
    /// The fractional (1/f) Kalman predictor, compiled once for the section shape.
    Kalman,
    /// The moving average (\[BP\] eq. 8 extended by eq. 9).
    MovingAverage,
    /// The calibration mean (\[BP\] eq. 9).
    CalibrationMean,
}

impl Method {
    /// Parses `"kf"`, `"ma"` or `"cm"`.
    pub fn parse(name: &str) -> Result<Self> {
        match name {
            "kf" => Ok(Self::Kalman),
            "ma" => Ok(Self::MovingAverage),
            "cm" => Ok(Self::CalibrationMean),
            other => Err(Error::invalid(
                "methods",
                format!("must be one of 'kf', 'ma', 'cm'; got {other:?}"),
            )),
        }
    }
}

/// The statistic compared by [`ratio`] and [`bootstrap_ratio`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Statistic {
    /// Mean of the per-section values (the mean RSSE).
    Mean,
    /// Sample standard deviation (`n − 1`) of the per-section values (the IE standard deviation).
    Std,
}

impl Statistic {
    /// Parses `"rsse"` (the ratio of mean RSSEs: [`Statistic::Mean`]) or `"ie_std"` (the ratio of
    /// IE standard deviations: [`Statistic::Std`]).
    pub fn parse(name: &str) -> Result<Self> {
        match name {
            "rsse" => Ok(Self::Mean),
            "ie_std" => Ok(Self::Std),
            other => Err(Error::invalid(
                "statistic",
                format!("must be one of 'rsse', 'ie_std'; got {other:?}"),
            )),
        }
    }

    fn of(self, values: impl Iterator<Item = f64> + Clone) -> f64 {
        let (mean, std) = mean_std_iter(values);
        match self {
            Self::Mean => mean,
            Self::Std => std,
        }
    }
}

/// Per-section scores of one method.
#[derive(Debug, Clone, PartialEq)]
pub struct Scores {
    /// Integrated error `Σ_j (y_j − ŷ_j)` of every section.
    pub integrated_error: Vec<f64>,
    /// `√Σ_j (y_j − ŷ_j)²` of every section.
    pub rsse: Vec<f64>,
}

/// Number of sections of a log of `len` samples for calibration `k` and horizon `h`.
///
/// `row_width = None`: a long 1-D log, cut into `⌊len/(k + h)⌋` sections (the remainder is
/// dropped); `Some(w)`: the sections themselves as rows of `w = k + h` samples.
///
/// # Errors
/// `k < 2` or `h = 0` ([`Error::InvalidParameter`] naming `calibration` / `horizon`); a log
/// shorter than one section ([`Error::TooShort`]); rows of another width
/// ([`Error::ShapeMismatch`]).
pub fn sections(len: usize, row_width: Option<usize>, k: usize, h: usize) -> Result<usize> {
    if k < 2 {
        return Err(Error::invalid(
            "calibration",
            format!("must be at least 2 samples, got {k}"),
        ));
    }
    if h == 0 {
        return Err(Error::invalid(
            "horizon",
            "must be at least 1 sample, got 0",
        ));
    }
    let width = k
        .checked_add(h)
        .ok_or_else(|| Error::invalid("horizon", "calibration + horizon overflows"))?;
    match row_width {
        None => {
            // A calibration or horizon longer than the log by itself names that argument.
            for (name, size) in [("calibration", k), ("horizon", h)] {
                if size >= len {
                    return Err(Error::invalid(
                        name,
                        format!("must be shorter than the log ({len} samples), got {size} samples"),
                    ));
                }
            }
            let count = len / width;
            if count == 0 {
                return Err(Error::TooShort {
                    name: "log",
                    needed: width,
                    got: len,
                });
            }
            Ok(count)
        }
        Some(w) if w != width => Err(Error::ShapeMismatch {
            name: "log",
            reason: format!("sections have {w} samples, calibration + horizon = {width}"),
        }),
        Some(w) => {
            if len % w != 0 {
                return Err(Error::ShapeMismatch {
                    name: "log",
                    reason: format!("{len} samples are not whole rows of {w}"),
                });
            }
            if len == 0 {
                return Err(Error::TooShort {
                    name: "log",
                    needed: width,
                    got: 0,
                });
            }
            Ok(len / w)
        }
    }
}

fn check_pair(y: &[f64], yhat: &[f64], width: usize, yhat_width: usize) -> Result<()> {
    if y.len() != yhat.len() || width != yhat_width {
        return Err(Error::ShapeMismatch {
            name: "yhat",
            reason: format!(
                "y has {} values in rows of {width} and yhat {} in rows of {yhat_width}: they \
                 must have the same shape",
                y.len(),
                yhat.len()
            ),
        });
    }
    if width == 0 || y.len() % width != 0 {
        return Err(Error::ShapeMismatch {
            name: "y",
            reason: format!("{} values are not whole rows of {width}", y.len()),
        });
    }
    validate::finite("y", y)?;
    validate::finite("yhat", yhat)
}

fn overflow(what: &str) -> Error {
    Error::invalid(
        "y",
        format!("y - yhat must have a finite {what} in float64, got an overflow"),
    )
}

/// Integrated error `Σ_j (y_j − ŷ_j)` of every row of two row-major arrays with rows of
/// `width` and `yhat_width` samples (compensated sum).
///
/// # Errors
/// Arrays of different lengths or not whole rows ([`Error::ShapeMismatch`]).
pub fn integrated_error(
    y: &[f64],
    yhat: &[f64],
    width: usize,
    yhat_width: usize,
) -> Result<Vec<f64>> {
    check_pair(y, yhat, width, yhat_width)?;
    y.chunks(width)
        .zip(yhat.chunks(width))
        .map(|(a, b)| {
            let s = validate::neumaier_sum(a.iter().zip(b).map(|(u, v)| u - v));
            if s.is_finite() {
                Ok(s)
            } else {
                Err(overflow("sum"))
            }
        })
        .collect()
}

/// Root of the sum of squared errors `√Σ_j (y_j − ŷ_j)²` of every row (compensated sum).
///
/// # Errors
/// As [`integrated_error`].
pub fn rsse(y: &[f64], yhat: &[f64], width: usize, yhat_width: usize) -> Result<Vec<f64>> {
    check_pair(y, yhat, width, yhat_width)?;
    y.chunks(width)
        .zip(yhat.chunks(width))
        .map(|(a, b)| {
            // Scaled by the largest error, so squares beyond float64 give the same root.
            let scale = a
                .iter()
                .zip(b)
                .map(|(u, v)| (u - v).abs())
                .fold(0.0, f64::max);
            if !scale.is_finite() {
                return Err(overflow("difference"));
            }
            if scale == 0.0 {
                return Ok(0.0);
            }
            let ss = validate::neumaier_sum(a.iter().zip(b).map(|(u, v)| {
                let e = (u - v) / scale;
                e * e
            }));
            Ok(scale * ss.sqrt())
        })
        .collect()
}

/// \[BP\]'s batch test: cuts `log` into sections ([`sections`]), forecasts the last `h` samples
/// of each from its first `k` with every method of `methods` and scores them.
///
/// `model` is the Kalman predictor's model (used only for [`Method::Kalman`], compiled once for
/// the section shape); `n_threads = 0` uses every thread.
///
/// # Errors
/// Those of [`sections`]; a non-finite sample ([`Error::NonFinite`] naming `log`); the Kalman
/// predictor's errors.
pub fn evaluate(
    log: &[f64],
    row_width: Option<usize>,
    k: usize,
    h: usize,
    methods: &[Method],
    model: &Model,
    n_threads: usize,
) -> Result<Vec<Scores>> {
    validate::threads(n_threads)?;
    let count = sections(log.len(), row_width, k, h)?;
    let width = k + h;
    let used = &log[..count * width];
    validate::finite("log", used)?;
    let mut calibration = Vec::with_capacity(count * k);
    let mut future = Vec::with_capacity(count * h);
    for row in used.chunks(width) {
        calibration.extend_from_slice(&row[..k]);
        future.extend_from_slice(&row[k..]);
    }
    let mut out = Vec::with_capacity(methods.len());
    for method in methods {
        let forecast = match method {
            Method::Kalman => {
                Compiled::new(model, k, h, n_threads)?
                    .apply(&calibration, n_threads)?
                    .bias
            }
            Method::MovingAverage => predict::moving_average(&calibration, k, h)?,
            Method::CalibrationMean => predict::calibration_mean(&calibration, k, h)?,
        };
        out.push(Scores {
            integrated_error: integrated_error(&future, &forecast, h, h)?,
            rsse: rsse(&future, &forecast, h, h)?,
        });
    }
    Ok(out)
}

fn mean_std_iter(values: impl Iterator<Item = f64> + Clone) -> (f64, f64) {
    let mut n = 0_usize;
    let (mut sum, mut comp) = (0.0, 0.0);
    for v in values.clone() {
        validate::neumaier_add(&mut sum, &mut comp, v);
        n += 1;
    }
    if n == 0 {
        return (f64::NAN, f64::NAN);
    }
    let mean = (sum + comp) / n as f64;
    if n < 2 {
        return (mean, f64::NAN);
    }
    let ss = validate::neumaier_sum(values.map(|v| (v - mean) * (v - mean)));
    (mean, (ss / (n - 1) as f64).sqrt())
}

/// Mean and sample standard deviation (`n − 1`) of `values` (two passes, compensated sums);
/// NaN where undefined (no value; one value for the standard deviation).
pub fn mean_std(values: &[f64]) -> (f64, f64) {
    mean_std_iter(values.iter().copied())
}

fn check_paired(a: &[f64], b: &[f64]) -> Result<()> {
    if a.len() != b.len() {
        return Err(Error::ShapeMismatch {
            name: "reference",
            reason: format!(
                "{} sections against {}: a paired comparison needs the same sections",
                b.len(),
                a.len()
            ),
        });
    }
    if a.is_empty() {
        return Err(Error::TooShort {
            name: "sections",
            needed: 1,
            got: 0,
        });
    }
    Ok(())
}

/// `statistic(a) / statistic(b)` over paired per-section values.
///
/// # Errors
/// Different lengths ([`Error::ShapeMismatch`]) or no section ([`Error::TooShort`]).
pub fn ratio(a: &[f64], b: &[f64], statistic: Statistic) -> Result<f64> {
    check_paired(a, b)?;
    Ok(statistic.of(a.iter().copied()) / statistic.of(b.iter().copied()))
}

/// [`ratio`] with its paired bootstrap standard error: `resamples` draws of the section
/// indices with replacement (the same for `a` and `b`) from the core generator seeded with
/// `seed`; the standard error is the sample standard deviation of the finite resampled ratios
/// (NaN with fewer than [`MIN_BOOTSTRAP_SECTIONS`] sections or fewer than two finite ratios).
///
/// # Errors
/// As [`ratio`]; `resamples < 2` ([`Error::InvalidParameter`]).
pub fn bootstrap_ratio(
    a: &[f64],
    b: &[f64],
    statistic: Statistic,
    resamples: usize,
    seed: u64,
) -> Result<(f64, f64)> {
    let value = ratio(a, b, statistic)?;
    if resamples < 2 {
        return Err(Error::invalid(
            "resamples",
            format!("must be at least 2, got {resamples}"),
        ));
    }
    let n = a.len();
    if n < MIN_BOOTSTRAP_SECTIONS {
        return Ok((value, f64::NAN));
    }
    // One ratio kept per resample: the count is the caller's, so it is checked before use.
    validate::allocatable::<f64>("resamples", resamples)?;
    let mut rng = NormalStream::new(seed);
    let mut idx = vec![0_usize; n];
    let mut ratios = Vec::with_capacity(resamples);
    for _ in 0..resamples {
        for i in &mut idx {
            // n fits in u64 and every draw is below n, so both conversions are exact.
            *i = usize::try_from(rng.below(n as u64)).unwrap_or(0);
        }
        let r = statistic.of(idx.iter().map(|&i| a[i])) / statistic.of(idx.iter().map(|&i| b[i]));
        if r.is_finite() {
            ratios.push(r);
        }
    }
    let se = if ratios.len() > 1 {
        mean_std(&ratios).1
    } else {
        f64::NAN
    };
    Ok((value, se))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::predict::MeanPrior;

    #[test]
    fn sections_cut_and_checks() {
        assert_eq!(sections(2500, None, 600, 400).unwrap(), 2);
        assert_eq!(sections(2000, Some(1000), 600, 400).unwrap(), 2);
        assert!(matches!(
            sections(900, None, 600, 400),
            Err(Error::TooShort {
                needed: 1000,
                got: 900,
                ..
            })
        ));
        assert!(matches!(
            sections(2000, Some(500), 600, 400),
            Err(Error::ShapeMismatch { .. })
        ));
        assert!(
            sections(2000, None, 1, 400)
                .unwrap_err()
                .to_string()
                .contains("calibration")
        );
        assert!(
            sections(2000, None, 10, 0)
                .unwrap_err()
                .to_string()
                .contains("horizon")
        );
    }

    #[test]
    fn scores_by_hand() {
        let y = [1.0, 2.0, 3.0, 4.0, 0.0, 0.0];
        let yhat = [0.0, 0.0, 0.0, 1.0, 1.0, 1.0];
        assert_eq!(integrated_error(&y, &yhat, 3, 3).unwrap(), vec![6.0, 1.0]);
        let r = rsse(&y, &yhat, 3, 3).unwrap();
        assert!((r[0] - 14.0_f64.sqrt()).abs() < 1e-15);
        assert!((r[1] - 11.0_f64.sqrt()).abs() < 1e-15);
        assert!(rsse(&y, &yhat[..3], 3, 3).is_err());
        assert!(rsse(&y, &yhat, 3, 2).is_err());
        // Squares beyond float64: the same root; differences beyond it: refused.
        let big = rsse(&[1e200; 4], &[0.0; 4], 4, 4).unwrap();
        assert!((big[0] / 2e200 - 1.0).abs() < 1e-15);
        assert!(rsse(&[1e308, -1e308], &[-1e308, 1e308], 2, 2).is_err());
        assert!(integrated_error(&[f64::MAX; 2], &[0.0; 2], 2, 2).is_err());
        assert!(integrated_error(&[f64::NAN; 2], &[0.0; 2], 2, 2).is_err());
    }

    #[test]
    fn evaluate_matches_the_predictors_directly() {
        let log: Vec<f64> = (0..2600).map(|i| (f64::from(i) * 0.37).sin()).collect();
        let model = Model::new(0.5, 1.0, 0.0, MeanPrior::Sample).unwrap();
        let methods = [Method::CalibrationMean, Method::MovingAverage];
        let s = evaluate(&log, None, 600, 400, &methods, &model, 1).unwrap();
        let cal: Vec<f64> = log[..600].to_vec();
        let cm = predict::calibration_mean(&cal, 600, 400).unwrap();
        let ie: f64 = log[600..1000].iter().zip(&cm).map(|(a, b)| a - b).sum();
        assert_eq!(s[0].integrated_error.len(), 2);
        assert!((s[0].integrated_error[0] - ie).abs() < 1e-10);
        let mut bad = log.clone();
        bad[5] = f64::NAN;
        assert!(matches!(
            evaluate(&bad, None, 600, 400, &methods, &model, 1),
            Err(Error::NonFinite { name: "log", .. })
        ));
        // The remainder after the last whole section is not read (nor checked).
        bad = log.clone();
        bad[2500] = f64::NAN;
        assert!(evaluate(&bad, None, 600, 400, &methods, &model, 1).is_ok());
    }

    #[test]
    fn bootstrap_matches_the_delta_method() {
        // Ratio of means of paired, independent sections: a ~ N(2, 0.5²), b ~ N(4, 0.5²), n = 400.
        // Delta method: s.e.(ā/b̄) ≈ (ā/b̄)·√(σa²/(n ā²) + σb²/(n b̄²)) = 0.5·√(0.0625 + 0.015625)/20
        // = 0.006988. The bootstrap s.e. has a relative s.d. ≈ 1/√(2B) = 2.5 % at B = 800:
        // a 15 % band is six of those.
        let mut z = NormalStream::new(3);
        let n = 400;
        let a: Vec<f64> = (0..n).map(|_| 2.0 + 0.5 * z.next_normal()).collect();
        let b: Vec<f64> = (0..n).map(|_| 4.0 + 0.5 * z.next_normal()).collect();
        let (value, se) = bootstrap_ratio(&a, &b, Statistic::Mean, 800, 12345).unwrap();
        let (ma, _) = mean_std(&a);
        let (mb, _) = mean_std(&b);
        assert!((value - ma / mb).abs() < 1e-15);
        let sa = mean_std(&a).1;
        let sb = mean_std(&b).1;
        let delta =
            value * ((sa * sa) / (n as f64 * ma * ma) + (sb * sb) / (n as f64 * mb * mb)).sqrt();
        assert!(
            (se / delta - 1.0).abs() < 0.15,
            "bootstrap {se}, delta {delta}"
        );
        // Reproducible from the seed, different for another seed.
        assert_eq!(
            bootstrap_ratio(&a, &b, Statistic::Mean, 800, 12345).unwrap(),
            (value, se)
        );
        assert_ne!(
            bootstrap_ratio(&a, &b, Statistic::Mean, 800, 1).unwrap().1,
            se
        );
        // Too few sections: no standard error.
        assert!(
            bootstrap_ratio(&a[..9], &b[..9], Statistic::Std, 400, 1)
                .unwrap()
                .1
                .is_nan()
        );
        assert!(bootstrap_ratio(&a, &b[..9], Statistic::Std, 400, 1).is_err());
        assert!(bootstrap_ratio(&a, &b, Statistic::Std, 1, 1).is_err());
    }

    #[test]
    fn mean_std_by_hand() {
        let (m, s) = mean_std(&[1.0, 2.0, 3.0, 4.0]);
        assert!((m - 2.5).abs() < 1e-15);
        assert!((s - (5.0_f64 / 3.0).sqrt()).abs() < 1e-15);
        assert!(mean_std(&[1.0]).1.is_nan());
        assert!(mean_std(&[]).0.is_nan());
    }
}
