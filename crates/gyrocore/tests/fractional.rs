//! SPEC §4 check values and cross-module behaviour of `gyrocore::fractional` through its public
//! API (differencing, ARFIMA simulation, ELW estimation).

use gyrocore::fractional::arfima::{Kind, arfima, autocovariance};
use gyrocore::fractional::elw::{Level, default_bandwidth, elw, elw_rows, level_weight};
use gyrocore::fractional::{Method, diff, diff_rows, integrate, integrate_rows, weights};

#[test]
fn spec_check_values() {
    assert_eq!(
        diff(&[0.0, 1.0, 2.0, 3.0, 4.0], 1.0).unwrap(),
        [0.0, 1.0, 1.0, 1.0, 1.0]
    );
    // Δ^{−d}Δ^{d}x = x to 1e-14 (direct evaluation).
    let x: Vec<f64> = (0..200)
        .map(|i| (f64::from(i) * 0.37).sin() + 1.0)
        .collect();
    for d in [0.25, 0.5, 0.9, 1.5] {
        let y = diff_rows(&x, x.len(), d, Method::Direct).unwrap();
        let back = integrate_rows(&y, y.len(), d, Method::Direct).unwrap();
        for (a, b) in back.iter().zip(&x) {
            assert!((a - b).abs() < 1e-14 * 2.0, "d {d}: {a} vs {b}");
        }
    }
    // Default bandwidth and standard error at n = 2000: m = 139, 1/(2√m) = 0.042.
    assert_eq!(default_bandwidth(2000), 139);
    assert_eq!(level_weight(0.5), 1.0);
    assert!(level_weight(0.75).abs() < 1e-15);
    assert!((level_weight(0.625) - 0.5).abs() < 1e-15);
}

#[test]
fn weights_are_the_binomial_series() {
    // π_l(d) = (−1)^l C(d, l): for d = 3, 1 −3 3 −1 0 …
    assert_eq!(weights(3.0, 6).unwrap(), [1.0, -3.0, 3.0, -1.0, 0.0, 0.0]);
    // Integration weights of order 1 are all ones (cumulative sum).
    assert_eq!(integrate(&[1.0, 2.0, 3.0], 1.0).unwrap(), [1.0, 3.0, 6.0]);
}

#[test]
fn type_two_arfima_whitens_back_and_elw_finds_half() {
    let n = 4000;
    let mut x = arfima(n, 0.5, 2.5, 1, 2024, Kind::TypeII).unwrap();
    for v in &mut x {
        *v += 300.0; // a gyro bias
    }
    let e = elw(&x, None, (-0.5, 2.0), Level::Shimotsu).unwrap();
    // s.e. 1/(2√m) = 0.034 at m = 219; 4 s.e.
    assert!((e.d - 0.5).abs() < 0.14, "{e:?}");
    assert!((e.standard_error - 0.5 / (e.m as f64).sqrt()).abs() < 1e-15);
}

#[test]
fn stationary_batch_variance_matches_gamma0() {
    let (n, rows, d) = (32, 3000, 0.3);
    let x = arfima(n, d, 1.0, rows, 5, Kind::Stationary).unwrap();
    let g0 = autocovariance(d, 1.0, 1).unwrap()[0];
    let var = x.iter().map(|v| v * v).sum::<f64>() / x.len() as f64;
    // Per replication the mean of x_t² over 32 correlated samples has s.d. ≤ √2·γ(0); over
    // 3000 replications the s.e. is ≤ 0.026·γ(0): 5 s.e.
    assert!((var / g0 - 1.0).abs() < 0.13, "{var} vs {g0}");
    let est = elw_rows(&x, n, None, (-0.5, 2.0), Level::Shimotsu).unwrap();
    assert_eq!(est.len(), rows);
}
