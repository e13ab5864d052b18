//! What a design or simulation run writes: the design's files, the simulation's files, the CAD
//! files of a toothed train (DXF, SVG, STEP), the loads' files, charts, the animation and the
//! JSON Schemas of the reports.

pub mod animate;
mod design_files;
mod dynamics_files;
mod error;
mod fixed;
pub mod json;
mod loads_files;
mod mechanism_preview;
pub mod plot;
pub mod schemas;
mod simulation_files;
mod simulation_plots;
mod step_files;
mod teeth_files;
mod tradeoff_files;

pub use design_files::{DesignFiles, pitch_csv, ratio_plot, write_design, write_design_with};
pub use dynamics_files::{PlotFormat, write_dynamics};
pub use error::OutputError;
pub use loads_files::{loads_csv, write_loads};
pub use mechanism_preview::{mechanism_chart, mechanism_svg};
pub use simulation_files::{SimulationReport, write_simulation};
pub use step_files::{
    SolidOptions, gear_prism, pair_step, train_step, train_step_models, write_step_models,
    write_teeth_step,
};
pub use teeth_files::write_teeth;
pub use tradeoff_files::{tradeoff_plot, write_tradeoff};
