//! Overlapping Allan variance kernel throughput (run: `cargo bench -p gyrobias-benches`).

use gyrocore::allan::{self, Column, DataType, Estimator, TauSpec, Taus};

fn main() {
    divan::main();
}

#[divan::bench(args = [100_000, 1_000_000, 10_000_000])]
fn oavar_octave(bencher: divan::Bencher, n: usize) {
    let data = gyrobias_benches::rate_series(n, 1);
    bencher.bench(|| {
        allan::analyse(
            Column::contiguous(divan::black_box(&data)),
            0.01,
            DataType::Rate,
            Estimator::Overlapping,
            &Taus::Spec(TauSpec::Octave),
            None,
        )
        .unwrap()
    });
}
