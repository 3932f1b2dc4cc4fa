//! Fixed-gain 2-state Kalman filter for real-time gyro denoising (\[NR\], SPEC §6).
//!
//! # Model
//!
//! The gyro output is `y = ω + b + n` with the true rate `ω` and the bias `b` both random walks
//! (\[NR\] eqs. 1–5): state `X = [ω, b]ᵀ`, `Φ = I`, `H = [1 1]` (a row; \[NR\] prints a column),
//! `Q = diag(q_ω, q_b)`, `R = q_n`. At sampling period `T` the discrete noise variances follow
//! from the Allan coefficients (SPEC §1, §6):
//!
//! ```text
//! R_d = N² / T   (white rate noise, N = ARW in u/√s)
//! Q_b = K² · T   (bias random walk, K = RRW in u/s^1.5)
//! q_ω            (per-step variance of the rate random walk, a design parameter)
//! ```
//!
//! # Steady-state gain
//!
//! The split `ω / b` is unobservable, so the Riccati recursion (\[NR\] eqs. 9–11) has no fixed
//! point (P grows by `q_ω q_b / q_s` per step), but the gain converges. On the observable sum
//! `s = ω + b`, a scalar random walk with `q_s = q_ω + Q_b`:
//!
//! ```text
//! P⁻ = (q_s + √(q_s² + 4 q_s R_d)) / 2,   κ = P⁻ / (P⁻ + R_d),   K_s = κ · [q_ω, Q_b]ᵀ / q_s
//! ```
//!
//! ([`steady_state_gain`]; [`riccati_gain`] iterates eqs. 9–11 for comparison).
//!
//! # Discrete fixed-gain form (\[NR\] eqs. 12–17)
//!
//! With a gain `K` in the continuous equation `dX/dt = K (z − H X)`, `m = −K H` has eigenvalues
//! `−κ_c` and 0 (`κ_c = H K`; \[NR\] prints `+(k1 + k2)`, which would make `A` unstable). As
//! `m² = −κ_c m`, no eigendecomposition is needed:
//!
//! ```text
//! A = e^{mT}        = I − K H · (1 − e^{−κ_c T}) / κ_c
//! B = ∫₀ᵀ e^{mt} dt = T·I − K H · T² φ₂(κ_c T),   φ₂(x) = (x − 1 + e^{−x}) / x²
//! G = B K,          X_{k+1} = A X_k + G z_{k+1} = X_k + G (z_{k+1} − H X_k)
//! ```
//!
//! * [`Form::Standard`] (default): the steady-state discrete KF `X ← X + K_s (z − H X)`, i.e.
//!   `G = K_s`, obtained from eq. 12 with `K_c = K_s · (−ln(1 − κ)) / (κ T)`.
//! * [`Form::Paper`]: eqs. 12–17 taken literally, the dimensionless discrete `K_s` used in the
//!   continuous eq. 12, so `G = K_s (1 − e^{−κT}) / κ ≈ T K_s`: a filter ~1/T times slower whose
//!   −3 dB bandwidth can never exceed `1/(2π)` Hz.
//!
//! # Frequency response and bandwidth
//!
//! With `G = [g1, g2]` the response `z → ω̂` is exactly first order,
//! `H_ω(z) = g1 / (1 − p z⁻¹)`, `p = 1 − (g1 + g2)`, DC gain `q_ω / q_s`. Its −3 dB point solves
//! `sin(π·BW·T) = (1 − p) / (2√p)` (none when the right side exceeds 1, i.e. `p < 3 − 2√2`);
//! for the standard form this is `q_s / R_d = 4 sin²(π·BW·T)`, so BW grows like `√q_ω` and
//! \[NR\]'s linear fit (eq. 18) is not reproducible. [`q_omega_for_bandwidth`] inverts it in closed
//! form for both forms.
//!
//! # The recursion as it is run
//!
//! `X ← X + G (z − H X)` is a first-order IIR on the observable sum `s = ω̂ + b̂` plus an
//! accumulation, `s_k = p s_{k−1} + (1 − p) z_k`, `ω̂_k = ω̂_{k−1} + g1 (z_k − s_{k−1})`. Both
//! increments are multiples of the innovation, so `ω̂ − g1·s/(1 − p)` is constant (the
//! unobservable mode) and with the scaled level `u = s/(1 − p)`:
//!
//! ```text
//! u_k = p u_{k−1} + z_k,   ω̂_k = g1 u_k + c,   b̂_k = (1 − p − g1) u_k − c
//! ```
//!
//! One multiply-add on the loop-carried path, two independent multiply-adds per output: the
//! loop runs at memory speed. The carried state is exactly `(u, c)` ([`KalmanState`], which also
//! records the estimates after the last sample, the gain of the filter that produced it and the
//! samples processed), which makes chunked processing equal one-shot processing bit for bit.

use nalgebra::{Matrix2, RowVector2, Vector2};

use crate::float::{Float, first_non_finite};
use crate::validate;
use crate::{Error, Result};

/// Which discretisation of \[NR\] eqs. 12–17 to run.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Form {
    /// The steady-state discrete Kalman filter `X ← X + K_s (z − H X)`.
    Standard,
    /// \[NR\] eqs. 12–17 taken literally (dimensionless `K_s` in the continuous eq. 12).
    Paper,
}

impl Form {
    /// Parses `"standard"` or `"paper"`.
    pub fn parse(name: &str) -> Result<Self> {
        match name {
            "standard" => Ok(Form::Standard),
            "paper" => Ok(Form::Paper),
            other => Err(Error::invalid(
                "form",
                format!("expected 'standard' or 'paper', got {other:?}"),
            )),
        }
    }
}

/// Discrete noise variances of the gyro model at one sampling period (SPEC §6).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DiscreteNoise {
    /// Sampling period `T` in s.
    pub period: f64,
    /// White-noise variance per sample `R_d = N²/T`, in (u/s)².
    pub r_d: f64,
    /// Bias random-walk variance per step `Q_b = K²·T`, in (u/s)².
    pub q_b: f64,
}

impl DiscreteNoise {
    /// From the sampling rate `fs` (Hz), ARW `arw` (u/√s, must be > 0) and RRW `rrw` (u/s^1.5, ≥ 0).
    pub fn from_coefficients(fs: f64, arw: f64, rrw: f64) -> Result<Self> {
        validate::positive("fs", fs)?;
        validate::positive("arw", arw)?;
        validate::non_negative("rrw", rrw)?;
        let period = 1.0 / fs;
        let r_d = arw * arw * fs;
        let q_b = rrw * rrw * period;
        if !(r_d.is_finite() && r_d > 0.0 && q_b.is_finite() && period > 0.0) {
            return Err(Error::invalid(
                "arw",
                format!(
                    "the per-sample noise variances overflow or underflow (R_d = {r_d}, Q_b = {q_b})"
                ),
            ));
        }
        Ok(DiscreteNoise { period, r_d, q_b })
    }
}

/// Steady-state gain `κ = H K_s` of a scalar random walk with per-step variance `q_s` observed
/// in white noise of variance `r_d`: `κ = P⁻/(P⁻ + R_d)`, `P⁻ = (q_s + √(q_s² + 4 q_s R_d))/2`.
///
/// Computed on `x = q_s/R_d` as `√x·√(x+4)` so that it neither overflows nor loses precision.
pub fn steady_state_kappa(q_s: f64, r_d: f64) -> f64 {
    let x = q_s / r_d;
    let p = 0.5 * (x + x.sqrt() * (x + 4.0).sqrt());
    p / (p + 1.0)
}

/// Closed-form steady-state gain `K_s = κ·[q_ω, q_b]ᵀ/q_s` of the 2-state filter (SPEC §6).
pub fn steady_state_gain(q_omega: f64, q_b: f64, r_d: f64) -> Result<Vector2<f64>> {
    validate::positive("q_omega", q_omega)?;
    validate::non_negative("q_b", q_b)?;
    validate::positive("r_d", r_d)?;
    let q_s = q_omega + q_b;
    let kappa = steady_state_kappa(q_s, r_d);
    if !(kappa > 0.0 && kappa < 1.0) {
        return Err(Error::invalid(
            "q_omega",
            format!(
                "q_omega + q_b = {q_s} against R_d = {r_d} gives a degenerate gain κ = {kappa} \
                 (the process noise is too small or too large relative to the white noise)"
            ),
        ));
    }
    Ok(Vector2::new(kappa * (q_omega / q_s), kappa * (q_b / q_s)))
}

/// Iterates the discrete Kalman recursion (\[NR\] eqs. 9–11, Joseph form) from `P₀ = 0` for
/// `iterations` steps and returns the last gain `K_k`.
///
/// This is the paper's off-line procedure; it converges to [`steady_state_gain`] although `P`
/// itself diverges along the unobservable direction `[1, −1]`.
pub fn riccati_gain(q_omega: f64, q_b: f64, r_d: f64, iterations: usize) -> Result<Vector2<f64>> {
    validate::positive("q_omega", q_omega)?;
    validate::non_negative("q_b", q_b)?;
    validate::positive("r_d", r_d)?;
    if iterations == 0 {
        return Err(Error::invalid("iterations", "must be >= 1"));
    }
    let h = RowVector2::new(1.0, 1.0);
    let q = Matrix2::new(q_omega, 0.0, 0.0, q_b);
    let identity = Matrix2::identity();
    let mut p = Matrix2::zeros();
    let mut k = Vector2::zeros();
    // The gain depends on P only through the observable direction, which converges: once a
    // step returns exactly the previous gain and the observable part of P (h P hᵀ, P hᵀ) has
    // stopped changing, every further step returns it too, so a huge `iterations` costs no
    // more than convergence does.
    let mut observable = (f64::NAN, Vector2::zeros());
    for _ in 0..iterations {
        let p_prior = p + q; // eq. 9 with Φ = I
        let innovation = (h * p_prior * h.transpose())[(0, 0)] + r_d;
        let k_next = p_prior * h.transpose() / innovation; // eq. 10
        let i_kh = identity - k_next * h;
        p = i_kh * p_prior * i_kh.transpose() + k_next * r_d * k_next.transpose(); // eq. 11
        let observable_next = (innovation, p_prior * h.transpose());
        let fixed = k_next == k && observable_next == observable;
        k = k_next;
        observable = observable_next;
        if fixed {
            break;
        }
    }
    if !(k[0].is_finite() && k[1].is_finite()) {
        return Err(Error::Singular {
            reason: "the Riccati iteration overflowed".into(),
        });
    }
    Ok(k)
}

/// `φ₂(x) = (x − 1 + e^{−x}) / x²`, accurate for all `x ≥ 0` (series below 0.01).
pub fn phi2(x: f64) -> f64 {
    if x.abs() < 1e-2 {
        // Taylor series Σ (−x)^n / (n+2)!; truncation error < x⁶/8! < 3e-17 for |x| < 0.01.
        let x2 = x * x;
        0.5 - x / 6.0 + x2 / 24.0 - x2 * x / 120.0 + x2 * x2 / 720.0 - x2 * x2 * x / 5040.0
    } else {
        (x + (-x).exp_m1()) / (x * x)
    }
}

/// Pole `p` of the first-order response for a target −3 dB bandwidth: the root `p < 1` of
/// `(1 − p)/(2√p) = sin(π·BW·T)`, returned as `(p, 1 − p)` (both computed without cancellation).
fn pole_for_bandwidth(bandwidth: f64, period: f64) -> (f64, f64) {
    let c = (std::f64::consts::PI * bandwidth * period).sin();
    // u = √p solves u² + 2cu − 1 = 0; 1 − p = 2cu.
    let u = 1.0 / (c + (c * c + 1.0).sqrt());
    (u * u, 2.0 * c * u)
}

/// Process noise `q_ω` (per step, (u/s)²) giving a −3 dB bandwidth `bandwidth` (Hz).
///
/// Closed form for both forms: the pole for the target bandwidth, `κ = 1 − p` (standard) or
/// `κ = −ln(p)/T` (paper), then `q_s = R_d κ²/(1 − κ)` and `q_ω = q_s − Q_b`. For the standard
/// form this is `q_ω = 4 R_d sin²(π·BW·T) − Q_b` (SPEC §6).
pub fn q_omega_for_bandwidth(bandwidth: f64, noise: &DiscreteNoise, form: Form) -> Result<f64> {
    validate::positive("bandwidth", bandwidth)?;
    let nyquist = 0.5 / noise.period;
    if bandwidth >= nyquist {
        return Err(Error::invalid(
            "bandwidth",
            format!(
                "{bandwidth} Hz is unreachable: it must be below the Nyquist frequency {nyquist} Hz"
            ),
        ));
    }
    let (p, one_minus_p) = pole_for_bandwidth(bandwidth, noise.period);
    let kappa = match form {
        Form::Standard => one_minus_p,
        Form::Paper => -p.ln() / noise.period,
    };
    if kappa.is_nan() || kappa >= 1.0 {
        let max_bw = bandwidth_of_pole((-noise.period).exp(), noise.period).unwrap_or(nyquist);
        return Err(Error::invalid(
            "bandwidth",
            format!(
                "{bandwidth} Hz is unreachable with form='paper': its gain is about T·K_s, so \
                 the bandwidth stays below {max_bw:.6} Hz (≈ 1/(2π)); use form='standard'"
            ),
        ));
    }
    let q_s = noise.r_d * kappa * kappa / (1.0 - kappa);
    let q_omega = q_s - noise.q_b;
    if q_omega.is_nan() || q_omega <= 0.0 {
        return Err(Error::invalid(
            "bandwidth",
            format!(
                "{bandwidth} Hz is unreachable: the bias random walk alone (Q_b = {:e}) already \
                 gives a wider bandwidth; choose a larger bandwidth",
                noise.q_b
            ),
        ));
    }
    Ok(q_omega)
}

/// −3 dB frequency (Hz) of `g/(1 − p z⁻¹)` at period `T`, or `None` if above Nyquist.
fn bandwidth_of_pole(p: f64, period: f64) -> Option<f64> {
    bandwidth_from(p, 1.0 - p, period)
}

fn bandwidth_from(p: f64, one_minus_p: f64, period: f64) -> Option<f64> {
    if p.is_nan() || p <= 0.0 {
        return None;
    }
    let c = one_minus_p / (2.0 * p.sqrt());
    if c > 1.0 {
        None
    } else {
        Some(c.asin() / (std::f64::consts::PI * period))
    }
}

/// The fixed-gain 2-state filter: design (gain, matrices, response) and the recursion.
#[derive(Debug, Clone, PartialEq)]
pub struct FixedGainKalman {
    noise: DiscreteNoise,
    q_omega: f64,
    form: Form,
    /// `κ = H K_s` (discrete steady state).
    kappa: f64,
    /// `K_s`.
    gain: Vector2<f64>,
    /// The gain of the continuous eq. 12 and its `κ_c = H K_c`.
    continuous_gain: Vector2<f64>,
    kappa_c: f64,
    /// Recursion gain `G`.
    g: Vector2<f64>,
    /// `p` and `1 − p = g1 + g2`.
    pole: f64,
    one_minus_pole: f64,
}

impl FixedGainKalman {
    /// Designs the filter for per-step rate process noise `q_omega` ((u/s)²).
    pub fn new(noise: DiscreteNoise, q_omega: f64, form: Form) -> Result<Self> {
        validate::positive("q_omega", q_omega)?;
        let gain = steady_state_gain(q_omega, noise.q_b, noise.r_d)?;
        let kappa = steady_state_kappa(q_omega + noise.q_b, noise.r_d);
        let t = noise.period;
        let (continuous_gain, kappa_c, g, one_minus_pole) = match form {
            Form::Standard => {
                // K_c = K_s·(−ln(1−κ))/(κT) makes eq. 12 reproduce the discrete KF exactly.
                let kappa_c = -(-kappa).ln_1p() / t;
                (gain * (kappa_c / kappa), kappa_c, gain, kappa)
            }
            Form::Paper => {
                let decay = -(-kappa * t).exp_m1(); // 1 − e^{−κT}
                (gain, kappa, gain * (decay / kappa), decay)
            }
        };
        if !(one_minus_pole > 0.0 && kappa_c.is_finite()) {
            return Err(Error::invalid(
                "q_omega",
                format!("q_omega = {q_omega} gives a degenerate filter (1 − p = {one_minus_pole})"),
            ));
        }
        Ok(FixedGainKalman {
            noise,
            q_omega,
            form,
            kappa,
            gain,
            continuous_gain,
            kappa_c,
            g,
            pole: 1.0 - one_minus_pole,
            one_minus_pole,
        })
    }

    /// Designs the filter for a target −3 dB bandwidth (Hz) via [`q_omega_for_bandwidth`].
    pub fn with_bandwidth(noise: DiscreteNoise, bandwidth: f64, form: Form) -> Result<Self> {
        let q_omega = q_omega_for_bandwidth(bandwidth, &noise, form)?;
        Self::new(noise, q_omega, form)
    }

    /// Designs the filter from exactly one of `q_omega` ([`new`](Self::new)) and `bandwidth`
    /// ([`with_bandwidth`](Self::with_bandwidth)).
    pub fn design(
        noise: DiscreteNoise,
        q_omega: Option<f64>,
        bandwidth: Option<f64>,
        form: Form,
    ) -> Result<Self> {
        match (q_omega, bandwidth) {
            (Some(q), None) => Self::new(noise, q, form),
            (None, Some(bw)) => Self::with_bandwidth(noise, bw, form),
            (Some(_), Some(_)) => Err(Error::invalid(
                "bandwidth",
                "give exactly one of q_omega and bandwidth (both given)",
            )),
            (None, None) => Err(Error::invalid(
                "q_omega",
                "give exactly one of q_omega and bandwidth (neither given)",
            )),
        }
    }

    /// The discrete noise the filter was designed for.
    pub fn noise(&self) -> &DiscreteNoise {
        &self.noise
    }

    /// Per-step rate process noise `q_ω`, (u/s)².
    pub fn q_omega(&self) -> f64 {
        self.q_omega
    }

    /// The discretisation.
    pub fn form(&self) -> Form {
        self.form
    }

    /// Steady-state discrete Kalman gain `K_s = [k1, k2]ᵀ` (dimensionless).
    pub fn gain(&self) -> Vector2<f64> {
        self.gain
    }

    /// `κ = k1 + k2`.
    pub fn kappa(&self) -> f64 {
        self.kappa
    }

    /// The gain `K` of the continuous equation 12 (1/s for the standard form; the paper uses
    /// the dimensionless `K_s` as is).
    pub fn continuous_gain(&self) -> Vector2<f64> {
        self.continuous_gain
    }

    /// `A = e^{mT} = I − K H (1 − e^{−κ_c T})/κ_c` (\[NR\] eqs. 15–16).
    pub fn a(&self) -> Matrix2<f64> {
        let h = RowVector2::new(1.0, 1.0);
        let t = self.noise.period;
        let decay = -(-self.kappa_c * t).exp_m1() / self.kappa_c;
        Matrix2::identity() - self.continuous_gain * h * decay
    }

    /// `B = ∫₀ᵀ e^{mt} dt = T·I − K H T² φ₂(κ_c T)` (\[NR\] eqs. 14, 16).
    pub fn b(&self) -> Matrix2<f64> {
        let h = RowVector2::new(1.0, 1.0);
        let t = self.noise.period;
        Matrix2::identity() * t - self.continuous_gain * h * (t * t * phi2(self.kappa_c * t))
    }

    /// `G = B K`, the gain of `X ← X + G (z − H X)` (\[NR\] eq. 17).
    pub fn g(&self) -> Vector2<f64> {
        self.g
    }

    /// Pole `p = 1 − (g1 + g2)` of the response `z → ω̂`.
    pub fn pole(&self) -> f64 {
        self.pole
    }

    /// DC gain `g1/(1 − p) = q_ω/(q_ω + q_b)` of `z → ω̂`.
    pub fn dc_gain(&self) -> f64 {
        self.g[0] / self.one_minus_pole
    }

    /// Standard deviation of `ω̂` per unit standard deviation of white input noise,
    /// `g1/√(1 − p²)`; for a unity DC gain this is `√(κ/(2 − κ))` (SPEC §6: the per-sample noise
    /// reduction is its inverse, 2.54× at 10 Hz bandwidth and fs = 200 Hz).
    pub fn white_noise_gain(&self) -> f64 {
        self.g[0] / (self.one_minus_pole * (1.0 + self.pole)).sqrt()
    }

    /// True −3 dB frequency (Hz) of `z → ω̂`, `None` if the response never drops 3 dB below
    /// Nyquist.
    pub fn bandwidth(&self) -> Option<f64> {
        bandwidth_from(self.pole, self.one_minus_pole, self.noise.period)
    }

    /// Complex response `g1/(1 − p e^{−j2πfT})` of `z → ω̂` at `freqs` (Hz), written as real and
    /// imaginary parts.
    pub fn frequency_response_into(
        &self,
        freqs: &[f64],
        real: &mut [f64],
        imag: &mut [f64],
    ) -> Result<()> {
        validate::finite("freqs", freqs)?;
        if real.len() != freqs.len() || imag.len() != freqs.len() {
            return Err(Error::ShapeMismatch {
                name: "freqs",
                reason: "output buffers must have the length of freqs".into(),
            });
        }
        let (p, g1, t) = (self.pole, self.g[0], self.noise.period);
        for ((&f, re), im) in freqs.iter().zip(real.iter_mut()).zip(imag.iter_mut()) {
            let w = 2.0 * std::f64::consts::PI * f * t;
            let half = (0.5 * w).sin();
            // |1 − p e^{−jw}|² = (1 − p)² + 4p sin²(w/2), without cancellation near DC.
            let den = self.one_minus_pole * self.one_minus_pole + 4.0 * p * half * half;
            // 1 − p cos w = (1 − p) + 2p sin²(w/2)
            *re = g1 * (self.one_minus_pole + 2.0 * p * half * half) / den;
            *im = -g1 * p * w.sin() / den;
        }
        Ok(())
    }

    /// The coefficients `[p, g1, g2, 1 − p]` of the recursion as the kernels use them
    /// (`u ← p·u + z`, `ω̂ = g1·u + c`, `b̂ = g2·u − c`, `u₀ = (ω̂₀ + b̂₀)/(1 − p)`), with
    /// `g2 = (1 − p) − g1` computed in float64; the float32 kernel rounds each to `f32` once.
    /// Generated C uses exactly these values.
    pub fn kernel_coefficients(&self) -> [f64; 4] {
        let c = Coefficients::<f64>::of(self);
        [c.p, c.g1, c.g2, c.k]
    }

    /// The state before the first sample for initial estimates `X₀ = [ω₀, b₀]` per axis
    /// (`rate[a] = ω₀`, `bias[a] = b₀` of axis `a`).
    pub fn initial_state(&self, rate: &[f64], bias: &[f64]) -> Result<KalmanState> {
        self.initial_state_in(rate, bias)
    }

    /// [`initial_state`](Self::initial_state) computed in `T` arithmetic (`u = (ω₀ + b₀)/(1 − p)`,
    /// `c = ω₀ − g1·u`, each operation rounded to `T`): for `f32` this is the state the float32
    /// kernel ([`filter_into_f32`](Self::filter_into_f32)) and the generated float32 C start from.
    pub fn initial_state_in<T: Float>(&self, rate: &[T], bias: &[T]) -> Result<KalmanState> {
        if rate.len() != bias.len() || rate.is_empty() {
            return Err(Error::ShapeMismatch {
                name: "x0",
                reason: format!(
                    "rate and bias need one value per axis (got {} and {})",
                    rate.len(),
                    bias.len()
                ),
            });
        }
        if let Some(i) = first_non_finite(rate).or_else(|| first_non_finite(bias)) {
            return Err(Error::NonFinite {
                name: "x0",
                index: i,
            });
        }
        let c = Coefficients::<T>::of(self);
        let level: Vec<T> = rate
            .iter()
            .zip(bias)
            .map(|(&w, &b)| (w + b) / c.k)
            .collect();
        let offset: Vec<T> = rate
            .iter()
            .zip(&level)
            .map(|(&w, &u)| w - c.g1 * u)
            .collect();
        if level.iter().chain(&offset).any(|v| !v.is_finite()) {
            return Err(Error::invalid(
                "x0",
                "the initial estimates overflow the filter's scaled level (values too large \
                 for the floating-point format)",
            ));
        }
        let wide = |v: &[T]| v.iter().map(|x| x.to_f64()).collect::<Vec<f64>>();
        Ok(KalmanState {
            level: wide(&level),
            offset: wide(&offset),
            rate: wide(rate),
            bias: wide(bias),
            gain: self.g.into(),
            samples: 0,
        })
    }

    /// The default `X₀ = [z₀, 0]` per axis (SPEC §6), from the first row of `z`
    /// (samples × `n_axes`).
    ///
    /// A NaN or infinity in that row is reported as a value of `z` with its sample and axis,
    /// like [`filter_into`](Self::filter_into) does.
    pub fn initial_state_from_first_sample(&self, z: &[f64], n_axes: usize) -> Result<KalmanState> {
        if n_axes == 0 {
            return Err(Error::invalid("z", "must have at least one axis"));
        }
        validate::min_len("z", z.len() / n_axes, 1)?;
        let first = &z[..n_axes];
        if let Some(axis) = first.iter().position(|v| !v.is_finite()) {
            return Err(Error::invalid(
                "z",
                format!("non-finite value (NaN or inf) at sample 0 axis {axis}"),
            ));
        }
        self.initial_state(first, &vec![0.0; n_axes])
    }

    /// Fails unless `state` was produced by this filter (same recursion gain `G`, bit for bit)
    /// for `n_axes` axes: resuming a stream with another filter's state would silently mix two
    /// designs.
    pub fn check_state(&self, state: &KalmanState, n_axes: usize) -> Result<()> {
        let gain: [f64; 2] = self.g.into();
        if state.gain != gain {
            return Err(Error::invalid(
                "state",
                format!(
                    "was produced by a different filter (gain {:?}, this filter {gain:?})",
                    state.gain
                ),
            ));
        }
        if state.level.len() != n_axes {
            return Err(Error::ShapeMismatch {
                name: "state",
                reason: format!(
                    "state carries {} axes but z has {n_axes}",
                    state.level.len()
                ),
            });
        }
        Ok(())
    }

    /// The estimates `(ω̂, b̂)` per axis that `state` (from this filter) stands for:
    /// `ω̂ = g1·u + c`, `b̂ = (1 − p − g1)·u − c`.
    pub fn estimates(&self, state: &KalmanState) -> Result<(Vec<f64>, Vec<f64>)> {
        self.check_state(state, state.n_axes())?;
        let c = Coefficients::<f64>::of(self);
        Ok(state
            .level
            .iter()
            .zip(&state.offset)
            .map(|(&u, &off)| (c.g1 * u + off, c.g2 * u - off))
            .unzip())
    }

    /// Filters `z` (C-order samples × `n_axes`) from `state`, writing the rate and bias estimates
    /// into `rate` and `bias` (same layout) and advancing `state` (its level, the estimates after
    /// the last sample and the sample count).
    ///
    /// `state` must come from this filter ([`check_state`](Self::check_state)). On error
    /// (including a NaN or infinity in `z`, reported with its sample and axis) `state` is left
    /// exactly as it was. An empty `z` leaves it unchanged.
    pub fn filter_into(
        &self,
        z: &[f64],
        n_axes: usize,
        state: &mut KalmanState,
        rate: &mut [f64],
        bias: &mut [f64],
    ) -> Result<()> {
        self.filter_into_generic(z, n_axes, state, rate, bias)
    }

    /// [`filter_into`](Self::filter_into) in float32 arithmetic: the coefficients `p`, `g1`,
    /// `g2 = (1 − p) − g1` and the state's `u`, `c` rounded to `f32` once, then exactly the
    /// operations of the float64 kernel (`u ← p·u + z`, `ω̂ = g1·u + c`, `b̂ = g2·u − c`), each
    /// rounded to `f32`. This is the reference the generated float32 C equals bit for bit; a
    /// state from [`initial_state_in::<f32>`](Self::initial_state_in) or from this function
    /// holds `f32` values exactly, so chunked float32 filtering equals one-shot filtering.
    pub fn filter_into_f32(
        &self,
        z: &[f32],
        n_axes: usize,
        state: &mut KalmanState,
        rate: &mut [f32],
        bias: &mut [f32],
    ) -> Result<()> {
        self.filter_into_generic(z, n_axes, state, rate, bias)
    }

    fn filter_into_generic<T: Float>(
        &self,
        z: &[T],
        n_axes: usize,
        state: &mut KalmanState,
        rate: &mut [T],
        bias: &mut [T],
    ) -> Result<()> {
        if n_axes == 0 {
            return Err(Error::invalid("z", "must have at least one axis"));
        }
        if z.len() % n_axes != 0 {
            return Err(Error::ShapeMismatch {
                name: "z",
                reason: format!("{} values do not fill rows of {n_axes} axes", z.len()),
            });
        }
        self.check_state(state, n_axes)?;
        state.check_finite()?;
        if rate.len() != z.len() || bias.len() != z.len() {
            return Err(Error::ShapeMismatch {
                name: "z",
                reason: "output buffers must have the length of z".into(),
            });
        }
        if z.is_empty() {
            return Ok(());
        }
        let mut level: Vec<T> = state.level.iter().map(|&v| T::from_f64(v)).collect();
        let c = Coefficients::<T>::of(self);
        let off: Vec<T> = state.offset.iter().map(|&v| T::from_f64(v)).collect();
        let off = &off[..];
        match n_axes {
            1 => run_fixed::<_, 1>(&c, z, &mut level, off, rate, bias),
            2 => run_fixed::<_, 2>(&c, z, &mut level, off, rate, bias),
            3 => run_fixed::<_, 3>(&c, z, &mut level, off, rate, bias),
            4 => run_fixed::<_, 4>(&c, z, &mut level, off, rate, bias),
            _ => run_dynamic(&c, z, &mut level, off, rate, bias),
        }
        // A NaN/inf in z makes the level non-finite from there on (p > 0), so checking the
        // final state finds every bad stream without a second pass over the data.
        if level.iter().any(|v| !v.is_finite()) {
            return Err(match first_non_finite(z) {
                Some(i) => Error::invalid(
                    "z",
                    format!(
                        "non-finite value (NaN or inf) at sample {} axis {} of this chunk; \
                         the filter state is unchanged",
                        i / n_axes,
                        i % n_axes
                    ),
                ),
                None => Error::invalid(
                    "z",
                    "the filter overflowed (values too large for the floating-point format); \
                     the filter state is unchanged",
                ),
            });
        }
        let last = z.len() - n_axes;
        state.level = level.iter().map(|v| v.to_f64()).collect();
        state.rate = rate[last..].iter().map(|v| v.to_f64()).collect();
        state.bias = bias[last..].iter().map(|v| v.to_f64()).collect();
        state.samples = state.samples.saturating_add((z.len() / n_axes) as u64);
        Ok(())
    }

    /// Convenience: filters `z` from `state` into newly allocated `(rate, bias)` arrays.
    pub fn filter(
        &self,
        z: &[f64],
        n_axes: usize,
        state: &mut KalmanState,
    ) -> Result<(Vec<f64>, Vec<f64>)> {
        let mut rate = vec![0.0; z.len()];
        let mut bias = vec![0.0; z.len()];
        self.filter_into(z, n_axes, state, &mut rate, &mut bias)?;
        Ok((rate, bias))
    }
}

/// Coefficients of the recursion in its scaled-level form, rounded once to `T`.
struct Coefficients<T> {
    p: T,
    g1: T,
    /// `1 − p − g1` (equals `g2`), computed in f64 then rounded.
    g2: T,
    /// `1 − p` (the scale of the level `u = s/(1 − p)`).
    k: T,
}

impl<T: Float> Coefficients<T> {
    fn of(f: &FixedGainKalman) -> Self {
        Coefficients {
            p: T::from_f64(f.pole),
            g1: T::from_f64(f.g[0]),
            g2: T::from_f64(f.one_minus_pole - f.g[0]),
            k: T::from_f64(f.one_minus_pole),
        }
    }
}

/// The per-sample update for one axis; identical arithmetic in every kernel so that any axis
/// count and any chunking give bit-identical results.
///
/// Since `s_k − s_{k−1} = (1 − p)·e_k` and `ω̂_k − ω̂_{k−1} = g1·e_k`, the quantity
/// `ω̂ − g1·s/(1 − p)` never changes (it is the unobservable mode). With the scaled level
/// `u = s/(1 − p)` the whole filter is `u_k = p·u_{k−1} + z_k`, `ω̂_k = g1·u_k + c`,
/// `b̂_k = g2·u_k − c`: one multiply-add on the loop-carried path, and no accumulated
/// rounding in `ω̂`.
#[allow(clippy::inline_always)] // the loop body of every kernel: identical code, no call
#[inline(always)]
fn step<T: Float>(c: &Coefficients<T>, z: T, u: &mut T, offset: T) -> (T, T) {
    *u = c.p * *u + z;
    (c.g1 * *u + offset, c.g2 * *u - offset)
}

fn run_fixed<T: Float, const N: usize>(
    c: &Coefficients<T>,
    z: &[T],
    level: &mut [T],
    offset: &[T],
    rate: &mut [T],
    bias: &mut [T],
) {
    // Loop-carried values live in local arrays (registers), not behind the slices.
    let mut u = [T::ZERO; N];
    let mut off = [T::ZERO; N];
    u.copy_from_slice(level);
    off.copy_from_slice(offset);
    for ((zr, rr), br) in z
        .chunks_exact(N)
        .zip(rate.chunks_exact_mut(N))
        .zip(bias.chunks_exact_mut(N))
    {
        for a in 0..N {
            let (r, b) = step(c, zr[a], &mut u[a], off[a]);
            rr[a] = r;
            br[a] = b;
        }
    }
    level.copy_from_slice(&u);
}

fn run_dynamic<T: Float>(
    c: &Coefficients<T>,
    z: &[T],
    level: &mut [T],
    offset: &[T],
    rate: &mut [T],
    bias: &mut [T],
) {
    let n = level.len();
    for ((zr, rr), br) in z
        .chunks_exact(n)
        .zip(rate.chunks_exact_mut(n))
        .zip(bias.chunks_exact_mut(n))
    {
        for a in 0..n {
            let (r, b) = step(c, zr[a], &mut level[a], offset[a]);
            rr[a] = r;
            br[a] = b;
        }
    }
}

/// The state a stream carries from one chunk to the next, per axis: the scaled observable
/// level `u = (ω̂ + b̂)/(1 − p)` and the constant offset `c = ω̂ − g1·u` of the unobservable mode
/// (exactly the loop's variables, so resuming from a state reproduces one-shot processing bit
/// for bit), the estimates `ω̂`, `b̂` after the last sample, the recursion gain `G` of the
/// filter that produced it (checked on resume: [`FixedGainKalman::check_state`]) and the number
/// of samples processed.
///
/// Build one with [`FixedGainKalman::initial_state`] (or
/// [`FixedGainKalman::initial_state_from_first_sample`]), advance it with
/// [`FixedGainKalman::filter_into`], rebuild a stored one with [`KalmanState::new`]; read the
/// estimates it stands for with [`FixedGainKalman::estimates`].
#[derive(Debug, Clone, PartialEq)]
pub struct KalmanState {
    level: Vec<f64>,
    offset: Vec<f64>,
    rate: Vec<f64>,
    bias: Vec<f64>,
    gain: [f64; 2],
    samples: u64,
}

impl KalmanState {
    /// A state from its parts, as read back from [`KalmanState::level`] and the other getters
    /// (e.g. when unpickling). Every part needs one value per axis, at least one axis, and
    /// `level` and `offset` must be finite.
    pub fn new(
        level: Vec<f64>,
        offset: Vec<f64>,
        rate: Vec<f64>,
        bias: Vec<f64>,
        gain: [f64; 2],
        samples: u64,
    ) -> Result<Self> {
        let n = level.len();
        if n == 0 || offset.len() != n || rate.len() != n || bias.len() != n {
            return Err(Error::ShapeMismatch {
                name: "state",
                reason: format!(
                    "level, offset, rate and bias need one value per axis (got {n}, {}, {} \
                     and {})",
                    offset.len(),
                    rate.len(),
                    bias.len()
                ),
            });
        }
        let state = KalmanState {
            level,
            offset,
            rate,
            bias,
            gain,
            samples,
        };
        state.check_finite()?;
        Ok(state)
    }

    fn check_finite(&self) -> Result<()> {
        if self
            .level
            .iter()
            .chain(&self.offset)
            .any(|v| !v.is_finite())
        {
            return Err(Error::invalid("state", "contains a non-finite value"));
        }
        Ok(())
    }

    /// `u = s/(1 − p)` per axis.
    pub fn level(&self) -> &[f64] {
        &self.level
    }

    /// `c = ω̂ − g1·u` per axis (constant while filtering).
    pub fn offset(&self) -> &[f64] {
        &self.offset
    }

    /// Rate estimate `ω̂` after the last sample (the initial `ω₀` before the first), per axis.
    pub fn rate(&self) -> &[f64] {
        &self.rate
    }

    /// Bias estimate `b̂` after the last sample (the initial `b₀` before the first), per axis.
    pub fn bias(&self) -> &[f64] {
        &self.bias
    }

    /// Recursion gain `G = [g1, g2]` of the filter that produced the state.
    pub fn gain(&self) -> [f64; 2] {
        self.gain
    }

    /// Samples (rows) processed since the initial state.
    pub fn samples(&self) -> u64 {
        self.samples
    }

    /// Number of axes.
    pub fn n_axes(&self) -> usize {
        self.level.len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// \[NR\]'s example in (deg/h)² units: T = 5 ms, ARW 0.1667 deg/√h, RRW 1200 deg/h^1.5.
    fn nr_noise() -> DiscreteNoise {
        let arw = 0.1667 / 60.0; // deg/√s
        let rrw = 1200.0 / 216_000.0; // deg/s^1.5
        let n = DiscreteNoise::from_coefficients(200.0, arw, rrw).unwrap();
        // Express R_d and Q_b in (deg/h)²: the gain depends only on ratios.
        let s = 3600.0_f64 * 3600.0;
        DiscreteNoise {
            period: n.period,
            r_d: n.r_d * s,
            q_b: n.q_b * s,
        }
    }

    fn rel(a: f64, b: f64) -> f64 {
        ((a - b) / b).abs()
    }

    #[test]
    fn spec_gain_check_value() {
        let n = nr_noise();
        assert!(rel(n.r_d, 2.0e4) < 1e-3 && rel(n.q_b, 2.0) < 1e-9);
        let k = steady_state_gain(1000.0, n.q_b, n.r_d).unwrap();
        assert!(rel(k[0], 0.199742606467) < 1e-11, "{k}");
        assert!(rel(k[1], 3.994852129331e-4) < 1e-11, "{k}");
        let it = riccati_gain(1000.0, n.q_b, n.r_d, 2000).unwrap();
        assert!(
            rel(it[0], k[0]) < 1e-13 && rel(it[1], k[1]) < 1e-13,
            "{it} vs {k}"
        );
    }

    #[test]
    fn spec_bandwidth_check_values() {
        let n = nr_noise();
        let f = FixedGainKalman::new(n, 1000.0, Form::Standard).unwrap();
        assert!((f.bandwidth().unwrap() - 7.138).abs() < 5e-4);
        for (bw, q) in [(10.0, 1956.52), (20.0, 7640.38), (30.0, 16493.19)] {
            let got = q_omega_for_bandwidth(bw, &n, Form::Standard).unwrap();
            assert!((got - q).abs() < 5e-3, "{bw}: {got}");
            let f = FixedGainKalman::new(n, got, Form::Standard).unwrap();
            assert!(rel(f.bandwidth().unwrap(), bw) < 1e-12);
        }
    }

    #[test]
    fn paper_form_is_slow_and_bounded() {
        let n = nr_noise();
        let f = FixedGainKalman::new(n, 1000.0, Form::Paper).unwrap();
        assert!(f.bandwidth().unwrap() < 1.0 / (2.0 * std::f64::consts::PI));
        let q = q_omega_for_bandwidth(0.1, &n, Form::Paper).unwrap();
        let f = FixedGainKalman::new(n, q, Form::Paper).unwrap();
        assert!(rel(f.bandwidth().unwrap(), 0.1) < 1e-10);
        assert!(q_omega_for_bandwidth(0.2, &n, Form::Paper).is_err());
    }

    #[test]
    fn matrices_match_series_and_gain() {
        let n = nr_noise();
        for form in [Form::Standard, Form::Paper] {
            let f = FixedGainKalman::new(n, 1000.0, form).unwrap();
            let t = n.period;
            let m = -f.continuous_gain() * RowVector2::new(1.0, 1.0);
            // Matrix exponential and its integral by a long Taylor series.
            let (mut a, mut b) = (Matrix2::identity(), Matrix2::identity() * t);
            let mut term = Matrix2::identity();
            for j in 1..60 {
                term = term * m * t / f64::from(j);
                a += term;
                b += term * t / f64::from(j + 1);
            }
            assert!((f.a() - a).abs().max() < 1e-12, "{form:?} A");
            assert!((f.b() - b).abs().max() < 1e-15, "{form:?} B");
            let g = f.b() * f.continuous_gain();
            assert!((g - f.g()).abs().max() < 1e-14, "{form:?} G");
            let ah = Matrix2::identity() - f.g() * RowVector2::new(1.0, 1.0);
            assert!((f.a() - ah).abs().max() < 1e-14, "{form:?} A = I - GH");
        }
        let f = FixedGainKalman::new(n, 1000.0, Form::Standard).unwrap();
        assert_eq!(f.g(), f.gain());
    }

    #[test]
    fn nonsymmetric_matrix_layout() {
        // A = I − G H has rows [1−g1, −g1; −g2, 1−g2] (nalgebra is column-major).
        let f = FixedGainKalman::new(nr_noise(), 1000.0, Form::Standard).unwrap();
        let (a, g) = (f.a(), f.g());
        assert!((a[(0, 1)] + g[0]).abs() < 1e-15 && (a[(1, 0)] + g[1]).abs() < 1e-15);
    }

    #[test]
    fn filter_matches_state_space_loop_and_chunks() {
        let f = FixedGainKalman::new(nr_noise(), 1000.0, Form::Standard).unwrap();
        let z: Vec<f64> = (0..500)
            .map(|i| (f64::from(i) * 0.37).sin() * 3.0 + 1.0)
            .collect();
        let mut st = f.initial_state_from_first_sample(&z, 1).unwrap();
        let (r, b) = f.filter(&z, 1, &mut st.clone()).unwrap();
        let (g, mut x) = (f.g(), Vector2::new(z[0], 0.0));
        for i in 0..z.len() {
            x += g * (z[i] - x[0] - x[1]);
            assert!((x[0] - r[i]).abs() < 1e-12 && (x[1] - b[i]).abs() < 1e-12);
        }
        let (r1, _) = f.filter(&z[..123], 1, &mut st).unwrap();
        let (r2, _) = f.filter(&z[123..], 1, &mut st).unwrap();
        assert_eq!([r1, r2].concat(), r);
    }

    #[test]
    fn nan_leaves_state_unchanged() {
        let f = FixedGainKalman::new(nr_noise(), 1000.0, Form::Standard).unwrap();
        let mut z = vec![1.0; 30];
        z[17] = f64::NAN;
        let mut st = f.initial_state_from_first_sample(&z, 3).unwrap();
        let before = st.clone();
        let err = f.filter(&z, 3, &mut st).unwrap_err();
        assert!(err.to_string().contains("sample 5 axis 2"), "{err}");
        assert_eq!(st, before);
    }

    #[test]
    fn state_records_estimates_and_rejects_foreign_states() {
        let f = FixedGainKalman::new(nr_noise(), 1000.0, Form::Standard).unwrap();
        let other = FixedGainKalman::new(nr_noise(), 2000.0, Form::Standard).unwrap();
        let z: Vec<f64> = (0..40).map(|i| f64::from(i).cos()).collect();
        let mut st = f.initial_state(&[0.5, 1.0], &[0.0, -1.0]).unwrap();
        assert_eq!(
            (st.rate(), st.bias(), st.samples()),
            (&[0.5, 1.0][..], &[0.0, -1.0][..], 0)
        );
        let (r, b) = f.filter(&z, 2, &mut st).unwrap();
        assert_eq!((st.rate(), st.bias()), (&r[38..], &b[38..]));
        assert_eq!(
            (st.samples(), st.n_axes(), st.gain()),
            (20, 2, f.g().into())
        );
        // An empty chunk is a no-op.
        let before = st.clone();
        f.filter(&[], 2, &mut st).unwrap();
        assert_eq!(st, before);
        // Rebuilt from its parts, the state resumes identically.
        let mut copy = KalmanState::new(
            st.level().to_vec(),
            st.offset().to_vec(),
            st.rate().to_vec(),
            st.bias().to_vec(),
            st.gain(),
            st.samples(),
        )
        .unwrap();
        assert_eq!(f.filter(&z, 2, &mut copy), f.filter(&z, 2, &mut st));
        let err = other.filter(&z, 2, &mut st).unwrap_err().to_string();
        assert!(
            err.contains("state") && err.contains("different filter"),
            "{err}"
        );
        assert!(other.estimates(&st).is_err());
        let err = f.filter(&z, 1, &mut st).unwrap_err().to_string();
        assert!(err.contains("state carries 2 axes but z has 1"), "{err}");
        assert_eq!(st, copy);
        let bad = |level: Vec<f64>, rate: Vec<f64>| {
            KalmanState::new(level, vec![0.0], rate, vec![0.0], [0.1, 0.0], 0)
        };
        assert!(
            bad(vec![f64::NAN], vec![0.0])
                .unwrap_err()
                .to_string()
                .contains("state")
        );
        assert!(
            bad(vec![0.0], vec![])
                .unwrap_err()
                .to_string()
                .contains("state")
        );
        let err = f
            .initial_state_from_first_sample(&[1.0, f64::NAN, 0.0, 0.0], 2)
            .unwrap_err()
            .to_string();
        assert!(
            err.contains('z') && err.contains("sample 0 axis 1"),
            "{err}"
        );
    }

    #[test]
    fn bad_parameters() {
        assert!(DiscreteNoise::from_coefficients(0.0, 1.0, 1.0).is_err());
        assert!(DiscreteNoise::from_coefficients(100.0, -1.0, 1.0).is_err());
        assert!(DiscreteNoise::from_coefficients(100.0, 1.0, -1.0).is_err());
        let n = nr_noise();
        assert!(FixedGainKalman::new(n, -1.0, Form::Standard).is_err());
        assert!(q_omega_for_bandwidth(100.0, &n, Form::Standard).is_err());
        assert!(q_omega_for_bandwidth(1e-3, &n, Form::Standard).is_err());
        assert!(Form::parse("fast").is_err());
        for (q, bw) in [(None, None), (Some(1.0), Some(1.0))] {
            let err = FixedGainKalman::design(n, q, bw, Form::Standard).unwrap_err();
            assert!(err.to_string().contains("exactly one"), "{err}");
        }
        let by_q = FixedGainKalman::design(n, Some(1000.0), None, Form::Standard).unwrap();
        assert_eq!(
            by_q,
            FixedGainKalman::new(n, 1000.0, Form::Standard).unwrap()
        );
    }
}
