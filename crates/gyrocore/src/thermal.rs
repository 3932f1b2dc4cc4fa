//! First-order autoregressive drift fits and temperature interpolation of noise parameters
//! (\[TS\] §4, SPEC §9).
//!
//! **AR(1).** $b_{k+1} = c\,b_k + e_k$ fitted by least squares without intercept (after the
//! optional removal of the mean):
//! $$ \hat c = \frac{\sum_k b_k b_{k+1}}{\sum_k b_k^2},\quad s_e^2 = \frac{RSS}{n-2},\quad
//!    se(\hat c) = \sqrt{s_e^2/\textstyle\sum_k b_k^2} \approx \sqrt{(1-c^2)/n}, $$
//! with the sums over the $n-1$ pairs and $n$ the number of samples. **Sign convention**: \[TS\]'s
//! tables follow $b_{k+1} + C_{AR} b_k = e$ (its white noise low-passed by its own Kaiser filters
//! gives $c$ = +0.961/+0.844/+0.671 where \[TS\] prints ≈ −0.96/−0.9/−0.7), so
//! $C_{AR} = -c$; both are reported. For $0 < c < 1$ the equivalent first-order Gauss–Markov
//! process has $\beta = -\ln(c)/\Delta t$ (correlation time $1/\beta$) and stationary standard
//! deviation $s_e/\sqrt{1-c^2}$.
//!
//! **Temperature interpolation** of one parameter given at distinct temperatures: piecewise
//! linear, PCHIP (Fritsch–Carlson monotone cubic with SciPy's `PchipInterpolator` end
//! conditions), or a least-squares polynomial of low degree. Evaluation outside the calibrated
//! range is refused unless extrapolation is asked for (then the end segment, end cubic or the
//! polynomial is continued).

use crate::{Error, Result, validate};

/// Least-squares AR(1) fit (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ar1Fit {
    /// $\hat c$ in $b_{k+1} = c\,b_k + e$.
    pub c: f64,
    /// Standard error of $\hat c$.
    pub c_std_error: f64,
    /// Innovation standard deviation $s_e$.
    pub sigma_e: f64,
    /// Mean removed before the fit (0 if not asked).
    pub mean: f64,
    /// Number of samples $n$.
    pub n: usize,
    /// Gauss–Markov rate $\beta = -\ln c/\Delta t$ (1/s); NaN unless $0 < c < 1$.
    pub beta: f64,
    /// Stationary standard deviation $s_e/\sqrt{1-c^2}$; NaN unless $|c| < 1$.
    pub process_std: f64,
}

/// Fits $b_{k+1} = c\,b_k + e$ to `x` sampled every `dt` seconds (see the module docs).
///
/// Errors: non-finite `x`; fewer than 3 samples; `dt` ≤ 0; a series that is constant (after
/// removing the mean when `demean`) or zero.
pub fn fit_ar1(x: &[f64], dt: f64, demean: bool) -> Result<Ar1Fit> {
    validate::finite("x", x)?;
    validate::min_len("x", x.len(), 3)?;
    validate::positive("dt", dt)?;
    let n = x.len();
    let mean = if demean {
        validate::neumaier_sum(x.iter().copied()) / n as f64
    } else {
        0.0
    };
    let (mut sxx, mut sxy) = (0.0, 0.0);
    for k in 0..n - 1 {
        let a = x[k] - mean;
        let b = x[k + 1] - mean;
        sxx += a * a;
        sxy += a * b;
    }
    let scale: f64 = x.iter().map(|v| (v - mean) * (v - mean)).sum();
    if sxx <= 1e-300 || sxx <= 1e-24 * scale {
        return Err(Error::Singular {
            reason:
                "x is constant (zero after removing its mean): the AR(1) coefficient is undefined"
                    .into(),
        });
    }
    let c = sxy / sxx;
    // Second pass: Σ(b_{k+1} − c b_k)² directly (Σb² − c Σ b b' cancels for c near 1).
    let rss: f64 = (0..n - 1)
        .map(|k| {
            let e = (x[k + 1] - mean) - c * (x[k] - mean);
            e * e
        })
        .sum();
    let s2 = rss / (n - 2) as f64;
    let beta = if c > 0.0 && c < 1.0 {
        -c.ln() / dt
    } else {
        f64::NAN
    };
    let process_std = if c.abs() < 1.0 {
        (s2 / (1.0 - c * c)).sqrt()
    } else {
        f64::NAN
    };
    Ok(Ar1Fit {
        c,
        c_std_error: (s2 / sxx).sqrt(),
        sigma_e: s2.sqrt(),
        mean,
        n,
        beta,
        process_std,
    })
}

/// Interpolation method of [`interpolate`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Method {
    /// Piecewise linear.
    Linear,
    /// Piecewise cubic Hermite, shape preserving (Fritsch–Carlson, SciPy's `PchipInterpolator`).
    Pchip,
    /// Least-squares polynomial of the given degree (≤ number of temperatures − 1).
    Polynomial(usize),
}

impl Method {
    /// Parses `"linear"`, `"pchip"` or `"polynomial"` (of degree `degree`, which the other
    /// methods ignore).
    pub fn parse(name: &str, degree: usize) -> Result<Self> {
        match name {
            "linear" => Ok(Method::Linear),
            "pchip" => Ok(Method::Pchip),
            "polynomial" => Ok(Method::Polynomial(degree)),
            other => Err(Error::invalid(
                "method",
                format!("must be 'linear', 'pchip' or 'polynomial', got {other:?}"),
            )),
        }
    }
}

/// Sorted, validated nodes.
/// Checks calibration temperatures: finite and distinct (any number of them, one included).
///
/// # Errors
/// [`Error::NonFinite`] or [`Error::InvalidParameter`] naming `temperatures`.
pub fn check_temperatures(x: &[f64]) -> Result<()> {
    validate::finite("temperatures", x)?;
    let mut sorted = x.to_vec();
    sorted.sort_by(f64::total_cmp);
    for w in sorted.windows(2) {
        #[allow(clippy::float_cmp)] // exact repetition is what is refused
        if w[0] == w[1] {
            return Err(Error::invalid(
                "temperatures",
                format!("must be distinct, {} is given twice", w[0]),
            ));
        }
    }
    Ok(())
}

fn nodes(x: &[f64], y: &[f64]) -> Result<(Vec<f64>, Vec<f64>)> {
    check_temperatures(x)?;
    validate::finite("values", y)?;
    if x.len() != y.len() {
        return Err(Error::ShapeMismatch {
            name: "values",
            reason: format!("{} values for {} temperatures", y.len(), x.len()),
        });
    }
    validate::min_len("temperatures", x.len(), 2)?;
    let mut idx: Vec<usize> = (0..x.len()).collect();
    idx.sort_by(|&a, &b| x[a].total_cmp(&x[b]));
    Ok((
        idx.iter().map(|&i| x[i]).collect(),
        idx.iter().map(|&i| y[i]).collect(),
    ))
}

/// `e` with `2^e <= v < 2^(e+1)` for finite `v > 0` (subnormals included); 0 for `v == 0`.
fn binary_exponent(v: f64) -> i32 {
    if v == 0.0 {
        return 0;
    }
    // Scale subnormals into the normal range first (exact), then read the biased exponent.
    let (v, shift) = if v < f64::MIN_POSITIVE {
        (v * 2f64.powi(64), 64)
    } else {
        (v, 0)
    };
    ((v.to_bits() >> 52) & 0x7ff) as i32 - 1023 - shift
}

/// `v · 2^e`, in steps that never overflow the scale factor itself; a single rounding at most
/// (only the last step can leave the normal range).
fn times_pow2(mut v: f64, mut e: i32) -> f64 {
    while e > 512 {
        v *= 2f64.powi(512);
        e -= 512;
    }
    while e < -512 {
        v *= 2f64.powi(-512);
        e += 512;
    }
    v * 2f64.powi(e)
}

/// PCHIP derivatives at the nodes (SciPy's `PchipInterpolator._find_derivatives`).
fn pchip_slopes(x: &[f64], y: &[f64]) -> Vec<f64> {
    let k = x.len();
    let h: Vec<f64> = x.windows(2).map(|w| w[1] - w[0]).collect();
    let m: Vec<f64> = (0..k - 1).map(|i| (y[i + 1] - y[i]) / h[i]).collect();
    if k == 2 {
        return vec![m[0], m[0]];
    }
    let mut d = vec![0.0; k];
    for i in 1..k - 1 {
        let (m0, m1) = (m[i - 1], m[i]);
        // Signs compared directly: the product m0·m1 underflows to 0 for tiny slopes of
        // the same sign, which would wrongly flatten the curve there.
        if m0 == 0.0 || m1 == 0.0 || (m0 > 0.0) != (m1 > 0.0) {
            d[i] = 0.0;
        } else {
            let w1 = 2.0 * h[i] + h[i - 1];
            let w2 = h[i] + 2.0 * h[i - 1];
            d[i] = (w1 + w2) / (w1 / m0 + w2 / m1);
        }
    }
    // np.sign: 0 for 0 (f64::signum gives ±1 there).
    let sign = |v: f64| if v == 0.0 { 0.0 } else { v.signum() };
    let edge = |h0: f64, h1: f64, m0: f64, m1: f64| {
        let d = ((2.0 * h0 + h1) * m0 - h0 * m1) / (h0 + h1);
        if sign(d) != sign(m0) {
            0.0
        } else if sign(m0) != sign(m1) && d.abs() > 3.0 * m0.abs() {
            3.0 * m0
        } else {
            d
        }
    };
    d[0] = edge(h[0], h[1], m[0], m[1]);
    d[k - 1] = edge(h[k - 2], h[k - 3], m[k - 2], m[k - 3]);
    d
}

/// Interpolates the parameter values `y` given at temperatures `x` (any order, distinct) at
/// `at`. Outside `[min x, max x]` an error names the offending temperature unless `extrapolate`.
///
/// Errors: non-finite input; fewer than 2 temperatures (or `degree + 1` for a polynomial);
/// duplicate temperatures; lengths that differ; out-of-range `at` without `extrapolate`.
pub fn interpolate(
    x: &[f64],
    y: &[f64],
    method: Method,
    at: &[f64],
    extrapolate: bool,
) -> Result<Vec<f64>> {
    let (xs, ys) = nodes(x, y)?;
    validate::finite("temperature", at)?;
    let k = xs.len();
    let (lo, hi) = (xs[0], xs[k - 1]);
    if !extrapolate {
        if let Some(&t) = at.iter().find(|&&t| t < lo || t > hi) {
            return Err(Error::invalid(
                "temperature",
                format!(
                    "{t} lies outside the calibrated range [{lo}, {hi}]; pass extrapolate=True to evaluate it anyway"
                ),
            ));
        }
    }
    let segment = |t: f64| -> usize {
        // Index i with xs[i] <= t < xs[i+1], clamped to the end segments.
        match xs.partition_point(|&v| v <= t) {
            0 => 0,
            p if p >= k => k - 2,
            p => p - 1,
        }
    };
    match method {
        Method::Linear => Ok(at
            .iter()
            .map(|&t| {
                let i = segment(t);
                let r = (t - xs[i]) / (xs[i + 1] - xs[i]);
                ys[i] + r * (ys[i + 1] - ys[i])
            })
            .collect()),
        Method::Pchip => {
            // PCHIP is homogeneous in y. Work on y·2^−e with max|y·2^−e| in [1, 2): exact for
            // normal numbers (results are bit-identical to the unscaled form), and keeps the
            // harmonic-mean slopes w/m from overflowing on subnormal or tiny-span data.
            let e = binary_exponent(ys.iter().fold(0.0_f64, |a, &v| a.max(v.abs())));
            let ys: Vec<f64> = ys.iter().map(|&v| times_pow2(v, -e)).collect();
            let d = pchip_slopes(&xs, &ys);
            Ok(at
                .iter()
                .map(|&t| {
                    let i = segment(t);
                    let h = xs[i + 1] - xs[i];
                    let s = (t - xs[i]) / h;
                    let h00 = (1.0 + 2.0 * s) * (1.0 - s) * (1.0 - s);
                    let h10 = s * (1.0 - s) * (1.0 - s);
                    let h01 = s * s * (3.0 - 2.0 * s);
                    let h11 = s * s * (s - 1.0);
                    times_pow2(
                        h00 * ys[i] + h10 * h * d[i] + h01 * ys[i + 1] + h11 * h * d[i + 1],
                        e,
                    )
                })
                .collect())
        }
        Method::Polynomial(degree) => {
            if k <= degree {
                return Err(Error::invalid(
                    "degree",
                    format!(
                        "degree {degree} needs at least {} temperatures, got {k}",
                        degree.saturating_add(1)
                    ),
                ));
            }
            // Least squares in the scaled variable z = (t − centre)/half-range (conditioning).
            let centre = 0.5 * (lo + hi);
            let half = 0.5 * (hi - lo);
            let p = degree + 1;
            let a =
                nalgebra::DMatrix::from_fn(k, p, |r, c| ((xs[r] - centre) / half).powi(c as i32));
            let b = nalgebra::DVector::from_column_slice(&ys);
            let coef = a
                .svd(true, true)
                .solve(&b, 1e-12)
                .map_err(|e| Error::Singular {
                    reason: format!("polynomial fit failed: {e}"),
                })?;
            Ok(at
                .iter()
                .map(|&t| {
                    let z = (t - centre) / half;
                    coef.iter().rev().fold(0.0, |acc, &c| acc * z + c)
                })
                .collect())
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn temperatures_finite_and_distinct() {
        assert!(check_temperatures(&[20.0]).is_ok());
        assert!(check_temperatures(&[20.0, -5.0, 40.0]).is_ok());
        let e = check_temperatures(&[20.0, -5.0, 20.0])
            .unwrap_err()
            .to_string();
        assert!(e.contains("distinct") && e.contains("20"), "{e}");
        assert!(check_temperatures(&[f64::NAN]).is_err());
    }

    #[test]
    fn method_parse() {
        assert_eq!(Method::parse("pchip", 7).unwrap(), Method::Pchip);
        assert_eq!(
            Method::parse("polynomial", 3).unwrap(),
            Method::Polynomial(3)
        );
        let err = Method::parse("cubic", 3).unwrap_err().to_string();
        assert!(err.contains("method") && err.contains("cubic"), "{err}");
    }

    #[test]
    fn ar1_exact_on_geometric_series() {
        let x: Vec<f64> = (0..50).map(|k| 0.8_f64.powi(k)).collect();
        let f = fit_ar1(&x, 0.01, false).unwrap();
        assert!((f.c - 0.8).abs() < 1e-14);
        assert!(f.sigma_e < 1e-12);
        assert!((f.beta - (-0.8_f64.ln() / 0.01)).abs() < 1e-9);
        assert!(fit_ar1(&[1.0, 1.0, 1.0], 0.01, true).is_err());
        assert!(fit_ar1(&[1.0, 2.0], 0.01, true).is_err());
    }

    #[test]
    fn pchip_tiny_slopes_keep_their_harmonic_mean() {
        // Equal tiny slopes of one sign: the harmonic mean is that slope (the product test
        // m0·m1 <= 0 used to underflow to 0 and flatten it).
        let x = [0.0, 1.0, 2.0, 3.0];
        let y = [0.0, 1e-170, 2e-170, 3e-170];
        let d = pchip_slopes(&x, &y);
        assert!((d[1] - 1e-170).abs() < 1e-184 && (d[2] - 1e-170).abs() < 1e-184);
        assert_eq!(binary_exponent(1.0), 0);
        assert_eq!(binary_exponent(3.0), 1);
        assert_eq!(binary_exponent(f64::MIN_POSITIVE), -1022);
        assert_eq!(binary_exponent(5e-324), -1074);
        assert_eq!(times_pow2(times_pow2(2.2e-311, 1040), -1040), 2.2e-311);
        // Subnormal data: interpolated exactly like the data scaled to O(1).
        let y = [0.0, 0.0, 0.0, 0.0, 2.2e-311];
        let x = [-30.0, -5.0, 0.0, 30.0, 60.0];
        let at = [45.0, 59.0];
        let tiny = interpolate(&x, &y, Method::Pchip, &at, false).unwrap();
        let big: Vec<f64> = y.iter().map(|&v| times_pow2(v, 1030)).collect();
        let unit = interpolate(&x, &big, Method::Pchip, &at, false).unwrap();
        for (a, b) in tiny.iter().zip(&unit) {
            assert!((a - times_pow2(*b, -1030)).abs() <= 5e-324);
            assert!(*a > 0.0);
        }
    }

    #[test]
    fn interpolation_methods() {
        let x = [60.0, -30.0, 0.0, 30.0];
        let y = [4.0, 1.0, 2.0, 3.0];
        for m in [
            Method::Linear,
            Method::Pchip,
            Method::Polynomial(1),
            Method::Polynomial(3),
        ] {
            let v = interpolate(&x, &y, m, &[-30.0, 15.0, 60.0], false).unwrap();
            assert!((v[1] - 2.5).abs() < 1e-12, "{m:?}");
            assert!((v[0] - 1.0).abs() < 1e-12 && (v[2] - 4.0).abs() < 1e-12);
        }
        assert!(interpolate(&x, &y, Method::Linear, &[61.0], false).is_err());
        assert!(
            (interpolate(&x, &y, Method::Linear, &[90.0], true).unwrap()[0] - 5.0).abs() < 1e-12
        );
        assert!(interpolate(&[0.0, 0.0], &[1.0, 2.0], Method::Linear, &[0.0], false).is_err());
        assert!(interpolate(&x, &y, Method::Polynomial(4), &[0.0], false).is_err());
    }
}
