//! Théo1 double sum of one averaging factor in `O(N log m)`: short overlapping blocks, each
//! expanded into correlations evaluated by FFT.
//!
//! The direct sum costs `(N − m)·m/2` brackets per τ, so an octave Théo1 reaching `m ≈ N`
//! is `O(N²)`. Expanding the squared bracket into products of samples turns the inner sum
//! over `k` into correlations (`O(N log N)` by FFT, Lewis's "repeated sums", B. Lewis, "A fast
//! algorithm for calculation of Thêo1", IEEE TUFFC 67(10), 2187–2190, 2020, there removed by
//! a recurrence over `m`, here per `m`), but products of samples cancel: on random-walk FM
//! the samples grow like `N^{3/2}` while a bracket at lag `m` is of size `m^{3/2}`, so a
//! plain expansion over the whole record loses `(N/m)³` of its digits (Lewis notes the same
//! loss for his recurrence).
//!
//! Two exact rearrangements keep the numbers small:
//!
//! * **Blocks.** Every bracket of the outer index `i` uses `x_i … x_{i+m}`, so the sum splits
//!   exactly into blocks of consecutive `i` (`V` of them), each a Théo1 double sum of its own
//!   sub-record of `V + m` samples. Théo1 ignores constants and linear trends, so each block
//!   is first made a residual about its own least-squares line (in double-double). A block
//!   spans a fixed multiple of `m` (`V + 2m` is one FFT length `P ≈ 6m`), so the samples
//!   of a block are only a bounded factor larger than its brackets, whatever `N`.
//! * **Expansion.** With `a, b, c, d = y_i, y_{i+k}, y_{i+m−k}, y_{i+m}` (`n′ = V` outer
//!   terms, `h = m/2`, `w = 1/k`):
//!
//!   ```text
//!   Σ_i (a − b − c + d)² = Σa² + Σb² + Σc² + Σd² − 2Σab − 2Σac + 2Σad + 2Σbc − 2Σbd − 2Σcd
//!   ```
//!
//!   the squares are prefix sums of `y²`; `Σab = C₁(k)`, `Σac = C₁(m−k)`, `Σad = C₁(m)` with
//!   `C₁(ℓ) = Σ_{i<n′} y_i y_{i+ℓ}`; `Σbd = C₂(m−k)`, `Σcd = C₂(k)` with
//!   `C₂(ℓ) = Σ_{j≥m} y_j y_{j−ℓ}`; and `Σ_k w Σbc` is, with `r = h − k` and the centre
//!   `c = i + h`, `Σ_r Σ_c y_{c−r} y_{c+r}/(h − r)` over the valid centres: the
//!   autocorrelation `R(2r)` minus the centres within `h` of either end of the block, a
//!   triangle of pairs summed by divide and conquer (`O(m log² m)`, [`edge`]). `C₁`, `C₂` and
//!   `R` come from three forward and three inverse real FFTs of length `P`.
//!
//! The rounding error of a block is `O(ε·log P·‖y‖²·H_h)` against a block sum that is, for the
//! noises Théo1 is used on, a bounded fraction of `‖y‖²` (measured in the tests). Each block
//! also checks its own result: when the a-priori bound exceeds [`TOLERANCE`] of the block sum
//! (constant, linear or pathological data), that block is summed directly instead.

use rayon::prelude::*;
use realfft::num_complex::Complex;

use crate::fractional::convolve::{fast_even_len, plans};
use crate::validate::neumaier_sum;

/// Target FFT length of a block, in units of `m` (`V = P − 2m` outer terms per block). Larger
/// blocks waste less on the `m`-sample overlap; smaller ones keep `‖y‖²/sum` small.
const BLOCK_FACTOR: usize = 6;

/// Largest accepted a-priori relative error bound of a block's expanded sum; above it the
/// block is summed directly.
const TOLERANCE: f64 = 1e-11;

/// Below this many multiply–adds a rectangle of the edge triangle is summed directly.
const DIRECT_AREA: usize = 4096;

/// Outer terms per block at `m`, and the FFT length of a block.
fn block_shape(m: usize) -> (usize, usize) {
    let p = fast_even_len(BLOCK_FACTOR * m);
    (p - 2 * m, p)
}

/// Estimated cost of [`bracket_sum`] at `m` on `n` samples, in nanosecond-like units (measured
/// on 2 cores, x86-64: six real FFTs of length `P` per block ≈ `8·P log₂P`, the two edge
/// triangles ≈ `3.2·m log₂²m`).
pub(super) fn cost(n: usize, m: usize) -> f64 {
    let count = n - m;
    let (valid, p) = block_shape(m);
    let (blocks, p) = if count <= valid {
        (1.0, fast_even_len(n + m))
    } else {
        (count.div_ceil(valid) as f64, p)
    };
    let (p, mf) = (p as f64, m.max(2) as f64);
    blocks * (8.0 * p * p.log2() + 3.2 * mf * mf.log2().powi(2))
}

/// `Σ_{i<N−m} Σ_{k=1}^{m/2} (1/k)·[(r_i − r_{i+k}) − (r_{i+m−k} − r_{i+m})]²` of the residual
/// `r` (the bracket sum of [`super::bracket_sum_direct`] with `p2 = 0`), by blocks.
///
/// Blocks run in parallel and are combined in their order: the result does not depend on the
/// thread count.
pub(super) fn bracket_sum(r: &[f64], m: usize) -> f64 {
    let n = r.len();
    let count = n - m;
    let (valid, _) = block_shape(m);
    let blocks = count.div_ceil(valid);
    let sums: Vec<f64> = (0..blocks)
        .into_par_iter()
        .with_max_len(1)
        .map(|b| {
            let start = b * valid;
            let len = valid.min(count - start);
            block_sum(&r[start..start + len + m], m)
        })
        .collect();
    neumaier_sum(sums)
}

/// The bracket sum of one sub-record `seg` (`len − m` outer terms).
fn block_sum(seg: &[f64], m: usize) -> f64 {
    let (expanded, bound) = block_sum_expanded(seg, m);
    if bound <= TOLERANCE * expanded {
        expanded
    } else {
        super::bracket_sum_direct(seg, 0.0, m)
    }
}

/// `y − (p0 + p1·u)` for the least-squares line of `y` (`u` centred), in double-double.
fn line_residual(y: &[f64]) -> Vec<f64> {
    let n = y.len();
    let centre = (n as f64 - 1.0) / 2.0;
    let (mut su2, mut sv, mut svu) = (0.0, 0.0, 0.0);
    for (t, &v) in y.iter().enumerate() {
        let u = t as f64 - centre;
        su2 += u * u;
        sv += v;
        svu += v * u;
    }
    let p0 = sv / n as f64;
    let p1 = if su2 > 0.0 { svu / su2 } else { 0.0 };
    if p0.is_finite() && p1.is_finite() {
        super::residual(y, [p0, p1, 0.0])
    } else {
        y.to_vec()
    }
}

/// Real spectrum (length `p/2 + 1`) of `y` with the samples outside `lo..hi` set to zero.
fn spectrum(y: &[f64], lo: usize, hi: usize, p: usize) -> Vec<Complex<f64>> {
    let (forward, _) = plans(p);
    let mut buf = vec![0.0; p];
    buf[lo..hi].copy_from_slice(&y[lo..hi]);
    let mut out = forward.make_output_vec();
    forward
        .process(&mut buf, &mut out)
        .expect("buffer lengths match the plan");
    out
}

/// `Σ_t a_t b_{t+ℓ}` for `ℓ = 0..=max_lag` from the spectra of `a` and `b` (length `p`, no
/// wrap-around for these lags).
fn correlation(a: &[Complex<f64>], b: &[Complex<f64>], p: usize, max_lag: usize) -> Vec<f64> {
    let (_, inverse) = plans(p);
    let mut prod: Vec<Complex<f64>> = a.iter().zip(b).map(|(u, v)| u.conj() * v).collect();
    // The DC and Nyquist bins of a product of real spectra are real; clear the rounding.
    prod[0].im = 0.0;
    if let Some(last) = prod.last_mut() {
        last.im = 0.0;
    }
    let mut out = inverse.make_output_vec();
    inverse
        .process(&mut prod, &mut out)
        .expect("buffer lengths match the plan");
    let scale = 1.0 / p as f64;
    out[..=max_lag].iter().map(|v| v * scale).collect()
}

/// The expanded bracket sum of `seg` and an a-priori bound of its absolute rounding error.
fn block_sum_expanded(seg: &[f64], m: usize) -> (f64, f64) {
    let len = seg.len();
    let h = m / 2;
    let nv = len - m;
    let y = line_residual(seg);
    let pre = super::prefix_sums(y.iter().map(|v| v * v), len);
    let norm2 = pre[len];
    let p = fast_even_len(len + m);
    let yf = spectrum(&y, 0, len, p);
    let af = spectrum(&y, 0, nv, p);
    let df = spectrum(&y, m, len, p);
    let c1 = correlation(&af, &yf, p, m);
    let c2 = correlation(&yf, &df, p, m);
    let rr = correlation(&yf, &yf, p, m);
    let head = edge(&y[..m], h);
    let tail: Vec<f64> = y[len - m..].iter().rev().copied().collect();
    let tail = edge(&tail, h);

    let mut terms = Vec::with_capacity(3 * h + 2);
    for k in 1..=h {
        let w = 1.0 / k as f64;
        let squares =
            pre[nv] + (pre[len] - pre[m]) + (pre[nv + k] - pre[k]) + (pre[nv + m - k] - pre[m - k]);
        terms.push(w * squares);
        terms.push(-2.0 * w * (c1[k] + c1[m - k] - c1[m] + c2[m - k] + c2[k]));
        terms.push(2.0 * rr[2 * (h - k)] * w);
    }
    terms.push(-2.0 * head);
    terms.push(-2.0 * tail);
    let sum = neumaier_sum(terms);
    // Every correlation value carries ≈ ε·log₂P·‖y‖² of FFT rounding (and each prefix
    // difference ε·‖y‖²); the sum weighs about 12 of them by 1/k.
    let harmonic: f64 = (1..=h).map(|k| 1.0 / k as f64).sum();
    let bound = f64::EPSILON * (p as f64).log2() * 12.0 * harmonic * norm2;
    (sum, bound)
}

/// `Σ_{r=0}^{h−1} Σ_{p=0}^{h−1−r} y_p y_{p+2r}/(h − r)` for the first `m = 2h` samples `y`:
/// the pairs of centre `< h` left out of a block's valid centres.
///
/// By parity of `p` (`y_{p+2r} = Y[j + r]`, `Y[j] = y_{2j+ρ}`), each is the triangle
/// `Σ_{2j + r ≤ h−1−ρ} Y[j]·w_r·Y[j + r]`, summed by divide and conquer ([`triangle`]).
fn edge(y: &[f64], h: usize) -> f64 {
    let w: Vec<f64> = (0..h).map(|r| 1.0 / (h - r) as f64).collect();
    let mut parts = Vec::new();
    for rho in 0..2 {
        if h < rho + 1 {
            continue;
        }
        let lim = h - 1 - rho;
        let yr: Vec<f64> = y.iter().skip(rho).step_by(2).copied().collect();
        triangle(&yr, &w, lim, (0, lim / 2 + 1), (0, lim + 1), &mut parts);
    }
    neumaier_sum(parts)
}

/// Pushes onto `out` the parts of `Σ Y[j]·w[r]·Y[j + r]` over `j ∈ js`, `r ∈ rs`,
/// `2j + r ≤ lim`: whole rectangles at once ([`rectangle`]), the rest split in halves.
fn triangle(
    yv: &[f64],
    w: &[f64],
    lim: usize,
    js: (usize, usize),
    rs: (usize, usize),
    out: &mut Vec<f64>,
) {
    let ((j0, j1), (r0, r1)) = (js, rs);
    if j0 >= j1 || r0 >= r1 || 2 * j0 + r0 > lim {
        return;
    }
    if 2 * (j1 - 1) + (r1 - 1) <= lim {
        out.push(rectangle(yv, w, js, rs));
        return;
    }
    let (nj, nr) = (j1 - j0, r1 - r0);
    if nj * nr <= DIRECT_AREA {
        let mut s = 0.0;
        for j in j0..j1 {
            if 2 * j + r0 > lim {
                break;
            }
            let end = r1.min(lim - 2 * j + 1);
            let mut a = 0.0;
            for r in r0..end {
                a += w[r] * yv[j + r];
            }
            s += yv[j] * a;
        }
        out.push(s);
        return;
    }
    if 2 * nj >= nr {
        let mid = j0 + nj / 2;
        triangle(yv, w, lim, (j0, mid), rs, out);
        triangle(yv, w, lim, (mid, j1), rs, out);
    } else {
        let mid = r0 + nr / 2;
        triangle(yv, w, lim, js, (r0, mid), out);
        triangle(yv, w, lim, js, (mid, r1), out);
    }
}

/// `Σ_{j∈js} Y[j]·Σ_{r∈rs} w[r]·Y[j + r]`: directly when small, else one FFT correlation.
fn rectangle(yv: &[f64], w: &[f64], js: (usize, usize), rs: (usize, usize)) -> f64 {
    let ((j0, j1), (r0, r1)) = (js, rs);
    let (nj, nr) = (j1 - j0, r1 - r0);
    if nj * nr <= 4 * DIRECT_AREA || nj.min(nr) < 16 {
        let mut s = 0.0;
        for j in j0..j1 {
            let mut a = 0.0;
            for r in r0..r1 {
                a += w[r] * yv[j + r];
            }
            s += yv[j] * a;
        }
        return s;
    }
    // u_t = Σ_s g_s·seg_{t+s}, g = w[r0..r1), seg = Y[j0 + r0 ..], t < nj.
    let seg_len = nj + nr - 1;
    let p = fast_even_len(seg_len);
    let g = spectrum(&w[r0..r1], 0, nr, p);
    let seg = &yv[j0 + r0..j0 + r0 + seg_len];
    let sf = spectrum(seg, 0, seg_len, p);
    let u = correlation(&g, &sf, p, nj - 1);
    neumaier_sum((0..nj).map(|t| yv[j0 + t] * u[t]))
}

#[cfg(test)]
mod tests {
    use super::super::tests_support::{drifting, error_free_sum, random_walk_fm, white_fm};
    use super::super::{bracket_sum_direct, detrend};
    use super::*;

    /// The block sum against the error-free literal sum of the same residual, at small `m`
    /// (many blocks), mid `m` and `m` near the record (one block), on the data where products
    /// of samples cancel most. Measured max relative difference 5.3e-14 (random-walk FM);
    /// bound 1e-11 = [`TOLERANCE`], the a-priori bound every accepted block satisfies.
    #[test]
    fn blocks_equal_error_free_sum() {
        for n in [3000usize, 20001] {
            for (name, x) in [
                ("white FM", white_fm(n, 1)),
                ("random-walk FM", random_walk_fm(n, 2)),
                ("drifting", drifting(n, 3)),
            ] {
                let d = detrend(&x);
                let top = n - 1 - (n - 1) % 2;
                for m in [
                    2usize,
                    8,
                    64,
                    256,
                    1000,
                    1202,
                    n / 2 - (n / 2) % 2,
                    top - 40,
                    top,
                ] {
                    let reference = error_free_sum(&d.r, m);
                    let fast = bracket_sum(&d.r, m);
                    let rel = ((fast - reference) / reference).abs();
                    assert!(rel <= TOLERANCE, "N={n} {name} m={m}: {rel:e}");
                }
            }
        }
    }

    /// Where the a-priori bound is not met (one outer term against a whole record of `y²`),
    /// the block is summed directly: bit-identical to the direct sum.
    #[test]
    fn loose_blocks_fall_back_to_the_direct_sum() {
        let x = random_walk_fm(4001, 4);
        let d = detrend(&x);
        let (expanded, bound) = block_sum_expanded(&d.r, 4000);
        assert!(
            bound > TOLERANCE * expanded,
            "the probe must exercise the fallback"
        );
        assert_eq!(
            bracket_sum(&d.r, 4000).to_bits(),
            bracket_sum_direct(&d.r, 0.0, 4000).to_bits()
        );
        // A constant record: every term is zero, accepted as exactly zero.
        assert_eq!(bracket_sum(&[7.0; 500], 64), 0.0);
    }

    /// Blocks are summed in their order whatever the thread count.
    #[test]
    fn blocks_do_not_depend_on_threads() {
        let d = detrend(&white_fm(30_000, 9));
        let run = |threads: usize| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| bracket_sum(&d.r, 512).to_bits())
        };
        assert_eq!(run(1), run(3));
    }

    /// The edge triangle by divide and conquer equals its definition, for sizes that take
    /// the direct, the split and the FFT-rectangle paths.
    #[test]
    fn edge_equals_definition() {
        for m in [2usize, 4, 10, 130, 2048, 6000] {
            let y = white_fm(m, m as u64);
            let h = m / 2;
            let literal = crate::validate::neumaier_sum((0..h).flat_map(|r| {
                let y = &y;
                (0..h - r).map(move |p| y[p] * y[p + 2 * r] / (h - r) as f64)
            }));
            let fast = edge(&y, h);
            let scale: f64 = y.iter().map(|v| v * v).sum::<f64>() * 10.0;
            // Absolute: FFT rounding ≈ ε·log₂P per unit of ‖y‖²·H_h.
            assert!(
                (fast - literal).abs() <= 1e-13 * scale,
                "m={m} {fast} {literal}"
            );
        }
    }
}
