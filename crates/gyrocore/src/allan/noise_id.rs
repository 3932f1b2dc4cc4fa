//! Power-law noise identification per averaging factor.
//!
//! **Lag-1 autocorrelation method** (W. J. Riley and C. A. Greenhall, "Power law noise
//! identification using the lag 1 autocorrelation", 18th EFTF, 2004; NIST SP1065 §5.5.6;
//! AllanTools `autocorr_noise_id`). On the phase (angle) series `x` at averaging factor `m`:
//!
//! 1. decimate: `z_k = x_{k·m}`, `k = 0..⌈M/m⌉−1` (needs at least 30 points);
//! 2. remove a quadratic trend (least squares) — a rate offset and drift;
//! 3. `r₁ = Σ_k (z_k − z̄)(z_{k+1} − z̄) / Σ_k (z_k − z̄)²`, `δ = r₁/(1 + r₁)`;
//!    while `δ ≥ 0.25` and `d < d_max`, difference `z` once more (`d += 1`) and repeat;
//! 4. `α = 2 − round(2δ) − 2d` (the phase exponent `p = −2(δ + d)`, `α = p + 2`), rounded half
//!    to even like NumPy.
//!
//! `d_max = 2` for the Allan-type variances, 3 for the Hadamard variance. Everything is computed
//! in streaming passes over the strided samples `x_{k·m}` (the trend, then one pass per
//! difference order, the differences rebuilt on the fly from `d + 1` consecutive residuals):
//! O(M/m) work and O(1) memory per τ, so an octave τ set costs O(M) in total.
//!
//! **Too few points.** When `⌈M/m⌉ < 30` the ACF method is not defined (AllanTools raises). We
//! carry the result of the largest averaging factor that still has 30 decimated points,
//! `m_c = ⌊(M − 1)/29⌋` — the nearest τ at which the method is valid (identified once, even if
//! `m_c` is not among the requested τ). Only when the whole record has fewer than 30 phase
//! points (no valid τ at all) do we fall back to Stable32's classic method: the **B1 ratio**
//! (Barnes 1969; Howe, Beard, Greenhall & Riley 2000, Table 3) of the standard variance to the
//! Allan variance of the `m`-averages, compared with its expectation `B1(N, μ)` for each noise
//! (decision at geometric means), and the **R(n) ratio** MVAR/AVAR (IEEE 1139) to separate white
//! from flicker angle noise, which B1 cannot distinguish (both μ = −2).

use rayon::prelude::*;

/// Minimum number of decimated points for the lag-1 ACF method (Riley & Greenhall 2004).
pub const MIN_POINTS: usize = 30;

/// Result of one lag-1 ACF identification.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Identification {
    /// Power-law exponent α of the rate PSD (S ∝ f^α), integer.
    pub alpha: i32,
    /// Number of differences taken.
    pub d: u32,
    /// δ = r₁/(1 + r₁) of the final (differenced) series.
    pub delta: f64,
}

/// Orthogonal quadratic trend of `z_k = x[k·m]`, `k < len`: `b0 + b1·u + b2·(u² − c)` with
/// `u = k − (len−1)/2`, `c = (len² − 1)/12` (1, u, u² − c are orthogonal on the symmetric grid).
struct Trend {
    b0: f64,
    b1: f64,
    b2: f64,
    half: f64,
    c: f64,
}

impl Trend {
    fn fit(x: &[f64], m: usize, len: usize) -> Trend {
        let n = len as f64;
        let half = (n - 1.0) / 2.0;
        let c = (n * n - 1.0) / 12.0;
        let (mut s0, mut s1, mut s2) = (0.0, 0.0, 0.0);
        let mut u = -half;
        for &z in x.iter().step_by(m).take(len) {
            s0 += z;
            s1 += z * u;
            s2 += z * (u * u - c);
            u += 1.0;
        }
        // Σu² = n(n²−1)/12, Σ(u² − c)² = Σu⁴ − n c², Σu⁴ = n(n²−1)(3n²−7)/240.
        let norm1 = n * (n * n - 1.0) / 12.0;
        let norm2 = n * (n * n - 1.0) * (3.0 * n * n - 7.0) / 240.0 - n * c * c;
        Trend {
            b0: s0 / n,
            b1: if norm1 > 0.0 { s1 / norm1 } else { 0.0 },
            b2: if norm2 > 0.0 { s2 / norm2 } else { 0.0 },
            half,
            c,
        }
    }

    /// Detrended decimated samples `r_k = x[k·m] − trend(k)`, streamed.
    fn residuals<'a>(&self, x: &'a [f64], m: usize, len: usize) -> impl Iterator<Item = f64> + 'a {
        let (b0, b1, b2) = (self.b0 - self.b2 * self.c, self.b1, self.b2);
        let mut u = -self.half;
        x.iter().step_by(m).take(len).map(move |&z| {
            let r = z - (b0 + u * (b1 + b2 * u));
            u += 1.0;
            r
        })
    }
}

/// Running sums for the lag-1 autocorrelation of one stream.
#[derive(Clone, Copy)]
struct Lag1Sums {
    s: f64,
    s2: f64,
    s11: f64,
    first: f64,
    prev: f64,
    count: usize,
}

impl Lag1Sums {
    const EMPTY: Lag1Sums = Lag1Sums {
        s: 0.0,
        s2: 0.0,
        s11: 0.0,
        first: 0.0,
        prev: 0.0,
        count: 0,
    };

    #[inline]
    fn push(&mut self, w: f64) {
        if self.count == 0 {
            self.first = w;
        } else {
            self.s11 += self.prev * w;
        }
        self.s += w;
        self.s2 += w * w;
        self.prev = w;
        self.count += 1;
    }

    /// `Σ(w_k − w̄)(w_{k+1} − w̄) / Σ(w_k − w̄)²`.
    fn value(&self) -> f64 {
        if self.count < 2 {
            return 0.0;
        }
        let n = self.count as f64;
        let mu = self.s / n;
        // Expansion of the centred sums; μ is ~0 after detrending/differencing, so it does
        // not cancel.
        let b = self.s2 - n * mu * mu;
        let a =
            self.s11 - mu * ((self.s - self.prev) + (self.s - self.first)) + (n - 1.0) * mu * mu;
        if b > 0.0 { a / b } else { 0.0 }
    }
}

/// Lag-1 autocorrelations of the detrended decimated series and of its first `dmax`
/// differences, all in one streaming pass (the passes are memory-bound; the extra
/// arithmetic for differences that may not be needed is free).
fn lag1_all_differences(x: &[f64], m: usize, len: usize, trend: &Trend, dmax: u32) -> [f64; 4] {
    let levels = (dmax as usize).min(3) + 1;
    let mut sums = [Lag1Sums::EMPTY; 4];
    // last[j] = value of the j-th difference at the previous index.
    let mut last = [0.0_f64; 3];
    for (k, r) in trend.residuals(x, m, len).enumerate() {
        let mut w = r;
        sums[0].push(w);
        for j in 1..levels {
            let previous = last[j - 1];
            last[j - 1] = w;
            if k < j {
                // The j-th difference starts at index j.
                break;
            }
            w -= previous;
            sums[j].push(w);
        }
    }
    let mut out = [0.0; 4];
    for j in 0..levels {
        out[j] = sums[j].value();
    }
    out
}

/// Lag-1 ACF identification at averaging factor `m` with at most `dmax` differences.
///
/// Returns `None` when fewer than [`MIN_POINTS`] decimated points are available.
pub fn lag1_acf(x: &[f64], m: usize, dmax: u32) -> Option<Identification> {
    if m == 0 || x.is_empty() {
        return None;
    }
    let len = x.len().div_ceil(m);
    if len < MIN_POINTS {
        return None;
    }
    let trend = Trend::fit(x, m, len);
    let r1s = lag1_all_differences(x, m, len, &trend, dmax);
    let mut d = 0u32;
    loop {
        let r1 = r1s[d as usize];
        let delta = r1 / (1.0 + r1);
        if delta < 0.25 || d >= dmax.min(3) {
            let alpha = 2 - (2.0 * delta).round_ties_even() as i32 - 2 * d as i32;
            return Some(Identification { alpha, d, delta });
        }
        d += 1;
    }
}

/// Expected B1 ratio for `n` averages and τ-exponent μ (Howe et al. 2000, Table 3).
fn b1_theory(n: f64, mu: i32) -> f64 {
    match mu {
        2 => n * (n + 1.0) / 6.0,
        1 => n / 2.0,
        0 => n * n.ln() / (2.0 * (n - 1.0) * std::f64::consts::LN_2),
        -1 => 1.0,
        -2 => (n * n - 1.0) / (1.5 * n * (n - 1.0)),
        _ => {
            let mu = f64::from(mu);
            n * (1.0 - n.powf(mu)) / (2.0 * (n - 1.0) * (1.0 - 2f64.powf(mu)))
        }
    }
}

/// Expected MVAR/AVAR ratio R(n) for white (α = 2) and flicker (α = 1) angle noise at factor m
/// (IEEE 1139; flicker with f_h = 1/(2τ0), as AllanTools `rn_theory`).
fn rn_theory(m: f64, alpha: i32) -> f64 {
    if alpha == 2 {
        1.0 / m
    } else {
        let avar = (1.038 + 3.0 * (2.0 * std::f64::consts::PI * 0.5 * m).ln())
            / (4.0 * std::f64::consts::PI.powi(2));
        let mvar = 3.0 * (256.0f64 / 27.0).ln() / (8.0 * std::f64::consts::PI.powi(2));
        mvar / avar
    }
}

/// B1 (and R(n)) identification for very short records; `None` when it cannot be formed.
pub fn b1_ratio(x: &[f64], m: usize) -> Option<i32> {
    let n_phase = x.len();
    if m == 0 || n_phase < 2 {
        return None;
    }
    let nb = (n_phase - 1) / m;
    if nb < 2 {
        return None;
    }
    let means: Vec<f64> = (0..nb)
        .map(|j| (x[(j + 1) * m] - x[j * m]) / m as f64)
        .collect();
    let mean = means.iter().sum::<f64>() / nb as f64;
    let var = means.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (nb - 1) as f64;
    let avar =
        means.windows(2).map(|w| (w[1] - w[0]).powi(2)).sum::<f64>() / (2.0 * (nb - 1) as f64);
    if avar <= 0.0 {
        return None;
    }
    let b1 = var / avar;
    let n = nb as f64;
    let boundary = |mu_hi: i32, mu_lo: i32| (b1_theory(n, mu_hi) * b1_theory(n, mu_lo)).sqrt();
    // μ = 1, 0, −1, −2 ↔ α = −2, −1, 0, {1, 2}.
    if b1 > boundary(1, 0) {
        return Some(-2);
    }
    if b1 > boundary(0, -1) {
        return Some(-1);
    }
    if b1 > boundary(-1, -2) {
        return Some(0);
    }
    // White or flicker angle noise: R(n) = MVAR/AVAR (overlapping AVAR, direct sums).
    let terms_a = n_phase.saturating_sub(2 * m);
    let terms_m = (n_phase + 1).saturating_sub(3 * m);
    if terms_a == 0 || terms_m == 0 {
        return Some(2);
    }
    let d2 = |i: usize| x[i + 2 * m] - 2.0 * x[i + m] + x[i];
    let oavar = (0..terms_a).map(|i| d2(i).powi(2)).sum::<f64>() / terms_a as f64;
    let mvar = (0..terms_m)
        .map(|j| (j..j + m).map(d2).sum::<f64>().powi(2))
        .sum::<f64>()
        / (terms_m as f64 * (m * m) as f64);
    if oavar <= 0.0 {
        return Some(2);
    }
    let rn = mvar / oavar;
    let mf = m as f64;
    let rn_boundary = (rn_theory(mf, 2) * rn_theory(mf, 1)).sqrt();
    Some(if rn > rn_boundary { 1 } else { 2 })
}

/// Identified α at each averaging factor (see the module docs for the fallbacks).
///
/// `dmax` is 2 for the Allan-type variances and 3 for the Hadamard variance. The α values are
/// as identified (the caller clamps them to the estimator's convergent range).
pub fn identify(x: &[f64], ms: &[usize], dmax: u32) -> Vec<i32> {
    let n_phase = x.len();
    let results: Vec<Option<i32>> = ms
        .par_iter()
        .with_max_len(1)
        .map(|&m| lag1_acf(x, m, dmax).map(|id| id.alpha))
        .collect();
    if results.iter().all(Option::is_some) {
        return results.into_iter().map(|a| a.unwrap_or(0)).collect();
    }
    // Largest factor with MIN_POINTS decimated points.
    let m_c = n_phase.saturating_sub(1) / (MIN_POINTS - 1);
    let carried = if m_c >= 1 {
        lag1_acf(x, m_c, dmax).map(|id| id.alpha)
    } else {
        None
    };
    let mut last_b1: Option<i32> = None;
    let mut out = Vec::with_capacity(ms.len());
    // Process in increasing m so the B1 fallback can carry the previous τ's result.
    let mut order: Vec<usize> = (0..ms.len()).collect();
    order.sort_by_key(|&i| ms[i]);
    out.resize(ms.len(), 0);
    for i in order {
        out[i] = match (results[i], carried) {
            (Some(a), _) | (None, Some(a)) => a,
            (None, None) => {
                let b = b1_ratio(x, ms[i]).or(last_b1);
                last_b1 = b;
                // Nothing identifiable (two or three samples): white rate noise, the model
                // whose EDF is the plain count of independent terms' neighbourhood.
                b.unwrap_or(0)
            }
        };
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Deterministic Gaussian-ish noise (sum of 12 uniforms from a 64-bit LCG).
    fn noise(n: usize, seed: u64) -> Vec<f64> {
        let mut s = seed;
        (0..n)
            .map(|_| {
                let mut acc = 0.0;
                for _ in 0..12 {
                    s = s
                        .wrapping_mul(6364136223846793005)
                        .wrapping_add(1442695040888963407);
                    acc += (s >> 11) as f64 / (1u64 << 53) as f64;
                }
                acc - 6.0
            })
            .collect()
    }

    fn cumsum(v: &[f64]) -> Vec<f64> {
        let mut acc = 0.0;
        let mut out = vec![0.0];
        for x in v {
            acc += x;
            out.push(acc);
        }
        out
    }

    #[test]
    fn identifies_integer_power_laws() {
        let w = noise(20_000, 7);
        // White angle: x white (α = 2); white rate: x = Σ white (α = 0); random-walk rate:
        // x = ΣΣ white (α = −2).
        let white_angle = w.clone();
        let white_rate = cumsum(&w);
        let rw_rate = cumsum(&white_rate);
        for m in [1usize, 4, 16, 64] {
            assert_eq!(lag1_acf(&white_angle, m, 2).unwrap().alpha, 2, "m={m}");
            assert_eq!(lag1_acf(&white_rate, m, 2).unwrap().alpha, 0, "m={m}");
            assert_eq!(lag1_acf(&rw_rate, m, 2).unwrap().alpha, -2, "m={m}");
        }
        // Hadamard range: a random run (α = −4) needs d = 3. Only at m = 1: decimating a
        // triple sum leaves third differences that are quadratic-B-spline filtered white noise
        // with lag-1 correlation 13/33 (δ = 0.28 ≥ 0.25), which the method reads as α = −5
        // (a property of the method; the confidence module clamps α to −4).
        let rr = cumsum(&rw_rate);
        assert_eq!(lag1_acf(&rr, 1, 3).unwrap().alpha, -4);
        assert_eq!(lag1_acf(&rr, 8, 3).unwrap().alpha, -5);
    }

    /// Direct (copying) evaluation: decimate, detrend by least squares (normal equations on a
    /// centred grid), difference d times, lag-1 ACF with the mean removed.
    fn direct_r1(x: &[f64], m: usize, d: usize) -> f64 {
        let z: Vec<f64> = x.iter().step_by(m).copied().collect();
        let n = z.len();
        let t: Vec<f64> = (0..n).map(|k| k as f64 - (n as f64 - 1.0) / 2.0).collect();
        // Solve the 3×3 normal equations for [1, t, t²].
        let mut a = [[0.0; 3]; 3];
        let mut b = [0.0; 3];
        for k in 0..n {
            let phi = [1.0, t[k], t[k] * t[k]];
            for i in 0..3 {
                b[i] += phi[i] * z[k];
                for j in 0..3 {
                    a[i][j] += phi[i] * phi[j];
                }
            }
        }
        // Gaussian elimination.
        for i in 0..3 {
            for r in i + 1..3 {
                let f = a[r][i] / a[i][i];
                for c in i..3 {
                    a[r][c] -= f * a[i][c];
                }
                b[r] -= f * b[i];
            }
        }
        let mut coef = [0.0; 3];
        for i in (0..3).rev() {
            let mut v = b[i];
            for c in i + 1..3 {
                v -= a[i][c] * coef[c];
            }
            coef[i] = v / a[i][i];
        }
        let mut w: Vec<f64> = (0..n)
            .map(|k| z[k] - coef[0] - coef[1] * t[k] - coef[2] * t[k] * t[k])
            .collect();
        for _ in 0..d {
            w = w.windows(2).map(|p| p[1] - p[0]).collect();
        }
        let mu = w.iter().sum::<f64>() / w.len() as f64;
        let num: f64 = w.windows(2).map(|p| (p[0] - mu) * (p[1] - mu)).sum();
        let den: f64 = w.iter().map(|v| (v - mu) * (v - mu)).sum();
        num / den
    }

    #[test]
    fn streaming_equals_direct() {
        let x = cumsum(&cumsum(&noise(3_001, 21)));
        for m in [1usize, 3, 16, 90] {
            let len = x.len().div_ceil(m);
            let trend = Trend::fit(&x, m, len);
            let r1 = lag1_all_differences(&x, m, len, &trend, 3);
            for d in 0..=3 {
                let reference = direct_r1(&x, m, d);
                // 1e-9 absolute on a correlation: the two detrending routes (orthogonal
                // projection vs normal equations, condition ~n⁴) differ by rounding only.
                assert!(
                    (r1[d] - reference).abs() < 1e-9,
                    "m={m} d={d}: {} vs {reference}",
                    r1[d]
                );
            }
        }
    }

    #[test]
    fn trend_does_not_matter() {
        let w = cumsum(&noise(5_000, 3));
        let with_drift: Vec<f64> = w
            .iter()
            .enumerate()
            .map(|(k, v)| v + 1e3 + 0.5 * k as f64 + 1e-3 * (k * k) as f64)
            .collect();
        for m in [1usize, 8, 64] {
            let a = lag1_acf(&w, m, 2).unwrap();
            let b = lag1_acf(&with_drift, m, 2).unwrap();
            assert_eq!(a.alpha, b.alpha);
            assert!((a.delta - b.delta).abs() < 1e-8);
        }
    }

    #[test]
    fn too_few_points_carry_the_nearest_valid_factor() {
        let x = cumsum(&noise(300, 11)); // 301 phase points
        assert!(lag1_acf(&x, 11, 2).is_none()); // ⌈301/11⌉ = 28 < 30
        let m_c = 300 / 29; // = 10: ⌈301/10⌉ = 31 points
        let expect = lag1_acf(&x, m_c, 2).unwrap().alpha;
        let ids = identify(&x, &[1, 2, 50, 100], 2);
        assert_eq!(ids[2], expect);
        assert_eq!(ids[3], expect);
        assert_eq!(ids[0], lag1_acf(&x, 1, 2).unwrap().alpha);
    }

    #[test]
    fn b1_for_tiny_records() {
        // 25 phase points: B1 ratio. A strong random walk of rate vs white angle noise.
        let w = noise(24, 5);
        let rw = cumsum(&cumsum(&w));
        assert!(lag1_acf(&rw, 1, 2).is_none());
        assert!(b1_ratio(&rw, 1).unwrap() <= -1);
        assert!(b1_ratio(&noise(25, 9), 1).unwrap() >= 1);
        let ids = identify(&noise(25, 9), &[1, 2, 4, 8, 12], 2);
        assert_eq!(ids.len(), 5);
        assert!(ids.iter().all(|a| (-2..=2).contains(a)));
    }
}
