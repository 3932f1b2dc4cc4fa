//! Seeded pseudo-random numbers for the simulators (ARFIMA, noise synthesis).
//!
//! The generator is xoshiro256++ (Blackman & Vigna 2019, crate `rand_xoshiro`) seeded from a
//! `u64` through SplitMix64 (`SeedableRng::seed_from_u64`). Standard normal deviates come from
//! Marsaglia's polar method (Marsaglia & Bray 1964), using both values of each accepted pair:
//!
//! ```text
//! u, v ~ U(−1, 1) until s = u² + v² ∈ (0, 1);   z₁ = u·√(−2 ln s / s),   z₂ = v·√(−2 ln s / s)
//! ```
//!
//! Uniforms use the top 53 bits of each 64-bit output: `U[0, 1) = (r >> 11)·2⁻⁵³`. Uniform
//! integers in `[0, n)` (the bootstrap's resampling indices) use Lemire's multiply-and-reject
//! method (Lemire 2019, "Fast random integer generation in an interval", ACM TOMACS 29(1)),
//! exactly unbiased: `m = r·n` as a 128-bit product, the high word is the draw unless the low
//! word falls below `2⁶⁴ mod n`, in which case `r` is drawn again.
//!
//! This is the one generator of gyrobias: every random number the library draws (simulation,
//! bootstrap) comes from it.
//!
//! **Reproducibility.** The same seed gives the same sequence, bit for bit, on every run of the
//! same build: both algorithms are fixed here (they do not follow a `rand` version's choice).
//! Across platforms the only possible difference is the last-bit rounding of the C library's
//! `ln`. Deviates are consumed in order, so [`normal_vec`]`(n, seed)` is a prefix of
//! `normal_vec(n + k, seed)`.

use rand_xoshiro::Xoshiro256PlusPlus;
use rand_xoshiro::rand_core::{Rng, SeedableRng};

/// A stream of standard normal deviates from a seed (see the module docs).
#[derive(Debug, Clone)]
pub struct NormalStream {
    rng: Xoshiro256PlusPlus,
    spare: Option<f64>,
}

impl NormalStream {
    /// A stream started from `seed`.
    pub fn new(seed: u64) -> Self {
        NormalStream {
            rng: Xoshiro256PlusPlus::seed_from_u64(seed),
            spare: None,
        }
    }

    /// The next raw 64-bit output of the generator (e.g. seeds for independent streams).
    pub fn next_u64(&mut self) -> u64 {
        self.rng.next_u64()
    }

    /// A uniform deviate in `[0, 1)` with 53 random bits.
    pub fn uniform(&mut self) -> f64 {
        (self.rng.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// A uniform integer in `[0, n)` (Lemire's unbiased method; see the module docs).
    /// `n = 0` is an empty range and returns 0 without drawing.
    pub fn below(&mut self, n: u64) -> u64 {
        if n == 0 {
            return 0;
        }
        let mut m = u128::from(self.rng.next_u64()) * u128::from(n);
        #[allow(clippy::cast_possible_truncation)]
        let mut low = m as u64;
        if low < n {
            let threshold = n.wrapping_neg() % n; // 2⁶⁴ mod n
            while low < threshold {
                m = u128::from(self.rng.next_u64()) * u128::from(n);
                #[allow(clippy::cast_possible_truncation)]
                {
                    low = m as u64;
                }
            }
        }
        #[allow(clippy::cast_possible_truncation)]
        let high = (m >> 64) as u64;
        high
    }

    /// The next standard normal deviate.
    pub fn next_normal(&mut self) -> f64 {
        if let Some(z) = self.spare.take() {
            return z;
        }
        loop {
            let u = 2.0 * self.uniform() - 1.0;
            let v = 2.0 * self.uniform() - 1.0;
            let s = u * u + v * v;
            if s > 0.0 && s < 1.0 {
                let f = (-2.0 * s.ln() / s).sqrt();
                self.spare = Some(v * f);
                return u * f;
            }
        }
    }

    /// Fills `out` with standard normal deviates, in stream order.
    pub fn fill(&mut self, out: &mut [f64]) {
        for o in out {
            *o = self.next_normal();
        }
    }
}

/// `n` standard normal deviates from `seed` (see the module docs for reproducibility).
pub fn normal_vec(n: usize, seed: u64) -> Vec<f64> {
    let mut out = vec![0.0; n];
    NormalStream::new(seed).fill(&mut out);
    out
}

/// `n` uniform deviates in `[0, 1)` from `seed` (53 random bits each).
pub fn uniform_vec(n: usize, seed: u64) -> Vec<f64> {
    let mut s = NormalStream::new(seed);
    (0..n).map(|_| s.uniform()).collect()
}

/// `k` seeds for independent streams derived from `seed` (the first `k` raw outputs of the
/// stream seeded with it): one call gives a reproducible seed per axis, per unit, ….
pub fn seeds(k: usize, seed: u64) -> Vec<u64> {
    let mut s = NormalStream::new(seed);
    (0..k).map(|_| s.next_u64()).collect()
}

/// `n` normal deviates with standard deviation `sigma` from `seed` (`sigma · normal_vec`).
pub fn scaled_normal_vec(n: usize, sigma: f64, seed: u64) -> Vec<f64> {
    let mut out = normal_vec(n, seed);
    for v in &mut out {
        *v *= sigma;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn same_seed_same_output_and_prefix_property() {
        let a = normal_vec(1001, 42);
        let b = normal_vec(1001, 42);
        assert_eq!(a, b);
        let c = normal_vec(500, 42);
        assert_eq!(&a[..500], &c[..]);
        assert_ne!(normal_vec(10, 43), normal_vec(10, 42));
    }

    #[test]
    fn uniform_and_seeds() {
        let u = uniform_vec(100_000, 5);
        assert!(u.iter().all(|v| (0.0..1.0).contains(v)));
        let mean = u.iter().sum::<f64>() / u.len() as f64;
        // s.e. of the mean of U(0, 1): √(1/12/n) = 0.00091; 5 s.e.
        assert!((mean - 0.5).abs() < 0.0046, "mean {mean}");
        let s = seeds(3, 9);
        assert_eq!(s, seeds(3, 9));
        assert!(s[0] != s[1] && s[1] != s[2]);
        assert_eq!(&seeds(5, 9)[..3], &s[..]);
    }

    #[test]
    fn below_is_uniform_and_in_range() {
        let mut s = NormalStream::new(11);
        let n = 7_u64;
        let draws = 70_000;
        let mut counts = [0_usize; 7];
        for _ in 0..draws {
            let v = s.below(n);
            assert!(v < n);
            counts[usize::try_from(v).unwrap()] += 1;
        }
        // Pearson χ² with 6 degrees of freedom: P(χ² > 22.46) = 0.001.
        let expected = draws as f64 / n as f64;
        let chi2: f64 = counts
            .iter()
            .map(|&c| (c as f64 - expected).powi(2) / expected)
            .sum();
        assert!(chi2 < 22.46, "chi2 {chi2}, counts {counts:?}");
        assert_eq!(s.below(0), 0);
        assert_eq!(s.below(1), 0);
        // Near 2⁶⁴ the rejection path runs and must still stay in range.
        let big = u64::MAX - 3;
        for _ in 0..1000 {
            assert!(s.below(big) < big);
        }
    }

    #[test]
    fn moments_are_standard_normal() {
        let n = 200_000;
        let z = normal_vec(n, 7);
        let mean = z.iter().sum::<f64>() / n as f64;
        let var = z.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1) as f64;
        let kurt = z.iter().map(|v| (v - mean).powi(4)).sum::<f64>() / n as f64 / (var * var);
        // 5 standard errors: s.e.(mean) = 1/√n = 0.0022, s.e.(var) = √(2/n) = 0.0032,
        // s.e.(kurtosis) = √(24/n) = 0.011.
        assert!(mean.abs() < 0.012, "mean {mean}");
        assert!((var - 1.0).abs() < 0.016, "var {var}");
        assert!((kurt - 3.0).abs() < 0.055, "kurtosis {kurt}");
        // Tail probability P(|z| > 2) = 0.0455, s.e. √(p(1−p)/n) = 0.00047.
        let tail = z.iter().filter(|v| v.abs() > 2.0).count() as f64 / n as f64;
        assert!((tail - 0.0455).abs() < 0.0024, "tail {tail}");
    }
}
