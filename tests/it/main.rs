//! The single integration-test crate (links once): one module per area.
// `!(x <= tol)` is how the quality checks fail a NaN together with an out-of-range value.
#![allow(clippy::neg_cmp_op_on_partial_ord)]
mod bounds;
mod cli;
mod cli_design;
mod compare;
mod design;
mod doc_refs;
mod drawings;
mod dynamics;
mod hard_cases;
mod input_ranges;
mod layout;
mod limits;
mod loads;
mod loads_cli;
mod loads_dynamic;
mod loads_rating;
mod looped_drawings;
mod noise;
mod options;
mod orbit;
mod pair_ratios;
mod pair_sector;
mod periodic_tables;
mod quality;
mod robust;
mod rotor_charts;
mod rotor_drive;
mod rotor_dynamics;
mod schemas;
mod shaper;
mod simulate;
mod step;
mod svg_render;
mod swept;
mod synthesis;
mod synthesis_targets;
mod teeth;
mod tolerance;
mod tradeoff;
mod train;
mod transplanter;
mod undercut;
mod warm;

use ncgear::design::Design;
use ncgear::design::train::TrainSource;

/// The train of `d` as read from its `design.json` (assembly and target, no mechanism): the
/// scaling tooth policies, the round trip over the target alone.
fn assembled(d: &Design) -> TrainSource<'_> {
    TrainSource::Assembly {
        assembly: &d.assembly,
        target_mm: &d.report.target_points,
    }
}
