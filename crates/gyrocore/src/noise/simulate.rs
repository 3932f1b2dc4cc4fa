//! Simulation of gyro (or accelerometer) rate noise with known IEEE-952 coefficients (SPEC §3).
//!
//! With sample period `t0 = 1/fs`, sample `k` of one axis is the sum of independent components
//!
//! | term | generator | Allan variance |
//! |---|---|---|
//! | quantisation Q | white *angle* noise `θ_k = Q·η_k` (k = 0..n), rate `(θ_{k+1} − θ_k)/t0` | `3Q²/τ²` |
//! | angle random walk N | white rate `N/√t0 · ξ_k` | `N²/τ` |
//! | bias instability B | flicker rate, one-sided PSD `B²/(π f)` (two-sided `B²/(2π f)`) by spectral shaping | `(0.664282·B)²` |
//! | rate random walk K | `Σ_{i≤k} K√t0 · ξ_i` | `K²τ/3` |
//! | rate ramp R | `R · k·t0` | `R²τ²/2` |
//! | AR(1) drift | `b_{k+1} = c·b_k + σ_e·ξ_k`, `b_0` from the stationary law | — |
//! | bias | constant | 0 |
//!
//! **Flicker by spectral shaping.** A complex white sequence `z = a + i·b` (a, b iid N(0, 1))
//! of length `L ≥ 2n` is transformed, multiplied by the real, even gain
//! `H(f_j) = √(B² / (2π f_j t0))` (`f_j = min(j, L−j)/(L·t0)`, `H(0) = 0`) and transformed back;
//! the first `n` samples of the real part are the flicker series. Unit-variance white noise has
//! the one-sided PSD `2t0`, so the result has the one-sided PSD `B²/(π f)` at every FFT
//! frequency from `1/(L t0)` to the Nyquist frequency, i.e. the two-sided `S(f) = B²/(2π f)` of
//! IEEE 952, whose Allan variance is `2 ln2/π · B² = (0.664282 B)²` for `τ ≫ t0`. Taking half of
//! a circular series of twice the length removes the wrap-around correlation; the missing
//! power below `1/(2n t0)` changes σ²(τ) by `O((τ/(n t0))²)`. Cost O(n log n) (rustfft).
//!
//! Normal deviates come from [`crate::random`] (xoshiro256++, polar method), one stream per
//! component and axis.
//!
//! The generated samples are in the rate unit of the coefficients (Q in u·s, N in u·√s, B in
//! u, K in u/√s, R in u/s for a rate unit u, e.g. deg/s).

use rayon::prelude::*;
use rustfft::FftPlanner;
use rustfft::num_complex::Complex;

use crate::random::NormalStream;
use crate::validate;
use crate::{Error, Result};

/// A first-order autoregressive (Gauss–Markov) drift `b_{k+1} = c·b_k + σ_e·ξ_k`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ar1 {
    /// Coefficient `c`, `|c| < 1` (correlation time `−t0/ln c` for `c > 0`).
    pub coefficient: f64,
    /// Driving noise standard deviation `σ_e` (rate unit).
    pub sigma: f64,
}

/// The coefficients of a simulated sensor axis, in the base units of the rate unit u.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct NoiseSpec {
    /// Quantisation noise Q (u·s, i.e. an angle).
    pub quantization: f64,
    /// Angle random walk N (u·√s).
    pub arw: f64,
    /// Bias instability B (u).
    pub bias_instability: f64,
    /// Rate random walk K (u/√s).
    pub rrw: f64,
    /// Rate ramp R (u/s).
    pub rate_ramp: f64,
    /// Optional AR(1) drift.
    pub ar1: Option<Ar1>,
    /// Constant bias (u).
    pub bias: f64,
}

impl NoiseSpec {
    fn validate(&self) -> Result<()> {
        validate::non_negative("quantization", self.quantization)?;
        validate::non_negative("arw", self.arw)?;
        validate::non_negative("bias_instability", self.bias_instability)?;
        validate::non_negative("rrw", self.rrw)?;
        if !self.rate_ramp.is_finite() {
            return Err(Error::invalid("rate_ramp", "must be finite"));
        }
        if !self.bias.is_finite() {
            return Err(Error::invalid("bias", "must be finite"));
        }
        if let Some(ar) = self.ar1 {
            if !(ar.coefficient.is_finite() && ar.coefficient.abs() < 1.0) {
                return Err(Error::invalid(
                    "ar1",
                    format!(
                        "coefficient must satisfy |c| < 1 (a stationary AR(1)), got {}",
                        ar.coefficient
                    ),
                ));
            }
            validate::non_negative("ar1", ar.sigma)?;
        }
        Ok(())
    }
}

/// The seed of the normal stream of one component of one axis: `(seed, axis, component)` mixed
/// by SplitMix64 (Steele, Lea & Flood 2014), so that every component of every axis has its own
/// stream and enabling one component or adding axes never changes the samples of another.
fn stream_seed(seed: u64, axis: usize, component: u64) -> u64 {
    let mix = |mut z: u64| {
        z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    };
    mix(seed ^ mix(((axis as u64) << 8) ^ component))
}

fn stream(seed: u64, axis: usize, component: u64) -> NormalStream {
    NormalStream::new(stream_seed(seed, axis, component))
}

/// Stream identifiers of the components (part of the reproducibility contract).
const WHITE: u64 = 1;
const QUANT: u64 = 2;
const FLICKER: u64 = 3;
const RRW: u64 = 4;
const AR1: u64 = 5;

/// Smallest `2^a·3^b·5^c ≥ min` (a length rustfft transforms with its fast radices).
fn smooth_length(min: usize) -> usize {
    let mut best = usize::MAX;
    let mut p5 = 1usize;
    while p5 < best {
        let mut p35 = p5;
        while p35 < best {
            let mut p = p35;
            while p < min {
                p *= 2;
            }
            best = best.min(p);
            p35 = p35.saturating_mul(3);
        }
        p5 = p5.saturating_mul(5);
    }
    best
}

/// Adds `n` samples of flicker rate noise with two-sided PSD `b²/(2π f)` to `out`.
fn add_flicker(out: &mut [f64], b: f64, rng: &mut NormalStream) {
    let n = out.len();
    let len = smooth_length(2 * n.max(1));
    let mut z: Vec<Complex<f64>> = (0..len)
        .map(|_| {
            let re = rng.next_normal();
            Complex::new(re, rng.next_normal())
        })
        .collect();
    let mut planner = FftPlanner::<f64>::new();
    planner.plan_fft_forward(len).process(&mut z);
    // Amplitude √(b²/(2π t0 f)) / len at f = j/(len·t0): t0 cancels, and b is kept out of the
    // square root, so no intermediate over- or underflows (b² overflowed for b ≳ 1e154).
    let len_f = len as f64;
    z[0] = Complex::new(0.0, 0.0);
    for (j, v) in z.iter_mut().enumerate().skip(1) {
        let jf = j.min(len - j) as f64;
        *v *= b * (len_f / (std::f64::consts::TAU * jf)).sqrt() / len_f;
    }
    planner.plan_fft_inverse(len).process(&mut z);
    for (o, v) in out.iter_mut().zip(&z) {
        *o += v.re;
    }
}

/// One axis of simulated rate noise (`n` samples at period `t0`).
pub fn simulate_axis(
    n: usize,
    t0: f64,
    spec: &NoiseSpec,
    seed: u64,
    axis: usize,
) -> Result<Vec<f64>> {
    validate::positive("fs", 1.0 / t0)?;
    spec.validate()?;
    let mut out: Vec<f64> = (0..n)
        .map(|k| spec.bias + spec.rate_ramp * (k as f64 * t0))
        .collect();
    if spec.arw > 0.0 {
        let s = spec.arw / t0.sqrt();
        let mut g = stream(seed, axis, WHITE);
        for o in &mut out {
            *o += s * g.next_normal();
        }
    }
    if spec.quantization > 0.0 {
        let s = spec.quantization / t0;
        let mut g = stream(seed, axis, QUANT);
        let mut previous = g.next_normal();
        for o in &mut out {
            let next = g.next_normal();
            *o += s * (next - previous);
            previous = next;
        }
    }
    if spec.bias_instability > 0.0 {
        let mut g = stream(seed, axis, FLICKER);
        add_flicker(&mut out, spec.bias_instability, &mut g);
    }
    if spec.rrw > 0.0 {
        let s = spec.rrw * t0.sqrt();
        let mut g = stream(seed, axis, RRW);
        let mut walk = 0.0;
        for o in &mut out {
            walk += s * g.next_normal();
            *o += walk;
        }
    }
    if let Some(ar) = spec.ar1 {
        if ar.sigma > 0.0 {
            let mut g = stream(seed, axis, AR1);
            let c = ar.coefficient;
            let mut state = ar.sigma / (1.0 - c * c).sqrt() * g.next_normal();
            for o in &mut out {
                *o += state;
                state = c * state + ar.sigma * g.next_normal();
            }
        }
    }
    Ok(out)
}

/// `axes` independent axes of simulated rate noise, row-major `(n, axes)`.
///
/// Axis `a` equals `simulate_axis(n, 1/fs, spec, seed, a)`: the same seed gives the same first
/// axes whatever `axes` is. Axes are generated in parallel.
pub fn simulate(n: usize, fs: f64, spec: &NoiseSpec, axes: usize, seed: u64) -> Result<Vec<f64>> {
    validate::positive("fs", fs)?;
    spec.validate()?;
    if n == 0 {
        return Err(Error::invalid("n", "must be >= 1"));
    }
    if axes == 0 {
        return Err(Error::invalid("axes", "must be >= 1"));
    }
    // A size too large to allocate is named after the larger of its two factors.
    let name = if axes > n { "axes" } else { "n" };
    let total = validate::product(name, n, axes)?;
    // One column per axis and the interleaved output.
    validate::allocatable::<f64>(name, validate::product(name, total, 2)?)?;
    let t0 = 1.0 / fs;
    let columns: Vec<Vec<f64>> = (0..axes)
        .into_par_iter()
        .map(|a| simulate_axis(n, t0, spec, seed, a))
        .collect::<Result<_>>()?;
    if axes == 1 {
        return Ok(columns.into_iter().next().unwrap_or_default());
    }
    let mut out = vec![0.0; total];
    for (a, col) in columns.iter().enumerate() {
        for (k, v) in col.iter().enumerate() {
            out[k * axes + a] = *v;
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::allan::{Column, DataType, Estimator, angle_series, variance};

    fn avar(rate: &[f64], t0: f64, m: usize) -> f64 {
        let x = angle_series(Column::contiguous(rate), t0, DataType::Rate).unwrap();
        variance(&x, t0, m, Estimator::Overlapping).unwrap().0
    }

    #[test]
    fn smooth_lengths() {
        assert_eq!(smooth_length(1), 1);
        assert_eq!(smooth_length(7), 8);
        assert_eq!(smooth_length(11), 12);
        assert_eq!(smooth_length(1001), 1024);
        assert_eq!(smooth_length(1_000_001), 1_012_500);
    }

    #[test]
    fn each_component_has_its_allan_variance() {
        let fs = 50.0;
        let t0 = 1.0 / fs;
        let n = 400_000;
        // White: σ²(τ) = N²/τ; at m = 1 the estimator has ≈ 2n/3 EDF → 0.3 % s.d.; 2 % margin.
        let spec = NoiseSpec {
            arw: 0.3,
            ..NoiseSpec::default()
        };
        let r = simulate(n, fs, &spec, 1, 1).unwrap();
        let v = avar(&r, t0, 10);
        assert!((v / (0.09 / (10.0 * t0)) - 1.0).abs() < 0.03, "{v}");
        // Quantisation: 3Q²/τ².
        let spec = NoiseSpec {
            quantization: 0.01,
            ..NoiseSpec::default()
        };
        let r = simulate(n, fs, &spec, 1, 2).unwrap();
        let tau = 4.0 * t0;
        let v = avar(&r, t0, 4);
        assert!((v / (3.0e-4 / (tau * tau)) - 1.0).abs() < 0.03, "{v}");
        // Flicker: (0.664282 B)² plateau; EDF of flicker at m = 100 is ≈ 5n/(4m) = 5000 → 2 %
        // s.d., 8 % margin.
        let spec = NoiseSpec {
            bias_instability: 2.0,
            ..NoiseSpec::default()
        };
        let r = simulate(n, fs, &spec, 1, 3).unwrap();
        let expect = (2.0 * std::f64::consts::LN_2 / std::f64::consts::PI) * 4.0;
        for m in [10, 100] {
            let v = avar(&r, t0, m);
            assert!((v / expect - 1.0).abs() < 0.08, "m={m}: {v} vs {expect}");
        }
        // Ramp: R²τ²/2 exactly (deterministic).
        let spec = NoiseSpec {
            rate_ramp: 0.5,
            ..NoiseSpec::default()
        };
        let r = simulate(1000, fs, &spec, 1, 4).unwrap();
        let tau = 20.0 * t0;
        assert!((avar(&r, t0, 20) / (0.125 * tau * tau) - 1.0).abs() < 1e-9);
    }

    #[test]
    fn axes_are_independent_of_axis_count() {
        let spec = NoiseSpec {
            arw: 1.0,
            bias_instability: 0.1,
            rrw: 0.01,
            ar1: Some(Ar1 {
                coefficient: 0.9,
                sigma: 0.1,
            }),
            ..NoiseSpec::default()
        };
        let one = simulate(500, 10.0, &spec, 1, 9).unwrap();
        let three = simulate(500, 10.0, &spec, 3, 9).unwrap();
        let col0: Vec<f64> = three.iter().step_by(3).copied().collect();
        assert_eq!(one, col0);
        let col1: Vec<f64> = three.iter().skip(1).step_by(3).copied().collect();
        assert_ne!(col0, col1);
    }

    #[test]
    fn bad_input() {
        let spec = NoiseSpec::default();
        assert!(simulate(0, 1.0, &spec, 1, 0).is_err());
        assert!(simulate(10, 0.0, &spec, 1, 0).is_err());
        assert!(simulate(10, 1.0, &spec, 0, 0).is_err());
        let bad = NoiseSpec { arw: -1.0, ..spec };
        assert!(simulate(10, 1.0, &bad, 1, 0).is_err());
        let bad = NoiseSpec {
            ar1: Some(Ar1 {
                coefficient: 1.0,
                sigma: 1.0,
            }),
            ..spec
        };
        assert!(simulate(10, 1.0, &bad, 1, 0).is_err());
    }
}
