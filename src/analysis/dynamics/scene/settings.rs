//! The scene's run settings: the `[solver]` table (integrator, tolerances, steady-state criterion,
//! recorded window) and the `[output]` table (signals, sampling, spectrum, orbits), with their
//! defaults.

use serde::{Deserialize, Serialize};

/// `[solver]`.
#[derive(Debug, Clone, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SolverSpec {
    /// Integrator (default `auto`).
    #[serde(default)]
    pub method: SolverMethod,
    /// Relative tolerance (default 1e-6).
    #[serde(default = "rtol")]
    pub rtol: f64,
    /// Absolute tolerance (m, rad, m/s units mixed; default 1e-12).
    #[serde(default = "atol")]
    pub atol: f64,
    /// Split the integration at the known switch times (default true).
    #[serde(default = "yes")]
    pub breakpoints: bool,
    /// Locate contact loss/re-contact events (default true).
    #[serde(default = "yes")]
    pub events: bool,
    /// RK4 steps per mesh period (default 80).
    #[serde(default = "steps")]
    pub rk4_steps_per_mesh: u32,
    /// Recorded window after the steady state, mesh periods (default 200).
    #[serde(default = "record")]
    pub record_mesh_periods: u32,
    /// Steady-state criterion.
    #[serde(default)]
    pub steady_state: SteadySpec,
}

/// `solver.method`.
#[derive(
    Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize, schemars::JsonSchema,
)]
#[serde(rename_all = "snake_case")]
pub enum SolverMethod {
    /// The linear fast path when the model is linear, DOPRI5 otherwise.
    #[default]
    Auto,
    /// Adaptive DOPRI5 with dense output.
    Dopri5,
    /// Fixed-step classical RK4.
    Rk4,
    /// The linear fast path (frequency response); an error for a nonlinear model.
    Linear,
}

impl SolverMethod {
    /// The `method` string of the file.
    #[must_use]
    pub fn as_str(self) -> &'static str {
        match self {
            Self::Auto => "auto",
            Self::Dopri5 => "dopri5",
            Self::Rk4 => "rk4",
            Self::Linear => "linear",
        }
    }
}

impl Default for SolverSpec {
    fn default() -> Self {
        Self {
            method: SolverMethod::Auto,
            rtol: rtol(),
            atol: atol(),
            breakpoints: true,
            events: true,
            rk4_steps_per_mesh: steps(),
            record_mesh_periods: record(),
            steady_state: SteadySpec::default(),
        }
    }
}

fn rtol() -> f64 {
    1e-6
}
fn atol() -> f64 {
    1e-12
}
fn steps() -> u32 {
    80
}
fn record() -> u32 {
    200
}

/// Poincaré steady-state criterion.
#[derive(Debug, Clone, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SteadySpec {
    /// Relative change of the Poincaré sample below which the run is steady (default 1e-7).
    #[serde(default = "ptol")]
    pub poincare_tol: f64,
    /// Maximal transient, Poincaré periods (default: as many as make
    /// [`crate::analysis::dynamics::DEFAULT_TRANSIENT_MESH_PERIODS`] mesh periods, at least one —
    /// 2000 when the Poincaré period is one mesh period, 10 with eccentricity on a 25/40 pair,
    /// whose Poincaré period is the hunting period of 200 mesh periods).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_periods: Option<u32>,
}

impl Default for SteadySpec {
    fn default() -> Self {
        Self {
            poincare_tol: ptol(),
            max_periods: None,
        }
    }
}

fn ptol() -> f64 {
    1e-7
}

/// `[output]`.
#[derive(Debug, Clone, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct OutputSpec {
    /// Signals: `dte`, `mesh_force`, or DOF names (default `["dte", "mesh_force"]`).
    #[serde(default = "signals")]
    pub signals: Vec<String>,
    /// Samples per mesh period (default 64).
    #[serde(default = "spm")]
    pub samples_per_mesh: u32,
    /// Compute the DTE spectrum (default true).
    #[serde(default = "yes")]
    pub spectrum: bool,
    /// Orbits: `pinion` and/or `gear` (default none).
    #[serde(default)]
    pub orbit: Vec<OrbitGear>,
}

/// `output.orbit` entries.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum OrbitGear {
    /// The pinion centre (x1, y1).
    Pinion,
    /// The gear centre (x2, y2).
    Gear,
}

impl OrbitGear {
    /// `pinion` or `gear`.
    #[must_use]
    pub fn as_str(self) -> &'static str {
        match self {
            Self::Pinion => "pinion",
            Self::Gear => "gear",
        }
    }
}

impl Default for OutputSpec {
    fn default() -> Self {
        Self {
            signals: signals(),
            samples_per_mesh: spm(),
            spectrum: true,
            orbit: Vec::new(),
        }
    }
}

fn signals() -> Vec<String> {
    vec!["dte".into(), "mesh_force".into()]
}
fn spm() -> u32 {
    64
}

pub(super) fn yes() -> bool {
    true
}
