//! Fixed-point (Q31) realisations of the streaming filters for generated C code.
//!
//! `gyrobias.codegen` writes C99 for the fixed-gain Kalman filter ([`crate::kalman`]), the FIR
//! stream ([`crate::fir`]) and the compiled bias predictor ([`crate::predict`]) in float64,
//! float32 and Q31. The numerical design decisions of the Q31 variants live here: which
//! power-of-two scale ("shift") each coefficient gets, the integer coefficients, and the
//! analytic bound on the difference from the float64 filter.
//!
//! # Conventions
//!
//! A Q31 sample `X` (an `int32_t`) stands for the value `x = X·2⁻³¹` of full scale `FS`
//! (`x ∈ [−1, 1)`): the C user chooses FS (e.g. the gyro's ±2000 °/s range). A coefficient `c`
//! is stored as `C = round(c·2ⁿ)` (round to nearest, ties away from zero) with the largest
//! shift `n` in the allowed range such that `|C| ≤ 2³¹ − 1`: a relative precision of at least
//! 2⁻³¹ whatever the coefficient's magnitude. Products are formed in 64 bits and brought back
//! with a rounding right shift `(P + 2ⁿ⁻¹) >> n` (ties towards +∞; arithmetic shift of a
//! signed value). Results are saturated to `[−2³¹, 2³¹ − 1]`. `ε = 2⁻³²` is half an LSB.
//!
//! # Kalman filter (SPEC §6)
//!
//! With `a = 1 − p`, `d₁ = g1/a` (the DC gain) and `d₂ = g2/a`, the float64 recursion
//! `u ← p·u + z`, `ω̂ = g1·u + c`, `b̂ = g2·u − c` is, in terms of the observable sum
//! `s = a·u = ω̂ + b̂`, `s ← s + a·(z − s)`, `ω̂ = d₁·s + c`, `b̂ = d₂·s − c`. The Q31 form keeps
//! `s` in an `int64_t` with 62 fractional bits (`S`), so that small gains `a` do not stall it:
//!
//! ```text
//! s₃₁ = sat32((S + 2³⁰) >> 31)                e = z − s₃₁              (int64, no overflow)
//! S  ← clamp(S + ((A·e + 2^(nA−32)) >> (nA − 31)), −2⁶², 2⁶² − 1)
//! ω̂ = sat32(((D₁·s₃₁ + 2^(n₁−1)) >> n₁) + c)  b̂ = sat32(((D₂·s₃₁ + 2^(n₂−1)) >> n₂) − c)
//! ```
//!
//! with `s₃₁` re-rounded after the update. Error analysis (exact arithmetic, inputs and the
//! initial sum `ω̂₀ + b̂₀` bounded by `Z ≤ 1` in magnitude): the state error obeys
//! `Δₖ = (1 − â)Δₖ₋₁ + (â − a)(zₖ − sₖ₋₁) − â·rₖ + ρₖ` with `|r| ≤ ε` (rounding of `s₃₁`) and
//! `|ρ| ≤ 2⁻⁶³` (rounding of the update), so `|Δ| ≤ (2Z·δa + â·ε + 2⁻⁶³)/â`, and
//! `|ω̂' − ω̂| ≤ d₁(|Δ| + ε) + δ₁(Z + |Δ| + ε) + ε + (ε + δ₁Z)` (the last term is the rounding
//! of the constant `c = ω̂₀ − D₁·s₀` at `init`; `b̂` has `d₂`, `δ₂` in the first two terms and
//! the same last term), where `δ` are the coefficient quantisation errors; the
//! float64 filter's own rounding adds at most `2⁻⁵¹·Z·(max(d₁, d₂)/a + 4)`. Treating the
//! roundings as independent uniform noise, the output noise variance is
//! `(2⁻³¹)²/12·(1 + d²(1 + â/(2 − â)))` (the rounding of `s₃₁` enters once directly and once
//! through the loop, whose white-noise power gain is `â/(2 − â)`).
//!
//! # FIR and compiled predictor
//!
//! Each output is a dot product `y = Σₖ hₖ·xₖ (+ w₀)`: the taps share one shift `n`, the
//! products accumulate exactly in an `int64_t` (the shift is lowered until `Σ|Hₖ|·2³¹ + 2ⁿ⁻¹`
//! cannot overflow it), and `y = sat32((acc + 2ⁿ⁻¹) >> n) (+ W₀)`. The error against exact
//! arithmetic is at most `Z·Σ|Hₖ·2⁻ⁿ − hₖ| + ε (+ ε for w₀)`; float64 summation adds at most
//! `2·N·2⁻⁵³·Z·Σ|hₖ|`. The output noise is the final rounding, `2⁻³¹/√12` RMS.

use crate::{Error, Result};

/// `2³¹`.
const TWO_31: f64 = 2_147_483_648.0;
/// Half an LSB of Q31, `2⁻³²`.
pub const HALF_LSB: f64 = 1.0 / 4_294_967_296.0;
/// Largest right shift the generated C applies to a 64-bit product.
pub const MAX_SHIFT: u32 = 62;

/// A coefficient `c` stored as `value = round(c·2^shift)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Scaled {
    /// The integer coefficient, `|value| ≤ 2³¹ − 1`.
    pub value: i32,
    /// Its scale `2^shift`.
    pub shift: u32,
    /// The value it stands for, `value·2^−shift`.
    pub represented: f64,
    /// `|represented − c|`.
    pub error: f64,
}

fn pow2(n: i32) -> f64 {
    2f64.powi(n)
}

/// `c` with the largest shift in `[min_shift, max_shift]` keeping `|round(c·2^shift)| ≤ 2³¹ − 1`
/// (`min_shift` for `c = 0`), or `None` if even `min_shift` overflows.
pub fn scale(c: f64, min_shift: u32, max_shift: u32) -> Option<Scaled> {
    if !c.is_finite() || min_shift > max_shift {
        return None;
    }
    let limit = TWO_31 - 1.0;
    let mut best = None;
    for n in min_shift..=max_shift {
        let v = (c * pow2(n as i32)).round();
        if v.abs() > limit {
            break;
        }
        best = Some(n);
        if c == 0.0 {
            break;
        }
    }
    best.map(|n| {
        #[allow(clippy::cast_possible_truncation)] // |v| ≤ 2³¹ − 1 checked above
        let value = (c * pow2(n as i32)).round() as i32;
        let represented = f64::from(value) / pow2(n as i32);
        Scaled {
            value,
            shift: n,
            represented,
            error: (represented - c).abs(),
        }
    })
}

fn check_amplitude(amplitude: f64) -> Result<()> {
    if !(amplitude > 0.0 && amplitude <= 1.0) {
        return Err(Error::invalid(
            "amplitude",
            format!("must be in (0, 1] (a fraction of full scale), got {amplitude}"),
        ));
    }
    Ok(())
}

/// Q31 realisation of the fixed-gain Kalman filter (see the module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct KalmanQ31 {
    /// `a = 1 − p`, with `31 ≤ shift ≤ 31 + 62`.
    pub a: Scaled,
    /// `d₁ = g1/(1 − p)` (the rate's DC gain), `1 ≤ shift ≤ 62`.
    pub rate_gain: Scaled,
    /// `d₂ = g2/(1 − p)`, `1 ≤ shift ≤ 62`.
    pub bias_gain: Scaled,
    /// Worst-case `|ω̂_Q31 − ω̂_float64|` and the same for `b̂`, in units of full scale, for
    /// inputs (and `ω̂₀ + b̂₀`) bounded by `amplitude`.
    pub error_bound: [f64; 2],
    /// RMS output quantisation noise of `ω̂` and `b̂` (units of full scale).
    pub noise_rms: [f64; 2],
}

/// Designs the Q31 realisation of the recursion with pole `pole`, `1 − p = one_minus_pole`
/// and gains `g1`, `g2` (`g1 + g2 = 1 − p`), for inputs bounded by `amplitude` (fraction of
/// full scale, ≤ 1).
///
/// Errors: non-finite values, an unstable or non-decaying recursion (`p ∉ [0, 1)`), gains
/// that are not consistent with the pole, or a gain `1 − p < 2⁻³¹` (the 62-bit state would
/// stall: no Q31 scaling represents it).
pub fn kalman_q31(
    pole: f64,
    one_minus_pole: f64,
    g1: f64,
    g2: f64,
    amplitude: f64,
) -> Result<KalmanQ31> {
    check_amplitude(amplitude)?;
    for (name, v) in [
        ("pole", pole),
        ("one_minus_pole", one_minus_pole),
        ("g1", g1),
        ("g2", g2),
    ] {
        if !v.is_finite() {
            return Err(Error::invalid(name, format!("must be finite, got {v}")));
        }
    }
    if pole.abs() >= 1.0 {
        return Err(Error::invalid(
            "pole",
            format!("the filter is unstable: its pole p = {pole} must satisfy |p| < 1"),
        ));
    }
    if !(pole >= 0.0 && one_minus_pole > 0.0 && one_minus_pole <= 1.0) {
        return Err(Error::invalid(
            "pole",
            format!(
                "the Q31 form needs 0 <= p < 1 (a decaying, non-oscillating recursion), got \
                 p = {pole}"
            ),
        ));
    }
    if !(g1 > 0.0 && g2 >= 0.0 && ((g1 + g2) - one_minus_pole).abs() <= 1e-12 * one_minus_pole) {
        return Err(Error::invalid(
            "g1",
            format!(
                "the gains g1 = {g1}, g2 = {g2} must be >= 0 with g1 + g2 = 1 − p = \
                 {one_minus_pole}"
            ),
        ));
    }
    let a = one_minus_pole;
    let too_small = || {
        Error::invalid(
            "one_minus_pole",
            format!(
                "the gain 1 − p = {a:e} cannot be represented in Q31: below 2^-31 a 62-bit \
                 state no longer moves by one LSB per step (choose a wider bandwidth)"
            ),
        )
    };
    if a < pow2(-31) {
        return Err(too_small());
    }
    let sa = scale(a, 31, 31 + MAX_SHIFT).ok_or_else(too_small)?;
    let (d1, d2) = (g1 / a, g2 / a);
    let gain = |name: &'static str, d: f64| {
        scale(d, 1, MAX_SHIFT).ok_or_else(|| {
            Error::invalid(
                name,
                format!("the output gain {d} cannot be represented in Q31 with a shift >= 1"),
            )
        })
    };
    let s1 = gain("g1", d1)?;
    let s2 = gain("g2", d2)?;
    let z = amplitude;
    let eps = HALF_LSB;
    let a_hat = sa.represented;
    // The float64 design quantities carry their own rounding (p = 1 − a rounded, d = g/a).
    let delta_a = sa.error + pow2(-53);
    let rho = if sa.shift > 31 { pow2(-63) } else { 0.0 };
    let state = (2.0 * z * delta_a + a_hat * eps + rho) / a_hat;
    let reference = pow2(-51) * z * (d1.max(d2) / a + 4.0);
    // The constant c = ω̂₀ − D₁·s₀ is rounded at init with the *rate* gain D₁ for both outputs.
    let offset_error = eps + (s1.error + pow2(-52)) * z;
    let bound = |d: f64, s: &Scaled| {
        let delta = s.error + pow2(-52);
        d * (state + eps) + delta * (z + state + eps) + eps + offset_error + reference
    };
    let lsb2 = pow2(-62) / 12.0;
    let rho_var = if sa.shift > 31 {
        pow2(-124) / 12.0
    } else {
        0.0
    };
    let loop_gain = a_hat / (2.0 - a_hat);
    let noise = |d: f64| {
        (lsb2 * (1.0 + d * d * (1.0 + loop_gain)) + d * d * rho_var / (a_hat * (2.0 - a_hat)))
            .sqrt()
    };
    // Slack for evaluating the bound itself in floating point.
    let slack = 1.0 + 1e-9;
    Ok(KalmanQ31 {
        a: sa,
        rate_gain: s1,
        bias_gain: s2,
        error_bound: [bound(d1, &s1) * slack, bound(d2, &s2) * slack],
        noise_rms: [noise(d1), noise(d2)],
    })
}

/// Q31 realisation of `rows` dot products sharing one shift (the FIR: one row of taps; the
/// compiled predictor: the weight matrix).
#[derive(Debug, Clone, PartialEq)]
pub struct DotQ31 {
    /// The integer coefficients, row-major like the input.
    pub values: Vec<i32>,
    /// Their common shift `n` (`1 ≤ n ≤ 62`).
    pub shift: u32,
    /// The offsets `w₀` in Q31 (`round(w₀·2³¹)`, saturated), one per row (empty if none).
    pub offsets: Vec<i32>,
    /// Worst-case `|y_Q31 − y_float64|` over the rows, units of full scale, inputs bounded by
    /// `amplitude` (outputs assumed inside full scale: beyond it they saturate).
    pub error_bound: f64,
    /// Largest coefficient error `Σₖ|Hₖ·2⁻ⁿ − hₖ|` over the rows (a bound on the change of
    /// the frequency response, for the FIR).
    pub coefficient_error: f64,
    /// RMS output quantisation noise (units of full scale).
    pub noise_rms: f64,
}

/// Designs the Q31 dot products `y_r = Σₖ w[r, k]·x_k + offsets[r]` for `rows` rows of
/// `w` (row-major) and inputs bounded by `amplitude` (fraction of full scale).
///
/// Errors: empty or non-finite weights or offsets, a weight whose magnitude needs a shift
/// below 1 (|w| ≥ 2³⁰) or all weights so small that even the largest shift (62) leaves them 0.
pub fn dot_q31(w: &[f64], rows: usize, offsets: &[f64], amplitude: f64) -> Result<DotQ31> {
    check_amplitude(amplitude)?;
    if w.is_empty() || rows == 0 || w.len() % rows != 0 {
        return Err(Error::ShapeMismatch {
            name: "weights",
            reason: format!("{} weights do not form {rows} non-empty rows", w.len()),
        });
    }
    if !offsets.is_empty() && offsets.len() != rows {
        return Err(Error::ShapeMismatch {
            name: "offset",
            reason: format!("{rows} rows need {rows} offsets, got {}", offsets.len()),
        });
    }
    if let Some(i) = w.iter().position(|v| !v.is_finite()) {
        return Err(Error::NonFinite {
            name: "weights",
            index: i,
        });
    }
    if let Some(i) = offsets.iter().position(|v| !v.is_finite()) {
        return Err(Error::NonFinite {
            name: "offset",
            index: i,
        });
    }
    let cols = w.len() / rows;
    let max = w.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    if max == 0.0 {
        return Err(Error::invalid("weights", "are all zero"));
    }
    let Some(first) = scale(max, 1, MAX_SHIFT) else {
        return Err(Error::invalid(
            "weights",
            format!(
                "cannot be represented in Q31: the largest |w| = {max} needs a shift below 1 \
                 (|w| must be below 2^30)"
            ),
        ));
    };
    // Lower the shift until no row's accumulator can overflow: Σ|H|·2³¹ + 2ⁿ⁻¹ < 2⁶³.
    let mut n = first.shift;
    let quantise = |n: u32| -> Vec<i64> {
        #[allow(clippy::cast_possible_truncation)] // |v| ≤ 2³¹ − 1 by the choice of n
        w.iter()
            .map(|&v| (v * pow2(n as i32)).round() as i64)
            .collect()
    };
    let fits = |q: &[i64], n: u32| {
        q.chunks(cols).all(|row| {
            let sum: i128 = row.iter().map(|v| i128::from(v.abs())).sum();
            sum * (1_i128 << 31) + (1_i128 << (n - 1)) < (1_i128 << 63)
        })
    };
    let mut q = quantise(n);
    while !fits(&q, n) {
        if n == 1 {
            return Err(Error::invalid(
                "weights",
                "cannot be represented in Q31: Σ|w| of a row reaches 2^31 (the 64-bit \
                 accumulator could overflow)",
            ));
        }
        n -= 1;
        q = quantise(n);
    }
    if q.iter().all(|&v| v == 0) {
        return Err(Error::invalid(
            "weights",
            format!("cannot be represented in Q31: all |w| <= {max:e} round to 0"),
        ));
    }
    let scale_n = pow2(-(n as i32));
    let mut coefficient_error = 0.0_f64;
    let mut l1_max = 0.0_f64;
    for (row_q, row_w) in q.chunks(cols).zip(w.chunks(cols)) {
        let err: f64 = row_q
            .iter()
            .zip(row_w)
            .map(|(&c, &v)| (c as f64 * scale_n - v).abs())
            .sum();
        coefficient_error = coefficient_error.max(err);
        l1_max = l1_max.max(row_w.iter().map(|v| v.abs()).sum());
    }
    let offset_q: Vec<i32> = offsets
        .iter()
        .map(|&o| {
            #[allow(clippy::cast_possible_truncation)] // clamped to the i32 range
            let v = (o * TWO_31).round().clamp(-TWO_31, TWO_31 - 1.0) as i32;
            v
        })
        .collect();
    let offset_err = if offsets.is_empty() { 0.0 } else { HALF_LSB };
    let reference = 2.0 * cols as f64 * pow2(-53) * amplitude * l1_max;
    let error_bound =
        (amplitude * coefficient_error + HALF_LSB + offset_err + reference) * (1.0 + 1e-9);
    #[allow(clippy::cast_possible_truncation)] // |v| ≤ 2³¹ − 1 by the choice of n
    let values = q.iter().map(|&v| v as i32).collect();
    Ok(DotQ31 {
        values,
        shift: n,
        offsets: offset_q,
        error_bound,
        coefficient_error,
        noise_rms: (pow2(-62) / 12.0).sqrt(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scale_uses_full_precision() {
        let s = scale(0.1, 0, 62).unwrap();
        assert_eq!(s.shift, 34);
        assert!(f64::from(s.value).abs() >= TWO_31 / 2.0);
        assert!(s.error <= pow2(-35));
        assert_eq!(scale(0.0, 3, 62).unwrap().value, 0);
        assert!(scale(4.0e9, 0, 62).is_none());
        // 1.0 itself needs shift 30 (2³¹ does not fit).
        assert_eq!(scale(1.0, 0, 62).unwrap().shift, 30);
    }

    #[test]
    fn kalman_design_and_errors() {
        let k = kalman_q31(0.98, 0.02, 0.019, 0.001, 1.0).unwrap();
        assert!(k.a.shift > 31 && k.rate_gain.shift >= 31);
        assert!(k.error_bound[0] < 1e-8 && k.noise_rms[0] < 2e-10);
        assert!(kalman_q31(1.5, -0.5, -0.4, -0.1, 1.0).is_err());
        assert!(kalman_q31(0.98, 0.02, 0.01, 0.001, 1.0).is_err()); // inconsistent
        let e = kalman_q31(1.0 - 1e-12, 1e-12, 1e-12, 0.0, 1.0).unwrap_err();
        assert!(
            e.to_string().contains("cannot be represented in Q31"),
            "{e}"
        );
        assert!(kalman_q31(0.9, 0.1, 0.1, 0.0, 0.0).is_err());
    }

    #[test]
    fn dot_design_shift_and_overflow_guard() {
        let d = dot_q31(&[0.25, 0.5, 0.25], 1, &[], 1.0).unwrap();
        assert_eq!(d.shift, 31);
        assert_eq!(d.values, vec![1 << 29, 1 << 30, 1 << 29]);
        assert_eq!(d.coefficient_error, 0.0);
        // Σ|w| = 8: the shift drops so that the accumulator cannot overflow.
        let d = dot_q31(&[2.0; 4], 1, &[], 1.0).unwrap();
        assert!(d.shift <= 28, "{}", d.shift);
        assert!(dot_q31(&[2.0e9], 1, &[], 1.0).is_err());
        assert!(dot_q31(&[1e-30], 1, &[], 1.0).is_err());
        assert!(dot_q31(&[f64::NAN], 1, &[], 1.0).is_err());
    }
}
