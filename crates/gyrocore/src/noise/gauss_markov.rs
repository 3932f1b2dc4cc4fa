//! First-order Gauss–Markov (exponentially correlated) rate noise as a model term.
//!
//! A stationary process with variance `q²` and correlation time `T` has the autocovariance
//! `R(t) = q² e^{−|t|/T}` and the two-sided PSD `S(f) = 2q²T / (1 + (2π f T)²)`. Its angle
//! increment over `t` has the variance `V(t) = 2q²T (t − T(1 − e^{−t/T}))`, and the Allan
//! variance follows from `σ²(τ) = (4V(τ) − V(2τ)) / (2τ²)`:
//!
//! ```text
//! σ²(τ) = (q²T²/τ²) · (2x − 3 + 4e^{−x} − e^{−2x}),   x = τ/T
//!       = (2q²T/τ) · [1 − (T/2τ)(3 − 4e^{−τ/T} + e^{−2τ/T})]
//! ```
//!
//! (IEEE Std 952-1997 Annex C, "exponentially correlated noise"; the limits are white rate noise
//! `N² = 2q²T` for `τ ≫ T` and a rate random walk `K² = 2q²/T` for `τ ≪ T`.) The bracket
//! `f(x) = 2x − 3 + 4e^{−x} − e^{−2x}` cancels to `2x³/3 − x⁴/2 + …` for small `x`, so it is
//! evaluated by its power series `Σ_{n≥3} (−1)ⁿ (4 − 2ⁿ) xⁿ/n!` below `x = 0.5` (full precision
//! in 30 terms) and directly above.
//!
//! The curve peaks at `τ ≈ 1.89 T` with `σ ≈ 0.618 q`. The sampled process (period `t0`) is the
//! AR(1) `b_{k+1} = φ b_k + e_k`, `φ = e^{−t0/T}`, `Var e = q²(1 − φ²)`; its Allan variance of
//! sample means equals the continuous formula up to `O((t0/τ)²)` relative, which is negligible
//! where the term is visible (`τ ≳ T/10`) when `T ≫ t0`.

use crate::{Error, Result, validate};

/// `f(x) = 2x − 3 + 4e^{−x} − e^{−2x}` without cancellation.
fn bracket(x: f64) -> f64 {
    if x < 0.5 {
        // Σ_{n≥3} (−1)ⁿ (4 − 2ⁿ) xⁿ / n!
        let mut term = x * x * x / 6.0; // xⁿ/n! at n = 3
        let mut pow2 = 8.0;
        let mut sum = 0.0;
        for n in 3..40 {
            let sign = if n % 2 == 0 { 1.0 } else { -1.0 };
            let add = sign * (4.0 - pow2) * term;
            sum += add;
            if add.abs() <= 1e-17 * sum.abs() {
                break;
            }
            pow2 *= 2.0;
            term *= x / f64::from(n + 1);
        }
        sum
    } else {
        2.0 * x - 3.0 + 4.0 * (-x).exp() - (-2.0 * x).exp()
    }
}

/// `f(x)/x²` without cancellation, over- or underflow: `Σ_{n≥3} (−1)ⁿ (4 − 2ⁿ) x^{n−2}/n!`
/// (`≈ 2x/3`) below `x = 0.5`, else `(f(x)/x)/x` (`≈ 2/x` for large `x`).
fn bracket_over_x2(x: f64) -> f64 {
    if x < 0.5 {
        let mut term = x / 6.0; // x^{n−2}/n! at n = 3
        let mut pow2 = 8.0;
        let mut sum = 0.0;
        for n in 3..40 {
            let sign = if n % 2 == 0 { 1.0 } else { -1.0 };
            let add = sign * (4.0 - pow2) * term;
            sum += add;
            if add.abs() <= 1e-17 * sum.abs() {
                break;
            }
            pow2 *= 2.0;
            term *= x / f64::from(n + 1);
        }
        sum
    } else {
        bracket(x) / x / x
    }
}

/// Allan variance per unit `q²` of a Gauss–Markov process with correlation time `t` (s):
/// `(T²/τ²)·f(τ/T) = f(x)/x²`, evaluated without forming `T²/τ²` (which overflows for
/// `τ ≪ T`, e.g. τ = 1e-300 s, where the product was ∞·0 = NaN).
pub fn basis(correlation_time: f64, tau: f64) -> f64 {
    bracket_over_x2(tau / correlation_time)
}

/// Allan variance of a Gauss–Markov process of variance `q2` and correlation time `t`.
pub fn allan_variance(q2: f64, correlation_time: f64, tau: f64) -> f64 {
    q2 * basis(correlation_time, tau)
}

/// Allan variance at every `taus[i]` of a Gauss–Markov process of standard deviation `sigma`
/// and correlation time `correlation_time` (s), with the preconditions checked: `sigma` finite
/// and ≥ 0, `correlation_time` finite and > 0, every τ finite and > 0.
pub fn allan_variance_curve(sigma: f64, correlation_time: f64, taus: &[f64]) -> Result<Vec<f64>> {
    validate::non_negative("sigma", sigma)?;
    validate::positive("correlation_time", correlation_time)?;
    if let Some(bad) = taus.iter().find(|t| !(t.is_finite() && **t > 0.0)) {
        return Err(Error::invalid(
            "taus",
            format!("must be finite and > 0, got {bad}"),
        ));
    }
    let q2 = validate::finite_square("sigma", sigma)?;
    Ok(taus
        .iter()
        .map(|&tau| allan_variance(q2, correlation_time, tau))
        .collect())
}

/// Two-sided PSD `2q²T / (1 + (2π f T)²)` at frequency `f` (Hz).
pub fn psd(q2: f64, correlation_time: f64, f: f64) -> f64 {
    let w = std::f64::consts::TAU * f * correlation_time;
    2.0 * q2 * correlation_time / (1.0 + w * w)
}

/// `∂ basis / ∂ ln T` at `tau`, by a central difference (relative step 1e-5).
pub fn basis_dlog_t(correlation_time: f64, tau: f64) -> f64 {
    let h: f64 = 1e-5;
    let up = basis(correlation_time * h.exp(), tau);
    let down = basis(correlation_time * (-h).exp(), tau);
    (up - down) / (2.0 * h)
}

/// AR(1) coefficient and driving-noise standard deviation that sample a Gauss–Markov process
/// of standard deviation `sigma` and correlation time `t` at period `t0`:
/// `φ = e^{−t0/T}`, `σ_e = σ √(1 − φ²)`.
pub fn ar1_parameters(sigma: f64, correlation_time: f64, t0: f64) -> (f64, f64) {
    let phi = (-t0 / correlation_time).exp();
    // 1 − φ² = −expm1(−2 t0/T) without cancellation.
    let one_minus = -(-2.0 * t0 / correlation_time).exp_m1();
    (phi, sigma * one_minus.sqrt())
}

/// [`allan_variance`] of each component `(q², T)` at `taus`: one curve per component.
pub fn allan_variance_curves(components: &[(f64, f64)], taus: &[f64]) -> Vec<Vec<f64>> {
    components
        .iter()
        .map(|&(q2, t)| taus.iter().map(|&tau| allan_variance(q2, t, tau)).collect())
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn basis_is_finite_at_extreme_ratios() {
        // Issue 27: τ = 1e-300 with T = 10 was (T²/τ²)·f(x) = ∞·0 = NaN. Limits: 2x/3 (rate
        // random walk, x = τ/T → 0) and 2/x (white rate, x → ∞).
        for (tau, want) in [(1e-300, 2.0 / 3.0 * 1e-301), (1e300, 2.0 * 1e-299)] {
            let b = basis(10.0, tau);
            assert!((b / want - 1.0).abs() < 1e-12, "tau = {tau}: {b} vs {want}");
        }
        // continuous across the switch of evaluation at x = 0.5
        let below = basis(1.0, 0.5 - 1e-12);
        let above = basis(1.0, 0.5);
        assert!((below / above - 1.0).abs() < 1e-9);
    }

    #[test]
    fn curve_checks_its_arguments_and_matches_the_pointwise_formula() {
        let taus = [0.1, 1.0, 10.0];
        let got = allan_variance_curve(1.5, 2.0, &taus).unwrap();
        for (g, &tau) in got.iter().zip(&taus) {
            assert_eq!(*g, allan_variance(2.25, 2.0, tau));
        }
        for (sigma, t, taus, name) in [
            (-1.0, 1.0, &[1.0][..], "sigma"),
            (f64::NAN, 1.0, &[1.0][..], "sigma"),
            (1.0, 0.0, &[1.0][..], "correlation_time"),
            (1.0, 1.0, &[1.0, 0.0][..], "taus"),
            (1.0, 1.0, &[f64::INFINITY][..], "taus"),
        ] {
            let err = allan_variance_curve(sigma, t, taus)
                .unwrap_err()
                .to_string();
            assert!(err.contains(name), "{err}");
        }
    }

    /// Numeric integration of the PSD against the Allan transfer function
    /// `σ²(τ) = 4 ∫₀^∞ S(f) sin⁴(π f τ)/(π f τ)² df` (an independent route to the closed form).
    fn integrate(q2: f64, t: f64, tau: f64) -> f64 {
        // Substitute u = ln f; fine grid over 14 decades around 1/τ.
        let lo = (1e-7 / tau).ln();
        let hi = (1e7 / tau).ln();
        let steps = 400_000;
        let h = (hi - lo) / f64::from(steps);
        let mut sum = 0.0;
        for s in 0..=steps {
            let f = (lo + f64::from(s) * h).exp();
            let x = std::f64::consts::PI * f * tau;
            let g = if x > 1e3 {
                // Average of sin⁴ over the fast oscillation: 3/8.
                0.375 / (x * x)
            } else {
                x.sin().powi(4) / (x * x)
            };
            let w = if s == 0 || s == steps { 0.5 } else { 1.0 };
            sum += w * 4.0 * psd(q2, t, f) * g * f * h;
        }
        sum
    }

    #[test]
    fn closed_form_matches_psd_integral() {
        for &(t, tau) in &[
            (1.0, 0.01),
            (1.0, 0.3),
            (1.0, 1.0),
            (1.0, 2.0),
            (5.0, 300.0),
        ] {
            let closed = allan_variance(2.0, t, tau);
            let numeric = integrate(2.0, t, tau);
            // The averaged tail (3/8 beyond x = 1000) and the grid give < 1e-4 relative.
            assert!(
                (closed / numeric - 1.0).abs() < 1e-4,
                "T={t} τ={tau}: {closed} vs {numeric}"
            );
        }
    }

    #[test]
    fn limits_and_series_switch() {
        let (q2, t) = (3.0, 2.0);
        // τ ≫ T: white noise N² = 2q²T.
        let tau = 1e6;
        assert!((allan_variance(q2, t, tau) * tau / (2.0 * q2 * t) - 1.0).abs() < 1e-5);
        // τ ≪ T: random walk K²τ/3 with K² = 2q²/T.
        let tau = 1e-6;
        assert!((allan_variance(q2, t, tau) / (2.0 * q2 / t * tau / 3.0) - 1.0).abs() < 1e-5);
        // Continuity where the series hands over to the direct formula.
        let a = bracket(0.5 - 1e-12);
        let b = bracket(0.5 + 1e-12);
        assert!((a / b - 1.0).abs() < 1e-10);
        // Peak near τ = 1.89 T with σ ≈ 0.618 q.
        let (best_tau, best) = (1..4000)
            .map(|k| f64::from(k) * 0.001 * t)
            .map(|tau| (tau, allan_variance(1.0, t, tau)))
            .fold((0.0, 0.0), |a, b| if b.1 > a.1 { b } else { a });
        assert!((best_tau / t - 1.89).abs() < 0.01, "{best_tau}");
        assert!((best.sqrt() - 0.618).abs() < 0.002, "{best}");
    }

    #[test]
    fn ar1_sampling() {
        let (phi, e) = ar1_parameters(2.0, 10.0, 0.01);
        assert!((phi - (-0.001f64).exp()).abs() < 1e-15);
        assert!((e * e / (1.0 - phi * phi) - 4.0).abs() < 1e-9);
    }

    #[test]
    fn curves_are_the_pointwise_variances() {
        let taus = [0.01, 1.0, 250.0];
        let curves = allan_variance_curves(&[(2.0, 5.0), (1e-3, 0.1)], &taus);
        assert_eq!(curves.len(), 2);
        for (c, (q2, t)) in curves.iter().zip([(2.0, 5.0), (1e-3, 0.1)]) {
            let expected: Vec<f64> = taus.iter().map(|&tau| allan_variance(q2, t, tau)).collect();
            assert_eq!(*c, expected);
        }
        assert!(allan_variance_curves(&[], &taus).is_empty());
    }
}
