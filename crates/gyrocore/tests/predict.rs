//! The fast (generalized Schur) and compiled predictors against the literal growing-state filter.

use gyrocore::fractional;
use gyrocore::predict::{
    Algorithm, MeanPrior, Model, batch::Compiled, fractional_kalman, fractional_kalman_rows,
};
use gyrocore::random::NormalStream;

/// Type-II ARFIMA(0, d, 0) plus white noise plus a constant.
fn simulate(seed: u64, n: usize, d: f64, q: f64, r: f64, bias: f64) -> Vec<f64> {
    let mut g = NormalStream::new(seed);
    let w: Vec<f64> = (0..n).map(|_| g.next_normal() * q.sqrt()).collect();
    let psi = fractional::weights(-d, n).unwrap();
    (0..n)
        .map(|t| {
            let x: f64 = (0..=t).map(|i| psi[t - i] * w[i]).sum();
            bias + x + r.sqrt() * g.next_normal()
        })
        .collect()
}

fn rel_close(a: &[f64], b: &[f64], tol: f64, what: &str) {
    let scale = b.iter().fold(0.0_f64, |m, v| m.max(v.abs())).max(1e-300);
    for (i, (x, y)) in a.iter().zip(b).enumerate() {
        assert!(
            (x - y).abs() <= tol * scale,
            "{what}[{i}]: {x} vs {y} (scale {scale})"
        );
    }
}

fn priors() -> [MeanPrior; 5] {
    [
        MeanPrior::Sample,
        MeanPrior::Diffuse,
        MeanPrior::Zero,
        MeanPrior::Proper { mu0: 3.0, p0: 4.0 },
        MeanPrior::Proper { mu0: 3.0, p0: 0.0 },
    ]
}

#[test]
fn schur_matches_literal_filter() {
    // Issue target: 1e-9 relative; the algorithms are both backward stable, observed ~1e-13.
    let tol = 1e-9;
    let mut seed = 1;
    for &d in &[0.25, 0.5, 0.7] {
        for &r in &[0.0, 0.3, 2.0] {
            for mean in priors() {
                seed += 1;
                let (k, h) = (60, 45);
                let y = simulate(seed, k, d, 1.3, r, 5.0);
                let model = Model::new(d, 1.3, r, mean).unwrap();
                let fast = fractional_kalman(&model, &y, h, Algorithm::Schur).unwrap();
                let lit = fractional_kalman(&model, &y, h, Algorithm::Literal).unwrap();
                let tag = format!("d={d} r={r} {mean:?}");
                rel_close(&fast.bias, &lit.bias, tol, &format!("bias {tag}"));
                rel_close(&fast.std, &lit.std, tol, &format!("std {tag}"));
                rel_close(
                    &fast.std_observation,
                    &lit.std_observation,
                    tol,
                    &format!("std_obs {tag}"),
                );
                assert!((fast.mean - lit.mean).abs() <= tol * lit.mean.abs().max(1.0));
                assert!((fast.mean_std - lit.mean_std).abs() <= tol * lit.mean_std.max(1.0));
            }
        }
    }
}

#[test]
fn compiled_matches_streaming() {
    // Same numbers through W·y + w0: agreement to rounding (1e-10 relative, W built by a
    // triangular solve instead of on-the-fly substitution).
    let (k, h, rows) = (50, 40, 7);
    for &r in &[0.0, 0.5] {
        for mean in priors() {
            let model = Model::new(0.45, 0.8, r, mean).unwrap();
            let data: Vec<f64> = (0..rows)
                .flat_map(|s| simulate(100 + s as u64, k, 0.45, 0.8, r, -2.0))
                .collect();
            let compiled = Compiled::new(&model, k, h, 1).unwrap();
            let batch = compiled.apply(&data, 1).unwrap();
            for (i, row) in data.chunks(k).enumerate() {
                let one = fractional_kalman(&model, row, h, Algorithm::Schur).unwrap();
                rel_close(
                    &batch.bias[i * h..(i + 1) * h],
                    &one.bias,
                    1e-10,
                    "compiled bias",
                );
                rel_close(&batch.std, &one.std, 1e-10, "compiled std");
                assert!((batch.mean[i] - one.mean).abs() <= 1e-10 * one.mean.abs().max(1.0));
            }
            // The automatic row path (per-row below the compile threshold) agrees too.
            let rowwise = fractional_kalman_rows(&model, &data, k, h, Algorithm::Schur, 1).unwrap();
            rel_close(&rowwise.bias, &batch.bias, 1e-10, "rows bias");
        }
    }
}

#[test]
fn white_noise_model_reduces_to_known_answers() {
    // d → 0 is not allowed exactly at the boundary, but d = 0 is inside the range: x is white,
    // so the forecast of x is 0 and the bias forecast is the mean estimate; with a diffuse prior
    // and white noise of variance q + r the GLS mean is the sample mean with variance (q+r)/k.
    let y = [1.0, 2.0, 4.0, 1.0, 7.0];
    let model = Model::new(0.0, 0.5, 0.25, MeanPrior::Diffuse).unwrap();
    let p = fractional_kalman(&model, &y, 3, Algorithm::Schur).unwrap();
    for b in &p.bias {
        assert!((b - 3.0).abs() < 1e-14);
    }
    assert!((p.mean_std - (0.75_f64 / 5.0).sqrt()).abs() < 1e-14);
    // Bias variance = Var(x) + Var(m̂) = q + (q + r)/k.
    assert!((p.std[0] - (0.5 + 0.75 / 5.0_f64).sqrt()).abs() < 1e-14);
    assert!((p.std_observation[0] - (0.75 + 0.75 / 5.0_f64).sqrt()).abs() < 1e-14);
}

#[test]
fn long_series_runs_in_linear_memory() {
    // n = 100 500: the Schur path only allocates O(n) vectors (a dense n × n matrix would be
    // 80 GB); k = h = 50 000 is timed in the benchmark. Sanity: finite output, variance
    // increasing with the horizon.
    let y = simulate(9, 500, 0.5, 1.0, 0.0, 0.0);
    let model = Model::new(0.5, 1.0, 0.1, MeanPrior::Sample).unwrap();
    let p = fractional_kalman(&model, &y, 100_000, Algorithm::Schur).unwrap();
    assert!(p.bias.iter().all(|v| v.is_finite()));
    assert!(p.std.windows(2).all(|w| w[1] >= w[0]));
}
