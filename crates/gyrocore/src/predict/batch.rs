//! The compiled (batch) fractional Kalman predictor: `ŷ = W·y + w0` (SPEC §5 "Batch").
//!
//! For fixed `(d, q, r, k, h, mean prior)` the forecast is linear in the calibration window:
//!
//! ```text
//! ŷ = F·y + m̂·(1 − F·1),   F = K_fc·K_cc⁻¹ = L_fc·L_cc⁻¹,   m̂ = cᵀ·y + c0
//! W = F + (1 − F·1)·cᵀ,    w0 = c0·(1 − F·1)
//! ```
//!
//! with `c = 1/k` (sample mean), `0` (zero mean), `K_cc⁻¹1 / 1ᵀK_cc⁻¹1` (diffuse) or
//! `K_cc⁻¹1 / (1/p0 + 1ᵀK_cc⁻¹1)`, `c0 = μ0/(p0·prec)` (proper prior). Compiling runs the Schur
//! recursion once, keeping the Cholesky factor `L` (`n × k`), and one triangular solve; a batch of
//! `R` windows is then one GEMM `Ŷ = Y·Wᵀ + 1·w0ᵀ` (faer, multi-threaded). The forecast standard
//! deviations do not depend on the data and are stored once.

use faer::linalg::matmul::matmul;
use faer::linalg::triangular_solve::solve_upper_triangular_in_place;
use faer::{Accum, Mat, MatMut, MatRef, Par};

use super::schur::{self, Conditional};
use super::{BatchPrediction, MeanPrior, Model, check_window, mean_posterior};
use crate::float::Float;
use crate::{Error, Result, validate};

/// Number of rows of a row-major array of `data.len()` values with `k` columns.
pub(crate) fn check_rows(name: &'static str, data: &[f64], k: usize) -> Result<usize> {
    if k == 0 || data.is_empty() {
        return Err(Error::TooShort {
            name,
            needed: 2,
            got: 0,
        });
    }
    if data.len() % k != 0 {
        return Err(Error::ShapeMismatch {
            name,
            reason: format!(
                "{} values do not form rows of {k} samples (ragged batch)",
                data.len()
            ),
        });
    }
    Ok(data.len() / k)
}

/// faer parallelism for `n_threads` (0 = every rayon thread).
pub(crate) fn par(n_threads: usize) -> Par {
    if n_threads == 1 {
        Par::Seq
    } else {
        Par::rayon(n_threads)
    }
}

/// Runs `f` on a rayon pool of `n_threads` threads (0 = the global pool).
pub(crate) fn with_threads<T: Send>(n_threads: usize, f: impl FnOnce() -> T + Send) -> T {
    if n_threads == 0 {
        return f();
    }
    match rayon::ThreadPoolBuilder::new()
        .num_threads(n_threads)
        .build()
    {
        Ok(pool) => pool.install(f),
        Err(_) => f(),
    }
}

/// A compiled linear predictor for windows of `k` samples and a horizon of `h`.
#[derive(Debug, Clone)]
pub struct Compiled {
    /// Calibration length `k`.
    pub calibration_length: usize,
    /// Horizon `h`.
    pub horizon: usize,
    /// `W`, `h × k` row-major.
    pub weights: Vec<f64>,
    /// `w0`, `h`.
    pub offset: Vec<f64>,
    /// Mean-state weights `c` (`k`) and offset `c0`: `m̂ = c·y + c0`.
    pub mean_weights: Vec<f64>,
    /// `c0`.
    pub mean_offset: f64,
    /// Forecast standard deviation (`h`).
    pub std: Vec<f64>,
    /// Observation standard deviation (`h`).
    pub std_observation: Vec<f64>,
    /// Standard deviation of `m̂`.
    pub mean_std: f64,
}

impl Compiled {
    /// Precomputes `W`, `w0` and the standard deviations (O(n·k) memory, O(h·k²) time).
    pub fn new(model: &Model, k: usize, horizon: usize, n_threads: usize) -> Result<Self> {
        validate::threads(n_threads)?;
        validate::min_len("calibration_length", k, 2)?;
        check_window(&[0.0, 0.0], horizon)?;
        let n = k.saturating_add(horizon);
        // L (n × k) plus the weights W (h × k), named after the larger of the two sizes.
        let name = if k >= horizon {
            "calibration_length"
        } else {
            "horizon"
        };
        validate::allocatable::<f64>(
            name,
            validate::product(name, validate::product(name, 2, n)?, k)?,
        )?;
        let mut l = Mat::<f64>::zeros(n, k);
        let cond: Conditional = schur::condition(model, None, k, horizon, |i, col| {
            for (m, v) in col.iter().enumerate() {
                l[(i + m, i)] = *v;
            }
        })?;
        let par = par(n_threads);
        let l_cc = l.as_ref().submatrix(0, 0, k, k);
        // Fᵀ = L_cc⁻ᵀ·L_fcᵀ (k × h).
        let mut ft = l
            .as_ref()
            .submatrix(k, 0, horizon, k)
            .transpose()
            .to_owned();
        solve_upper_triangular_in_place(l_cc.transpose(), ft.as_mut(), par);
        // Mean-state weights.
        let (c, c0, var_m) = match model.mean {
            MeanPrior::Sample => (vec![1.0 / k as f64; k], 0.0, 0.0),
            MeanPrior::Zero => (vec![0.0; k], 0.0, 0.0),
            MeanPrior::Proper { mu0, p0: 0.0 } => (vec![0.0; k], mu0, 0.0),
            MeanPrior::Diffuse | MeanPrior::Proper { .. } => {
                // K_cc⁻¹·1 = L_cc⁻ᵀ·u.
                let mut kinv1 = Mat::<f64>::from_fn(k, 1, |i, _| cond.u[i]);
                solve_upper_triangular_in_place(l_cc.transpose(), kinv1.as_mut(), par);
                let (prec, c0) = match model.mean {
                    MeanPrior::Proper { mu0, p0 } => {
                        let prec = 1.0 / p0 + cond.uu;
                        (prec, mu0 / (p0 * prec))
                    }
                    _ => (cond.uu, 0.0),
                };
                let c = (0..k).map(|i| kinv1[(i, 0)] / prec).collect();
                (c, c0, 1.0 / prec)
            }
        };
        // Consistency with the streaming posterior (same formula, data-free part).
        let (_, var_check) = mean_posterior(model.mean, cond.uu, 0.0, 0.0);
        debug_assert!((var_check - var_m).abs() <= 1e-12 * var_m.abs().max(1.0));
        let mut weights = vec![0.0; horizon * k];
        let mut offset = Vec::with_capacity(horizon);
        for j in 0..horizon {
            let g = 1.0 - cond.f1[j];
            let row = &mut weights[j * k..(j + 1) * k];
            for (i, w) in row.iter_mut().enumerate() {
                *w = ft[(i, j)] + g * c[i];
            }
            offset.push(c0 * g);
        }
        let pred = schur::assemble(
            model.r,
            &Conditional {
                fy: vec![0.0; horizon],
                ..cond
            },
            0.0,
            var_m,
        )?;
        let compiled = Self {
            calibration_length: k,
            horizon,
            weights,
            offset,
            mean_weights: c,
            mean_offset: c0,
            std: pred.std,
            std_observation: pred.std_observation,
            mean_std: pred.mean_std,
        };
        if compiled.weights.iter().any(|v| !v.is_finite()) {
            return Err(Error::Singular {
                reason: "the compiled prediction weights are not finite (ill-conditioned model)"
                    .into(),
            });
        }
        Ok(compiled)
    }

    /// Predicts every row of a row-major `rows × k` batch into `out` (`rows × h`, row-major) and
    /// the mean-state estimates into `mean` (`rows`). One GEMM; `par` as faer's.
    pub fn apply_into(
        &self,
        data: &[f64],
        out: &mut [f64],
        mean: &mut [f64],
        par: Par,
    ) -> Result<()> {
        let k = self.calibration_length;
        let h = self.horizon;
        let rows = check_rows("batch", data, k)?;
        if out.len() != rows * h || mean.len() != rows {
            return Err(Error::ShapeMismatch {
                name: "out",
                reason: format!("expected {rows} × {h} outputs and {rows} means"),
            });
        }
        validate::finite("batch", data)?;
        for row in out.chunks_mut(h) {
            row.copy_from_slice(&self.offset);
        }
        let y = MatRef::from_row_major_slice(data, rows, k);
        let wt = MatRef::from_column_major_slice(&self.weights, k, h);
        let dst = MatMut::from_row_major_slice_mut(out, rows, h);
        matmul(dst, Accum::Add, y, wt, 1.0, par);
        let c = MatRef::from_column_major_slice(&self.mean_weights, k, 1);
        mean.fill(self.mean_offset);
        let dst = MatMut::from_column_major_slice_mut(mean, rows, 1);
        matmul(dst, Accum::Add, y, c, 1.0, par);
        Ok(())
    }

    /// Predicts every row of a row-major `rows × k` batch in the evaluation order of the C that
    /// `gyrobias.codegen` generates (`CompiledPredictor.to_c`), in `T` arithmetic: `W`, `w0`,
    /// `c` and `c0` rounded to `T` first, then for each window and each forecast `j`
    ///
    /// ```text
    /// acc = 0;  acc = acc + W[j][i]·y[i]  for i = 0, 1, …, k−1;  ŷ[j] = acc + w0[j]
    /// ```
    ///
    /// one rounding per `×` and per `+`, never a fused multiply-add (Rust does not contract), so
    /// the generated float64/float32 C gives these bits exactly. The mean state is the same sum
    /// with `c`, `c0`. Sequential (no GEMM blocking, no threads): the reference for the C, not
    /// the fast path ([`apply_rows`](Self::apply_rows)), from which it differs by rounding.
    /// Returns `(bias (rows·h, row-major), mean (rows))`.
    pub fn apply_sequential<T: Float>(
        &self,
        data: &[T],
        n_columns: usize,
    ) -> Result<(Vec<T>, Vec<T>)> {
        let k = self.calibration_length;
        let h = self.horizon;
        if n_columns != k {
            return Err(Error::ShapeMismatch {
                name: "batch",
                reason: format!(
                    "batch rows have {n_columns} samples, the predictor was compiled for \
                     calibration_length = {k}"
                ),
            });
        }
        if data.is_empty() || data.len() % k != 0 {
            return Err(Error::ShapeMismatch {
                name: "batch",
                reason: format!("{} values do not form rows of {k} samples", data.len()),
            });
        }
        if let Some(index) = data.iter().position(|v| !v.is_finite()) {
            return Err(Error::NonFinite {
                name: "batch",
                index,
            });
        }
        let rows = data.len() / k;
        let w: Vec<T> = self.weights.iter().map(|&v| T::from_f64(v)).collect();
        let w0: Vec<T> = self.offset.iter().map(|&v| T::from_f64(v)).collect();
        let c: Vec<T> = self.mean_weights.iter().map(|&v| T::from_f64(v)).collect();
        let c0 = T::from_f64(self.mean_offset);
        let dot = |row: &[T], y: &[T]| {
            let mut acc = T::ZERO;
            for (&a, &b) in row.iter().zip(y) {
                acc += a * b;
            }
            acc
        };
        let mut bias = vec![T::ZERO; validate::product("batch", rows, h)?];
        let mut mean = Vec::with_capacity(rows);
        for (y, out) in data.chunks_exact(k).zip(bias.chunks_exact_mut(h)) {
            for ((o, row), &off) in out.iter_mut().zip(w.chunks_exact(k)).zip(&w0) {
                *o = dot(row, y) + off;
            }
            mean.push(dot(&c, y) + c0);
        }
        Ok((bias, mean))
    }

    /// Predicts every row of a row-major `rows × k` batch (`n_threads = 0`: all threads).
    pub fn apply(&self, data: &[f64], n_threads: usize) -> Result<BatchPrediction> {
        self.apply_rows(data, self.calibration_length, n_threads)
    }

    /// [`apply`](Self::apply) to a row-major batch of rows of `n_columns` samples, which must
    /// be the calibration length the predictor was compiled for.
    pub fn apply_rows(
        &self,
        data: &[f64],
        n_columns: usize,
        n_threads: usize,
    ) -> Result<BatchPrediction> {
        validate::threads(n_threads)?;
        if n_columns != self.calibration_length {
            return Err(Error::ShapeMismatch {
                name: "batch",
                reason: format!(
                    "batch rows have {n_columns} samples, the predictor was compiled for \
                     calibration_length = {}",
                    self.calibration_length
                ),
            });
        }
        let rows = check_rows("batch", data, self.calibration_length)?;
        let mut bias = vec![0.0; rows * self.horizon];
        let mut mean = vec![0.0; rows];
        self.apply_into(data, &mut bias, &mut mean, par(n_threads))?;
        Ok(BatchPrediction {
            rows,
            horizon: self.horizon,
            bias,
            std: self.std.clone(),
            std_observation: self.std_observation.clone(),
            mean,
            mean_std: self.mean_std,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn compiled(mean: MeanPrior) -> Compiled {
        let model = Model::new(0.5, 1e-4, 1e-4, mean).unwrap();
        Compiled::new(&model, 12, 5, 1).unwrap()
    }

    fn window(rows: usize) -> Vec<f64> {
        (0..rows * 12)
            .map(|i| 0.2 + 0.01 * ((i * 7919 % 97) as f64 - 48.0))
            .collect()
    }

    #[test]
    fn sequential_is_the_left_to_right_sum_and_close_to_the_gemm() {
        for mean in [MeanPrior::Sample, MeanPrior::Proper { mu0: 0.3, p0: 2.0 }] {
            let c = compiled(mean);
            let y = window(3);
            let (bias, m) = c.apply_sequential::<f64>(&y, 12).unwrap();
            let gemm = c.apply(&y, 1).unwrap();
            for (r, yr) in y.chunks(12).enumerate() {
                for j in 0..5 {
                    let mut acc = 0.0_f64;
                    for i in 0..12 {
                        acc += c.weights[j * 12 + i] * yr[i];
                    }
                    let want = acc + c.offset[j];
                    assert_eq!(bias[r * 5 + j].to_bits(), want.to_bits());
                    // the GEMM sums in another order: equal to a few ulps of Σ|W||y|
                    assert!((gemm.bias[r * 5 + j] - want).abs() <= 1e-14);
                }
                assert!((m[r] - gemm.mean[r]).abs() <= 1e-14);
            }
            // float32: the same sum with every operand and operation in f32
            let y32: Vec<f32> = y.iter().map(|&v| v as f32).collect();
            let (b32, _) = c.apply_sequential::<f32>(&y32, 12).unwrap();
            let mut acc = 0.0_f32;
            for i in 0..12 {
                acc += (c.weights[i] as f32) * y32[i];
            }
            assert_eq!(b32[0].to_bits(), (acc + c.offset[0] as f32).to_bits());
        }
    }

    #[test]
    fn sequential_checks_its_batch() {
        let c = compiled(MeanPrior::Sample);
        let mut y = window(2);
        assert!(matches!(
            c.apply_sequential::<f64>(&y, 11),
            Err(Error::ShapeMismatch { name: "batch", .. })
        ));
        assert!(matches!(
            c.apply_sequential::<f64>(&y[..13], 12),
            Err(Error::ShapeMismatch { name: "batch", .. })
        ));
        assert!(matches!(
            c.apply_sequential::<f64>(&[], 12),
            Err(Error::ShapeMismatch { name: "batch", .. })
        ));
        y[17] = f64::NAN;
        assert_eq!(
            c.apply_sequential::<f64>(&y, 12),
            Err(Error::NonFinite {
                name: "batch",
                index: 17
            })
        );
    }
}
