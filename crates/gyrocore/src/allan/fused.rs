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
    crate::simd::arch().dispatch(Windows(a, b, c))
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

/// Smallest averaging factor computed on a lattice (see [`difference_sums`]); smaller lags are
/// served from cache by the block pass.
const FAR: usize = 1 << 15;
/// Largest `q = m / base` in one lattice group: the `span·MAX_Q + 1` windows that one lattice
/// walk keeps alive (≈ 2 MiB per thread for the Allan difference) stay in the last-level cache,
/// and octave factors from `FAR` to `2^22` share one lattice.
const MAX_Q: usize = 128;

/// The far averaging factors that share one lattice: `m_j = q_j·base`, `q_j ≤ MAX_Q`.
struct Lattice {
    base: usize,
    /// Indices into `ms`.
    members: Vec<usize>,
}

/// Groups the factors that are multiples of [`BLOCK`] and at least [`FAR`] into lattices
/// (greedily from the smallest), returning them and the indices of all other factors.
fn plan(ms: &[usize]) -> (Vec<usize>, Vec<Lattice>) {
    let mut near = Vec::new();
    let mut far: Vec<usize> = Vec::new();
    for (j, &m) in ms.iter().enumerate() {
        if m >= FAR && m % BLOCK == 0 {
            far.push(j);
        } else {
            near.push(j);
        }
    }
    far.sort_by_key(|&j| ms[j]);
    let mut lattices: Vec<Lattice> = Vec::new();
    let mut left = far;
    while let Some(&first) = left.first() {
        let base = ms[first];
        let (members, rest): (Vec<usize>, Vec<usize>) = left
            .iter()
            .partition(|&&j| ms[j] % base == 0 && ms[j] / base <= MAX_Q);
        lattices.push(Lattice { base, members });
        left = rest;
    }
    (near, lattices)
}

/// One walk of a lattice: the windows `x[s·base + r0 ..][..BLOCK]`, `s = 0, 1, …`, and for every
/// member the sum of each [`BLOCK`] of terms starting there (`sums[i][s]`, member `i`). A
/// window is fetched from memory once, at its largest offset, and reused from cache by the
/// smaller offsets of the following steps.
struct LatticeWalk<'a> {
    x: &'a [f64],
    ms: &'a [usize],
    terms: &'a [usize],
    base: usize,
    r0: usize,
    diff: Difference,
    sums: &'a mut [Vec<f64>],
}

impl pulp::WithSimd for LatticeWalk<'_> {
    type Output = ();

    #[allow(clippy::inline_always)] // pulp's contract: inlined into the dispatched function
    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) {
        let longest = self.terms.iter().copied().max().unwrap_or(0);
        let mut p = self.r0;
        while p < longest {
            for ((&m, &t), out) in self.ms.iter().zip(self.terms).zip(self.sums.iter_mut()) {
                if p < t {
                    out.push(block_sum(self.x, m, p, (p + BLOCK).min(t), self.diff));
                }
            }
            p += self.base;
        }
    }
}

/// `Σ_{k < n_terms(m)} diff(x, k, m)²` for every `m` in `ms`, with `n_terms = len − span·m`.
///
/// Every `m` must satisfy `span·m < x.len()` (checked by the caller). `weight` progress units
/// are reported as work items complete; once cancelled, the remaining items are skipped (the
/// caller checks [`Progress::check`]).
///
/// Every sum is defined the same way, whatever the traversal: the terms are cut into blocks of
/// [`BLOCK`] (block sums in [`LANES`] lanes), the block sums of each chunk of [`CHUNK`] terms
/// are added in order from zero, and the chunk sums are combined with compensated addition.
/// Two traversals produce these numbers:
///
/// * the **block pass** (small factors): chunks in parallel, and inside a chunk every factor
///   block by block, so that each region of `x` is fetched once and reused from cache by all
///   factors whose lags stay within the cache;
/// * **lattices** (factors `m = q·base`, `m ≥ FAR`, multiples of `BLOCK`, `q ≤ MAX_Q`): a
///   lag of `m` is too far for reuse in the block pass (each far factor would stream `x` again
///   from memory at its own two offsets). A lattice walks the windows `s·base + r0` in order of
///   `s`, so the windows at offsets `q·base` and `2q·base` of one step are those of earlier
///   steps still in cache: `x` is read from memory about once per lattice (octave factors up
///   to `2^22` form one lattice). Walks (one per `r0`) run in parallel and store block sums,
///   which are then added chunk by chunk exactly as the block pass adds them.
///
/// The result is bit-identical to a τ-by-τ evaluation of the same definition and does not
/// depend on the number of threads.
pub(crate) fn difference_sums(
    x: &[f64],
    ms: &[usize],
    diff: Difference,
    progress: &Progress<'_>,
    weight: f64,
) -> Vec<f64> {
    let span = diff.span();
    let (near, lattices) = plan(ms);
    let near_ms: Vec<usize> = near.iter().map(|&j| ms[j]).collect();
    let walks: usize = lattices.iter().map(|l| l.base / BLOCK).sum();
    let near_sums = block_pass(x, &near_ms, diff, progress, weight, walks);
    let mut out = vec![0.0; ms.len()];
    for (&j, s) in near.iter().zip(near_sums) {
        out[j] = s;
    }
    let per_walk = weight / (near_ms.len() + walks).max(1) as f64;
    for lattice in &lattices {
        let l_ms: Vec<usize> = lattice.members.iter().map(|&j| ms[j]).collect();
        let l_terms: Vec<usize> = l_ms.iter().map(|&m| x.len() - span * m).collect();
        let stage = progress.stage(
            per_walk * (lattice.base / BLOCK) as f64,
            lattice.base / BLOCK,
        );
        let walks: Vec<Vec<Vec<f64>>> = (0..lattice.base)
            .step_by(BLOCK)
            .collect::<Vec<_>>()
            .par_iter()
            .with_max_len(1)
            .map(|&r0| {
                let mut sums: Vec<Vec<f64>> = l_terms
                    .iter()
                    .map(|&t| Vec::with_capacity(t.div_ceil(lattice.base)))
                    .collect();
                if stage.is_cancelled() {
                    return sums;
                }
                crate::simd::arch().dispatch(LatticeWalk {
                    x,
                    ms: &l_ms,
                    terms: &l_terms,
                    base: lattice.base,
                    r0,
                    diff,
                    sums: &mut sums,
                });
                stage.item_done();
                sums
            })
            .collect();
        if stage.is_cancelled() {
            continue;
        }
        let stride = lattice.base / BLOCK;
        for (i, &j) in lattice.members.iter().enumerate() {
            let blocks = l_terms[i].div_ceil(BLOCK);
            // Block q = s·stride + w was computed by walk w at step s.
            let chunk_sums = (0..blocks).step_by(CHUNK / BLOCK).map(|q0| {
                let mut sum = 0.0_f64;
                for q in q0..(q0 + CHUNK / BLOCK).min(blocks) {
                    sum += walks[q % stride][i][q / stride];
                }
                sum
            });
            out[j] = crate::validate::neumaier_sum(chunk_sums);
        }
    }
    out
}

/// The block pass of [`difference_sums`] for the factors `ms`; `extra_items` later work items
/// share `weight` with it.
fn block_pass(
    x: &[f64],
    ms: &[usize],
    diff: Difference,
    progress: &Progress<'_>,
    weight: f64,
    extra_items: usize,
) -> Vec<f64> {
    if ms.is_empty() {
        return Vec::new();
    }
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
    let share = ms.len() as f64 / (ms.len() + extra_items) as f64;
    let stage = progress.stage(weight * share, items.len());
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
            crate::simd::arch().dispatch(ChunkSums {
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The definition of [`difference_sums`] evaluated τ by τ, chunk by chunk, block by block.
    fn reference(x: &[f64], m: usize, diff: Difference) -> f64 {
        let t = x.len() - diff.span() * m;
        let chunks = (0..t).step_by(CHUNK).map(|c0| {
            let mut sum = 0.0;
            for b0 in (c0..(c0 + CHUNK).min(t)).step_by(BLOCK) {
                sum += block_sum(x, m, b0, (b0 + BLOCK).min(t).min(c0 + CHUNK), diff);
            }
            sum
        });
        crate::validate::neumaier_sum(chunks)
    }

    #[test]
    fn lattices_and_block_pass_equal_the_definition() {
        // A random walk (cumulative sum of normal steps) long enough for two lattices.
        let mut level = 0.0;
        let x: Vec<f64> = crate::random::normal_vec(700_001, 21)
            .into_iter()
            .map(|z| {
                level += z;
                level
            })
            .collect();
        let ms = [
            1, 3, 1000, 1024, 4096, 8192, 9216, 16384, 24576, 32768, 65536, 131072, 139264, 196608,
            229376,
        ];
        let (near, lattices) = plan(&ms);
        assert!(lattices.len() >= 2 && !near.is_empty());
        for diff in [Difference::Second, Difference::Third] {
            let usable: Vec<usize> = ms
                .iter()
                .copied()
                .filter(|&m| diff.span() * m < x.len())
                .collect();
            let run = |threads: usize| {
                rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .unwrap()
                    .install(|| difference_sums(&x, &usable, diff, &Progress::none(), 1.0))
            };
            let got = run(2);
            for (&m, &s) in usable.iter().zip(&got) {
                assert_eq!(s, reference(&x, m, diff), "{diff:?} m={m}");
            }
            assert_eq!(got, run(1));
            assert_eq!(got, run(5));
            // One τ alone gives the same number as within the set.
            for (&m, &s) in usable.iter().zip(&got) {
                assert_eq!(
                    difference_sums(&x, &[m], diff, &Progress::none(), 0.0)[0],
                    s
                );
            }
        }
    }
}
