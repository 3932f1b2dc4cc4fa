//! Equivalent degrees of freedom (scaffold).
