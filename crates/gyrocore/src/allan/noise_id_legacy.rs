//! Frozen copy of [`super::noise_id`] as it was before its speed-up (issue 35, commit
//! 9b2f450): the reference of the randomized old-versus-new equality tests of the noise
//! identification (same α at every factor, same lag-1 autocorrelations bit for bit). Compiled
//! for the tests only; do not change it (only the visibility of what the tests compare was
//! widened).
#![allow(dead_code, unreachable_pub, clippy::pedantic)]

use rayon::prelude::*;

/// Minimum number of decimated points for the lag-1 ACF method (Riley & Greenhall 2004).
pub const MIN_POINTS: usize = 30;

/// Differences always taken before the ACF decision: the method runs on the first differences
/// of the decimated angle, i.e. on the `m`-averaged rate, as Riley & Greenhall do for
/// frequency data (see the module docs).
const DMIN: u32 = 1;

/// Below this many decimated points the lag-1 ACF result is checked against R(n) (module docs,
/// "Consistency with the local slope").
pub const CHECK_POINTS: usize = 100;

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
#[derive(Clone)]
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
        let mut add_at = |u: f64, l: usize, z: f64| {
            s0[l] += z;
            s1[l] += z * u;
            s2[l] += z * (u * u - c);
        };
        let start = range.start;
        if m == 1 {
            let chunks = x[range.start - base..range.end - base].chunks_exact(LANES);
            let rest = chunks.remainder();
            // u = k − half stepped by whole numbers instead of converted from k: every value is
            // a multiple of ½ below 2⁵², so both are exact and equal bit for bit (and the loop
            // vectorises without an integer conversion per sample).
            let mut u0 = start as f64 - half;
            for chunk in chunks {
                for (l, &z) in chunk.iter().enumerate() {
                    add_at(u0 + l as f64, l, z);
                }
                u0 += LANES as f64;
            }
            // Lane i % LANES like the strided branch, so that the decimated series z = x[k·m]
            // identified at factor 1 gives bit for bit the result at factor m.
            for (i, &z) in rest.iter().enumerate() {
                add_at((range.end - rest.len() + i) as f64 - half, i, z);
            }
        } else {
            for (i, &z) in x[start * m - base..]
                .iter()
                .step_by(m)
                .take(range.len())
                .enumerate()
            {
                add_at((start + i) as f64 - half, i % LANES, z);
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
            // u stepped as in TrendSums::add (exact, equal to the converted k − half).
            let chunks = x[range.start - base..range.end - base].chunks_exact(LANES);
            let rest = chunks.remainder();
            let mut u0 = start as f64 - half;
            for chunk in chunks {
                let mut r = [0.0; LANES];
                for (l, (r, &z)) in r.iter_mut().zip(chunk).enumerate() {
                    let u = u0 + l as f64;
                    *r = z - (b0 + u * (b1 + b2 * u));
                }
                out.extend_from_slice(&r);
                u0 += LANES as f64;
            }
            let tail = range.end - rest.len();
            out.extend(rest.iter().enumerate().map(|(i, &z)| value(tail + i, z)));
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

/// Streaming state of the lag-1 autocorrelations of the detrended decimated series' differences
/// of orders `lowest..=dmax` (the lower orders are formed, as the higher ones need them, but
/// their sums are not accumulated). Fed block by block through two small buffers. The sums of
/// an order do not depend on which other orders are accumulated: a state of orders `1..=1`
/// and one of orders `2..=dmax` fed the same blocks give, bit for bit, the values of one
/// state of orders `1..=dmax` (see [`refined`]).
#[derive(Clone)]
struct AcfState {
    levels: usize,
    lowest: usize,
    sums: [Lag1Sums; 4],
    /// carry[j] = last value of level j from the previous block.
    carry: [Option<f64>; 3],
    current: Vec<f64>,
    next: Vec<f64>,
}

impl AcfState {
    /// Every order the decision may read (`DMIN..=dmax`), in one pass (the streamed path:
    /// one pass over the file).
    fn new(dmax: u32) -> AcfState {
        AcfState::orders(DMIN as usize, dmax)
    }

    /// Orders `lowest..=min(dmax, 3)`.
    fn orders(lowest: usize, dmax: u32) -> AcfState {
        AcfState {
            levels: (dmax as usize).min(3) + 1,
            lowest,
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
            // Orders below DMIN never enter the decision (`decide` starts at d = DMIN): their
            // sums are not accumulated (a third of the pass for the Allan variances).
            if self.lowest == 0 {
                self.sums[0].extend(&self.current);
            }
            for j in 1..self.levels {
                self.next.clear();
                if let (Some(c), Some(&h)) = (self.carry[j - 1], self.current.first()) {
                    self.next.push(h - c);
                }
                let current = &self.current;
                self.next.extend(current.windows(2).map(|w| w[1] - w[0]));
                self.carry[j - 1] = self.current.last().copied().or(self.carry[j - 1]);
                if j >= self.lowest {
                    self.sums[j].extend(&self.next);
                }
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

/// Lag-1 autocorrelations of the `DMIN..=dmax`-th differences at one factor, in one pass (the
/// reference of the tests: [`lag1_acf`] forms the higher orders only when it reads them).
#[cfg(test)]
fn lag1_all_differences(x: &[f64], m: usize, len: usize, trend: &Trend, dmax: u32) -> [f64; 4] {
    let mut state = AcfState::new(dmax);
    state.feed(x, 0, m, trend, 0..len);
    state.values()
}

/// Whether the decision needs the orders above `DMIN` (δ at `DMIN` is ≥ 0.25 and `dmax`
/// allows more differences).
fn needs_more(r1s: &[f64; 4], dmax: u32) -> bool {
    let r1 = r1s[DMIN as usize];
    DMIN < dmax.min(3) && r1 / (1.0 + r1) >= 0.25
}

/// The decision of [`lag1_all_differences`] with the orders above `DMIN` accumulated only when
/// the decision reads them: white rate noise (most τ of an inertial log) stops at the first
/// difference, so the second and third are not formed at all. `more(state)` feeds a state of
/// the higher orders (a second pass over the same blocks); the lag-1 sums are those of one
/// pass over every order, bit for bit (each order's sums see the same values in the same
/// blocks).
fn refined(first: &AcfState, dmax: u32, more: impl FnOnce(&mut AcfState)) -> Identification {
    let mut r1s = first.values();
    if needs_more(&r1s, dmax) {
        let mut state = AcfState::orders(DMIN as usize + 1, dmax);
        more(&mut state);
        let higher = state.values();
        r1s[DMIN as usize + 1..].copy_from_slice(&higher[DMIN as usize + 1..]);
    }
    decide(&r1s, dmax)
}

/// The ACF decision rule (steps 3–4 of the module docs) from the lag-1 autocorrelations.
fn decide(r1s: &[f64; 4], dmax: u32) -> Identification {
    let mut d = DMIN;
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
pub fn lag1_acf_joint(x: &[f64], ms: &[usize], dmax: u32) -> Vec<Option<Identification>> {
    let n = x.len();
    // The first difference of every factor in one sweep; the higher orders (see [`refined`])
    // in a second sweep over the factors whose decision reads them.
    let mut sweep = JointSweep::new(n, ms, dmax);
    for state in &mut sweep.states {
        *state = AcfState::orders(DMIN as usize, u32::min(dmax, DMIN));
    }
    for s in (0..n).step_by(SWEEP) {
        sweep.trend_block(&x[s..(s + SWEEP).min(n)], s);
    }
    for s in (0..n).step_by(SWEEP) {
        sweep.acf_block(&x[s..(s + SWEEP).min(n)], s);
    }
    let mut second = JointSweep {
        ms: sweep.ms.clone(),
        lens: sweep.lens.clone(),
        valid: sweep.valid.clone(),
        dmax,
        trend_sums: Vec::new(),
        trends: sweep.trends.clone(),
        states: ms
            .iter()
            .map(|_| AcfState::orders(DMIN as usize + 1, dmax))
            .collect(),
    };
    for (i, state) in sweep.states.iter().enumerate() {
        second.valid[i] = sweep.valid[i] && needs_more(&state.values(), dmax);
    }
    if second.valid.iter().any(|&v| v) {
        for s in (0..n).step_by(SWEEP) {
            second.acf_block(&x[s..(s + SWEEP).min(n)], s);
        }
    }
    sweep
        .states
        .iter()
        .zip(&second.states)
        .zip(&sweep.valid)
        .map(|((first, more), &ok)| ok.then(|| refined(first, dmax, |state| *state = more.clone())))
        .collect()
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
    let mut first = AcfState::orders(DMIN as usize, u32::min(dmax, DMIN));
    first.feed(x, 0, m, &trend, 0..len);
    Some(refined(&first, dmax, |state| {
        state.feed(x, 0, m, &trend, 0..len);
    }))
}

/// Expected B1 ratio for `n` averages and τ-exponent μ (Howe et al. 2000, Table 3; SP1065
/// §5.6.2 "B1 bias ratio").
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
/// (IEEE 1139; flicker with f_h = 1/(2τ0), as AllanTools `rn_theory`). The frequency noises
/// have R(n) ≥ [`RN_FREQUENCY`].
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

/// R(n) of white rate noise for large m (MVAR/AVAR → 1/2); flicker and random-walk rate noise
/// have larger ratios (≈ 0.67 and 0.82), so 1/2 is the frequency-noise side of the PM/FM
/// boundary.
const RN_FREQUENCY: f64 = 0.5;

/// R(n) below this is angle (phase) noise: the geometric mean of flicker angle noise's R(n)
/// and [`RN_FREQUENCY`].
fn rn_boundary(m: usize) -> f64 {
    (rn_theory(m as f64, 1) * RN_FREQUENCY).sqrt()
}

/// The outer sums of R(n) run over `j = 0, q, 2q, …` with `q = ⌈m / RN_GRID⌉` (see
/// [`FewPoints`]): every term keeps its expectation, and a streamed record needs only
/// `O(RN_GRID · N/m)` gathered samples per factor.
const RN_GRID: usize = 8;

/// Samples `x[base + k·stride]` (or prefix sums `P[...]`), `k < count`, gathered in order.
#[derive(Debug, Clone)]
struct Grid {
    base: usize,
    stride: usize,
    count: usize,
    values: Vec<f64>,
}

impl Grid {
    fn new(base: usize, stride: usize, count: usize) -> Grid {
        Grid {
            base,
            stride,
            count,
            values: Vec::with_capacity(count),
        }
    }

    /// Gathers the grid positions inside `[s, s + len)` from `value(i)` (absolute index `i`).
    fn gather(&mut self, s: usize, len: usize, value: impl Fn(usize) -> f64) {
        let e = s + len;
        while self.values.len() < self.count {
            let pos = self.base + self.values.len() * self.stride;
            if pos < s {
                // Not reached when windows are fed in order from 0.
                return;
            }
            if pos >= e {
                return;
            }
            self.values.push(value(pos));
        }
    }
}

/// Gathered samples of one factor with fewer than [`MIN_POINTS`] decimated points.
#[derive(Debug, Clone)]
pub struct FewFactor {
    pub m: usize,
    /// `x[k·m]`, `k·m ≤ N − 1` (the B1 averages).
    decimated: Grid,
    /// `x[c·m + k·q]`, c = 0, 1, 2 (the R(n) Allan terms, `k·q ≤ N − 2m − 1`).
    angle: [Grid; 3],
    /// `P[c·m + k·q]`, c = 0..3, `P[i] = Σ_{i' < i} x_{i'}` (the R(n) modified terms,
    /// `k·q ≤ N − 3m`).
    prefix: [Grid; 4],
}

/// B1 ratio / R(n) identification of the factors that have fewer than [`MIN_POINTS`] decimated
/// angle points (NIST SP1065 §5.6, "Power-law noise identification": B1 bias ratio and R(n);
/// what Stable32 uses where the lag-1 ACF has too few points).
///
/// Fed with consecutive windows of the angle series (all of it in memory, or streamed from
/// disk: the result is the same bit for bit, the running prefix sum is sequential), it gathers
/// for each factor `m` the decimated samples `x_{k·m}` and, on the grid `j = 0, q, 2q, …`
/// (`q = ⌈m/8⌉`), the samples and prefix sums that the Allan and modified Allan terms at `j` need.
/// Then, with `y_k = (x_{(k+1)m} − x_{k·m})/m` the `n = ⌊(N − 1)/m⌋` rate averages:
///
/// ```text
/// R(n) = MVAR/AVAR = [Σ_j (P_{j+3m} − 3P_{j+2m} + 3P_{j+m} − P_j)² / (m² J_M)] / [Σ_j (x_{j+2m} − 2x_{j+m} + x_j)² / J_A]
/// B1   = s²(y) / AVAR(y) = [Σ (y_k − ȳ)²/(n − 1)] / [Σ (y_{k+1} − y_k)² / (2(n − 1))]
/// ```
///
/// 1. **Phase or frequency noise (R(n)).** Angle (phase) noise has R(n) ≈ 1/m (white) or
///    R_f(m) = 3 ln(256/27)/(8π²) / [(1.038 + 3 ln(π m))/(4π²)] (flicker, IEEE 1139), rate
///    (frequency) noise R(n) ≥ 1/2. Angle noise if `R(n) < √(R_f · ½)`; then flicker (α = 1) if
///    `R(n) > √(R_f/m)`, white (α = 2) otherwise. R(n) needs `N ≥ 3m` and is uninformative for
///    m < 4 (R_f ≥ ½ there; MVAR = AVAR at m = 1): there angle noise is also declared when B1 is
///    below its PM boundary `√(B1(n, −1)·B1(n, −2))`.
/// 2. **Which rate noise (B1).** Compare B1 with its expectation `B1(n, μ)` (Barnes 1969; Howe,
///    Beard, Greenhall & Riley 2000, Table 3; μ the τ-exponent of the Allan variance):
///    α = −2 (μ = 1) if `B1 > √(B1(n,1)·B1(n,0))`, α = −1 (μ = 0) if `B1 > √(B1(n,0)·B1(n,−1))`,
///    α = 0 (μ = −1) otherwise. B1 needs n ≥ 3 averages (with two, B1 ≡ 1 for every noise).
///
/// Both ratios are local slope estimates: B1 compares the variance of the averages at τ with
/// their Allan variance, i.e. how fast σ²(τ) changes with τ (μ = −α − 1), and R(n) compares the
/// modified and the plain Allan variance at τ (their slopes differ only for angle noise, MDEV
/// falling as τ^{−3/2} for white angle noise). The identification is therefore consistent with
/// the local ADEV/MDEV slope by construction where the points are few (checked by a test). The
/// Hadamard range (α < −2) is not identified here: the Allan-type ratios diverge there.
#[derive(Debug, Clone)]
pub struct FewPoints {
    n: usize,
    pub factors: Vec<FewFactor>,
    /// Running prefix sum (Neumaier-compensated) of the samples fed so far.
    sum: f64,
    comp: f64,
    fed: usize,
    window_prefix: Vec<f64>,
}

impl FewPoints {
    /// Gatherer for the factors `ms` (each with fewer than [`CHECK_POINTS`] decimated points)
    /// of an angle series of `n` samples.
    pub fn new(n: usize, ms: &[usize]) -> FewPoints {
        let factors = ms
            .iter()
            .map(|&m| {
                let m = m.max(1);
                let q = m.div_ceil(RN_GRID);
                let count_a = if n > 2 * m {
                    (n - 2 * m - 1) / q + 1
                } else {
                    0
                };
                let count_m = if n >= 3 * m { (n - 3 * m) / q + 1 } else { 0 };
                FewFactor {
                    m,
                    decimated: Grid::new(0, m, if n == 0 { 0 } else { (n - 1) / m + 1 }),
                    angle: [0, 1, 2].map(|c| Grid::new(c * m, q, count_a)),
                    prefix: [0, 1, 2, 3].map(|c| Grid::new(c * m, q, count_m)),
                }
            })
            .collect();
        FewPoints {
            n,
            factors,
            sum: 0.0,
            comp: 0.0,
            fed: 0,
            window_prefix: Vec::new(),
        }
    }

    /// Feeds the next window `x[s..s + window.len()]` (windows in order, starting at 0).
    pub fn feed(&mut self, window: &[f64], s: usize) {
        debug_assert_eq!(s, self.fed);
        self.window_prefix.clear();
        self.window_prefix.reserve(window.len());
        let (mut sum, mut comp) = (self.sum, self.comp);
        for &v in window {
            self.window_prefix.push(sum + comp);
            // Neumaier's compensated summation; both corrections formed and one selected (the
            // same operations as a branch, without its mispredictions where |sum| ≈ |v|).
            let t = sum + v;
            let big = (sum - t) + v;
            let small = (v - t) + sum;
            comp += if sum.abs() >= v.abs() { big } else { small };
            sum = t;
        }
        (self.sum, self.comp) = (sum, comp);
        self.fed = s + window.len();
        let total = self.sum + self.comp;
        let len = window.len();
        let at_end = self.fed == self.n;
        for f in &mut self.factors {
            f.decimated.gather(s, len, |i| window[i - s]);
            for g in &mut f.angle {
                g.gather(s, len, |i| window[i - s]);
            }
            let prefix = &self.window_prefix;
            for g in &mut f.prefix {
                g.gather(s, len, |i| prefix[i - s]);
                // P[N] (after the last sample) closes the last modified term.
                if at_end
                    && g.values.len() + 1 == g.count
                    && g.base + (g.count - 1) * g.stride == s + len
                {
                    g.values.push(total);
                }
            }
        }
    }

    /// The α at factor `m` given the lag-1 ACF result `acf` there (`None`: fewer than 30
    /// points): the B1/R(n) identification when there is no ACF result or when the ACF result's
    /// family (angle noise α ≥ 1 or rate noise α ≤ 0) contradicts R(n) (module docs); the ACF
    /// result otherwise. `None` when nothing can be formed.
    pub fn resolve(&self, m: usize, acf: Option<i32>) -> Option<i32> {
        match acf {
            None => self.identify(m),
            Some(a) => {
                let Some(f) = self.factors.iter().find(|f| f.m == m) else {
                    return Some(a);
                };
                match f.rn() {
                    Some(rn) if (rn < rn_boundary(m)) != (a >= 1) => self.identify(m).or(Some(a)),
                    _ => Some(a),
                }
            }
        }
    }

    /// The B1/R(n) identification at factor `m` (one of those given to [`FewPoints::new`]),
    /// `None` when it cannot be formed (fewer than three averages, or `N < 3m`, or not all
    /// samples fed).
    pub fn identify(&self, m: usize) -> Option<i32> {
        let f = self.factors.iter().find(|f| f.m == m)?;
        let b1 = f.b1()?;
        let rn = f.rn()?;
        let mf = m as f64;
        let n = (f.decimated.values.len() - 1) as f64;
        let geo = |a: i32, b: i32| (b1_theory(n, a) * b1_theory(n, b)).sqrt();
        let r_flicker = rn_theory(mf, 1);
        let angle_noise = rn < rn_boundary(m) || (m < 4 && b1 < geo(-1, -2));
        Some(if angle_noise {
            if rn > (r_flicker * rn_theory(mf, 2)).sqrt() {
                1
            } else {
                2
            }
        } else if b1 > geo(1, 0) {
            -2
        } else if b1 > geo(0, -1) {
            -1
        } else {
            0
        })
    }
}

impl FewFactor {
    fn complete(g: &Grid) -> bool {
        g.values.len() == g.count
    }

    /// B1 of the rate averages (needs ≥ 3 of them).
    pub fn b1(&self) -> Option<f64> {
        if !Self::complete(&self.decimated) || self.decimated.count < 4 {
            return None;
        }
        let m = self.m as f64;
        let y: Vec<f64> = self
            .decimated
            .values
            .windows(2)
            .map(|w| (w[1] - w[0]) / m)
            .collect();
        let n = y.len() as f64;
        let mean = y.iter().sum::<f64>() / n;
        let var = y.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
        let avar = y.windows(2).map(|w| (w[1] - w[0]).powi(2)).sum::<f64>() / (2.0 * (n - 1.0));
        (avar > 0.0 && var.is_finite()).then(|| var / avar)
    }

    /// R(n) = MVAR/AVAR on the grid (needs `N ≥ 3m`).
    pub fn rn(&self) -> Option<f64> {
        let [a0, a1, a2] = &self.angle;
        let [p0, p1, p2, p3] = &self.prefix;
        if a0.count == 0
            || p0.count == 0
            || !self.angle.iter().chain(&self.prefix).all(Self::complete)
        {
            return None;
        }
        let avar = a0
            .values
            .iter()
            .zip(&a1.values)
            .zip(&a2.values)
            .map(|((&x0, &x1), &x2)| (x2 - 2.0 * x1 + x0).powi(2))
            .sum::<f64>()
            / a0.count as f64;
        let m = self.m as f64;
        let mvar = p0
            .values
            .iter()
            .zip(&p1.values)
            .zip(&p2.values)
            .zip(&p3.values)
            .map(|(((&q0, &q1), &q2), &q3)| (q3 - 3.0 * q2 + 3.0 * q1 - q0).powi(2))
            .sum::<f64>()
            / (p0.count as f64 * m * m);
        (avar > 0.0 && mvar.is_finite()).then(|| mvar / avar)
    }
}

/// Factors of `ms` with fewer than [`CHECK_POINTS`] decimated points in a record of `n_phase`
/// angle samples (identified or checked by [`FewPoints`]), sorted, without repeats.
pub fn few_point_factors(n_phase: usize, ms: &[usize]) -> Vec<usize> {
    let mut few: Vec<usize> = ms
        .iter()
        .copied()
        .filter(|&m| m >= 1 && n_phase.div_ceil(m) < CHECK_POINTS)
        .collect();
    few.sort_unstable();
    few.dedup();
    few
}

/// [`FewPoints`] for the few-point factors of `ms`, fed with the whole in-memory series `x`.
fn few_points_in_memory(x: &[f64], ms: &[usize]) -> FewPoints {
    let mut few = FewPoints::new(x.len(), &few_point_factors(x.len(), ms));
    if !few.factors.is_empty() {
        for s in (0..x.len()).step_by(SWEEP) {
            few.feed(&x[s..(s + SWEEP).min(x.len())], s);
        }
    }
    few
}

/// Identified α at each averaging factor (see the module docs for the fallbacks).
///
/// `dmax` is 2 for the Allan-type variances and 3 for the Hadamard variance. The α values are
/// as identified (the caller clamps them to the estimator's convergent range).
pub fn identify(x: &[f64], ms: &[usize], dmax: u32) -> Vec<i32> {
    let few = few_points_in_memory(x, ms);
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
        |m, acf| few.resolve(m, acf),
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
/// [`split_factors`]); `single(m_c)` is [`lag1_acf`] at the fallback factor; `few(m, acf)` is
/// [`FewPoints::resolve`] for the factors with fewer than [`CHECK_POINTS`] decimated points.
pub fn identify_with(
    n_phase: usize,
    ms: &[usize],
    sweep: impl FnOnce(&[usize], &[usize]) -> (Vec<Option<Identification>>, Vec<Option<Identification>>),
    single: impl FnOnce(usize) -> Option<Identification>,
    mut few: impl FnMut(usize, Option<i32>) -> Option<i32>,
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
    // Fewer than 30 decimated points: B1 ratio and R(n); fewer than 100: the ACF result
    // checked against R(n).
    for (i, r) in results.iter_mut().enumerate() {
        if ms[i] >= 1 && n_phase.div_ceil(ms[i]) < CHECK_POINTS {
            *r = few(ms[i], *r);
        }
    }
    if results.iter().all(Option::is_some) {
        return results.into_iter().map(|a| a.unwrap_or(0)).collect();
    }
    // Neither could be formed (B1 needs 3 averages, R(n) needs N ≥ 3m): the result of the
    // largest requested factor below; failing that, the ACF at m_c (the largest factor with 30
    // points, identified once); white rate noise (α = 0) if nothing can be identified at all.
    let m_c = fallback_factor(n_phase);
    let mut order: Vec<usize> = (0..ms.len()).collect();
    order.sort_by_key(|&i| ms[i]);
    let mut neighbour: Option<i32> = None;
    let mut fallback: Option<Option<i32>> = None;
    let mut single = Some(single);
    let mut out = vec![0; ms.len()];
    for i in order {
        out[i] = if let Some(a) = results[i] {
            neighbour = Some(a);
            a
        } else if let Some(a) = neighbour {
            a
        } else {
            fallback
                .get_or_insert_with(|| {
                    (m_c >= 1)
                        .then(|| single.take().and_then(|f| f(m_c)))
                        .flatten()
                        .map(|id| id.alpha)
                })
                .unwrap_or(0)
        };
    }
    out
}
