//! Bias prediction from a calibration window (\[BP\] §IV–V, SPEC §5).
//!
//! A vehicle stops; the gyro output `y_0..y_{k−1}` during the standstill is a calibration window
//! and the bias is predicted for the `h` samples that follow (time 0 is the first calibration
//! sample, the forecast covers `t = k..k+h−1`).
//!
//! * **Calibration mean** (\[BP\] eq. 9): `ŷ_j = mean(y_0..y_{k−1})`.
//! * **Moving average** (\[BP\] eq. 8 extended by eq. 9): for `1 ≤ j ≤ k` the mean of the last `j`
//!   calibration samples, for `j > k` the calibration mean.
//! * **Fractional Kalman predictor** (\[BP\] §IV-A). The bias is a constant `m` plus type-II
//!   fractionally integrated noise (ARFIMA(0, d, 0), \[BP\] eq. 6 read as in SPEC §4):
//!
//!   ```text
//!   x_t = Σ_{l=1}^{t} φ_l x_{t−l} + w_t,  φ_l = −π_l(d),  w_t ~ N(0, q),  x_0 = w_0
//!   y_t = m + x_t + v_t,                   v_t ~ N(0, r)         (calibration, t < k)
//!   ```
//!
//!   The forecast is `b̂_t = m̂ + x̂_t` with variance `P_mm + 2P_mx + P_xx` (an observation adds
//!   `r`). The mean state `m` has one of the priors of [`MeanPrior`]; the infinite (diffuse)
//!   prior is handled exactly (GLS / BLUP), never with a large number.
//!
//! Two exact implementations give the same numbers:
//!
//! * [`literal`]: the growing-state Kalman filter exactly as \[BP\] describes it, O(t²) per step,
//!   O(n³) time and O(n²) memory for `n = k + h` (the reference, for validation and small `n`);
//! * [`schur`]: the generalized Schur algorithm on the displacement structure of
//!   `Cov(x + v) = q·L·Lᵀ + r·I` (L lower-triangular Toeplitz in `ψ = π(−d)`, displacement rank
//!   2), O(n·k) time and O(n) memory (the default).
//!
//! For a fixed model the predictor is linear, `ŷ = W·y + w0`; [`batch`] precomputes `W` once and
//! predicts many windows with one matrix product.

pub mod batch;
pub mod evaluate;
pub mod literal;
pub mod schur;

use rayon::prelude::*;

use crate::validate;
use crate::{Error, Result};

/// Smallest supported memory parameter (exclusive): at `d ≤ −½` the model is over-differenced
/// (non-invertible).
pub const D_MIN: f64 = -0.5;
/// Largest supported memory parameter (exclusive): at `d ≥ 3/2` the weights `ψ_l ~ l^{d−1}` grow
/// without bound and the "bias" is an integrated random walk, not a bias model.
pub const D_MAX: f64 = 1.5;

/// Prior of the mean state `m` (SPEC §5).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum MeanPrior {
    /// `m` is the calibration sample mean, held with zero variance (\[BP\]'s reading; the forecast
    /// decays to it). Reproduces \[BP\] Table I.
    Sample,
    /// `m` is a random constant with an exactly infinite prior variance (GLS / BLUP estimate).
    Diffuse,
    /// `m = 0` (zero-mean data).
    Zero,
    /// `m ~ N(mu0, p0)`; `p0 = 0` means `m = mu0` is known.
    Proper {
        /// Prior mean.
        mu0: f64,
        /// Prior variance (finite, ≥ 0).
        p0: f64,
    },
}

impl MeanPrior {
    /// Parses the prior's name: `"sample"`, `"diffuse"`, `"none"` (m = 0) or `"proper"` with
    /// `mu0` and `p0` (ignored by the other names; checked by [`Model::new`]).
    pub fn parse(name: &str, mu0: f64, p0: f64) -> Result<Self> {
        match name {
            "sample" => Ok(Self::Sample),
            "diffuse" => Ok(Self::Diffuse),
            "none" => Ok(Self::Zero),
            "proper" => Ok(Self::Proper { mu0, p0 }),
            other => Err(Error::invalid(
                "mean",
                format!("expected 'sample', 'diffuse', 'none' or a pair (mu0, p0), got {other:?}"),
            )),
        }
    }
}

/// The fractional Kalman predictor's model.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Model {
    /// Memory parameter `d` of the ARFIMA(0, d, 0) bias, in (−½, 3/2).
    pub d: f64,
    /// Variance `q` of the driving noise `w_t` (> 0), per sample.
    pub q: f64,
    /// Variance `r` of the white measurement noise `v_t` (≥ 0), per sample.
    pub r: f64,
    /// Prior of the mean state.
    pub mean: MeanPrior,
}

impl Model {
    /// Validates and builds a model.
    pub fn new(d: f64, q: f64, r: f64, mean: MeanPrior) -> Result<Self> {
        if !(d.is_finite() && d > D_MIN && d < D_MAX) {
            return Err(Error::invalid(
                "d",
                format!(
                    "the fractional model supports {D_MIN} < d < {D_MAX} (d ≤ −½ is \
                     non-invertible, d ≥ 3/2 is not a bias model), got {d}"
                ),
            ));
        }
        validate::positive("q", q)?;
        validate::non_negative("r", r)?;
        if let MeanPrior::Proper { mu0, p0 } = mean {
            if !mu0.is_finite() {
                return Err(Error::invalid("mu0", format!("must be finite, got {mu0}")));
            }
            validate::non_negative("p0", p0)?;
        }
        Ok(Self { d, q, r, mean })
    }
}

/// The per-sample variances `(q, r)` of a [`Model`] from Allan noise coefficients: the bias
/// instability `B` and angle random walk `N` (base units: rate unit and rate unit·√s) at the
/// sample rate `fs` (Hz).
///
/// White rate noise of per-sample variance σ² at period `t0` has the two-sided PSD `N² = σ²·t0`
/// (IEEE 952), so `r = N²·fs`; the flicker PSD `B²/(2π f)` equals that of ARFIMA(0, ½, 0) driven
/// by variance `q` for `f ≪ fs`, so `q = B²` (\[BP\] §IV, IEEE 952 Annex C).
///
/// Errors name the argument: `arw` negative or not finite, `bias_instability` not finite and
/// > 0, `fs` as [`validate::sample_period`], and a `B²` or `N²·fs` beyond float64.
pub fn noise_parameters(arw: f64, bias_instability: f64, fs: f64) -> Result<(f64, f64)> {
    validate::non_negative("arw", arw)?;
    validate::positive("bias_instability", bias_instability)?;
    validate::sample_period(fs)?;
    let q = bias_instability * bias_instability;
    if !(q.is_finite() && q > 0.0) {
        return Err(Error::invalid(
            "bias_instability",
            format!(
                "its square q = B² must be a positive finite float64, got B = {bias_instability:e}"
            ),
        ));
    }
    let r = arw * arw * fs;
    if !r.is_finite() {
        return Err(Error::invalid(
            "arw",
            format!("r = N²·fs overflows float64 (N = {arw:e}, fs = {fs:e})"),
        ));
    }
    Ok((q, r))
}

/// Which exact algorithm computes the Kalman prediction.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Algorithm {
    /// Generalized Schur, O(n·k) time, O(n) memory (default).
    Schur,
    /// The literal growing-state filter of \[BP\] §IV-A, O(n³) time, O(n²) memory.
    Literal,
}

impl Algorithm {
    /// Parses `"schur"` or `"literal"`.
    pub fn parse(name: &str) -> Result<Self> {
        match name {
            "schur" => Ok(Self::Schur),
            "literal" => Ok(Self::Literal),
            other => Err(Error::invalid(
                "algorithm",
                format!("expected 'schur' or 'literal', got {other:?}"),
            )),
        }
    }
}

/// A bias forecast over the horizon.
#[derive(Debug, Clone, PartialEq)]
pub struct Prediction {
    /// Predicted bias `b̂_t`, `t = k..k+h−1`.
    pub bias: Vec<f64>,
    /// Standard deviation of the bias forecast error.
    pub std: Vec<f64>,
    /// Standard deviation of a future observation around the forecast (white noise included).
    pub std_observation: Vec<f64>,
    /// Estimated mean state `m̂`.
    pub mean: f64,
    /// Standard deviation of `m̂` (0 for the sample mean, zero and known-mean priors).
    pub mean_std: f64,
}

/// Checks shared by every predictor: calibration of ≥ 2 finite samples, horizon ≥ 1.
pub(crate) fn check_window(calibration: &[f64], horizon: usize) -> Result<()> {
    validate::min_len("calibration", calibration.len(), 2)?;
    validate::finite("calibration", calibration)?;
    if horizon < 1 {
        return Err(Error::invalid("horizon", "must be at least 1 sample"));
    }
    // Every predictor keeps a few state vectors of the joint (calibration + horizon) length.
    let joint = calibration.len().saturating_add(horizon);
    validate::allocatable::<f64>("horizon", validate::product("horizon", joint, 8)?)
}

/// Posterior of the mean state from `u·u = 1ᵀC⁻¹1`, `u·v = 1ᵀC⁻¹y` and the sample mean:
/// returns `(m̂, Var m̂)`.
pub(crate) fn mean_posterior(prior: MeanPrior, uu: f64, uv: f64, sample_mean: f64) -> (f64, f64) {
    match prior {
        MeanPrior::Sample => (sample_mean, 0.0),
        MeanPrior::Zero => (0.0, 0.0),
        MeanPrior::Diffuse => (uv / uu, 1.0 / uu),
        MeanPrior::Proper { mu0, p0 } => {
            if p0 == 0.0 {
                (mu0, 0.0)
            } else {
                let prec = 1.0 / p0 + uu;
                ((mu0 / p0 + uv) / prec, 1.0 / prec)
            }
        }
    }
}

/// Fails with [`Error::Singular`] unless every value is finite and variances are ≥ 0.
pub(crate) fn check_result(p: &Prediction) -> Result<()> {
    let bad = p
        .bias
        .iter()
        .chain(&p.std)
        .chain(&p.std_observation)
        .position(|v| !v.is_finite());
    if bad.is_some() || !p.mean.is_finite() || !p.mean_std.is_finite() {
        return Err(Error::Singular {
            reason: "the prediction overflowed or lost all precision (non-finite result); \
                     the model is too ill-conditioned for this window"
                .into(),
        });
    }
    Ok(())
}

/// Fractional Kalman prediction of one calibration window (SPEC §5).
pub fn fractional_kalman(
    model: &Model,
    calibration: &[f64],
    horizon: usize,
    algorithm: Algorithm,
) -> Result<Prediction> {
    check_window(calibration, horizon)?;
    let p = match algorithm {
        Algorithm::Schur => schur::predict(model, calibration, horizon)?,
        Algorithm::Literal => literal::predict(model, calibration, horizon)?,
    };
    check_result(&p)?;
    Ok(p)
}

/// Predictions of many windows (row-major `rows × k`), flattened row-major (`rows × h`).
#[derive(Debug, Clone, PartialEq)]
pub struct BatchPrediction {
    /// Number of windows.
    pub rows: usize,
    /// Horizon `h`.
    pub horizon: usize,
    /// Forecasts, `rows × h` row-major.
    pub bias: Vec<f64>,
    /// Forecast standard deviations, `h` (the same for every window).
    pub std: Vec<f64>,
    /// Observation standard deviations, `h`.
    pub std_observation: Vec<f64>,
    /// Mean-state estimates, one per window.
    pub mean: Vec<f64>,
    /// Standard deviation of the mean-state estimate.
    pub mean_std: f64,
}

/// Windows at or above which [`fractional_kalman_rows`] compiles the linear map and uses one
/// GEMM instead of one Schur recursion per window.
const COMPILE_MIN_ROWS: usize = 32;
/// Largest `h·k` for which the automatic compiled path is used (memory of `W`).
const COMPILE_MAX_ENTRIES: usize = 50_000_000;

/// Fractional Kalman prediction of every row of a row-major `rows × k` array.
///
/// With many windows the linear map is compiled ([`batch::Compiled`]) and applied as one matrix
/// product; otherwise the windows are predicted independently in parallel. `n_threads = 0` uses
/// every rayon thread.
pub fn fractional_kalman_rows(
    model: &Model,
    data: &[f64],
    k: usize,
    horizon: usize,
    algorithm: Algorithm,
    n_threads: usize,
) -> Result<BatchPrediction> {
    validate::threads(n_threads)?;
    let rows = batch::check_rows("calibration", data, k)?;
    check_window(&data[..k], horizon)?;
    validate::allocatable::<f64>("horizon", validate::product("horizon", rows, horizon)?)?;
    validate::finite("calibration", data)?;
    if algorithm == Algorithm::Schur
        && rows >= COMPILE_MIN_ROWS
        && horizon.saturating_mul(k) <= COMPILE_MAX_ENTRIES
    {
        let compiled = batch::Compiled::new(model, k, horizon, n_threads)?;
        return compiled.apply(data, n_threads);
    }
    let run = || {
        data.par_chunks(k)
            .map(|row| fractional_kalman(model, row, horizon, algorithm))
            .collect::<Result<Vec<_>>>()
    };
    let preds = batch::with_threads(n_threads, run)?;
    let mut bias = Vec::with_capacity(rows * horizon);
    let mut mean = Vec::with_capacity(rows);
    for p in &preds {
        bias.extend_from_slice(&p.bias);
        mean.push(p.mean);
    }
    let first = &preds[0];
    Ok(BatchPrediction {
        rows,
        horizon,
        bias,
        std: first.std.clone(),
        std_observation: first.std_observation.clone(),
        mean,
        mean_std: first.mean_std,
    })
}

/// Calibration-mean forecast (\[BP\] eq. 9) of every row of a row-major `rows × k` array:
/// `rows × h`, row-major.
pub fn calibration_mean(data: &[f64], k: usize, horizon: usize) -> Result<Vec<f64>> {
    let rows = batch::check_rows("calibration", data, k)?;
    check_window(&data[..k], horizon)?;
    validate::allocatable::<f64>("horizon", validate::product("horizon", rows, horizon)?)?;
    validate::finite("calibration", data)?;
    let mut out = vec![0.0; rows * horizon];
    out.par_chunks_mut(horizon)
        .zip(data.par_chunks(k))
        .for_each(|(o, y)| {
            let m = validate::neumaier_sum(y.iter().copied()) / k as f64;
            o.fill(m);
        });
    Ok(out)
}

/// Moving-average forecast (\[BP\] eq. 8, extended by eq. 9) of every row: for `1 ≤ j ≤ k` the
/// mean of the last `j` calibration samples, for `j > k` the calibration mean.
pub fn moving_average(data: &[f64], k: usize, horizon: usize) -> Result<Vec<f64>> {
    let rows = batch::check_rows("calibration", data, k)?;
    check_window(&data[..k], horizon)?;
    validate::allocatable::<f64>("horizon", validate::product("horizon", rows, horizon)?)?;
    validate::finite("calibration", data)?;
    let mut out = vec![0.0; rows * horizon];
    out.par_chunks_mut(horizon)
        .zip(data.par_chunks(k))
        .for_each(|(o, y)| {
            // Running compensated sum of the last j samples.
            let (mut sum, mut comp) = (0.0_f64, 0.0_f64);
            for j in 1..=horizon.min(k) {
                let v = y[k - j];
                let t = sum + v;
                if sum.abs() >= v.abs() {
                    comp += (sum - t) + v;
                } else {
                    comp += (v - t) + sum;
                }
                sum = t;
                o[j - 1] = (sum + comp) / j as f64;
            }
            if horizon > k {
                let m = (sum + comp) / k as f64;
                o[k..].fill(m);
            }
        });
    Ok(out)
}

#[cfg(test)]
mod tests {
    #[test]
    fn noise_parameters_map_and_name_their_arguments() {
        assert_eq!(
            super::noise_parameters(0.1, 0.01, 100.0),
            Ok((0.01 * 0.01, 0.1 * 0.1 * 100.0))
        );
        assert_eq!(
            super::noise_parameters(0.0, 0.01, 100.0),
            Ok((0.01 * 0.01, 0.0))
        );
        for (args, name) in [
            ((-0.1, 0.01, 100.0), "arw"),
            ((f64::NAN, 0.01, 100.0), "arw"),
            ((1e200, 0.01, 100.0), "arw"),
            ((0.1, 0.0, 100.0), "bias_instability"),
            ((0.1, 1e-200, 100.0), "bias_instability"),
            ((0.1, 1e200, 100.0), "bias_instability"),
            ((0.1, 0.01, 0.0), "fs"),
            ((0.1, 0.01, 1e-320), "fs"),
        ] {
            match super::noise_parameters(args.0, args.1, args.2) {
                Err(Error::InvalidParameter { name: got, .. }) => assert_eq!(got, name, "{args:?}"),
                other => panic!("{args:?}: expected an error naming {name}, got {other:?}"),
            }
        }
    }

    use super::*;

    #[test]
    fn moving_average_definition() {
        let y = [1.0, 2.0, 3.0, 4.0];
        let ma = moving_average(&y, 4, 6).unwrap();
        assert_eq!(ma, vec![4.0, 3.5, 3.0, 2.5, 2.5, 2.5]);
        let cm = calibration_mean(&y, 4, 2).unwrap();
        assert_eq!(cm, vec![2.5, 2.5]);
    }

    #[test]
    fn mean_prior_names() {
        assert_eq!(
            MeanPrior::parse("sample", 1.0, 2.0).unwrap(),
            MeanPrior::Sample
        );
        assert_eq!(MeanPrior::parse("none", 0.0, 0.0).unwrap(), MeanPrior::Zero);
        assert_eq!(
            MeanPrior::parse("diffuse", 0.0, 0.0).unwrap(),
            MeanPrior::Diffuse
        );
        assert_eq!(
            MeanPrior::parse("proper", 1.0, 2.0).unwrap(),
            MeanPrior::Proper { mu0: 1.0, p0: 2.0 }
        );
        let err = MeanPrior::parse("mystery", 0.0, 0.0)
            .unwrap_err()
            .to_string();
        assert!(err.contains("mean") && err.contains("mystery"), "{err}");
    }

    #[test]
    fn bad_parameters_are_rejected() {
        assert!(Model::new(1.5, 1.0, 0.0, MeanPrior::Sample).is_err());
        assert!(Model::new(-0.5, 1.0, 0.0, MeanPrior::Sample).is_err());
        assert!(Model::new(0.5, 0.0, 0.0, MeanPrior::Sample).is_err());
        assert!(Model::new(0.5, 1.0, -1.0, MeanPrior::Sample).is_err());
        assert!(Model::new(0.5, 1.0, 0.0, MeanPrior::Proper { mu0: 0.0, p0: -1.0 }).is_err());
        let m = Model::new(0.5, 1.0, 0.0, MeanPrior::Sample).unwrap();
        assert!(matches!(
            fractional_kalman(&m, &[1.0], 3, Algorithm::Schur),
            Err(Error::TooShort { .. })
        ));
        assert!(fractional_kalman(&m, &[1.0, 2.0], 0, Algorithm::Schur).is_err());
        assert!(matches!(
            fractional_kalman(&m, &[1.0, f64::NAN], 3, Algorithm::Schur),
            Err(Error::NonFinite { index: 1, .. })
        ));
        assert!(matches!(
            fractional_kalman_rows(&m, &[1.0, 2.0, 3.0], 2, 3, Algorithm::Schur, 1),
            Err(Error::ShapeMismatch { .. })
        ));
    }
}
