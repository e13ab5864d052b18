//! Companion analyses from the same field (docs/math/companion.md).

pub mod dynamics;
pub mod orbit;
pub mod peak;
pub mod tolerance;
pub mod transplanter;
