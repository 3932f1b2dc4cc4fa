//! Théo1, bias-removed ThéoBR and the hybrid ThéoH (NIST SP 1065 §5.2.14–5.2.16).
//!
//! **Théo1** (D. A. Howe and T. K. Peppler, "Very long-term frequency stability: estimation
//! using a special-purpose statistic", IFCS 2003; SP 1065 eq. 30) on `N` angle samples at even
//! `m` (`2 ≤ m ≤ N − 1`) estimates the Allan variance at `τ = 0.75·m·t0`:
//!
//! ```text
//! Théo1(m) = 1/(0.75 (N − m)(m t0)²) · Σ_{i=0}^{N−m−1} Σ_{δ=0}^{m/2−1} 1/(m/2 − δ)
//!            · [(x_i − x_{i−δ+m/2}) + (x_{i+m} − x_{i+δ+m/2})]²
//! ```
//!
//! With `k = m/2 − δ` the bracket is `(x_i − x_{i+k}) − (x_{i+m−k} − x_{i+m})`, the difference of
//! two `k`-lag increments `m − k` apart. Three exact evaluations:
//!
//! * **direct** — the brackets summed from differences of `x` (no expansion into products of
//!   samples, which loses digits on drifting data), cache-blocked and vectorised,
//!   `(N − m)·m/2` brackets per τ: used for small `m`.
//! * **blocks** — the record split exactly into blocks of `≈ 4m` outer terms, each a residual
//!   about its own line, the squared bracket expanded into prefix sums and correlations by
//!   FFT, the triangle of pairs at each block end by divide and conquer: `O(N log m)` per τ
//!   (module `blocks`). Each block checks an a-priori rounding bound (≤ 1e-11 of its sum) and is
//!   summed directly where it fails. Used for large `m`: the octave set costs
//!   `O(N log² N)`, Allan-like, instead of `O(N²)` (measured 3.7 s at N = 1e6, was 204 s).
//! * **structure-function sweep** — polarisation turns every squared bracket into six squared
//!   increments, so each τ is a weighted sum of the lag structure functions
//!   `SF(ℓ) = Σ_t (x_{t+ℓ} − x_t)²` minus edge sums that are updated in `O(m)` per step of
//!   `m` (details at `theo1_sums_sweep`; the structure functions cache-blocked over groups of
//!   lags, measured 1.75× faster at N = 5e5). All even `m ≤ M` cost `≈ N·M + 2M²` together,
//!   `O(N)` per τ like all-τ Allan (the complexity of B. Lewis's recurrence, "A fast algorithm
//!   for calculation of Thêo1", IEEE TUFFC 67(10), 2020): used for dense sets (ThéoBR's bias
//!   ratio, all τ).
//!
//! All run on the residual of a least-squares quadratic (exact split, the quadratic's part
//! added in closed form), so bias and rate ramp do not cost digits. They are checked against
//! the literal sum with error-free brackets (TwoSum) on white FM, random-walk FM and white FM
//! under a bias 3e6× its noise plus a rate ramp: measured max relative difference 1.2e-14
//! (direct), 5.3e-14 (blocks), 5.4e-13 (sweep).
//!
//! [`theo1`] and [`theo1_many`] pick the cheapest from `N`, `m` and the τ set alone (never
//! from threads or chunking), so a value can differ in its last digits with the τ set.
//!
//! **ThéoBR** (Howe & Tasset, "ThêoH: a hybrid, high-confidence statistic that improves on the
//! Allan deviation", Metrologia 43 (2006) S322; SP 1065 eq. 31) removes Théo1's bias for the
//! noise at hand using the AVAR/Théo1 ratio at the same τ over the short-τ region:
//!
//! ```text
//! ThéoBR(m) = [1/(n+1) · Σ_{i=0}^{n} AVAR(9 + 3i) / Théo1(12 + 4i)] · Théo1(m),   n = ⌊N/30 − 3⌋
//! ```
//!
//! (AVAR the overlapping Allan variance at `m = 9 + 3i`, the same τ as Théo1 at `12 + 4i`).
//! **ThéoH** joins AVAR below and ThéoBR above the break τ `k`, the largest τ ≤ 10 % of the
//! record `T = (N − 1)·t0` (SP 1065 eq. 32).

use rayon::prelude::*;

use crate::validate;

mod blocks;
use crate::{Error, Result};

/// Direct Théo1 double sum `Σ_{k=1}^{m/2} (1/k) Σ_i [(x_i − x_{i+k}) − (x_{i+m−k} − x_{i+m})]²`
/// (SP 1065 eq. 30 without the normalisation), `(N − m)·m/2` squared brackets.
///
/// Runs on the detrended record: each bracket is `B(r) + β_k`, `β_k = 2·p2·k(m − k)` the
/// bracket of the quadratic (constant in `i`), so the differences are of residual-sized
/// numbers. On raw drifting data (`x` ≈ 1e10, increments ≈ 3e6·k) the differences of `x` are
/// inexact and the plain sum was measured 2.2e-11 off the error-free sum; this one is exact to
/// ≈ 1e-15 there (test `sweep_and_direct_are_exact_at_every_factor`).
fn theo1_sum_direct(d: &Detrended, m: usize) -> f64 {
    bracket_sum_direct(&d.r, d.p2, m)
}

/// [`theo1_sum_direct`] on a residual `x` with quadratic coefficient `p2` per sample².
fn bracket_sum_direct(x: &[f64], p2: f64, m: usize) -> f64 {
    // Cache blocking: a task owns `K_CHUNK` consecutive k and walks i in blocks of `I_BLOCK`;
    // inside a block the k-slices `x[i+k..]`, `x[i+m−k..]` of consecutive k overlap, so the
    // passes hit L1 instead of streaming the record once per k. Each k's sum is accumulated
    // over the blocks in order: the result does not depend on the thread count.
    const K_CHUNK: usize = 32;
    const I_BLOCK: usize = 1024;
    let n = x.len();
    let count = n - m;
    let h = m / 2;
    let chunks: Vec<f64> = (0..h.div_ceil(K_CHUNK))
        .into_par_iter()
        .map(|chunk| {
            let k_lo = 1 + chunk * K_CHUNK;
            let k_hi = h.min(k_lo + K_CHUNK - 1);
            let mut acc = [0.0_f64; K_CHUNK];
            let mut i0 = 0;
            while i0 < count {
                let len = I_BLOCK.min(count - i0);
                let a = &x[i0..i0 + len];
                let dd = &x[i0 + m..i0 + m + len];
                for k in k_lo..=k_hi {
                    let b = &x[i0 + k..i0 + k + len];
                    let c = &x[i0 + m - k..i0 + m - k + len];
                    let beta = 2.0 * p2 * (k * (m - k)) as f64;
                    acc[k - k_lo] += bracket_squares(a, b, c, dd, beta);
                }
                i0 += len;
            }
            validate::neumaier_sum((k_lo..=k_hi).map(|k| acc[k - k_lo] / k as f64))
        })
        .collect();
    validate::neumaier_sum(chunks)
}

/// `Σ_i [(a_i − b_i) − (c_i − d_i) + β]²` over equal-length slices, in eight lanes.
#[inline]
fn bracket_squares(a: &[f64], b: &[f64], c: &[f64], d: &[f64], beta: f64) -> f64 {
    let len = a.len();
    let mut lanes = [0.0_f64; 8];
    let whole = len - len % 8;
    for (((ca, cb), cc), cd) in a[..whole]
        .chunks_exact(8)
        .zip(b[..whole].chunks_exact(8))
        .zip(c[..whole].chunks_exact(8))
        .zip(d[..whole].chunks_exact(8))
    {
        for l in 0..8 {
            let t = (ca[l] - cb[l]) - (cc[l] - cd[l]) + beta;
            lanes[l] += t * t;
        }
    }
    let mut tail = 0.0;
    for i in whole..len {
        let t = (a[i] - b[i]) - (c[i] - d[i]) + beta;
        tail += t * t;
    }
    lanes.iter().sum::<f64>() + tail
}

/// `a·b` as an unevaluated sum `hi + lo` (exact, via fused multiply-add).
#[inline]
fn two_prod(a: f64, b: f64) -> (f64, f64) {
    let p = a * b;
    (p, a.mul_add(b, -p))
}

/// `a + b` as an unevaluated sum `hi + lo` (exact, Knuth's TwoSum).
#[inline]
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

/// Least-squares quadratic `p0 + p1·u + p2·u²` of `v` in `u = t − (N − 1)/2` (normal
/// equations; odd moments of `u` vanish). Zeros when degenerate (N < 3) or not finite.
fn quadratic_fit(v: &[f64]) -> [f64; 3] {
    let n = v.len();
    let centre = (n as f64 - 1.0) / 2.0;
    let (mut s2, mut s4, mut sv, mut svu, mut svu2) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for (t, &a) in v.iter().enumerate() {
        let u = t as f64 - centre;
        let u2 = u * u;
        s2 += u2;
        s4 += u2 * u2;
        sv += a;
        svu += a * u;
        svu2 += a * u2;
    }
    let s0 = n as f64;
    let det = s0 * s4 - s2 * s2;
    let p = [
        (sv * s4 - s2 * svu2) / det,
        svu / s2,
        (s0 * svu2 - s2 * sv) / det,
    ];
    if n >= 3 && det > 0.0 && p.iter().all(|c| c.is_finite()) {
        p
    } else {
        [0.0; 3]
    }
}

/// `x_t − (p0 + p1·u + p2·u²)`, `u = t − (N − 1)/2` (exact: `N − 1` is even or odd, `u` a
/// multiple of 1/2), evaluated in double-double so that the only rounding is the final one of
/// each residual (`|error| ≤ ε·|r_t|`, not `ε·|x_t|`).
fn residual(x: &[f64], p: [f64; 3]) -> Vec<f64> {
    let centre = (x.len() as f64 - 1.0) / 2.0;
    x.iter()
        .enumerate()
        .map(|(t, &v)| {
            let u = t as f64 - centre;
            let (uu, uu_lo) = two_prod(u, u);
            let (a, a_lo) = two_prod(p[2], uu);
            let (b, b_lo) = two_prod(p[1], u);
            let (s, e1) = two_sum(a, b);
            let (s, e2) = two_sum(s, p[0]);
            let lo = p[2].mul_add(uu_lo, a_lo) + b_lo + e1 + e2;
            let (d, e3) = two_sum(v, -s);
            d + (e3 - lo)
        })
        .collect()
}

/// A record split exactly into `q + r`: `q` the least-squares quadratic (fitted twice: the
/// second fit, on the residual of the first, removes what the first lost to rounding on
/// drifting data), `r` the residual, `p2` the quadratic coefficient of `q` per sample².
///
/// Théo1 ignores constants and linear trends, and the bracket of `q` is the constant
/// `β_k = 2·p2·k(m − k)`, so both methods sum brackets of `r` plus `β_k`: any `q` would be
/// exact, a good one keeps the numbers small (bias and rate ramp cost no digits).
struct Detrended {
    r: Vec<f64>,
    p2: f64,
}

fn detrend(x: &[f64]) -> Detrended {
    let mut p = quadratic_fit(x);
    let first = residual(x, p);
    let d = quadratic_fit(&first);
    for (c, dc) in p.iter_mut().zip(d) {
        *c += dc;
    }
    Detrended {
        r: residual(x, p),
        p2: p[2],
    }
}

/// Terms per compensated block of [`structure_function`]: each lag's sum is the Neumaier sum
/// of plain (eight-lane) sums over consecutive blocks of this many terms, from `t = 0`.
const SF_BLOCK: usize = 2048;

/// Consecutive lags that share one pass over the record in [`structure_function`].
const SF_LAGS: usize = 64;

/// `Σ_{t=0}^{N−ℓ−1} (r_{t+ℓ} − r_t)²` for `ℓ = 0..=max_lag` (structure function; entry 0 is 0).
///
/// Each lag's sum is, in a fixed order, the Neumaier sum of its blocks of [`SF_BLOCK`] terms
/// (`t` in `[j·B, (j + 1)·B)`), each block summed in eight lanes: relative error ≈ 256 ε
/// worst case, the terms being non-negative.
///
/// Cache blocking: a task owns [`SF_LAGS`] consecutive lags and walks the record once, block by
/// block; the block's `r[t..]` and the overlapping slices `r[t + ℓ..]` of its lags (≈ 33 kB)
/// stay in L1/L2 while all lags of the group use them, instead of streaming the whole record
/// once per lag. The per-lag block sums and their order are those of one pass per lag
/// (`structure_function_per_lag` in the tests gives identical bits), so the result depends
/// neither on the grouping nor on the thread count. With the other `O(M²)` parts of the sweep,
/// measured on white FM (ThéoBR, octave τ; 2 shared cores, load ≈ 1.5–2, alternating runs):
/// N = 2e5 2.5 s → 1.65 s, N = 5e5 12.1–13.6 s → 6.9–7.8 s, N = 1e6 46 s → 26 s. The kernel
/// is now compute-bound (AVX2); about half of the remaining time is the `O(M²)` edge and
/// combination sums.
fn structure_function(r: &[f64], max_lag: usize) -> Vec<f64> {
    let n = r.len();
    let groups: Vec<Vec<f64>> = (0..max_lag.div_ceil(SF_LAGS))
        .into_par_iter()
        .with_min_len(if n < 4096 { 8 } else { 1 })
        .map(|g| {
            let lo = 1 + g * SF_LAGS;
            let hi = max_lag.min(lo + SF_LAGS - 1);
            crate::simd::arch().dispatch(LagGroup { r, lo, hi })
        })
        .collect();
    let mut sf = Vec::with_capacity(max_lag + 1);
    sf.push(0.0);
    sf.extend(groups.into_iter().flatten());
    sf
}

/// The lags `lo..=hi` of [`structure_function`] in one walk over the record, as a `pulp`
/// operation so that it is compiled (fully inlined) inside the CPU-feature-specific function
/// the dispatcher selects (AVX2 where available; the lanes make the same roundings in every
/// variant, no fused multiply-add is formed, so the bits do not depend on the CPU).
struct LagGroup<'a> {
    r: &'a [f64],
    lo: usize,
    hi: usize,
}

impl pulp::WithSimd for LagGroup<'_> {
    type Output = Vec<f64>;

    #[allow(clippy::inline_always)] // pulp's contract: inlined into the dispatched function
    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) -> Vec<f64> {
        let LagGroup { r, lo, hi } = self;
        let n = r.len();
        let mut acc = [(0.0_f64, 0.0_f64); SF_LAGS];
        // Lag `lo` has the most terms: its blocks cover every block of the group.
        let mut t = 0;
        while t < n - lo {
            for lag in lo..=hi {
                let count = n - lag;
                if t >= count {
                    break;
                }
                let len = SF_BLOCK.min(count - t);
                let block = squared_increments(&r[t..t + len], &r[t + lag..t + lag + len]);
                let (sum, comp) = &mut acc[lag - lo];
                validate::neumaier_add(sum, comp, block);
            }
            t += SF_BLOCK;
        }
        acc[..=hi - lo].iter().map(|&(s, c)| s + c).collect()
    }
}

/// `Σ_i (b_i − a_i)²` over equal-length slices, in eight lanes (lanes summed in order, then
/// the ragged tail).
#[allow(clippy::inline_always)] // inlined into the dispatched [`LagGroup`]
#[inline(always)]
fn squared_increments(a: &[f64], b: &[f64]) -> f64 {
    let mut lanes = [0.0_f64; 8];
    let whole = a.len() - a.len() % 8;
    for (pa, pb) in a[..whole].chunks_exact(8).zip(b[..whole].chunks_exact(8)) {
        for l in 0..8 {
            let d = pb[l] - pa[l];
            lanes[l] += d * d;
        }
    }
    let mut tail = 0.0;
    for i in whole..a.len() {
        let d = b[i] - a[i];
        tail += d * d;
    }
    lanes.iter().sum::<f64>() + tail
}

/// Neumaier prefix sums `[0, v_0, v_0 + v_1, …]` of the first `len` values of `v`.
fn prefix_sums(v: impl Iterator<Item = f64>, len: usize) -> Vec<f64> {
    let mut out = Vec::with_capacity(len + 1);
    let (mut s, mut c) = (0.0_f64, 0.0_f64);
    out.push(0.0);
    for a in v.take(len) {
        let (t, e) = two_sum(s, a);
        s = t;
        c += e;
        out.push(s + c);
    }
    out
}

/// The quadratic's part of the bracket sum at `m` on a record of `n` samples:
/// `Σ_k (β_k/k)·[(N − m)·β_k + 2 Σ_i B_k(r, i)]`, `β_k = 2·p2·k(m − k)`, where
/// `Σ_i B_k(r, i)` telescopes to four edge windows of `r` of length `k`: from the prefix sums
/// `rp` of `r` and `zp` of `r` reversed (at least `m + 1` entries each).
fn quadratic_part(p2: f64, n: usize, m: usize, rp: &[f64], zp: &[f64]) -> f64 {
    validate::neumaier_sum(quadratic_terms(p2, n, m, rp, zp))
}

/// The terms `k = 1..=m/2` of [`quadratic_part`] (none when `p2 = 0`).
fn quadratic_terms<'a>(
    p2: f64,
    n: usize,
    m: usize,
    rp: &'a [f64],
    zp: &'a [f64],
) -> impl Iterator<Item = f64> + 'a {
    let count = (n - m) as f64;
    let h = if p2 == 0.0 { 0 } else { m / 2 };
    (1..=h).map(move |k| {
        let beta = 2.0 * p2 * (k * (m - k)) as f64;
        let sum_b = (rp[k] - rp[m] + rp[m - k]) + (zp[k] - zp[m] + zp[m - k]);
        beta * (count * beta + 2.0 * sum_b) / k as f64
    })
}

/// Neumaier sum of `values` in four interleaved lanes (value `i` to lane `i mod 4`), the
/// lanes' sums and compensations then combined by [`validate::neumaier_sum`]. Same error
/// bound as one Neumaier sum (≈ 2ε·|S| + O(n ε²)·Σ|v|), but four independent dependency
/// chains instead of one: the `O(M²)` combinations of the sweep were latency-bound on it.
#[inline]
fn neumaier_lanes(values: &[f64]) -> f64 {
    let mut sum = [0.0_f64; 4];
    let mut comp = [0.0_f64; 4];
    let whole = values.len() - values.len() % 4;
    for c in values[..whole].chunks_exact(4) {
        for l in 0..4 {
            validate::neumaier_add(&mut sum[l], &mut comp[l], c[l]);
        }
    }
    for (l, &v) in values[whole..].iter().enumerate() {
        validate::neumaier_add(&mut sum[l], &mut comp[l], v);
    }
    validate::neumaier_sum(sum.into_iter().chain(comp))
}

/// Cost of one bracket of the direct sum, in the nanosecond-like units of [`blocks::cost`]
/// (measured on 2 cores, x86-64 with AVX2: ≈ 0.86 ns per bracket).
const BRACKET_COST: f64 = 0.86;

/// Cost of the direct sum at `m` on `n` samples (`(N − m)·m/2` brackets).
fn direct_cost(n: usize, m: usize) -> f64 {
    BRACKET_COST * (n - m) as f64 * (m / 2) as f64
}

/// Whether the block-FFT sum is cheaper than the direct sum at `m` (a function of `n` and
/// `m` only, so the method and the last digits never depend on threads or the τ set).
fn prefer_blocks(n: usize, m: usize) -> bool {
    blocks::cost(n, m) < direct_cost(n, m)
}

/// The Théo1 double sum at one `m` by the cheaper exact method: the direct sum or the
/// block-FFT sum ([`blocks`]) of the residual plus the quadratic's part in closed form.
fn theo1_sum_single(d: &Detrended, m: usize) -> f64 {
    if prefer_blocks(d.r.len(), m) {
        let n = d.r.len();
        let z = d.r.iter().rev().copied();
        let (rp, zp) = (prefix_sums(d.r.iter().copied(), m), prefix_sums(z, m));
        blocks::bracket_sum(&d.r, m) + quadratic_part(d.p2, n, m, &rp, &zp)
    } else {
        theo1_sum_direct(d, m)
    }
}

/// Edge sums of one end of the record, swept over even `m` (see [`theo1_sums_sweep`]).
///
/// After [`EdgeSweep::advance`] to `m`: `pairs[ℓ] = Σ_{t=0}^{m−1−ℓ} (x_{t+ℓ} − x_t)²` (the lag-ℓ
/// structure function of the first `m` samples) and `tri[h − k] = Σ_{t<k} (x_{t+m−2k} − x_t)²`,
/// `h = m/2`, using `tri^{(m+2)}(k+1) = tri^{(m)}(k) + (x_{m−k} − x_k)²`: `O(m)` per step.
struct EdgeSweep<'a> {
    x: &'a [f64],
    m: usize,
    pairs: Vec<f64>,
    tri: Vec<f64>,
}

impl<'a> EdgeSweep<'a> {
    fn new(x: &'a [f64]) -> Self {
        EdgeSweep {
            x,
            m: 0,
            pairs: Vec::new(),
            tri: Vec::new(),
        }
    }

    /// From `m` to `m + 2`.
    ///
    /// Both loops run over contiguous slices (one of them reversed) without index
    /// arithmetic, so they vectorise; the two new samples `m`, `m + 1` update `pairs` in one
    /// pass (each entry still gets `+ d_m²` then `+ d_{m+1}²`, the order of one pass each).
    #[allow(clippy::inline_always)] // inlined into the dispatched `edge_series`
    #[inline(always)]
    fn advance(&mut self) {
        let (x, m) = (self.x, self.m);
        let h = m / 2;
        // tri[j] += (x_{m−k} − x_k)², k = h − j: x_{m−h..m} ascending against x_{1..=h} reversed.
        for ((v, &a), &b) in self
            .tri
            .iter_mut()
            .zip(&x[m - h..m])
            .zip(x[1..=h].iter().rev())
        {
            let d = a - b;
            *v += d * d;
        }
        self.tri.push((x[m] - x[0]).powi(2));
        // pairs[ℓ] += (x_m − x_{m−ℓ})², then += (x_{m+1} − x_{m+1−ℓ})², for ℓ = 1..m; the new
        // lags m and m + 1 start from zero.
        let (xm, xm1) = (x[m], x[m + 1]);
        if m == 0 {
            self.pairs.push(0.0);
        }
        for ((v, &a), &b) in self.pairs[1..]
            .iter_mut()
            .zip(x[..m].iter().rev())
            .zip(x[1..=m].iter().rev())
        {
            let d = xm - a;
            let e = xm1 - b;
            *v += d * d;
            *v += e * e;
        }
        if m > 0 {
            let (d, e) = (xm - x[0], xm1 - x[1]);
            self.pairs.push(d * d + e * e);
        }
        let d = xm1 - x[0];
        self.pairs.push(d * d);
        self.m = m + 2;
    }

    /// `Σ_{k=1}^{h} (1/k)·[pairs(k) + pairs(m − k) − tri(k)]` at the current `m`.
    #[allow(clippy::inline_always)] // inlined into the dispatched `edge_series`
    #[inline(always)]
    fn edge(&self, terms: &mut Vec<f64>) -> f64 {
        let (m, h) = (self.m, self.m / 2);
        terms.clear();
        terms.extend(
            (1..=h).map(|k| (self.pairs[k] + self.pairs[m - k] - self.tri[h - k]) / k as f64),
        );
        neumaier_lanes(terms)
    }
}

/// Théo1 double sums (as [`theo1_sum_direct`]) at every even `m` of the ascending list `ms`,
/// exactly, in `O(N·M + M²)` for `M = max(ms)` instead of `Σ (N − m)·m/2`.
///
/// With `a, b, c, d = x_i, x_{i+k}, x_{i+m−k}, x_{i+m}` the bracket is `(d − c) − (b − a)` and
/// polarisation gives `bracket² = (d−c)² + (b−a)² + (d−b)² + (c−a)² − (d−a)² − (c−b)²`: every
/// term is a squared increment (no products of samples, so no cancellation of `x²`-sized
/// numbers). Summed over `i`, each is a window of the lag-ℓ structure function
/// `SF(ℓ) = Σ_t (x_{t+ℓ} − x_t)²`, so
///
/// ```text
/// S(m) = Σ_k (1/k)·[2 SF(k) + 2 SF(m−k) − SF(m) − SF(m−2k)] − E(x, m) − E(x reversed, m),
/// E(x, m) = Σ_k (1/k)·[A_m(k) + A_m(m−k) − T_m(k)],
/// ```
///
/// `A_m(ℓ)` the lag-ℓ structure function of the first `m` samples and
/// `T_m(k) = Σ_{t<k} (x_{t+m−2k} − x_t)²` (the window parts outside the sum), both updated in
/// `O(m)` per step of `m` ([`EdgeSweep`]). The statistic is invariant to a linear trend but
/// not to a quadratic one, which would dominate the structure functions of drifting data; so
/// the sums run on the residual `r = x − q` of the least-squares quadratic `q` (exact split,
/// [`Detrended`]) and `q`'s part is added in closed form: its bracket is the
/// constant `β_k = 2·p2·k(m − k)`, giving `+ (N − m) Σ_k β_k²/k + 2 Σ_k (β_k/k)·Σ_i B_k(r, i)`,
/// where `Σ_i B_k(r, i)` telescopes to four edge windows of `r` of length `k`.
///
/// Measured agreement with the error-free literal sum (tests): max relative difference
/// 5.4e-13 on white FM, 1.3e-13 on random-walk FM, 1.0e-15 on drifting white FM.
fn theo1_sums_sweep(d: &Detrended, ms: &[usize]) -> Vec<f64> {
    let Some(&max_m) = ms.last() else {
        return Vec::new();
    };
    let (r, p2) = (&d.r[..], d.p2);
    let n = r.len();
    let z: Vec<f64> = r.iter().rev().copied().collect();
    let (sf, (head, tail)) = rayon::join(
        || structure_function(r, max_m),
        || rayon::join(|| edge_series(r, ms), || edge_series(&z, ms)),
    );
    let (rp, zp) = (
        prefix_sums(r.iter().copied(), max_m),
        prefix_sums(z.iter().copied(), max_m),
    );
    let inverse: Vec<f64> = (0..=max_m / 2).map(|k| 1.0 / k as f64).collect();
    ms.par_iter()
        .zip(head.par_iter().zip(&tail))
        .map(|(&m, (&eh, &et))| {
            let h = m / 2;
            let mut terms = Vec::with_capacity(3 * h + 2);
            for (k, &w) in (1..=h).zip(&inverse[1..]) {
                terms.push(w * (2.0 * sf[k] + 2.0 * sf[m - k]));
                terms.push(-w * (sf[m] + sf[m - 2 * k]));
            }
            terms.push(-eh);
            terms.push(-et);
            terms.extend(quadratic_terms(p2, n, m, &rp, &zp));
            neumaier_lanes(&terms)
        })
        .collect()
}

/// `E(x, m)` of [`theo1_sums_sweep`] at each (ascending, even) `m` of `ms`.
///
/// Dispatched by `pulp` so that [`EdgeSweep::advance`]'s loops are compiled for the CPU
/// (AVX2 where available; same roundings in every variant, no fused multiply-add).
fn edge_series(x: &[f64], ms: &[usize]) -> Vec<f64> {
    crate::simd::arch().dispatch(
        #[inline(always)]
        || {
            let mut sweep = EdgeSweep::new(x);
            let mut terms = Vec::new();
            ms.iter()
                .map(|&m| {
                    while sweep.m < m {
                        sweep.advance();
                    }
                    sweep.edge(&mut terms)
                })
                .collect()
        },
    )
}

/// Largest even `m` of Théo1 on `n_angle` samples (`m ≤ N − 1`).
pub fn max_factor(n_angle: usize) -> usize {
    let m = n_angle.saturating_sub(1);
    m - m % 2
}

fn check_factor(n: usize, m: usize) -> Result<()> {
    if m < 2 || m % 2 != 0 {
        return Err(Error::invalid(
            "taus",
            format!("Théo1 needs an even averaging factor m >= 2 (τ = 0.75·m·t0), got m = {m}"),
        ));
    }
    if m > max_factor(n) {
        return Err(Error::TooShort {
            name: "data",
            needed: m + 1,
            got: n,
        });
    }
    Ok(())
}

/// Théo1 variance at even averaging factor `m` (τ = 0.75·m·t0) from the angle series `x`
/// (direct sum of `(N − m)·m/2` brackets for small `m`, block-FFT sum in `O(N log m)` for
/// large `m`; see the module notes).
///
/// Returns `(variance, n_terms)` with `n_terms = N − m` outer terms.
pub fn theo1(x: &[f64], t0: f64, m: usize) -> Result<(f64, usize)> {
    let n = x.len();
    check_factor(n, m)?;
    let tau = m as f64 * t0;
    let count = n - m;
    Ok((
        theo1_sum_single(&detrend(x), m) / (0.75 * count as f64 * tau * tau),
        count,
    ))
}

/// Théo1 at each even averaging factor of `ms` (any order), as [`theo1`].
///
/// Chooses, from `N` and the set `ms` alone, the cheaper exact way: each `m` on its own (the
/// direct sum for small `m`, the block-FFT sum for large `m`; best for sparse sets such as
/// octaves) or the structure-function sweep (`≈ N·M + 2M²` for `M = max m`, best for dense
/// sets such as ThéoBR's bias ratio or all τ; see `theo1_sums_sweep`). They agree to ≈ 1e-12
/// relative (measured max 5.4e-13), so a value can differ in the last digits with the
/// requested set, never with threads or chunking.
pub fn theo1_many(x: &[f64], t0: f64, ms: &[usize]) -> Result<Vec<(f64, usize)>> {
    let n = x.len();
    for &m in ms {
        check_factor(n, m)?;
    }
    let Some(&max_m) = ms.iter().max() else {
        return Ok(Vec::new());
    };
    let single: f64 = ms
        .iter()
        .map(|&m| direct_cost(n, m).min(blocks::cost(n, m)))
        .sum();
    // The sweep's N·M + 2M² squared increments cost about as much as as many brackets.
    let sweep = BRACKET_COST * (n as f64 * max_m as f64 + 2.0 * (max_m as f64).powi(2));
    let norm = |m: usize, sum: f64| {
        let tau = m as f64 * t0;
        let count = n - m;
        (sum / (0.75 * count as f64 * tau * tau), count)
    };
    let detrended = detrend(x);
    if sweep < single {
        let mut sorted = ms.to_vec();
        sorted.sort_unstable();
        sorted.dedup();
        let sums = theo1_sums_sweep(&detrended, &sorted);
        Ok(ms
            .iter()
            .map(|&m| {
                let at = sorted.binary_search(&m).unwrap_or_default();
                norm(m, sums[at])
            })
            .collect())
    } else {
        Ok(ms
            .par_iter()
            .with_max_len(1)
            .map(|&m| norm(m, theo1_sum_single(&detrended, m)))
            .collect())
    }
}

/// Number of terms `n + 1` of the ThéoBR bias ratio on `n_angle` samples (`n = ⌊N/30 − 3⌋`),
/// or `None` when the record is too short (N < 90).
pub fn bias_terms(n_angle: usize) -> Option<usize> {
    let n = (n_angle as f64 / 30.0 - 3.0).floor();
    if n < 0.0 { None } else { Some(n as usize + 1) }
}

/// Smallest record for ThéoBR / ThéoH.
pub const MIN_SAMPLES_BR: usize = 90;

/// ThéoBR bias ratio `1/(n+1) Σ_i AVAR(9 + 3i)/Théo1(12 + 4i)` of the angle series `x`.
pub fn bias_ratio(x: &[f64], t0: f64) -> Result<f64> {
    let terms = bias_terms(x.len()).ok_or(Error::TooShort {
        name: "data",
        needed: MIN_SAMPLES_BR,
        got: x.len(),
    })?;
    let theo_ms: Vec<usize> = (0..terms).map(|i| 12 + 4 * i).collect();
    let theos = theo1_many(x, t0, &theo_ms)?;
    // The fused all-τ pass: the same bits as `variance` at each factor, one cache-blocked
    // walk over the record instead of one pass per factor.
    let avar_ms: Vec<usize> = (0..terms).map(|i| 9 + 3 * i).collect();
    let (mut avars, mut counts) = (vec![0.0; terms], vec![0; terms]);
    super::variances_into(
        x,
        t0,
        &avar_ms,
        super::Estimator::Overlapping,
        &mut avars,
        &mut counts,
    )?;
    let vals: Vec<f64> = avars.iter().zip(theos).map(|(a, (th, _))| a / th).collect();
    let ratio = validate::neumaier_sum(vals) / terms as f64;
    if ratio.is_finite() {
        Ok(ratio)
    } else {
        Err(Error::invalid(
            "data",
            "ThéoBR bias ratio undefined: Théo1 is zero at short τ (constant or linear data)",
        ))
    }
}

/// Break point of ThéoH in units of t0: the largest τ/t0 ≤ 10 % of the record `(N − 1)`.
pub fn theoh_break(n_angle: usize) -> f64 {
    (0.1 * n_angle.saturating_sub(1) as f64).floor().max(1.0)
}

#[cfg(test)]
#[cfg(test)]
mod tests_support {
    use super::{two_sum, validate};
    use crate::random::normal_vec;

    pub(super) fn cumsum(v: &[f64]) -> Vec<f64> {
        let mut acc = 0.0;
        v.iter()
            .map(|&d| {
                acc += d;
                acc
            })
            .collect()
    }

    /// White FM: the angle is a random walk.
    pub(super) fn white_fm(n: usize, seed: u64) -> Vec<f64> {
        cumsum(&normal_vec(n, seed))
    }

    /// Random-walk FM: the angle is an integrated random walk.
    pub(super) fn random_walk_fm(n: usize, seed: u64) -> Vec<f64> {
        cumsum(&white_fm(n, seed))
    }

    /// White FM under an offset, a rate bias 3e6 times its step noise (invisible to Théo1, but
    /// it makes `x` ≈ 1e10 and every increment ≈ 3e6·k) and a rate ramp whose brackets are
    /// comparable to the noise's at m ≈ 100.
    pub(super) fn drifting(n: usize, seed: u64) -> Vec<f64> {
        white_fm(n, seed)
            .iter()
            .enumerate()
            .map(|(t, &v)| {
                let t = t as f64;
                v + 3e6 * t + 1e-3 * t * t + 2.5e9
            })
            .collect()
    }

    /// The double sum with error-free brackets: each difference of samples and the difference
    /// of the two increments carry their TwoSum rounding error along, the squares are summed
    /// with compensation. The literal reference for both methods.
    pub(super) fn error_free_sum(x: &[f64], m: usize) -> f64 {
        let n = x.len();
        let per_k = (1..=m / 2).map(|k| {
            validate::neumaier_sum((0..n - m).map(|i| {
                let (ab, e1) = two_sum(x[i], -x[i + k]);
                let (cd, e2) = two_sum(x[i + m - k], -x[i + m]);
                let (b, e3) = two_sum(ab, -cd);
                let t = b + (e3 + (e1 - e2));
                t * t
            })) / k as f64
        });
        validate::neumaier_sum(per_k)
    }
}

#[cfg(test)]
mod tests {
    use super::tests_support::*;
    use super::*;

    /// SP 1065 eq. 30 literally.
    fn naive(x: &[f64], t0: f64, m: usize) -> f64 {
        let n = x.len();
        let h = m / 2;
        let mut s = 0.0;
        for i in 0..n - m {
            for d in 0..h {
                let t = x[i] - x[i + h - d] + x[i + m] - x[i + d + h];
                s += t * t / (h - d) as f64;
            }
        }
        s / (0.75 * (n - m) as f64 * (m as f64 * t0).powi(2))
    }

    fn max_rel(a: &[f64], b: &[f64]) -> f64 {
        a.iter()
            .zip(b)
            .map(|(u, v)| ((u - v) / v).abs())
            .fold(0.0, f64::max)
    }

    #[test]
    fn theo1_equals_definition() {
        let x = white_fm(301, 3);
        for m in [2usize, 4, 10, 64, 150, 300] {
            let (v, n) = theo1(&x, 0.5, m).unwrap();
            let r = naive(&x, 0.5, m);
            assert_eq!(n, 301 - m);
            // 1e-12: same terms, summed in a different order.
            assert!((v - r).abs() <= 1e-12 * r, "m={m} {v} {r}");
        }
    }

    /// Max relative difference of the sweep and of the direct sum to [`error_free_sum`].
    fn errors(x: &[f64], ms: &[usize]) -> (f64, f64) {
        let d = detrend(x);
        let reference: Vec<f64> = ms.iter().map(|&m| error_free_sum(x, m)).collect();
        let sweep = theo1_sums_sweep(&d, ms);
        let direct: Vec<f64> = ms.iter().map(|&m| theo1_sum_direct(&d, m)).collect();
        (max_rel(&sweep, &reference), max_rel(&direct, &reference))
    }

    /// Both methods against the error-free sum at every even `m` (all τ), on the three kinds
    /// of data where an expansion into products would lose digits. Measured max relative
    /// difference (this build), sweep / direct: white FM 1.3e-14 / 2.2e-16, random-walk FM
    /// 1.3e-13 / 3.5e-15, drifting 7.6e-16 / 1.0e-15 (a direct sum on the raw drifting `x`
    /// was measured 2.2e-11 off). Bound 1e-10: the sweep's sums are of non-negative squared increments
    /// (≈ 256 ε each) and the final combination cancels by ≈ N/m on random-walk FM.
    #[test]
    fn sweep_and_direct_are_exact_at_every_factor() {
        let n = 1201;
        let ms: Vec<usize> = (1..=max_factor(n) / 2).map(|h| 2 * h).collect();
        for (name, x) in [
            ("white FM", white_fm(n, 11)),
            ("random-walk FM", random_walk_fm(n, 12)),
            ("drifting", drifting(n, 13)),
        ] {
            let (sweep, direct) = errors(&x, &ms);
            eprintln!("{name}: max rel sweep {sweep:.1e} direct {direct:.1e}");
            assert!(
                sweep <= 1e-10 && direct <= 1e-10,
                "{name}: {sweep} {direct}"
            );
        }
    }

    /// Longer records (even and odd N): ThéoBR's factors (every fifth) and the extremes.
    /// Measured max relative difference, sweep / direct: 5.4e-13 / 1.2e-14.
    #[test]
    fn sweep_and_direct_are_exact_on_long_records() {
        for n in [6000usize, 6001] {
            let mut ms: Vec<usize> = (0..n / 30 - 2).step_by(5).map(|i| 12 + 4 * i).collect();
            ms.extend([2, 4, 1024, 2048, max_factor(n) - 2, max_factor(n)]);
            ms.sort_unstable();
            ms.dedup();
            for (name, x) in [
                ("white FM", white_fm(n, 21)),
                ("random-walk FM", random_walk_fm(n, 22)),
                ("drifting", drifting(n, 23)),
            ] {
                let (sweep, direct) = errors(&x, &ms);
                eprintln!("N={n} {name}: max rel sweep {sweep:.1e} direct {direct:.1e}");
                assert!(
                    sweep <= 1e-10 && direct <= 1e-10,
                    "N={n} {name}: {sweep} {direct}"
                );
            }
        }
    }

    /// One pass per lag (the unblocked structure function): the same per-lag blocks of
    /// [`SF_BLOCK`] terms, eight-lane sums, combined by [`validate::neumaier_sum`] in order.
    fn structure_function_per_lag(r: &[f64], max_lag: usize) -> Vec<f64> {
        let n = r.len();
        let mut sf = vec![0.0];
        sf.extend((1..=max_lag).map(|lag| {
            let count = n - lag;
            validate::neumaier_sum(
                r[..count]
                    .chunks(SF_BLOCK)
                    .zip(r[lag..].chunks(SF_BLOCK))
                    .map(|(a, b)| squared_increments(a, b)),
            )
        }));
        sf
    }

    /// The lag-blocked structure function equals one pass per lag bit for bit, and the
    /// error-free sum (TwoSum differences, compensated squares) to ≈ 256 ε, for lags spanning
    /// several lag groups and record blocks with ragged ends (N not a multiple of the block,
    /// last group partial, lags whose term count ends inside / on a block boundary); and it
    /// is bit-identical with 1 and 3 threads.
    #[test]
    fn blocked_structure_function_equals_per_lag_passes() {
        let n = 3 * SF_BLOCK + 517;
        let max_lag = 3 * SF_LAGS + 29 + SF_BLOCK;
        let mut worst = 0.0_f64;
        for (name, x) in [("white FM", white_fm(n, 41)), ("drifting", drifting(n, 42))] {
            let r = detrend(&x).r;
            let per_lag = structure_function_per_lag(&r, max_lag);
            let run = |threads: usize| {
                rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .unwrap()
                    .install(|| structure_function(&r, max_lag))
            };
            let (one, three) = (run(1), run(3));
            assert_eq!(one.len(), max_lag + 1);
            for lag in 0..=max_lag {
                assert_eq!(
                    one[lag].to_bits(),
                    per_lag[lag].to_bits(),
                    "{name} lag {lag}"
                );
                assert_eq!(one[lag].to_bits(), three[lag].to_bits(), "{name} lag {lag}");
            }
            for lag in 1..=max_lag {
                let exact = validate::neumaier_sum((0..n - lag).map(|t| {
                    let (d, e) = two_sum(r[t + lag], -r[t]);
                    let (s, s_lo) = two_prod(d, d);
                    s + (s_lo + 2.0 * d * e)
                }));
                worst = worst.max(((one[lag] - exact) / exact).abs());
            }
        }
        eprintln!("blocked structure function: max rel to error-free {worst:.1e}");
        // 1e-12: ≈ 256 ε bound of eight-lane block sums of non-negative terms.
        assert!(worst <= 1e-12, "{worst}");
    }

    /// [`EdgeSweep`]'s slice loops make the roundings of the index form of its recurrences
    /// (`tri` from `x_{m−k} − x_k`, `pairs` from one pass per new sample), bit for bit, and
    /// `pairs` is the structure function of the first `m` samples.
    #[test]
    fn edge_sweep_equals_index_form() {
        let x = white_fm(301, 51);
        let mut sweep = EdgeSweep::new(&x);
        let (mut pairs, mut tri): (Vec<f64>, Vec<f64>) = (Vec::new(), Vec::new());
        for m in (0..290).step_by(2) {
            let h = m / 2;
            for (j, v) in tri.iter_mut().enumerate() {
                let k = h - j;
                let d = x[m - k] - x[k];
                *v += d * d;
            }
            tri.push((x[m] - x[0]).powi(2));
            for new in [m, m + 1] {
                pairs.push(0.0);
                for (lag, v) in pairs.iter_mut().enumerate().skip(1) {
                    let d = x[new] - x[new - lag];
                    *v += d * d;
                }
            }
            sweep.advance();
            assert_eq!(sweep.m, m + 2);
            let bits = |v: &[f64]| v.iter().map(|a| a.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&sweep.pairs), bits(&pairs), "m={m}");
            assert_eq!(bits(&sweep.tri), bits(&tri), "m={m}");
        }
        let m = sweep.m;
        for lag in 1..m {
            let direct: f64 = (0..m - lag).map(|t| (x[t + lag] - x[t]).powi(2)).sum();
            // 1e-12: the same squares, accumulated in another order.
            assert!(
                (sweep.pairs[lag] - direct).abs() <= 1e-12 * direct,
                "lag {lag}"
            );
        }
    }

    #[test]
    fn many_matches_single_in_any_order() {
        let x = random_walk_fm(900, 5);
        // Dense (sweep) and sparse (direct) sets, unsorted, with a repeat.
        for ms in [
            (1..=400).map(|h| 2 * h).rev().collect::<Vec<_>>(),
            vec![898, 2, 64, 64],
        ] {
            let many = theo1_many(&x, 0.25, &ms).unwrap();
            for (&m, &(v, cnt)) in ms.iter().zip(&many) {
                let (r, rc) = theo1(&x, 0.25, m).unwrap();
                assert_eq!(cnt, rc);
                assert!((v - r).abs() <= 1e-10 * r, "m={m} {v} {r}");
            }
        }
        assert!(theo1_many(&x, 0.25, &[]).unwrap().is_empty());
        assert!(theo1_many(&x, 0.25, &[4, 5]).is_err());
        assert!(theo1_many(&x, 0.25, &[4, 900]).is_err());
    }

    /// A single large τ goes through the block-FFT sum and still equals the definition.
    #[test]
    fn single_large_factor_uses_blocks_and_equals_definition() {
        let n = 20_001;
        let x = random_walk_fm(n, 31);
        for m in [1024usize, 16_384] {
            assert!(prefer_blocks(n, m), "m={m} must exercise the blocks");
            let (v, _) = theo1(&x, 0.1, m).unwrap();
            let reference =
                error_free_sum(&x, m) / (0.75 * (n - m) as f64 * (m as f64 * 0.1).powi(2));
            // 1e-11: the blocks' a-priori tolerance (measured ≈ 1e-14).
            assert!(
                (v - reference).abs() <= 1e-11 * reference,
                "m={m} {v} {reference}"
            );
        }
        assert!(!prefer_blocks(n, 16), "small m stays direct");
    }

    #[test]
    fn theo1_rejects_odd_and_long() {
        let x = white_fm(50, 1);
        assert!(theo1(&x, 1.0, 3).is_err());
        assert!(theo1(&x, 1.0, 0).is_err());
        assert!(theo1(&x, 1.0, 48).is_ok());
        assert!(theo1(&x, 1.0, 50).is_err());
    }

    #[test]
    fn bias_ratio_needs_record() {
        assert!(bias_ratio(&white_fm(89, 2), 1.0).is_err());
        assert!(bias_ratio(&white_fm(90, 2), 1.0).is_ok());
        let r = bias_ratio(&white_fm(2000, 2), 1.0).unwrap();
        assert!(r > 0.3 && r < 3.0, "{r}");
    }

    /// The bias ratio from the sweep equals the one from direct Théo1 sums (SP 1065 eq. 31).
    #[test]
    fn bias_ratio_matches_direct_definition() {
        let x = random_walk_fm(3000, 8);
        let terms = bias_terms(x.len()).unwrap();
        let direct = validate::neumaier_sum((0..terms).map(|i| {
            let (a, _) =
                super::super::variance(&x, 1.0, 9 + 3 * i, super::super::Estimator::Overlapping)
                    .unwrap();
            a / theo1(&x, 1.0, 12 + 4 * i).unwrap().0
        })) / terms as f64;
        let fast = bias_ratio(&x, 1.0).unwrap();
        assert!((fast - direct).abs() <= 1e-10 * direct, "{fast} {direct}");
    }
}
