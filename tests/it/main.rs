//! The single integration-test crate (links once): one module per area.
mod dynamics;
mod orbit;
mod teeth;
mod tolerance;
