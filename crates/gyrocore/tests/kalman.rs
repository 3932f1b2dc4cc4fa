//! Integration tests of `gyrocore::kalman`: streaming, multi-axis layout and the response.

use gyrocore::kalman::{DiscreteNoise, FixedGainKalman, Form};
use gyrocore::random::NormalStream;

fn signal(n: usize, seed: u64) -> Vec<f64> {
    // A deterministic pseudo-random walk plus a sine.
    let mut stream = NormalStream::new(seed);
    let mut walk = 0.0;
    (0..n)
        .map(|i| {
            let u = stream.uniform() - 0.5;
            walk += 1e-2 * u;
            u + walk + (i as f64 * 0.01).sin()
        })
        .collect()
}

fn filters() -> Vec<FixedGainKalman> {
    let noise = DiscreteNoise::from_coefficients(200.0, 0.05, 1e-3).unwrap();
    vec![
        FixedGainKalman::with_bandwidth(noise, 10.0, Form::Standard).unwrap(),
        FixedGainKalman::new(noise, 1e-3, Form::Paper).unwrap(),
    ]
}

#[test]
fn chunked_equals_one_shot_for_every_axis_count() {
    for kf in filters() {
        for axes in [1, 2, 3, 4, 5, 7] {
            let z = signal(600 * axes, axes as u64);
            let mut one_state = kf.initial_state_from_first_sample(&z, axes).unwrap();
            let mut state = one_state.clone();
            let (rate, bias) = kf.filter(&z, axes, &mut one_state).unwrap();
            let (mut r, mut b) = (Vec::new(), Vec::new());
            for rows in [1, 17, 200, 382] {
                let take = rows * axes;
                let start = r.len();
                let (cr, cb) = kf
                    .filter(&z[start..start + take], axes, &mut state)
                    .unwrap();
                r.extend(cr);
                b.extend(cb);
            }
            assert_eq!(r, rate, "{axes} axes");
            assert_eq!(b, bias, "{axes} axes");
            assert_eq!(state, one_state);
            // Every axis equals filtering that column alone (the kernels share one step).
            for a in 0..axes {
                let col: Vec<f64> = z.iter().skip(a).step_by(axes).copied().collect();
                let mut s = kf.initial_state_from_first_sample(&col, 1).unwrap();
                let (rc, _) = kf.filter(&col, 1, &mut s).unwrap();
                let from_multi: Vec<f64> = rate.iter().skip(a).step_by(axes).copied().collect();
                assert_eq!(rc, from_multi, "axis {a} of {axes}");
            }
        }
    }
}

#[test]
fn estimates_of_state_are_the_last_outputs_and_x0_round_trips() {
    for kf in filters() {
        let z = signal(300, 3);
        let mut st = kf.initial_state(&[1.5], &[-0.25]).unwrap();
        let (r0, b0) = kf.estimates(&st).unwrap();
        assert!((r0[0] - 1.5).abs() < 1e-14 && (b0[0] + 0.25).abs() < 1e-14);
        let (rate, bias) = kf.filter(&z, 1, &mut st).unwrap();
        let (r, b) = kf.estimates(&st).unwrap();
        assert_eq!((r[0], b[0]), (rate[299], bias[299]));
        // The state records the same estimates and the rows processed.
        assert_eq!((st.rate(), st.bias()), (&r[..], &b[..]));
        assert_eq!(st.samples(), 300);
    }
}

#[test]
fn frequency_response_matches_dft_of_impulse_response() {
    for kf in filters() {
        let n = 1 << 16;
        let mut z = vec![0.0; n];
        z[0] = 1.0;
        let mut st = kf.initial_state(&[0.0], &[0.0]).unwrap();
        let (h, _) = kf.filter(&z, 1, &mut st).unwrap();
        let fs = 200.0;
        let freqs = [0.0, 0.5, 3.0, 10.0, 60.0, 99.0];
        let (mut re, mut im) = (vec![0.0; 6], vec![0.0; 6]);
        kf.frequency_response_into(&freqs, &mut re, &mut im)
            .unwrap();
        for (i, f) in freqs.iter().enumerate() {
            let w = std::f64::consts::TAU * f / fs;
            let (mut sr, mut si) = (0.0, 0.0);
            for (k, hk) in h.iter().enumerate() {
                sr += hk * (w * k as f64).cos();
                si -= hk * (w * k as f64).sin();
            }
            // The impulse response decays like p^k; the paper form's p is close to 1, so the
            // truncated tail p^n/(1 − p) bounds the difference.
            let tail = kf.pole().powi(n as i32) / (1.0 - kf.pole());
            let tol = 1e-9 + 2.0 * tail;
            assert!(
                (sr - re[i]).abs() < tol && (si - im[i]).abs() < tol,
                "f = {f}"
            );
        }
    }
}
