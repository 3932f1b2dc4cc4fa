//! Fractional differencing and integration, ARFIMA(0, d, 0) simulation and exact local Whittle
//! estimation of `d` (SPEC §4, Hosking 1981, \[BP\] eq. 3 and §III).
//!
//! The type-II (truncated at the first sample) fractional difference is
//!
//! ```text
//! (Δ^d x)_k = Σ_{i=0}^{k} π_{k−i}(d) x_i,   π_0 = 1,   π_l = π_{l−1}·(l − 1 − d)/l
//! ```
//!
//! (\[BP\] eq. 3 is misprinted: read literally it expands `(1 + B)^{−d}`; this is the consistent
//! reading, see SPEC §4). Fractional integration is `Δ^{−d}` with weights `ψ_l = π_l(−d)`. As
//! lower-triangular Toeplitz operators `Δ^{d}Δ^{−d} = I` exactly (a power-series identity), for
//! every real `d`.
//!
//! Evaluation ([`convolve`]): direct summation (`O(n·K)`, `K` the number of non-zero weights:
//! `d + 1` for a non-negative integer `d`, else `n`) or FFT convolution (`O(n log n)`), chosen
//! from the operation counts; both agree to ~1e-13 relative to the largest output. Integer `d ≥ 0`
//! always takes the direct path with the `d + 1` exact integer weights, so integer data give
//! exact integer differences.
//!
//! Submodules: [`arfima`] (type-II and stationary ARFIMA(0, d, 0) generators), [`elw`] (exact
//! local Whittle estimator of `d`, Shimotsu & Phillips 2005, with Shimotsu's 2010 level
//! correction).

pub mod arfima;
pub mod convolve;
pub mod elw;

use rayon::prelude::*;

use convolve::CausalConvolution;
pub use convolve::Method;

use crate::validate;
use crate::{Error, Result};

/// The fractional-difference weights `π_0..π_{n−1}` of `(1 − B)^d` by the product recursion.
///
/// The recursion `π_l = π_{l−1}·(l − 1 − d)/l` is stable (no Gamma functions of large
/// arguments) and gives exact zeros for non-negative integer `d` beyond lag `d`.
/// Integration weights are `weights(-d, n)`.
pub fn weights(d: f64, n: usize) -> Result<Vec<f64>> {
    if !d.is_finite() {
        return Err(Error::invalid("d", format!("must be finite, got {d}")));
    }
    validate::allocatable::<f64>("n", n)?;
    let mut w = Vec::with_capacity(n);
    let mut current = 1.0_f64;
    for l in 0..n {
        if l > 0 {
            current *= (l as f64 - 1.0 - d) / l as f64;
            if current == 0.0 {
                current = 0.0; // +0, not −0, past the last lag of an integer order
            }
            if !current.is_finite() {
                // |π_l| grows like |d|^l / l!: large orders overflow float64 within a few
                // hundred lags, and every result would be inf or NaN.
                return Err(Error::invalid(
                    "d",
                    format!(
                        "|d| = {} is too large for {n} lags: the weight of lag {l} of (1 − B)^d \
                         overflows float64",
                        d.abs()
                    ),
                ));
            }
        }
        w.push(current);
    }
    Ok(w)
}

/// The weights that can be non-zero: `d + 1` of them for a non-negative integer `d`, else `n`.
fn kernel(d: f64, n: usize) -> Result<Vec<f64>> {
    let k = if d >= 0.0 && d.fract() == 0.0 && d < n as f64 {
        d as usize + 1
    } else {
        n
    };
    weights(d, k)
}

/// `(Δ^d x)` of one series (method chosen automatically).
pub fn diff(x: &[f64], d: f64) -> Result<Vec<f64>> {
    diff_rows(x, x.len(), d, Method::Auto)
}

/// `(Δ^{−d} w)`, the type-II fractional integral of one series (method chosen automatically).
pub fn integrate(w: &[f64], d: f64) -> Result<Vec<f64>> {
    integrate_rows(w, w.len(), d, Method::Auto)
}

/// `Δ^d` applied to each row of a C-contiguous `(rows × n)` array; returns the same layout.
pub fn diff_rows(data: &[f64], n: usize, d: f64, method: Method) -> Result<Vec<f64>> {
    let mut out = vec![0.0; data.len()];
    diff_rows_into(data, n, d, method, &mut out)?;
    Ok(out)
}

/// `Δ^{−d}` applied to each row of a C-contiguous `(rows × n)` array; returns the same layout.
pub fn integrate_rows(data: &[f64], n: usize, d: f64, method: Method) -> Result<Vec<f64>> {
    let mut out = vec![0.0; data.len()];
    apply_rows_into("w", data, n, d, -1.0, method, &mut out)?;
    Ok(out)
}

/// [`diff_rows`] writing into `out` (same length as `data`); rows are processed in parallel.
pub fn diff_rows_into(
    data: &[f64],
    n: usize,
    d: f64,
    method: Method,
    out: &mut [f64],
) -> Result<()> {
    apply_rows_into("x", data, n, d, 1.0, method, out)
}

/// `Δ^{sign·d}` by rows; `name` is the data argument's name in error messages.
fn apply_rows_into(
    name: &'static str,
    data: &[f64],
    n: usize,
    d: f64,
    sign: f64,
    method: Method,
    out: &mut [f64],
) -> Result<()> {
    if !d.is_finite() {
        return Err(Error::invalid("d", format!("must be finite, got {d}")));
    }
    check_rows(name, data, n)?;
    if out.len() != data.len() {
        return Err(Error::ShapeMismatch {
            name: "out",
            reason: format!(
                "length {} differs from the data length {}",
                out.len(),
                data.len()
            ),
        });
    }
    validate::finite(name, data)?;
    let kernel = kernel(sign * d, n)?;
    if data.len() == n {
        // One series: overlap the kernel's and the data's transforms instead.
        CausalConvolution::new_applied(kernel, method, data, out);
    } else {
        let conv = CausalConvolution::new(kernel, n, method);
        out.par_chunks_mut(n).zip(data.par_chunks(n)).for_each_init(
            || conv.scratch(),
            |scratch, (o, x)| conv.apply_into(x, o, scratch),
        );
    }
    // Finite data and finite weights can still sum beyond float64 (large data, large |d|).
    if validate::finite("out", out).is_err() {
        return Err(Error::invalid(
            "d",
            format!("the result of order {d} on this {name} overflows float64"),
        ));
    }
    Ok(())
}

/// Checks a `(rows × n)` layout: `n ≥ 1`, at least one row, whole rows.
pub(crate) fn check_rows(name: &'static str, data: &[f64], n: usize) -> Result<()> {
    validate::min_len(name, n, 1)?;
    validate::min_len(name, data.len(), 1)?;
    if data.len() % n != 0 {
        return Err(Error::ShapeMismatch {
            name,
            reason: format!("{} values do not form rows of length {n}", data.len()),
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn huge_orders_are_errors_naming_d() {
        let x: Vec<f64> = (0..1000).map(|i| (i as f64 * 0.37).sin()).collect();
        for d in [1e6, -1e6, 5e3 + 0.5] {
            match diff(&x, d) {
                Err(Error::InvalidParameter { name: "d", .. }) => {}
                other => panic!("d = {d}: expected an error naming d, got {other:?}"),
            }
        }
        // Large integer orders with few lags are exact and fine.
        assert_eq!(diff(&[1.0, 2.0, 4.0], 1e6).unwrap().len(), 3);
    }

    fn naive(x: &[f64], d: f64) -> Vec<f64> {
        let w = weights(d, x.len()).unwrap();
        (0..x.len())
            .map(|k| (0..=k).map(|i| w[k - i] * x[i]).sum())
            .collect()
    }

    #[test]
    fn first_difference_of_a_ramp() {
        assert_eq!(
            diff(&[0.0, 1.0, 2.0, 3.0, 4.0], 1.0).unwrap(),
            vec![0.0, 1.0, 1.0, 1.0, 1.0]
        );
    }

    #[test]
    fn integer_differences_are_exact_even_for_long_series() {
        let x: Vec<f64> = (0..5000_u32)
            .map(|i| f64::from((i * i) % 1013) - 500.0)
            .collect();
        let y = diff(&x, 2.0).unwrap();
        for k in 2..x.len() {
            assert_eq!(y[k], x[k] - 2.0 * x[k - 1] + x[k - 2]);
        }
        assert_eq!(y[0], x[0]);
        assert_eq!(y[1], x[1] - 2.0 * x[0]);
    }

    #[test]
    fn round_trip_and_methods_agree() {
        for &n in &[1usize, 2, 17, 300, 2500] {
            let x: Vec<f64> = (0..n)
                .map(|i| ((i * 7919) % 211) as f64 / 13.0 - 8.0)
                .collect();
            for &d in &[-0.7, 0.3, 0.5, 1.4] {
                let a = diff_rows(&x, n, d, Method::Direct).unwrap();
                let b = diff_rows(&x, n, d, Method::Fft).unwrap();
                let scale = a.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
                for (p, q) in a.iter().zip(&b) {
                    assert!((p - q).abs() <= 1e-12 * scale, "n {n} d {d}");
                }
                if n <= 300 {
                    let c = naive(&x, d);
                    for (p, q) in a.iter().zip(&c) {
                        assert!((p - q).abs() <= 1e-12 * scale);
                    }
                }
                let back = diff(&integrate(&x, d).unwrap(), d).unwrap();
                let xs = x.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
                for (p, q) in back.iter().zip(&x) {
                    assert!((p - q).abs() <= 1e-12 * xs, "round trip n {n} d {d}");
                }
            }
        }
    }

    #[test]
    fn rows_equal_loop_and_bad_input_is_reported() {
        let n = 64;
        let data: Vec<f64> = (0..3 * n).map(|i| (i as f64).sin()).collect();
        let all = diff_rows(&data, n, 0.4, Method::Auto).unwrap();
        for r in 0..3 {
            assert_eq!(
                &all[r * n..(r + 1) * n],
                &diff(&data[r * n..(r + 1) * n], 0.4).unwrap()[..]
            );
        }
        assert!(matches!(
            diff(&[1.0, f64::NAN], 0.5),
            Err(Error::NonFinite { index: 1, .. })
        ));
        assert!(matches!(
            diff(&[1.0], f64::INFINITY),
            Err(Error::InvalidParameter { name: "d", .. })
        ));
        assert!(matches!(diff(&[], 0.5), Err(Error::TooShort { .. })));
        assert!(matches!(
            diff_rows(&data, 5, 0.5, Method::Auto),
            Err(Error::ShapeMismatch { .. })
        ));
    }

    #[test]
    fn first_difference_weights() {
        assert_eq!(weights(1.0, 4).unwrap(), vec![1.0, -1.0, 0.0, 0.0]);
    }

    #[test]
    fn half_integration_weights_match_binomial() {
        // ψ_l = Γ(l + ½)/(Γ(½) l!) = (2l choose l)/4^l
        let psi = weights(-0.5, 6).unwrap();
        let exact = [1.0, 0.5, 0.375, 0.3125, 0.2734375, 0.24609375];
        for (a, b) in psi.iter().zip(exact) {
            assert!((a - b).abs() < 1e-15);
        }
    }
}
