//! Deterministic fixtures shared by the gyrocore benchmarks.

/// A reproducible white-noise-plus-random-walk rate series (normal deviates from
/// `gyrocore::random`).
pub fn rate_series(n: usize, seed: u64) -> Vec<f64> {
    let mut walk = 0.0;
    gyrocore::random::normal_vec(n, seed)
        .into_iter()
        .map(|g| {
            walk += 1e-3 * g;
            0.5 + g + walk
        })
        .collect()
}
