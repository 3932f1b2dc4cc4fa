//! The modified Allan sum, several re-seeded segments in lockstep.
//!
//! The modified Allan variance at factor `m` needs `S = Σ_j s_j²` with the inner m-sums of
//! second differences `s_j = Σ_{i=j}^{j+m−1} d_i`, `d_i = x_{i+2m} − 2x_{i+m} + x_i`
//! (SP1065 eq. 14). They are carried as a running sum, `s_{j} = s_{j−1} + (d_{j+m−1} − d_{j−1})`,
//! re-seeded by an exact (Neumaier) m-sum at the start of every segment of
//! `max(BLOCK, 4m)` terms so rounding cannot drift over long records; segment sums `Σ s_j²`
//! are added in order with Neumaier compensation.
//!
//! Inside a segment every step waits for the previous one (one addition's latency), so a
//! single running sum leaves most of the CPU idle. The segments are independent, though: here
//! four of them run in lockstep, one per vector lane. Per lane and per tile of four steps,
//! the step increments are formed with contiguous vector loads (four steps of one segment in
//! a vector), the 4×4 tile is transposed in registers (one step of four segments in a
//! vector), and the four running sums advance together. The re-seeding m-sums are evaluated
//! the same way (a Neumaier step per lane, with a select instead of the branch).
//!
//! Every lane performs exactly the additions of the serial loop, in the same order, with no
//! fused multiply-add, so the result has the same bits as the serial evaluation
//! ([`sum_serial`], kept as the reference of the tests), on every instruction set: the
//! transposition needs AVX (x86-64-v3); other CPUs and `GYROBIAS_SIMD=scalar` run the same
//! lanes in scalar code.

use crate::validate;

/// Shortest segment of the running sum (in terms): re-seeding costs O(m), doing it every
/// `max(BLOCK, 4m)` steps bounds that work by a quarter pass per τ while keeping the running
/// sum's drift negligible.
const BLOCK: usize = 4096;

/// Segments run in lockstep (one per lane of a 256-bit vector of f64). Four lanes beat eight
/// here: eight segments read 32 far-apart streams of the series at once, four read 16, which
/// the hardware prefetchers follow.
const LANES: usize = 4;

/// Steps per tile (the transposed block is `LANES × TILE`).
const TILE: usize = 4;

type Lanes = [f64; LANES];

/// `d_i = x_{i+2m} − 2x_{i+m} + x_i`, as every path evaluates it.
#[inline(always)]
#[allow(clippy::inline_always)] // inlined into the dispatched (feature-specific) bodies
fn second(x: &[f64], m: usize, i: usize) -> f64 {
    x[i + 2 * m] - 2.0 * x[i + m] + x[i]
}

/// The step `s_j − s_{j−1} = d_{j+m−1} − d_{j−1}` of the running sum.
#[inline(always)]
#[allow(clippy::inline_always)]
fn step(x: &[f64], m: usize, j: usize) -> f64 {
    second(x, m, j + m - 1) - second(x, m, j - 1)
}

/// The segment sum `Σ s_j²` over `j in start..end`, serially: the exact seed `s_start`, then
/// the running sum.
fn segment_serial(x: &[f64], m: usize, start: usize, end: usize) -> f64 {
    let mut s = validate::neumaier_sum((start..start + m).map(|i| second(x, m, i)));
    let mut block = s * s;
    for j in start + 1..end {
        s += step(x, m, j);
        block += s * s;
    }
    block
}

/// The raw modified Allan sum `Σ_{j<terms} s_j²`, bit for bit the serial evaluation
/// ([`sum_serial`]) with four segments in lockstep.
pub(super) fn sum_modified(x: &[f64], m: usize, terms: usize) -> f64 {
    let reseed = BLOCK.max(4 * m);
    let segments: Vec<(usize, usize)> = (0..terms)
        .step_by(reseed)
        .map(|j| (j, (j + reseed).min(terms)))
        .collect();
    let mut blocks = vec![0.0_f64; segments.len()];
    // The full segments (`reseed` terms) in lockstep groups of LANES; the short last one
    // serially, unless the full ones leave a lone segment to pair it with (a group runs in
    // lockstep as long as its shortest member; its longer lanes then finish alone).
    let arch = crate::simd::arch();
    let full = terms / reseed;
    let lone = full % LANES == 1 && full < segments.len();
    let grouped = if lone { full - 1 } else { full };
    for (group, out) in segments[..grouped]
        .chunks(LANES)
        .zip(blocks[..grouped].chunks_mut(LANES))
    {
        if group.len() == 1 {
            out[0] = segment_serial(x, m, group[0].0, group[0].1);
        } else {
            lockstep(arch, x, m, group, out);
        }
    }
    if lone {
        lockstep(arch, x, m, &segments[grouped..], &mut blocks[grouped..]);
    } else if full < segments.len() {
        let (start, end) = segments[full];
        blocks[full] = segment_serial(x, m, start, end);
    }
    compensated(&blocks)
}

/// Neumaier sum of the segment sums, in order.
fn compensated(blocks: &[f64]) -> f64 {
    let (mut total, mut comp) = (0.0_f64, 0.0_f64);
    for &block in blocks {
        validate::neumaier_add(&mut total, &mut comp, block);
    }
    total + comp
}

/// The segment sums of up to [`LANES`] segments `group` (`(start, end)` each), into `out`.
/// Unused lanes repeat the first segment and are dropped.
fn lockstep(arch: pulp::Arch, x: &[f64], m: usize, group: &[(usize, usize)], out: &mut [f64]) {
    let mut starts = [group[0].0; LANES];
    let mut ends = [group[0].1; LANES];
    for (l, &(a, b)) in group.iter().enumerate() {
        starts[l] = a;
        ends[l] = b;
    }
    let seeded = m - m % TILE;
    let steps = (0..LANES)
        .map(|l| ends[l] - starts[l] - 1)
        .min()
        .unwrap_or(0);
    let stepped = steps - steps % TILE;
    // The seeds: Neumaier m-sums, the tiles in lockstep, the last m % TILE terms per lane.
    let (mut sum, mut comp) = seeds(arch, x, m, starts, seeded);
    let (mut run, mut acc) = ([0.0_f64; LANES], [0.0_f64; LANES]);
    for l in 0..LANES {
        for i in starts[l] + seeded..starts[l] + m {
            validate::neumaier_add(&mut sum[l], &mut comp[l], second(x, m, i));
        }
        run[l] = sum[l] + comp[l];
        acc[l] = run[l] * run[l];
    }
    // The running sums: whole tiles in lockstep, then each lane's last steps.
    chain(arch, x, m, starts, stepped, &mut run, &mut acc);
    for l in 0..LANES {
        for j in starts[l] + 1 + stepped..ends[l] {
            run[l] += step(x, m, j);
            acc[l] += run[l] * run[l];
        }
    }
    out.copy_from_slice(&acc[..group.len()]);
}

/// Neumaier sums `(sum, comp)` of `d_{start_l + i}` for `i in 0..len` (`len` a multiple of
/// [`TILE`]), per lane.
fn seeds(
    arch: pulp::Arch,
    x: &[f64],
    m: usize,
    starts: [usize; LANES],
    len: usize,
) -> (Lanes, Lanes) {
    match arch {
        #[cfg(target_arch = "x86_64")]
        pulp::Arch::V3(simd) => pulp::Simd::vectorize(
            simd,
            avx::Seeds {
                simd,
                x,
                m,
                starts,
                len,
            },
        ),
        _ => {
            let (mut sum, mut comp) = ([0.0_f64; LANES], [0.0_f64; LANES]);
            for l in 0..LANES {
                for i in starts[l]..starts[l] + len {
                    validate::neumaier_add(&mut sum[l], &mut comp[l], second(x, m, i));
                }
            }
            (sum, comp)
        }
    }
}

/// `steps` (a multiple of [`TILE`]) steps of the running sums `run` and their sums of squares
/// `acc`, per lane, from `j = start_l + 1`.
fn chain(
    arch: pulp::Arch,
    x: &[f64],
    m: usize,
    starts: [usize; LANES],
    steps: usize,
    run: &mut Lanes,
    acc: &mut Lanes,
) {
    match arch {
        #[cfg(target_arch = "x86_64")]
        pulp::Arch::V3(simd) => {
            (*run, *acc) = pulp::Simd::vectorize(
                simd,
                avx::Chain {
                    simd,
                    x,
                    m,
                    starts,
                    steps,
                    run: *run,
                    acc: *acc,
                },
            );
        }
        _ => {
            for l in 0..LANES {
                for j in starts[l] + 1..starts[l] + 1 + steps {
                    run[l] += step(x, m, j);
                    acc[l] += run[l] * run[l];
                }
            }
        }
    }
}

/// The lockstep loops with AVX (x86-64-v3): contiguous loads, an in-register 4×4 transpose.
#[cfg(target_arch = "x86_64")]
mod avx {
    use core::arch::x86_64::__m256d;

    use pulp::{cast, f64x4, x86::V3};

    use super::{LANES, Lanes, TILE};

    /// Four consecutive samples from `x[i]`.
    #[inline(always)]
    #[allow(clippy::inline_always)]
    fn load(x: &[f64], i: usize) -> f64x4 {
        let v: [f64; 4] = x[i..i + 4].try_into().expect("four samples");
        cast(v)
    }

    /// Rows (one segment's four steps each) to columns (one step of four segments each).
    #[inline(always)]
    #[allow(clippy::inline_always)]
    fn transpose(simd: V3, e: [f64x4; LANES]) -> [f64x4; TILE] {
        let e: [__m256d; LANES] = e.map(cast);
        let t0 = simd.avx._mm256_unpacklo_pd(e[0], e[1]);
        let t1 = simd.avx._mm256_unpackhi_pd(e[0], e[1]);
        let t2 = simd.avx._mm256_unpacklo_pd(e[2], e[3]);
        let t3 = simd.avx._mm256_unpackhi_pd(e[2], e[3]);
        [
            cast(simd.avx._mm256_permute2f128_pd::<0x20>(t0, t2)),
            cast(simd.avx._mm256_permute2f128_pd::<0x20>(t1, t3)),
            cast(simd.avx._mm256_permute2f128_pd::<0x31>(t0, t2)),
            cast(simd.avx._mm256_permute2f128_pd::<0x31>(t1, t3)),
        ]
    }

    /// [`super::seeds`] on x86-64-v3.
    pub(super) struct Seeds<'a> {
        pub(super) simd: V3,
        pub(super) x: &'a [f64],
        pub(super) m: usize,
        pub(super) starts: [usize; LANES],
        pub(super) len: usize,
    }

    impl pulp::WithSimd for Seeds<'_> {
        type Output = (Lanes, Lanes);

        #[allow(clippy::inline_always)] // pulp's contract: inlined into the dispatched function
        #[inline(always)]
        fn with_simd<S: pulp::Simd>(self, _: S) -> (Lanes, Lanes) {
            let Seeds {
                simd,
                x,
                m,
                starts,
                len,
            } = self;
            let zero = simd.splat_f64x4(0.0);
            let two = simd.splat_f64x4(2.0);
            let (mut sum, mut comp) = (zero, zero);
            // Per lane, the windows x[start + {0, m, 2m}..][..len], sliced once (the loads
            // below then need no bounds check of their own).
            let windows: [[&[f64]; 3]; LANES] = core::array::from_fn(|l| {
                let w = &x[starts[l]..starts[l] + len + 2 * m];
                [&w[..len], &w[m..m + len], &w[2 * m..2 * m + len]]
            });
            let mut i = 0;
            while i + TILE <= len {
                let mut rows = [zero; LANES];
                for (row, [a, b, c]) in rows.iter_mut().zip(&windows) {
                    let (a, b, c) = (load(a, i), load(b, i), load(c, i));
                    // (x_{i+2m} − 2x_{i+m}) + x_i, as `second`
                    *row = simd.add_f64x4(simd.sub_f64x4(c, simd.mul_f64x4(two, b)), a);
                }
                for v in transpose(simd, rows) {
                    // validate::neumaier_add, the branch as a select
                    let t = simd.add_f64x4(sum, v);
                    let ge = simd.cmp_ge_f64x4(simd.abs_f64x4(sum), simd.abs_f64x4(v));
                    let big = simd.select_f64x4(ge, sum, v);
                    let small = simd.select_f64x4(ge, v, sum);
                    comp = simd.add_f64x4(comp, simd.add_f64x4(simd.sub_f64x4(big, t), small));
                    sum = t;
                }
                i += TILE;
            }
            (cast(sum), cast(comp))
        }
    }

    /// [`super::chain`] on x86-64-v3.
    pub(super) struct Chain<'a> {
        pub(super) simd: V3,
        pub(super) x: &'a [f64],
        pub(super) m: usize,
        pub(super) starts: [usize; LANES],
        pub(super) steps: usize,
        pub(super) run: Lanes,
        pub(super) acc: Lanes,
    }

    impl pulp::WithSimd for Chain<'_> {
        type Output = (Lanes, Lanes);

        #[allow(clippy::inline_always)] // pulp's contract: inlined into the dispatched function
        #[inline(always)]
        fn with_simd<S: pulp::Simd>(self, _: S) -> (Lanes, Lanes) {
            let Chain {
                simd,
                x,
                m,
                starts,
                steps,
                run,
                acc,
            } = self;
            let zero = simd.splat_f64x4(0.0);
            let two = simd.splat_f64x4(2.0);
            let (mut run, mut acc): (f64x4, f64x4) = (cast(run), cast(acc));
            // Step j = start + 1 + p reads x at j − 1 + {0, m, 2m, 3m}: per lane, the windows
            // x[start + {0, m, 2m, 3m}..][..steps], sliced once.
            let windows: [[&[f64]; 4]; LANES] = core::array::from_fn(|l| {
                let w = &x[starts[l]..starts[l] + steps + 3 * m];
                [
                    &w[..steps],
                    &w[m..m + steps],
                    &w[2 * m..2 * m + steps],
                    &w[3 * m..3 * m + steps],
                ]
            });
            let mut p = 0;
            while p + TILE <= steps {
                let mut rows = [zero; LANES];
                for (row, [a, b, c, d]) in rows.iter_mut().zip(&windows) {
                    let (a, b, c, d) = (load(a, p), load(b, p), load(c, p), load(d, p));
                    let late = simd.add_f64x4(simd.sub_f64x4(d, simd.mul_f64x4(two, c)), b);
                    let early = simd.add_f64x4(simd.sub_f64x4(c, simd.mul_f64x4(two, b)), a);
                    *row = simd.sub_f64x4(late, early);
                }
                for v in transpose(simd, rows) {
                    run = simd.add_f64x4(run, v);
                    acc = simd.add_f64x4(acc, simd.mul_f64x4(run, run));
                }
                p += TILE;
            }
            (cast(run), cast(acc))
        }
    }
}

/// The serial evaluation: segment by segment, one running sum at a time (the reference of
/// the lockstep kernel; what [`sum_modified`] computed before it).
#[cfg(test)]
pub(super) fn sum_serial(x: &[f64], m: usize, terms: usize) -> f64 {
    let reseed = BLOCK.max(4 * m);
    let blocks: Vec<f64> = (0..terms)
        .step_by(reseed)
        .map(|j| segment_serial(x, m, j, (j + reseed).min(terms)))
        .collect();
    compensated(&blocks)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A random walk with white noise, a drift and a quantised part (every path of the kernel
    /// sees nonzero, non-trivial increments).
    fn series(n: usize, seed: u64) -> Vec<f64> {
        let mut state = seed;
        let mut uniform = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1_u64 << 53) as f64 - 0.5
        };
        let mut x = vec![0.0; n];
        let (mut walk, mut angle) = (0.0, 0.0);
        for (i, slot) in x.iter_mut().enumerate().skip(1) {
            walk += 1e-3 * uniform();
            let rate = 0.2 + uniform() + walk + 1e-6 * i as f64;
            angle += (rate * 1024.0).round() / 1024.0 * 0.01;
            *slot = angle;
        }
        x
    }

    fn terms(n: usize, m: usize) -> usize {
        n + 1 - 3 * m
    }

    #[test]
    fn lockstep_gives_the_serial_bits() {
        // lengths and factors that exercise: many full groups, a partial group, a lone full
        // segment alone (n = 4096·5 + 2) and paired with the short last one (m = 3000), the
        // short last segment alone, m % 4 ≠ 0 seed tails, step tails, m = 1.
        let x = series(70_003, 7);
        for m in [
            1, 2, 3, 5, 8, 13, 64, 100, 1023, 1024, 1500, 4096, 5000, 11_000, 23_334,
        ] {
            let t = terms(x.len(), m);
            let (a, b) = (sum_modified(&x, m, t), sum_serial(&x, m, t));
            assert_eq!(a.to_bits(), b.to_bits(), "m = {m}: {a:e} vs {b:e}");
        }
        for n in [
            4097 * 3 + 5,
            4096 * 4 + 2,
            4096 * 5 + 2,
            4096 * 8 + 3,
            4096 * 9 + 1,
        ] {
            let x = series(n, n as u64);
            for m in [1, 4, 7] {
                let t = terms(n, m);
                assert_eq!(
                    sum_modified(&x, m, t).to_bits(),
                    sum_serial(&x, m, t).to_bits(),
                    "n = {n}, m = {m}"
                );
            }
        }
    }

    #[test]
    fn scalar_lanes_give_the_serial_bits() {
        // The fallback lanes (other CPUs, GYROBIAS_SIMD=scalar) called directly.
        let x = series(40_000, 3);
        for m in [1, 6, 333] {
            let t = terms(x.len(), m);
            let reseed = BLOCK.max(4 * m);
            let group: Vec<(usize, usize)> =
                (0..4).map(|k| (k * reseed, (k + 1) * reseed)).collect();
            let mut out = [0.0; 4];
            lockstep(pulp::Arch::Scalar, &x, m, &group, &mut out);
            for (k, &(a, b)) in group.iter().enumerate() {
                assert!(b <= t);
                assert_eq!(
                    out[k].to_bits(),
                    segment_serial(&x, m, a, b).to_bits(),
                    "m = {m}"
                );
            }
        }
    }

    #[test]
    fn equals_the_exact_direct_sum() {
        // Against exact rational arithmetic is too slow in Rust; Neumaier over the direct
        // double sum (each s_j summed from scratch) is accurate to ~1 ulp of each s_j.
        let x = series(30_001, 11);
        for m in [1, 3, 16, 250, 2000] {
            let t = terms(x.len(), m);
            let direct = validate::neumaier_sum((0..t).map(|j| {
                let s = validate::neumaier_sum((j..j + m).map(|i| second(&x, m, i)));
                s * s
            }));
            let fast = sum_modified(&x, m, t);
            let rel = ((fast - direct) / direct).abs();
            // drift of the running sum over ≤ max(4096, 4m) steps of ~1 ulp each, relative
            // to the sum of squares: far below 1e-10 on this data
            assert!(rel < 1e-10, "m = {m}: relative error {rel:e}");
        }
    }
}
