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
//! carry the neighbouring τ's result: that of the largest requested factor below `m` that had
//! 30 points; if no requested factor had them, that of `m_c = ⌊(M − 1)/29⌋`, the largest factor
//! with 30 decimated points (identified once). Only when the whole record has fewer than 30 phase
//! points (no valid τ at all) do we fall back to Stable32's classic method: the **B1 ratio**
//! (Barnes 1969; Howe, Beard, Greenhall & Riley 2000, Table 3) of the standard variance to the
//! Allan variance of the `m`-averages, compared with its expectation `B1(N, μ)` for each noise
//! (decision at geometric means), and the **R(n) ratio** MVAR/AVAR (IEEE 1139) to separate white
//! from flicker angle noise, which B1 cannot distinguish (both μ = −2).

use rayon::prelude::*;

/// Minimum number of decimated points for the lag-1 ACF method (Riley & Greenhall 2004).
pub const MIN_POINTS: usize = 30;

/// Largest factor identified in the joint sweep (smaller strides touch every cache line).
const JOINT_MAX: usize = 8;

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

/// Block length of the streaming passes (fits in L1 with the difference buffers).
const BLOCK: usize = 1024;
const LANES: usize = 4;

/// Lane-split accumulators of the trend projections `Σz, Σz·u, Σz·(u² − c)`.
struct TrendSums {
    s0: [f64; LANES],
    s1: [f64; LANES],
    s2: [f64; LANES],
    half: f64,
    c: f64,
}

impl TrendSums {
    fn new(len: usize) -> TrendSums {
        let n = len as f64;
        TrendSums {
            s0: [0.0; LANES],
            s1: [0.0; LANES],
            s2: [0.0; LANES],
            half: (n - 1.0) / 2.0,
            c: (n * n - 1.0) / 12.0,
        }
    }

    /// Adds the decimated samples `z_k = x[k·m − base]`, `k in range` (`x` is the window of
    /// the angle series that starts at sample `base`; 0 for the whole series).
    fn add(&mut self, x: &[f64], base: usize, m: usize, range: std::ops::Range<usize>) {
        let (half, c) = (self.half, self.c);
        let (s0, s1, s2) = (&mut self.s0, &mut self.s1, &mut self.s2);
        let mut add = |k: usize, l: usize, z: f64| {
            let u = k as f64 - half;
            s0[l] += z;
            s1[l] += z * u;
            s2[l] += z * (u * u - c);
        };
        let start = range.start;
        if m == 1 {
            let chunks = x[range.start - base..range.end - base].chunks_exact(LANES);
            let rest = chunks.remainder();
            for (i, chunk) in chunks.enumerate() {
                for (l, &z) in chunk.iter().enumerate() {
                    add(start + i * LANES + l, l, z);
                }
            }
            // Lane i % LANES like the strided branch, so that the decimated series z = x[k·m]
            // identified at factor 1 gives bit for bit the result at factor m.
            for (i, &z) in rest.iter().enumerate() {
                add(range.end - rest.len() + i, i, z);
            }
        } else {
            for (i, &z) in x[start * m - base..]
                .iter()
                .step_by(m)
                .take(range.len())
                .enumerate()
            {
                add(start + i, i % LANES, z);
            }
        }
    }

    fn finish(&self, len: usize) -> Trend {
        let n = len as f64;
        let c = self.c;
        let (s0, s1, s2): (f64, f64, f64) = (
            self.s0.iter().sum(),
            self.s1.iter().sum(),
            self.s2.iter().sum(),
        );
        // Σu² = n(n²−1)/12, Σ(u² − c)² = Σu⁴ − n c², Σu⁴ = n(n²−1)(3n²−7)/240.
        let norm1 = n * (n * n - 1.0) / 12.0;
        let norm2 = n * (n * n - 1.0) * (3.0 * n * n - 7.0) / 240.0 - n * c * c;
        Trend {
            b0: s0 / n,
            b1: if norm1 > 0.0 { s1 / norm1 } else { 0.0 },
            b2: if norm2 > 0.0 { s2 / norm2 } else { 0.0 },
            half: self.half,
            c,
        }
    }
}

impl Trend {
    fn fit(x: &[f64], m: usize, len: usize) -> Trend {
        let mut sums = TrendSums::new(len);
        sums.add(x, 0, m, 0..len);
        sums.finish(len)
    }

    /// Appends the detrended decimated samples `r_k = x[k·m − base] − trend(k)`, `k in range`.
    fn residuals_into(
        &self,
        x: &[f64],
        base: usize,
        m: usize,
        range: std::ops::Range<usize>,
        out: &mut Vec<f64>,
    ) {
        let (b0, b1, b2) = (self.b0 - self.b2 * self.c, self.b1, self.b2);
        let half = self.half;
        let start = range.start;
        let value = move |k: usize, z: f64| {
            let u = k as f64 - half;
            z - (b0 + u * (b1 + b2 * u))
        };
        if m == 1 {
            out.extend(
                x[range.start - base..range.end - base]
                    .iter()
                    .enumerate()
                    .map(|(i, &z)| value(start + i, z)),
            );
        } else {
            let count = range.len();
            out.extend(
                x[start * m - base..]
                    .iter()
                    .step_by(m)
                    .take(count)
                    .enumerate()
                    .map(|(i, &z)| value(start + i, z)),
            );
        }
    }
}

/// Running sums for the lag-1 autocorrelation of one stream, fed block by block.
#[derive(Clone, Copy)]
struct Lag1Sums {
    s: f64,
    s2: f64,
    s11: f64,
    first: f64,
    last: f64,
    count: usize,
}

impl Lag1Sums {
    const EMPTY: Lag1Sums = Lag1Sums {
        s: 0.0,
        s2: 0.0,
        s11: 0.0,
        first: 0.0,
        last: 0.0,
        count: 0,
    };

    /// Adds the next consecutive values of the stream.
    fn extend(&mut self, block: &[f64]) {
        let Some((&head, _)) = block.split_first() else {
            return;
        };
        if self.count == 0 {
            self.first = head;
        } else {
            self.s11 += self.last * head;
        }
        let mut s = [0.0_f64; LANES];
        let mut s2 = [0.0_f64; LANES];
        let mut s11 = [0.0_f64; LANES];
        let pairs = block.len() - 1;
        let (lead, follow) = (&block[..pairs], &block[1..]);
        let lead_chunks = lead.chunks_exact(LANES);
        let follow_chunks = follow.chunks_exact(LANES);
        let (lead_rest, follow_rest) = (lead_chunks.remainder(), follow_chunks.remainder());
        for (a, b) in lead_chunks.zip(follow_chunks) {
            for l in 0..LANES {
                let w = a[l];
                s[l] += w;
                s2[l] += w * w;
                s11[l] += w * b[l];
            }
        }
        for (&w, &v) in lead_rest.iter().zip(follow_rest) {
            s[0] += w;
            s2[0] += w * w;
            s11[0] += w * v;
        }
        let tail = block[pairs];
        self.s += s.iter().sum::<f64>() + tail;
        self.s2 += s2.iter().sum::<f64>() + tail * tail;
        self.s11 += s11.iter().sum::<f64>();
        self.last = tail;
        self.count += block.len();
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
            self.s11 - mu * ((self.s - self.last) + (self.s - self.first)) + (n - 1.0) * mu * mu;
        if b > 0.0 { a / b } else { 0.0 }
    }
}

/// Streaming state of the lag-1 autocorrelations of the detrended decimated series and of its
/// first `dmax` differences (all orders in the same pass: the pass is memory-bound, the extra
/// arithmetic for differences that may not be needed is free). Fed block by block through two
/// small buffers.
struct AcfState {
    levels: usize,
    sums: [Lag1Sums; 4],
    /// carry[j] = last value of level j from the previous block.
    carry: [Option<f64>; 3],
    current: Vec<f64>,
    next: Vec<f64>,
}

impl AcfState {
    fn new(dmax: u32) -> AcfState {
        AcfState {
            levels: (dmax as usize).min(3) + 1,
            sums: [Lag1Sums::EMPTY; 4],
            carry: [None; 3],
            current: Vec::with_capacity(BLOCK + 1),
            next: Vec::with_capacity(BLOCK + 1),
        }
    }

    /// Feeds the decimated indices `range` (consecutive with the previous call) of the window
    /// `x` that starts at sample `base`.
    fn feed(
        &mut self,
        x: &[f64],
        base: usize,
        m: usize,
        trend: &Trend,
        range: std::ops::Range<usize>,
    ) {
        let mut start = range.start;
        while start < range.end {
            let end = (start + BLOCK).min(range.end);
            self.current.clear();
            trend.residuals_into(x, base, m, start..end, &mut self.current);
            self.sums[0].extend(&self.current);
            for j in 1..self.levels {
                self.next.clear();
                if let (Some(c), Some(&h)) = (self.carry[j - 1], self.current.first()) {
                    self.next.push(h - c);
                }
                let current = &self.current;
                self.next.extend(current.windows(2).map(|w| w[1] - w[0]));
                self.carry[j - 1] = self.current.last().copied().or(self.carry[j - 1]);
                self.sums[j].extend(&self.next);
                std::mem::swap(&mut self.current, &mut self.next);
            }
            start = end;
        }
    }

    fn values(&self) -> [f64; 4] {
        let mut out = [0.0; 4];
        for j in 0..self.levels {
            out[j] = self.sums[j].value();
        }
        out
    }
}

/// Lag-1 autocorrelations of the `0..=dmax`-th differences at one factor (two passes).
fn lag1_all_differences(x: &[f64], m: usize, len: usize, trend: &Trend, dmax: u32) -> [f64; 4] {
    let mut state = AcfState::new(dmax);
    state.feed(x, 0, m, trend, 0..len);
    state.values()
}

/// The ACF decision rule (steps 3–4 of the module docs) from the lag-1 autocorrelations.
fn decide(r1s: &[f64; 4], dmax: u32) -> Identification {
    let mut d = 0u32;
    loop {
        let r1 = r1s[d as usize];
        let delta = r1 / (1.0 + r1);
        if delta < 0.25 || d >= dmax.min(3) {
            let alpha = 2 - (2.0 * delta).round_ties_even() as i32 - 2 * d as i32;
            return Identification { alpha, d, delta };
        }
        d += 1;
    }
}

/// Sample block of the joint sweep over several small factors (fits in L2 with the states).
const SWEEP: usize = 16 * 1024;

/// The joint sweep of `lag1_acf_joint` as a state machine fed with consecutive windows of
/// the angle series (two passes: trends, then autocorrelations), so that a series streamed from
/// disk is identified exactly like one in memory. Windows must be the sample blocks
/// `[s, min(s + SWEEP, n))`, `s = 0, SWEEP, 2·SWEEP, …`, in order, in each pass.
#[derive(Debug)]
pub struct JointSweep {
    ms: Vec<usize>,
    lens: Vec<usize>,
    valid: Vec<bool>,
    dmax: u32,
    trend_sums: Vec<TrendSums>,
    trends: Vec<Trend>,
    states: Vec<AcfState>,
}

impl std::fmt::Debug for TrendSums {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("TrendSums")
    }
}

impl std::fmt::Debug for Trend {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("Trend")
    }
}

impl std::fmt::Debug for AcfState {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("AcfState")
    }
}

impl JointSweep {
    /// Sample block of the sweep (fits in L2 with the states).
    pub const SWEEP: usize = SWEEP;

    /// A sweep over `n` angle samples identifying the factors `ms`.
    pub fn new(n: usize, ms: &[usize], dmax: u32) -> Self {
        let lens: Vec<usize> = ms
            .iter()
            .map(|&m| if m == 0 { 0 } else { n.div_ceil(m) })
            .collect();
        JointSweep {
            ms: ms.to_vec(),
            valid: lens.iter().map(|&l| l >= MIN_POINTS).collect(),
            trend_sums: lens.iter().map(|&l| TrendSums::new(l)).collect(),
            lens,
            dmax,
            trends: Vec::new(),
            states: ms.iter().map(|_| AcfState::new(dmax)).collect(),
        }
    }

    /// Decimated index range of factor `m` inside the sample block `[s, e)`.
    fn krange(m: usize, len: usize, s: usize, e: usize) -> std::ops::Range<usize> {
        s.div_ceil(m)..e.div_ceil(m).min(len)
    }

    /// First pass: the block `window = x[s..s + window.len()]`.
    pub fn trend_block(&mut self, window: &[f64], s: usize) {
        let e = s + window.len();
        for (i, &m) in self.ms.iter().enumerate() {
            if self.valid[i] {
                self.trend_sums[i].add(window, s, m, Self::krange(m, self.lens[i], s, e));
            }
        }
    }

    /// Second pass: the block `window = x[s..s + window.len()]` (the trends are fitted on the
    /// first call).
    pub fn acf_block(&mut self, window: &[f64], s: usize) {
        if self.trends.is_empty() {
            self.trends = self
                .trend_sums
                .iter()
                .zip(&self.lens)
                .map(|(t, &l)| t.finish(l))
                .collect();
        }
        let e = s + window.len();
        for (i, &m) in self.ms.iter().enumerate() {
            if self.valid[i] {
                self.states[i].feed(
                    window,
                    s,
                    m,
                    &self.trends[i],
                    Self::krange(m, self.lens[i], s, e),
                );
            }
        }
    }

    /// The identifications (`None` for factors with fewer than 30 decimated points).
    pub fn finish(&self) -> Vec<Option<Identification>> {
        self.states
            .iter()
            .zip(&self.valid)
            .map(|(st, &ok)| ok.then(|| decide(&st.values(), self.dmax)))
            .collect()
    }
}

/// Lag-1 ACF identification at several (small) factors in one joint sweep: every block of `x`
/// is read once from memory and used by all factors while it sits in cache, so the small
/// factors (which all touch every cache line) cost two passes over memory together instead of
/// two passes each. Factors with fewer than 30 decimated points give `None`.
fn lag1_acf_joint(x: &[f64], ms: &[usize], dmax: u32) -> Vec<Option<Identification>> {
    let n = x.len();
    let mut sweep = JointSweep::new(n, ms, dmax);
    for s in (0..n).step_by(SWEEP) {
        sweep.trend_block(&x[s..(s + SWEEP).min(n)], s);
    }
    for s in (0..n).step_by(SWEEP) {
        sweep.acf_block(&x[s..(s + SWEEP).min(n)], s);
    }
    sweep.finish()
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
    Some(decide(&lag1_all_differences(x, m, len, &trend, dmax), dmax))
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
    identify_with(
        x.len(),
        ms,
        // Factors up to JOINT_MAX read every cache line of x: identify them in one joint
        // sweep, the larger ones (cheap, strided) in parallel beside it.
        |small, large| {
            rayon::join(
                || lag1_acf_joint(x, small, dmax),
                || {
                    large
                        .par_iter()
                        .with_max_len(1)
                        .map(|&m| lag1_acf(x, m, dmax))
                        .collect::<Vec<_>>()
                },
            )
        },
        |m| lag1_acf(x, m, dmax),
        |m| b1_ratio(x, m),
    )
}

/// Factors identified in the joint sweep (`≤ JOINT_MAX`) and one by one, as [`identify_with`]
/// splits them.
pub fn split_factors(ms: &[usize]) -> (Vec<usize>, Vec<usize>) {
    (
        ms.iter().copied().filter(|&m| m <= JOINT_MAX).collect(),
        ms.iter().copied().filter(|&m| m > JOINT_MAX).collect(),
    )
}

/// The fallback factor `m_c = ⌊(M − 1)/29⌋` of a record of `n_phase` samples (module docs).
pub fn fallback_factor(n_phase: usize) -> usize {
    n_phase.saturating_sub(1) / (MIN_POINTS - 1)
}

/// [`identify`] with the data access supplied by the caller (used to identify a series that
/// is streamed from disk exactly like one in memory): `sweep(small, large)` returns the
/// joint-sweep identifications of the small factors and [`lag1_acf`] of the large ones (see
/// [`split_factors`]); `single(m_c)` is [`lag1_acf`] at the fallback factor, `b1(m)` is
/// [`b1_ratio`] (only called for records under 30 samples).
pub fn identify_with(
    n_phase: usize,
    ms: &[usize],
    sweep: impl FnOnce(&[usize], &[usize]) -> (Vec<Option<Identification>>, Vec<Option<Identification>>),
    single: impl FnOnce(usize) -> Option<Identification>,
    mut b1: impl FnMut(usize) -> Option<i32>,
) -> Vec<i32> {
    let small: Vec<usize> = (0..ms.len()).filter(|&i| ms[i] <= JOINT_MAX).collect();
    let large: Vec<usize> = (0..ms.len()).filter(|&i| ms[i] > JOINT_MAX).collect();
    let (small_ms, large_ms) = split_factors(ms);
    let (small_ids, large_ids) = sweep(&small_ms, &large_ms);
    let mut results: Vec<Option<i32>> = vec![None; ms.len()];
    for (&i, id) in small
        .iter()
        .zip(small_ids)
        .chain(large.iter().zip(large_ids))
    {
        results[i] = id.map(|id| id.alpha);
    }
    if results.iter().all(Option::is_some) {
        return results.into_iter().map(|a| a.unwrap_or(0)).collect();
    }
    // Neighbour rule: a factor without 30 decimated points takes the result of the largest
    // requested factor below it that had them; failing that, of m_c (the largest factor with
    // 30 points, identified once).
    let m_c = fallback_factor(n_phase);
    let mut single = Some(single);
    let mut order: Vec<usize> = (0..ms.len()).collect();
    order.sort_by_key(|&i| ms[i]);
    let mut neighbour: Option<i32> = None;
    let mut fallback: Option<Option<i32>> = None;
    let mut last_b1: Option<i32> = None;
    let mut out = vec![0; ms.len()];
    for i in order {
        out[i] = if let Some(a) = results[i] {
            neighbour = Some(a);
            a
        } else if let Some(a) = neighbour {
            a
        } else if let Some(a) = *fallback.get_or_insert_with(|| {
            (m_c >= 1)
                .then(|| single.take().and_then(|f| f(m_c)))
                .flatten()
                .map(|id| id.alpha)
        }) {
            a
        } else {
            // Fewer than 30 phase points in the whole record: B1 ratio (and R(n)), carrying
            // the previous τ's result where B1 cannot be formed; white rate noise (α = 0) if
            // nothing can be identified at all (two or three samples).
            let b = b1(ms[i]).or(last_b1);
            last_b1 = b;
            b.unwrap_or(0)
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
    fn joint_sweep_equals_single_factor() {
        // 50 001 samples cross several SWEEP (16 384) and BLOCK (1 024) boundaries.
        let x = cumsum(&noise(50_000, 17));
        let ms = [1usize, 2, 3, 5, 7, 8, 2000];
        let joint = lag1_acf_joint(&x, &ms, 3);
        for (&m, j) in ms.iter().zip(&joint) {
            let single = lag1_acf(&x, m, 3);
            match (j, single) {
                (Some(a), Some(b)) => {
                    assert_eq!((a.alpha, a.d), (b.alpha, b.d), "m={m}");
                    // Only the lane split of the sums differs: rounding.
                    assert!((a.delta - b.delta).abs() < 1e-12, "m={m}");
                }
                (None, None) => {}
                _ => panic!("m={m}: {j:?} vs {single:?}"),
            }
        }
        assert!(joint[6].is_none()); // ⌈50001/2000⌉ = 26 < 30
    }

    #[test]
    fn decimated_series_equals_strided_factor_bit_for_bit() {
        // The streaming path identifies large factors on z_k = x[k·m] at factor 1.
        let x = cumsum(&noise(20_003, 29));
        for m in [9usize, 16, 17, 100, 689] {
            let z: Vec<f64> = x.iter().step_by(m).copied().collect();
            assert_eq!(lag1_acf(&x, m, 3), lag1_acf(&z, 1, 3), "m={m}");
        }
    }

    #[test]
    fn joint_sweep_fed_by_windows_equals_in_memory() {
        let x = cumsum(&noise(40_001, 31));
        let ms = [1usize, 2, 4, 8];
        let mut sweep = JointSweep::new(x.len(), &ms, 2);
        for s in (0..x.len()).step_by(JointSweep::SWEEP) {
            let w: Vec<f64> = x[s..(s + JointSweep::SWEEP).min(x.len())].to_vec();
            sweep.trend_block(&w, s);
        }
        for s in (0..x.len()).step_by(JointSweep::SWEEP) {
            let w: Vec<f64> = x[s..(s + JointSweep::SWEEP).min(x.len())].to_vec();
            sweep.acf_block(&w, s);
        }
        assert_eq!(sweep.finish(), lag1_acf_joint(&x, &ms, 2));
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
    fn too_few_points_carry_the_neighbouring_factor() {
        let x = cumsum(&noise(300, 11)); // 301 phase points
        assert!(lag1_acf(&x, 11, 2).is_none()); // ⌈301/11⌉ = 28 < 30
        // Requested factors 1, 4 valid; 50, 100 take the result at 4.
        let ids = identify(&x, &[100, 1, 4, 50], 2);
        let at4 = lag1_acf(&x, 4, 2).unwrap().alpha;
        assert_eq!(ids, vec![at4, lag1_acf(&x, 1, 2).unwrap().alpha, at4, at4]);
        // No requested factor valid: m_c = ⌊300/29⌋ = 10 (⌈301/10⌉ = 31 points).
        let expect = lag1_acf(&x, 10, 2).unwrap().alpha;
        assert_eq!(identify(&x, &[50, 100], 2), vec![expect, expect]);
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
