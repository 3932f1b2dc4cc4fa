//! Causal (lower-triangular Toeplitz) convolution `y_k = Σ_{l=0}^{min(k, K−1)} c_l x_{k−l}`,
//! `k = 0..n−1`, by direct summation or by FFT, chosen from the operation counts.
//!
//! * Direct: `n·K − K(K−1)/2` multiply–adds, evaluated lag by lag as vectorisable AXPYs. Exact
//!   for integer kernels and data (e.g. integer-order differences).
//! * FFT: a real FFT of even 5-smooth length `N ≥ n + K − 1` (no wrap-around into the first `n`
//!   outputs), the kernel spectrum computed once and shared by all rows; `O(N log N)` per row.
//!   Rounding error is `O(ε log N)` relative to the largest output magnitude.

use std::sync::Arc;

use realfft::num_complex::Complex;
use realfft::{ComplexToReal, RealFftPlanner, RealToComplex};

/// How to evaluate the convolution.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Method {
    /// Whichever of direct and FFT needs fewer operations (the default).
    Auto,
    /// Direct summation.
    Direct,
    /// FFT convolution.
    Fft,
}

impl Method {
    /// Parses `"auto"`, `"direct"` or `"fft"`.
    pub fn parse(name: &str) -> crate::Result<Self> {
        match name {
            "auto" => Ok(Method::Auto),
            "direct" => Ok(Method::Direct),
            "fft" => Ok(Method::Fft),
            other => Err(crate::Error::invalid(
                "method",
                format!("expected 'auto', 'direct' or 'fft', got {other:?}"),
            )),
        }
    }
}

/// Relative cost of one `N log₂ N` unit of a real FFT against one direct multiply–add (measured
/// on x86-64 with AVX2: a forward plus an inverse real FFT of size N costs about as much as
/// `8·N log₂ N` vectorised multiply–adds, planning included; crossover near n = 400 for a
/// full-memory kernel).
const FFT_COST_PER_NLOGN: f64 = 8.0;

/// Smallest even `2^a·3^b·5^c` that is `≥ target` (fast sizes for rustfft's mixed radix).
pub(crate) fn fast_even_len(target: usize) -> usize {
    let target = target.max(2);
    let mut best = usize::MAX;
    let mut p5 = 1usize;
    while p5 < best {
        let mut p35 = p5;
        while p35 < best {
            // Smallest power of two times p35 that reaches the target, at least ×2 (even).
            let mut v = p35 * 2;
            while v < target {
                v *= 2;
            }
            best = best.min(v);
            p35 = p35.saturating_mul(3);
        }
        p5 = p5.saturating_mul(5);
    }
    best
}

/// Number of direct multiply–adds for `n` outputs and a kernel of length `k ≤ n`.
fn direct_ops(n: usize, k: usize) -> f64 {
    let (n, k) = (n as f64, k as f64);
    n * k - k * (k - 1.0) / 2.0
}

/// Whether the FFT is expected to be faster than direct summation for `n` outputs and a kernel
/// of `k` weights.
pub(crate) fn prefer_fft(n: usize, k: usize) -> bool {
    let nf = fast_even_len(n + k.max(1) - 1) as f64;
    direct_ops(n, k.min(n)) > FFT_COST_PER_NLOGN * nf * nf.log2()
}

enum Plan {
    Direct,
    Fft {
        len: usize,
        forward: Arc<dyn RealToComplex<f64>>,
        inverse: Arc<dyn ComplexToReal<f64>>,
        /// Kernel spectrum, already scaled by 1/len.
        kernel_spectrum: Vec<Complex<f64>>,
    },
}

/// A prepared causal convolution with a fixed kernel and output length.
pub(crate) struct CausalConvolution {
    n: usize,
    kernel: Vec<f64>,
    plan: Plan,
}

/// Per-thread work space of a [`CausalConvolution`].
pub(crate) struct Scratch {
    real: Vec<f64>,
    spectrum: Vec<Complex<f64>>,
    fft: Vec<Complex<f64>>,
}

impl CausalConvolution {
    /// Prepares the convolution of series of length `n` with `kernel` (only its first `n`
    /// values matter; it is truncated to them).
    pub(crate) fn new(mut kernel: Vec<f64>, n: usize, method: Method) -> Self {
        kernel.truncate(n);
        let k = kernel.len();
        let fft_len = fast_even_len(n + k.max(1) - 1);
        let use_fft = match method {
            Method::Direct => false,
            Method::Fft => true,
            Method::Auto => prefer_fft(n, k),
        };
        let plan = if use_fft && k > 0 {
            let mut planner = RealFftPlanner::<f64>::new();
            let forward = planner.plan_fft_forward(fft_len);
            let inverse = planner.plan_fft_inverse(fft_len);
            let mut padded = vec![0.0; fft_len];
            let scale = 1.0 / fft_len as f64;
            for (p, c) in padded.iter_mut().zip(&kernel) {
                *p = c * scale;
            }
            let mut kernel_spectrum = forward.make_output_vec();
            // Lengths come from the plan itself: the transform cannot fail.
            forward
                .process(&mut padded, &mut kernel_spectrum)
                .expect("FFT buffer lengths come from the plan");
            Plan::Fft {
                len: fft_len,
                forward,
                inverse,
                kernel_spectrum,
            }
        } else {
            Plan::Direct
        };
        CausalConvolution { n, kernel, plan }
    }

    /// Whether the FFT path was chosen.
    #[cfg(test)]
    pub(crate) fn uses_fft(&self) -> bool {
        matches!(self.plan, Plan::Fft { .. })
    }

    /// Work space for [`Self::apply_into`].
    pub(crate) fn scratch(&self) -> Scratch {
        match &self.plan {
            Plan::Direct => Scratch {
                real: Vec::new(),
                spectrum: Vec::new(),
                fft: Vec::new(),
            },
            Plan::Fft {
                len,
                forward,
                inverse,
                ..
            } => Scratch {
                real: vec![0.0; *len],
                spectrum: forward.make_output_vec(),
                fft: vec![
                    Complex::default();
                    forward.get_scratch_len().max(inverse.get_scratch_len())
                ],
            },
        }
    }

    /// `out = c ⋆ x` (causal, first `n` outputs). `x.len() == out.len() == n`.
    pub(crate) fn apply_into(&self, x: &[f64], out: &mut [f64], scratch: &mut Scratch) {
        debug_assert_eq!(x.len(), self.n);
        debug_assert_eq!(out.len(), self.n);
        match &self.plan {
            Plan::Direct => direct_into(&self.kernel, x, out),
            Plan::Fft {
                forward,
                inverse,
                kernel_spectrum,
                ..
            } => {
                let Scratch {
                    real,
                    spectrum,
                    fft,
                } = scratch;
                real[..self.n].copy_from_slice(x);
                real[self.n..].fill(0.0);
                forward
                    .process_with_scratch(real, spectrum, fft)
                    .expect("FFT buffer lengths come from the plan");
                for (s, k) in spectrum.iter_mut().zip(kernel_spectrum) {
                    *s *= k;
                }
                // Spectra of real signals: DC and Nyquist bins are real; make that exact.
                spectrum[0].im = 0.0;
                if let Some(last) = spectrum.last_mut() {
                    last.im = 0.0;
                }
                inverse
                    .process_with_scratch(spectrum, real, fft)
                    .expect("FFT buffer lengths come from the plan");
                out.copy_from_slice(&real[..self.n]);
            }
        }
    }
}

/// Direct causal convolution, lag by lag (each lag is a vectorisable AXPY).
fn direct_into(kernel: &[f64], x: &[f64], out: &mut [f64]) {
    let n = x.len();
    out.fill(0.0);
    for (l, &c) in kernel.iter().enumerate().take(n) {
        if c == 0.0 {
            continue;
        }
        for (o, xi) in out[l..].iter_mut().zip(&x[..n - l]) {
            *o += c * xi;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fast_lengths_are_even_smooth_and_minimal() {
        assert_eq!(fast_even_len(1), 2);
        assert_eq!(fast_even_len(7), 8);
        assert_eq!(fast_even_len(11), 12);
        assert_eq!(fast_even_len(3999), 4000);
        assert_eq!(fast_even_len(1_999_999), 2_000_000);
        for t in 2..3000 {
            let v = fast_even_len(t);
            assert!(v >= t && v % 2 == 0);
            let mut r = v;
            for p in [2, 3, 5] {
                while r % p == 0 {
                    r /= p;
                }
            }
            assert_eq!(r, 1, "{v} is not 5-smooth");
        }
    }

    #[test]
    fn fft_matches_direct() {
        let n = 777;
        let kernel: Vec<f64> = (0..n).map(|l| 1.0 / (1.0 + l as f64).powf(0.7)).collect();
        let x: Vec<f64> = (0..n)
            .map(|i| ((i * 37 % 101) as f64 - 50.0) / 7.0)
            .collect();
        let direct = CausalConvolution::new(kernel.clone(), n, Method::Direct);
        let fft = CausalConvolution::new(kernel, n, Method::Fft);
        assert!(fft.uses_fft() && !direct.uses_fft());
        let mut a = vec![0.0; n];
        let mut b = vec![0.0; n];
        direct.apply_into(&x, &mut a, &mut direct.scratch());
        fft.apply_into(&x, &mut b, &mut fft.scratch());
        let scale = a.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        for (p, q) in a.iter().zip(&b) {
            assert!((p - q).abs() <= 1e-13 * scale);
        }
    }
}
