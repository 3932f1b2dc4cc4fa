//! Statistical special functions (scaffold).
