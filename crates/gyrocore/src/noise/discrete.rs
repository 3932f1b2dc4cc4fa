//! Discrete-time (per-sample) equivalents of the continuous noise terms, and the datasheet
//! conventions that lead to the IEEE-952 coefficients, with the uncertainties carried through.
//!
//! **Discretisation** at period `Δt = 1/f` (Kalibr wiki "IMU Noise Model"; SPEC §1):
//!
//! ```text
//! σ_white = N/√Δt = N·√f        white rate noise (two-sided PSD N²) averaged over Δt
//! σ_walk  = K·√Δt = K/√f        one step of the rate random walk ḃ = w, E[w(t)w(s)] = K²δ(t−s)
//! φ = exp(−Δt/τ_c),  σ_drive = σ·√(1 − φ²)     first-order Gauss–Markov b_{k+1} = φ b_k + w_k
//! ```
//!
//! `1 − φ² = −expm1(−2Δt/τ_c)` is evaluated that way, so a correlation time far longer than the
//! sample period keeps its relative accuracy. Uncertainties: the linear maps scale them; `φ`'s
//! by the delta method `u(φ) = |∂φ/∂τ_c|·u(τ_c) = φ·Δt·u(τ_c)/τ_c²`; `σ_drive`'s scales with `σ`
//! (`τ_c`'s contribution is not propagated: its value is reported separately through `φ`).
//! Bias instability (flicker noise) has no exact finite-state discretisation and is not
//! converted.
//!
//! **Datasheet conventions** (SPEC §1; IEEE Std 952-1997 Annex C):
//!
//! ```text
//! N = nd/√2      a one-sided noise density nd (…/√Hz, most MEMS datasheets); two-sided: N = nd
//! B = σ_min/0.664282   the Allan-deviation minimum ("in-run bias stability") to the IEEE B
//! ```

use crate::noise::FLICKER_FACTOR;
use crate::validate;
use crate::{Error, Result};

/// A value with an optional 1σ uncertainty.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Estimate {
    /// The value.
    pub value: f64,
    /// Its standard uncertainty, if known.
    pub uncertainty: Option<f64>,
}

impl Estimate {
    fn scaled(value: f64, uncertainty: Option<f64>, factor: f64) -> Self {
        Self {
            value: value * factor,
            uncertainty: uncertainty.map(|u| u * factor),
        }
    }
}

fn check_term(name: &'static str, value: f64, uncertainty: Option<f64>) -> Result<()> {
    validate::non_negative(name, value)?;
    if let Some(u) = uncertainty {
        validate::non_negative("uncertainty", u)?;
    }
    Ok(())
}

/// The filter rate `rate` (Hz) if it is finite and > 0 with a finite period `1/rate`: the one
/// check of the rate for callers that discretise no term at all.
///
/// # Errors
/// [`Error::InvalidParameter`] naming `rate`.
pub fn rate(rate: f64) -> Result<f64> {
    validate::positive("rate", rate)?;
    if (1.0 / rate).is_finite() {
        Ok(rate)
    } else {
        Err(Error::invalid(
            "rate",
            format!("must be finite and > 0 with a finite period 1/rate, got {rate:e}"),
        ))
    }
}

/// `σ_white = N·√rate` (per-sample standard deviation of white rate noise with IEEE
/// coefficient `N`), with its uncertainty.
///
/// # Errors
/// `rate` not finite and > 0; `n` or its uncertainty negative or not finite.
pub fn white(n: f64, uncertainty: Option<f64>, rate: f64) -> Result<Estimate> {
    self::rate(rate)?;
    check_term("N", n, uncertainty)?;
    Ok(Estimate::scaled(n, uncertainty, rate.sqrt()))
}

/// `σ_walk = K/√rate` (standard deviation of one step of the rate random walk with IEEE
/// coefficient `K`), with its uncertainty.
///
/// # Errors
/// As [`white`].
pub fn random_walk(k: f64, uncertainty: Option<f64>, rate: f64) -> Result<Estimate> {
    self::rate(rate)?;
    check_term("K", k, uncertainty)?;
    Ok(Estimate::scaled(k, uncertainty, 1.0 / rate.sqrt()))
}

/// The exact discretisation of a first-order Gauss–Markov term.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GaussMarkovStep {
    /// `φ = exp(−Δt/τ_c)`, with the delta-method uncertainty from `τ_c`'s.
    pub phi: Estimate,
    /// Driving standard deviation `σ·√(1 − φ²)`, with the uncertainty from `σ`'s.
    pub driving_sigma: Estimate,
}

/// `b_{k+1} = φ·b_k + w_k` for a Gauss–Markov term of stationary standard deviation `sigma`
/// and correlation time `tau` (s), sampled at `rate` Hz (module docs).
///
/// # Errors
/// `rate` or `tau` not finite and > 0; `sigma` or an uncertainty negative or not finite.
pub fn gauss_markov(
    sigma: f64,
    sigma_uncertainty: Option<f64>,
    tau: f64,
    tau_uncertainty: Option<f64>,
    rate: f64,
) -> Result<GaussMarkovStep> {
    self::rate(rate)?;
    validate::positive("tau", tau)?;
    check_term("sigma", sigma, sigma_uncertainty)?;
    if let Some(u) = tau_uncertainty {
        validate::non_negative("uncertainty", u)?;
    }
    let dt = 1.0 / rate;
    let phi = (-dt / tau).exp();
    let drive = (-(-2.0 * dt / tau).exp_m1()).sqrt();
    Ok(GaussMarkovStep {
        phi: Estimate {
            value: phi,
            uncertainty: tau_uncertainty.map(|u| phi * dt * u / (tau * tau)),
        },
        driving_sigma: Estimate::scaled(sigma, sigma_uncertainty, drive),
    })
}

/// How a datasheet value per √Hz is read.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Density {
    /// One-sided PSD amplitude (datasheets): `N = nd/√2`.
    OneSided,
    /// Two-sided (Kalibr): the density is `N`.
    TwoSided,
}

impl Density {
    /// Parses `"one-sided"` or `"two-sided"`.
    pub fn parse(name: &str) -> Result<Self> {
        match name {
            "one-sided" => Ok(Self::OneSided),
            "two-sided" => Ok(Self::TwoSided),
            other => Err(Error::invalid(
                "density",
                format!("must be one of 'one-sided', 'two-sided'; got {other:?}"),
            )),
        }
    }
}

/// How a datasheet bias instability is read.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BiasReading {
    /// The value is the Allan-deviation minimum: `B = value/0.664282`.
    AllanMinimum,
    /// The value is the IEEE coefficient `B`.
    Coefficient,
}

impl BiasReading {
    /// Parses `"allan_minimum"` or `"coefficient"`.
    pub fn parse(name: &str) -> Result<Self> {
        match name {
            "allan_minimum" => Ok(Self::AllanMinimum),
            "coefficient" => Ok(Self::Coefficient),
            other => Err(Error::invalid(
                "bias_instability_is",
                format!("must be one of 'allan_minimum', 'coefficient'; got {other:?}"),
            )),
        }
    }
}

/// Which conversion [`datasheet_coefficient`] applied.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Conversion {
    /// A one-sided density divided by √2.
    OneSidedDensity,
    /// A two-sided density taken as is.
    TwoSidedDensity,
    /// An Allan-deviation minimum divided by the flicker factor 0.664282.
    AllanMinimum,
    /// The value already was the IEEE coefficient.
    Coefficient,
}

impl Conversion {
    /// A short name: `"one-sided density"`, `"two-sided density"`, `"allan minimum"`,
    /// `"coefficient"`.
    pub fn name(self) -> &'static str {
        match self {
            Self::OneSidedDensity => "one-sided density",
            Self::TwoSidedDensity => "two-sided density",
            Self::AllanMinimum => "allan minimum",
            Self::Coefficient => "coefficient",
        }
    }
}

/// The IEEE-952 coefficient of term `symbol` (`"Q"`, `"N"`, `"B"`, `"K"`, `"R"`) from a
/// datasheet `value` as written, times `unit_factor` (> 0) to the coefficient's unit (module
/// docs). `per_root_hz`: the value was given per √Hz (a density), which matters for `N` and `K`.
///
/// # Errors
/// `value` negative or not finite (named `value`), `unit_factor` not finite and > 0; an unknown
/// `symbol`.
pub fn datasheet_coefficient(
    value: f64,
    unit_factor: f64,
    symbol: &str,
    per_root_hz: bool,
    density: Density,
    bias: BiasReading,
) -> Result<(f64, Conversion)> {
    validate::non_negative("value", value)?;
    validate::positive("unit_factor", unit_factor)?;
    let value = value * unit_factor;
    match symbol {
        "N" | "K" if per_root_hz => Ok(match density {
            Density::OneSided => (
                value / std::f64::consts::SQRT_2,
                Conversion::OneSidedDensity,
            ),
            Density::TwoSided => (value, Conversion::TwoSidedDensity),
        }),
        "B" => Ok(match bias {
            BiasReading::AllanMinimum => (value / FLICKER_FACTOR, Conversion::AllanMinimum),
            BiasReading::Coefficient => (value, Conversion::Coefficient),
        }),
        "Q" | "N" | "K" | "R" => Ok((value, Conversion::Coefficient)),
        other => Err(Error::invalid(
            "symbol",
            format!("must be one of Q, N, B, K, R; got {other:?}"),
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn white_and_walk() {
        // 0.6 deg/√h = 0.01 deg/√s; at 100 Hz σ_white = 0.1 deg/s.
        let w = white(0.01, Some(0.001), 100.0).unwrap();
        assert!((w.value - 0.1).abs() < 1e-16);
        assert!((w.uncertainty.unwrap() - 0.01).abs() < 1e-17);
        let k = random_walk(0.5, None, 100.0).unwrap();
        assert!((k.value - 0.05).abs() < 1e-16);
        assert_eq!(k.uncertainty, None);
        assert!(white(0.01, None, 0.0).is_err());
        assert!(rate(1e-320).is_err());
        assert_eq!(rate(200.0).unwrap(), 200.0);
        assert!(white(-0.01, None, 1.0).is_err());
        assert!(random_walk(0.01, Some(f64::NAN), 1.0).is_err());
    }

    #[test]
    fn gauss_markov_exact_and_delta_method() {
        let g = gauss_markov(2.0, Some(0.2), 10.0, Some(1.0), 100.0).unwrap();
        let phi = (-0.001_f64).exp();
        assert!((g.phi.value - phi).abs() < 1e-16);
        assert!((g.phi.uncertainty.unwrap() - phi * 0.01 * 1.0 / 100.0).abs() < 1e-18);
        // σ√(1 − φ²) against the direct form (fine at this φ).
        let direct = 2.0 * (1.0 - phi * phi).sqrt();
        assert!((g.driving_sigma.value / direct - 1.0).abs() < 1e-12);
        assert!((g.driving_sigma.uncertainty.unwrap() / g.driving_sigma.value - 0.1).abs() < 1e-15);
        // τ_c ≫ Δt: the direct form loses digits, expm1 does not (1 − φ² ≈ 2Δt/τ_c).
        let g = gauss_markov(1.0, None, 1e9, None, 1e3).unwrap();
        let exact = (2.0e-12_f64 - 2.0e-24).sqrt();
        assert!((g.driving_sigma.value / exact - 1.0).abs() < 1e-15);
        // The derivative of φ against a central difference.
        let (tau, h) = (3.0, 1e-6);
        let num = (gauss_markov(1.0, None, tau + h, None, 10.0)
            .unwrap()
            .phi
            .value
            - gauss_markov(1.0, None, tau - h, None, 10.0)
                .unwrap()
                .phi
                .value)
            / (2.0 * h);
        let ana = gauss_markov(1.0, None, tau, Some(1.0), 10.0)
            .unwrap()
            .phi
            .uncertainty
            .unwrap();
        assert!((num / ana - 1.0).abs() < 1e-8);
        assert!(gauss_markov(1.0, None, 0.0, None, 10.0).is_err());
        assert!(gauss_markov(1.0, None, 1.0, None, -1.0).is_err());
    }

    #[test]
    fn datasheet_conventions() {
        // ADIS16470: 0.008 °/s/√Hz one-sided = 0.008/√2·60 = 0.3394 °/√h.
        let (n, c) = datasheet_coefficient(
            0.008,
            1.0,
            "N",
            true,
            Density::OneSided,
            BiasReading::AllanMinimum,
        )
        .unwrap();
        assert!((n * 60.0 - 0.339_411_254_969_542_8).abs() < 1e-15);
        assert_eq!(c, Conversion::OneSidedDensity);
        let (n, c) = datasheet_coefficient(
            0.008,
            1.0,
            "N",
            true,
            Density::TwoSided,
            BiasReading::AllanMinimum,
        )
        .unwrap();
        assert_eq!((n, c), (0.008, Conversion::TwoSidedDensity));
        // A random walk per √h is not a density: taken as is.
        let (k, c) = datasheet_coefficient(
            3.0,
            1.0,
            "K",
            false,
            Density::OneSided,
            BiasReading::AllanMinimum,
        )
        .unwrap();
        assert_eq!((k, c), (3.0, Conversion::Coefficient));
        let (b, c) = datasheet_coefficient(
            8.0,
            1.0,
            "B",
            false,
            Density::OneSided,
            BiasReading::AllanMinimum,
        )
        .unwrap();
        assert!((b - 8.0 / 0.664_282_470_267_960_1).abs() < 1e-15);
        assert_eq!(c, Conversion::AllanMinimum);
        assert!(
            datasheet_coefficient(
                -1.0,
                1.0,
                "B",
                false,
                Density::OneSided,
                BiasReading::Coefficient
            )
            .is_err()
        );
        assert!(
            datasheet_coefficient(
                1.0,
                1.0,
                "X",
                false,
                Density::OneSided,
                BiasReading::Coefficient
            )
            .is_err()
        );
        assert!(Density::parse("both").is_err());
        assert!(BiasReading::parse("min").is_err());
    }
}
