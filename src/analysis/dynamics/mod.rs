//! Spur-gear pair nonlinear dynamics driven by scene files (docs/math/companion.md §B,
//! patent CN110162909B): the 16-DOF lumped-mass model with time-varying mesh stiffness,
//! static transmission error, tip relief, backlash, sliding friction, eccentricity, gravity,
//! shafts and nonlinear (Hertz) bearings. Every effect is off unless the scene names it (docs/math/companion.md §B.10);
//! the loader prunes the DOF set (16 / 6 / 4 / 2 / 1), builds the force-term list and the
//! breakpoint/event sets once.
//!
//! Units: scene files speak mm, µm, degrees, rpm; the library works in SI (m, kg, s, rad, N).
//!
//! A newcomer's map: [`scene`] reads and validates a scene file and builds the [`model::Model`];
//! [`options`] holds the integrator settings; [`simulation`] integrates (static state, transient,
//! recorded window); [`linear`] holds the eigen- and frequency-response analyses; [`mod@sweep`] the
//! frequency sweeps; [`report`] runs a whole scene as the CLI does and returns a serialisable
//! [`DynamicsReport`]. [`ode`] and [`tvms`] are the integrators and the mesh-stiffness formulas.

pub mod linear;
pub mod model;
pub mod ode;
pub mod options;
pub mod report;
pub mod rotor;
pub mod scene;
pub mod simulation;
pub mod sweep;
pub mod tvms;

pub use linear::{linear_dte_amplitude, natural_frequencies_hz};
pub use options::{
    DEFAULT_TRANSIENT_MESH_PERIODS, MAX_RECORDED_SAMPLES, MAX_TRANSIENT_PERIODS, Method,
    RunOptions, default_transient_periods,
};
pub use report::{
    AnalysisOptions, DynamicsReport, Prepared, Recording, ReportHeader, RunReport, run,
};
pub use scene::{Derived, Scene, SceneError};
pub use simulation::{Run, energy_audit, harmonics, simulate, static_state};
pub use sweep::{SweepPoint, sdof_contact_loss_ratio, sweep};

use ode::OdeError;

/// Errors of a dynamics run.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum DynamicsError {
    /// Bad scene.
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// Integrator failure or bad settings.
    #[error(transparent)]
    Ode(#[from] OdeError),
    /// The requested analysis needs a linear model.
    #[error("the linear analysis needs a linear model, but term `{0}` has no linear form")]
    NotLinear(String),
    /// A non-finite state appeared (diverging response).
    #[error("the response diverged (non-finite state) at t = {0} s")]
    Diverged(f64),
    /// An `[output]` request the model cannot serve (a signal or orbit without its DOFs).
    #[error("{key}: {message}")]
    Output {
        /// Scene key.
        key: &'static str,
        /// What is wrong, with the available choices.
        message: String,
    },
    /// A bad option value.
    #[error("option `{name}` = {value}: expected {expected}")]
    BadOption {
        /// Option.
        name: &'static str,
        /// Value.
        value: String,
        /// Expected form.
        expected: &'static str,
    },
}
