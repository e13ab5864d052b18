//! The single integration-test crate (links once): one module per area.
mod design;
mod dynamics;
mod orbit;
mod teeth;
mod tolerance;
