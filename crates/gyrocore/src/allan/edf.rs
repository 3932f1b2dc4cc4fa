//! Equivalent degrees of freedom (EDF) of Allan-family variance estimates.
//!
//! A variance estimate `σ̂²` of a power-law noise is modelled as `σ² · χ²_edf / edf`; the EDF
//! depends on the estimator, the noise type `α` (rate PSD `S ∝ f^α`), the averaging factor
//! `m` and the number of phase (angle) samples `N`.
//!
//! **Allan, modified Allan, Hadamard: Greenhall's algorithm** (C. A. Greenhall and W. J. Riley,
//! "Uncertainty of stability variances based on finite differences", 35th PTTI, 2003; the
//! equation and table numbers below are that paper's; SP1065 §5.2.x cites it). A variance built
//! from `d`-th differences (`d = 2` Allan, `3` Hadamard) of the phase, with filter factor `F`
//! (`F = m` unmodified, `F = 1` modified) and stride factor `S` (`S = m` overlapping, `1`
//! non-overlapping), has
//!
//! ```text
//! L = m/F + m·d,   M = 1 + ⌊S(N − L)/m⌋,   J = min(M, (d+1)S),   r = M/S
//! sw(t) = −|t|, t² ln|t|, |t|³, t⁴ ln|t|, |t|⁵, t⁶ ln|t|, |t|⁷   for α = 2, 1, 0, −1, −2, −3, −4  (eq. 7)
//! sx(t) = F² [2 sw(t) − sw(t − 1/F) − sw(t + 1/F)]   (sw of α+2 when F = ∞)        (eq. 8)
//! sz(t) = Σ_k (−1)^k C(2d, d+k) sx(t + k),  k = −d..d                               (eq. 9)
//! BasicSum = sz(0)² + (1 − J/M) sz(J/S)² + 2 Σ_{j=1}^{J−1} (1 − j/M) sz(j/S)²       (eq. 10)
//! 1/edf = BasicSum / (M · sz(0)²)                                                   (eq. 13)
//! ```
//!
//! with the paper's case split (J_max = 100; large-r asymptotes of Tables 1–3) for modified
//! variances (case 1), unmodified α ≤ 0 (case 2), α = 1 (case 3) and α = 2 (case 4). The code
//! follows AllanTools' `edf_greenhall` case by case, with two improvements: case 4 with
//! `⌈r⌉ ≤ d` (AllanTools raises `NotImplementedError`) uses the exact eq. 13, and the second
//! differences in `sx` are evaluated without cancellation (binomial / log1p series), so very
//! large `m` (10⁶ and more, where AllanTools loses digits as `F²·ε` grows) stay accurate.
//! Reproduces Stable32's published intervals (AllanTools' test files) to their 4–5 digits.
//!
//! **Total variance** (SP1065 §5.2.11 and Table 11, from Howe & Greenhall): for white, flicker and
//! random-walk rate noise `edf = b·(N/m) − c` with `(b, c) = (1.50, 0), (1.17, 0.22), (0.93, 0.36)`
//! for α = 0, −1, −2. For the angle noises, where TOTVAR ≈ AVAR: α = 2 uses Greenhall's
//! overlapping-Allan EDF (what Stable32 does: its TOTDEV intervals match it to 5 digits) and
//! α = 1 SP1065 Table 5's simple flicker-PM formula
//! `exp(√(ln((N−1)/2m) · ln((2m+1)(N−1)/4)))` (as AllanTools' `edf_totdev`; Stable32's
//! intervals imply an EDF ≈ 1.5 % larger).

//!
//! **Cap.** An estimate `σ̂² = Σ_{k<T} z_k²/T` of `T` (correlated, Gaussian) terms has
//! `edf = 2(E σ̂²)²/Var σ̂² = (tr C)²/tr(C²) ≤ rank C ≤ T` (Cauchy–Schwarz on the eigenvalues of
//! the terms' covariance `C`), and `rank C ≤ N − d` for a `d`-th difference structure on `N`
//! angle samples. So the EDF reported never exceeds the number of terms actually summed
//! (Greenhall's `M`: `N − 2m` overlapping Allan, `⌊(N−1)/m⌋ − 1` non-overlapping, `N − 3m + 1`
//! modified, `N − 3m` Hadamard) nor `N − d` (total-type and Théo1 formulas); the empirical
//! formulas and large-r table fits are clamped to it. With a correct noise type this never binds
//! on real records (the exact EDF is below it); it guards against formulas evaluated outside
//! their range.

use super::Estimator;
use crate::{Error, Result};

/// `sw(t)` of eq. 7 for power-law exponent `alpha` (−4 ..= 2; higher alphas use `alpha + 2` too).
fn sw(t: f64, alpha: i32) -> f64 {
    let a = t.abs();
    match alpha {
        2 => -a,
        1 => log_term(t, 2),
        0 => a.powi(3),
        -1 => log_term(t, 4),
        -2 => a.powi(5),
        -3 => log_term(t, 6),
        -4 => a.powi(7),
        // sx with F = ∞ asks for sw of α + 2 ≤ 4: |t|^{1−α}... not reached (α ≥ −4 ⇒ α+2 ≥ −2).
        _ => f64::NAN,
    }
}

fn log_term(t: f64, n: i32) -> f64 {
    if t == 0.0 {
        0.0
    } else {
        t.powi(n) * t.abs().ln()
    }
}

fn binomial(n: u32, k: u32) -> f64 {
    if k > n {
        return 0.0;
    }
    let k = k.min(n - k);
    let mut c = 1.0;
    for i in 0..k {
        c = c * f64::from(n - i) / f64::from(i + 1);
    }
    c
}

/// `sw(t + h) + sw(t − h) − 2 sw(t)` without catastrophic cancellation when `h ≪ |t|`.
fn second_difference(t: f64, h: f64, alpha: i32) -> f64 {
    let a = t.abs();
    let direct = || sw(t + h, alpha) + sw(t - h, alpha) - 2.0 * sw(t, alpha);
    match alpha {
        2 | 0 | -2 | -4 => {
            // sw = s·|t|^p; for |t| ≥ h both neighbours have the sign of t:
            // (a+h)^p + (a−h)^p − 2a^p = 2 Σ_{k even ≥ 2} C(p,k) a^{p−k} h^k.
            if a < h {
                return direct();
            }
            let (p, sign) = match alpha {
                2 => (1u32, -1.0),
                0 => (3, 1.0),
                -2 => (5, 1.0),
                _ => (7, 1.0),
            };
            let mut sum = 0.0;
            let mut k = 2;
            while k <= p {
                sum += binomial(p, k) * a.powi((p - k) as i32) * h.powi(k as i32);
                k += 2;
            }
            sign * 2.0 * sum
        }
        1 | -1 | -3 => {
            // sw = t^n ln|t| (n even). With u = h/|t|:
            // D = a^n [ ((1+u)^n + (1−u)^n − 2) ln a + (1+u)^n ln(1+u) + (1−u)^n ln(1−u) ].
            let n: u32 = match alpha {
                1 => 2,
                -1 => 4,
                _ => 6,
            };
            if a < 10.0 * h {
                return direct();
            }
            let u = h / a;
            let mut poly = 0.0;
            let mut k = 2;
            while k <= n {
                poly += binomial(n, k) * u.powi(k as i32);
                k += 2;
            }
            poly *= 2.0;
            // (1+u)^n ln(1+u) = Σ_k c_k u^k,  c_k = Σ_{i=0}^{min(n,k−1)} C(n,i)(−1)^{k−i+1}/(k−i);
            // the ln(1−u) partner cancels the odd k, so the sum is 2 Σ_{k even} c_k u^k.
            let mut series = 0.0;
            let mut uk = u * u;
            let mut k = 2u32;
            while k < 80 {
                let mut c = 0.0;
                for i in 0..=n.min(k - 1) {
                    let j = k - i;
                    let s = if (j + 1) % 2 == 0 { 1.0 } else { -1.0 };
                    c += binomial(n, i) * s / f64::from(j);
                }
                let term = c * uk;
                series += term;
                if term.abs() <= 1e-18 * series.abs() {
                    break;
                }
                uk *= u * u;
                k += 2;
            }
            a.powi(n as i32) * (poly * a.ln() + 2.0 * series)
        }
        _ => f64::NAN,
    }
}

/// Filter factor `F` of eq. 8: finite, or `None` for F = ∞.
#[derive(Clone, Copy)]
enum Filter {
    Finite(f64),
    Infinite,
}

/// `sx(t)` of eq. 8.
fn sx(t: f64, f: Filter, alpha: i32) -> f64 {
    match f {
        Filter::Infinite => sw(t, alpha + 2),
        Filter::Finite(f) => {
            if alpha == 2 {
                // Exact: F²(|t−h| + |t+h| − 2|t|) = 2F·max(0, 1 − F|t|).
                return 2.0 * f * (1.0 - f * t.abs()).max(0.0);
            }
            -f * f * second_difference(t, 1.0 / f, alpha)
        }
    }
}

/// `sz(t)` of eq. 9: the `d`-th difference structure (d = 1, 2, 3).
fn sz(t: f64, f: Filter, alpha: i32, d: u32) -> f64 {
    let d_i = d as i32;
    let mut s = 0.0;
    for k in -d_i..=d_i {
        let sign = if k % 2 == 0 { 1.0 } else { -1.0 };
        let c = binomial(2 * d, (d_i + k) as u32);
        s += sign * c * sx(t + f64::from(k), f, alpha);
    }
    s
}

/// BasicSum of eq. 10.
fn basic_sum(j_count: f64, m_count: f64, s: f64, f: Filter, alpha: i32, d: u32) -> f64 {
    let first = sz(0.0, f, alpha, d).powi(2);
    let second = (1.0 - j_count / m_count) * sz(j_count / s, f, alpha, d).powi(2);
    let jn = j_count as u64;
    let mut third = 0.0;
    let term = |j: u64| 2.0 * (1.0 - j as f64 / m_count) * sz(j as f64 / s, f, alpha, d).powi(2);
    match (alpha, f) {
        (2, Filter::Finite(fv)) => {
            // sz(t) vanishes unless t lies within 1/F of an integer 0..=d (white PM): visit only
            // those j (keeps the exact eq. 13 cheap when J is large).
            let mut last: Option<u64> = None;
            for k in 0..=u64::from(d) {
                let lo = (((k as f64) - 1.0 / fv) * s).floor().max(1.0) as u64;
                let hi = ((((k as f64) + 1.0 / fv) * s).ceil() as u64).min(jn.saturating_sub(1));
                let mut j = lo.max(last.map_or(0, |l| l + 1));
                while j <= hi {
                    third += term(j);
                    last = Some(j);
                    j += 1;
                }
            }
        }
        _ => {
            for j in 1..jn {
                third += term(j);
            }
        }
    }
    first + second + third
}

/// Table 1 (modified variances, case 1.2): `(a0, a1)` by α (2..−4) and d (1..3).
fn table1(alpha: i32, d: u32) -> (f64, f64) {
    const T: [[(f64, f64); 3]; 7] = [
        [
            (2.0 / 3.0, 1.0 / 3.0),
            (7.0 / 9.0, 1.0 / 2.0),
            (22.0 / 25.0, 2.0 / 3.0),
        ],
        [(0.840, 0.345), (0.997, 0.616), (1.141, 0.843)],
        [(1.079, 0.368), (1.033, 0.607), (1.184, 0.848)],
        [(-1.0, -1.0), (1.048, 0.534), (1.180, 0.816)],
        [(-1.0, -1.0), (1.302, 0.535), (1.175, 0.777)],
        [(-1.0, -1.0), (-1.0, -1.0), (1.194, 0.703)],
        [(-1.0, -1.0), (-1.0, -1.0), (1.489, 0.702)],
    ];
    T[(2 - alpha) as usize][(d - 1) as usize]
}

/// Table 2 (unmodified variances, cases 2.2 and 3.2).
fn table2(alpha: i32, d: u32) -> (f64, f64) {
    const T: [[(f64, f64); 3]; 7] = [
        [
            (3.0 / 2.0, 1.0 / 2.0),
            (35.0 / 18.0, 1.0),
            (231.0 / 100.0, 3.0 / 2.0),
        ],
        [(78.6, 25.2), (790.0, 410.0), (9950.0, 6520.0)],
        [
            (2.0 / 3.0, 1.0 / 6.0),
            (2.0 / 3.0, 1.0 / 3.0),
            (7.0 / 9.0, 1.0 / 2.0),
        ],
        [(-1.0, -1.0), (0.852, 0.375), (0.997, 0.617)],
        [(-1.0, -1.0), (1.079, 0.368), (1.033, 0.607)],
        [(-1.0, -1.0), (-1.0, -1.0), (1.053, 0.553)],
        [(-1.0, -1.0), (-1.0, -1.0), (1.302, 0.535)],
    ];
    T[(2 - alpha) as usize][(d - 1) as usize]
}

/// Table 3 (α = 1, unmodified): `(b0, b1)` by d.
fn table3(d: u32) -> (f64, f64) {
    [(6.0, 4.0), (15.23, 12.0), (47.8, 40.0)][(d - 1) as usize]
}

const J_MAX: f64 = 100.0;

/// Greenhall's EDF for a `d`-th difference variance (d = 1, 2, 3) at averaging factor `m` from
/// `n_phase` phase samples, noise exponent `alpha` (−4 ..= 2 with `alpha + 2d > 1`).
pub fn greenhall(
    alpha: i32,
    d: u32,
    m: usize,
    n_phase: usize,
    overlapping: bool,
    modified: bool,
) -> Result<f64> {
    if !(1..=3).contains(&d) {
        return Err(Error::invalid("d", format!("must be 1, 2 or 3, got {d}")));
    }
    if !(-4..=2).contains(&alpha) || alpha + 2 * d as i32 <= 1 {
        return Err(Error::invalid(
            "alpha",
            format!(
                "Greenhall's EDF needs -4 <= alpha <= 2 and alpha + 2d > 1, got alpha = {alpha}, d = {d}"
            ),
        ));
    }
    if m == 0 {
        return Err(Error::invalid("m", "must be >= 1"));
    }
    let mf = m as f64;
    let n = n_phase as f64;
    let df = f64::from(d);
    let f_val = if modified { 1.0 } else { mf };
    let s = if overlapping { mf } else { 1.0 };
    let l = mf / f_val + mf * df;
    if n < l {
        return Err(Error::TooShort {
            name: "data",
            needed: l.ceil() as usize,
            got: n_phase,
        });
    }
    let big_m = 1.0 + (s * (n - l) / mf).floor();
    let j = big_m.min((df + 1.0) * s);
    let r = big_m / s;
    let inv = if modified {
        // Case 1: modified variances, all α.
        if j <= J_MAX {
            basic_sum(j, big_m, s, Filter::Finite(1.0), alpha, d)
                / (sz(0.0, Filter::Finite(1.0), alpha, d).powi(2) * big_m)
        } else if r > df + 1.0 {
            let (a0, a1) = table1(alpha, d);
            (a0 - a1 / r) / r
        } else {
            let m_prime = J_MAX / r;
            basic_sum(J_MAX, J_MAX, m_prime, Filter::Finite(1.0), alpha, d)
                / (sz(0.0, Filter::Finite(1.0), alpha, d).powi(2) * J_MAX)
        }
    } else if alpha <= 0 {
        // Case 2: unmodified, α ≤ 0.
        if j <= J_MAX {
            let f = if mf * (df + 1.0) <= J_MAX {
                Filter::Finite(mf)
            } else {
                Filter::Infinite
            };
            basic_sum(j, big_m, s, f, alpha, d) / (sz(0.0, f, alpha, d).powi(2) * big_m)
        } else if r > df + 1.0 {
            let (a0, a1) = table2(alpha, d);
            (a0 - a1 / r) / r
        } else {
            let m_prime = J_MAX / r;
            basic_sum(J_MAX, J_MAX, m_prime, Filter::Infinite, alpha, d)
                / (sz(0.0, Filter::Infinite, alpha, d).powi(2) * J_MAX)
        }
    } else if alpha == 1 {
        // Case 3: unmodified, α = 1.
        if j <= J_MAX {
            let f = Filter::Finite(mf);
            basic_sum(j, big_m, s, f, 1, d) / (sz(0.0, f, 1, d).powi(2) * big_m)
        } else if r > df + 1.0 {
            let (a0, a1) = table2(1, d);
            let (b0, b1) = table3(d);
            (a0 - a1 / r) / ((b0 + b1 * mf.ln()).powi(2) * r)
        } else {
            let m_prime = J_MAX / r;
            let (b0, b1) = table3(d);
            basic_sum(J_MAX, J_MAX, m_prime, Filter::Finite(m_prime), 1, d)
                / ((b0 + b1 * mf.ln()).powi(2) * J_MAX)
        }
    } else {
        // Case 4: unmodified, α = 2.
        let k = r.ceil();
        if k <= df {
            // Exact eq. 13 (AllanTools leaves this sub-case unimplemented).
            let f = Filter::Finite(mf);
            basic_sum(j, big_m, s, f, 2, d) / (sz(0.0, f, 2, d).powi(2) * big_m)
        } else {
            let a0 = binomial(4 * d, 2 * d) / binomial(2 * d, d).powi(2);
            let a1 = df / 2.0;
            (a0 - a1 / r) / big_m
        }
    };
    // Never more degrees of freedom than terms in the sum (module docs, "Cap"); binds only
    // where the large-r table fits run past their range.
    let edf = (1.0 / inv).min(big_m);
    if edf.is_finite() && edf > 0.0 {
        Ok(edf)
    } else {
        Err(Error::invalid(
            "edf",
            format!("no valid EDF for alpha = {alpha}, d = {d}, m = {m}, N = {n_phase}"),
        ))
    }
}

/// SP1065 Table 5's simple EDF formulas (Stein 1985) for the overlapping Allan variance.
pub fn simple_allan(alpha: i32, m: usize, n_phase: usize) -> f64 {
    let n = n_phase as f64;
    let m = m as f64;
    match alpha {
        2 => (n + 1.0) * (n - 2.0 * m) / (2.0 * (n - m)),
        1 => (((n - 1.0) / (2.0 * m)).ln() * ((2.0 * m + 1.0) * (n - 1.0) / 4.0).ln())
            .sqrt()
            .exp(),
        0 => {
            (3.0 * (n - 1.0) / (2.0 * m) - 2.0 * (n - 2.0) / n)
                * (4.0 * m * m / (4.0 * m * m + 5.0))
        }
        -1 => {
            if m == 1.0 {
                2.0 * (n - 2.0) / (2.3 * n - 4.9)
            } else {
                5.0 * n * n / (4.0 * m * (n + 3.0 * m))
            }
        }
        _ => {
            (n - 2.0) / (m * (n - 3.0).powi(2))
                * ((n - 1.0).powi(2) - 3.0 * m * (n - 1.0) + 4.0 * m * m)
        }
    }
}

/// Total-variance EDF (SP1065 Table 11 for α = 0, −1, −2; see the module docs for α = 1, 2).
pub fn total(alpha: i32, m: usize, n_phase: usize) -> Result<f64> {
    let ratio = n_phase as f64 / m as f64;
    let edf = match alpha {
        0 => 1.50 * ratio,
        -1 => 1.17 * ratio - 0.22,
        -2 => 0.93 * ratio - 0.36,
        1 => simple_allan(1, m, n_phase),
        2 => return greenhall(2, 2, m, n_phase, true, false),
        other => {
            return Err(Error::invalid(
                "alpha",
                format!("total-variance EDF needs -2 <= alpha <= 2, got {other}"),
            ));
        }
    };
    let edf = edf.min(rank_bound(n_phase, 2));
    if edf.is_finite() && edf > 0.0 {
        Ok(edf)
    } else {
        Err(Error::invalid(
            "edf",
            format!("no valid total-variance EDF for alpha = {alpha}, m = {m}, N = {n_phase}"),
        ))
    }
}

/// Modified-total-variance EDF, SP 1065 Table 12 (Greenhall's fits): `edf = b·(N/m) − c` with
/// `(b, c) = (1.90, 2.10), (1.20, 1.40), (1.10, 1.20), (0.85, 0.50), (0.75, 0.31)` for
/// α = 2, 1, 0, −1, −2 (`N` angle samples).
pub fn modified_total(alpha: i32, m: usize, n_phase: usize) -> Result<f64> {
    let (b, c) = match alpha {
        2 => (1.90, 2.10),
        1 => (1.20, 1.40),
        0 => (1.10, 1.20),
        -1 => (0.85, 0.50),
        -2 => (0.75, 0.31),
        other => {
            return Err(Error::invalid(
                "alpha",
                format!("modified-total EDF is tabulated for -2 <= alpha <= 2, got {other}"),
            ));
        }
    };
    positive_edf(
        (b * n_phase as f64 / m as f64 - c).min(rank_bound(n_phase, 2)),
        "modified-total",
        alpha,
        m,
        n_phase,
    )
}

/// Hadamard-total-variance EDF, SP 1065 Table 13 (Howe, Beard, Greenhall, Riley):
/// `edf = (T/τ)/(b0 + b1·τ/T)`, `T/τ = (N − 1)/m` rate samples per τ, with `(b0, b1) =
/// (0.559, 1.004), (0.868, 1.140), (0.938, 1.696), (0.974, 2.554), (1.276, 3.149)` for
/// α = 0 … −4. The table covers the frequency noises only: for α = 1, 2 (and at m = 1, where
/// HTOTVAR is the overlapping Hadamard variance) Greenhall's overlapping-Hadamard EDF is used.
pub fn hadamard_total(alpha: i32, m: usize, n_phase: usize) -> Result<f64> {
    let (b0, b1) = match alpha {
        0 => (0.559, 1.004),
        -1 => (0.868, 1.140),
        -2 => (0.938, 1.696),
        -3 => (0.974, 2.554),
        -4 => (1.276, 3.149),
        _ => return greenhall(alpha, 3, m, n_phase, true, false),
    };
    if m == 1 {
        return greenhall(alpha, 3, m, n_phase, true, false);
    }
    let ratio = n_phase.saturating_sub(1) as f64 / m as f64;
    positive_edf(
        (ratio / (b0 + b1 / ratio)).min(rank_bound(n_phase, 3)),
        "Hadamard-total",
        alpha,
        m,
        n_phase,
    )
}

/// Théo1 / ThéoBR EDF, Howe & Tasset's empirical formulas (SP 1065 Table 14) with
/// `r = 0.75·m` and `N` angle samples:
///
/// ```text
/// α =  2: 0.86 (N + 1)(N − 4r/3)/(N − r) · r/(r + 1.14)
/// α =  1: (4.798 N² − 6.374 r N + 12.387 r)/(√(r + 36.6) (N − r)) · r/(r + 0.3)
/// α =  0: [(4.1 N + 0.8)/r − (3.1 N + 6.5)/N] · r^1.5/(r^1.5 + 5.2)
/// α = −1: (2 N² − 1.3 N r − 3.5 r)/(N r) · r³/(r³ + 2.3)
/// α = −2: (4.4 N − 2)/(2.9 r) · [(4.4 N − 1)² − 8.6 r (4.4 N − 1) + 11.4 r²]/(4.4 N − 3)²
/// ```
///
/// The random-walk fit turns negative near the end of the record (r > 0.63 N); the EDF is
/// floored at 1 (one degree of freedom, the least any estimate carries).
pub fn theo1(alpha: i32, m: usize, n_phase: usize) -> Result<f64> {
    let r = 0.75 * m as f64;
    let n = n_phase as f64;
    let edf = match alpha {
        2 => 0.86 * (n + 1.0) * (n - 4.0 * r / 3.0) / (n - r) * (r / (r + 1.14)),
        1 => {
            (4.798 * n * n - 6.374 * r * n + 12.387 * r) / ((r + 36.6).sqrt() * (n - r))
                * (r / (r + 0.3))
        }
        0 => ((4.1 * n + 0.8) / r - (3.1 * n + 6.5) / n) * (r.powf(1.5) / (r.powf(1.5) + 5.2)),
        -1 => (2.0 * n * n - 1.3 * n * r - 3.5 * r) / (n * r) * (r.powi(3) / (r.powi(3) + 2.3)),
        -2 => {
            let a = 4.4 * n - 1.0;
            (4.4 * n - 2.0) / (2.9 * r) * ((a * a - 8.6 * r * a + 11.4 * r * r) / (a - 2.0).powi(2))
        }
        other => {
            return Err(Error::invalid(
                "alpha",
                format!("Théo1 EDF is defined for -2 <= alpha <= 2, got {other}"),
            ));
        }
    };
    if edf.is_finite() {
        Ok(edf.max(1.0).min(rank_bound(n_phase, 2).max(1.0)))
    } else {
        Err(Error::invalid(
            "edf",
            format!("no valid Théo1 EDF for alpha = {alpha}, m = {m}, N = {n_phase}"),
        ))
    }
}

/// `N − d`: the rank of a quadratic form in `N` angle samples that annihilates polynomials of
/// degree `< d` (the d-th difference structure), an upper bound of its EDF (module docs, "Cap").
fn rank_bound(n_phase: usize, d: usize) -> f64 {
    n_phase.saturating_sub(d) as f64
}

fn positive_edf(edf: f64, what: &str, alpha: i32, m: usize, n_phase: usize) -> Result<f64> {
    if edf.is_finite() && edf > 0.0 {
        Ok(edf)
    } else {
        Err(Error::invalid(
            "edf",
            format!("no valid {what} EDF for alpha = {alpha}, m = {m}, N = {n_phase}"),
        ))
    }
}

/// Number of differences `d` of an estimator's kernel (2 Allan-type, 3 Hadamard).
pub fn differences(estimator: Estimator) -> u32 {
    match estimator {
        Estimator::Hadamard => 3,
        _ => 2,
    }
}

/// Lowest α for which the estimator converges (`α + 2d > 1`).
pub fn min_alpha(estimator: Estimator) -> i32 {
    match estimator {
        Estimator::Hadamard => -4,
        _ => -2,
    }
}

/// EDF of `estimator` at averaging factor `m` on `n_phase` phase samples for noise `alpha`.
pub fn edf(estimator: Estimator, alpha: i32, m: usize, n_phase: usize) -> Result<f64> {
    match estimator {
        Estimator::Overlapping => greenhall(alpha, 2, m, n_phase, true, false),
        Estimator::NonOverlapping => greenhall(alpha, 2, m, n_phase, false, false),
        Estimator::Modified => greenhall(alpha, 2, m, n_phase, true, true),
        Estimator::Hadamard => greenhall(alpha, 3, m, n_phase, true, false),
        Estimator::Total => total(alpha, m, n_phase),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rel(a: f64, b: f64) -> f64 {
        ((a - b) / b).abs()
    }

    /// Values of AllanTools 2024.06 `edf_greenhall(alpha, d, m, N, overlapping, modified)`
    /// (same algorithm; small m, where its F²-scaled differences are still accurate).
    #[test]
    fn matches_allantools_greenhall() {
        // (alpha, d, m, N, overlapping, modified, edf)
        let cases: [(i32, u32, usize, usize, bool, bool, f64); 16] = [
            (0, 2, 1, 1000, true, false, 781.2476904305386),
            (0, 2, 10, 1000, true, false, 134.9344212246053),
            (-1, 2, 10, 1000, true, false, 114.55231109237145),
            (-2, 2, 100, 1000, true, false, 7.744433688286545),
            (1, 2, 10, 1000, true, false, 247.05607572839637),
            (2, 2, 10, 1000, true, false, 506.65885111371625),
            (2, 2, 10, 1000, false, false, 50.66588511137163),
            (0, 2, 10, 1000, true, true, 94.5374886048681),
            (2, 2, 50, 1000, true, true, 22.741831821353802),
            (-2, 3, 10, 1000, true, false, 94.22727919283604),
            (-3, 3, 30, 1000, true, false, 29.314104470215085),
            (1, 3, 5, 1000, false, false, 90.11427760454454),
            (-1, 2, 1, 1000, true, true, 894.351406796214),
            (1, 2, 2, 1000, true, false, 531.7575397999223),
            (-1, 3, 200, 1000, true, false, 2.8968012157050733),
            (-4, 3, 3, 1000, true, false, 249.97201907012024),
        ];
        for (alpha, d, m, n, ov, md, expect) in cases {
            let got = greenhall(alpha, d, m, n, ov, md).unwrap();
            // 1e-9: same formulas; only the cancellation-free second differences differ
            // (AllanTools' direct form loses ~F²ε ≈ 1e-13 at these m).
            assert!(
                rel(got, expect) < 1e-9,
                "{alpha} {d} {m} {n} {ov} {md}: {got} vs {expect}"
            );
        }
    }

    /// Stable32 1.60 intervals for the OCXO data set in AllanTools' test suite
    /// (tests/ocxo/{oadev,mdev,ohdev,adev,hdev}_octave.txt; 19982 frequency points → N = 19983
    /// phase points; confidence factor 0.683). Columns: AF, alpha, min σ, σ, max σ.
    #[test]
    fn reproduces_stable32_intervals() {
        type Row = (usize, i32, f64, f64, f64);
        let oadev: [Row; 6] = [
            (1, 1, 7.5672e-11, 7.6143e-11, 7.6622e-11),
            (4, 0, 1.8650e-11, 1.8816e-11, 1.8987e-11),
            (16, -2, 6.0842e-12, 6.2088e-12, 6.3413e-12),
            (256, -1, 4.7422e-12, 5.0826e-12, 5.5085e-12),
            (2048, 0, 6.9598e-12, 8.2071e-12, 1.0509e-11),
            (4096, 0, 7.2435e-12, 9.1057e-12, 1.4019e-11),
        ];
        let mdev: [Row; 4] = [
            (2, 1, 2.8003e-11, 2.8204e-11, 2.8410e-11),
            (32, -2, 3.5145e-12, 3.6257e-12, 3.7483e-12),
            (1024, -1, 5.1767e-12, 6.0005e-12, 7.4049e-12),
            (4096, 0, 7.3831e-12, 9.8071e-12, 1.9848e-11),
        ];
        let ohdev: [Row; 3] = [
            (8, 1, 9.8549e-12, 9.9549e-12, 1.0058e-11),
            (512, -2, 3.8499e-12, 4.2789e-12, 4.8931e-12),
            (4096, 0, 6.5430e-12, 8.4681e-12, 1.4748e-11),
        ];
        let adev: [Row; 3] = [
            (2, 1, 3.9622e-11, 3.9987e-11, 4.0363e-11),
            (128, -1, 5.3875e-12, 5.7008e-12, 6.0765e-12),
            (2048, -2, 7.5297e-12, 9.2304e-12, 1.3075e-11),
        ];
        let hdev: [Row; 2] = [
            (4, 0, 1.9211e-11, 1.9473e-11, 1.9745e-11),
            (1024, -2, 3.9794e-12, 4.6669e-12, 5.9030e-12),
        ];
        let totdev: [Row; 4] = [
            // tests/ocxo/totdev_octave.txt; α = 0, −1, −2 use SP1065 Table 11.
            (4, 0, 1.8666e-11, 1.8817e-11, 1.8972e-11),
            (64, -2, 6.1397e-12, 6.3882e-12, 6.6697e-12),
            (1024, -1, 5.6419e-12, 6.4162e-12, 7.6321e-12),
            (8192, 0, 6.7277e-12, 8.7041e-12, 1.5133e-11),
        ];
        let n = 19983;
        let level = 0.683;
        let check = |estimator: Estimator, rows: &[Row]| {
            for &(m, alpha, lo, s, hi) in rows {
                let e = edf(estimator, alpha, m, n).unwrap();
                let q = (1.0 - level) / 2.0;
                let low = s * (e / crate::stats::chi2_isf(q, e).unwrap()).sqrt();
                let high = s * (e / crate::stats::chi2_ppf(q, e).unwrap()).sqrt();
                // 6e-4: Stable32 prints 5 digits (σ and bounds each rounded, ≤ 1e-4 relative
                // together) and evaluates Greenhall's large-r cases from tables with 3-4
                // significant digits (AllanTools shows the same ≤ 4e-4 differences).
                assert!(
                    rel(low, lo) < 6e-4,
                    "{estimator:?} m={m}: low {low} vs {lo}"
                );
                assert!(
                    rel(high, hi) < 6e-4,
                    "{estimator:?} m={m}: high {high} vs {hi}"
                );
            }
        };
        check(Estimator::Overlapping, &oadev);
        check(Estimator::Modified, &mdev);
        check(Estimator::Hadamard, &ohdev);
        check(Estimator::NonOverlapping, &adev);
        check(Estimator::Total, &totdev);
        // Non-overlapping Hadamard is not an estimator here; check it through `greenhall`.
        for (m, alpha, lo, s, hi) in hdev {
            let e = greenhall(alpha, 3, m, n, false, false).unwrap();
            let low = s * (e / crate::stats::chi2_isf(0.1585, e).unwrap()).sqrt();
            let high = s * (e / crate::stats::chi2_ppf(0.1585, e).unwrap()).sqrt();
            assert!(rel(low, lo) < 6e-4 && rel(high, hi) < 6e-4, "hdev m={m}");
        }
    }

    #[test]
    fn large_m_is_stable() {
        // The EDF of white rate noise at r = M/S fixed must not depend on how large m is
        // (case 2.1b / 2.3 use F = ∞); for α = 1 (F = m) it must vary smoothly in ln m.
        let e1 = greenhall(0, 2, 1000, 10_000, true, false).unwrap();
        let e2 = greenhall(0, 2, 1_000_000, 10_000_000, true, false).unwrap();
        assert!(rel(e1, e2) < 1e-3, "{e1} {e2}");
        let a = greenhall(1, 2, 1 << 20, 1 << 24, false, false).unwrap();
        let b = greenhall(1, 2, 1 << 21, 1 << 25, false, false).unwrap();
        let c = greenhall(1, 2, 1 << 22, 1 << 26, false, false).unwrap();
        // Second difference in ln m of 1/edf is small compared to the values themselves.
        let curvature = (1.0 / a - 2.0 / b + 1.0 / c).abs() * b;
        assert!(curvature < 1e-3, "{a} {b} {c}");
    }

    #[test]
    fn white_pm_short_records_use_exact_sum() {
        // ⌈r⌉ ≤ d (case 4 with few terms, exact eq. 13). With N = 1001, m = 400 the 201
        // overlapping second differences x_{k+2m} − 2x_{k+m} + x_k (k = 0..200 < m) share no
        // sample, so for white angle noise they are independent: edf = 201 exactly.
        let e = greenhall(2, 2, 400, 1001, true, false).unwrap();
        assert!((e - 201.0).abs() < 1e-9, "{e}");
    }

    #[test]
    fn invalid_alpha() {
        assert!(greenhall(-3, 2, 4, 100, true, false).is_err());
        assert!(greenhall(3, 2, 4, 100, true, false).is_err());
        assert!(total(-3, 4, 100).is_err());
    }
}
