//! The fractional Kalman predictor by the generalized Schur algorithm: O(n·k) time, O(n) memory.
//!
//! With `e = x + v` over `n = k + h` samples, `K = Cov(e) = q·L·Lᵀ + r·I` (L lower-triangular
//! Toeplitz in `ψ = π(−d)`) has displacement rank 2:
//!
//! ```text
//! K − Z·K·Zᵀ = G·Gᵀ,   G = [√q·ψ, √r·e_0],   Z the down-shift.
//! ```
//!
//! Each step of the generalized Schur algorithm rotates the generator (a Givens rotation: the
//! displacement signature is positive, so no hyperbolic rotation and no instability) so that its
//! row `i` is `[δ, 0]`; the first column is then column `i` of the Cholesky factor of `K`, and
//! the shifted column with the untouched second one generates the next Schur complement. The
//! calibration data `[y, 1]` are forward-substituted on the fly. After `k` steps
//!
//! * `−B[k:, y] = K_fc·K_cc⁻¹·y = E[e_future | e_cal = y]`, `−B[k:, 1] = K_fc·K_cc⁻¹·1 = F·1`;
//! * the collected normalised innovations are `v = L_cc⁻¹·y`, `u = L_cc⁻¹·1`, so `u·u = 1ᵀK_cc⁻¹1`
//!   and `u·v = 1ᵀK_cc⁻¹y` give the mean state's GLS posterior;
//! * the remaining generator `g` satisfies `S − Z·S·Zᵀ = g·gᵀ` for the future's conditional
//!   covariance `S`, so `diag S = cumsum(g0² + g1²)`.
//!
//! The prediction is `−B[k:, y] + m̂·(1 + B[k:, 1])` with observation variance
//! `diag S + Var(m̂)·(1 + B[k:, 1])²` (the bias variance is that minus `r`), SPEC §5.
//!
//! Storage trick: the generator column `g0` is shifted down by one row at every step; it is kept
//! in coordinates relative to the current row, so the shift costs nothing and the Cholesky column
//! overwrites it in place.

use super::{MeanPrior, Model, Prediction, mean_posterior};
use crate::{Error, Result, fractional, validate};

/// The conditional distribution of the future noise given the calibration window.
#[derive(Debug, Clone)]
pub(crate) struct Conditional {
    /// `E[e_future | e_cal = y]` (`h`).
    pub(crate) fy: Vec<f64>,
    /// `F·1 = K_fc·K_cc⁻¹·1` (`h`).
    pub(crate) f1: Vec<f64>,
    /// `Var(e_future | e_cal)` (`h`, white noise included).
    pub(crate) var_e: Vec<f64>,
    /// `1ᵀ·K_cc⁻¹·1`.
    pub(crate) uu: f64,
    /// `1ᵀ·K_cc⁻¹·y`.
    pub(crate) uv: f64,
    /// `u = L_cc⁻¹·1` (`k`).
    pub(crate) u: Vec<f64>,
}

/// Runs the generalized Schur recursion for `k` calibration and `h` future samples.
///
/// `y` (length `k`, or `None` for zeros) is forward-substituted on the fly. `column(i, l)` is
/// called with the Cholesky column `i` of `K` over rows `i..n` (`l[0]` is the diagonal), for
/// callers that need the factor itself.
pub(crate) fn condition(
    model: &Model,
    y: Option<&[f64]>,
    k: usize,
    h: usize,
    mut column: impl FnMut(usize, &[f64]),
) -> Result<Conditional> {
    let n = k + h;
    let sq = model.q.sqrt();
    let sr = model.r.sqrt();
    // g0 in coordinates relative to the current row: a[m] is row i + m at step i.
    let mut a = fractional::weights(-model.d, n)?;
    for v in &mut a {
        *v *= sq;
    }
    let mut g1 = vec![0.0; n];
    g1[0] = sr;
    let mut by = vec![0.0; n];
    if let Some(y) = y {
        by[..k].copy_from_slice(y);
    }
    let mut b1 = vec![0.0; n];
    b1[..k].fill(1.0);
    let mut u = Vec::with_capacity(k);
    let (mut uu, mut uv) = (0.0_f64, 0.0_f64);
    // Theory: the innovation variance of e_i is at least q + r (w_i and v_i are new at step i).
    let floor = (model.q + model.r) * (1.0 - 1e-8);
    let white = model.r == 0.0;
    // The recursion runs inside a runtime CPU-feature dispatch (pulp: AVX2 where available) so
    // the element loops are vectorised 4-wide; plain multiply-add (no FMA contraction) keeps the
    // results identical on every CPU.
    crate::simd::arch().dispatch(|| -> Result<()> {
        for i in 0..k {
            let len = n - i;
            let a = &mut a[..len];
            let g1 = &mut g1[i..];
            let by = &mut by[i..];
            let b1 = &mut b1[i..];
            let delta = a[0].hypot(g1[0]);
            if !delta.is_finite() || delta * delta < floor {
                return Err(Error::Singular {
                    reason: format!(
                        "innovation variance {:.3e} at calibration sample {i} fell below its \
                         theoretical floor q + r = {:.3e} (loss of precision)",
                        delta * delta,
                        model.q + model.r
                    ),
                });
            }
            let ay = by[0] / delta;
            let a1 = b1[0] / delta;
            uu += a1 * a1;
            uv += a1 * ay;
            u.push(a1);
            if white {
                // r = 0: g1 stays zero, the rotation is the identity and a is √q·ψ throughout.
                for ((l, y), o) in a[1..].iter().zip(&mut by[1..]).zip(&mut b1[1..]) {
                    *y -= l * ay;
                    *o -= l * a1;
                }
            } else {
                let c = a[0] / delta;
                let s = g1[0] / delta;
                a[0] = delta;
                g1[0] = 0.0;
                for (((g0, g1), y), o) in a[1..]
                    .iter_mut()
                    .zip(&mut g1[1..])
                    .zip(&mut by[1..])
                    .zip(&mut b1[1..])
                {
                    let x0 = *g0;
                    let x1 = *g1;
                    let l = c * x0 + s * x1;
                    *g1 = c * x1 - s * x0;
                    *g0 = l;
                    *y -= l * ay;
                    *o -= l * a1;
                }
            }
            column(i, a);
            // The shift Z·l is implicit: next step reads a[m] as row i + 1 + m.
        }
        Ok(())
    })?;
    let mut var_e = Vec::with_capacity(h);
    let mut acc = 0.0_f64;
    for j in 0..h {
        acc += a[j] * a[j] + g1[k + j] * g1[k + j];
        var_e.push(acc);
    }
    let fy = by[k..].iter().map(|v| -v).collect();
    let f1 = b1[k..].iter().map(|v| -v).collect();
    Ok(Conditional {
        fy,
        f1,
        var_e,
        uu,
        uv,
        u,
    })
}

/// Fractional Kalman prediction of one window by the generalized Schur algorithm.
pub(crate) fn predict(model: &Model, calibration: &[f64], horizon: usize) -> Result<Prediction> {
    let k = calibration.len();
    let cond = condition(model, Some(calibration), k, horizon, |_, _| {})?;
    let sample_mean = if model.mean == MeanPrior::Sample {
        validate::neumaier_sum(calibration.iter().copied()) / k as f64
    } else {
        0.0
    };
    let (mean, var_m) = mean_posterior(model.mean, cond.uu, cond.uv, sample_mean);
    assemble(model.r, &cond, mean, var_m)
}

/// Combines the conditional noise forecast with the mean state's posterior.
pub(crate) fn assemble(r: f64, cond: &Conditional, mean: f64, var_m: f64) -> Result<Prediction> {
    let h = cond.fy.len();
    let mut bias = Vec::with_capacity(h);
    let mut std = Vec::with_capacity(h);
    let mut std_observation = Vec::with_capacity(h);
    for j in 0..h {
        let g = 1.0 - cond.f1[j];
        bias.push(cond.fy[j] + mean * g);
        let var_obs = cond.var_e[j] + var_m * g * g;
        let var_b = var_obs - r;
        if var_b.is_nan() || var_b < 0.0 {
            return Err(Error::Singular {
                reason: format!(
                    "negative forecast variance {var_b:.3e} at horizon step {j} (loss of precision)"
                ),
            });
        }
        std.push(var_b.sqrt());
        std_observation.push(var_obs.sqrt());
    }
    Ok(Prediction {
        bias,
        std,
        std_observation,
        mean,
        mean_std: var_m.sqrt(),
    })
}
