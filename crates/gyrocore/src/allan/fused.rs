//! Cache-blocked evaluation of many overlapping difference sums in one pass over the data.
//!
//! For a set of averaging factors `m_j`, the overlapping Allan sum `Σ_k (x_{k+2m} − 2x_{k+m} + x_k)²`
//! reads `x` at the offsets `0, m_j, 2m_j`. Evaluated τ by τ, every τ streams the whole series
//! from memory (three times for lags beyond the cache). Here the index range is cut into blocks
//! of [`BLOCK`] samples and every τ is accumulated block by block, so each region of `x` is
//! fetched from memory once per block and reused from cache by all τ that touch it: for
//! octave τ the traffic drops from about 3 passes per τ to about one per distinct lag. Blocks
//! are grouped into chunks processed in parallel; chunk sums are combined in a fixed order with
//! compensated addition, so results do not depend on the number of threads.

use rayon::prelude::*;

use super::Progress;

const BLOCK: usize = 1024;
/// Terms per parallel work item (a multiple of [`BLOCK`]); chunk sums are combined in order.
pub(crate) const CHUNK: usize = BLOCK * 256;
const LANES: usize = 8;

/// Which finite difference of the angle series is squared and summed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Difference {
    /// `x_{k+2m} − 2x_{k+m} + x_k` (Allan).
    Second,
    /// `x_{k+3m} − 3x_{k+2m} + 3x_{k+m} − x_k` (Hadamard).
    Third,
}

impl Difference {
    fn span(self) -> usize {
        match self {
            Difference::Second => 2,
            Difference::Third => 3,
        }
    }
}

/// `Σ_k (c_k − 2b_k + a_k)²` over equally long slices, in `LANES` lanes plus a tail (the
/// fixed order of every addition makes the result independent of the CPU's vector width).
// inline(always): must be inlined into the feature-specific body the dispatcher selects.
#[allow(clippy::inline_always)]
#[inline(always)]
fn second_sum(a: &[f64], b: &[f64], c: &[f64]) -> f64 {
    let count = a.len();
    let mut lanes = [0.0_f64; LANES];
    let mut tail = 0.0_f64;
    let whole = count - count % LANES;
    for ((ca, cb), cc) in a[..whole]
        .chunks_exact(LANES)
        .zip(b[..whole].chunks_exact(LANES))
        .zip(c[..whole].chunks_exact(LANES))
    {
        for l in 0..LANES {
            let d = cc[l] - 2.0 * cb[l] + ca[l];
            lanes[l] += d * d;
        }
    }
    for k in whole..count {
        let d = c[k] - 2.0 * b[k] + a[k];
        tail += d * d;
    }
    lanes.iter().sum::<f64>() + tail
}

// inline(always): must be inlined into the feature-specific body the dispatcher selects.
#[allow(clippy::inline_always)]
#[inline(always)]
fn block_sum(x: &[f64], m: usize, start: usize, end: usize, diff: Difference) -> f64 {
    let count = end - start;
    match diff {
        Difference::Second => second_sum(
            &x[start..end],
            &x[start + m..end + m],
            &x[start + 2 * m..end + 2 * m],
        ),
        Difference::Third => {
            let mut lanes = [0.0_f64; LANES];
            let mut tail = 0.0_f64;
            let a = &x[start..end];
            let b = &x[start + m..end + m];
            let c = &x[start + 2 * m..end + 2 * m];
            let e = &x[start + 3 * m..end + 3 * m];
            let whole = count - count % LANES;
            for (((ca, cb), cc), ce) in a[..whole]
                .chunks_exact(LANES)
                .zip(b[..whole].chunks_exact(LANES))
                .zip(c[..whole].chunks_exact(LANES))
                .zip(e[..whole].chunks_exact(LANES))
            {
                for l in 0..LANES {
                    let d = ce[l] - 3.0 * cc[l] + 3.0 * cb[l] - ca[l];
                    lanes[l] += d * d;
                }
            }
            for k in whole..count {
                let d = e[k] - 3.0 * c[k] + 3.0 * b[k] - a[k];
                tail += d * d;
            }
            lanes.iter().sum::<f64>() + tail
        }
    }
}

/// One chunk of one τ of the overlapping Allan sum from three windows of the angle series
/// (`a = x[c0..c0+len]`, `b` and `c` the same range shifted by m and 2m), block by block
/// exactly as [`difference_sums`] does it: a chunk streamed from disk gives the same bits.
pub(crate) fn second_chunk_sum(a: &[f64], b: &[f64], c: &[f64]) -> f64 {
    struct Windows<'a>(&'a [f64], &'a [f64], &'a [f64]);
    impl pulp::WithSimd for Windows<'_> {
        type Output = f64;
        #[allow(clippy::inline_always)] // pulp's contract
        #[inline(always)]
        fn with_simd<S: pulp::Simd>(self, _simd: S) -> f64 {
            let Windows(a, b, c) = self;
            let mut sum = 0.0_f64;
            let mut o = 0;
            while o < a.len() {
                let e = (o + BLOCK).min(a.len());
                sum += second_sum(&a[o..e], &b[o..e], &c[o..e]);
                o = e;
            }
            sum
        }
    }
    pulp::Arch::new().dispatch(Windows(a, b, c))
}

/// The block loop of one chunk, as a `pulp` operation so that it is compiled (fully inlined)
/// inside the CPU-feature-specific function the dispatcher selects.
struct ChunkSums<'a> {
    x: &'a [f64],
    ms: &'a [usize],
    terms: &'a [usize],
    range: (usize, usize),
    diff: Difference,
    sums: &'a mut [f64],
}

impl pulp::WithSimd for ChunkSums<'_> {
    type Output = ();

    #[allow(clippy::inline_always)] // pulp's contract: inlined into the dispatched function
    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) {
        let (c0, c1) = self.range;
        let mut b0 = c0;
        while b0 < c1 {
            let b1 = (b0 + BLOCK).min(c1);
            for (j, (&m, &t)) in self.ms.iter().zip(self.terms).enumerate() {
                let end = b1.min(t);
                if b0 < end {
                    self.sums[j] += block_sum(self.x, m, b0, end, self.diff);
                }
            }
            b0 = b1;
        }
    }
}

/// `Σ_{k < n_terms(m)} diff(x, k, m)²` for every `m` in `ms`, with `n_terms = len − span·m`.
///
/// Every `m` must satisfy `span·m < x.len()` (checked by the caller). `weight` progress units
/// are reported as chunks complete; once cancelled, the remaining chunks are skipped (the
/// caller checks [`Progress::check`]).
pub(crate) fn difference_sums(
    x: &[f64],
    ms: &[usize],
    diff: Difference,
    progress: &Progress<'_>,
    weight: f64,
) -> Vec<f64> {
    let span = diff.span();
    let terms: Vec<usize> = ms.iter().map(|&m| x.len() - span * m).collect();
    let longest = terms.iter().copied().max().unwrap_or(0);
    let chunk_starts: Vec<usize> = (0..longest).step_by(CHUNK).collect();
    // Short records have few chunks: then the τ are also dealt round-robin into groups so that
    // every thread has work. Each τ's sum over a chunk is the same whichever group computes
    // it, so the grouping (which depends on the thread count) never changes a result.
    let want = 4 * rayon::current_num_threads();
    let groups = want
        .div_ceil(chunk_starts.len().max(1))
        .clamp(1, ms.len().max(1));
    let items: Vec<(usize, usize)> = chunk_starts
        .iter()
        .flat_map(|&c0| (0..groups).map(move |g| (c0, g)))
        .collect();
    let stage = progress.stage(weight, items.len());
    let partials: Vec<(usize, usize, Vec<f64>)> = items
        .par_iter()
        .map(|&(c0, g)| {
            let c1 = (c0 + CHUNK).min(longest);
            let sel: Vec<usize> = (g..ms.len()).step_by(groups).collect();
            let sub_ms: Vec<usize> = sel.iter().map(|&j| ms[j]).collect();
            let sub_terms: Vec<usize> = sel.iter().map(|&j| terms[j]).collect();
            let mut sums = vec![0.0_f64; sel.len()];
            if stage.is_cancelled() {
                return (c0, g, sums);
            }
            // Runtime CPU dispatch (AVX2 where available): the lane loops vectorise 4-wide
            // instead of SSE2's 2-wide. The lane layout fixes the order of every addition and
            // nothing is fused, so the result is bit-identical on every CPU.
            pulp::Arch::new().dispatch(ChunkSums {
                x,
                ms: &sub_ms,
                terms: &sub_terms,
                range: (c0, c1),
                diff,
                sums: &mut sums,
            });
            stage.item_done();
            (c0, g, sums)
        })
        .collect();
    // Chunk sums per τ, in chunk order, combined with compensated addition.
    let mut per_tau: Vec<Vec<f64>> = vec![Vec::with_capacity(chunk_starts.len()); ms.len()];
    for (_, g, sums) in &partials {
        for (i, s) in sums.iter().enumerate() {
            per_tau[g + i * groups].push(*s);
        }
    }
    per_tau
        .iter()
        .map(|chunks| crate::validate::neumaier_sum(chunks.iter().copied()))
        .collect()
}
