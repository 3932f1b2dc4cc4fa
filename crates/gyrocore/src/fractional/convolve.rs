//! Causal (lower-triangular Toeplitz) convolution `y_k = Σ_{l=0}^{min(k, K−1)} c_l x_{k−l}`,
//! `k = 0..n−1`, by direct summation or by FFT, chosen from the operation counts.
//!
//! * Direct: `n·K − K(K−1)/2` multiply–adds, evaluated lag by lag as vectorisable AXPYs. Exact
//!   for integer kernels and data (e.g. integer-order differences).
//! * FFT: a real FFT of even 5-smooth length `N ≥ n + K − 1` (no wrap-around into the first `n`
//!   outputs), the kernel spectrum computed once and shared by all rows; `O(N log N)` per row.
//!   Rounding error is `O(ε log N)` relative to the largest output magnitude.

use std::sync::{Arc, Mutex, OnceLock};

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

/// A forward and an inverse real FFT plan of one length.
pub(crate) type PlanPair = (Arc<dyn RealToComplex<f64>>, Arc<dyn ComplexToReal<f64>>);

/// Number of FFT lengths whose plans are kept (most recently used first).
const PLAN_CACHE_SIZE: usize = 8;

/// Real FFT plans of length `len`, from a small process-wide cache.
///
/// Planning a large FFT (twiddle tables) costs several times the transform itself, so repeated
/// calls with the same length reuse the plans, as SciPy's pocketfft does. The cache keeps the
/// plans of the last [`PLAN_CACHE_SIZE`] lengths; the plans are immutable and shared by threads.
pub(crate) fn plans(len: usize) -> PlanPair {
    static CACHE: OnceLock<Mutex<Vec<(usize, PlanPair)>>> = OnceLock::new();
    let cache = CACHE.get_or_init(|| Mutex::new(Vec::new()));
    // A poisoned lock only means another thread panicked while holding it; the Vec is valid.
    let mut entries = cache
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner);
    if let Some(pos) = entries.iter().position(|(l, _)| *l == len) {
        let entry = entries.remove(pos);
        let pair = entry.1.clone();
        entries.insert(0, entry);
        return pair;
    }
    let mut planner = RealFftPlanner::<f64>::new();
    let pair: PlanPair = (planner.plan_fft_forward(len), planner.plan_fft_inverse(len));
    entries.insert(0, (len, pair.clone()));
    entries.truncate(PLAN_CACHE_SIZE);
    pair
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
    /// FFT length if the FFT path is taken for `n` outputs and `k` weights, else `None`.
    fn fft_len(n: usize, k: usize, method: Method) -> Option<usize> {
        let use_fft = match method {
            Method::Direct => false,
            Method::Fft => true,
            Method::Auto => prefer_fft(n, k),
        };
        (use_fft && k > 0).then(|| fast_even_len(n + k - 1))
    }

    /// Prepares the convolution of series of length `n` with `kernel` (only its first `n`
    /// values matter; it is truncated to them).
    pub(crate) fn new(mut kernel: Vec<f64>, n: usize, method: Method) -> Self {
        kernel.truncate(n);
        let plan = match Self::fft_len(n, kernel.len(), method) {
            Some(len) => Self::fft_plan(&kernel, len),
            None => Plan::Direct,
        };
        CausalConvolution { n, kernel, plan }
    }

    /// [`Self::new`] followed by [`Self::apply_into`] of one series, with the kernel's and the
    /// series' forward transforms running concurrently (the result is bitwise the same).
    pub(crate) fn new_applied(
        mut kernel: Vec<f64>,
        method: Method,
        x: &[f64],
        out: &mut [f64],
    ) -> Self {
        let n = x.len();
        kernel.truncate(n);
        let Some(len) = Self::fft_len(n, kernel.len(), method) else {
            direct_into(&kernel, x, out);
            return CausalConvolution {
                n,
                kernel,
                plan: Plan::Direct,
            };
        };
        let (plan, mut scratch) = rayon::join(
            || Self::fft_plan(&kernel, len),
            || {
                let (forward, inverse) = plans(len);
                let mut scratch = Scratch::fft(len, &forward, &inverse);
                forward_into(&forward, x, &mut scratch);
                scratch
            },
        );
        let conv = CausalConvolution { n, kernel, plan };
        conv.finish_into(&mut scratch, out);
        conv
    }

    fn fft_plan(kernel: &[f64], len: usize) -> Plan {
        let (forward, inverse) = plans(len);
        let mut padded = vec![0.0; len];
        let scale = 1.0 / len as f64;
        for (p, c) in padded.iter_mut().zip(kernel) {
            *p = c * scale;
        }
        let mut kernel_spectrum = forward.make_output_vec();
        // Lengths come from the plan itself: the transform cannot fail.
        forward
            .process(&mut padded, &mut kernel_spectrum)
            .expect("FFT buffer lengths come from the plan");
        Plan::Fft {
            len,
            forward,
            inverse,
            kernel_spectrum,
        }
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
            } => Scratch::fft(*len, forward, inverse),
        }
    }

    /// `out = c ⋆ x` (causal, first `n` outputs). `x.len() == out.len() == n`.
    pub(crate) fn apply_into(&self, x: &[f64], out: &mut [f64], scratch: &mut Scratch) {
        debug_assert_eq!(x.len(), self.n);
        debug_assert_eq!(out.len(), self.n);
        match &self.plan {
            Plan::Direct => direct_into(&self.kernel, x, out),
            Plan::Fft { forward, .. } => {
                forward_into(forward, x, scratch);
                self.finish_into(scratch, out);
            }
        }
    }

    /// Multiplies the series spectrum in `scratch` by the kernel's and transforms back.
    fn finish_into(&self, scratch: &mut Scratch, out: &mut [f64]) {
        let Plan::Fft {
            inverse,
            kernel_spectrum,
            ..
        } = &self.plan
        else {
            return;
        };
        let Scratch {
            real,
            spectrum,
            fft,
        } = scratch;
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

impl Scratch {
    fn fft(
        len: usize,
        forward: &Arc<dyn RealToComplex<f64>>,
        inverse: &Arc<dyn ComplexToReal<f64>>,
    ) -> Self {
        Scratch {
            real: vec![0.0; len],
            spectrum: forward.make_output_vec(),
            fft: vec![Complex::default(); forward.get_scratch_len().max(inverse.get_scratch_len())],
        }
    }
}

/// Zero-padded forward transform of `x` into `scratch.spectrum`.
fn forward_into(forward: &Arc<dyn RealToComplex<f64>>, x: &[f64], scratch: &mut Scratch) {
    let n = x.len();
    scratch.real[..n].copy_from_slice(x);
    scratch.real[n..].fill(0.0);
    forward
        .process_with_scratch(&mut scratch.real, &mut scratch.spectrum, &mut scratch.fft)
        .expect("FFT buffer lengths come from the plan");
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
