//! Integration checks of the [TS] toolkit through the public gyrocore API (SPEC §7–9 values).

use gyrocore::fir::{self, Mode, Padding};
use gyrocore::spectral::{self, LssaOptions};
use gyrocore::thermal;

#[test]
fn ts_filter_then_ar1_gives_spec_coefficient() {
    // SPEC §9: white noise through the 16 Hz [TS] filter gives c ≈ +0.846 ([TS] prints −0.9).
    let f = fir::kaiser_lowpass(100.0, 14.0, 18.0, 0.0001, 100.0).unwrap();
    assert_eq!(f.numtaps(), 171);
    // Deterministic white noise.
    let x = gyrocore::random::normal_vec(200_000, 0x2545_f491_4f6c_dd1d);
    let y = fir::filter(&f.taps, &x, Mode::Causal).unwrap();
    let fit = thermal::fit_ar1(&y[170..], 0.01, true).unwrap();
    assert!((fit.c - 0.846).abs() < 0.005, "c = {}", fit.c);
    assert!(fit.beta > 0.0);
    // Zero phase keeps length and a constant level.
    let z = fir::filter(
        &f.taps,
        &vec![1.0; 1000],
        Mode::ZeroPhase {
            padding: Padding::Odd,
            padlen: 513,
        },
    )
    .unwrap();
    assert!(z.iter().all(|v| (v - 1.0).abs() < 3e-5));
}

#[test]
fn lssa_finds_a_sinusoid_in_gappy_data_and_the_critical_value_matches() {
    let t: Vec<f64> = (0..600)
        .map(|i| f64::from(i) * 0.7 + if i >= 300 { 40.0 } else { 0.0 })
        .collect();
    let y: Vec<f64> = t
        .iter()
        .enumerate()
        .map(|(i, &v)| {
            (2.0 * std::f64::consts::PI * 0.2 * v).sin()
                + 0.5 * (f64::from(i as u32) * 0.618).fract()
        })
        .collect();
    let freqs: Vec<f64> = (1..500).map(|k| f64::from(k) * 0.0014).collect();
    let r = spectral::lssa(&t, &y, &freqs, &LssaOptions::default()).unwrap();
    let best = (0..freqs.len())
        .max_by(|&a, &b| r.spectrum[a].total_cmp(&r.spectrum[b]))
        .unwrap();
    assert!((freqs[best] - 0.2).abs() < 0.002);
    let crit = spectral::critical_value(600, r.n_known, 0.01).unwrap();
    assert!((crit - 0.01530931).abs() < 5e-9);
    assert!(r.spectrum[best] > crit);
}
