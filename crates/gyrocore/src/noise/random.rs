//! Seeded standard-normal streams for the noise simulator (private to `noise`).
//!
//! xoshiro256++ (Blackman & Vigna 2021) seeded through SplitMix64, Gaussian pairs by the
//! Box–Muller transform. Each simulated component of each axis draws from its own stream,
//! derived from `(seed, axis, component)`, so enabling one component or adding axes never
//! changes the samples of another.
//!
//! This is a private generator: the crate-wide seeded normals (`crate::random`) were not yet
//! available when the simulator was written.

/// One SplitMix64 step (Steele, Lea & Flood 2014): used to expand seeds.
fn splitmix64(state: &mut u64) -> u64 {
    *state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let mut z = *state;
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// A stream of independent N(0, 1) variates.
#[derive(Debug, Clone)]
pub(crate) struct NormalStream {
    s: [u64; 4],
    spare: Option<f64>,
}

impl NormalStream {
    /// The stream for `(seed, axis, component)`.
    pub(crate) fn new(seed: u64, axis: usize, component: u64) -> Self {
        let mut key = (axis as u64).wrapping_shl(8) ^ component;
        let mixed = splitmix64(&mut key);
        let mut state = seed ^ mixed;
        let s = [
            splitmix64(&mut state),
            splitmix64(&mut state),
            splitmix64(&mut state),
            splitmix64(&mut state),
        ];
        NormalStream { s, spare: None }
    }

    fn next_u64(&mut self) -> u64 {
        let s = &mut self.s;
        let result = s[0].wrapping_add(s[3]).rotate_left(23).wrapping_add(s[0]);
        let t = s[1] << 17;
        s[2] ^= s[0];
        s[3] ^= s[1];
        s[1] ^= s[2];
        s[0] ^= s[3];
        s[2] ^= t;
        s[3] = s[3].rotate_left(45);
        result
    }

    /// Uniform on (0, 1]: never 0, so the logarithm below is finite.
    fn uniform_open0(&mut self) -> f64 {
        ((self.next_u64() >> 11) + 1) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// The next N(0, 1) variate.
    pub(crate) fn next(&mut self) -> f64 {
        if let Some(z) = self.spare.take() {
            return z;
        }
        let r = (-2.0 * self.uniform_open0().ln()).sqrt();
        let phi = std::f64::consts::TAU * self.uniform_open0();
        let (s, c) = phi.sin_cos();
        self.spare = Some(r * s);
        r * c
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn moments_are_standard_normal() {
        let mut g = NormalStream::new(42, 0, 0);
        let n: usize = 400_000;
        let v: Vec<f64> = (0..n).map(|_| g.next()).collect();
        let mean = v.iter().sum::<f64>() / n as f64;
        let var = v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n as f64;
        let kurt = v.iter().map(|x| (x - mean).powi(4)).sum::<f64>() / n as f64 / (var * var);
        // 5 standard errors: se(mean) = 1/√n, se(var) = √(2/n), se(kurtosis) = √(24/n).
        assert!(mean.abs() < 5.0 / (n as f64).sqrt(), "{mean}");
        assert!((var - 1.0).abs() < 5.0 * (2.0 / n as f64).sqrt(), "{var}");
        assert!(
            (kurt - 3.0).abs() < 5.0 * (24.0 / n as f64).sqrt(),
            "{kurt}"
        );
    }

    #[test]
    fn streams_are_reproducible_and_distinct() {
        let a: Vec<f64> = {
            let mut g = NormalStream::new(7, 1, 2);
            (0..5).map(|_| g.next()).collect()
        };
        let b: Vec<f64> = {
            let mut g = NormalStream::new(7, 1, 2);
            (0..5).map(|_| g.next()).collect()
        };
        let c: Vec<f64> = {
            let mut g = NormalStream::new(7, 2, 2);
            (0..5).map(|_| g.next()).collect()
        };
        assert_eq!(a, b);
        assert_ne!(a, c);
    }
}
