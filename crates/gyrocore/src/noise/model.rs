//! The five-term Allan-variance model and the simple EDF approximations used to weight fits.
//!
//! ```text
//! σ²(τ) = 3Q²/τ² + N²/τ + (0.664282·B)² + K²τ/3 + R²τ²/2
//! ```
//!
//! is linear in `c = (Q², N², B², K², R²)` with basis functions `g_j(τ)` ([`Term::basis`]).
//! Each term has a log-log slope of the Allan *deviation* (−1, −½, 0, +½, +1) and an IEEE-952
//! read-off time at which its asymptote equals the coefficient (√3, 1, —, 3, √2 s).

use crate::{Error, Result};

/// `√(2 ln 2 / π)`: the Allan-deviation plateau of flicker rate noise per unit `B`.
pub const FLICKER_FACTOR: f64 = 0.664_282_470_267_960_1;

/// One of the five IEEE-952 noise terms.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Term {
    /// Quantisation noise Q (angle unit).
    Quantization,
    /// Angle (velocity) random walk N.
    AngleRandomWalk,
    /// Bias instability B.
    BiasInstability,
    /// Rate random walk K.
    RateRandomWalk,
    /// Rate ramp R.
    RateRamp,
}

impl Term {
    /// All terms in model order (Q, N, B, K, R).
    pub const ALL: [Term; 5] = [
        Term::Quantization,
        Term::AngleRandomWalk,
        Term::BiasInstability,
        Term::RateRandomWalk,
        Term::RateRamp,
    ];

    /// Position in [`Term::ALL`].
    pub fn index(self) -> usize {
        match self {
            Term::Quantization => 0,
            Term::AngleRandomWalk => 1,
            Term::BiasInstability => 2,
            Term::RateRandomWalk => 3,
            Term::RateRamp => 4,
        }
    }

    /// The customary symbol ("Q", "N", "B", "K", "R").
    pub fn symbol(self) -> &'static str {
        ["Q", "N", "B", "K", "R"][self.index()]
    }

    /// Parses a symbol.
    pub fn parse(symbol: &str) -> Result<Self> {
        Term::ALL
            .into_iter()
            .find(|t| t.symbol() == symbol)
            .ok_or_else(|| {
                Error::invalid(
                    "terms",
                    format!("unknown term {symbol:?}; expected 'Q', 'N', 'B', 'K' or 'R'"),
                )
            })
    }

    /// `g(τ)`: the term's Allan variance per unit squared coefficient.
    pub fn basis(self, tau: f64) -> f64 {
        match self {
            Term::Quantization => 3.0 / (tau * tau),
            Term::AngleRandomWalk => 1.0 / tau,
            Term::BiasInstability => FLICKER_FACTOR * FLICKER_FACTOR,
            Term::RateRandomWalk => tau / 3.0,
            Term::RateRamp => tau * tau / 2.0,
        }
    }

    /// Log-log slope of the term's Allan *deviation*.
    pub fn slope(self) -> f64 {
        [-1.0, -0.5, 0.0, 0.5, 1.0][self.index()]
    }

    /// τ at which the deviation asymptote equals the coefficient (IEEE 952 read-off);
    /// `None` for B, which is read from the minimum.
    pub fn read_off_tau(self) -> Option<f64> {
        match self {
            Term::Quantization => Some(3f64.sqrt()),
            Term::AngleRandomWalk => Some(1.0),
            Term::BiasInstability => None,
            Term::RateRandomWalk => Some(3.0),
            Term::RateRamp => Some(2f64.sqrt()),
        }
    }

    /// Power-law exponent α of the rate PSD (S ∝ f^α) the term produces, as used by the EDF
    /// formulas (rate ramp has no stationary PSD; the random-walk formula stands in for it).
    pub fn alpha(self) -> i32 {
        [2, 0, -1, -2, -2][self.index()]
    }
}

/// Model variance `Σ_j c_j g_j(τ)` for squared coefficients `c` in [`Term::ALL`] order.
pub fn model_variance(c: &[f64; 5], tau: f64) -> f64 {
    Term::ALL.iter().map(|t| c[t.index()] * t.basis(tau)).sum()
}

/// The model's curves at `taus`: the total [`model_variance`] and each term's contribution
/// `c_j g_j(τ)`, in [`Term::ALL`] order.
///
/// `filter_time` is a sensor filter's correlation time `τ_c` (s, 0 for none; see
/// [`super::fit`](mod@super::fit), "Sensor filter"): the total then includes its `−3N²τ_c/τ²`,
/// which has no curve of its own. That law holds only beyond the filter's length: below 3τ_c,
/// where its white-noise part `N²/τ·(1 − 3τ_c/τ)` would be negative, the model is not valid and
/// the total is NaN (a plot then leaves a gap there instead of plunging towards zero).
///
/// Every τ must be finite and > 0 (the terms' `τ^-2 … τ^2` are NaN or infinite at τ ≤ 0), and
/// the squared coefficients `c` and `filter_time` finite and ≥ 0; a τ at which the model
/// variance overflows float64 is refused too, so the curves never hold infinity, nor NaN
/// other than the total's below 3τ_c.
pub fn model_curves(
    c: &[f64; 5],
    filter_time: f64,
    taus: &[f64],
) -> Result<(Vec<f64>, [Vec<f64>; 5])> {
    for (t, &v) in Term::ALL.iter().zip(c) {
        crate::validate::non_negative(["Q²", "N²", "B²", "K²", "R²"][t.index()], v)?;
    }
    crate::validate::non_negative("filter_time", filter_time)?;
    if let Some((i, bad)) = taus
        .iter()
        .enumerate()
        .find(|(_, t)| !(t.is_finite() && **t > 0.0))
    {
        return Err(Error::invalid(
            "taus",
            format!("must be finite and > 0, got taus[{i}] = {bad}"),
        ));
    }
    let filter = 3.0 * c[Term::AngleRandomWalk.index()] * filter_time;
    let total: Vec<f64> = taus
        .iter()
        .map(|&tau| {
            if filter > 0.0 && tau < 3.0 * filter_time {
                f64::NAN
            } else {
                (model_variance(c, tau) - filter / (tau * tau)).max(0.0)
            }
        })
        .collect();
    if let Some(i) = total.iter().position(|v| v.is_infinite()) {
        return Err(Error::invalid(
            "taus",
            format!(
                "the model variance overflows float64 at taus[{i}] = {:e} s",
                taus[i]
            ),
        ));
    }
    let parts = Term::ALL.map(|t| {
        taus.iter()
            .map(|&tau| c[t.index()] * t.basis(tau))
            .collect()
    });
    Ok((total, parts))
}

/// SP1065's simple EDF approximations for the overlapping Allan variance (Table 5, after
/// Howe, Allan & Barnes 1981) with `n_phase` angle samples at averaging factor `m` for
/// power-law noise α (rate PSD ∝ f^α):
///
/// | α | EDF |
/// |---|---|
/// | 2 (white angle) | `(N+1)(N−2m) / (2(N−m))` |
/// | 1 (flicker angle) | `exp(√(ln((N−1)/2m)·ln((2m+1)(N−1)/4)))` |
/// | 0 (white rate) | `(3(N−1)/(2m) − 2(N−2)/N) · 4m²/(4m²+5)` |
/// | −1 (flicker rate) | `2(N−2)/(2.3N−4.9)` for m = 1, else `5N²/(4m(N+3m))` |
/// | −2 (random-walk rate) | `(N−2)/m · ((N−1)² − 3m(N−1) + 4m²)/(N−3)²` |
///
/// Other α use the nearest formula. The result is clamped to at least 1 (the formulas can go
/// below one, or negative, at the largest m).
pub fn approximate_edf(n_phase: usize, m: usize, alpha: i32) -> f64 {
    let n = n_phase as f64;
    let mf = m as f64;
    let edf = match alpha.clamp(-2, 2) {
        2 => (n + 1.0) * (n - 2.0 * mf) / (2.0 * (n - mf)),
        1 => {
            let a = ((n - 1.0) / (2.0 * mf)).ln();
            let b = ((2.0 * mf + 1.0) * (n - 1.0) / 4.0).ln();
            if a > 0.0 && b > 0.0 {
                (a * b).sqrt().exp()
            } else {
                1.0
            }
        }
        0 => {
            (3.0 * (n - 1.0) / (2.0 * mf) - 2.0 * (n - 2.0) / n) * 4.0 * mf * mf
                / (4.0 * mf * mf + 5.0)
        }
        -1 => {
            if m == 1 {
                2.0 * (n - 2.0) / (2.3 * n - 4.9)
            } else {
                5.0 * n * n / (4.0 * mf * (n + 3.0 * mf))
            }
        }
        _ => {
            (n - 2.0) / mf * ((n - 1.0).powi(2) - 3.0 * mf * (n - 1.0) + 4.0 * mf * mf)
                / (n - 3.0).powi(2)
        }
    };
    if edf.is_finite() { edf.max(1.0) } else { 1.0 }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn model_curves_sum_to_the_total() {
        let c = [1e-6, 4e-4, 1e-5, 1e-7, 1e-9];
        let taus = [0.01, 0.3, 1.0, 17.0, 1e3];
        let (total, parts) = model_curves(&c, 0.0, &taus).unwrap();
        for (i, &tau) in taus.iter().enumerate() {
            assert_eq!(total[i], model_variance(&c, tau));
            let sum: f64 = parts.iter().map(|p| p[i]).sum();
            // Five positive terms summed in the same order: equal up to rounding.
            assert!((sum - total[i]).abs() <= 4.0 * f64::EPSILON * total[i]);
            assert_eq!(parts[2][i], c[2] * Term::BiasInstability.basis(tau));
        }
    }

    #[test]
    fn a_filter_lowers_the_total_only() {
        // −3N²τ_c/τ² on the total (the filter law), parts unchanged, NaN below 3τ_c.
        let c = [0.0, 1e-4, 1e-8, 0.0, 0.0];
        let taus = [0.001, 0.029, 0.03, 0.5, 10.0];
        let tc = 0.01;
        let (plain, parts) = model_curves(&c, 0.0, &taus).unwrap();
        let (total, with) = model_curves(&c, tc, &taus).unwrap();
        assert_eq!(parts, with);
        for (i, &tau) in taus.iter().enumerate().skip(2) {
            let law = (plain[i] - 3.0 * c[1] * tc / (tau * tau)).max(0.0);
            assert!((total[i] - law).abs() <= 1e-15 * plain[i], "{tau}");
        }
        assert!(total[0].is_nan() && total[1].is_nan());
        // No filter: the total is the plain sum everywhere, never NaN.
        assert!(plain.iter().all(|v| v.is_finite()));
        for bad in [-1e-3, f64::NAN, f64::INFINITY] {
            assert!(model_curves(&c, bad, &taus).is_err());
        }
    }

    #[test]
    fn model_curves_refuse_what_has_no_finite_value() {
        let c = [1e-6, 4e-4, 1e-5, 1e-7, 1e-9];
        for taus in [[0.0], [-1.0], [f64::NAN], [f64::INFINITY], [1e300]] {
            match model_curves(&c, 0.0, &taus) {
                Err(Error::InvalidParameter { name: "taus", .. }) => {}
                other => panic!("taus = {taus:?}: expected a taus error, got {other:?}"),
            }
        }
        let mut bad = c;
        bad[1] = f64::NAN;
        assert!(model_curves(&bad, 0.0, &[1.0]).is_err());
        let (total, _) = model_curves(&c, 0.0, &[1e-100, 1e100]).unwrap();
        assert!(total.iter().all(|v| v.is_finite()));
    }

    #[test]
    fn flicker_factor() {
        let f = (2.0 * std::f64::consts::LN_2 / std::f64::consts::PI).sqrt();
        assert!((FLICKER_FACTOR - f).abs() < 1e-16);
    }

    #[test]
    fn read_off_taus_recover_coefficients() {
        for t in Term::ALL {
            if let Some(tau) = t.read_off_tau() {
                assert!((t.basis(tau) - 1.0).abs() < 1e-15, "{t:?}");
            }
        }
    }

    #[test]
    fn edf_matches_allantools_edf_simple() {
        // allantools.edf_simple(N, m, alpha) evaluated in Python (same SP1065 formulas).
        let cases = [
            (1001, 1, 2, 500.499),
            (1001, 10, 0, 146.17678617678618),
            (1001, 10, -1, 121.48411736178467),
            (1001, 1, -1, 0.8696787673021678),
            (1001, 10, -2, 97.33189826546881),
            (1001, 10, 1, 326.6241874875244),
        ];
        for (n, m, a, expect) in cases {
            let got = approximate_edf(n, m, a);
            let expect = f64::max(expect, 1.0);
            assert!(
                (got - expect).abs() < 1e-6 * expect,
                "{n} {m} {a}: {got} vs {expect}"
            );
        }
    }
}
