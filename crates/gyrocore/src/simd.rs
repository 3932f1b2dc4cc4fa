//! Runtime choice of the vector instruction set of the core's own kernels.
//!
//! The core is compiled for the target's baseline (x86-64: SSE2; no CPU-specific flags), so a
//! wheel built anywhere runs on every CPU of its architecture. The hot loops are written as
//! `pulp` operations (`pulp::WithSimd`): each is compiled a second time for x86-64-v3 (AVX2,
//! FMA, enabled by pulp's `x86-v3` feature) and [`arch`] picks the variant at run time from the
//! CPU's feature flags, so an older CPU takes the baseline code instead of dying of an illegal
//! instruction.
//!
//! The kernels fix the order of every addition in lanes and form no fused multiply-add, so the
//! two variants give the same bits (the Allan difference sums, Théo1's structure function and
//! edge sums, the Allan-correlation integrals of the noise fit, the generalized Schur
//! recursion of the fractional predictor). Setting the environment variable
//! `GYROBIAS_SIMD=scalar` forces the baseline variant, to check that claim or to rule out the
//! vector code when hunting a problem; it is read once, on first use. Only the core's own
//! kernels follow it: the FFT (`rustfft`) and dense linear algebra (`faer`) libraries detect
//! the CPU on their own, also at run time.

use std::sync::OnceLock;

use crate::{Error, Result};

/// The environment variable read by [`arch`]: `auto` (or unset, or empty) detects the CPU,
/// `scalar` forces the baseline instruction set.
pub const ENV_VAR: &str = "GYROBIAS_SIMD";

/// How [`arch`] chooses the instruction set.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    /// The best instruction set the CPU supports (the default).
    Auto,
    /// The baseline instruction set of the target, whatever the CPU supports.
    Scalar,
}

impl Mode {
    /// Parses a value of [`ENV_VAR`]: `""` or `"auto"`, or `"scalar"` (ASCII case ignored,
    /// surrounding blanks ignored).
    pub fn parse(value: &str) -> Result<Mode> {
        parse(value).map_err(|reason| Error::invalid(ENV_VAR, reason))
    }
}

fn parse(value: &str) -> std::result::Result<Mode, String> {
    match value.trim().to_ascii_lowercase().as_str() {
        "" | "auto" => Ok(Mode::Auto),
        "scalar" => Ok(Mode::Scalar),
        _ => Err(format!("must be 'auto' or 'scalar', got {value:?}")),
    }
}

/// The value of [`ENV_VAR`] when first asked (an invalid value reads as `Err(reason)`).
fn configured() -> &'static std::result::Result<Mode, String> {
    static MODE: OnceLock<std::result::Result<Mode, String>> = OnceLock::new();
    MODE.get_or_init(|| {
        // A value that is not Unicode is as invalid as a misspelt one.
        let value = std::env::var_os(ENV_VAR).unwrap_or_default();
        match value.to_str() {
            Some(text) => parse(text),
            None => Err(format!("must be 'auto' or 'scalar', got {value:?}")),
        }
    })
}

/// Checks the value of [`ENV_VAR`] (the binding calls it when the extension is imported, so a
/// misspelt value is an error instead of silently meaning `auto`).
pub fn check() -> Result<Mode> {
    configured()
        .clone()
        .map_err(|reason| Error::invalid(ENV_VAR, reason))
}

/// The mode in force: [`Mode::Auto`] unless [`ENV_VAR`] says `scalar` (an invalid value, which
/// [`check`] reports, counts as `auto`).
pub fn mode() -> Mode {
    configured().clone().unwrap_or(Mode::Auto)
}

/// The `pulp` dispatcher every kernel of the core uses: the CPU's best variant, or the baseline
/// one when [`mode`] is [`Mode::Scalar`].
#[inline]
pub fn arch() -> pulp::Arch {
    match mode() {
        // The one place that detects the CPU (clippy.toml disallows it elsewhere).
        #[allow(clippy::disallowed_methods)]
        Mode::Auto => pulp::Arch::new(),
        Mode::Scalar => pulp::Arch::Scalar,
    }
}

/// The instruction set [`arch`] selects, by name: `"scalar"` (the target's baseline),
/// `"x86-64-v3"` (AVX2 and FMA) or `"neon"`.
pub fn instruction_set() -> &'static str {
    let arch = arch();
    if matches!(arch, pulp::Arch::Scalar) {
        "scalar"
    } else if cfg!(target_arch = "x86_64") || cfg!(target_arch = "x86") {
        "x86-64-v3"
    } else if cfg!(target_arch = "aarch64") {
        "neon"
    } else {
        "vector"
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parse_accepts_the_documented_values() {
        assert_eq!(Mode::parse("").unwrap(), Mode::Auto);
        assert_eq!(Mode::parse("auto").unwrap(), Mode::Auto);
        assert_eq!(Mode::parse(" Scalar\n").unwrap(), Mode::Scalar);
        let err = Mode::parse("scaler").unwrap_err().to_string();
        assert!(
            err.contains("GYROBIAS_SIMD") && err.contains("\"scaler\""),
            "{err}"
        );
    }

    #[test]
    fn the_selected_instruction_set_has_a_name() {
        let name = instruction_set();
        assert!(["scalar", "x86-64-v3", "neon", "vector"].contains(&name));
        if mode() == Mode::Scalar {
            assert_eq!(name, "scalar");
        }
    }
}
