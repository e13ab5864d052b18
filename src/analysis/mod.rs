//! Companion analyses from the same field (spec `companion-methods.md`).

pub mod dynamics;
pub mod orbit;
pub mod tolerance;
