//! The one error type of gyrocore.
//!
//! Every variant names the argument at fault and what was wrong with it, so that the Python
//! layer can map it to a `ValueError` whose message a user can act on.

/// Errors reported by gyrocore routines.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A value that must be finite is NaN or infinite.
    #[error("{name} contains a non-finite value (NaN or inf) at index {index}")]
    NonFinite {
        /// Argument name.
        name: &'static str,
        /// Flat index of the first offending value.
        index: usize,
    },
    /// Not enough samples for what was asked.
    #[error("{name} is too short: {needed} samples needed, {got} given")]
    TooShort {
        /// Argument name.
        name: &'static str,
        /// Samples needed.
        needed: usize,
        /// Samples given.
        got: usize,
    },
    /// A parameter outside its valid range or otherwise unusable. Displayed in the package's
    /// one message style, `<name> must be …, got …`, when the reason is a requirement (starts
    /// with "must "), else as `invalid <name>: <reason>`.
    #[error("{}", invalid_message(name, reason))]
    InvalidParameter {
        /// Argument name.
        name: &'static str,
        /// What is wrong with it.
        reason: String,
    },
    /// Arrays whose shapes do not fit together.
    #[error("shape mismatch in {name}: {reason}")]
    ShapeMismatch {
        /// Argument name.
        name: &'static str,
        /// What does not fit.
        reason: String,
    },
    /// A size request (derived from the argument `name`) that this machine cannot allocate:
    /// checked before allocating, so it is an error instead of an abort.
    #[error("{name} asks for {bytes} bytes of memory, more than can be allocated")]
    Allocation {
        /// Argument name.
        name: &'static str,
        /// Bytes requested (exact even when beyond the address space).
        bytes: u128,
    },
    /// A matrix that must be positive definite is not (numerically), or a problem is too
    /// ill-conditioned to give a trustworthy answer.
    #[error("numerically singular or ill-conditioned problem: {reason}")]
    Singular {
        /// What failed and where.
        reason: String,
    },
    /// The caller's progress hook asked to stop (see `allan::progress`).
    #[error("cancelled by the progress callback")]
    Cancelled,
}

/// The message of [`Error::InvalidParameter`]: `"fs must be finite and > 0, got NaN"` for a
/// requirement, `"invalid taus: …"` for any other reason.
fn invalid_message(name: &str, reason: &str) -> String {
    if reason.starts_with("must ") {
        format!("{name} {reason}")
    } else {
        format!("invalid {name}: {reason}")
    }
}

/// Result alias used throughout gyrocore.
pub type Result<T> = std::result::Result<T, Error>;

impl Error {
    /// Shorthand for [`Error::InvalidParameter`].
    pub fn invalid(name: &'static str, reason: impl Into<String>) -> Self {
        Error::InvalidParameter {
            name,
            reason: reason.into(),
        }
    }
}
