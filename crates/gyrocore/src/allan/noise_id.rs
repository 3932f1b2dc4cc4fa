//! Power-law noise identification per averaging factor.
//!
//! Stable32's rule, as NIST SP1065 §5.6 ("Power-law noise identification") describes it: the
//! lag-1 autocorrelation method where the decimated series has at least 30 points, the B1 bias
//! ratio with R(n) where it has fewer.
//!
//! **Lag-1 autocorrelation method** (W. J. Riley and C. A. Greenhall, "Power law noise
//! identification using the lag 1 autocorrelation", 18th EFTF, 2004; SP1065 §5.6; AllanTools
//! `autocorr_noise_id`). On the phase (angle) series `x` at averaging factor `m`:
//!
//! 1. decimate: `z_k = x_{k·m}`, `k = 0..⌈M/m⌉−1` (needs at least 30 points);
//! 2. remove a quadratic trend (least squares) — a rate offset and drift;
//! 3. difference once (`d = 1`): the first differences are `m` times the `m`-averaged rate;
//! 4. `r₁ = Σ_k (w_k − w̄)(w_{k+1} − w̄) / Σ_k (w_k − w̄)²`, `δ = r₁/(1 + r₁)`;
//!    while `δ ≥ 0.25` and `d < d_max`, difference once more (`d += 1`) and repeat;
//! 5. `α = 2 − round(2δ) − 2d` (the phase exponent `p = −2(δ + d)`, `α = p + 2`), rounded half
//!    to even like NumPy.
//!
//! Step 3 (AllanTools' `dmin = 1`) makes the decision on the averaged rate, as Riley & Greenhall
//! do for frequency data, instead of first testing the detrended phase itself (`dmin = 0`). The
//! two agree in expectation (white angle noise: `δ = 0` on the phase, `δ = −1` on its
//! differences, both α = 2), but with a few dozen points a quadratically detrended random walk
//! can look stationary: on the Cs 5071A record (AllanTools' test data) at τ = 10⁴ s (56 points)
//! the phase test reads white phase noise (α = 2, EDF ≈ 5·10⁵) where the rate averages are
//! plainly white frequency noise — what Stable32 reports. With `dmin = 1` every published
//! Stable32 α of AllanTools' tables with ≥ 30 points is reproduced.
//!
//! `d_max = 2` for the Allan-type variances, 3 for the Hadamard variance. Everything is computed
//! in streaming passes over the decimated samples `x_{k·m}` (the trend, then one pass per
//! difference order, the differences rebuilt block by block from the residuals): O(M/m) work
//! per τ, so an octave τ set costs O(M) in total. The factors up to 8 share one sweep over the
//! series (each block gathered per factor into a small buffer); a larger factor is read once,
//! strided, into a copy of its M/m decimated samples. The sums run in four fixed lanes, in
//! vector registers where the CPU has four-lane f64 vectors and in arrays otherwise, with the
//! same operations per lane (no fused multiply-add): the same bits on every CPU.
//!
//! **Too few points.** When `⌈M/m⌉ < 30` the ACF method is not used: [`FewPoints`] applies the
//! B1 ratio (Barnes 1969; Howe, Beard, Greenhall & Riley 2000) and R(n) = MVAR/AVAR (IEEE 1139)
//! at that τ, one extra pass for all such factors together (beside the ACF passes). Where neither can be
//! formed (fewer than three `m`-averages, or `M < 3m`) the factor takes the result of the
//! largest requested factor below it; failing that, the ACF result at `m_c = ⌊(M − 1)/29⌋`, the
//! largest factor with 30 points; failing that, white rate noise (α = 0).
//!
//! **Consistency with the local slope.** Between 30 and [`CHECK_POINTS`] = 100 decimated points
//! the ACF's δ still scatters by ±1/√n (white rate noise with 40 points reads as flicker angle
//! noise — an EDF several times too large — in about one record in six). There the ACF result
//! must agree with R(n) = MVAR/AVAR, the ratio of the local MDEV and ADEV slopes, on the noise
//! family (angle noise α ≥ 1 or rate noise α ≤ 0); when it does not, the B1/R(n) rule decides.
//! This is not in Stable32: on its published tables it changes the six rows of the GPS record
//! at τ = 8192 s (30 points), where Stable32's ACF reads white FM while R(n) = 0.11 and the
//! ADEV slope from 4096 to 8192 s (τ^−1.05) both say phase noise; in simulations it cuts the
//! white-FM misreading at 40 points from ~16 % to ~1 %.
//!
//! On AllanTools' Stable32 tables (tests/test_allan_stable32_intervals.py, 440 rows) this
//! reproduces Stable32's α on 401 rows and its interval bounds with a median relative error of
//! 1.0e-4 (the 5 printed digits) and a 90th percentile of 1.2e-3; the other α are the six GPS
//! rows above and rows with fewer than 30 points, where Stable32's own choices differ between
//! statistics at the same τ.

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

/// The decimated samples `z_k = x[k·m − base]`, `k in range`, copied in order into `out`
/// (`x` is the window of the angle series that starts at sample `base`). Every kernel below
/// reads a contiguous decimated series: a factor `m > 1` is identified on its copy, exactly as
/// the decimated series itself at factor 1 (bit for bit, a test checks it).
fn gather(x: &[f64], base: usize, m: usize, range: std::ops::Range<usize>, out: &mut Vec<f64>) {
    out.clear();
    if range.is_empty() {
        return;
    }
    let from = &x[range.start * m - base..];
    out.extend(from.iter().step_by(m).take(range.len()));
}

/// Four f64 lanes and the operations of the kernels below, each lane rounded on its own (no
/// fused multiply-add): one vector register where the CPU has four-lane f64 vectors
/// ([`SimdLanes`]), an array otherwise ([`ArrayLanes`]); both give the same bits, so the
/// results do not depend on the CPU (see [`crate::simd`]).
trait Lanes: Copy {
    type V: Copy;
    /// The first [`LANES`] values of `a`.
    fn load(self, a: &[f64]) -> Self::V;
    fn store(self, v: Self::V, out: &mut [f64]);
    fn splat(self, x: f64) -> Self::V;
    fn add(self, a: Self::V, b: Self::V) -> Self::V;
    fn sub(self, a: Self::V, b: Self::V) -> Self::V;
    fn mul(self, a: Self::V, b: Self::V) -> Self::V;
}

#[derive(Clone, Copy)]
struct ArrayLanes;

#[allow(clippy::inline_always)] // inlined into the dispatched kernels
impl Lanes for ArrayLanes {
    type V = [f64; LANES];
    #[inline(always)]
    fn load(self, a: &[f64]) -> Self::V {
        std::array::from_fn(|l| a[l])
    }
    #[inline(always)]
    fn store(self, v: Self::V, out: &mut [f64]) {
        out[..LANES].copy_from_slice(&v);
    }
    #[inline(always)]
    fn splat(self, x: f64) -> Self::V {
        [x; LANES]
    }
    #[inline(always)]
    fn add(self, a: Self::V, b: Self::V) -> Self::V {
        std::array::from_fn(|l| a[l] + b[l])
    }
    #[inline(always)]
    fn sub(self, a: Self::V, b: Self::V) -> Self::V {
        std::array::from_fn(|l| a[l] - b[l])
    }
    #[inline(always)]
    fn mul(self, a: Self::V, b: Self::V) -> Self::V {
        std::array::from_fn(|l| a[l] * b[l])
    }
}

/// [`Lanes`] as one `pulp` vector (only for `S::F64_LANES == LANES`).
#[derive(Clone, Copy)]
struct SimdLanes<S>(S);

#[allow(clippy::inline_always)] // inlined into the dispatched kernels
impl<S: pulp::Simd> Lanes for SimdLanes<S> {
    type V = S::f64s;
    #[inline(always)]
    fn load(self, a: &[f64]) -> Self::V {
        S::as_simd_f64s(&a[..LANES]).0[0]
    }
    #[inline(always)]
    fn store(self, v: Self::V, out: &mut [f64]) {
        S::as_mut_simd_f64s(&mut out[..LANES]).0[0] = v;
    }
    #[inline(always)]
    fn splat(self, x: f64) -> Self::V {
        self.0.splat_f64s(x)
    }
    #[inline(always)]
    fn add(self, a: Self::V, b: Self::V) -> Self::V {
        self.0.add_f64s(a, b)
    }
    #[inline(always)]
    fn sub(self, a: Self::V, b: Self::V) -> Self::V {
        self.0.sub_f64s(a, b)
    }
    #[inline(always)]
    fn mul(self, a: Self::V, b: Self::V) -> Self::V {
        self.0.mul_f64s(a, b)
    }
}

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
    /// the angle series that starts at sample `base`; 0 for the whole series), through `scratch`
    /// when `m > 1`.
    fn add(
        &mut self,
        x: &[f64],
        base: usize,
        m: usize,
        range: std::ops::Range<usize>,
        scratch: &mut Vec<f64>,
    ) {
        if m == 1 {
            self.add_decimated(&x[range.start - base..range.end - base], range.start);
        } else {
            gather(x, base, m, range.clone(), scratch);
            self.add_decimated(scratch, range.start);
        }
    }

    /// Adds the consecutive decimated samples `z[i] = z_{start + i}`, compiled for the CPU's
    /// vector unit (the lanes make the same roundings in every variant).
    fn add_decimated(&mut self, z: &[f64], start: usize) {
        struct Add<'a>(&'a mut TrendSums, &'a [f64], usize);
        impl pulp::WithSimd for Add<'_> {
            type Output = ();
            #[allow(clippy::inline_always)] // pulp's contract: inlined into the dispatched function
            #[inline(always)]
            fn with_simd<S: pulp::Simd>(self, simd: S) {
                if S::F64_LANES == LANES {
                    self.0.add_lanes(SimdLanes(simd), self.1, self.2);
                } else {
                    self.0.add_lanes(ArrayLanes, self.1, self.2);
                }
            }
        }
        crate::simd::arch().dispatch(Add(self, z, start));
    }

    #[allow(clippy::inline_always)] // inlined into the dispatched [`TrendSums::add_decimated`]
    #[inline(always)]
    fn add_lanes<L: Lanes>(&mut self, lanes: L, z: &[f64], start: usize) {
        let half = self.half;
        let c = lanes.splat(self.c);
        let step = lanes.splat(LANES as f64);
        let (mut s0, mut s1, mut s2) = (
            lanes.load(&self.s0),
            lanes.load(&self.s1),
            lanes.load(&self.s2),
        );
        let chunks = z.chunks_exact(LANES);
        let rest = chunks.remainder();
        // u = k − half stepped by whole numbers instead of converted from k: every value is a
        // multiple of ½ below 2⁵², so both are exact and equal bit for bit (a test checks it).
        let u0 = start as f64 - half;
        let mut u = lanes.load(&std::array::from_fn::<f64, LANES, _>(|l| u0 + l as f64));
        for chunk in chunks {
            let v = lanes.load(chunk);
            s0 = lanes.add(s0, v);
            s1 = lanes.add(s1, lanes.mul(v, u));
            s2 = lanes.add(s2, lanes.mul(v, lanes.sub(lanes.mul(u, u), c)));
            u = lanes.add(u, step);
        }
        lanes.store(s0, &mut self.s0);
        lanes.store(s1, &mut self.s1);
        lanes.store(s2, &mut self.s2);
        // Lane i of the tail, as every chunk's lane i: the lane of a sample is its position
        // from `start` modulo LANES.
        let tail = start + z.len() - rest.len();
        let c = self.c;
        for (l, &v) in rest.iter().enumerate() {
            let u = (tail + l) as f64 - half;
            self.s0[l] += v;
            self.s1[l] += v * u;
            self.s2[l] += v * (u * u - c);
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
    /// The trend of the consecutive decimated samples `z` (`z_k`, `k < z.len()`).
    fn fit(z: &[f64]) -> Trend {
        let mut sums = TrendSums::new(z.len());
        sums.add_decimated(z, 0);
        sums.finish(z.len())
    }

    /// The detrended decimated samples `out[i] = z[i] − trend(start + i)` (`out` as long as
    /// `z`).
    #[allow(clippy::inline_always)] // inlined into the dispatched [`AcfState::feed`]
    #[inline(always)]
    fn residuals<L: Lanes>(&self, lanes: L, z: &[f64], start: usize, out: &mut [f64]) {
        let (b0, b1, b2) = (self.b0 - self.b2 * self.c, self.b1, self.b2);
        let half = self.half;
        let (vb0, vb1, vb2) = (lanes.splat(b0), lanes.splat(b1), lanes.splat(b2));
        let step = lanes.splat(LANES as f64);
        // u stepped as in TrendSums::add_lanes (exact, equal to the converted k − half).
        let chunks = z.chunks_exact(LANES);
        let rest = chunks.remainder();
        let whole = z.len() - rest.len();
        let u0 = start as f64 - half;
        let mut u = lanes.load(&std::array::from_fn::<f64, LANES, _>(|l| u0 + l as f64));
        for (chunk, r) in chunks.zip(out[..whole].chunks_exact_mut(LANES)) {
            let v = lanes.load(chunk);
            let t = lanes.add(vb0, lanes.mul(u, lanes.add(vb1, lanes.mul(vb2, u))));
            lanes.store(lanes.sub(v, t), r);
            u = lanes.add(u, step);
        }
        for (i, (&v, r)) in rest.iter().zip(&mut out[whole..z.len()]).enumerate() {
            let u = (start + whole + i) as f64 - half;
            *r = v - (b0 + u * (b1 + b2 * u));
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
    #[allow(clippy::inline_always)] // inlined into the dispatched [`AcfState::feed`]
    #[inline(always)]
    fn extend<L: Lanes>(&mut self, lanes: L, block: &[f64]) {
        let Some((&head, _)) = block.split_first() else {
            return;
        };
        if self.count == 0 {
            self.first = head;
        } else {
            self.s11 += self.last * head;
        }
        let pairs = block.len() - 1;
        let (lead, follow) = (&block[..pairs], &block[1..]);
        let lead_chunks = lead.chunks_exact(LANES);
        let follow_chunks = follow.chunks_exact(LANES);
        let (lead_rest, follow_rest) = (lead_chunks.remainder(), follow_chunks.remainder());
        let zero = lanes.splat(0.0);
        let (mut vs, mut vs2, mut vs11) = (zero, zero, zero);
        for (a, b) in lead_chunks.zip(follow_chunks) {
            let (w, v) = (lanes.load(a), lanes.load(b));
            vs = lanes.add(vs, w);
            vs2 = lanes.add(vs2, lanes.mul(w, w));
            vs11 = lanes.add(vs11, lanes.mul(w, v));
        }
        let mut s = [0.0_f64; LANES];
        let mut s2 = [0.0_f64; LANES];
        let mut s11 = [0.0_f64; LANES];
        lanes.store(vs, &mut s);
        lanes.store(vs2, &mut s2);
        lanes.store(vs11, &mut s11);
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
    /// The current block's values of one difference order and of the next ([`BLOCK`] each).
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
            current: vec![0.0; BLOCK],
            next: vec![0.0; BLOCK],
        }
    }

    /// Feeds the decimated samples `x[k·m − base]`, `k in range` (consecutive with the previous
    /// call), of the window `x` that starts at sample `base`, through `scratch` when `m > 1`.
    fn feed_window(
        &mut self,
        x: &[f64],
        base: usize,
        m: usize,
        trend: &Trend,
        range: std::ops::Range<usize>,
        scratch: &mut Vec<f64>,
    ) {
        if m == 1 {
            self.feed(&x[range.start - base..range.end - base], range.start, trend);
        } else {
            gather(x, base, m, range.clone(), scratch);
            self.feed(scratch, range.start, trend);
        }
    }

    /// Feeds the consecutive decimated samples `z[i] = z_{start + i}` (following the previous
    /// call's), compiled for the CPU's vector unit (the lanes make the same roundings in every
    /// variant).
    fn feed(&mut self, z: &[f64], start: usize, trend: &Trend) {
        struct Feed<'a>(&'a mut AcfState, &'a [f64], usize, &'a Trend);
        impl pulp::WithSimd for Feed<'_> {
            type Output = ();
            #[allow(clippy::inline_always)] // pulp's contract: inlined into the dispatched function
            #[inline(always)]
            fn with_simd<S: pulp::Simd>(self, simd: S) {
                if S::F64_LANES == LANES {
                    self.0.feed_blocks(SimdLanes(simd), self.1, self.2, self.3);
                } else {
                    self.0.feed_blocks(ArrayLanes, self.1, self.2, self.3);
                }
            }
        }
        crate::simd::arch().dispatch(Feed(self, z, start, trend));
    }

    #[allow(clippy::inline_always)] // inlined into the dispatched [`AcfState::feed`]
    #[inline(always)]
    fn feed_blocks<L: Lanes>(&mut self, lanes: L, z: &[f64], start: usize, trend: &Trend) {
        let mut o = 0;
        while o < z.len() {
            let e = (o + BLOCK).min(z.len());
            let mut len = e - o;
            trend.residuals(lanes, &z[o..e], start + o, &mut self.current[..len]);
            // Orders below DMIN never enter the decision (`decide` starts at d = DMIN): their
            // sums are not accumulated (a third of the pass for the Allan variances).
            if self.lowest == 0 {
                self.sums[0].extend(lanes, &self.current[..len]);
            }
            for j in 1..self.levels {
                let (current, next) = (&self.current[..len], &mut self.next);
                let mut out = 0;
                if let (Some(c), Some(&h)) = (self.carry[j - 1], current.first()) {
                    next[0] = h - c;
                    out = 1;
                }
                let pairs = len.saturating_sub(1);
                for ((d, &b), &a) in next[out..out + pairs]
                    .iter_mut()
                    .zip(&current[1..])
                    .zip(current)
                {
                    *d = b - a;
                }
                self.carry[j - 1] = current.last().copied().or(self.carry[j - 1]);
                len = out + pairs;
                if j >= self.lowest {
                    self.sums[j].extend(lanes, &self.next[..len]);
                }
                std::mem::swap(&mut self.current, &mut self.next);
            }
            o = e;
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
fn lag1_all_differences(z: &[f64], trend: &Trend, dmax: u32) -> [f64; 4] {
    let mut state = AcfState::new(dmax);
    state.feed(z, 0, trend);
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
    /// The decimated samples of one factor in the current window (factors `m > 1`).
    scratch: Vec<f64>,
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
            scratch: Vec::new(),
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
                self.trend_sums[i].add(
                    window,
                    s,
                    m,
                    Self::krange(m, self.lens[i], s, e),
                    &mut self.scratch,
                );
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
                self.states[i].feed_window(
                    window,
                    s,
                    m,
                    &self.trends[i],
                    Self::krange(m, self.lens[i], s, e),
                    &mut self.scratch,
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
        scratch: Vec::new(),
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
    if m > 1 {
        // One strided read into a copy instead of one per pass (the kernels then run on
        // contiguous memory): the decimated series at factor 1, the same bits.
        let mut z = Vec::with_capacity(len);
        gather(x, 0, m, 0..len, &mut z);
        return lag1_acf(&z, 1, dmax);
    }
    let trend = Trend::fit(x);
    let mut first = AcfState::orders(DMIN as usize, u32::min(dmax, DMIN));
    first.feed(x, 0, &trend);
    Some(refined(&first, dmax, |state| {
        state.feed(x, 0, &trend);
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
struct FewFactor {
    m: usize,
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
/// disk: the result is the same bit for bit whatever the windows), it gathers for each factor
/// `m` the decimated samples `x_{k·m}` and, on the grid `j = 0, q, 2q, …` (`q = ⌈m/8⌉`), the
/// samples and prefix sums that the Allan and modified Allan terms at `j` need. The prefix sums
/// are formed only at those positions (the "marks", sorted, of every factor): the samples
/// between two marks are summed in 16 lanes relative to the first one, `x_r`
/// (`Σ (x_i − x_r)` plus the exact product `L·x_r`, so that the sum of a random walk's stretch
/// loses nothing to its offset), and the stretch sums are added with Neumaier's compensated
/// summation. Each sample's lane is its distance from the stretch's start modulo the lane
/// count, whatever the windows.
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
    factors: Vec<FewFactor>,
    /// Every position of the factors' prefix grids, sorted, without repeats.
    marks: Vec<usize>,
    /// `P[marks[i]]` for the marks reached so far.
    mark_values: Vec<f64>,
    /// `P[start]` (Neumaier-compensated: `sum + comp`) at the start of the running stretch.
    sum: f64,
    comp: f64,
    /// First sample of the running stretch (the last mark reached; 0 at first) and its value.
    start: usize,
    reference: f64,
    /// Lane sums of `x_i − reference` over the running stretch's samples fed so far.
    lanes: [f64; PREFIX_LANES],
    fed: usize,
}

/// Lanes of the prefix sums' stretch sums (independent additions in flight: four AVX2 or eight
/// SSE2 accumulators).
const PREFIX_LANES: usize = 16;

/// `Σ (v_i − reference)` added to `lanes`, the first value in lane `offset` (then the following
/// lanes, cyclically), compiled for the CPU's vector unit (the lanes make the same roundings
/// in every variant).
fn stretch_sum(lanes: &mut [f64; PREFIX_LANES], v: &[f64], offset: usize, reference: f64) {
    struct Sum<'a>(&'a mut [f64; PREFIX_LANES], &'a [f64], usize, f64);
    impl pulp::WithSimd for Sum<'_> {
        type Output = ();
        #[allow(clippy::inline_always)] // pulp's contract: inlined into the dispatched function
        #[inline(always)]
        fn with_simd<S: pulp::Simd>(self, _simd: S) {
            let Sum(out, v, offset, r) = self;
            let mut lanes = *out;
            let head = ((PREFIX_LANES - offset) % PREFIX_LANES).min(v.len());
            for (l, &x) in lanes[offset..offset + head].iter_mut().zip(v) {
                *l += x - r;
            }
            let chunks = v[head..].chunks_exact(PREFIX_LANES);
            let rest = chunks.remainder();
            for chunk in chunks {
                for l in 0..PREFIX_LANES {
                    lanes[l] += chunk[l] - r;
                }
            }
            for (l, &x) in lanes.iter_mut().zip(rest) {
                *l += x - r;
            }
            *out = lanes;
        }
    }
    crate::simd::arch().dispatch(Sum(lanes, v, offset, reference));
}

impl FewPoints {
    /// Gatherer for the factors `ms` (each with fewer than [`CHECK_POINTS`] decimated points)
    /// of an angle series of `n` samples.
    pub fn new(n: usize, ms: &[usize]) -> FewPoints {
        let factors: Vec<FewFactor> = ms
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
        let mut marks: Vec<usize> = factors
            .iter()
            .flat_map(|f| f.prefix.iter())
            .flat_map(|g| (0..g.count).map(|k| g.base + k * g.stride))
            .collect();
        marks.sort_unstable();
        marks.dedup();
        FewPoints {
            n,
            factors,
            mark_values: Vec::with_capacity(marks.len()),
            marks,
            sum: 0.0,
            comp: 0.0,
            start: 0,
            reference: 0.0,
            lanes: [0.0; PREFIX_LANES],
            fed: 0,
        }
    }

    /// Feeds the next window `x[s..s + window.len()]` (windows in order, starting at 0).
    pub fn feed(&mut self, window: &[f64], s: usize) {
        debug_assert_eq!(s, self.fed);
        let len = window.len();
        self.prefix_marks(window, s);
        self.fed = s + len;
        for f in &mut self.factors {
            f.decimated.gather(s, len, |i| window[i - s]);
            for g in &mut f.angle {
                g.gather(s, len, |i| window[i - s]);
            }
        }
        if self.fed == self.n && self.mark_values.len() == self.marks.len() {
            for f in &mut self.factors {
                for g in &mut f.prefix {
                    g.values.clear();
                    g.values.extend((0..g.count).map(|k| {
                        let at = self.marks.partition_point(|&p| p < g.base + k * g.stride);
                        self.mark_values[at]
                    }));
                }
            }
        }
    }

    /// The prefix sums at the marks inside `[s, s + window.len()]` (module docs of
    /// [`FewPoints`]).
    fn prefix_marks(&mut self, window: &[f64], s: usize) {
        let e = s + window.len();
        let mut i = s;
        loop {
            while self.marks.get(self.mark_values.len()) == Some(&i) {
                let value = self.close_stretch(i);
                self.mark_values.push(value);
            }
            let Some(&next) = self.marks.get(self.mark_values.len()) else {
                return;
            };
            if i == e {
                return;
            }
            if i == self.start {
                self.reference = window[i - s];
            }
            let stop = next.min(e);
            stretch_sum(
                &mut self.lanes,
                &window[i - s..stop - s],
                (i - self.start) % PREFIX_LANES,
                self.reference,
            );
            i = stop;
        }
    }

    /// Ends the running stretch at sample `i` (exclusive) and returns `P[i]`.
    fn close_stretch(&mut self, i: usize) -> f64 {
        let count = (i - self.start) as f64;
        if count > 0.0 {
            // Σ x_i = Σ (x_i − x_r) + L·x_r, the product split exactly into value and error.
            let scaled = count * self.reference;
            let error = count.mul_add(self.reference, -scaled);
            let part: f64 = self.lanes.iter().sum();
            for v in [scaled, part, error] {
                crate::validate::neumaier_add(&mut self.sum, &mut self.comp, v);
            }
            self.lanes = [0.0; PREFIX_LANES];
        }
        self.start = i;
        self.sum + self.comp
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
    fn b1(&self) -> Option<f64> {
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
    fn rn(&self) -> Option<f64> {
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
    let few = std::cell::OnceCell::new();
    identify_with(
        x.len(),
        ms,
        // Factors up to JOINT_MAX read every cache line of x: identify them in one joint
        // sweep, the larger ones (cheap, strided) and the few-point factors' B1/R(n) in
        // parallel beside it.
        |small, large| {
            let (joint, (large, gathered)) = rayon::join(
                || lag1_acf_joint(x, small, dmax),
                || {
                    rayon::join(
                        || {
                            large
                                .par_iter()
                                .with_max_len(1)
                                .map(|&m| lag1_acf(x, m, dmax))
                                .collect::<Vec<_>>()
                        },
                        || few_points_in_memory(x, ms),
                    )
                },
            );
            // Set once, here, before `few` below reads it.
            let _ = few.set(gathered);
            (joint, large)
        },
        |m| lag1_acf(x, m, dmax),
        |m, acf| few.get().and_then(|f| f.resolve(m, acf)),
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

#[cfg(test)]
mod tests {
    use super::*;

    fn noise(n: usize, seed: u64) -> Vec<f64> {
        crate::random::normal_vec(n, seed)
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
            let z: Vec<f64> = x.iter().step_by(m).copied().collect();
            let trend = Trend::fit(&z);
            let r1 = lag1_all_differences(&z, &trend, 3);
            // The orders the decision reads (from DMIN: lower ones are not accumulated).
            for d in DMIN as usize..=3 {
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

    /// The one-pass identification (every order accumulated in the same pass, as the
    /// streamed path does): the reference of the refined in-memory path.
    fn one_pass(x: &[f64], m: usize, dmax: u32) -> Option<Identification> {
        let len = x.len().div_ceil(m);
        (len >= MIN_POINTS).then(|| {
            let z: Vec<f64> = x.iter().step_by(m).copied().collect();
            let trend = Trend::fit(&z);
            decide(&lag1_all_differences(&z, &trend, dmax), dmax)
        })
    }

    /// Angle series of the kinds an inertial log gives: white angle, white rate (random walk),
    /// random-walk rate, each with a large offset and a rate bias (the drift that makes the
    /// angle series' magnitude grow), and a pure random walk without them.
    fn realistic(n: usize, seed: u64) -> Vec<Vec<f64>> {
        let w = noise(n, seed);
        let bias = 0.5 + (seed % 7) as f64;
        let offset = 1e4 * (seed % 5) as f64 - 2e4;
        let drifting = |v: &[f64]| -> Vec<f64> {
            v.iter()
                .enumerate()
                .map(|(k, y)| offset + bias * k as f64 + y)
                .collect()
        };
        let rate = cumsum(&w);
        let rw = cumsum(&rate);
        vec![drifting(&w), drifting(&rate), drifting(&rw), rate]
    }

    #[test]
    fn prefix_marks_equal_a_direct_compensated_sum() {
        // P at every mark against an exactly rounded reference (Neumaier over the samples in
        // order, then the stretch rule's result must agree to a few ulps of Σ|x|).
        let x = realistic(30_011, 3).swap_remove(2);
        let ms = [400usize, 1_000, 1_001, 7_000, 10_000];
        let few = few_points_in_memory(&x, &ms);
        let mut exact = Vec::with_capacity(x.len() + 1);
        let (mut sum, mut comp) = (0.0_f64, 0.0_f64);
        exact.push(0.0);
        for &v in &x {
            crate::validate::neumaier_add(&mut sum, &mut comp, v);
            exact.push(sum + comp);
        }
        let scale: f64 = x.iter().map(|v| v.abs()).sum();
        assert_eq!(few.mark_values.len(), few.marks.len());
        for (&p, &v) in few.marks.iter().zip(&few.mark_values) {
            // 1e-15 of Σ|x|: both are compensated sums (error ~ε·|P| plus ε² terms).
            assert!(
                (v - exact[p]).abs() <= 1e-15 * scale,
                "P[{p}]: {v} vs {}",
                exact[p]
            );
        }
    }

    #[test]
    fn stepped_u_equals_converted_bit_for_bit() {
        // TrendSums::add_lanes and Trend::residuals step u = k − half by whole numbers at
        // factor 1; the reference converts k per sample (same lanes, same operations).
        let x = cumsum(&cumsum(&noise(5_003, 7)));
        let bits = |v: &[f64]| v.iter().map(|f| f.to_bits()).collect::<Vec<_>>();
        for (start, end) in [(0, 5_003), (17, 4_099), (1, 2), (4_000, 5_003)] {
            let len = 5_003;
            let mut sums = TrendSums::new(len);
            sums.add_decimated(&x[start..end], start);
            let (half, c) = (sums.half, sums.c);
            let mut reference = [[0.0_f64; LANES]; 3];
            let rest_start = end - (end - start) % LANES;
            for k in start..end {
                let l = if k < rest_start {
                    (k - start) % LANES
                } else {
                    k - rest_start
                };
                let (u, z) = (k as f64 - half, x[k]);
                reference[0][l] += z;
                reference[1][l] += z * u;
                reference[2][l] += z * (u * u - c);
            }
            assert_eq!(bits(&sums.s0), bits(&reference[0]));
            assert_eq!(bits(&sums.s1), bits(&reference[1]));
            assert_eq!(bits(&sums.s2), bits(&reference[2]));
            let trend = Trend::fit(&x);
            let mut out = vec![0.0; end - start];
            trend.residuals(ArrayLanes, &x[start..end], start, &mut out);
            let (b0, b1, b2) = (trend.b0 - trend.b2 * trend.c, trend.b1, trend.b2);
            let expected: Vec<f64> = (start..end)
                .map(|k| {
                    let u = k as f64 - trend.half;
                    x[k] - (b0 + u * (b1 + b2 * u))
                })
                .collect();
            assert_eq!(bits(&out), bits(&expected));
        }
    }

    #[test]
    fn refined_orders_equal_one_pass_bit_for_bit() {
        // White angle, white rate, random-walk rate and a drifting walk: the decision stops at
        // the first difference or reads the second and third; 40 001 samples cross the sweep
        // and block boundaries.
        let w = noise(40_001, 31);
        let series = [w.clone(), cumsum(&w), cumsum(&cumsum(&w)), {
            let walk = cumsum(&cumsum(&w));
            walk.iter()
                .enumerate()
                .map(|(i, v)| v + 1e-3 * (i as f64).powi(2))
                .collect()
        }];
        let ms = [1usize, 2, 3, 4, 5, 8, 9, 16, 100, 1000];
        let mut read_more = 0;
        for x in &series {
            for dmax in [2u32, 3] {
                let joint = lag1_acf_joint(x, &ms, dmax);
                let mut stream = JointSweep::new(x.len(), &ms, dmax);
                for s in (0..x.len()).step_by(SWEEP) {
                    stream.trend_block(&x[s..(s + SWEEP).min(x.len())], s);
                }
                for s in (0..x.len()).step_by(SWEEP) {
                    stream.acf_block(&x[s..(s + SWEEP).min(x.len())], s);
                }
                let streamed = stream.finish();
                for (i, &m) in ms.iter().enumerate() {
                    let reference = one_pass(x, m, dmax);
                    let bits =
                        |id: Option<Identification>| id.map(|i| (i.alpha, i.d, i.delta.to_bits()));
                    assert_eq!(
                        bits(lag1_acf(x, m, dmax)),
                        bits(reference),
                        "m={m} dmax={dmax}"
                    );
                    // The joint sweep's blocks follow the sweep windows (its sums round
                    // differently from a single factor's: the same decision, δ within a few
                    // ulps); its reference is the one-pass sweep the streamed path runs.
                    assert_eq!(
                        joint[i].map(|i| (i.alpha, i.d)),
                        reference.map(|i| (i.alpha, i.d)),
                        "joint m={m} dmax={dmax}"
                    );
                    assert_eq!(
                        bits(joint[i]),
                        bits(streamed[i]),
                        "stream m={m} dmax={dmax}"
                    );
                    read_more += usize::from(reference.is_some_and(|r| r.d > DMIN));
                }
            }
        }
        // both branches ran
        assert!(read_more > 0);
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
    fn few_points_use_b1_and_rn() {
        let x = cumsum(&noise(300, 11)); // 301 phase points, white rate noise
        assert!(lag1_acf(&x, 11, 2).is_none()); // ⌈301/11⌉ = 28 < 30
        // Requested factors 1, 4 by the ACF; 11, 20, 50 by B1/R(n); 120 (N < 3m, two
        // averages) carries 50's.
        let ids = identify(&x, &[120, 1, 4, 11, 20, 50], 2);
        let few = few_points_in_memory(&x, &[4, 11, 20, 50, 120]);
        assert_eq!(few.identify(120), None);
        assert_eq!(ids[1], lag1_acf(&x, 1, 2).unwrap().alpha); // 301 points: ACF alone
        // 76 points: the ACF result checked against R(n).
        let acf4 = lag1_acf(&x, 4, 2).unwrap().alpha;
        assert_eq!(Some(ids[2]), few.resolve(4, Some(acf4)));
        for (i, m) in [(3, 11), (4, 20), (5, 50)] {
            assert_eq!(Some(ids[i]), few.identify(m), "m={m}");
        }
        assert_eq!(ids[0], ids[5]);
    }

    /// Direct evaluation of R(n) on the same grid: the Allan and modified Allan terms summed
    /// from their definitions (inner sum of m second differences, no prefix sums).
    fn direct_rn(x: &[f64], m: usize) -> f64 {
        let q = m.div_ceil(RN_GRID);
        let n = x.len();
        let d2 = |i: usize| x[i + 2 * m] - 2.0 * x[i + m] + x[i];
        let a: Vec<f64> = (0..n - 2 * m).step_by(q).map(|j| d2(j).powi(2)).collect();
        let b: Vec<f64> = (0..=n - 3 * m)
            .step_by(q)
            .map(|j| (j..j + m).map(d2).sum::<f64>().powi(2))
            .collect();
        let avar = a.iter().sum::<f64>() / a.len() as f64;
        let mvar = b.iter().sum::<f64>() / (b.len() as f64 * (m * m) as f64);
        mvar / avar
    }

    #[test]
    fn rn_and_b1_equal_their_definitions() {
        let x = cumsum(&noise(2_000, 5));
        for m in [70usize, 71, 100, 333, 666] {
            let few = few_points_in_memory(&x, &[m]);
            let f = &few.factors[0];
            // 1e-9: prefix-sum differences vs direct sums of m terms (rounding of the
            // compensated prefix sums of a random walk, ~1e-13 relative).
            let rn = f.rn().unwrap();
            assert!((rn / direct_rn(&x, m) - 1.0).abs() < 1e-9, "m={m}: {rn}");
            // B1 from the rate averages (x_{(k+1)m} − x_{km})/m.
            let y: Vec<f64> = (0..(x.len() - 1) / m)
                .map(|k| (x[(k + 1) * m] - x[k * m]) / m as f64)
                .collect();
            let mean = y.iter().sum::<f64>() / y.len() as f64;
            let var = y.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (y.len() - 1) as f64;
            let avar = y.windows(2).map(|w| (w[1] - w[0]).powi(2)).sum::<f64>()
                / (2 * (y.len() - 1)) as f64;
            let b1 = f.b1().unwrap();
            assert!((b1 / (var / avar) - 1.0).abs() < 1e-12, "m={m}");
        }
    }

    #[test]
    fn few_points_windows_equal_one_feed_bit_for_bit() {
        let x = cumsum(&noise(10_007, 13));
        let ms = [400usize, 401, 1000, 2500, 3335, 5000];
        let whole = few_points_in_memory(&x, &ms);
        for w in [1usize, 7, 1000, 4096] {
            let mut few = FewPoints::new(x.len(), &ms);
            for s in (0..x.len()).step_by(w) {
                few.feed(&x[s..(s + w).min(x.len())], s);
            }
            for &m in &ms {
                assert_eq!(few.identify(m), whole.identify(m), "w={w} m={m}");
                let (a, b) = (
                    &few.factors.iter().find(|f| f.m == m).unwrap(),
                    &whole.factors.iter().find(|f| f.m == m).unwrap(),
                );
                assert_eq!(a.rn().map(f64::to_bits), b.rn().map(f64::to_bits));
            }
        }
    }

    #[test]
    fn few_points_find_the_simulated_noise() {
        // 20 000 samples, factors with 8–25 decimated points. Over 20 records per noise the
        // B1/R(n) rule must find the simulated α in most cases (the ratios of ~10 averages
        // scatter; Howe et al. 2000 report the same), and never a wrong family (angle vs rate
        // noise) for white angle / random-walk rate noise.
        let ms = [800usize, 1600, 2400];
        let mut hits = [0usize; 3];
        let total = 20 * ms.len();
        for seed in 0..20u64 {
            let w = noise(20_000, 100 + seed);
            let white_rate = cumsum(&w);
            let rw_rate = cumsum(&white_rate);
            let white_angle = noise(20_001, 200 + seed);
            for (k, (x, alpha)) in [(&white_angle, 2), (&white_rate, 0), (&rw_rate, -2)]
                .into_iter()
                .enumerate()
            {
                let ids = identify(x, &ms, 2);
                hits[k] += ids.iter().filter(|&&a| a == alpha).count();
                if alpha != 0 {
                    assert!(
                        ids.iter().all(|&a| (a > 0) == (alpha > 0)),
                        "{alpha}: {ids:?}"
                    );
                }
            }
        }
        // Measured: random-walk rate 39/60 (the B1 of 8–25 averages of a random walk scatters
        // widely around n/2; the misses read flicker rate, the neighbouring α); ≥ 60 % each.
        for (k, &h) in hits.iter().enumerate() {
            assert!(h * 10 >= total * 6, "noise {k}: {h}/{total}");
        }
    }

    #[test]
    fn acf_with_few_dozen_points_is_checked_against_rn() {
        // White rate noise, 20 001 angle samples, m = 512 (40 decimated points): over 100
        // records the checked identification misreads it at most 5 times; the ACF alone
        // scatters (δ ± 1/√39) into a neighbouring α in ~16 % (measured 33/200 in Python).
        let mut wrong = 0;
        let mut wrong_acf = 0;
        for seed in 0..100u64 {
            let x = cumsum(&noise(20_000, 300 + seed));
            wrong += usize::from(identify(&x, &[512], 2)[0] != 0);
            wrong_acf += usize::from(lag1_acf(&x, 512, 2).unwrap().alpha != 0);
        }
        assert!(wrong <= 5, "{wrong}");
        assert!(wrong_acf >= 5, "{wrong_acf}");
    }

    #[test]
    fn tiny_records() {
        // 25 phase points: no ACF anywhere; B1/R(n) where they can be formed.
        let w = noise(24, 5);
        let rw = cumsum(&cumsum(&w));
        assert!(lag1_acf(&rw, 1, 2).is_none());
        let ids = identify(&rw, &[1, 2, 4], 2);
        assert!(ids.iter().all(|&a| a <= -1), "{ids:?}");
        let ids = identify(&noise(25, 9), &[1, 2, 4, 8, 12], 2);
        assert_eq!(ids.len(), 5);
        assert!(ids.iter().all(|a| (-2..=2).contains(a)));
        // Two or three samples: nothing can be identified, white rate noise.
        assert_eq!(identify(&[0.0, 1.0, 0.5], &[1], 2), vec![0]);
    }

    #[test]
    fn scaling_by_powers_of_two_changes_nothing() {
        let x = cumsum(&noise(5_000, 21));
        let ms = [1usize, 2, 8, 64, 200, 400, 1000, 2000];
        let base = identify(&x, &ms, 3);
        for k in [-30i32, -1, 1, 40] {
            let s = 2f64.powi(k);
            let y: Vec<f64> = x.iter().map(|v| v * s).collect();
            assert_eq!(identify(&y, &ms, 3), base, "2^{k}");
        }
    }
}
