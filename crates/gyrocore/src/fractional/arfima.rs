//! ARFIMA(0, d, 0) simulation (SPEC §4, Hosking 1981, \[BP\] §III).
//!
//! * **Type II** (`Kind::TypeII`, any real `d`): `x = Δ^{−d} w`, `w_t` iid `N(0, σ²)` for
//!   `t ≥ 0` and `w_t = 0` before: `x_k = Σ_{i=0}^{k} ψ_{k−i} w_i`, `ψ_l = π_l(−d)`. This is
//!   \[BP\]'s "half-integrated white noise" for `d = ½` and the model its bias predictor assumes.
//! * **Stationary** (`Kind::Stationary`, `|d| < ½`): the stationary Gaussian process with
//!   autocovariance
//!
//!   ```text
//!   γ(0) = σ²·Γ(1 − 2d)/Γ(1 − d)²,   γ(k) = γ(k − 1)·(k − 1 + d)/(k − d)
//!   ```
//!
//!   generated exactly by circulant embedding (Davies & Harte 1987; Craigmile 2003 for the
//!   non-negativity of the embedding of ARFIMA autocovariances): with `M = 2m` (`m ≥ n − 1`,
//!   a fast FFT size), `c_j = γ(min(j, M − j))`, eigenvalues `λ_k = Σ_j c_j e^{−2πijk/M} ≥ 0`,
//!   `Z_0 = √(λ_0/M)·ξ_0`, `Z_m = √(λ_m/M)·ξ_m`, `Z_k = √(λ_k/(2M))·(ξ_k + iη_k)` for
//!   `0 < k < m`, `Z_{M−k} = conj(Z_k)`, and `x_t = Σ_k Z_k e^{2πikt/M}` for `t < n`.
//!   `Cov(x_t, x_s) = γ(t − s)` exactly (up to rounding).
//!
//! Random numbers come from [`crate::random::NormalStream`] seeded with `seed` and are consumed
//! row after row (`n` deviates per type-II row, `M` per stationary row), so the same seed gives
//! the same output and row 0 of a batch equals the single series with that seed.

use rayon::prelude::*;
use realfft::num_complex::Complex;

use super::{Method, convolve, diff_rows_into};
use crate::random::NormalStream;
use crate::stats::ln_gamma;
use crate::{Error, Result};

/// Which ARFIMA(0, d, 0) process to simulate.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// Fractionally integrated white noise started at time 0 (any real `d`).
    TypeII,
    /// The stationary process (`|d| < ½`), exact by circulant embedding.
    Stationary,
}

impl Kind {
    /// Parses `"type2"` or `"stationary"`.
    pub fn parse(name: &str) -> Result<Self> {
        match name {
            "type2" => Ok(Kind::TypeII),
            "stationary" => Ok(Kind::Stationary),
            other => Err(Error::invalid(
                "kind",
                format!("expected 'type2' or 'stationary', got {other:?}"),
            )),
        }
    }
}

/// `rows` independent ARFIMA(0, d, 0) series of length `n` with innovation s.d. `sigma`, as a
/// C-contiguous `(rows × n)` array (see the module docs for both kinds and reproducibility).
pub fn arfima(
    n: usize,
    d: f64,
    sigma: f64,
    rows: usize,
    seed: u64,
    kind: Kind,
) -> Result<Vec<f64>> {
    if n < 2 {
        return Err(Error::TooShort {
            name: "n",
            needed: 2,
            got: n,
        });
    }
    if rows == 0 {
        return Err(Error::invalid("size", "must be at least 1"));
    }
    if !d.is_finite() {
        return Err(Error::invalid("d", format!("must be finite, got {d}")));
    }
    crate::validate::positive("sigma", sigma)?;
    // A size too large to allocate is named after the larger of its two factors.
    let name = if rows > n { "size" } else { "n" };
    let total = crate::validate::product(name, n, rows)?;
    // Innovations, output and the transform buffers of about twice the length.
    crate::validate::allocatable::<f64>(name, crate::validate::product(name, total, 4)?)?;
    match kind {
        Kind::TypeII => {
            let mut w = vec![0.0; total];
            NormalStream::new(seed).fill(&mut w);
            for v in &mut w {
                *v *= sigma;
            }
            let mut out = vec![0.0; total];
            diff_rows_into(&w, n, -d, Method::Auto, &mut out)?;
            Ok(out)
        }
        Kind::Stationary => stationary(n, d, sigma, rows, seed),
    }
}

/// Autocovariances `γ(0..lags)` of the stationary ARFIMA(0, d, 0) with innovation s.d. `sigma`
/// (`|d| < ½`).
pub fn autocovariance(d: f64, sigma: f64, lags: usize) -> Result<Vec<f64>> {
    if !(d.is_finite() && d.abs() < 0.5) {
        return Err(Error::invalid(
            "d",
            format!("the stationary ARFIMA(0, d, 0) needs |d| < 0.5, got {d}"),
        ));
    }
    crate::validate::positive("sigma", sigma)?;
    let mut g = Vec::with_capacity(lags);
    // Γ(1 − 2d)/Γ(1 − d)² (exactly 1 for white noise, where Lanczos would be off by an ulp).
    let ratio = if d == 0.0 {
        1.0
    } else {
        // Γ(1 − 2d)/Γ(1 − d)²; both arguments are positive for |d| < ½.
        (ln_gamma(1.0 - 2.0 * d) - 2.0 * ln_gamma(1.0 - d)).exp()
    };
    let mut current = sigma * sigma * ratio;
    for k in 0..lags {
        if k > 0 {
            let kf = k as f64;
            current *= (kf - 1.0 + d) / (kf - d);
        }
        g.push(current);
    }
    Ok(g)
}

/// Square roots of the scaled circulant eigenvalues, `√(λ_k/M)` for `k = 0..=m`.
fn embedding(n: usize, d: f64, sigma: f64) -> Result<(usize, Vec<f64>)> {
    let big_m = convolve::fast_even_len(2 * (n - 1));
    let half = big_m / 2;
    let gam = autocovariance(d, sigma, half + 1)?;
    let mut c: Vec<f64> = (0..big_m).map(|j| gam[j.min(big_m - j)]).collect();
    let (fft, _) = convolve::plans(big_m);
    let mut spec = fft.make_output_vec();
    fft.process(&mut c, &mut spec)
        .expect("FFT buffer lengths come from the plan");
    let lmax = spec.iter().fold(0.0_f64, |m, z| m.max(z.re.abs()));
    let mut roots = Vec::with_capacity(half + 1);
    for (k, z) in spec.iter().enumerate() {
        if z.re < -1e-10 * lmax {
            return Err(Error::Singular {
                reason: format!(
                    "circulant embedding of the ARFIMA(0, {d}, 0) autocovariance has a negative \
                     eigenvalue {:.3e} at k = {k}",
                    z.re
                ),
            });
        }
        roots.push((z.re.max(0.0) / big_m as f64).sqrt());
    }
    Ok((big_m, roots))
}

fn stationary(n: usize, d: f64, sigma: f64, rows: usize, seed: u64) -> Result<Vec<f64>> {
    let (big_m, roots) = embedding(n, d, sigma)?;
    let mut normals = vec![0.0; big_m * rows];
    NormalStream::new(seed).fill(&mut normals);
    let (_, inverse) = convolve::plans(big_m);
    let mut out = vec![0.0; n * rows];
    out.par_chunks_mut(n)
        .zip(normals.par_chunks(big_m))
        .for_each_init(
            || {
                (
                    inverse.make_input_vec(),
                    inverse.make_output_vec(),
                    inverse.make_scratch_vec(),
                )
            },
            |(spec, real, scratch), (o, xi)| {
                synthesise(&roots, xi, spec);
                inverse
                    .process_with_scratch(spec, real, scratch)
                    .expect("FFT buffer lengths come from the plan");
                o.copy_from_slice(&real[..n]);
            },
        );
    Ok(out)
}

/// The Hermitian half-spectrum `Z_0..Z_m` from `M` standard normals.
fn synthesise(roots: &[f64], xi: &[f64], spec: &mut [Complex<f64>]) {
    let half = roots.len() - 1;
    let r2 = std::f64::consts::FRAC_1_SQRT_2;
    spec[0] = Complex::new(roots[0] * xi[0], 0.0);
    spec[half] = Complex::new(roots[half] * xi[1], 0.0);
    for k in 1..half {
        let s = roots[k] * r2;
        spec[k] = Complex::new(s * xi[2 * k], s * xi[2 * k + 1]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use realfft::RealFftPlanner;

    #[test]
    fn autocovariance_of_white_noise_and_of_d_quarter() {
        assert_eq!(autocovariance(0.0, 2.0, 3).unwrap(), vec![4.0, 0.0, 0.0]);
        let g = autocovariance(0.25, 1.0, 3).unwrap();
        // γ(0) = Γ(½)/Γ(¾)², ρ(1) = d/(1 − d) = 1/3.
        let g0 = std::f64::consts::PI.sqrt() / 1.225_416_702_465_177_6_f64.powi(2);
        assert!((g[0] - g0).abs() < 1e-14 * g0);
        assert!((g[1] / g[0] - 1.0 / 3.0).abs() < 1e-15);
        // ρ(2) = ρ(1)·(1 + d)/(2 − d)
        assert!((g[2] / g[1] - 1.25 / 1.75).abs() < 1e-15);
    }

    /// The generator is linear in the normals: build its matrix A column by column and check
    /// A·Aᵀ = Toeplitz(γ), the exactness claim of Davies–Harte.
    #[test]
    fn circulant_embedding_has_the_exact_covariance() {
        for &(n, d) in &[(20usize, 0.45), (33, -0.3), (2, 0.1)] {
            let (big_m, roots) = embedding(n, d, 1.3).unwrap();
            let mut planner = RealFftPlanner::<f64>::new();
            let inv = planner.plan_fft_inverse(big_m);
            let mut cols = Vec::new();
            for j in 0..big_m {
                let mut xi = vec![0.0; big_m];
                xi[j] = 1.0;
                let mut spec = inv.make_input_vec();
                let mut real = inv.make_output_vec();
                synthesise(&roots, &xi, &mut spec);
                inv.process(&mut spec, &mut real).unwrap();
                cols.push(real[..n].to_vec());
            }
            let gam = autocovariance(d, 1.3, n).unwrap();
            for t in 0..n {
                for s in 0..n {
                    let cov: f64 = cols.iter().map(|c| c[t] * c[s]).sum();
                    let want = gam[t.abs_diff(s)];
                    assert!(
                        (cov - want).abs() < 1e-12 * gam[0],
                        "n {n} d {d} t {t} s {s}"
                    );
                }
            }
        }
    }

    #[test]
    fn type_two_is_integrated_white_noise_and_reproducible() {
        let x = arfima(50, 0.5, 2.0, 3, 9, Kind::TypeII).unwrap();
        assert_eq!(x, arfima(50, 0.5, 2.0, 3, 9, Kind::TypeII).unwrap());
        let w = crate::random::scaled_normal_vec(150, 2.0, 9);
        let back = crate::fractional::diff_rows(&x, 50, 0.5, Method::Direct).unwrap();
        for (a, b) in back.iter().zip(&w) {
            assert!((a - b).abs() < 1e-12);
        }
        let single = arfima(50, 0.5, 2.0, 1, 9, Kind::TypeII).unwrap();
        assert_eq!(&x[..50], &single[..]);
        let st = arfima(50, 0.2, 1.0, 2, 9, Kind::Stationary).unwrap();
        assert_eq!(
            &st[..50],
            &arfima(50, 0.2, 1.0, 1, 9, Kind::Stationary).unwrap()[..]
        );
    }

    #[test]
    fn bad_parameters() {
        assert!(matches!(
            arfima(1, 0.3, 1.0, 1, 0, Kind::TypeII),
            Err(Error::TooShort { name: "n", .. })
        ));
        assert!(matches!(
            arfima(10, 0.5, 1.0, 1, 0, Kind::Stationary),
            Err(Error::InvalidParameter { name: "d", .. })
        ));
        assert!(matches!(
            arfima(10, f64::NAN, 1.0, 1, 0, Kind::TypeII),
            Err(Error::InvalidParameter { name: "d", .. })
        ));
        assert!(matches!(
            arfima(10, 0.2, 0.0, 1, 0, Kind::TypeII),
            Err(Error::InvalidParameter { name: "sigma", .. })
        ));
        assert!(matches!(
            arfima(10, 0.2, 1.0, 0, 0, Kind::TypeII),
            Err(Error::InvalidParameter { name: "size", .. })
        ));
    }
}
