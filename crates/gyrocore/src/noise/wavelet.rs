//! Haar wavelet variance at dyadic scales (MODWT; Percival & Walden, *Wavelet Methods for Time
//! Series Analysis*, 2000, §8.1).
//!
//! The level-j Haar MODWT coefficient of a rate series `y` (scale `τ_j = 2^j t0`, half-width
//! `m = 2^{j−1}` samples) is the difference of two adjacent means of `m` samples, halved:
//!
//! ```text
//! W_{j,t} = (ȳ_{t+m..t+2m} − ȳ_{t..t+m}) / 2,   t = 0 … n − 2m,   M_j = n − 2m + 1
//! ν̂²_j = (1/M_j) Σ_t W_{j,t}²
//! ```
//!
//! (sign and time alignment do not matter for the variance). Hence `E ν̂²_j = σ²_A(m·t0)/2`:
//! the Haar wavelet variance is half the overlapping Allan variance at `τ = m·t0` with the same
//! number of terms (Percival & Guttorp 1994). The sums use prefix sums of the mean-removed
//! series, one pass per scale, scales in parallel.

use rayon::prelude::*;

use crate::validate;
use crate::{Error, Result};

/// Haar wavelet variance of a rate series.
#[derive(Debug, Clone, PartialEq)]
pub struct WaveletVariance {
    /// Half-widths `m = 2^{j−1}` (samples), j = 1 … J.
    pub m: Vec<usize>,
    /// Wavelet scales `τ_j = 2m·t0` (s).
    pub scales: Vec<f64>,
    /// `ν̂²_j` (rate unit²).
    pub variance: Vec<f64>,
    /// Number of coefficients `M_j = n − 2m + 1`.
    pub n_coefficients: Vec<usize>,
}

/// The prefix sums of the mean-removed data divided by a power of two `2^e` (exact), and `e`
/// ([`validate::pow2_exponent`]): the sums of squares of the wavelet coefficients then neither
/// overflow (data near 1e155) nor underflow (subnormal data). Ordinary data (`|e| <= 400`) are
/// used as given, so their variances are bit-identical to the unscaled computation.
fn scaled_prefix(rate: &[f64]) -> (Vec<f64>, i32) {
    let n = rate.len();
    let e = validate::pow2_exponent(rate);
    let e = if e.abs() > 400 { e } else { 0 };
    let value = |v: f64| {
        if e == 0 {
            v
        } else {
            validate::times_pow2(v, -e)
        }
    };
    let mean = rate.iter().map(|v| value(*v)).sum::<f64>() / n as f64;
    let mut prefix = Vec::with_capacity(n + 1);
    prefix.push(0.0);
    let mut acc = 0.0;
    for v in rate {
        acc += value(*v) - mean;
        prefix.push(acc);
    }
    (prefix, e)
}

/// Variances of data scaled by `2^-e` ([`scaled_prefix`]) brought back to the data's scale
/// (times `4^e`), or an error naming `data` when float64 cannot hold them.
fn unscaled(variance: Vec<f64>, e: i32) -> Result<Vec<f64>> {
    if e == 0 {
        return Ok(variance);
    }
    let scaled_nonzero = variance.iter().any(|v| *v != 0.0);
    let variance: Vec<f64> = variance
        .into_iter()
        .map(|v| validate::times_pow2(v, 2 * e))
        .collect();
    if variance.iter().any(|v| !v.is_finite()) {
        return Err(Error::invalid(
            "data",
            format!(
                "the wavelet variance of data this large (max |x| ≈ 2^{e}) exceeds float64's \
                 range (about 1.8e308): rescale the data (another unit)"
            ),
        ));
    }
    if scaled_nonzero && variance.iter().all(|v| *v == 0.0) {
        return Err(Error::invalid(
            "data",
            format!(
                "the wavelet variance of data this small (max |x| ≈ 2^{e}) is below float64's \
                 smallest number: rescale the data (another unit)"
            ),
        ));
    }
    Ok(variance)
}

/// Haar wavelet variance of `rate` (period `t0`) at every dyadic scale with
/// `n / m ≥ min_blocks` (`m` the half-width), at least two scales.
pub fn haar(rate: &[f64], t0: f64, min_blocks: usize) -> Result<WaveletVariance> {
    validate::positive("fs", 1.0 / t0)?;
    validate::finite("data", rate)?;
    let n = rate.len();
    let min_blocks = min_blocks.max(2);
    let mut m = Vec::new();
    let mut half = 1usize;
    while half.saturating_mul(min_blocks) <= n {
        m.push(half);
        half *= 2;
    }
    if m.len() < 2 {
        return Err(Error::TooShort {
            name: "data",
            needed: 2 * min_blocks,
            got: n,
        });
    }
    let (prefix, e) = scaled_prefix(rate);
    let variance: Vec<f64> = m
        .par_iter()
        .map(|&h| {
            let count = n - 2 * h + 1;
            let scale = 1.0 / (2.0 * h as f64);
            let mut sum = 0.0;
            for t in 0..count {
                let w = (prefix[t + 2 * h] - 2.0 * prefix[t + h] + prefix[t]) * scale;
                sum += w * w;
            }
            sum / count as f64
        })
        .collect();
    let variance = unscaled(variance, e)?;
    if variance.iter().all(|v| *v == 0.0) {
        return Err(Error::invalid(
            "data",
            "the wavelet variance is zero at every scale (constant data): there is no noise to \
             identify",
        ));
    }
    Ok(WaveletVariance {
        scales: m.iter().map(|&h| 2.0 * h as f64 * t0).collect(),
        n_coefficients: m.iter().map(|&h| n - 2 * h + 1).collect(),
        m,
        variance,
    })
}

/// Wavelet variance with confidence intervals ([`wvar`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Wvar {
    /// Levels `j = 1 … J`.
    pub levels: Vec<usize>,
    /// Half-widths `m = 2^{j−1}` (samples).
    pub m: Vec<usize>,
    /// Wavelet scales (filter widths) `τ_j = 2^j t0` (s), as the R `wv` package labels them.
    pub scales: Vec<f64>,
    /// `ν̂²_j` (rate unit²), classical or robust.
    pub variance: Vec<f64>,
    /// Number of coefficients `M_j = n − 2^j + 1`.
    pub n_coefficients: Vec<usize>,
    /// Equivalent degrees of freedom of the interval (`max(M_j/2^j, 1)`, times the efficiency
    /// for the robust estimator).
    pub edf: Vec<f64>,
    /// Lower confidence limit of `ν²_j`.
    pub ci_low: Vec<f64>,
    /// Upper confidence limit of `ν²_j`.
    pub ci_high: Vec<f64>,
    /// Tukey-biweight tuning constant `c` (robust only; NaN otherwise).
    pub tuning: f64,
}

/// `E[Z^k 1{|Z| ≤ c}]` for even `k = 0, 2, …, 2·(len − 1)` and Z standard normal:
/// `μ_0 = 2Φ(c) − 1`, `μ_k = (k − 1) μ_{k−2} − 2 c^{k−1} φ(c)`.
fn truncated_moments(c: f64, len: usize) -> Vec<f64> {
    let phi = (-0.5 * c * c).exp() / (2.0 * std::f64::consts::PI).sqrt();
    let mut mu = Vec::with_capacity(len);
    mu.push(crate::stats::gamma_p(0.5, 0.5 * c * c).unwrap_or(1.0));
    for i in 1..len {
        let k = 2 * i;
        mu.push((k as f64 - 1.0) * mu[i - 1] - 2.0 * c.powi(k as i32 - 1) * phi);
    }
    mu
}

/// Binomial coefficient `C(n, i)` as f64.
fn binomial(n: usize, i: usize) -> f64 {
    (0..i).fold(1.0, |acc, k| acc * (n - k) as f64 / (k + 1) as f64)
}

/// Gaussian moments of the biweight ρ (module docs of [`robust_variance`]):
/// `(a, D, Q) = (E ρ(Z), E[Z²ρ(Z)] − E ρ(Z), Var ρ(Z))`.
fn biweight_moments(c: f64) -> (f64, f64, f64) {
    let mu = truncated_moments(c, 11);
    let c2 = c * c;
    let sum = |order: usize, offset: usize| -> f64 {
        (0..=order)
            .map(|i| {
                let sign = if i % 2 == 0 { 1.0 } else { -1.0 };
                sign * binomial(order, i) * mu[offset + i] / c2.powi(i as i32)
            })
            .sum()
    };
    let a = sum(4, 1);
    let d = sum(4, 2) - a;
    let q = sum(8, 2) - a * a;
    (a, d, q)
}

/// Asymptotic efficiency at Gaussian data of the biweight scale estimator with constant `c`,
/// relative to the classical mean of squares: `D²/(2Q)` (module docs of [`robust_variance`]).
pub fn biweight_efficiency(c: f64) -> f64 {
    let (_, d, q) = biweight_moments(c);
    d * d / (2.0 * q)
}

/// The tuning constant `c` whose [`biweight_efficiency`] is `efficiency` (bisection; the
/// efficiency increases with `c`). Errors: efficiency outside (0, 1) or beyond what c ≤ 100
/// reaches.
pub fn biweight_constant(efficiency: f64) -> Result<f64> {
    if !(efficiency > 0.0 && efficiency < 1.0) {
        return Err(Error::invalid(
            "efficiency",
            format!("must be in (0, 1), got {efficiency}"),
        ));
    }
    let (mut lo, mut hi) = (1e-3_f64, 100.0_f64);
    if biweight_efficiency(hi) < efficiency {
        return Err(Error::invalid(
            "efficiency",
            format!(
                "{efficiency} is too close to 1 for a robust estimator (at most {}); use the \
                 classical estimator",
                biweight_efficiency(hi)
            ),
        ));
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if biweight_efficiency(mid) < efficiency {
            lo = mid;
        } else {
            hi = mid;
        }
        if hi - lo <= 1e-14 * hi {
            break;
        }
    }
    Ok(0.5 * (lo + hi))
}

/// Robust (Tukey-biweight M-) estimate of the variance of zero-mean coefficients `w`
/// (Guerrier & Molinari's robust wavelet variance, as in the R `wv`/`gmwm` packages).
///
/// ```text
/// (1/M) Σ_t ρ_c(W_t / ν) = a(c),   ρ_c(r) = r² (1 − r²/c²)⁴ for |r| ≤ c, 0 otherwise,
/// a(c) = E ρ_c(Z),  Z ~ N(0, 1)   (Fisher consistency at Gaussian coefficients)
/// ```
///
/// `ρ_c = ψ_c²` with ψ_c Tukey's biweight; the M-estimator's asymptotic variance at Gaussian data
/// is `4Q/D²·ν⁴/M` with `D = E[Z²ρ(Z)] − a`, `Q = Var ρ(Z)`, i.e. an efficiency `D²/(2Q)`
/// relative to the classical `2ν⁴/M`; `c` is chosen for the requested efficiency
/// ([`biweight_constant`]). The left side vanishes at ν → 0 and ν → ∞; the estimate is the root
/// on its decreasing branch (where `D > 0` puts the Gaussian solution), bracketed from the MAD
/// scale `ν₀ = 1.482602·median|W|` by doubling/halving (at most 60 halvings) and refined by
/// bisection in `ln ν` (tolerance 1e-13 relative). When the left side never reaches `a(c)`
/// below ν₀ (coefficients far from Gaussian, e.g. every one hit by a spike) there is no root
/// and the estimate is the left side's maximum over `[ν₀ 2⁻⁶⁰, ν₀]` (golden section in `ln ν`),
/// the closest approach — what minimising the squared difference, as the R packages do, gives.
pub fn robust_variance(w: &[f64], c: f64) -> f64 {
    let (a, _, _) = biweight_moments(c);
    let m = w.len() as f64;
    let lhs = |nu: f64| -> f64 {
        let inv = 1.0 / nu;
        let c2 = c * c;
        let s: f64 = w
            .iter()
            .map(|&x| {
                let r = x * inv;
                let r2 = r * r;
                if r2 <= c2 {
                    let u = 1.0 - r2 / c2;
                    r2 * u * u * u * u
                } else {
                    0.0
                }
            })
            .sum();
        s / m - a
    };
    let mut abs: Vec<f64> = w.iter().map(|v| v.abs()).collect();
    let mid = abs.len() / 2;
    let (_, med, _) = abs.select_nth_unstable_by(mid, f64::total_cmp);
    let mut nu0 = 1.482_602_218_505_602 * *med;
    if nu0 <= 0.0 {
        let ms = w.iter().map(|v| v * v).sum::<f64>() / m;
        if ms <= 0.0 {
            return 0.0;
        }
        nu0 = ms.sqrt();
    }
    let (mut lo, mut hi);
    if lhs(nu0) > 0.0 {
        lo = nu0;
        hi = nu0 * 2.0;
        let mut k = 0;
        while lhs(hi) > 0.0 && k < 200 {
            lo = hi;
            hi *= 2.0;
            k += 1;
        }
    } else {
        hi = nu0;
        lo = nu0 / 2.0;
        let mut k = 0;
        while lhs(lo) <= 0.0 && k < 60 {
            hi = lo;
            lo /= 2.0;
            k += 1;
        }
        if lhs(lo) <= 0.0 {
            // No root (the coefficients are too far from Gaussian for the left side to reach
            // a(c)): the closest approach, the maximum of the left side over ν ≤ ν₀ (what
            // minimising the squared difference, as the R packages do, also gives).
            let (mut a, mut b) = (lo.ln(), nu0.ln());
            let g = 0.5 * (5f64.sqrt() - 1.0);
            for _ in 0..200 {
                let x1 = b - g * (b - a);
                let x2 = a + g * (b - a);
                if lhs(x1.exp()) >= lhs(x2.exp()) {
                    b = x2;
                } else {
                    a = x1;
                }
                if b - a < 1e-13 {
                    break;
                }
            }
            let nu = (0.5 * (a + b)).exp();
            return nu * nu;
        }
    }
    for _ in 0..200 {
        let mid = (lo * hi).sqrt();
        if lhs(mid) > 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
        if hi - lo <= 1e-13 * hi {
            break;
        }
    }
    let nu = (lo * hi).sqrt();
    nu * nu
}

/// Haar MODWT wavelet variance of `rate` (period `t0`) at levels `j = 1 … J` with chi-square
/// confidence intervals (Percival 1995; the R `wv` package's `wvar`):
///
/// * `J = ⌊log₂ n⌋ − 1` by default (every dyadic scale the record supports: filter width
///   `2^j ≤ n/2`), or `levels` if given (≤ that maximum);
/// * classical `ν̂²_j = (1/M_j) Σ_t W²_{j,t}` (= half the overlapping Allan variance at
///   `τ = 2^{j−1} t0`, [`haar`]), robust: [`robust_variance`] of the same coefficients with the
///   biweight constant of `efficiency`;
/// * interval `[η ν̂²/χ²_η(1 − α/2), η ν̂²/χ²_η(α/2)]` with `η_j = max(M_j/2^j, 1)` (Percival's
///   "η₃"), times `efficiency` for the robust estimator (its variance at Gaussian data is the
///   classical one divided by the efficiency; `wv` instead widens the classical interval's
///   half-widths by `1/√eff`, which agrees to first order).
///
/// Errors: non-finite data, `fs` ≤ 0, fewer than 4 samples (16 for `robust`: at least three
/// scales), `levels` 0 or beyond `J`, `confidence` outside (0, 1), `efficiency` outside (0, 1).
pub fn wvar(
    rate: &[f64],
    t0: f64,
    robust: Option<f64>,
    confidence: f64,
    levels: Option<usize>,
) -> Result<Wvar> {
    validate::positive("fs", 1.0 / t0)?;
    validate::finite("data", rate)?;
    if !(confidence > 0.0 && confidence < 1.0) {
        return Err(Error::invalid(
            "confidence",
            format!("must be in (0, 1), got {confidence}"),
        ));
    }
    let tuning = match robust {
        Some(eff) => biweight_constant(eff)?,
        None => f64::NAN,
    };
    let n = rate.len();
    let needed = if robust.is_some() { 16 } else { 4 };
    if n < needed {
        return Err(if robust.is_some() {
            Error::invalid(
                "robust",
                format!(
                    "the robust wavelet variance needs at least 3 dyadic scales (16 samples), \
                     got {n} samples"
                ),
            )
        } else {
            Error::TooShort {
                name: "data",
                needed,
                got: n,
            }
        });
    }
    let j_max = (usize::BITS - 1 - n.leading_zeros()) as usize - 1;
    let j_count = match levels {
        None => j_max,
        Some(l) if l >= 1 && l <= j_max => l,
        Some(l) => {
            return Err(Error::invalid(
                "levels",
                format!("must be in 1..={j_max} for {n} samples (2^j ≤ n/2), got {l}"),
            ));
        }
    };
    let (prefix, e) = scaled_prefix(rate);
    let levels: Vec<usize> = (1..=j_count).collect();
    let m: Vec<usize> = levels.iter().map(|&j| 1usize << (j - 1)).collect();
    let variance: Vec<f64> = m
        .par_iter()
        .map(|&h| {
            let count = n - 2 * h + 1;
            let scale = 1.0 / (2.0 * h as f64);
            let coeff = |t: usize| (prefix[t + 2 * h] - 2.0 * prefix[t + h] + prefix[t]) * scale;
            if robust.is_some() {
                let w: Vec<f64> = (0..count).map(coeff).collect();
                robust_variance(&w, tuning)
            } else {
                (0..count).map(|t| coeff(t).powi(2)).sum::<f64>() / count as f64
            }
        })
        .collect();
    let variance = unscaled(variance, e)?;
    if variance.iter().all(|v| *v == 0.0) {
        return Err(Error::invalid(
            "data",
            "the wavelet variance is zero at every scale (constant data)",
        ));
    }
    let n_coefficients: Vec<usize> = m.iter().map(|&h| n - 2 * h + 1).collect();
    let factor = robust.unwrap_or(1.0);
    let edf: Vec<f64> = n_coefficients
        .iter()
        .zip(&m)
        .map(|(&mj, &h)| (mj as f64 / (2 * h) as f64).max(1.0) * factor)
        .collect();
    let alpha = 1.0 - confidence;
    let mut ci_low = Vec::with_capacity(j_count);
    let mut ci_high = Vec::with_capacity(j_count);
    for (v, &e) in variance.iter().zip(&edf) {
        ci_low.push(e * v / crate::stats::chi2_ppf(1.0 - alpha / 2.0, e)?);
        ci_high.push(e * v / crate::stats::chi2_ppf(alpha / 2.0, e)?);
    }
    Ok(Wvar {
        scales: m.iter().map(|&h| 2.0 * h as f64 * t0).collect(),
        levels,
        m,
        variance,
        n_coefficients,
        edf,
        ci_low,
        ci_high,
        tuning,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::allan::{Column, DataType, Estimator, angle_series, variance};

    #[test]
    fn half_the_overlapping_allan_variance() {
        let rate: Vec<f64> = (0..1000)
            .map(|k| ((k * 7919) % 113) as f64 * 0.01 + (k as f64 * 0.001).sin())
            .collect();
        let t0 = 0.1;
        let wv = haar(&rate, t0, 4).unwrap();
        let x = angle_series(Column::contiguous(&rate), t0, DataType::Rate).unwrap();
        for (i, &h) in wv.m.iter().enumerate() {
            let (avar, terms) = variance(&x, t0, h, Estimator::Overlapping).unwrap();
            assert_eq!(terms, wv.n_coefficients[i]);
            assert!(
                (2.0 * wv.variance[i] / avar - 1.0).abs() < 1e-10,
                "m={h}: {} vs {avar}",
                2.0 * wv.variance[i]
            );
        }
        assert_eq!(wv.m.last(), Some(&128));
    }

    #[test]
    fn constant_and_short_data_are_errors() {
        assert!(haar(&[1.0; 100], 1.0, 4).is_err());
        assert!(matches!(
            haar(&[1.0, 2.0, 3.0], 1.0, 4),
            Err(Error::TooShort { .. })
        ));
    }

    #[test]
    fn wvar_levels_and_classical_equals_haar() {
        let rate: Vec<f64> = (0..1000)
            .map(|k| ((k * 7919) % 113) as f64 * 0.01)
            .collect();
        let w = wvar(&rate, 0.1, None, 0.95, None).unwrap();
        assert_eq!(w.levels.len(), 8); // ⌊log₂ 1000⌋ − 1
        let h = haar(&rate, 0.1, 4).unwrap();
        assert_eq!(h.variance.len(), 8);
        for (a, b) in w.variance.iter().zip(&h.variance) {
            assert!((a - b).abs() <= 1e-12 * b);
        }
        for i in 0..8 {
            assert!(w.ci_low[i] < w.variance[i] && w.variance[i] < w.ci_high[i]);
        }
    }

    #[test]
    fn biweight_efficiency_limits() {
        // c → ∞ is the classical estimator (efficiency 1).
        assert!((biweight_efficiency(60.0) - 1.0).abs() < 1e-3);
        let c = biweight_constant(0.6).unwrap();
        assert!((biweight_efficiency(c) - 0.6).abs() < 1e-10);
        assert!(biweight_constant(1.0).is_err());
        assert!(biweight_constant(0.0).is_err());
    }

    #[test]
    fn robust_estimate_solves_its_equation() {
        let mut g = crate::random::NormalStream::new(3);
        let w: Vec<f64> = (0..5000).map(|_| 2.0 * g.next_normal()).collect();
        let c = biweight_constant(0.6).unwrap();
        let v = robust_variance(&w, c);
        assert!((v / 4.0 - 1.0).abs() < 0.1, "{v}");
    }
}
