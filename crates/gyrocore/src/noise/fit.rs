//! Joint identification: weighted non-negative least squares of the noise model (SPEC §3),
//! with first-order Gauss–Markov terms, goodness-of-fit diagnostics and automatic selection of
//! the τ range the model explains.
//!
//! The model `σ²(τ) = Σ_j c_j g_j(τ) + Σ_k q_k² g_GM(τ; T_k)` is linear in
//! `c = (Q², N², B², K², R²) ≥ 0` and in the Gauss–Markov variances `q_k² ≥ 0`
//! ([`super::gauss_markov`]); the correlation times `T_k` enter non-linearly and are profiled out
//! (for fixed weights: a log-spaced grid over the search range — by default `[5 τ_lo, τ_hi/5]`,
//! where a Gauss–Markov term can neither imitate a sensor filter's roll-off at the shortest τ nor
//! pass for a random walk at the longest — then golden-section refinement in
//! `ln T`; for two terms a grid over ordered pairs and alternating refinement). Each estimate
//! `σ̂²_i` has relative standard deviation `√(2/edf_i)` (chi-square with `edf_i` degrees of
//! freedom), so the weights are `w_i = edf_i / (2 σ²_i²)`. Weighting by the *observed* `σ̂²_i`
//! favours low estimates (a known downward bias), so the weights use the fitted model instead,
//! by iteratively reweighted least squares (first pass: observed values; then the previous
//! model, floored at 1 % of the observation; ≤ 50 passes, stop when the parameters change by
//! < 1e-10 relative).
//!
//! **Non-negativity** is exact: with few unknowns, if the unconstrained solution on all columns
//! is feasible it is the NNLS solution; otherwise every subset is solved unconstrained
//! (Householder QR of the column-scaled weighted design) and the feasible subset with the
//! smallest χ² is the NNLS solution (its KKT point is the unconstrained optimum on its passive
//! set). Subsets that leave no degree of freedom are not used.
//!
//! **Uncertainties**: the estimates at neighbouring τ are strongly correlated, so the
//! covariance of the parameters θ (active `c_j`, `q_k²`, `ln T_k`) is the sandwich
//! `(JᵀWJ)⁻¹ JᵀW V W J (JᵀWJ)⁻¹` with `J = ∂σ²/∂θ`, `V_ij = ρ_ij s_i s_j`,
//! `s_i = σ²_i √(2/edf_i)` and the correlation ρ of the fitted model's estimates
//! ([`super::covariance`]); it is inflated by `max(1, χ²/ν)` of the goodness-of-fit statistic
//! below when the model does not explain the scatter. For an amplitude `√c` the delta method
//! gives `u = u(c) / (2√c)`, for `T` it gives `u(T) = T·u(ln T)`.
//!
//! **Goodness of fit** ([`Diagnostics`]): the log-ratio residuals
//! `r_i = ln(σ̂²_i/σ²_i) − (ψ(ν_i/2) − ln(ν_i/2))` have variance `ψ'(ν_i/2)` under the model
//! (`σ̂²/σ² ~ χ²_ν/ν`; ψ the digamma function), and are far closer to Gaussian than `σ̂²` itself
//! at small ν. The standardised residuals are `z_i = r_i / √ψ'(ν_i/2)`; the statistic is the
//! generalised `χ² = zᵀ R⁻¹ z` with `R` the model correlation of the estimates, referred to the
//! chi-square law with `ν = points − fitted parameters` degrees of freedom (p-value = its
//! survival function). A fit with p < 0.001 is reported with a warning.
//!
//! **Automatic τ range** (when no range is given): (1) the longest-τ points whose EDF is below
//! [`MIN_EDF`] are excluded (a chi-square with fewer than 3 degrees of freedom spans more than a
//! factor 10 at 90 %, and such points are where non-stationary drift shows); (2) while the fit is
//! rejected (p < [`REFIT_P`]) the leading points up to the last one with `z < −2` before any
//! `z > 2` (within the first half; `leading_run`) (σ below the model at the shortest τ: a sensor's anti-alias/decimation filter correlates the samples and bends the
//! curve below the −½ line, which no positive term can follow) or the trailing run with `z > 2`
//! (σ above the model at long τ: drift the terms do not describe) is excluded and the model
//! refitted, keeping at least half of the points. What was excluded and why is recorded.
//!
//! **Sensor filter.** A sensor's anti-alias/decimation filter `h` (unity DC gain) correlates
//! the white rate noise: its autocovariance `r(k)` is `σ²·Σ_i h_i h_{i+k}`. For an averaging
//! length `m` beyond the filter's impulse response, the sums of `m` samples give exactly
//!
//! ```text
//! σ²_A(m) = [Var S_m − Cov(S_m, S'_m)]/m² = s₀/m − 3A/m²,   s₀ = Σ_k r(k),  A = Σ_{k≥1} k r(k),
//! ```
//!
//! i.e. `σ²(τ) = N²/τ·(1 − 3τ_c/τ)` with `N² = s₀ t0` and the filter's correlation time
//! `τ_c = t0·A/s₀` (the first moment of the normalised autocovariance; 0.05 t0 for a 31-tap FIR
//! at 0.8 Nyquist, 0.625 t0 for a 4-tap moving average). The filter leaves a *negative* `1/τ²`
//! term — the quantisation term's shape with the opposite sign — which lowers the Allan variance
//! by 3τ_c/τ relative (2 % at m = 8 for the FIR) well past the points it visibly bends; a fit
//! without it biases N low by about half that. So once the automatic range selection has
//! excluded a leading run (the filter's signature), the `1/τ²` column is refitted as the net of
//! quantisation and filter: sign-free when Q is requested, `≤ 0` when it is not
//! (`InverseSquare`); a negative net is reported as `Diagnostics::filter_correlation_time`
//! `τ_c = −c_Q/c_N` (uncertainty by the delta method) and Q as missing. Inside the filter's
//! length the law is not exact (a real filter's curve may sit above it there: pass-band
//! ripple, a long FIR's ringing), so in this mode the leading points up to the first with
//! `|z| > 2` are excluded too, one run per refit, while the fit is rejected (`transition`; also
//! before any filter is seen when the rejection is gross, `χ²/ν > 10`: `gross`). A first point
//! still inside the transition by less than its residual shows is caught by a Hausman test on
//! N² (`hausman_trim`). Spectral computations (correlations, EDF) use the noise
//! terms only (`spectral`): the correction is a few per cent of the white noise at the shortest
//! τ used.
//!
//! **EDF**: from noise identification when the caller has it (`Curve::edf`, capped at the
//! white-rate EDF, the most any rate noise supports: see `edf_given`), else SP1065's
//! simple approximations ([`super::model::approximate_edf`]) for the noise type of the term that
//! dominates the current model at each τ (white rate in the first pass; a Gauss–Markov term
//! counts as random walk below its correlation time and white noise above).

use nalgebra::DMatrix;

use super::covariance::correlation_with;
use super::curve::{Curve, TermEstimate};
use super::gauss_markov;
use super::model::{FLICKER_FACTOR, Term, approximate_edf, model_variance};
use super::sinusoid;
use super::variance_limit::Limit;
use crate::stats;
use crate::{Error, Result};

/// Smallest EDF of a long-τ point kept by the automatic range selection.
pub const MIN_EDF: f64 = 3.0;

/// p-value below which the automatic range selection trims systematic departures.
pub const REFIT_P: f64 = 0.01;

/// p-value below which a fit is reported as rejected.
pub const REJECT_P: f64 = 0.001;

/// One identified Gauss–Markov term (or why it is missing).
#[derive(Debug, Clone, PartialEq)]
pub struct GaussMarkovEstimate {
    /// Standard deviation `q` of the process (rate unit); `None` when missing.
    pub sigma: Option<f64>,
    /// Standard uncertainty of `sigma`.
    pub sigma_uncertainty: f64,
    /// Correlation time `T` (s); `None` when missing.
    pub correlation_time: Option<f64>,
    /// Standard uncertainty of `T` (s).
    pub correlation_time_uncertainty: f64,
    /// τ range (s) of the points where the term is ≥ 10 % of the model.
    pub tau_range: Option<(f64, f64)>,
    /// Why the term is missing.
    pub missing: Option<String>,
}

/// One fitted sinusoidal term (IEEE 952 "S", [`super::sinusoid`]).
#[derive(Debug, Clone, PartialEq)]
pub struct LineEstimate {
    /// Frequency `f₀` (Hz) after refinement in the fit.
    pub frequency: f64,
    /// Standard uncertainty of `frequency` (Hz; NaN when not available).
    pub frequency_uncertainty: f64,
    /// Amplitude `Ω₀` (rate unit); `None` when the fit set it to zero.
    pub amplitude: Option<f64>,
    /// Standard uncertainty of `amplitude`.
    pub amplitude_uncertainty: f64,
    /// τ range (s) of the points where the term is ≥ 10 % of the model.
    pub tau_range: Option<(f64, f64)>,
    /// Why the term is missing.
    pub missing: Option<String>,
}

/// Goodness-of-fit diagnostics of an identification (module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct Diagnostics {
    /// Generalised χ² of the log-ratio residuals.
    pub chi2: f64,
    /// Degrees of freedom (points used − fitted parameters).
    pub dof: usize,
    /// Chi-square survival function of `chi2` (NaN without degrees of freedom).
    pub p_value: f64,
    /// Standardised residual of every curve point (NaN where the point was not used).
    pub residuals: Vec<f64>,
    /// τ range (s) of the points used.
    pub tau_range: (f64, f64),
    /// Excluded τ ranges (s) with the reason.
    pub excluded: Vec<(f64, f64, String)>,
    /// Plain sentences about anything the user must know before trusting the numbers.
    pub warnings: Vec<String>,
    /// The sensor filter's correlation time `τ_c` (s) and its standard uncertainty, when the
    /// automatic range selection saw a filter at the shortest τ and the fit modelled its
    /// `−3N²τ_c/τ²` (module docs, "Sensor filter"); `None` otherwise.
    pub filter_correlation_time: Option<(f64, f64)>,
    /// `(claimed, V)` when the fit was constrained by the data's variance `V`
    /// ([`super::variance_limit`]): `claimed = Σ q_j a_j c_j` of the fitted terms, `= V` when
    /// the limit is active (the terms are as large as the data allow); `None` without a known
    /// data variance.
    pub variance_limit: Option<(f64, f64)>,
}

/// Options of [`fit`].
#[derive(Debug, Clone, PartialEq)]
pub struct FitOptions {
    /// Which of the five power-law terms to fit, in [`Term::ALL`] order.
    pub enabled: [bool; 5],
    /// Number of Gauss–Markov terms (0, 1 or 2).
    pub gauss_markov: usize,
    /// Only use points with τ in this range (s); disables the automatic selection.
    pub tau_range: Option<(f64, f64)>,
    /// Search range (s) of the correlation times; default `[5 τ_lo, τ_hi/5]` of the points used.
    pub correlation_time: Option<(f64, f64)>,
    /// Select the τ range automatically (module docs) when `tau_range` is `None`.
    pub automatic_range: bool,
    /// Sinusoidal terms: `(seed frequency, half-width)` in Hz. Each adds the sampled-sine Allan
    /// variance `Ω₀² sin⁴(π f₀ τ)/(m sin(π f₀ t0))²` ([`super::sinusoid::avar`]) with `Ω₀² ≥ 0`
    /// linear and `f₀` refined within `seed ± half-width` (profiled, golden section).
    pub lines: Vec<(f64, f64)>,
    /// One-sided confidence level of the upper bounds of the terms the fit sets to zero
    /// ([`super::bound`]; default [`super::BOUND_CONFIDENCE`]).
    pub bound_confidence: f64,
    /// The variance of the data the curve was computed from (rate unit²,
    /// [`crate::allan::AllanAnalysis::data_variance`]): every fitted term is kept within what
    /// it allows ([`super::variance_limit`]); `None` fits without that constraint.
    pub data_variance: Option<f64>,
}

impl Default for FitOptions {
    fn default() -> Self {
        FitOptions {
            enabled: [true; 5],
            gauss_markov: 0,
            tau_range: None,
            correlation_time: None,
            automatic_range: true,
            lines: Vec::new(),
            bound_confidence: super::bound::BOUND_CONFIDENCE,
            data_variance: None,
        }
    }
}

/// Result of [`joint`] / [`fit`].
#[derive(Debug, Clone, PartialEq)]
pub struct JointFit {
    /// One estimate per term in [`Term::ALL`] order.
    pub terms: Vec<TermEstimate>,
    /// Squared coefficients `c` (zero for terms not in the solution).
    pub squared: [f64; 5],
    /// Covariance of `c` (after the χ² inflation).
    pub covariance: [[f64; 5]; 5],
    /// Fitted Gauss–Markov components `(q², T)`, sorted by `T` (q² = 0 when dropped).
    pub gauss_markov_squared: Vec<(f64, f64)>,
    /// The Gauss–Markov terms as reported.
    pub gauss_markov: Vec<GaussMarkovEstimate>,
    /// Fitted sinusoidal components `(Ω₀², f₀)`, in the order of [`FitOptions::lines`].
    pub lines_squared: Vec<(f64, f64)>,
    /// The sinusoidal terms as reported.
    pub lines: Vec<LineEstimate>,
    /// Weighted residual sum of squares of the least-squares fit.
    pub chi2: f64,
    /// Degrees of freedom `points − fitted parameters`.
    pub dof: usize,
    /// τ range of the points used (s).
    pub tau_range: (f64, f64),
    /// Indices of the curve points used.
    pub used: Vec<usize>,
    /// EDF used for each point of `used`.
    pub edf: Vec<f64>,
    /// IRLS passes made.
    pub iterations: usize,
    /// Goodness of fit, range selection and warnings.
    pub diagnostics: Diagnostics,
}

/// Minimum share of the model variance at which a point counts towards a term's τ range.
const SHARE: f64 = 0.1;

/// `x` with `digits` significant digits (like Python's `g` format).
pub(crate) fn sig(x: f64, digits: usize) -> String {
    if !x.is_finite() || x == 0.0 {
        return format!("{x}");
    }
    let e = x.abs().log10().floor() as i32;
    if (-4..6).contains(&e) {
        let decimals = (digits as i32 - 1 - e).max(0) as usize;
        format!("{x:.decimals$}")
    } else {
        format!("{:.*e}", digits.saturating_sub(1), x)
    }
}

/// Model variance of the power-law terms plus Gauss–Markov components.
pub fn full_model(c: &[f64; 5], gm: &[(f64, f64)], tau: f64) -> f64 {
    model_variance(c, tau)
        + gm.iter()
            .map(|&(q2, t)| q2 * gauss_markov::basis(t, tau))
            .sum::<f64>()
}

/// Sampling period of a curve (`τ_i / m_i` of its first point).
pub(crate) fn curve_t0(curve: &Curve<'_>) -> f64 {
    curve.taus[0] / curve.m[0] as f64
}

/// Model variance of power-law, Gauss–Markov and sinusoidal (`(Ω₀², f₀)`, period `t0`) terms.
pub fn model_with_lines(
    c: &[f64; 5],
    gm: &[(f64, f64)],
    lines: &[(f64, f64)],
    t0: f64,
    tau: f64,
) -> f64 {
    full_model(c, gm, tau)
        + lines
            .iter()
            .map(|&(a2, f)| a2 * sinusoid::basis(f, t0, tau))
            .sum::<f64>()
}

/// Where a point lies against the model, for an exclusion's reason: `σ² − model` at `tau`.
/// Below 3τ_c a modelled filter's `N²/τ·(1 − 3τ_c/τ)` is negative and has no meaning (module
/// docs, "Sensor filter"); there the model without the filter's `1/τ²` term is the reference,
/// the white-noise line the filter bends the curve below.
pub(crate) fn side(
    variance: f64,
    c: &[f64; 5],
    gm: &[(f64, f64)],
    lines: &[(f64, f64)],
    t0: f64,
    tau: f64,
) -> f64 {
    let mut c = *c;
    if c[0] < 0.0 && c[1] * tau + 3.0 * c[0] < 0.0 {
        c[0] = 0.0;
    }
    variance - model_with_lines(&c, gm, lines, t0, tau)
}

/// The sides of the used points for [`trim_ends`]' reason: the standardised residuals `z`,
/// except where a modelled filter's law is invalid (τ < 3τ_c, see [`side`]), where the point
/// counts as departing (±∞) on its side of the model without the filter term.
pub(crate) fn sides(
    curve: &Curve<'_>,
    used: &[usize],
    c: &[f64; 5],
    gm: &[(f64, f64)],
    lines: &[(f64, f64)],
    z: &[f64],
) -> Vec<f64> {
    let t0 = curve_t0(curve);
    used.iter()
        .zip(z)
        .map(|(&i, &v)| {
            let tau = curve.taus[i];
            if c[0] < 0.0 && c[1] * tau + 3.0 * c[0] < 0.0 {
                let d = side(curve.variance[i], c, gm, lines, t0, tau);
                if d > 0.0 {
                    f64::INFINITY
                } else {
                    f64::NEG_INFINITY
                }
            } else {
                v
            }
        })
        .collect()
}

/// Digamma ψ(x) for x > 0 (recurrence to x ≥ 6, then the asymptotic series; error < 1e-13).
pub(crate) fn digamma(mut x: f64) -> f64 {
    let mut acc = 0.0;
    while x < 6.0 {
        acc -= 1.0 / x;
        x += 1.0;
    }
    let r = 1.0 / (x * x);
    acc + x.ln()
        - 0.5 / x
        - r * (1.0 / 12.0 - r * (1.0 / 120.0 - r * (1.0 / 252.0 - r * (1.0 / 240.0 - r / 132.0))))
}

/// Trigamma ψ'(x) for x > 0 (recurrence to x ≥ 6, then the asymptotic series).
pub(crate) fn trigamma(mut x: f64) -> f64 {
    let mut acc = 0.0;
    while x < 6.0 {
        acc += 1.0 / (x * x);
        x += 1.0;
    }
    let r = 1.0 / (x * x);
    acc + 1.0 / x
        + r / 2.0
        + (r / x)
            * (1.0 / 6.0 - r * (1.0 / 30.0 - r * (1.0 / 42.0 - r * (1.0 / 30.0 - r * 5.0 / 66.0))))
}

/// How the design and data are whitened before the least-squares solve.
pub(crate) enum Whitener<'a> {
    /// Diagonal weights `√w_i`.
    Diagonal(&'a [f64]),
    /// Inverse of a lower Cholesky factor: solve `L x = v` (GLS).
    Cholesky(&'a DMatrix<f64>),
}

impl Whitener<'_> {
    pub(crate) fn apply(&self, v: &[f64]) -> Vec<f64> {
        match self {
            Whitener::Diagonal(w) => v.iter().zip(w.iter()).map(|(a, b)| a * b).collect(),
            Whitener::Cholesky(l) => {
                let n = v.len();
                let mut x = v.to_vec();
                for i in 0..n {
                    let mut s = x[i];
                    for k in 0..i {
                        s -= l[(i, k)] * x[k];
                    }
                    x[i] = s / l[(i, i)];
                }
                x
            }
        }
    }
}

/// Unconstrained least squares of whitened `b` on whitened columns `a` (Householder QR of the
/// column-scaled design); `None` if singular or without a degree of freedom.
/// Returns (coefficients, χ²).
fn solve_whitened(mut a: Vec<Vec<f64>>, mut b: Vec<f64>) -> Option<(Vec<f64>, f64)> {
    let n = b.len();
    let p = a.len();
    if p == 0 || n <= p {
        return None;
    }
    let scale: Vec<f64> = a
        .iter()
        .map(|col| col.iter().map(|v| v * v).sum::<f64>().sqrt())
        .collect();
    if scale.iter().any(|s| !(s.is_finite() && *s > 0.0)) {
        return None;
    }
    for (col, s) in a.iter_mut().zip(&scale) {
        for v in col.iter_mut() {
            *v /= s;
        }
    }
    let mut r = vec![vec![0.0; p]; p];
    for j in 0..p {
        let norm = a[j][j..].iter().map(|v| v * v).sum::<f64>().sqrt();
        if norm == 0.0 {
            return None;
        }
        let alpha = if a[j][j] > 0.0 { -norm } else { norm };
        let mut v: Vec<f64> = a[j][j..].to_vec();
        v[0] -= alpha;
        let vnorm2: f64 = v.iter().map(|x| x * x).sum();
        if vnorm2 > 0.0 {
            for col in a.iter_mut().skip(j) {
                let dot: f64 = v.iter().zip(&col[j..]).map(|(x, y)| x * y).sum();
                let f = 2.0 * dot / vnorm2;
                for (c, x) in col[j..].iter_mut().zip(&v) {
                    *c -= f * x;
                }
            }
            let dot: f64 = v.iter().zip(&b[j..]).map(|(x, y)| x * y).sum();
            let f = 2.0 * dot / vnorm2;
            for (c, x) in b[j..].iter_mut().zip(&v) {
                *c -= f * x;
            }
        }
        for i in 0..=j {
            r[i][j] = a[j][i];
        }
    }
    // Columns have unit norm, so |r_jj| is a direct measure of the loss of rank.
    if r.iter().enumerate().any(|(j, row)| row[j].abs() < 1e-10) {
        return None;
    }
    let mut z = vec![0.0; p];
    for j in (0..p).rev() {
        let s: f64 = (j + 1..p).map(|k| r[j][k] * z[k]).sum();
        z[j] = (b[j] - s) / r[j][j];
    }
    let chi2 = b[p..].iter().map(|v| v * v).sum::<f64>().max(0.0);
    if !chi2.is_finite() {
        return None;
    }
    Some((z.iter().zip(&scale).map(|(z, s)| z / s).collect(), chi2))
}

/// Exact NNLS of `y` on the basis `columns` (values at the points) under `whitener`.
/// Returns the coefficient of every column (0 when inactive) and χ².
///
/// The column `free` (if any) is not sign-constrained: it is in every candidate passive set
/// (its KKT condition is a zero gradient), and only the other coefficients must be ≥ 0.
///
/// With `limit = (w, V)` the coefficients also satisfy `w·c ≤ V` (the data's variance,
/// [`super::variance_limit`]): the problem stays a convex quadratic programme, whose optimum is
/// the unconstrained optimum on some passive set either with the limit inactive or on the
/// hyperplane `w·c = V` (the equality-constrained least squares
/// `c = ĉ − G⁻¹w (w·ĉ − V)/(wᵀG⁻¹w)`, `χ² = χ̂² + (w·ĉ − V)²/(wᵀG⁻¹w)`, `G = AᵀA`); every
/// feasible candidate is examined and the smallest χ² wins. When the unconstrained NNLS
/// solution satisfies the limit it is returned unchanged (the same code path as without it).
pub(crate) fn nnls(
    columns: &[Vec<f64>],
    y: &[f64],
    whitener: &Whitener<'_>,
    free: Option<usize>,
    limit: Option<(&[f64], f64)>,
) -> Option<(Vec<f64>, f64)> {
    let wa: Vec<Vec<f64>> = columns.iter().map(|c| whitener.apply(c)).collect();
    let wb = whitener.apply(y);
    let p = columns.len();
    let feasible = |idx: &[usize], coef: &[f64]| {
        idx.iter()
            .zip(coef)
            .all(|(&k, v)| *v >= 0.0 || Some(k) == free)
    };
    // Relative tolerance of the limit (rounding of the constrained solve).
    let within = |idx: &[usize], coef: &[f64]| match limit {
        Some((w, v)) => {
            idx.iter().zip(coef).map(|(&k, c)| w[k] * c).sum::<f64>() <= v * (1.0 + 1e-9)
        }
        None => true,
    };
    let all: Vec<usize> = (0..p).collect();
    let unconstrained = solve_whitened(wa.clone(), wb.clone());
    if let Some((coef, chi2)) = &unconstrained {
        if feasible(&all, coef) && within(&all, coef) {
            return Some((coef.clone(), *chi2));
        }
    }
    let mut best: Option<(Vec<f64>, f64)> = None;
    let mut consider = |idx: &[usize], coef: &[f64], chi2: f64| {
        if best.as_ref().is_none_or(|b| chi2 < b.1) {
            let mut full = vec![0.0; p];
            for (&k, v) in idx.iter().zip(coef) {
                full[k] = *v;
            }
            best = Some((full, chi2));
        }
    };
    for mask in 1u32..(1 << p) {
        let idx: Vec<usize> = (0..p).filter(|k| mask & (1 << k) != 0).collect();
        if free.is_some_and(|f| !idx.contains(&f)) {
            continue;
        }
        let sub: Vec<Vec<f64>> = idx.iter().map(|&k| wa[k].clone()).collect();
        let solved = if idx.len() == p {
            unconstrained.clone()
        } else {
            solve_whitened(sub.clone(), wb.clone())
        };
        let Some((coef, chi2)) = solved else {
            continue;
        };
        if idx.len() < p && feasible(&idx, &coef) && within(&idx, &coef) {
            consider(&idx, &coef, chi2);
        }
        if let Some((w, v)) = limit {
            let ws: Vec<f64> = idx.iter().map(|&k| w[k]).collect();
            if let Some((cc, x2)) = on_limit(&sub, &coef, chi2, &ws, v) {
                if feasible(&idx, &cc) {
                    consider(&idx, &cc, x2);
                }
            }
        }
    }
    best
}

/// The least squares on whitened columns `a` with unconstrained solution `coef` (χ² `chi2`)
/// restricted to the hyperplane `w·c = v` (see [`nnls`]); `None` when `w·coef ≤ v` already or
/// the constraint does not involve the columns.
fn on_limit(a: &[Vec<f64>], coef: &[f64], chi2: f64, w: &[f64], v: f64) -> Option<(Vec<f64>, f64)> {
    let excess = w.iter().zip(coef).map(|(w, c)| w * c).sum::<f64>() - v;
    if excess.is_nan() || excess <= 0.0 {
        return None;
    }
    let p = a.len();
    // Column-scaled Gram matrix (unit-norm columns), as solve_whitened scales the design.
    let scale: Vec<f64> = a
        .iter()
        .map(|col| col.iter().map(|x| x * x).sum::<f64>().sqrt())
        .collect();
    if scale.iter().any(|s| !(s.is_finite() && *s > 0.0)) {
        return None;
    }
    let g = DMatrix::from_fn(p, p, |i, j| {
        a[i].iter().zip(&a[j]).map(|(x, y)| x * y).sum::<f64>() / (scale[i] * scale[j])
    });
    let ws = nalgebra::DVector::from_fn(p, |i, _| w[i] / scale[i]);
    let z = g.lu().solve(&ws)?;
    let denom = ws.dot(&z);
    if !(denom.is_finite() && denom > 0.0) {
        return None;
    }
    let step = excess / denom;
    let out: Vec<f64> = (0..p).map(|i| coef[i] - z[i] * step / scale[i]).collect();
    let x2 = chi2 + excess * excess / denom;
    x2.is_finite().then_some((out, x2))
}

/// How the `1/τ²` column (the quantisation term's) enters the fit (module docs, "Sensor
/// filter"): as quantisation noise (`Q² ≥ 0`), or — once the automatic range selection has seen
/// a sensor filter at the shortest τ — as the net of quantisation and the filter's negative
/// `−3N²τ_c/τ²`: sign-free when Q is requested, `≤ 0` (the filter alone) when it is not.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) enum InverseSquare {
    /// Quantisation noise only: `c_Q ≥ 0`.
    #[default]
    Quantization,
    /// Quantisation and filter: `c_Q` of either sign.
    Net,
    /// Filter only (Q not requested): `c_Q ≤ 0`.
    Filter,
}

impl InverseSquare {
    /// The mode once a filter has been seen, for the requested terms; returns the terms with Q
    /// added when the filter needs its column.
    pub(crate) fn filtered(requested: &[Term]) -> (Vec<Term>, InverseSquare) {
        if requested.contains(&Term::Quantization) {
            (requested.to_vec(), InverseSquare::Net)
        } else {
            let mut terms = vec![Term::Quantization];
            terms.extend_from_slice(requested);
            (terms, InverseSquare::Filter)
        }
    }
}

/// Basis columns (values at `taus`) of the requested power-law terms, of GM terms at `ts` and
/// of sinusoids at frequencies `fl` (period `t0`). With [`InverseSquare::Filter`] the Q column
/// is negated (its non-negative coefficient is `−c_Q`).
pub(crate) fn design(
    taus: &[f64],
    requested: &[Term],
    ts: &[f64],
    fl: &[f64],
    t0: f64,
    q: InverseSquare,
) -> Vec<Vec<f64>> {
    let sign = |t: &Term| {
        if *t == Term::Quantization && q == InverseSquare::Filter {
            -1.0
        } else {
            1.0
        }
    };
    let mut cols: Vec<Vec<f64>> = requested
        .iter()
        .map(|t| taus.iter().map(|&tau| sign(t) * t.basis(tau)).collect())
        .collect();
    for &t in ts {
        cols.push(
            taus.iter()
                .map(|&tau| gauss_markov::basis(t, tau))
                .collect(),
        );
    }
    for &f in fl {
        cols.push(
            taus.iter()
                .map(|&tau| sinusoid::basis(f, t0, tau))
                .collect(),
        );
    }
    cols
}

/// Exact NNLS of `y` on [`design`]'s columns under the [`InverseSquare`] mode `q`, within the
/// data's variance when `limit` is given ([`super::variance_limit`]); returns the coefficients
/// with `c_Q` signed (negative for a filter) and χ².
#[allow(clippy::too_many_arguments)]
pub(crate) fn solve_design(
    taus: &[f64],
    y: &[f64],
    requested: &[Term],
    ts: &[f64],
    fl: &[f64],
    t0: f64,
    q: InverseSquare,
    whitener: &Whitener<'_>,
    limit: Option<&Limit>,
) -> Option<(Vec<f64>, f64)> {
    let qi = requested.iter().position(|t| *t == Term::Quantization);
    let free = if q == InverseSquare::Net { qi } else { None };
    let weights = limit.map(|l| l.weights(requested, ts, fl, q));
    let (mut coef, chi2) = nnls(
        &design(taus, requested, ts, fl, t0, q),
        y,
        whitener,
        free,
        weights.as_deref().zip(limit.map(|l| l.variance)),
    )?;
    if let (InverseSquare::Filter, Some(k)) = (q, qi) {
        coef[k] = -coef[k];
    }
    Some((coef, chi2))
}

/// Golden-section minimum of `f` over `[a, b]` (in `ln T` or Hz), 40 iterations.
fn golden(a: f64, b: f64, f: &mut dyn FnMut(f64) -> f64) -> (f64, f64) {
    crate::optimize::golden_section(a, b, 40, 0.0, f)
}

/// What [`profile_times`] returns: correlation times, line frequencies, coefficients, χ².
pub(crate) type Profiled = (Vec<f64>, Vec<f64>, Vec<f64>, f64);

/// Profiles the correlation times and line frequencies: the `ts` (ascending, within `bounds`)
/// and `fl` (each within its `lines` window `seed ± half-width`) minimising the NNLS χ² for fixed
/// whitening, with the coefficients there (power-law, then GM, then line columns).
#[allow(clippy::too_many_arguments)]
pub(crate) fn profile_times(
    taus: &[f64],
    y: &[f64],
    requested: &[Term],
    n_gm: usize,
    bounds: (f64, f64),
    whitener: &Whitener<'_>,
    lines: &[(f64, f64)],
    t0: f64,
    q: InverseSquare,
    limit: Option<&Limit>,
) -> Option<Profiled> {
    let eval = |ts: &[f64], fl: &[f64]| -> f64 {
        solve_design(taus, y, requested, ts, fl, t0, q, whitener, limit)
            .map_or(f64::INFINITY, |s| s.1)
    };
    let mut fl: Vec<f64> = lines.iter().map(|l| l.0).collect();
    let search_times = |fl: &[f64]| -> Option<Vec<f64>> {
        let (lo, hi) = (bounds.0.ln(), bounds.1.ln());
        Some(match n_gm {
            0 => Vec::new(),
            1 => {
                let k = 24;
                let grid: Vec<f64> = (0..=k)
                    .map(|i| lo + (hi - lo) * i as f64 / k as f64)
                    .collect();
                let values: Vec<f64> = grid.iter().map(|&g| eval(&[g.exp()], fl)).collect();
                let best = (0..=k).min_by(|&a, &b| values[a].total_cmp(&values[b]))?;
                let a = grid[best.saturating_sub(1)];
                let b = grid[(best + 1).min(k)];
                let (x, fx) = golden(a, b, &mut |x| eval(&[x.exp()], fl));
                vec![if fx <= values[best] { x } else { grid[best] }.exp()]
            }
            _ => {
                let k = 14;
                let grid: Vec<f64> = (0..=k)
                    .map(|i| lo + (hi - lo) * i as f64 / k as f64)
                    .collect();
                let mut best = (0, 1, f64::INFINITY);
                for i in 0..k {
                    for j in i + 1..=k {
                        let v = eval(&[grid[i].exp(), grid[j].exp()], fl);
                        if v < best.2 {
                            best = (i, j, v);
                        }
                    }
                }
                let mut t1 = grid[best.0];
                let mut t2 = grid[best.1];
                let step = (hi - lo) / k as f64;
                for _ in 0..3 {
                    let (x, _) = golden((t1 - step).max(lo), (t1 + step).min(t2), &mut |x| {
                        eval(&[x.exp(), t2.exp()], fl)
                    });
                    t1 = x;
                    let (x, _) = golden((t2 - step).max(t1), (t2 + step).min(hi), &mut |x| {
                        eval(&[t1.exp(), x.exp()], fl)
                    });
                    t2 = x;
                }
                vec![t1.exp(), t2.exp()]
            }
        })
    };
    let mut ts = search_times(&fl)?;
    if !lines.is_empty() {
        // Each frequency: a grid over its window (the χ² is oscillatory in f₀ at long τ), then
        // golden section around the best node; two sweeps over the lines, then the times again.
        for _ in 0..2 {
            for (k, &(seed, half)) in lines.iter().enumerate() {
                if half <= 0.0 {
                    continue;
                }
                let nodes = 16;
                let (a, b) = (seed - half, seed + half);
                let mut best = (fl[k], eval(&ts, &fl));
                for i in 0..=nodes {
                    let f = a + (b - a) * i as f64 / nodes as f64;
                    let mut trial = fl.clone();
                    trial[k] = f;
                    let v = eval(&ts, &trial);
                    if v < best.1 {
                        best = (f, v);
                    }
                }
                let width = (b - a) / nodes as f64;
                let (x, fx) = golden((best.0 - width).max(a), (best.0 + width).min(b), &mut |f| {
                    let mut trial = fl.clone();
                    trial[k] = f;
                    eval(&ts, &trial)
                });
                fl[k] = if fx <= best.1 { x } else { best.0 };
            }
            if n_gm > 0 {
                ts = search_times(&fl)?;
            }
        }
    }
    let (coef, chi2) = solve_design(taus, y, requested, &ts, &fl, t0, q, whitener, limit)?;
    Some((ts, fl, coef, chi2))
}

/// EDF of point `i` under the model `(c, gm, lines)`: the caller's, else SP1065's approximation
/// for the noise type that dominates there (a sinusoid counts as white rate noise: its estimate
/// varies less than a noise's of the same variance, so this is conservative).
pub(crate) fn edf_model(
    curve: &Curve<'_>,
    i: usize,
    c: &[f64; 5],
    gm: &[(f64, f64)],
    lines: &[(f64, f64)],
) -> f64 {
    if curve.edf.is_some() {
        return edf_given(curve, i);
    }
    let tau = curve.taus[i];
    let mut alpha = 0;
    let mut best = 0.0;
    for t in Term::ALL {
        let v = c[t.index()] * t.basis(tau);
        if v > best {
            best = v;
            alpha = t.alpha();
        }
    }
    for &(q2, t) in gm {
        let v = q2 * gauss_markov::basis(t, tau);
        if v > best {
            best = v;
            alpha = if tau < t { -2 } else { 0 };
        }
    }
    let t0 = curve_t0(curve);
    for &(a2, f) in lines {
        if a2 * sinusoid::basis(f, t0, tau) > best {
            best = a2 * sinusoid::basis(f, t0, tau);
            alpha = 0;
        }
    }
    approximate_edf(curve.n_phase(), curve.m[i], alpha)
}

/// The caller's EDF of point `i`, capped at what the record can support for rate noise: the
/// white-rate EDF of SP1065's approximation (≈ 1.5 n/m at large m), the largest of the rate-noise
/// types (α ≤ 0). A noise identification that mistakes the few decimated points at long τ for
/// white angle noise would otherwise claim hundreds of degrees of freedom for a τ with a handful
/// of independent averages, and that one point would dominate the fit.
fn edf_given(curve: &Curve<'_>, i: usize) -> f64 {
    let given = curve.edf.map_or(f64::INFINITY, |e| e[i]);
    given.min(approximate_edf(curve.n_phase(), curve.m[i], 0))
}

/// A converged IRLS fit on a fixed set of points.
pub(crate) struct Inner {
    pub(crate) c: [f64; 5],
    pub(crate) gm: Vec<(f64, f64)>,
    /// Sinusoids `(Ω₀², f₀)`.
    pub(crate) lines: Vec<(f64, f64)>,
    /// The line windows `(seed, half-width)` the frequencies were refined in.
    pub(crate) windows: Vec<(f64, f64)>,
    pub(crate) t0: f64,
    pub(crate) edf: Vec<f64>,
    pub(crate) sqrt_w: Vec<f64>,
    pub(crate) chi2: f64,
    pub(crate) iterations: usize,
    pub(crate) bounds: (f64, f64),
    /// How the `1/τ²` column entered ([`InverseSquare`]).
    pub(crate) q: InverseSquare,
    /// The data's variance constraint the fit respected ([`super::variance_limit`]).
    pub(crate) limit: Option<Limit>,
}

/// Default search range of the correlation times: `[5 τ_lo, τ_hi/5]` (the whole range when that
/// is empty). A Gauss–Markov term with `T` near the shortest τ has an Allan variance below its
/// white-noise asymptote there and could imitate a sensor filter's roll-off; with `T` near the
/// longest τ it is indistinguishable from a random walk.
pub(crate) fn default_time_bounds(lo: f64, hi: f64) -> (f64, f64) {
    if 25.0 * lo < hi {
        (5.0 * lo, hi / 5.0)
    } else {
        (lo, hi)
    }
}

pub(crate) fn irls(
    curve: &Curve<'_>,
    used: &[usize],
    requested: &[Term],
    n_gm: usize,
    bounds: Option<(f64, f64)>,
    windows: &[(f64, f64)],
    q: InverseSquare,
    data_variance: Option<f64>,
) -> Result<Inner> {
    let t0 = curve_t0(curve);
    let taus: Vec<f64> = used.iter().map(|&i| curve.taus[i]).collect();
    // The data's variance bounds what the terms may claim (variance_limit), counted over the
    // band of the points used.
    let limit = Limit::new(
        data_variance,
        curve.n_phase().saturating_sub(1),
        t0,
        taus[0],
    );
    let y: Vec<f64> = used.iter().map(|&i| curve.variance[i]).collect();
    let bounds = bounds.unwrap_or_else(|| default_time_bounds(taus[0], taus[taus.len() - 1]));
    let mut c = [0.0_f64; 5];
    let mut gm: Vec<(f64, f64)> = Vec::new();
    let mut lines: Vec<(f64, f64)> = Vec::new();
    let mut reference = y.clone();
    let mut edf: Vec<f64> = used
        .iter()
        .map(|&i| {
            if curve.edf.is_some() {
                edf_given(curve, i)
            } else {
                curve.edf_at(i, Term::AngleRandomWalk)
            }
        })
        .collect();
    let mut chi2 = f64::NAN;
    let mut sqrt_w = Vec::new();
    let mut iterations = 0;
    let tolerance = if n_gm > 0 { 1e-7 } else { 1e-10 };
    let passes = if n_gm > 0 { 30 } else { 50 };
    for pass in 0..passes {
        iterations = pass + 1;
        sqrt_w = reference
            .iter()
            .zip(&edf)
            .map(|(r, e)| (e / 2.0).sqrt() / r)
            .collect();
        let Some((ts, fl, coef, x2)) = profile_times(
            &taus,
            &y,
            requested,
            n_gm,
            bounds,
            &Whitener::Diagonal(&sqrt_w),
            windows,
            t0,
            q,
            limit.as_ref(),
        ) else {
            return Err(Error::Singular {
                reason: "no subset of the requested terms gives a non-negative weighted \
                         least-squares solution with a degree of freedom left"
                    .into(),
            });
        };
        let mut next = [0.0_f64; 5];
        for (t, v) in requested.iter().zip(&coef) {
            next[t.index()] = *v;
        }
        let next_gm: Vec<(f64, f64)> = ts
            .iter()
            .zip(&coef[requested.len()..])
            .map(|(t, q2)| (*q2, *t))
            .collect();
        let next_lines: Vec<(f64, f64)> = fl
            .iter()
            .zip(&coef[requested.len() + ts.len()..])
            .map(|(f, a2)| (*a2, *f))
            .collect();
        let rel = |a: f64, b: f64| (a - b).abs() / a.abs().max(b.abs()).max(f64::MIN_POSITIVE);
        let mut change = (0..5).map(|j| rel(next[j], c[j])).fold(0.0_f64, f64::max);
        if gm.len() == next_gm.len() {
            for (a, b) in gm.iter().zip(&next_gm) {
                change = change.max(rel(a.0, b.0)).max((a.1.ln() - b.1.ln()).abs());
            }
        } else {
            change = f64::INFINITY;
        }
        if lines.len() == next_lines.len() {
            for (a, b) in lines.iter().zip(&next_lines) {
                change = change.max(rel(a.0, b.0)).max(rel(a.1, b.1));
            }
        } else {
            change = f64::INFINITY;
        }
        c = next;
        gm = next_gm;
        lines = next_lines;
        chi2 = x2;
        if pass > 0 && change < tolerance {
            break;
        }
        reference = taus
            .iter()
            .zip(&y)
            .map(|(t, obs)| model_with_lines(&c, &gm, &lines, t0, *t).max(0.01 * obs))
            .collect();
        if curve.edf.is_none() {
            edf = used
                .iter()
                .map(|&i| edf_model(curve, i, &c, &gm, &lines))
                .collect();
        }
    }
    gm.sort_by(|a, b| a.1.total_cmp(&b.1));
    Ok(Inner {
        c,
        gm,
        lines,
        windows: windows.to_vec(),
        t0,
        edf,
        sqrt_w,
        chi2,
        iterations,
        bounds,
        q,
        limit,
    })
}

/// The model correlation of the estimates at the points `used` ([`correlation_with`]),
/// remembered for the last points and model: within one fit, the goodness-of-fit test that
/// ends the range selection, the reported test and the sandwich covariance all need it for the
/// same fitted model (an O(n²) matrix of spectral integrals, the dominant cost on dense τ
/// grids), and it is computed once. The key is exact (indices and the bits of `c` and `gm`),
/// so a remembered matrix is the one a fresh call returns.
#[derive(Default)]
pub(crate) struct CorrelationMemo {
    key: Option<MemoKey>,
    rho: Vec<f64>,
}

impl CorrelationMemo {
    fn get(
        &mut self,
        curve: &Curve<'_>,
        used: &[usize],
        c: &[f64; 5],
        gm: &[(f64, f64)],
    ) -> &[f64] {
        let key = (
            used.to_vec(),
            c.map(f64::to_bits),
            gm.iter()
                .map(|&(q, t)| (q.to_bits(), t.to_bits()))
                .collect(),
        );
        if self.key.as_ref() != Some(&key) {
            let m: Vec<usize> = used.iter().map(|&i| curve.m[i]).collect();
            let terms: Vec<usize> = used.iter().map(|&i| curve.n_terms[i]).collect();
            let t0 = curve.taus[used[0]] / m[0] as f64;
            self.rho = correlation_with(&m, &terms, t0, &spectral(c), gm);
            self.key = Some(key);
        }
        &self.rho
    }
}

/// The noise terms' coefficients for spectral computations (correlations, EDF): a negative
/// `c_Q` is a sensor filter's correction ([`InverseSquare`]), a few per cent of the white noise
/// at the shortest τ used, not a noise process with a spectrum of its own.
pub(crate) fn spectral(c: &[f64; 5]) -> [f64; 5] {
    c.map(|v| v.max(0.0))
}

/// What a [`CorrelationMemo`] was computed for: the points and the bits of `c` and `gm`.
type MemoKey = (Vec<usize>, [u64; 5], Vec<(u64, u64)>);

/// Goodness of fit on the points `used` (module docs): (χ², ν, p, z per used point).
#[allow(clippy::too_many_arguments)]
pub(crate) fn goodness(
    curve: &Curve<'_>,
    used: &[usize],
    c: &[f64; 5],
    gm: &[(f64, f64)],
    lines: &[(f64, f64)],
    edf: &[f64],
    n_params: usize,
    memo: &mut CorrelationMemo,
) -> (f64, usize, f64, Vec<f64>) {
    let n = used.len();
    let t0 = curve_t0(curve);
    let z: Vec<f64> = used
        .iter()
        .zip(edf)
        .map(|(&i, &nu)| {
            let mu = model_with_lines(c, gm, lines, t0, curve.taus[i]).max(f64::MIN_POSITIVE);
            let half = nu / 2.0;
            let r = (curve.variance[i] / mu).ln() - (digamma(half) - half.ln());
            r / trigamma(half).sqrt()
        })
        .collect();
    let mut r = DMatrix::from_row_slice(n, n, memo.get(curve, used, c, gm));
    // A little ridge keeps the factorisation stable when neighbouring τ are almost collinear.
    for i in 0..n {
        r[(i, i)] += 1e-9;
    }
    let chi2 = match r.cholesky() {
        Some(ch) => {
            let zv = nalgebra::DVector::from_column_slice(&z);
            let s = ch.solve(&zv);
            zv.dot(&s)
        }
        None => z.iter().map(|v| v * v).sum(),
    };
    let dof = n.saturating_sub(n_params);
    let p = if dof > 0 && chi2.is_finite() {
        stats::chi2_sf(chi2, dof as f64).unwrap_or(f64::NAN)
    } else if chi2.is_infinite() {
        0.0
    } else {
        f64::NAN
    };
    (chi2, dof, p, z)
}

/// Parameters of the sandwich covariance.
#[derive(Clone, Copy)]
pub(crate) enum Param {
    Linear(Term),
    Variance(usize),
    LogTime(usize),
    LineVariance(usize),
    LineFrequency(usize),
}

/// `∂σ²(τ_i)/∂θ_k` of the active parameters at `taus`.
pub(crate) fn jacobian(
    taus: &[f64],
    gm: &[(f64, f64)],
    lines: &[(f64, f64)],
    t0: f64,
    params: &[Param],
) -> DMatrix<f64> {
    let mut j = DMatrix::zeros(taus.len(), params.len());
    for (i, &tau) in taus.iter().enumerate() {
        for (k, par) in params.iter().enumerate() {
            j[(i, k)] = match *par {
                Param::Linear(t) => t.basis(tau),
                Param::Variance(g) => gauss_markov::basis(gm[g].1, tau),
                Param::LogTime(g) => gm[g].0 * gauss_markov::basis_dlog_t(gm[g].1, tau),
                Param::LineVariance(k) => sinusoid::basis(lines[k].1, t0, tau),
                Param::LineFrequency(k) => lines[k].0 * sinusoid::basis_dfreq(lines[k].1, t0, tau),
            };
        }
    }
    j
}

/// The active parameters of a fit: power-law terms with `c ≠ 0` (`c_Q < 0`: a filter), then `(q², ln T)` of every
/// Gauss–Markov term with `q² > 0`, then `(Ω₀², f₀)` of every line with `Ω₀² > 0` (the frequency
/// only when it was refined, i.e. its window has a positive half-width).
pub(crate) fn active_params(
    requested: &[Term],
    c: &[f64; 5],
    gm: &[(f64, f64)],
    lines: &[(f64, f64)],
    windows: &[(f64, f64)],
) -> Vec<Param> {
    let mut params: Vec<Param> = requested
        .iter()
        .filter(|t| c[t.index()] != 0.0)
        .map(|t| Param::Linear(*t))
        .collect();
    for (g, x) in gm.iter().enumerate() {
        if x.0 > 0.0 {
            params.push(Param::Variance(g));
            params.push(Param::LogTime(g));
        }
    }
    for (k, x) in lines.iter().enumerate() {
        if x.0 > 0.0 {
            params.push(Param::LineVariance(k));
            if windows.get(k).is_some_and(|w| w.1 > 0.0) {
                params.push(Param::LineFrequency(k));
            }
        }
    }
    params
}

/// Sandwich covariance of the active parameters (module docs), unscaled by the χ² inflation.
fn parameter_covariance(
    curve: &Curve<'_>,
    used: &[usize],
    inner: &Inner,
    params: &[Param],
    memo: &mut CorrelationMemo,
) -> Option<DMatrix<f64>> {
    let n = used.len();
    let p = params.len();
    if p == 0 {
        return Some(DMatrix::zeros(0, 0));
    }
    let taus: Vec<f64> = used.iter().map(|&i| curve.taus[i]).collect();
    let y: Vec<f64> = used.iter().map(|&i| curve.variance[i]).collect();
    let j = jacobian(&taus, &inner.gm, &inner.lines, inner.t0, params);
    // Column scaling keeps JᵀWJ well conditioned (coefficients span many decades).
    let scale: Vec<f64> = (0..p)
        .map(|k| {
            let s = (0..n)
                .map(|i| (inner.sqrt_w[i] * j[(i, k)]).powi(2))
                .sum::<f64>()
                .sqrt();
            if s > 0.0 { s } else { 1.0 }
        })
        .collect();
    let mut u = DMatrix::zeros(n, p);
    let mut a = DMatrix::zeros(n, p);
    for i in 0..n {
        let w = inner.sqrt_w[i] * inner.sqrt_w[i];
        for k in 0..p {
            a[(i, k)] = inner.sqrt_w[i] * j[(i, k)] / scale[k];
            u[(i, k)] = w * j[(i, k)] / scale[k];
        }
    }
    let ata = a.transpose() * &a;
    let bread = ata.cholesky()?.inverse();
    let rho = memo.get(curve, used, &inner.c, &inner.gm);
    let s: Vec<f64> = taus
        .iter()
        .zip(&y)
        .zip(&inner.edf)
        .map(|((t, obs), e)| {
            model_with_lines(&inner.c, &inner.gm, &inner.lines, inner.t0, *t).max(0.01 * obs)
                * (2.0 / e).sqrt()
        })
        .collect();
    let mut v = DMatrix::zeros(n, n);
    for i in 0..n {
        for k in 0..n {
            v[(i, k)] = rho[i * n + k] * s[i] * s[k];
        }
    }
    let meat = u.transpose() * v * &u;
    let mut cov = &bread * meat * &bread;
    for a in 0..p {
        for b in 0..p {
            cov[(a, b)] /= scale[a] * scale[b];
        }
    }
    Some(cov)
}

/// Joint weighted NNLS fit of the requested terms over the points with τ in `tau_range`
/// (no Gauss–Markov terms, no automatic range selection).
pub fn joint(
    curve: &Curve<'_>,
    enabled: [bool; 5],
    tau_range: Option<(f64, f64)>,
) -> Result<JointFit> {
    fit(
        curve,
        &FitOptions {
            enabled,
            gauss_markov: 0,
            tau_range,
            correlation_time: None,
            automatic_range: false,
            lines: Vec::new(),
            bound_confidence: super::bound::BOUND_CONFIDENCE,
            data_variance: None,
        },
    )
}

/// Parses the model's term symbols: the five power-law terms ("Q", "N", "B", "K", "R") and
/// Gauss–Markov terms ("GM" one, "GM2" two). Returns the enabled power-law terms and the number
/// of Gauss–Markov terms.
pub fn parse_model_terms(symbols: &[&str]) -> Result<([bool; 5], usize)> {
    let mut enabled = [false; 5];
    let mut n_gm = 0;
    for s in symbols {
        match *s {
            "GM" | "GM1" => n_gm = n_gm.max(1),
            "GM2" => n_gm = 2,
            other => match Term::parse(other) {
                Ok(t) => enabled[t.index()] = true,
                Err(_) => {
                    return Err(Error::invalid(
                        "terms",
                        format!(
                            "unknown term {other:?}; expected 'Q', 'N', 'B', 'K', 'R', 'GM' or \
                             'GM2'"
                        ),
                    ));
                }
            },
        }
    }
    if !enabled.iter().any(|e| *e) && n_gm == 0 {
        return Err(Error::invalid("terms", "no term requested"));
    }
    Ok((enabled, n_gm))
}

/// The term symbols of a model, the inverse of [`parse_model_terms`]: the enabled power-law
/// terms in [`Term::ALL`] order, then "GM" and "GM2" for one or two Gauss–Markov terms.
pub fn model_term_symbols(enabled: &[bool; 5], gauss_markov: usize) -> Vec<&'static str> {
    let mut symbols: Vec<&'static str> = Term::ALL
        .iter()
        .filter(|t| enabled[t.index()])
        .map(|t| t.symbol())
        .collect();
    symbols.extend(["GM", "GM2"].iter().take(gauss_markov.min(2)));
    symbols
}

/// Length of the leading run of points to exclude when the fit is rejected: the longest prefix
/// that ends at a point with `z < −2`, lies below the model after its first point (`z < 0`),
/// contains no point with `z > 2` and is at most half of the points. A sensor's anti-alias
/// filter bends the curve below the −½ line at the shortest τ; when another term (a sinusoid)
/// is free at those τ, the first point can still fit while the next ones fall below the model,
/// so the run is not required to start with `z < −2`. It must stay below the model, though: a
/// lone `z < −2` further up on an unfiltered curve (residuals of both signs before it) is not a
/// filter's signature, and cutting the τ range there cost N a factor 4 in precision.
pub(crate) fn leading_run(z: &[f64]) -> usize {
    let limit = z.len() / 2;
    let mut lead = 0;
    for (i, &v) in z.iter().enumerate().take(limit) {
        if v > 2.0 || v.is_nan() || (i > 0 && v >= 0.0) {
            break;
        }
        if v < -2.0 {
            lead = i + 1;
        }
    }
    lead
}

/// Once a filter has been seen ([`InverseSquare`]), the leading points up to the first one that
/// departs from the model either way (`|z| > 2`, within the first half): the
/// `N²/τ·(1 − 3τ_c/τ)` law holds exactly only for averaging lengths beyond the filter's impulse
/// response, and inside it a real filter's curve can sit above the line (pass-band ripple, the
/// ringing of a long FIR) as well as below it, with points on the line in between. One such
/// run per refit, while the fit is rejected.
pub(crate) fn transition(z: &[f64]) -> usize {
    z.iter()
        .take(z.len() / 2)
        .position(|v| v.abs() > 2.0)
        .map_or(0, |i| i + 1)
}

/// A gross rejection (`χ²/ν > 10`: the model misses the curve systematically, not by noise)
/// with the first point not above the model (`z₀ ≤ 2`). A long filter (a 41-tap FIR at 0.3
/// Nyquist) can leave the first point on the model and the next ones far above and below it,
/// which [`leading_run`] (built not to cut an unfiltered curve at a lone low point) does not
/// take; under a gross rejection [`transition`] does, and the filter is then modelled as after
/// any excluded leading run. A first point far *above* the model is not a filter's signature
/// (unmodelled quantisation noise or a line lifts the shortest τ): the fit stays rejected, and
/// says so.
pub(crate) fn gross(chi2: f64, dof: usize, z: &[f64]) -> bool {
    dof > 0 && chi2 > 10.0 * dof as f64 && z.first().is_some_and(|v| *v <= 2.0)
}

/// Hausman's test of the first used point once a filter is modelled (module docs, "Sensor
/// filter"): the law `N²/τ·(1 − 3τ_c/τ)` is exact only beyond the filter's impulse response, and
/// the first point used may still sit in the transition by less than its residual shows yet more
/// than N's uncertainty allows (a second-order Butterworth: +1 % at m = 2; a 41-tap FIR at 0.3
/// Nyquist: −2 % at m = 8). Under the law, dropping the first point changes the estimate of `N²`
/// by `d` with `Var(d) = Var(N²_without) − Var(N²_with)` (Hausman, Econometrica 46 (1978) 1251,
/// for an efficient estimator); while `|d| > 2√Var(d)` the first point is dropped. `white`
/// returns `(c_N, Var c_N, r₀)` of a fit on the given points, `r₀` the first point's residual
/// (σ² − model: the exclusion's reason says whether it lay above or below the model).
pub(crate) fn hausman_trim(
    used: &mut Vec<usize>,
    excluded: &mut Vec<(f64, f64, String)>,
    taus: &[f64],
    min_keep: usize,
    white: impl Fn(&[usize]) -> Option<(f64, f64, f64)>,
) {
    while used.len() > min_keep {
        let (Some((kept, v_kept, _)), Some((dropped, v_dropped, _))) =
            (white(used), white(&used[1..]))
        else {
            return;
        };
        let var = v_dropped - v_kept;
        if !(var > 0.0 && (dropped - kept).abs() > 2.0 * var.sqrt()) {
            return;
        }
        let above = white(used).is_some_and(|w| w.2 > 0.0);
        exclude_short(excluded, taus[used[0]], taus[used[0]], above, !above);
        used.remove(0);
    }
}

/// Records shortest-τ points excluded as a filter's transition, with the reason that says where
/// they lay: above the model, below it, or both (`above`/`below`: whether any of the new points
/// did); merged with the shortest-τ band already excluded, whose reason then covers both.
pub(crate) fn exclude_short(
    list: &mut Vec<(f64, f64, String)>,
    lo: f64,
    hi: f64,
    above: bool,
    below: bool,
) {
    let (mut above, mut below) = (above, below);
    if let Some(k) = list.iter().position(|e| is_short_reason(&e.2)) {
        let e = list.remove(k);
        above |= e.2 != SHORT_REASON;
        below |= e.2 != SHORT_ABOVE_REASON;
        exclude(list, e.0.min(lo), e.1.max(hi), short_reason(above, below));
    } else {
        exclude(list, lo, hi, short_reason(above, below));
    }
}

/// Whether excluded points lay above and/or below the model, from their standardised residuals
/// `z`: the points that depart from it (`|z| > 2`) say so; points on it (`|z| ≤ 2`, such as the
/// first point of a [`leading_run`]) do not count, unless none departs, when the sign of their
/// mean does.
pub(crate) fn departures(z: &[f64]) -> (bool, bool) {
    let above = z.iter().any(|v| *v > 2.0);
    let below = z.iter().any(|v| *v < -2.0);
    if above || below {
        return (above, below);
    }
    let mean: f64 = z.iter().sum::<f64>();
    (mean > 0.0, mean <= 0.0)
}

/// The reason for shortest-τ points excluded as a filter's transition, from whether they lay
/// above and/or below the model.
pub(crate) fn short_reason(above: bool, below: bool) -> &'static str {
    match (above, below) {
        (true, true) => SHORT_MIXED_REASON,
        (true, false) => SHORT_ABOVE_REASON,
        _ => SHORT_REASON,
    }
}

/// Whether an exclusion reason is one of the shortest-τ (filter transition) reasons.
pub(crate) fn is_short_reason(reason: &str) -> bool {
    [SHORT_REASON, SHORT_ABOVE_REASON, SHORT_MIXED_REASON].contains(&reason)
}

/// Merges a newly excluded τ range into the list (adjacent ranges with the same reason join).
pub(crate) fn exclude(list: &mut Vec<(f64, f64, String)>, lo: f64, hi: f64, reason: &str) {
    if let Some(e) = list.iter_mut().find(|e| e.2 == reason) {
        e.0 = e.0.min(lo);
        e.1 = e.1.max(hi);
    } else {
        list.push((lo, hi, reason.to_string()));
    }
}

/// One step of the automatic τ-range selection shared by the joint fit and GMWM: drops the
/// `lead` shortest used points (filtered first scales, [`SHORT_REASON`] or its siblings, from
/// `sides`: [`sides`] of the used points) or else the trailing
/// run of standardised residuals `z` above +2 (drift, [`LONG_REASON`]), as long as `min_keep`
/// points remain; records the excluded τ band. Returns `false` when nothing could be dropped.
pub(crate) fn trim_ends(
    used: &mut Vec<usize>,
    excluded: &mut Vec<(f64, f64, String)>,
    taus: &[f64],
    z: &[f64],
    lead: usize,
    min_keep: usize,
    sides: &[f64],
) -> bool {
    let trail = z.iter().rev().take_while(|v| **v > 2.0).count();
    if lead > 0 && used.len() - lead >= min_keep {
        let (above, below) = departures(&sides[..lead]);
        exclude_short(excluded, taus[used[0]], taus[used[lead - 1]], above, below);
        used.drain(..lead);
    } else if trail > 0 && used.len() - trail >= min_keep {
        let cut = used.len() - trail;
        exclude(
            excluded,
            taus[used[cut]],
            taus[used[used.len() - 1]],
            LONG_REASON,
        );
        used.truncate(cut);
    } else {
        return false;
    }
    true
}

pub(crate) const SHORT_REASON: &str = "σ below the model at the shortest τ with correlated residuals \
                            (typically the sensor's anti-alias/decimation filter)";
pub(crate) const SHORT_ABOVE_REASON: &str = "σ above the model at the shortest τ with correlated \
                            residuals (a sensor filter's transition, or noise the requested terms do \
                            not describe, such as quantisation)";
pub(crate) const SHORT_MIXED_REASON: &str = "σ above and below the model at the shortest τ with \
                            correlated residuals (typically the transition of the sensor's \
                            anti-alias/decimation filter)";
pub(crate) const LONG_REASON: &str = "σ above the model at the longest τ (drift or non-stationarity the \
                           requested terms do not describe)";
pub(crate) const EDF_REASON: &str = "fewer than 3 equivalent degrees of freedom";

/// Joint fit with Gauss–Markov terms, diagnostics and (optionally) automatic τ-range selection
/// (module docs).
pub fn fit(curve: &Curve<'_>, options: &FitOptions) -> Result<JointFit> {
    curve.validate()?;
    let enabled = options.enabled;
    let n_gm = options.gauss_markov;
    if n_gm > 2 {
        return Err(Error::invalid(
            "terms",
            format!("at most two Gauss–Markov terms ('GM', 'GM2') are supported, got {n_gm}"),
        ));
    }
    if !enabled.iter().any(|e| *e) && n_gm == 0 {
        return Err(Error::invalid("terms", "no term requested"));
    }
    crate::validate::probability("bound_confidence", options.bound_confidence)?;
    let (lo, hi) = options.tau_range.unwrap_or((0.0, f64::INFINITY));
    if !(lo.is_finite() || lo == 0.0) || lo.is_nan() || hi.is_nan() || hi <= lo {
        return Err(Error::invalid(
            "tau_range",
            format!("must be (low, high) with low < high, got ({lo}, {hi})"),
        ));
    }
    // Points with σ² = 0 carry no usable weight (their relative error is undefined).
    let mut used: Vec<usize> = (0..curve.len())
        .filter(|&i| curve.taus[i] >= lo && curve.taus[i] <= hi && curve.variance[i] > 0.0)
        .collect();
    let requested: Vec<Term> = Term::ALL
        .into_iter()
        .filter(|t| enabled[t.index()])
        .collect();
    let t0 = curve_t0(curve);
    for &(f, half) in &options.lines {
        sinusoid::validate_lines("lines", &[(f, 1.0)], t0)?;
        if !(half.is_finite() && half >= 0.0 && half < f) {
            return Err(Error::invalid(
                "lines",
                format!(
                    "the refinement half-width of the line at {f} Hz must be finite, >= 0 and \
                     below the frequency, got {half}"
                ),
            ));
        }
    }
    let n_max_params = requested.len() + 2 * n_gm + 2 * options.lines.len();
    let needed = 3.max(n_max_params.min(3) + 1);
    if used.len() < needed {
        return Err(Error::TooShort {
            name: "allan",
            needed,
            got: used.len(),
        });
    }
    if let Some((a, b)) = options.correlation_time {
        let (t_lo, t_hi) = (curve.taus[used[0]], curve.taus[used[used.len() - 1]]);
        if !(a.is_finite() && b.is_finite() && a > 0.0 && b > a) {
            return Err(Error::invalid(
                "correlation_time",
                format!("must be (low, high) seconds with 0 < low < high, got ({a}, {b})"),
            ));
        }
        if a < t_lo || b > t_hi {
            return Err(Error::invalid(
                "correlation_time",
                format!(
                    "the range ({}, {}) s reaches outside the τ range of the data \
                     ({}–{} s): a Gauss–Markov term with a correlation time there \
                     cannot be told apart from white noise (T ≪ τ) or a random walk (T ≫ τ)",
                    sig(a, 4),
                    sig(b, 4),
                    sig(t_lo, 4),
                    sig(t_hi, 4)
                ),
            ));
        }
    }
    let automatic = options.automatic_range && options.tau_range.is_none();
    let mut excluded: Vec<(f64, f64, String)> = Vec::new();
    // The terms fitted: the requested ones, plus the 1/τ² column once a filter is seen.
    let mut terms = requested.clone();
    let mut q = InverseSquare::Quantization;
    let refit = |used: &[usize], terms: &[Term], q: InverseSquare| {
        irls(
            curve,
            used,
            terms,
            n_gm,
            options.correlation_time,
            &options.lines,
            q,
            options.data_variance,
        )
    };
    let mut inner = refit(&used, &terms, q)?;
    let mut memo = CorrelationMemo::default();
    if automatic {
        let min_keep = (n_max_params + 2).max(used.len().div_ceil(2)).max(3);
        let mut drop = 0;
        while used.len() - drop > min_keep && inner.edf[used.len() - 1 - drop] < MIN_EDF {
            drop += 1;
        }
        if drop > 0 {
            let cut = used.len() - drop;
            exclude(
                &mut excluded,
                curve.taus[used[cut]],
                curve.taus[used[used.len() - 1]],
                EDF_REASON,
            );
            used.truncate(cut);
            inner = refit(&used, &terms, q)?;
        }
        for _ in 0..curve.len() {
            let n_params =
                active_params(&terms, &inner.c, &inner.gm, &inner.lines, &inner.windows).len();
            let (chi2, dof, p, z) = goodness(
                curve,
                &used,
                &inner.c,
                &inner.gm,
                &inner.lines,
                &inner.edf,
                n_params,
                &mut memo,
            );
            if p >= REFIT_P || p.is_nan() {
                break;
            }
            let mut lead = leading_run(&z);
            if lead == 0 && (q != InverseSquare::Quantization || gross(chi2, dof, &z)) {
                lead = transition(&z);
            }
            let first = used[0];
            let at = sides(curve, &used, &inner.c, &inner.gm, &inner.lines, &z);
            if !trim_ends(
                &mut used,
                &mut excluded,
                curve.taus,
                &z,
                lead,
                min_keep,
                &at,
            ) {
                break;
            }
            if used[0] != first && q == InverseSquare::Quantization {
                // A filter bent the shortest τ: the points beyond the excluded ones still carry
                // its −3N²τ_c/τ² (module docs, "Sensor filter").
                (terms, q) = InverseSquare::filtered(&requested);
            }
            inner = refit(&used, &terms, q)?;
        }
        if q != InverseSquare::Quantization {
            let white = |used: &[usize]| -> Option<(f64, f64, f64)> {
                let inner = refit(used, &terms, q).ok()?;
                let params =
                    active_params(&terms, &inner.c, &inner.gm, &inner.lines, &inner.windows);
                let k = params
                    .iter()
                    .position(|p| matches!(p, Param::Linear(Term::AngleRandomWalk)))?;
                let cov = parameter_covariance(
                    curve,
                    used,
                    &inner,
                    &params,
                    &mut CorrelationMemo::default(),
                )?;
                let i = used[0];
                let r0 = side(
                    curve.variance[i],
                    &inner.c,
                    &inner.gm,
                    &inner.lines,
                    curve_t0(curve),
                    curve.taus[i],
                );
                Some((inner.c[Term::AngleRandomWalk.index()], cov[(k, k)], r0))
            };
            let before = used.len();
            hausman_trim(&mut used, &mut excluded, curve.taus, min_keep, white);
            if used.len() != before {
                inner = refit(&used, &terms, q)?;
            }
        }
    }
    Ok(finish(
        curve,
        &used,
        &terms,
        enabled,
        n_gm,
        inner,
        excluded,
        CovarianceSource::Sandwich,
        &mut memo,
        options.bound_confidence,
    ))
}

/// Where [`finish`] takes the parameter covariance from.
pub(crate) enum CovarianceSource {
    /// The WLS sandwich of the joint fit.
    Sandwich,
    /// Given by the caller (GMWM), unscaled by the χ² inflation; `None` if not available.
    Given(Option<DMatrix<f64>>),
}

/// Builds the reported fit.
pub(crate) fn finish(
    curve: &Curve<'_>,
    used: &[usize],
    requested: &[Term],
    enabled: [bool; 5],
    n_gm: usize,
    inner: Inner,
    excluded: Vec<(f64, f64, String)>,
    covariance: CovarianceSource,
    memo: &mut CorrelationMemo,
    bound_confidence: f64,
) -> JointFit {
    let taus: Vec<f64> = used.iter().map(|&i| curve.taus[i]).collect();
    let c = inner.c;
    let params = active_params(requested, &c, &inner.gm, &inner.lines, &inner.windows);
    let n_params = params.len();
    let (gof_chi2, dof, p_value, z) = goodness(
        curve,
        used,
        &c,
        &inner.gm,
        &inner.lines,
        &inner.edf,
        n_params,
        memo,
    );
    let mut warnings = Vec::new();
    if let Some((a, b, _)) = excluded.iter().find(|e| e.2 == LONG_REASON) {
        warnings.push(format!(
            "the points at τ {}–{} s were excluded because the model could not follow them; if \
             this is not drift, add terms (e.g. 'GM', 'K' or 'R') or pass tau_range",
            sig(*a, 3),
            sig(*b, 3)
        ));
    }
    let inflation = if dof > 0 && gof_chi2.is_finite() {
        (gof_chi2 / dof as f64).max(1.0)
    } else {
        1.0
    };
    if dof == 0 {
        warnings.push(format!(
            "no degree of freedom is left ({} points for {n_params} parameters): the fit cannot \
             be tested and its uncertainties rest on the model alone",
            used.len()
        ));
    } else if p_value < REJECT_P {
        warnings.push(format!(
            "the model does not fit the Allan curve (goodness-of-fit p = {} < 0.001, \
             χ²/ν = {}): the uncertainties are inflated by √(χ²/ν) = {}, but the \
             coefficients may be biased; inspect diagnostics.residuals, restrict tau_range or \
             add terms (e.g. 'GM')",
            sig(p_value, 2),
            sig(gof_chi2 / dof as f64, 3),
            sig(inflation.sqrt(), 3)
        ));
    }
    let cov = match covariance {
        CovarianceSource::Given(given) => given,
        CovarianceSource::Sandwich => parameter_covariance(curve, used, &inner, &params, memo),
    };
    if cov.is_none() {
        warnings.push(
            "the fitted terms are not separable on these points (singular information matrix): \
             uncertainties are not available"
                .to_string(),
        );
    }
    let variance_of = |k: usize| -> f64 {
        cov.as_ref()
            .map_or(f64::NAN, |m| m[(k, k)].max(0.0) * inflation)
    };
    let mut covariance = [[0.0_f64; 5]; 5];
    if let Some(m) = &cov {
        for (a, pa) in params.iter().enumerate() {
            for (b, pb) in params.iter().enumerate() {
                if let (Param::Linear(ta), Param::Linear(tb)) = (pa, pb) {
                    if c[ta.index()] > 0.0 && c[tb.index()] > 0.0 {
                        covariance[ta.index()][tb.index()] = m[(a, b)] * inflation;
                    }
                }
            }
        }
    }
    // A negative 1/τ² coefficient is the sensor filter's −3N²τ_c/τ²: τ_c = −c_Q/c_N, its
    // uncertainty by the delta method from the (inflated) covariance of (c_Q, c_N).
    let (qi, ni) = (Term::Quantization.index(), Term::AngleRandomWalk.index());
    let position = |t: Term| {
        params
            .iter()
            .position(|p| matches!(p, Param::Linear(x) if *x == t))
    };
    let filter_correlation_time = (c[qi] < 0.0 && c[ni] > 0.0).then(|| {
        let tau_c = -c[qi] / c[ni];
        let u = match (
            &cov,
            position(Term::Quantization),
            position(Term::AngleRandomWalk),
        ) {
            (Some(m), Some(a), Some(b)) => {
                let (vq, vn, vqn) = (m[(a, a)], m[(b, b)], m[(a, b)]);
                let rel2 =
                    vq / (c[qi] * c[qi]) + vn / (c[ni] * c[ni]) - 2.0 * vqn / (c[qi] * c[ni]);
                tau_c * (rel2.max(0.0) * inflation).sqrt()
            }
            _ => f64::NAN,
        };
        (tau_c, u)
    });
    let model: Vec<f64> = taus
        .iter()
        .map(|t| model_with_lines(&c, &inner.gm, &inner.lines, inner.t0, *t))
        .collect();
    let tau_min = taus
        .iter()
        .zip(&model)
        .min_by(|a, b| a.1.total_cmp(b.1))
        .map_or(taus[0], |p| *p.0);
    let visible_range = |share: &dyn Fn(f64) -> f64| -> Option<(f64, f64)> {
        let visible: Vec<f64> = taus
            .iter()
            .zip(&model)
            .filter(|(tau, m)| share(**tau) >= SHARE * **m)
            .map(|(tau, _)| *tau)
            .collect();
        visible.first().map(|a| (*a, *visible.last().unwrap_or(a)))
    };
    let mut terms: Vec<TermEstimate> = Term::ALL
        .into_iter()
        .map(|t| {
            let j = t.index();
            if !enabled[j] {
                return TermEstimate::missing(t, "not requested");
            }
            if c[j] < 0.0 {
                return TermEstimate::missing(
                    t,
                    format!(
                        "the net 1/τ² part of the model is negative: the sensor's filter \
                         ({}diagnostics.filter_correlation_time) outweighs any quantisation \
                         noise in {}..{} s",
                        filter_correlation_time
                            .map_or(String::new(), |(tc, _)| format!("τ_c = {} s, ", sig(tc, 3))),
                        taus[0],
                        taus[taus.len() - 1]
                    ),
                );
            }
            if c[j] == 0.0 {
                return TermEstimate::missing(
                    t,
                    format!(
                        "the non-negative fit set it to zero: no τ in {}..{} s where this \
                         term is visible above the others",
                        taus[0],
                        taus[taus.len() - 1]
                    ),
                );
            }
            let value = c[j].sqrt();
            let k = params
                .iter()
                .position(|p| matches!(p, Param::Linear(x) if *x == t))
                .unwrap_or(0);
            let uncertainty = variance_of(k).sqrt() / (2.0 * value);
            let marker = match t.read_off_tau() {
                Some(tau) => Some((tau, value)),
                None => Some((tau_min, FLICKER_FACTOR * value)),
            };
            TermEstimate {
                term: t,
                value: Some(value),
                uncertainty,
                tau_range: visible_range(&|tau| c[j] * t.basis(tau)),
                marker,
                missing: None,
                upper_bound: None,
            }
        })
        .collect();
    // A requested term the fit set to zero is bounded from above by the points it used.
    super::bound::attach(
        &mut terms,
        enabled,
        curve,
        used,
        &inner.edf,
        bound_confidence,
    );
    let mut gauss_markov_terms = Vec::new();
    for (g, &(q2, t)) in inner.gm.iter().enumerate() {
        if q2 <= 0.0 {
            gauss_markov_terms.push(GaussMarkovEstimate {
                sigma: None,
                sigma_uncertainty: f64::NAN,
                correlation_time: None,
                correlation_time_uncertainty: f64::NAN,
                tau_range: None,
                missing: Some(format!(
                    "the non-negative fit set it to zero: no correlation time in {}..{} s \
                     where an exponentially correlated term is visible above the others",
                    sig(inner.bounds.0, 4),
                    sig(inner.bounds.1, 4)
                )),
            });
            continue;
        }
        let kq = params
            .iter()
            .position(|p| matches!(p, Param::Variance(x) if *x == g))
            .unwrap_or(0);
        let sigma = q2.sqrt();
        let at_edge = (t.ln() - inner.bounds.0.ln()).abs() < 1e-3
            || (t.ln() - inner.bounds.1.ln()).abs() < 1e-3;
        if at_edge {
            warnings.push(format!(
                "Gauss–Markov term {}: the correlation time {} s lies at the edge of the \
                 searched range ({}–{} s), where it cannot be told apart from white \
                 noise or a random walk; treat it as unidentified",
                g + 1,
                sig(t, 4),
                sig(inner.bounds.0, 4),
                sig(inner.bounds.1, 4)
            ));
        }
        gauss_markov_terms.push(GaussMarkovEstimate {
            sigma: Some(sigma),
            sigma_uncertainty: variance_of(kq).sqrt() / (2.0 * sigma),
            correlation_time: Some(t),
            correlation_time_uncertainty: t * variance_of(kq + 1).sqrt(),
            tau_range: visible_range(&|tau| q2 * gauss_markov::basis(t, tau)),
            missing: None,
        });
    }
    while gauss_markov_terms.len() < n_gm {
        gauss_markov_terms.push(GaussMarkovEstimate {
            sigma: None,
            sigma_uncertainty: f64::NAN,
            correlation_time: None,
            correlation_time_uncertainty: f64::NAN,
            tau_range: None,
            missing: Some("not identified".into()),
        });
    }
    let mut line_terms = Vec::new();
    for (k, &(a2, f)) in inner.lines.iter().enumerate() {
        let kv = params
            .iter()
            .position(|p| matches!(p, Param::LineVariance(x) if *x == k));
        let kf = params
            .iter()
            .position(|p| matches!(p, Param::LineFrequency(x) if *x == k));
        if a2 <= 0.0 || kv.is_none() {
            line_terms.push(LineEstimate {
                frequency: f,
                frequency_uncertainty: f64::NAN,
                amplitude: None,
                amplitude_uncertainty: f64::NAN,
                tau_range: None,
                missing: Some(format!(
                    "the non-negative fit set it to zero: the sinusoid at {} Hz is not visible \
                     above the noise in {}..{} s",
                    sig(f, 6),
                    sig(taus[0], 3),
                    sig(taus[taus.len() - 1], 3)
                )),
            });
            continue;
        }
        let amplitude = a2.sqrt();
        line_terms.push(LineEstimate {
            frequency: f,
            frequency_uncertainty: kf.map_or(f64::NAN, |kf| variance_of(kf).sqrt()),
            amplitude: Some(amplitude),
            amplitude_uncertainty: kv.map_or(f64::NAN, |kv| variance_of(kv).sqrt())
                / (2.0 * amplitude),
            tau_range: visible_range(&|tau| a2 * sinusoid::basis(f, inner.t0, tau)),
            missing: None,
        });
    }
    let mut residuals = vec![f64::NAN; curve.len()];
    for (k, &i) in used.iter().enumerate() {
        residuals[i] = z[k];
    }
    let tau_range = (taus[0], taus[taus.len() - 1]);
    let variance_limit = inner.limit.map(|l| {
        let claimed = l.claimed(
            &c,
            &inner.gm,
            &inner.lines,
            inner.q != InverseSquare::Quantization,
        );
        (claimed, l.variance)
    });
    if let Some((claimed, v)) = variance_limit {
        if claimed >= v * (1.0 - 1e-6) {
            warnings.push(limited_warning(&inner, v));
        }
    }
    JointFit {
        terms,
        squared: spectral(&c),
        covariance,
        gauss_markov_squared: inner.gm,
        gauss_markov: gauss_markov_terms,
        lines_squared: inner.lines,
        lines: line_terms,
        chi2: inner.chi2,
        dof,
        tau_range,
        used: used.to_vec(),
        edf: inner.edf,
        iterations: inner.iterations,
        diagnostics: Diagnostics {
            chi2: gof_chi2,
            dof,
            p_value,
            residuals,
            tau_range,
            excluded,
            warnings,
            filter_correlation_time,
            variance_limit,
        },
    }
}

/// The warning of a fit whose terms were limited by the data's variance `v`.
fn limited_warning(inner: &Inner, v: f64) -> String {
    let mut names: Vec<String> = Term::ALL
        .iter()
        .filter(|t| inner.c[t.index()] > 0.0)
        .filter(|t| **t != Term::Quantization || inner.q == InverseSquare::Quantization)
        .map(|t| t.symbol().to_string())
        .collect();
    names.extend(
        inner
            .gm
            .iter()
            .filter(|g| g.0 > 0.0)
            .map(|g| format!("GM (T = {} s)", sig(g.1, 3))),
    );
    names.extend(
        inner
            .lines
            .iter()
            .filter(|l| l.0 > 0.0)
            .map(|l| format!("S at {} Hz", sig(l.1, 6))),
    );
    format!(
        "the fit was limited by the data's variance ({} in the rate unit squared): unconstrained, \
         the terms that \
         fit the Allan curve would imply more variance than the samples have, so {} are as \
         large as the data allow (each term's implied sample variance, with its statistical \
         slack, sums to the data's; see diagnostics.variance_limit). A term that fits the curve \
         but not the data's variance is usually a line or drift the Allan curve cannot \
         separate from the noise: check the lines' frequencies or restrict tau_range",
        sig(v, 4),
        if names.is_empty() {
            "the terms".to_string()
        } else {
            names.join(", ")
        }
    )
}

/// Diagnostics of a given model (e.g. an IEEE read-off) on every point of the curve with
/// σ² > 0; `n_params` is the number of coefficients the model was identified with.
pub fn diagnose(
    curve: &Curve<'_>,
    c: &[f64; 5],
    gm: &[(f64, f64)],
    n_params: usize,
) -> Result<Diagnostics> {
    curve.validate()?;
    let used: Vec<usize> = (0..curve.len())
        .filter(|&i| curve.variance[i] > 0.0)
        .collect();
    let edf: Vec<f64> = used
        .iter()
        .map(|&i| edf_model(curve, i, c, gm, &[]))
        .collect();
    let (chi2, dof, p_value, z) = goodness(
        curve,
        &used,
        c,
        gm,
        &[],
        &edf,
        n_params,
        &mut CorrelationMemo::default(),
    );
    let mut warnings = Vec::new();
    if dof > 0 && p_value < REJECT_P {
        warnings.push(format!(
            "the model does not fit the Allan curve (goodness-of-fit p = {} < 0.001, \
             χ²/ν = {}): the stated uncertainties assume a model that the data reject",
            sig(p_value, 2),
            sig(chi2 / dof as f64, 3)
        ));
    }
    let mut residuals = vec![f64::NAN; curve.len()];
    for (k, &i) in used.iter().enumerate() {
        residuals[i] = z[k];
    }
    Ok(Diagnostics {
        chi2,
        dof,
        p_value,
        residuals,
        tau_range: (curve.taus[used[0]], curve.taus[used[used.len() - 1]]),
        excluded: Vec::new(),
        warnings,
        filter_correlation_time: None,
        variance_limit: None,
    })
}

#[cfg(test)]
mod tests {
    #[test]
    fn below_three_filter_times_the_side_is_against_the_white_line() {
        // N² = 1e-4, a filter with τ_c = 0.01 s (3c_Q = −3N²τ_c): at τ = 0.01 s < 3τ_c the
        // filtered model is negative (−0.02); a point at half the white line (0.005) lies below
        // the model the user sees, not above the negative value.
        let c = [-1e-6, 1e-4, 0.0, 0.0, 0.0];
        assert!(model_with_lines(&c, &[], &[], 0.01, 0.01) < 0.0);
        assert!(side(0.005, &c, &[], &[], 0.01, 0.01) < 0.0);
        // Beyond 3τ_c the filter's law is the reference: N²/τ·(1 − 3τ_c/τ) at 0.1 s is 7e-4.
        assert!((side(7e-4, &c, &[], &[], 0.01, 0.1)).abs() < 1e-15);
        let taus = [0.01, 0.1];
        let variance = [0.005, 1e-3];
        let m = [1, 10];
        let curve = Curve {
            taus: &taus,
            variance: &variance,
            m: &m,
            n_terms: &[100, 90],
            overlapping: true,
            edf: None,
        };
        let at = sides(&curve, &[0, 1], &c, &[], &[], &[5.0, 0.3]);
        assert_eq!(at, [f64::NEG_INFINITY, 0.3]);
    }

    #[test]
    fn short_exclusions_say_where_the_points_lay() {
        // Points that depart from the model say which side; points on it count only alone.
        assert_eq!(departures(&[0.5, 2.5, 3.0]), (true, false));
        assert_eq!(departures(&[1.0, -2.5, -3.0]), (false, true));
        assert_eq!(departures(&[-1.0, 2.5, -3.0]), (true, true));
        assert_eq!(departures(&[1.5, 0.2]), (true, false));
        assert_eq!(departures(&[-1.5, 0.2]), (false, true));
        let mut list = Vec::new();
        exclude_short(&mut list, 0.01, 0.02, true, false);
        assert_eq!(list, [(0.01, 0.02, SHORT_ABOVE_REASON.to_string())]);
        exclude_short(&mut list, 0.04, 0.04, true, false);
        assert_eq!(list, [(0.01, 0.04, SHORT_ABOVE_REASON.to_string())]);
        // A later run below the model: one band, above and below.
        exclude(&mut list, 100.0, 200.0, LONG_REASON);
        exclude_short(&mut list, 0.08, 0.08, false, true);
        assert_eq!(list.len(), 2);
        assert!(list.contains(&(0.01, 0.08, SHORT_MIXED_REASON.to_string())));
        let mut list = Vec::new();
        exclude_short(&mut list, 0.01, 0.02, false, true);
        assert_eq!(list, [(0.01, 0.02, SHORT_REASON.to_string())]);
        assert!(
            [SHORT_REASON, SHORT_ABOVE_REASON, SHORT_MIXED_REASON]
                .iter()
                .all(|r| is_short_reason(r))
        );
        assert!(!is_short_reason(LONG_REASON));
    }

    #[test]
    fn leading_run_follows_a_filter_not_a_lone_low_point() {
        // A filtered start: below the model from the second point on, ending at z < −2.
        assert_eq!(
            leading_run(&[0.5, -1.0, -3.0, -2.5, 0.3, 1.0, 0.0, -0.2]),
            4
        );
        assert_eq!(leading_run(&[-3.0, -2.5, 0.4, 1.0, 0.0, -0.2]), 2);
        // Residuals of both signs before a lone low point (an unfiltered curve): nothing.
        assert_eq!(
            leading_run(&[
                -0.47, 0.21, 1.97, 1.25, -0.15, -2.86, -4.45, -1.6, 0.4, 0.1, 1.3, 1.6
            ]),
            0
        );
        // Never more than half the points, never past z > 2.
        assert_eq!(leading_run(&[-3.0, -3.0, -3.0, -3.0]), 2);
        assert_eq!(leading_run(&[-1.0, 2.5, -3.0, 0.0, 0.0, 0.0]), 0);
    }

    use super::*;

    #[test]
    fn term_symbols_invert_the_parser() {
        for symbols in [
            vec!["N", "B", "K"],
            vec!["Q", "R", "GM"],
            vec!["N", "GM", "GM2"],
        ] {
            let (enabled, n_gm) = parse_model_terms(&symbols).unwrap();
            assert_eq!(model_term_symbols(&enabled, n_gm), symbols);
        }
    }

    /// Exact Allan variance of unit white noise through a moving average of `len` taps, from
    /// its autocovariance `r(k) = (len − |k|)/len²`: `AVAR(m) = [Var S_m − Cov(S_m, S'_m)]/m²`
    /// with `S_m` the sum of `m` consecutive samples (no approximation).
    fn moving_average_avar(len: usize, m: usize) -> f64 {
        let r = |k: i64| {
            let k = k.unsigned_abs() as usize;
            if k < len {
                (len - k) as f64 / (len * len) as f64
            } else {
                0.0
            }
        };
        let m = m as i64;
        let var: f64 = (-m + 1..m).map(|j| (m - j.abs()) as f64 * r(j)).sum();
        let cov: f64 = (1..2 * m).map(|j| (m - (j - m).abs()) as f64 * r(j)).sum();
        (var - cov) / (m * m) as f64
    }

    #[test]
    fn free_column_is_not_sign_constrained() {
        // y = 2·a − 1·b exactly: plain NNLS must zero b, with b free it is recovered.
        let a: Vec<f64> = (1..=6).map(|i| i as f64).collect();
        let b: Vec<f64> = (1..=6).map(|i| 1.0 / i as f64).collect();
        let y: Vec<f64> = a.iter().zip(&b).map(|(a, b)| 2.0 * a - b).collect();
        let w = vec![1.0; 6];
        let cols = vec![a.clone(), b.clone()];
        let (coef, chi2) = nnls(&cols, &y, &Whitener::Diagonal(&w), Some(1), None).unwrap();
        assert!((coef[0] - 2.0).abs() < 1e-12 && (coef[1] + 1.0).abs() < 1e-12 && chi2 < 1e-20);
        let (coef, chi2) = nnls(&cols, &y, &Whitener::Diagonal(&w), None, None).unwrap();
        assert!(coef[1] == 0.0 && coef[0] > 0.0 && chi2 > 1e-3);
        // A free column never forces the others negative: y = −a + b, a constrained.
        let y: Vec<f64> = a.iter().zip(&b).map(|(a, b)| -a + b).collect();
        // (the free coefficient is then the projection of y on b, whatever its sign).
        let (coef, _) = nnls(&cols, &y, &Whitener::Diagonal(&w), Some(1), None).unwrap();
        let projection = y.iter().zip(&b).map(|(y, b)| y * b).sum::<f64>()
            / b.iter().map(|b| b * b).sum::<f64>();
        assert_eq!(coef[0], 0.0);
        assert!((coef[1] - projection).abs() < 1e-12 && projection < 0.0);
    }

    /// The exact Allan variance of white noise through a 4-tap moving average (plus flicker and
    /// a random walk): the automatic fit excludes the filter's first points and models the rest
    /// as N²/τ·(1 − 3τ_c/τ), τ_c = t0·Σ_k k ρ(k) = 0.625 t0, recovering N and τ_c.
    #[test]
    fn a_filters_law_is_recovered_beyond_its_length() {
        let t0 = 0.01;
        let n = 2_880_000usize;
        let m: Vec<usize> = (0..21).map(|k| 1usize << k).collect();
        let taus: Vec<f64> = m.iter().map(|&m| m as f64 * t0).collect();
        let truth = [0.0, 1e-5, 4e-8, 1e-9, 0.0];
        // Unit white noise has N² = t0 per unit variance: scale to N² = 1e-5.
        let var: Vec<f64> = m
            .iter()
            .zip(&taus)
            .map(|(&mm, &tau)| {
                truth[1] / t0 * moving_average_avar(4, mm)
                    + model_variance(&[0.0, 0.0, 4e-8, 1e-9, 0.0], tau)
            })
            .collect();
        let terms: Vec<usize> = m.iter().map(|&m| n + 1 - 2 * m).collect();
        let curve = Curve {
            taus: &taus,
            variance: &var,
            m: &m,
            n_terms: &terms,
            overlapping: true,
            edf: None,
        };
        let options = FitOptions {
            enabled: [false, true, true, true, false],
            ..FitOptions::default()
        };
        let fit = fit(&curve, &options).unwrap();
        let (tau_c, u) = fit
            .diagnostics
            .filter_correlation_time
            .expect("a filter is seen");
        assert!((tau_c / (0.625 * t0) - 1.0).abs() < 1e-6, "τ_c = {tau_c}");
        assert!(u.is_finite());
        assert!((fit.squared[1] / truth[1] - 1.0).abs() < 1e-8);
        assert!(fit.squared[0] == 0.0, "a filter is not quantisation noise");
        assert!(
            fit.diagnostics
                .excluded
                .iter()
                .any(|e| is_short_reason(&e.2))
        );
        assert!(
            fit.used[0] >= 2,
            "the points inside the filter's length are not used"
        );
        // Without the automatic range (no filter seen) N absorbs the filter instead.
        let plain = fit_no_auto(&curve);
        assert!(plain.diagnostics.filter_correlation_time.is_none());
    }

    fn fit_no_auto(curve: &Curve<'_>) -> JointFit {
        fit(
            curve,
            &FitOptions {
                enabled: [false, true, true, true, false],
                automatic_range: false,
                ..FitOptions::default()
            },
        )
        .unwrap()
    }

    /// Exact model curve on octave τ (no noise): the fit must return the coefficients.
    #[test]
    fn exact_model_is_recovered() {
        let t0 = 0.01;
        let n = 2_880_000usize;
        let m: Vec<usize> = (0..21).map(|k| 1usize << k).collect();
        let taus: Vec<f64> = m.iter().map(|&m| m as f64 * t0).collect();
        let truth = [1e-6, 1e-5, 4e-8, 1e-9, 1e-13];
        let var: Vec<f64> = taus.iter().map(|t| model_variance(&truth, *t)).collect();
        let terms: Vec<usize> = m.iter().map(|&m| n + 1 - 2 * m).collect();
        let curve = Curve {
            taus: &taus,
            variance: &var,
            m: &m,
            n_terms: &terms,
            overlapping: true,
            edf: None,
        };
        let fit = joint(&curve, [true; 5], None).unwrap();
        for (j, t) in truth.iter().enumerate() {
            assert!(
                (fit.squared[j] - t).abs() <= 1e-8 * t,
                "{j}: {} vs {t}",
                fit.squared[j]
            );
        }
        assert!(fit.chi2 < 1e-12);
    }

    #[test]
    fn absent_term_is_missing_with_reason() {
        let m: Vec<usize> = (0..12).map(|k| 1usize << k).collect();
        let taus: Vec<f64> = m.iter().map(|&m| m as f64).collect();
        // Pure white rate noise: Q, B, K, R must come out missing or tiny; N exact.
        let var: Vec<f64> = taus.iter().map(|t| 4.0 / t).collect();
        let terms: Vec<usize> = m.iter().map(|&m| 100_001 - 2 * m).collect();
        let curve = Curve {
            taus: &taus,
            variance: &var,
            m: &m,
            n_terms: &terms,
            overlapping: true,
            edf: None,
        };
        let fit = joint(&curve, [true; 5], None).unwrap();
        let n = &fit.terms[1];
        assert!((n.value.unwrap() - 2.0).abs() < 1e-9);
        for j in [0, 2, 3, 4] {
            let t = &fit.terms[j];
            assert!(t.value.is_none() || t.value.unwrap() < 1e-6, "{t:?}");
        }
        let missing = fit.terms.iter().filter(|t| t.missing.is_some()).count();
        assert!(missing >= 1);
    }

    #[test]
    fn constant_and_short_curves_are_errors() {
        let m = [1usize, 2, 4];
        let taus = [1.0, 2.0, 4.0];
        let zero = [0.0; 3];
        let terms = [99usize, 97, 93];
        let curve = Curve {
            taus: &taus,
            variance: &zero,
            m: &m,
            n_terms: &terms,
            overlapping: true,
            edf: None,
        };
        assert!(joint(&curve, [true; 5], None).is_err());
        let var = [1.0, 0.5, 0.25];
        let curve = Curve {
            variance: &var,
            ..curve
        };
        assert!(matches!(
            joint(&curve, [true; 5], Some((1.5, 10.0))),
            Err(Error::TooShort { .. })
        ));
        assert!(joint(&curve, [false; 5], None).is_err());
    }
}
