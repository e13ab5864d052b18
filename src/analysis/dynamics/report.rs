//! A whole scene run as `ncgear dynamics` runs it: the solver choice (linear fast path, frequency
//! sweep or transient + recorded window) and the serialisable [`DynamicsReport`], so that a
//! program gets exactly what the CLI prints (serialise it through `serde_json::Value` for the
//! CLI's sorted key order) plus the recorded signals the CLI writes to files.
//!
//! ```no_run
//! use ncgear::analysis::dynamics::{AnalysisOptions, Scene, run};
//! let scene = Scene::from_path("assets/dynamics/sdof_6000.toml".as_ref()).unwrap();
//! let report = run(&scene, "sdof_6000.toml", &AnalysisOptions::default()).unwrap();
//! println!("{}", serde_json::to_value(&report).unwrap());
//! ```

use super::model::Model;
use super::ode::OdeStats;
use super::scene::{Derived, OrbitGear, Scene, SolverMethod};
use super::{
    DynamicsError, Run, RunOptions, SweepPoint, linear_dte_amplitude, natural_frequencies_hz,
    simulate, static_state, sweep,
};
use crate::progress::Progress;
use serde::Serialize;
use std::f64::consts::PI;

/// What [`Prepared::run`] computes besides the scene's own settings. (De)serialisable (a missing field takes its default, an unknown one is an error) and
/// built with `with_*`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, serde::Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
#[non_exhaustive]
pub struct AnalysisOptions {
    /// Frequency sweep over these Ω = ωe/ωn, run in the given order and then back in reverse,
    /// each point starting from the previous point's final state. Default `None`: one run from
    /// the static state. Ignored when the scene takes the linear fast path.
    pub sweep: Option<Vec<f64>>,
}

crate::builder::with_fields!(AnalysisOptions {
    with_sweep => sweep: Option<Vec<f64>>,
});

/// The run log's header: what was built from the scene.
#[derive(Debug, Clone, Serialize, schemars::JsonSchema)]
pub struct ReportHeader {
    /// Scene name.
    pub scene: String,
    /// Kept DOFs, in model order.
    pub dofs: Vec<String>,
    /// Force terms, in model order (names with their parameters).
    pub terms: Vec<String>,
    /// The integrator settings ([`super::Method`] in `Debug` form).
    pub solver: String,
    /// Derived physical parameters.
    pub derived: Derived,
    /// Natural frequencies of the mean-stiffness linearisation, Hz (`None` when a term has no
    /// linear form).
    pub natural_frequencies_hz: Option<Vec<f64>>,
}

/// Summary of a transient + recorded run.
#[derive(Debug, Clone, Serialize, schemars::JsonSchema)]
pub struct RunReport {
    /// Integrator counters (transient + record).
    pub stats: OdeStats,
    /// Transient length, Poincaré periods.
    pub transient_periods: u32,
    /// Whether the Poincaré criterion was met.
    pub steady: bool,
    /// Last relative Poincaré change.
    pub poincare_change: f64,
    /// Mean DTE, m.
    pub dte_mean_m: f64,
    /// DTE amplitudes at k·f_mesh, k = 1..=6, m.
    pub dte_harmonics_m: Vec<f64>,
    /// Half peak-to-peak DTE, m.
    pub dte_half_pp_m: f64,
    /// Largest non-harmonic line of the DTE spectrum, m.
    pub dte_non_harmonic_max_m: f64,
    /// Poincaré section once per mesh period: (DTE µm, dDTE/dt mm/s).
    pub poincare_section: Vec<(f64, f64)>,
}

/// The recorded signals of a run, for files and plots (not serialised).
#[derive(Debug, Clone)]
pub struct Recording {
    /// The raw record (times, DTE, mesh force, states).
    pub run: Run,
    /// Extra time-series columns of `output.signals`: (DOF name, state index).
    pub signals: Vec<(String, usize)>,
    /// Phase plane (DTE µm, dDTE/dt mm/s), the rate by spectral derivative over the
    /// integer-period record.
    pub phase: Vec<(f64, f64)>,
    /// DTE spectrum (f Hz, amplitude m) for k ≥ 1, when `output.spectrum`.
    pub spectrum: Option<Vec<(f64, f64)>>,
    /// Orbits of `output.orbit`: the gear and its centre's (x, y) in µm.
    pub orbits: Vec<(OrbitGear, Vec<(f64, f64)>)>,
}

impl Recording {
    /// Column names of the time series: `t_s`, `dte_m`, `mesh_force_n`, then the DOF signals.
    #[must_use]
    pub fn timeseries_header(&self) -> Vec<String> {
        let mut h = vec!["t_s".to_string(), "dte_m".into(), "mesh_force_n".into()];
        h.extend(self.signals.iter().map(|(s, _)| s.clone()));
        h
    }

    /// Time-series rows, in the order of [`Self::timeseries_header`] (SI units).
    pub fn timeseries_rows(&self) -> impl Iterator<Item = Vec<f64>> + '_ {
        let r = &self.run;
        (0..r.t_s.len()).map(move |k| {
            let mut row = vec![r.t_s[k], r.dte_m[k], r.mesh_force_n[k]];
            row.extend(self.signals.iter().map(|&(_, i)| r.states[k][i]));
            row
        })
    }
}

/// Everything `ncgear dynamics --json` prints: the header, then the result of the path taken
/// (linear amplitude, sweep, or run summary); `recording` holds the run's signals.
#[derive(Debug, Clone, Serialize, schemars::JsonSchema)]
pub struct DynamicsReport {
    /// What was built.
    #[serde(flatten)]
    pub header: ReportHeader,
    /// Linear fast path: DTE amplitude at the mesh frequency, m.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub linear_dte_amplitude_m: Option<f64>,
    /// Sweep: the points in the requested order.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sweep_up: Option<Vec<SweepPoint>>,
    /// Sweep: the points back in reverse order.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sweep_down: Option<Vec<SweepPoint>>,
    /// Transient + recorded run.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub run: Option<RunReport>,
    /// The run's signals (with `run` only).
    #[serde(skip)]
    pub recording: Option<Recording>,
}

/// A scene ready to run: the built model, the run options and the run log's header.
pub struct Prepared {
    /// The scene.
    pub scene: Scene,
    /// Its file name, for messages.
    pub file: String,
    /// The built model.
    pub model: Model,
    /// Run options from `[solver]` and `[output]`.
    pub options: RunOptions,
    /// The run log's header.
    pub header: ReportHeader,
}

impl Prepared {
    /// Builds the model and the run options of `scene` (`file` names it in errors).
    ///
    /// # Errors
    /// [`DynamicsError::Scene`], [`DynamicsError::BadOption`].
    pub fn new(scene: Scene, file: &str) -> Result<Self, DynamicsError> {
        let (model, derived) = scene.build(file)?;
        let options = RunOptions::from_scene(&scene, &model)?;
        let header = ReportHeader {
            scene: scene.scene.name.clone(),
            dofs: model.dof_names().iter().map(|s| s.to_string()).collect(),
            terms: model.terms.iter().map(|t| t.name()).collect(),
            solver: format!("{:?}", options.method),
            derived,
            natural_frequencies_hz: natural_frequencies_hz(&model).ok(),
        };
        Ok(Self {
            scene,
            file: file.into(),
            model,
            options,
            header,
        })
    }

    /// Whether [`Self::run`] takes the linear fast path: `method = "linear"`, or `"auto"` with a
    /// linear model.
    #[must_use]
    pub fn takes_linear_path(&self) -> bool {
        match self.scene.solver.method {
            SolverMethod::Linear => true,
            SolverMethod::Auto => self.model.is_linear(),
            SolverMethod::Dopri5 | SolverMethod::Rk4 => false,
        }
    }

    /// Runs the scene: the linear fast path if [`Self::takes_linear_path`], else the sweep of
    /// `options.sweep`, else a transient from the static state and the recorded window.
    /// `progress` hears the finished Poincaré periods (run) or sweep points (up, then down,
    /// counted on).
    ///
    /// # Errors
    /// [`DynamicsError`]: a nonlinear model on the linear path, an `[output]` request without
    /// its DOFs, integrator failure or divergence.
    pub fn run(
        &self,
        options: &AnalysisOptions,
        progress: &Progress,
    ) -> Result<DynamicsReport, DynamicsError> {
        let mut report = DynamicsReport {
            header: self.header.clone(),
            linear_dte_amplitude_m: None,
            sweep_up: None,
            sweep_down: None,
            run: None,
            recording: None,
        };
        if self.takes_linear_path() {
            report.linear_dte_amplitude_m = Some(linear_dte_amplitude(&self.model)?);
        } else if let Some(up) = &options.sweep {
            let (s, f, o) = (&self.scene, self.file.as_str(), &self.options);
            let down: Vec<f64> = up.iter().rev().copied().collect();
            // Both sweeps start from the static state: they run side by side (each in order,
            // so the same numbers for any thread count); `progress` counts the points of both.
            let (res_up, res_down) = rayon::join(
                || sweep(s, f, up, o, None, progress),
                || sweep(s, f, &down, o, None, progress),
            );
            report.sweep_up = Some(res_up?);
            report.sweep_down = Some(res_down?);
        } else {
            let (summary, recording) = self.record(progress)?;
            report.run = Some(summary);
            report.recording = Some(recording);
        }
        Ok(report)
    }

    /// The transient + recorded run and what is derived from it.
    fn record(&self, progress: &Progress) -> Result<(RunReport, Recording), DynamicsError> {
        let model = &self.model;
        let signals = self.signal_columns()?;
        let orbit_dofs = self.orbit_dofs()?;
        let y0 = static_state(model, 1e-6);
        let run = simulate(model, &y0, &self.options, progress)?;
        // phase plane (spectral derivative over the integer-period record, period t_rec)
        let t_rec = model.mesh.t0 * f64::from(self.options.record_mesh_periods);
        let rate: Vec<f64> = crate::math::periodic::spectral_derivative(&run.dte_m)
            .iter()
            .map(|d| d * 2.0 * PI / t_rec)
            .collect();
        let phase: Vec<(f64, f64)> = run
            .dte_m
            .iter()
            .zip(&rate)
            .map(|(d, v)| (d * 1e6, v * 1e3))
            .collect();
        let spm = run.samples_per_mesh as usize;
        let poincare_section: Vec<(f64, f64)> = phase.iter().step_by(spm).copied().collect();
        // one-sided amplitude spectrum 2|c_k| at f_k = k / t_rec
        let spectrum = self.scene.output.spectrum.then(|| {
            let df = 1.0 / t_rec;
            crate::math::periodic::fft_coefficients(&run.dte_m)
                .iter()
                .enumerate()
                .skip(1)
                .map(|(k, z)| (k as f64 * df, 2.0 * z.norm()))
                .collect()
        });
        let orbits = orbit_dofs
            .into_iter()
            .map(|(gear, ix, iy)| {
                let pts = run.states.iter().map(|s| (s[ix] * 1e6, s[iy] * 1e6));
                (gear, pts.collect())
            })
            .collect();
        let h = run.dte_harmonics(6);
        let summary = RunReport {
            stats: run.stats,
            transient_periods: run.transient_periods,
            steady: run.steady,
            poincare_change: run.poincare_change,
            dte_mean_m: h[0],
            dte_harmonics_m: h[1..].to_vec(),
            dte_half_pp_m: run.dte_half_pp(),
            dte_non_harmonic_max_m: run.dte_non_harmonic(),
            poincare_section,
        };
        let recording = Recording {
            run,
            signals,
            phase,
            spectrum,
            orbits,
        };
        Ok((summary, recording))
    }

    /// The DOF columns of `output.signals` (`dte` and `mesh_force` are always recorded).
    fn signal_columns(&self) -> Result<Vec<(String, usize)>, DynamicsError> {
        let model = &self.model;
        let mut cols = Vec::new();
        for s in &self.scene.output.signals {
            if s == "dte" || s == "mesh_force" {
                continue;
            }
            let i = model.index_of(s).ok_or_else(|| DynamicsError::Output {
                key: "output.signals",
                message: format!(
                    "`{s}` is not a DOF of this scene; DOFs: {}",
                    model.dof_names().join(", ")
                ),
            })?;
            cols.push((s.clone(), i));
        }
        Ok(cols)
    }

    /// The (x, y) DOFs of each `output.orbit` gear centre.
    fn orbit_dofs(&self) -> Result<Vec<(OrbitGear, usize, usize)>, DynamicsError> {
        let model = &self.model;
        let mut out = Vec::new();
        for &gear in &self.scene.output.orbit {
            let (which, g) = match gear {
                OrbitGear::Pinion => ("pinion", 1),
                OrbitGear::Gear => ("gear", 2),
            };
            let (Some(ix), Some(iy)) = (
                model.index_of(&format!("x{g}")),
                model.index_of(&format!("y{g}")),
            ) else {
                return Err(DynamicsError::Output {
                    key: "output.orbit",
                    message: format!(
                        "the {which} centre has no lateral DOFs (x{g}, y{g}) in this scene"
                    ),
                });
            };
            out.push((gear, ix, iy));
        }
        Ok(out)
    }
}

/// Runs `scene` as `ncgear dynamics` does ([`Prepared::new`], then [`Prepared::run`] without
/// progress reports); `file` names the scene in errors.
///
/// # Errors
/// [`DynamicsError`].
pub fn run(
    scene: &Scene,
    file: &str,
    options: &AnalysisOptions,
) -> Result<DynamicsReport, DynamicsError> {
    Prepared::new(scene.clone(), file)?.run(options, &Progress::none())
}
