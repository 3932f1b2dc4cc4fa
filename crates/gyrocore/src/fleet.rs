//! Fleet statistics: how one unit's noise coefficient compares with its fleet's, and whether
//! the unit-to-unit spread of a coefficient is real or within the estimates' uncertainties.
//!
//! **Robust z-score** of unit `i` with value `X_i` and 1σ uncertainty `u_i` among `n` units:
//!
//! ```text
//! m = median(X),   s = 1.482602·median|X − m|          (MAD scaled to a normal s.d.)
//! σ_fleet² = max(s² − median(u²), 0)                    (spread not explained by the estimates)
//! z_i = (X_i − m) / √(σ_fleet² + u_i² + (π/2)·s²/n)     ((π/2)s²/n: the variance of the median)
//! ```
//!
//! (Rousseeuw & Croux 1993 for the MAD's consistency factor `1/Φ⁻¹(3/4)`; the large-sample
//! variance of the median of a normal sample is `(π/2)σ²/n`, Kenney & Keeping 1962 §13.13.)
//! A zero denominator gives `z = 0` for a value equal to the median and `±∞` otherwise.
//!
//! **Homogeneity test** ("is the spread real?", Birge 1932; the PDG's scale factor): with the
//! weighted mean `X̄_w = Σ X_i/u_i² / Σ 1/u_i²`,
//!
//! ```text
//! χ² = Σ_i (X_i − X̄_w)²/u_i²  ~  χ²_{n−1} if all units had the same true value,
//! Birge ratio R_B = √(χ²/(n − 1)),   p = P(χ²_{n−1} > χ²)
//! ```
//!
//! over the units with a finite positive uncertainty. The spread is called real when
//! `p < α` **and** `R_B ≥ min_ratio`: the fit's uncertainties are themselves only right to
//! ~15 %, so a scatter slightly larger than them is not evidence however many units there are.

use crate::stats;
use crate::validate;
use crate::{Error, Result};

/// `1/Φ⁻¹(3/4)`: the MAD of a normal sample times this estimates its standard deviation.
pub const MAD_TO_SD: f64 = 1.482_602_218_505_602;

/// Median of `values` (a copy is sorted partially; NaN when empty).
pub fn median(values: &[f64]) -> f64 {
    stats::median_in_place(&mut values.to_vec())
}

/// Median and scaled MAD `1.482602·median|X − m|` of finite values.
fn median_spread(values: &[f64]) -> (f64, f64) {
    let m = median(values);
    let mut dev: Vec<f64> = values.iter().map(|v| (v - m).abs()).collect();
    (m, MAD_TO_SD * stats::median_in_place(&mut dev))
}

/// Robust z-scores of the units' values (module docs).
///
/// `uncertainties` are the 1σ uncertainties of the values; one that is not finite (unknown)
/// counts as 0.
///
/// # Errors
/// Different lengths ([`Error::ShapeMismatch`]); no value ([`Error::TooShort`]); a non-finite
/// value ([`Error::NonFinite`]).
pub fn robust_z(values: &[f64], uncertainties: &[f64]) -> Result<Vec<f64>> {
    check(values, uncertainties)?;
    let u2: Vec<f64> = uncertainties
        .iter()
        .map(|&u| if u.is_finite() { u * u } else { 0.0 })
        .collect();
    let (m, s) = median_spread(values);
    let fleet_var = (s * s - median(&u2)).max(0.0);
    let median_var = std::f64::consts::FRAC_PI_2 * s * s / values.len() as f64;
    Ok(values
        .iter()
        .zip(&u2)
        .map(|(&x, &u2)| {
            let denom = (fleet_var + u2 + median_var).sqrt();
            let dev = x - m;
            if denom > 0.0 {
                dev / denom
            } else if dev == 0.0 {
                0.0
            } else {
                f64::INFINITY.copysign(dev)
            }
        })
        .collect())
}

fn check(values: &[f64], uncertainties: &[f64]) -> Result<()> {
    if values.len() != uncertainties.len() {
        return Err(Error::ShapeMismatch {
            name: "uncertainties",
            reason: format!(
                "{} uncertainties for {} values",
                uncertainties.len(),
                values.len()
            ),
        });
    }
    validate::min_len("values", values.len(), 1)?;
    validate::finite("values", values)
}

/// The statistics of one coefficient over the units that have it (see [`spread`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spread {
    /// Median of the values.
    pub median: f64,
    /// Scaled MAD `1.482602·median|X − m|`.
    pub spread: f64,
    /// RMS of the finite positive uncertainties (NaN if none).
    pub mean_uncertainty: f64,
    /// `√max(spread² − mean_uncertainty², 0)` (NaN without uncertainties).
    pub intrinsic_spread: f64,
    /// Homogeneity statistic `Σ (X_i − X̄_w)²/u_i²` (NaN with fewer than two weighted units).
    pub chi2: f64,
    /// Degrees of freedom `n_w − 1` (`None` with fewer than two weighted units).
    pub dof: Option<usize>,
    /// Birge ratio `√(χ²/dof)`.
    pub birge_ratio: f64,
    /// `P(χ²_dof > χ²)`.
    pub p_value: f64,
    /// `p < alpha` and Birge ratio `≥ min_ratio` (`None` without a test).
    pub real: Option<bool>,
}

/// The levels of the "is the spread real?" test of [`spread`] (module docs): the significance
/// level `alpha` and the smallest Birge ratio `min_ratio` that counts as a real spread.
///
/// Checked once, when built ([`SpreadTest::new`]): a caller that tests many coefficients with
/// the same levels (the fleet summary, one test per axis and term) builds one and refuses bad
/// levels before any work, and [`spread`] cannot be given unchecked ones.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpreadTest {
    alpha: f64,
    min_ratio: f64,
}

impl SpreadTest {
    /// The test at level `alpha` with the Birge-ratio floor `min_ratio`.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming `alpha` unless it lies strictly between 0 and 1
    /// ([`validate::probability`]), or naming `min_ratio` unless it is finite and > 0
    /// ([`validate::positive`]).
    pub fn new(alpha: f64, min_ratio: f64) -> Result<Self> {
        validate::probability("alpha", alpha)?;
        validate::positive("min_ratio", min_ratio)?;
        Ok(Self { alpha, min_ratio })
    }

    /// The significance level, in (0, 1).
    #[must_use]
    pub fn alpha(&self) -> f64 {
        self.alpha
    }

    /// The smallest Birge ratio of a real spread, finite and > 0.
    #[must_use]
    pub fn min_ratio(&self) -> f64 {
        self.min_ratio
    }
}

/// Median, spread, mean uncertainty and the homogeneity test of one coefficient over a fleet
/// (module docs), at the levels of `test`. Units whose uncertainty is not finite and positive
/// take part in the median and spread but not in the weighted test.
///
/// # Errors
/// As [`robust_z`] (the levels were checked when `test` was built).
pub fn spread(values: &[f64], uncertainties: &[f64], test: SpreadTest) -> Result<Spread> {
    check(values, uncertainties)?;
    let (median, spread) = median_spread(values);
    let weighted: Vec<(f64, f64)> = values
        .iter()
        .zip(uncertainties)
        .filter(|(_, u)| u.is_finite() && **u > 0.0)
        .map(|(&x, &u)| (x, 1.0 / (u * u)))
        .collect();
    let mean_uncertainty = if weighted.is_empty() {
        f64::NAN
    } else {
        let u2 = validate::neumaier_sum(
            uncertainties
                .iter()
                .filter(|u| u.is_finite() && **u > 0.0)
                .map(|u| u * u),
        );
        (u2 / weighted.len() as f64).sqrt()
    };
    let intrinsic_spread = if mean_uncertainty.is_finite() {
        (spread * spread - mean_uncertainty * mean_uncertainty)
            .max(0.0)
            .sqrt()
    } else {
        f64::NAN
    };
    let mut out = Spread {
        median,
        spread,
        mean_uncertainty,
        intrinsic_spread,
        chi2: f64::NAN,
        dof: None,
        birge_ratio: f64::NAN,
        p_value: f64::NAN,
        real: None,
    };
    if weighted.len() >= 2 {
        let dof = weighted.len() - 1;
        let sw = validate::neumaier_sum(weighted.iter().map(|(_, w)| *w));
        let swx = validate::neumaier_sum(weighted.iter().map(|(x, w)| w * x));
        let mean = swx / sw;
        let chi2 =
            validate::neumaier_sum(weighted.iter().map(|(x, w)| w * (x - mean) * (x - mean)));
        let p = stats::chi2_sf(chi2, dof as f64)?;
        let ratio = (chi2 / dof as f64).sqrt();
        out.chi2 = chi2;
        out.dof = Some(dof);
        out.birge_ratio = ratio;
        out.p_value = p;
        out.real = Some(p < test.alpha && ratio >= test.min_ratio);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn median_matches_numpy_convention() {
        assert_eq!(median(&[3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median(&[4.0, 1.0, 3.0, 2.0]), 2.5);
        assert!(median(&[]).is_nan());
    }

    #[test]
    fn robust_z_by_hand() {
        // values 1..5 and 10: m = 3.5, |X − m| = 2.5 1.5 .5 .5 1.5 6.5 → MAD = 1.5.
        let x = [1.0, 2.0, 3.0, 4.0, 5.0, 10.0];
        let u = [0.0; 6];
        let z = robust_z(&x, &u).unwrap();
        let s = MAD_TO_SD * 1.5;
        let denom = (s * s + std::f64::consts::FRAC_PI_2 * s * s / 6.0).sqrt();
        assert!((z[5] - 6.5 / denom).abs() < 1e-14);
        assert!((z[0] + 2.5 / denom).abs() < 1e-14);
        // Unknown uncertainties count as zero.
        assert_eq!(robust_z(&x, &[f64::NAN; 6]).unwrap(), z);
        // All equal: z = 0 (zero denominator, zero deviation).
        assert_eq!(robust_z(&[2.0, 2.0, 2.0], &[0.0; 3]).unwrap(), vec![0.0; 3]);
        // Zero denominator with a deviation: ±inf.
        let z = robust_z(&[2.0, 2.0, 2.0, 2.0, 5.0], &[0.0; 5]).unwrap();
        assert_eq!(z[4], f64::INFINITY);
        assert!(robust_z(&[1.0, f64::NAN], &[0.0; 2]).is_err());
        assert!(robust_z(&[1.0], &[0.0; 2]).is_err());
    }

    #[test]
    fn homogeneity_by_hand() {
        let x = [1.0, 2.0, 4.0];
        let u = [1.0, 1.0, 2.0];
        let test = SpreadTest::new(0.05, 1.2).unwrap();
        let s = spread(&x, &u, test).unwrap();
        // weights 1, 1, 0.25: X̄_w = (1 + 2 + 1)/2.25 = 16/9.
        let m: f64 = 16.0 / 9.0;
        let chi2 = (1.0 - m).powi(2) + (2.0 - m).powi(2) + 0.25 * (4.0 - m).powi(2);
        assert!((s.chi2 - chi2).abs() < 1e-14);
        assert_eq!(s.dof, Some(2));
        assert!((s.birge_ratio - (chi2 / 2.0).sqrt()).abs() < 1e-14);
        // χ²₂ survival is exp(−x/2).
        assert!((s.p_value - (-chi2 / 2.0).exp()).abs() < 1e-14);
        assert_eq!(s.real, Some(false));
        assert!((s.mean_uncertainty - 2.0_f64.sqrt()).abs() < 1e-15);
        assert_eq!(s.median, 2.0);
        // One weighted unit: no test.
        let s = spread(&x, &[1.0, f64::NAN, 0.0], test).unwrap();
        assert_eq!(s.dof, None);
        assert!(s.chi2.is_nan());
        assert_eq!(s.real, None);
    }

    #[test]
    fn test_levels_are_checked_once_when_built() {
        for alpha in [0.0, 1.0, -0.1, 1.5, f64::NAN, f64::INFINITY] {
            let e = SpreadTest::new(alpha, 1.2).unwrap_err().to_string();
            assert!(e.contains("alpha must lie strictly between 0 and 1"), "{e}");
        }
        for ratio in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            let e = SpreadTest::new(0.05, ratio).unwrap_err().to_string();
            assert!(e.contains("min_ratio must be finite and > 0"), "{e}");
        }
        let t = SpreadTest::new(0.01, 1.2).unwrap();
        assert_eq!((t.alpha(), t.min_ratio()), (0.01, 1.2));
    }
}
