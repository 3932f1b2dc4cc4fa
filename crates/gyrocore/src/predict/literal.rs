//! The literal growing-state Kalman filter of \[BP\] §IV-A (the reference implementation).
//!
//! The state at time `t` is `[m, x_0, …, x_t]`; every step appends the new 1/f realisation
//!
//! ```text
//! x_t = Σ_{l=1}^{t} φ_l x_{t−l} + w_t,   φ_l = −π_l(d),   w_t ~ N(0, q)
//! ```
//!
//! to the state (the covariance grows by one row and column: `P_new,· = a·P`,
//! `P_new,new = a·P·aᵀ + q`), then, during calibration, applies the measurement
//! `y_t = m + x_t + v_t` (`H = e_m + e_{x_t}`, `v_t ~ N(0, r)`). After the window the state is
//! propagated without measurements and the bias forecast is `m̂ + x̂_t` with variance
//! `P_mm + 2P_mx + P_xx`.
//!
//! The diffuse mean prior is handled exactly (Koopman's exact initialisation, which here is
//! closed-form): conditioning on `y_0` with a flat prior on `m` leaves `x_0 ~ N(0, q)` and gives
//! `m = y_0 − x_0 − v_0`, so the filter starts from `m̂ = y_0`, `x̂_0 = 0`,
//! `P = [[q + r, −q], [−q, q]]` and continues normally at `t = 1`.
//!
//! Cost O(t²) per step, O(n³) in all, O(n²) memory: kept for validation and small `n`.

use super::{MeanPrior, Model, Prediction, mean_posterior};
use crate::{Error, Result, fractional, validate};

/// Predicts one window with the literal growing-state filter.
pub(crate) fn predict(model: &Model, calibration: &[f64], horizon: usize) -> Result<Prediction> {
    let k = calibration.len();
    let n = k + horizon;
    let dim = n + 1; // [m, x_0..x_{n-1}]
    // φ_l = −π_l(d), l ≥ 1.
    let pi = fractional::weights(model.d, n)?;
    let mut xs = vec![0.0_f64; dim];
    let mut p = vec![0.0_f64; dim * dim];
    let (m0, pm0) = match model.mean {
        MeanPrior::Sample => {
            let ybar = validate::neumaier_sum(calibration.iter().copied()) / k as f64;
            mean_posterior(model.mean, 0.0, 0.0, ybar)
        }
        MeanPrior::Zero | MeanPrior::Diffuse => (0.0, 0.0),
        MeanPrior::Proper { mu0, p0 } => (mu0, p0),
    };
    xs[0] = m0;
    p[0] = pm0;
    let scale = model.q + model.r;
    let mut bias = Vec::with_capacity(horizon);
    let mut std = Vec::with_capacity(horizon);
    let mut std_observation = Vec::with_capacity(horizon);
    let mut row = vec![0.0_f64; dim];
    for t in 0..n {
        let it = t + 1; // index of x_t
        // Augment: row = a·P over the current states 0..it, a[1 + t − l] = φ_l.
        let mut mean_xt = 0.0;
        row[..it].fill(0.0);
        for l in 1..=t {
            let phi = -pi[l];
            let src = 1 + t - l;
            mean_xt += phi * xs[src];
            let prow = &p[src * dim..src * dim + it];
            for (r, v) in row[..it].iter_mut().zip(prow) {
                *r += phi * v;
            }
        }
        let mut var_xt = model.q;
        for l in 1..=t {
            var_xt += -pi[l] * row[1 + t - l];
        }
        xs[it] = mean_xt;
        for j in 0..it {
            p[it * dim + j] = row[j];
            p[j * dim + it] = row[j];
        }
        p[it * dim + it] = var_xt;

        if t < k {
            let y = calibration[t];
            if t == 0 && model.mean == MeanPrior::Diffuse {
                // Exact diffuse initialisation (module docs).
                xs[0] = y;
                p[0] = model.q + model.r;
                p[it] = -model.q;
                p[it * dim] = -model.q;
                continue;
            }
            // Measurement y = m + x_t + v.
            for j in 0..=it {
                row[j] = p[j * dim] + p[j * dim + it];
            }
            let s = row[0] + row[it] + model.r;
            if s.is_nan() || s < scale * (1.0 - 1e-8) {
                return Err(Error::Singular {
                    reason: format!(
                        "innovation variance {s:.3e} at calibration sample {t} fell below its \
                         theoretical floor q + r = {scale:.3e} (the literal filter lost \
                         positive definiteness)"
                    ),
                });
            }
            let innov = y - xs[0] - xs[it];
            for j in 0..=it {
                xs[j] += row[j] * innov / s;
            }
            for i in 0..=it {
                let gi = row[i] / s;
                let prow = &mut p[i * dim..=i * dim + it];
                for (v, rj) in prow.iter_mut().zip(&row[..=it]) {
                    *v -= gi * rj;
                }
            }
        } else {
            let var_b = p[0] + 2.0 * p[it] + p[it * dim + it];
            if var_b < -1e-9 * scale {
                return Err(Error::Singular {
                    reason: format!(
                        "negative forecast variance {var_b:.3e} at horizon step {} (the literal \
                         filter lost positive definiteness)",
                        t - k
                    ),
                });
            }
            let var_b = var_b.max(0.0);
            bias.push(xs[0] + xs[it]);
            std.push(var_b.sqrt());
            std_observation.push((var_b + model.r).sqrt());
        }
    }
    Ok(Prediction {
        bias,
        std,
        std_observation,
        mean: xs[0],
        mean_std: p[0].max(0.0).sqrt(),
    })
}
