//! Companion analyses from the same field (spec `companion-methods.md`).

pub mod dynamics;
pub mod montecarlo;
pub mod optimise;
pub mod orbit;
pub mod peak;
pub mod tolerance;
pub mod transplanter;
