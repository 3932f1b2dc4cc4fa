//! Fixed-gain Kalman filter throughput (run: `cargo bench -p gyrobias-benches --bench kalman`).
//! Outputs are preallocated once: this measures the recursion, not page faults.

use gyrocore::kalman::{DiscreteNoise, FixedGainKalman, Form};

fn main() {
    divan::main();
}

fn design() -> FixedGainKalman {
    let noise = DiscreteNoise::from_coefficients(200.0, 0.1667 / 60.0, 1200.0 / 216_000.0).unwrap();
    FixedGainKalman::with_bandwidth(noise, 10.0, Form::Standard).unwrap()
}

#[divan::bench(args = [1, 3])]
fn filter_1m_samples(bencher: divan::Bencher, axes: usize) {
    let kf = design();
    let z = gyrobias_benches::rate_series(1_000_000 * axes, 7);
    let (mut rate, mut bias) = (vec![0.0; z.len()], vec![0.0; z.len()]);
    let initial = kf.initial_state_from_first_sample(&z, axes).unwrap();
    bencher
        .counter(divan::counter::ItemsCount::new(z.len()))
        .bench_local(|| {
            let mut state = initial.clone();
            kf.filter_into(divan::black_box(&z), axes, &mut state, &mut rate, &mut bias)
                .unwrap();
            state
        });
}
