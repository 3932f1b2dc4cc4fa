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
    /// A parameter outside its valid range or otherwise unusable.
    #[error("invalid {name}: {reason}")]
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
