//! The single integration-test crate (links once): one module per area.
mod cli;
mod cli_design;
mod design;
mod dynamics;
mod hard_cases;
mod orbit;
mod robust;
mod simulate;
mod svg_render;
mod teeth;
mod tolerance;
mod train;
mod transplanter;
