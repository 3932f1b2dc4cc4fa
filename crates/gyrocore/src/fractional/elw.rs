//! Exact local Whittle (ELW) estimation of the memory parameter `d` (Shimotsu & Phillips 2005,
//! with Shimotsu's 2010 correction for an unknown level; SPEC §4).
//!
//! ```text
//! d̂ = argmin_{d ∈ [d₁, d₂]} R(d),   R(d) = log G(d) − 2d·(1/m) Σ_{j=1}^{m} log λ_j,
//! G(d) = (1/m) Σ_{j=1}^{m} I_{Δ^d x̃}(λ_j),   λ_j = 2πj/n,   I_u(λ) = |Σ_t u_t e^{−iλt}|²/(2πn)
//! ```
//!
//! with the type-II difference `Δ^d` of [`super`] and the bandwidth `m = ⌊n^0.65⌋` by default
//! (`1 ≤ m ≤ n/2`). The level correction (`Level::Shimotsu`, Shimotsu 2010 §3) works on
//! `x̃(d) = x − μ(d)` with `μ(d) = w(d)·x̄ + (1 − w(d))·x_0`, `w(d) = 1` for `d ≤ ½`, `0` for
//! `d ≥ ¾` and `(1 + cos 4πd)/2` between: the sample mean estimates the level well for
//! `d < ½` and the first observation for `d > ¾`. Gyro data carry an unknown bias, hence it is the
//! default; without it (`Level::None`) the data are used as given (right for type-II data that
//! start at zero).
//!
//! `d̂` is asymptotically `N(d, 1/(4m))` for `d` inside the bounds; the standard error reported
//! is `1/(2√m)`. The theory needs `d₂ − d₁ ≤ 9/2` (Shimotsu & Phillips 2005, Thm 2.2), and with
//! the level correction the bounds within `[−½, 2]` (Shimotsu 2010, Thm 3).
//!
//! Minimisation: `R` on a grid of step ≤ 0.1 across the bounds (robust against a local
//! minimum), then Brent's method ([`crate::optimize`]) in the grid cell pair around the best
//! point. Each evaluation costs three real FFTs: `Δ^d x` by FFT convolution (the spectrum of `x`
//! is computed once; `Δ^d 1 = Σ_{l≤k} π_l(d)` handles the level term exactly), and the
//! periodogram of `u` (length `n`). Short series use the direct `O(n²)` difference instead.

use rayon::prelude::*;
use realfft::num_complex::Complex;

use super::{check_rows, convolve, weights};
use crate::optimize::brent_minimize;
use crate::validate;
use crate::{Error, Result};

/// How the unknown level (bias) of the data is handled.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Level {
    /// Shimotsu's (2010) correction `x − [w(d)·x̄ + (1 − w(d))·x_0]` (the default).
    Shimotsu,
    /// The data are used as given.
    None,
}

impl Level {
    /// Parses `"shimotsu"` or `"none"`.
    pub fn parse(name: &str) -> Result<Self> {
        match name {
            "shimotsu" => Ok(Level::Shimotsu),
            "none" => Ok(Level::None),
            other => Err(Error::invalid(
                "level",
                format!("expected 'shimotsu' or 'none', got {other:?}"),
            )),
        }
    }
}

/// An ELW estimate of `d`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Estimate {
    /// The estimate `d̂`.
    pub d: f64,
    /// Asymptotic standard error `1/(2√m)`.
    pub standard_error: f64,
    /// Bandwidth (number of Fourier frequencies used).
    pub m: usize,
    /// Series length.
    pub n: usize,
    /// The objective `R(d̂)`.
    pub objective: f64,
    /// Whether `d̂` lies on (within 1e-6 of) one of the bounds: the minimum may be outside.
    pub at_bound: bool,
}

/// Default bandwidth `⌊n^0.65⌋`, kept within `[1, ⌊n/2⌋]`.
pub fn default_bandwidth(n: usize) -> usize {
    ((n as f64).powf(0.65).floor() as usize).clamp(1, (n / 2).max(1))
}

/// Shimotsu's weight `w(d)` of the sample mean in the level estimate.
pub fn level_weight(d: f64) -> f64 {
    if d <= 0.5 {
        1.0
    } else if d >= 0.75 {
        0.0
    } else {
        0.5 * (1.0 + (4.0 * std::f64::consts::PI * d).cos())
    }
}

/// Validated settings shared by all rows.
#[derive(Debug, Clone, Copy)]
struct Settings {
    n: usize,
    m: usize,
    lo: f64,
    hi: f64,
    level: Level,
}

fn settings(n: usize, m: Option<usize>, bounds: (f64, f64), level: Level) -> Result<Settings> {
    if n < 2 {
        return Err(Error::TooShort {
            name: "x",
            needed: 2,
            got: n,
        });
    }
    let m = m.unwrap_or_else(|| default_bandwidth(n));
    if m < 1 || m > n / 2 {
        return Err(Error::invalid(
            "m",
            format!("must be in [1, n/2] = [1, {}] for n = {n}, got {m}", n / 2),
        ));
    }
    let (lo, hi) = bounds;
    if !(lo.is_finite() && hi.is_finite() && lo < hi) {
        return Err(Error::invalid(
            "bounds",
            format!("must be finite with lower < upper, got ({lo}, {hi})"),
        ));
    }
    if hi - lo > 4.5 {
        return Err(Error::invalid(
            "bounds",
            format!("the ELW estimator needs upper − lower ≤ 9/2, got ({lo}, {hi})"),
        ));
    }
    if level == Level::Shimotsu && (lo < -0.5 || hi > 2.0) {
        return Err(Error::invalid(
            "bounds",
            format!("with the Shimotsu level correction d must lie in [-0.5, 2], got ({lo}, {hi})"),
        ));
    }
    Ok(Settings {
        n,
        m,
        lo,
        hi,
        level,
    })
}

/// FFT plans shared by all rows.
struct Plans {
    /// Convolution length `N ≥ 2n − 1` (FFT path) or `None` (direct difference).
    conv: Option<(usize, convolve::PlanPair)>,
    /// Periodogram transforms of length `n` (only the forward one is used).
    periodogram: convolve::PlanPair,
    mean_log_lambda: f64,
}

impl Plans {
    fn new(s: &Settings) -> Self {
        let conv = convolve::prefer_fft(s.n, s.n).then(|| {
            let len = convolve::fast_even_len(2 * s.n - 1);
            (len, convolve::plans(len))
        });
        let periodogram = convolve::plans(s.n);
        let mean_log_lambda = (1..=s.m)
            .map(|j| (std::f64::consts::TAU * j as f64 / s.n as f64).ln())
            .sum::<f64>()
            / s.m as f64;
        Plans {
            conv,
            periodogram,
            mean_log_lambda,
        }
    }
}

/// One series prepared for repeated evaluation of `R(d)`.
struct Objective<'a> {
    s: Settings,
    plans: &'a Plans,
    x: &'a [f64],
    mean: f64,
    x_spectrum: Vec<Complex<f64>>,
    real: Vec<f64>,
    spectrum: Vec<Complex<f64>>,
    u: Vec<f64>,
    u_spectrum: Vec<Complex<f64>>,
    scratch: Vec<Complex<f64>>,
}

impl<'a> Objective<'a> {
    fn new(s: Settings, plans: &'a Plans, x: &'a [f64]) -> Self {
        let n = s.n;
        let mut scratch_len = plans.periodogram.0.get_scratch_len();
        let (mut x_spectrum, mut real, mut spectrum) = (Vec::new(), Vec::new(), Vec::new());
        if let Some((len, (fwd, inv))) = &plans.conv {
            scratch_len = scratch_len
                .max(fwd.get_scratch_len())
                .max(inv.get_scratch_len());
            real = vec![0.0; *len];
            spectrum = fwd.make_output_vec();
            x_spectrum = fwd.make_output_vec();
        }
        let mut scratch = vec![Complex::default(); scratch_len];
        if let Some((_, (fwd, _))) = &plans.conv {
            real[..n].copy_from_slice(x);
            real[n..].fill(0.0);
            fwd.process_with_scratch(&mut real, &mut x_spectrum, &mut scratch)
                .expect("FFT buffer lengths come from the plan");
        }
        Objective {
            s,
            plans,
            x,
            mean: validate::neumaier_sum(x.iter().copied()) / n as f64,
            x_spectrum,
            real,
            spectrum,
            u: vec![0.0; n],
            u_spectrum: plans.periodogram.0.make_output_vec(),
            scratch,
        }
    }

    /// `R(d)`; `+∞` where `G(d)` is not positive (all periodogram ordinates zero).
    fn eval(&mut self, d: f64) -> f64 {
        let n = self.s.n;
        let pi = weights(d, n).expect("d is finite inside the bounds");
        // u = Δ^d x (before the level term).
        match &self.plans.conv {
            Some((len, (fwd, inv))) => {
                let scale = 1.0 / *len as f64;
                for (r, p) in self.real.iter_mut().zip(&pi) {
                    *r = p * scale;
                }
                self.real[n..].fill(0.0);
                fwd.process_with_scratch(&mut self.real, &mut self.spectrum, &mut self.scratch)
                    .expect("FFT buffer lengths come from the plan");
                for (s, xs) in self.spectrum.iter_mut().zip(&self.x_spectrum) {
                    *s *= xs;
                }
                self.spectrum[0].im = 0.0;
                if let Some(last) = self.spectrum.last_mut() {
                    last.im = 0.0;
                }
                inv.process_with_scratch(&mut self.spectrum, &mut self.real, &mut self.scratch)
                    .expect("FFT buffer lengths come from the plan");
                self.u.copy_from_slice(&self.real[..n]);
            }
            None => {
                for k in 0..n {
                    self.u[k] = (0..=k).map(|i| pi[k - i] * self.x[i]).sum();
                }
            }
        }
        // Level term: u −= μ(d)·Δ^d 1, with (Δ^d 1)_k = Σ_{l≤k} π_l.
        let mu = match self.s.level {
            Level::None => 0.0,
            Level::Shimotsu => {
                let w = level_weight(d);
                w * self.mean + (1.0 - w) * self.x[0]
            }
        };
        if mu != 0.0 {
            let mut partial = 0.0;
            for (u, p) in self.u.iter_mut().zip(&pi) {
                partial += p;
                *u -= mu * partial;
            }
        }
        self.plans
            .periodogram
            .0
            .process_with_scratch(&mut self.u, &mut self.u_spectrum, &mut self.scratch)
            .expect("FFT buffer lengths come from the plan");
        let m = self.s.m;
        let norm = 1.0 / (std::f64::consts::TAU * n as f64);
        let g = self.u_spectrum[1..=m]
            .iter()
            .map(|z| z.norm_sqr() * norm)
            .sum::<f64>()
            / m as f64;
        if g > 0.0 && g.is_finite() {
            g.ln() - 2.0 * d * self.plans.mean_log_lambda
        } else {
            f64::INFINITY
        }
    }
}

fn estimate_one(s: Settings, plans: &Plans, x: &[f64]) -> Result<Estimate> {
    if x.iter().all(|&v| v == x[0]) {
        return Err(Error::invalid(
            "x",
            "is constant: the memory parameter d is not identified",
        ));
    }
    let mut obj = Objective::new(s, plans, x);
    let cells = ((s.hi - s.lo) / 0.1).ceil().max(1.0) as usize;
    let step = (s.hi - s.lo) / cells as f64;
    let mut best = (0usize, f64::INFINITY);
    for i in 0..=cells {
        let r = obj.eval(s.lo + step * i as f64);
        if r < best.1 {
            best = (i, r);
        }
    }
    if !best.1.is_finite() {
        return Err(Error::Singular {
            reason: "the ELW objective is not finite anywhere within the bounds".into(),
        });
    }
    let centre = s.lo + step * best.0 as f64;
    let a = (centre - step).max(s.lo);
    let b = (centre + step).min(s.hi);
    let found = brent_minimize(|d| obj.eval(d), a, b, 1e-8, 200);
    let (d, objective) = if found.fx <= best.1 {
        (found.x, found.fx)
    } else {
        (centre, best.1)
    };
    let tol = 1e-6 * (s.hi - s.lo).max(1.0);
    Ok(Estimate {
        d,
        standard_error: 0.5 / (s.m as f64).sqrt(),
        m: s.m,
        n: s.n,
        objective,
        at_bound: d - s.lo <= tol || s.hi - d <= tol,
    })
}

/// ELW estimate of `d` for one series (see the module docs). `m = None` uses `⌊n^0.65⌋`.
pub fn elw(x: &[f64], m: Option<usize>, bounds: (f64, f64), level: Level) -> Result<Estimate> {
    Ok(elw_rows(x, x.len(), m, bounds, level)?.remove(0))
}

/// ELW estimates for each row of a C-contiguous `(rows × n)` array (rows in parallel).
pub fn elw_rows(
    data: &[f64],
    n: usize,
    m: Option<usize>,
    bounds: (f64, f64),
    level: Level,
) -> Result<Vec<Estimate>> {
    check_rows("x", data, n)?;
    let s = settings(n, m, bounds, level)?;
    validate::finite("x", data)?;
    let plans = Plans::new(&s);
    data.par_chunks(n)
        .map(|x| estimate_one(s, &plans, x))
        .collect()
}

/// The ELW objective `R(d)` of one series at each of `ds` (for diagnostics and plots).
pub fn objective(x: &[f64], ds: &[f64], m: Option<usize>, level: Level) -> Result<Vec<f64>> {
    check_rows("x", x, x.len())?;
    let s = settings(x.len(), m, (-0.5, 2.0), Level::None)?;
    let s = Settings { level, ..s };
    validate::finite("x", x)?;
    validate::finite("d", ds)?;
    if x.iter().all(|&v| v == x[0]) {
        // the periodogram is zero at every Fourier frequency: R(d) = ln 0 = −inf, not a value
        return Err(Error::invalid(
            "x",
            "is constant: the ELW objective is undefined (the periodogram is zero)",
        ));
    }
    // Data of extreme magnitude (the periodogram's squares over- or underflow) are analysed
    // scaled by 2^-e (exact): R(d) of c·x is R(d) of x plus ln c², added back below. Ordinary
    // data (|e| <= 400) are used as given.
    let e = validate::pow2_exponent(x);
    let e = if e.abs() > 400 { e } else { 0 };
    let scaled: Option<Vec<f64>> =
        (e != 0).then(|| x.iter().map(|v| validate::times_pow2(*v, -e)).collect());
    let shift = 2.0 * f64::from(e) * std::f64::consts::LN_2;
    let plans = Plans::new(&s);
    let mut obj = Objective::new(s, &plans, scaled.as_deref().unwrap_or(x));
    Ok(ds.iter().map(|&d| obj.eval(d) + shift).collect())
}

/// The asymptotic normal interval `d̂ ∓ z·se` at the two-sided `confidence` level for each
/// estimate of `d`, `z = Φ⁻¹(½ + confidence/2)`, computed exactly as `z = √(χ²₁ quantile at
/// confidence)` (`Z² ~ χ²₁`, [`crate::stats::chi2_ppf`]). Returns `(lower, upper)`.
///
/// # Errors
/// `confidence` not in (0, 1) or `standard_error` not finite and ≥ 0
/// ([`Error::InvalidParameter`]).
pub fn confidence_interval(
    d: &[f64],
    standard_error: f64,
    confidence: f64,
) -> Result<(Vec<f64>, Vec<f64>)> {
    if !(confidence > 0.0 && confidence < 1.0) {
        return Err(Error::invalid(
            "confidence",
            format!("must be in (0, 1), got {confidence}"),
        ));
    }
    validate::non_negative("standard_error", standard_error)?;
    let z = crate::stats::chi2_ppf(confidence, 1.0)?.sqrt();
    let half = z * standard_error;
    Ok((
        d.iter().map(|v| v - half).collect(),
        d.iter().map(|v| v + half).collect(),
    ))
}

#[cfg(test)]
mod tests {
    #[test]
    fn confidence_interval_uses_the_normal_quantile() {
        // Φ⁻¹(0.975) = 1.959963984540054, Φ⁻¹(0.95) = 1.6448536269514722 (SciPy).
        let (lo, hi) = super::confidence_interval(&[0.5, 0.3], 0.04, 0.95).unwrap();
        assert!((hi[0] - 0.5 - 1.959_963_984_540_054 * 0.04).abs() < 1e-13);
        assert!((0.3 - lo[1] - 1.959_963_984_540_054 * 0.04).abs() < 1e-13);
        let (_, hi) = super::confidence_interval(&[0.0], 1.0, 0.9).unwrap();
        assert!((hi[0] - 1.644_853_626_951_472_2).abs() < 1e-12);
        assert!(super::confidence_interval(&[0.0], 1.0, 1.0).is_err());
        assert!(super::confidence_interval(&[0.0], 1.0, 0.0).is_err());
        assert!(super::confidence_interval(&[0.0], -1.0, 0.5).is_err());
    }

    use super::*;
    use crate::fractional::arfima::{Kind, arfima};

    /// The objective straight from the definition (direct difference, direct DFT).
    fn naive_objective(x: &[f64], d: f64, m: usize, level: Level) -> f64 {
        let n = x.len();
        let mean = x.iter().sum::<f64>() / n as f64;
        let mu = match level {
            Level::None => 0.0,
            Level::Shimotsu => level_weight(d) * mean + (1.0 - level_weight(d)) * x[0],
        };
        let xt: Vec<f64> = x.iter().map(|v| v - mu).collect();
        let pi = weights(d, n).unwrap();
        let u: Vec<f64> = (0..n)
            .map(|k| (0..=k).map(|i| pi[k - i] * xt[i]).sum())
            .collect();
        let mut g = 0.0;
        let mut ll = 0.0;
        for j in 1..=m {
            let lam = std::f64::consts::TAU * j as f64 / n as f64;
            let (mut re, mut im) = (0.0, 0.0);
            for (t, ut) in u.iter().enumerate() {
                re += ut * (lam * t as f64).cos();
                im -= ut * (lam * t as f64).sin();
            }
            g += (re * re + im * im) / (std::f64::consts::TAU * n as f64);
            ll += lam.ln();
        }
        (g / m as f64).ln() - 2.0 * d * ll / m as f64
    }

    #[test]
    fn objective_matches_definition_on_both_paths() {
        for &n in &[40usize, 1500] {
            let mut x = arfima(n, 0.4, 1.0, 1, 3, Kind::Stationary).unwrap();
            for v in &mut x {
                *v += 5.0;
            }
            let m = default_bandwidth(n);
            let ds = [-0.4, 0.1, 0.5, 0.6, 0.7, 1.2, 1.9];
            for level in [Level::Shimotsu, Level::None] {
                let fast = objective(&x, &ds, None, level).unwrap();
                for (&d, f) in ds.iter().zip(&fast) {
                    let slow = naive_objective(&x, d, m, level);
                    assert!((f - slow).abs() < 1e-9, "n {n} d {d} {f} vs {slow}");
                }
            }
        }
    }

    #[test]
    fn recovers_d_on_one_long_series() {
        let x = arfima(20_000, 0.3, 1.0, 1, 11, Kind::Stationary).unwrap();
        let e = elw(&x, None, (-0.5, 2.0), Level::Shimotsu).unwrap();
        // s.e. 1/(2√m) = 0.013 at m = ⌊20000^0.65⌋ = 624: 4 s.e.
        assert!((e.d - 0.3).abs() < 0.052, "{e:?}");
        assert_eq!(e.m, 624);
        assert!(!e.at_bound);
    }

    #[test]
    fn bad_settings() {
        let x = vec![1.0, 2.0, 0.5, 3.0];
        assert!(matches!(
            elw(&x, Some(3), (-0.5, 2.0), Level::Shimotsu),
            Err(Error::InvalidParameter { name: "m", .. })
        ));
        assert!(matches!(
            elw(&x, Some(0), (-0.5, 2.0), Level::Shimotsu),
            Err(Error::InvalidParameter { name: "m", .. })
        ));
        assert!(matches!(
            elw(&x[..1], None, (-0.5, 2.0), Level::Shimotsu),
            Err(Error::TooShort { .. })
        ));
        assert!(matches!(
            elw(&x, None, (0.5, 0.2), Level::Shimotsu),
            Err(Error::InvalidParameter { name: "bounds", .. })
        ));
        assert!(matches!(
            elw(&x, None, (-1.0, 2.0), Level::Shimotsu),
            Err(Error::InvalidParameter { name: "bounds", .. })
        ));
        assert!(elw(&x, None, (-1.0, 2.0), Level::None).is_ok());
        assert!(matches!(
            elw(&x, None, (-1.0, 4.0), Level::None),
            Err(Error::InvalidParameter { name: "bounds", .. })
        ));
        assert!(matches!(
            elw(&[2.0; 10], None, (-0.5, 2.0), Level::Shimotsu),
            Err(Error::InvalidParameter { name: "x", .. })
        ));
        assert!(matches!(
            elw(&[2.0, f64::NAN, 1.0], None, (-0.5, 2.0), Level::Shimotsu),
            Err(Error::NonFinite { index: 1, .. })
        ));
    }
}
