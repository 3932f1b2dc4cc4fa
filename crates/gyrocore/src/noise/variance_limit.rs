//! What the data's variance allows: the constraint that keeps every fitted noise term within
//! the variance of the samples it was fitted to.
//!
//! An Allan-variance fit sees the data only through σ²(τ), which does not carry the variance of
//! the samples themselves; a term whose Allan signature fits the curve can then imply a sample
//! variance the data do not have (a sinusoid of amplitude 0.122 on a log whose rate has standard
//! deviation 0.0562, issue 34). Every model term `j` with squared coefficient `c_j` implies a
//! contribution `a_j·c_j` to the expected variance of the samples; the fit keeps
//!
//! ```text
//! Σ_j q_j·a_j·c_j ≤ V,      V = Σ(Ω_i − Ω̄)²/n  (the data's variance, allan::Moments)
//! ```
//!
//! where `q_j ≤ 1` is the lower [`LEVEL`] quantile of the term's own sample variance relative to
//! its expectation (the "slack": a random term's sample variance scatters about `a_j c_j`, and the
//! bound must not cut a true term whose realisation happened to come out low). Each term's
//! realised sample variance is ≥ `q_j a_j c_j` with probability ≥ 1 − [`LEVEL`], so by the union
//! bound the sum is ≥ `Σ q_j a_j c_j` with probability ≥ 1 − J·[`LEVEL`] (J terms); the
//! cross-covariances of independent components average to zero (relative size `O(1/√n)`). Since
//! every `c_j ≥ 0`, the joint constraint implies each term's own bound `q_j a_j c_j ≤ V`.
//!
//! **The terms** (IEEE Std 952-1997 Annex C definitions; `n` rate samples at period `t0`,
//! `T = n·t0`, `τ_lo` the shortest τ the fit uses, `f_hi = 1/(2τ_lo)`, `u = t0/τ_lo ≤ 1`). The
//! random terms are counted over the band the fit describes, `|f| < f_hi`: a sensor's
//! anti-alias filter removes variance above that band that the white-noise model would claim
//! (a 4-tap average has sample variance N²fs/4), so this is what the data must contain
//! whatever the sensor's filter does above the band the Allan curve explains.
//!
//! * Sinusoid `Ω₀ sin(2πf₀t + φ)` (deterministic, `q = 1`): the sample variance of a sampled
//!   sine is `Ω₀²·uᵀCu` with `C` the covariance matrix of the sampled `(cos, sin)` pair and `u`
//!   the phase's unit vector, so at least `Ω₀²·λ_min(C)` — `Ω₀²/2` for a record of many periods
//!   (the issue's `A²/2 ≤ var`), less for a fraction of a period or a line at Nyquist, where a
//!   sine can hide. `C` is evaluated exactly with the Dirichlet kernel sums.
//! * Rate ramp `R·t` (deterministic, `q = 1`): the sampled ramp's variance `R²t0²(n² − 1)/12`
//!   (`R²T²/12` for a long record).
//! * White rate noise N (two-sided PSD `N²`): `a = 2N²f_hi/N² = 1/τ_lo` (`N²·fs` when the fit
//!   starts at `t0`). Its sample variance is `χ²_ν/ν` with `ν = (n − 1)·u` (the number of
//!   independent Fourier components in the band), so `q = χ²_ν⁻¹(LEVEL)/ν`.
//! * Quantisation Q (white angle noise of standard deviation Q: rate PSD
//!   `(Q²/t0)·4 sin²(πf t0)`): `a = (2/t0²)(u − sin(πu)/π)` (`2Q²/t0²` for `u = 1`), `q` as for
//!   N. In the fit's filter mode the `1/τ²` column is the net of quantisation and a sensor
//!   filter (it may be negative) and is not counted (`a = 0`).
//! * **A sensor filter seen by the fit** (the `1/τ²` column in its filter mode, `fit` module
//!   docs): the filter's gain inside the band is not known, and a low-pass filter removes
//!   white-noise variance that the Allan curve at τ ≥ τ_lo does not show (a 6-tap average at
//!   `τ_lo = 6 t0` passes only 0.4 of the power at `f_hi`): N and Q are then not counted
//!   (`a = 0`), and B only over the band up to `f_hi/4`, where such filters pass ≥ 0.9 of the
//!   power. Counting N there would pull N below the data's white noise and push the other
//!   terms up to compensate (measured: it changed filtered fits whose terms were well inside
//!   the data's variance).
//! * Bias instability B (flicker, two-sided PSD `B²/(2π|f|)`): its variance diverges
//!   logarithmically at both ends of the band, so it is bounded only over the band the record
//!   and the fit resolve. Removing the sample mean weights the PSD by `1 − F(f)` with the Fejér
//!   kernel `F(f) = (sin(πfT)/(n sin(πft0)))² ≤ 1/(2fT)² ≤ 1/4` for `f ≥ 1/T` (from
//!   `sin x ≥ 2x/π`), so `a ≥ (3/4)·(1/π)·ln(T/(2τ_lo))` (0 for `T ≤ 2τ_lo`) — a lower bound
//!   of its expected contribution, not the divergent total. Its sample variance is a sum of
//!   independent χ²₂ components weighted `1/k` (`k = 1 … K`, `K = T/(2τ_lo)`), whose
//!   Satterthwaite degrees of freedom are `ν = 2(Σ1/k)²/Σ1/k² ≥ 2·H_K²/(π²/6)`.
//! * Rate random walk K (the rate is a Wiener process `K·W(t)`): the expected sample variance
//!   about the mean of `n` samples of a random walk with step variance `K²t0` is
//!   `K²t0(n² − 1)/(6n)` (`K²T/6`: `E∫(W − W̄)² = T²/6`), minus the part above the band,
//!   `2∫_{f_hi}^∞ K²/(2πf)² df = K²τ_lo/π²`. Its realisation scatters widely: `∫(W − W̄)²` of a
//!   standard Wiener process on [0, 1] is `Σ_k Z_k²/(πk)²` (Karhunen–Loève of the demeaned
//!   process), whose 0.1 % quantile is 0.1005 of its mean (Monte Carlo, 2·10⁶ draws; see the
//!   test); `q` = [`RANDOM_WALK_QUANTILE`] = 0.10, i.e. K is limited to `K²T/6 ≤ 10·V`.
//! * Gauss–Markov `(q², T_c)`: the stationary variance `q²` within the band
//!   (`(2/π)·atan(πT_c/τ_lo)` of it) minus the variance of the sample mean
//!   (`2q²(x − 1 + e^{−x})/x²`, `x = T/T_c`); `q` as for the random walk, which it becomes for
//!   `T_c ≫ T` and whose sample variance scatters the most.

use super::fit::InverseSquare;
use super::model::Term;

/// Probability, per term, that a true term's sample variance falls below `q_j` times its
/// expectation (the one-sided level of the slack).
pub const LEVEL: f64 = 1e-3;

/// The 0.1 % quantile of the sample variance of a random walk (or a Wiener process) relative
/// to its expectation, rounded down: `Σ_k Z_k²/(πk)² / (1/6)` has quantile 0.1005 (module docs).
pub const RANDOM_WALK_QUANTILE: f64 = 0.10;

/// The constraint of one fit: the data's variance and what each term implies.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Limit {
    /// The data's variance `V` (rate unit²).
    pub variance: f64,
    /// Number of rate samples `n`.
    pub n: usize,
    /// Sample period `t0` (s).
    pub t0: f64,
    /// Shortest τ the fit uses (s).
    pub tau_lo: f64,
    /// The χ² quantiles of [`Limit::term`], computed once in [`Limit::new`] (a fit asks for
    /// the weights at every step of its profile and each quantile of a large `ν` costs ~10⁴
    /// series terms): `q` of the white terms, and `(a, q)` of bias instability without and
    /// with a sensor filter.
    white_q: f64,
    flicker: [(f64, f64); 2],
}

/// `χ²_ν⁻¹(LEVEL)/ν`: the lower quantile of a sample variance with `ν` degrees of freedom
/// relative to its expectation.
fn chi2_quantile(nu: f64) -> f64 {
    if !(nu.is_finite() && nu > 0.0) {
        return RANDOM_WALK_QUANTILE;
    }
    crate::stats::chi2_ppf(LEVEL, nu).map_or(RANDOM_WALK_QUANTILE, |x| (x / nu).clamp(0.0, 1.0))
}

/// `Σ_{k=0}^{n−1} e^{iθk}` as `(re, im)`.
fn dirichlet(theta: f64, n: f64) -> (f64, f64) {
    let half = (theta / 2.0).sin();
    let mag = if half.abs() < 1e-300 {
        n
    } else {
        (n * theta / 2.0).sin() / half
    };
    let phase = theta * (n - 1.0) / 2.0;
    (mag * phase.cos(), mag * phase.sin())
}

impl Limit {
    /// A limit from a known, finite, positive data variance; `None` otherwise.
    pub fn new(variance: Option<f64>, n: usize, t0: f64, tau_lo: f64) -> Option<Limit> {
        let variance = variance?;
        (variance.is_finite() && variance > 0.0 && n >= 2 && t0 > 0.0 && tau_lo >= t0).then(|| {
            let mut limit = Limit {
                variance,
                n,
                t0,
                tau_lo,
                white_q: f64::NAN,
                flicker: [(f64::NAN, f64::NAN); 2],
            };
            limit.white_q = chi2_quantile(((n - 1) as f64 * limit.u()).max(1.0));
            limit.flicker = [limit.flicker_term(false), limit.flicker_term(true)];
            limit
        })
    }

    fn u(&self) -> f64 {
        (self.t0 / self.tau_lo).min(1.0)
    }

    fn record(&self) -> f64 {
        self.n as f64 * self.t0
    }

    /// Quantile `q` of the white components (N, Q) in the band (computed in [`Limit::new`]).
    fn white_quantile(&self) -> f64 {
        self.white_q
    }

    /// `(a, q)` of bias instability (module docs); `filtered`: the fit models a sensor filter.
    fn flicker_term(&self, filtered: bool) -> (f64, f64) {
        let top = if filtered { 4.0 } else { 1.0 };
        let k = self.record() / (2.0 * top * self.tau_lo);
        if k <= 1.0 {
            return (0.0, 1.0);
        }
        let a = 0.75 / std::f64::consts::PI * k.ln();
        let harmonic = k.ln() + 0.577_215_664_901_532_9;
        let nu = 2.0 * harmonic * harmonic / (std::f64::consts::PI.powi(2) / 6.0);
        (a, chi2_quantile(nu))
    }

    /// `(a, q)` of a power-law term (module docs); `filtered`: the fit models a sensor filter.
    pub fn term(&self, t: Term, filtered: bool) -> (f64, f64) {
        let (n, t0, u) = (self.n as f64, self.t0, self.u());
        if filtered && matches!(t, Term::Quantization | Term::AngleRandomWalk) {
            return (0.0, 1.0);
        }
        match t {
            Term::Quantization => (
                2.0 / (t0 * t0) * (u - (std::f64::consts::PI * u).sin() / std::f64::consts::PI),
                self.white_quantile(),
            ),
            Term::AngleRandomWalk => (1.0 / self.tau_lo, self.white_quantile()),
            Term::BiasInstability => self.flicker[usize::from(filtered)],
            Term::RateRandomWalk => {
                let a = t0 * (n * n - 1.0) / (6.0 * n) - self.tau_lo / std::f64::consts::PI.powi(2);
                (a.max(0.0), RANDOM_WALK_QUANTILE)
            }
            Term::RateRamp => (t0 * t0 * (n * n - 1.0) / 12.0, 1.0),
        }
    }

    /// `(a, q)` of a Gauss–Markov term of correlation time `tc` (module docs).
    pub fn gauss_markov(&self, tc: f64) -> (f64, f64) {
        let x = self.record() / tc;
        let mean_part = if x < 1e-3 {
            1.0 - x / 3.0
        } else {
            2.0 * (x + (-x).exp_m1()) / (x * x)
        };
        let band = 2.0 / std::f64::consts::PI * (std::f64::consts::PI * tc / self.tau_lo).atan();
        ((band - mean_part).max(0.0), RANDOM_WALK_QUANTILE)
    }

    /// `(a, q)` of a sinusoid at `f` Hz: the smallest variance over its phase of `n` samples of
    /// a unit-amplitude sine, `λ_min` of the sampled `(cos, sin)` covariance (module docs).
    pub fn line(&self, f: f64) -> (f64, f64) {
        let n = self.n as f64;
        let theta = 2.0 * std::f64::consts::PI * f * self.t0;
        let (c, s) = dirichlet(theta, n);
        let (c2, s2) = dirichlet(2.0 * theta, n);
        let (mc, ms) = (c / n, s / n);
        let cc = 0.5 + c2 / (2.0 * n) - mc * mc;
        let ss = 0.5 - c2 / (2.0 * n) - ms * ms;
        let cs = s2 / (2.0 * n) - mc * ms;
        let half_trace = f64::midpoint(cc, ss);
        let radius = (((cc - ss) / 2.0).powi(2) + cs * cs).sqrt();
        ((half_trace - radius).clamp(0.0, 0.5), 1.0)
    }

    /// The constraint's weights `q_j·a_j` for [`super::fit::design`]'s columns: the requested
    /// power-law terms, Gauss–Markov terms at `ts`, sinusoids at `fl`. The `1/τ²` column counts
    /// only as quantisation ([`InverseSquare::Quantization`]).
    pub(crate) fn weights(
        &self,
        requested: &[Term],
        ts: &[f64],
        fl: &[f64],
        q: InverseSquare,
    ) -> Vec<f64> {
        let filtered = q != InverseSquare::Quantization;
        let mut w: Vec<f64> = requested
            .iter()
            .map(|&t| {
                let (a, q) = self.term(t, filtered);
                a * q
            })
            .collect();
        w.extend(ts.iter().map(|&t| {
            let (a, q) = self.gauss_markov(t);
            a * q
        }));
        w.extend(fl.iter().map(|&f| {
            let (a, q) = self.line(f);
            a * q
        }));
        w
    }

    /// `Σ q_j a_j c_j` of a fitted model (power-law `c`, Gauss–Markov `(q², T)`, sinusoids
    /// `(Ω₀², f₀)`): the share of the data's variance the model claims at the least.
    /// `filtered`: the fit models a sensor filter (module docs).
    pub fn claimed(
        &self,
        c: &[f64; 5],
        gm: &[(f64, f64)],
        lines: &[(f64, f64)],
        filtered: bool,
    ) -> f64 {
        let mut total = 0.0;
        for t in Term::ALL {
            let v = c[t.index()];
            if v > 0.0 {
                let (a, q) = self.term(t, filtered);
                total += a * q * v;
            }
        }
        for &(q2, tc) in gm {
            let (a, q) = self.gauss_markov(tc);
            total += a * q * q2;
        }
        for &(a2, f) in lines {
            let (a, q) = self.line(f);
            total += a * q * a2;
        }
        total
    }
}

/// The variance `Σ(v − v̄)²/n` of rate samples (NumPy's `var`), as the Allan kernels compute
/// it ([`crate::allan::Moments`]: centred sums, corrected, of the data scaled by a power of two
/// when extreme); `None` for fewer than two samples or non-finite data.
pub fn sample_variance(rate: &[f64]) -> Option<f64> {
    if rate.len() < 2 || rate.iter().any(|v| !v.is_finite()) {
        return None;
    }
    let peak = rate.iter().fold(0.0_f64, |p, v| p.max(v.abs()));
    let k = crate::allan::scale_exponent(peak);
    let factor = crate::allan::ldexp(1.0, -k);
    let n = rate.len() as f64;
    let mean = crate::validate::neumaier_sum(rate.iter().map(|v| v * factor)) / n;
    let s1 = crate::validate::neumaier_sum(rate.iter().map(|v| v * factor - mean));
    let s2 = crate::validate::neumaier_sum(rate.iter().map(|v| (v * factor - mean).powi(2)));
    let m2 = (s2 - s1 * s1 / n).max(0.0);
    Some(crate::allan::ldexp(m2 / n, 2 * k))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn limit(n: usize) -> Limit {
        Limit::new(Some(1.0), n, 0.01, 0.01).unwrap()
    }

    #[test]
    fn sine_variance_is_the_smallest_over_phase() {
        // Reference: the sample variance of sin(2πf t + φ) over a fine grid of phases.
        let l = Limit::new(Some(1.0), 257, 0.01, 0.01).unwrap();
        for f in [0.3, 1.7, 23.0, 49.0, 50.0] {
            let (a, q) = l.line(f);
            assert_eq!(q, 1.0);
            let mut least = f64::INFINITY;
            for p in 0..2000 {
                let phi = p as f64 * std::f64::consts::PI / 1000.0;
                let x: Vec<f64> = (0..257)
                    .map(|i| (2.0 * std::f64::consts::PI * f * i as f64 * 0.01 + phi).sin())
                    .collect();
                let mean = x.iter().sum::<f64>() / 257.0;
                let v = x.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / 257.0;
                least = least.min(v);
            }
            // The phase grid (π/1000) finds the minimum to ~(π/1000)² relative.
            assert!((a - least).abs() < 1e-5, "{f}: {a} vs {least}");
        }
        // Many periods: A²/2.
        assert!((limit(100_000).line(23.0).0 - 0.5).abs() < 1e-4);
    }

    #[test]
    fn ramp_and_random_walk_expectations() {
        let l = limit(1000);
        // Sampled ramp i·t0: variance t0²(n²−1)/12 exactly.
        let x: Vec<f64> = (0..1000).map(|i| i as f64 * 0.01).collect();
        let mean = x.iter().sum::<f64>() / 1000.0;
        let v = x.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / 1000.0;
        assert!((l.term(Term::RateRamp, false).0 - v).abs() < 1e-12 * v);
        // Random walk: t0(n²−1)/(6n) minus the part above the band.
        let (a, q) = l.term(Term::RateRandomWalk, false);
        let expected = 0.01 * (1e6 - 1.0) / 6000.0 - 0.01 / std::f64::consts::PI.powi(2);
        assert!((a - expected).abs() < 1e-12);
        assert_eq!(q, RANDOM_WALK_QUANTILE);
    }

    #[test]
    fn white_noise_counts_its_band() {
        let full = limit(10_000);
        assert!((full.term(Term::AngleRandomWalk, false).0 - 100.0).abs() < 1e-12);
        assert!((full.term(Term::Quantization, false).0 - 2.0 / 1e-4).abs() < 1e-6);
        let q = full.term(Term::AngleRandomWalk, false).1;
        // χ²_ν lower 0.1 % quantile / ν ≈ 1 − 3.09·√(2/ν) for large ν.
        assert!(
            (q - (1.0 - 3.09 * (2.0 / 9999.0_f64).sqrt())).abs() < 3e-3,
            "{q}"
        );
        let band = Limit::new(Some(1.0), 10_000, 0.01, 0.04).unwrap();
        assert!((band.term(Term::AngleRandomWalk, false).0 - 25.0).abs() < 1e-12);
        // A sensor filter: white noise and quantisation are not bounded by the variance.
        assert_eq!(band.term(Term::AngleRandomWalk, true).0, 0.0);
        assert_eq!(band.term(Term::Quantization, true).0, 0.0);
        let b = Term::BiasInstability;
        assert!(band.term(b, true).0 < band.term(b, false).0);
    }
}
