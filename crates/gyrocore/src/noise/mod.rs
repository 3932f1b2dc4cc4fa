//! IEEE-952 noise terms of rate sensors: simulation with known coefficients and their
//! identification from an Allan variance (SPEC §3, IEEE Std 952-1997 Annex C, \[NR\] Table 1).
//!
//! The five-term model of the (overlapping) Allan variance of a rate signal is
//!
//! ```text
//! σ²(τ) = 3Q²/τ² + N²/τ + (0.664282·B)² + K²τ/3 + R²τ²/2
//! ```
//!
//! with quantisation Q, angle random walk N, bias instability B (flicker rate noise, two-sided
//! PSD `B²/(2π f)`, plateau factor `√(2 ln 2/π)`), rate random walk K and rate ramp R. For a rate
//! in u/s: Q in u, N in u/√s, B in u/s, K in u/s^1.5, R in u/s².
//!
//! * [`simulate()`]: synthetic rate noise with exactly these coefficients.
//! * [`fit`](mod@fit): joint weighted non-negative least squares of the model (the better estimator),
//!   with Gauss–Markov terms, goodness-of-fit diagnostics and automatic τ-range selection.
//! * [`gauss_markov`]: first-order Gauss–Markov (exponentially correlated) terms.
//! * [`gmwm`](mod@gmwm): the generalized method of wavelet moments (Guerrier et al. 2013) on the Haar
//!   wavelet variance ([`wavelet`]).
//! * [`ieee`]: the IEEE-952 read-off (fixed-slope lines on detected slope regions, B from the
//!   minimum).
//! * [`mod@overbound`]: conservative coefficients whose model overbounds the curve's upper
//!   confidence bound (Lethander & Taylor 2023).
//! * [`bound`]: upper bounds of the terms the curve does not show.
//! * [`discrete`]: per-sample equivalents (white, random-walk step, Gauss–Markov φ) and the
//!   datasheet conventions (one/two-sided densities, Allan-minimum bias instability).
//! * [`sinusoid`]: the IEEE-952 sinusoidal term (a periodic disturbance) and spectral-line
//!   detection against the local noise floor.
//! * [`model`]: the basis functions, slopes, read-off times and simple EDF approximations.

pub mod bound;
pub mod covariance;
pub mod curve;
pub mod discrete;
pub mod fit;
pub mod gauss_markov;
pub mod gmwm;
pub mod ieee;
pub mod model;
pub mod overbound;
pub mod simulate;
pub mod sinusoid;
pub mod variance_limit;
pub mod wavelet;

pub use bound::{BOUND_CONFIDENCE, UpperBound, upper_bound};
pub use curve::{Curve, TermEstimate, parse_terms};
pub use fit::{
    Diagnostics, FitOptions, GaussMarkovEstimate, JointFit, LineEstimate, diagnose, fit,
    full_model, joint, model_term_symbols, parse_model_terms,
};
pub use gmwm::{GmwmFit, GmwmOptions, gmwm};
pub use ieee::{ReadOff, ReadOffOptions, read_off};
pub use model::{FLICKER_FACTOR, Term, approximate_edf, model_curves, model_variance};
pub use overbound::{Conservative, Overbound, conservative, overbound, overbound_above};
pub use simulate::{Ar1, NoiseSpec, simulate, simulate_axis};
pub use wavelet::{WaveletVariance, haar};
