//! Run options: the time integrator (docs/math/companion.md §B.11), the Poincaré steady-state criterion and the recorded
//! window, read from a scene's `[solver]` and `[output]` tables or set directly.

use super::DynamicsError;
use super::model::Model;
use super::ode::Dopri5;
use super::scene::{Scene, SolverMethod};

/// Largest number of recorded samples of a run (`record_mesh_periods × samples_per_mesh`).
pub const MAX_RECORDED_SAMPLES: u64 = 2_000_000;

/// Largest transient length, Poincaré periods.
pub const MAX_TRANSIENT_PERIODS: u32 = 100_000;

/// Time integrator choice (docs/math/companion.md §B.11); written `{"dopri5": {"rtol": …, "atol":
/// …, "breakpoints": …, "events": …}}` or `{"rk4": {"steps_per_mesh": …, "aligned": …}}`.
#[derive(
    Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Method {
    /// Adaptive DOPRI5 with dense output.
    Dopri5 {
        /// Relative tolerance.
        rtol: f64,
        /// Absolute tolerance.
        atol: f64,
        /// Split at the known switch times.
        breakpoints: bool,
        /// Locate backlash contact loss / re-contact.
        events: bool,
    },
    /// Fixed-step classical RK4.
    Rk4 {
        /// Steps per mesh period.
        steps_per_mesh: u32,
        /// Align the steps to the switch times.
        aligned: bool,
    },
}

/// Run options (solver, steady state, recording). The defaults are those of a scene without
/// `[solver]` and `[output]` tables. (De)serialisable (a missing field takes its default, an unknown one is an error) and
/// built with `with_*`.
#[derive(
    Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize, schemars::JsonSchema,
)]
#[serde(default, deny_unknown_fields)]
#[non_exhaustive]
pub struct RunOptions {
    /// Integrator (default DOPRI5, rtol 1e-6, atol 1e-12, breakpoints and events on).
    pub method: Method,
    /// Poincaré steady-state tolerance (relative change per Poincaré period; default 1e-7).
    pub poincare_tol: f64,
    /// Maximal transient, Poincaré periods (0: no transient; default 2000).
    pub max_periods: u32,
    /// Recorded mesh periods (default 200).
    pub record_mesh_periods: u32,
    /// Samples per mesh period (default 64).
    pub samples_per_mesh: u32,
}

/// The longest transient a scene gets when it does not set `steady_state.max_periods`, in mesh
/// periods. A scene whose Poincaré criterion is never met (friction lets the rigid-body rotation
/// drift) runs its whole transient: counted in Poincaré periods, 2000 hunting periods of a
/// 25/40 pair with eccentricity were 400 000 mesh periods, minutes of integration.
pub const DEFAULT_TRANSIENT_MESH_PERIODS: u32 = 2000;

/// The default transient of `model` in Poincaré periods: `⌈2000·t_mesh/T_Poincaré⌉`, at least 1
/// ([`DEFAULT_TRANSIENT_MESH_PERIODS`]).
#[must_use]
pub fn default_transient_periods(model: &Model) -> u32 {
    let per = (model.poincare_period / model.mesh.t0).round().max(1.0);
    let n = (f64::from(DEFAULT_TRANSIENT_MESH_PERIODS) / per).ceil();
    // `per` ≥ 1, so n ≤ 2000.
    (n as u32).max(1)
}

crate::builder::with_fields!(RunOptions {
    with_method => method: Method,
    with_poincare_tol => poincare_tol: f64,
    with_max_periods => max_periods: u32,
    with_record_mesh_periods => record_mesh_periods: u32,
    with_samples_per_mesh => samples_per_mesh: u32,
});

impl Default for RunOptions {
    fn default() -> Self {
        Self {
            method: Method::Dopri5 {
                rtol: 1e-6,
                atol: 1e-12,
                breakpoints: true,
                events: true,
            },
            poincare_tol: 1e-7,
            max_periods: 2000,
            record_mesh_periods: 200,
            samples_per_mesh: 64,
        }
    }
}

impl RunOptions {
    /// Options from the scene's `[solver]` and `[output]` tables (`auto` and `linear` integrate
    /// with DOPRI5 when they integrate at all), for the scene's built `model`: without
    /// `steady_state.max_periods` the transient is at most [`DEFAULT_TRANSIENT_MESH_PERIODS`]
    /// mesh periods ([`default_transient_periods`]).
    ///
    /// # Errors
    /// [`DynamicsError::BadOption`] naming the scene key.
    pub fn from_scene(s: &Scene, model: &Model) -> Result<Self, DynamicsError> {
        let v = &s.solver;
        let method = match v.method {
            SolverMethod::Auto | SolverMethod::Dopri5 | SolverMethod::Linear => Method::Dopri5 {
                rtol: v.rtol,
                atol: v.atol,
                breakpoints: v.breakpoints,
                events: v.events,
            },
            SolverMethod::Rk4 => Method::Rk4 {
                steps_per_mesh: v.rk4_steps_per_mesh,
                aligned: v.breakpoints,
            },
        };
        let o = Self {
            method,
            poincare_tol: v.steady_state.poincare_tol,
            max_periods: v
                .steady_state
                .max_periods
                .unwrap_or_else(|| default_transient_periods(model)),
            record_mesh_periods: v.record_mesh_periods,
            samples_per_mesh: s.output.samples_per_mesh,
        };
        o.validate()?;
        Ok(o)
    }

    /// A fixed window without transient: integrate `mesh_periods` from the initial state and
    /// record them at `samples_per_mesh` (used for accuracy studies and benchmarks).
    #[must_use]
    pub fn window(method: Method, mesh_periods: u32, samples_per_mesh: u32) -> Self {
        Self {
            method,
            poincare_tol: 1.0,
            max_periods: 0,
            record_mesh_periods: mesh_periods,
            samples_per_mesh,
        }
    }

    pub(super) fn validate(&self) -> Result<(), DynamicsError> {
        if self.samples_per_mesh < 2 {
            return Err(DynamicsError::BadOption {
                name: "output.samples_per_mesh",
                value: self.samples_per_mesh.to_string(),
                expected: "an integer ≥ 2",
            });
        }
        let samples = u64::from(self.record_mesh_periods) * u64::from(self.samples_per_mesh);
        if samples > MAX_RECORDED_SAMPLES {
            return Err(DynamicsError::BadOption {
                name: "solver.record_mesh_periods × output.samples_per_mesh",
                value: samples.to_string(),
                expected: "at most 2 000 000 recorded samples",
            });
        }
        if self.max_periods > MAX_TRANSIENT_PERIODS {
            return Err(DynamicsError::BadOption {
                name: "solver.steady_state.max_periods",
                value: self.max_periods.to_string(),
                expected: "at most 100 000 Poincaré periods",
            });
        }
        if self.record_mesh_periods < 1 {
            return Err(DynamicsError::BadOption {
                name: "solver.record_mesh_periods",
                value: "0".into(),
                expected: "an integer ≥ 1",
            });
        }
        if !(self.poincare_tol > 0.0 && self.poincare_tol.is_finite()) {
            return Err(DynamicsError::BadOption {
                name: "solver.steady_state.poincare_tol",
                value: self.poincare_tol.to_string(),
                expected: "a positive finite number",
            });
        }
        match self.method {
            Method::Dopri5 { rtol, atol, .. } => {
                // A bad tolerance is the scene's input (exit 2), named by its key, not an
                // integrator failure.
                for (name, v) in [("solver.rtol", rtol), ("solver.atol", atol)] {
                    if !(v > 0.0 && v.is_finite()) {
                        return Err(DynamicsError::BadOption {
                            name,
                            value: v.to_string(),
                            expected: "a positive finite number",
                        });
                    }
                }
                Dopri5::new(rtol, atol)?;
            }
            Method::Rk4 { steps_per_mesh, .. } if !(4..=1_000_000).contains(&steps_per_mesh) => {
                return Err(DynamicsError::BadOption {
                    name: "solver.rk4_steps_per_mesh",
                    value: steps_per_mesh.to_string(),
                    expected: "an integer in 4..=1000000",
                });
            }
            Method::Rk4 { .. } => {}
        }
        Ok(())
    }
}
