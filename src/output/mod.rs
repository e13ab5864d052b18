//! What a run writes: the design's files, the simulation's files, the CAD files of a toothed
//! train (DXF, SVG, STEP), the pair's report, the synthesis', loads', dynamics' (the rotor's too), orbit and tolerance files, charts, the
//! animation and the JSON Schemas of the reports.

pub mod animate;
mod compare_files;
pub mod compare_plot;
mod design_files;
mod dynamics_files;
mod error;
mod fixed;
pub mod json;
mod loads_files;
mod mechanism_preview;
mod orbit_files;
mod pair_files;
pub mod plot;
mod rotor_files;
mod rotor_plots;
pub mod schemas;
mod simulation_files;
mod simulation_plots;
mod step_files;
mod synthesis_files;
mod teeth_files;
mod tolerance_files;
mod tradeoff_files;

pub use compare_files::{compare_frames_csv, write_compare};
pub use design_files::{DesignFiles, pitch_csv, ratio_plot, write_design, write_design_with};
pub use dynamics_files::write_dynamics;
pub use error::OutputError;
pub use loads_files::{loads_csv, write_loads};
pub use mechanism_preview::{mechanism_chart, mechanism_svg};
pub use orbit_files::{write_orbit_measure_plots, write_orbit_model_plot};
pub use pair_files::write_pair_report;
pub use plot::PlotFormat;
pub use rotor_files::{rotor_sweep_csv, rotor_sweep_table, write_rotor, write_rotor_sweep};
pub use simulation_files::{SimulationReport, write_simulation};
pub use step_files::{
    SolidOptions, gear_prism, pair_step, train_step, train_step_models, write_step_models,
    write_teeth_step,
};
pub use synthesis_files::write_synthesis;
pub use teeth_files::write_teeth;
pub use tolerance_files::{write_tolerance, write_transplanter};
pub use tradeoff_files::{tradeoff_plot, write_tradeoff};
