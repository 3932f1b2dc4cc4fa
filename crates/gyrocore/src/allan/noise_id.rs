//! Power-law noise identification (scaffold).
