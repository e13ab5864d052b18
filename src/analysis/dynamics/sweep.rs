//! Frequency sweeps (docs/math/companion.md §B.7, §B.9-3): the response over Ω = ωe/ωn, each point continuing from the
//! previous one's final state so that the jump phenomenon shows, and the closed-form contact-loss
//! ratio of the dimensionless backlash oscillator.

use super::scene::Scene;
use super::{DynamicsError, RunOptions, simulate, static_state};
use crate::progress::Progress;
use serde::Serialize;

/// One point of a frequency sweep.
#[derive(Debug, Clone, Serialize, schemars::JsonSchema)]
pub struct SweepPoint {
    /// Pinion speed, rpm.
    pub n1_rpm: f64,
    /// Ω = ωe/ωn.
    pub omega_ratio: f64,
    /// Half peak-to-peak DTE, m.
    pub dte_half_pp_m: f64,
    /// Mean DTE, m.
    pub dte_mean_m: f64,
    /// Amplitude of the DTE at the mesh frequency, m.
    pub dte_first_harmonic_m: f64,
    /// Fraction of samples with |δ| ≤ b (contact loss), 0 without backlash.
    pub contact_loss_fraction: f64,
    /// Poincaré criterion met.
    pub steady: bool,
}

/// Frequency sweep over `omega_ratios` (Ω = ωe/ωn, in the given order: ascending = sweep up,
/// descending = sweep down), each point starting from the previous point's final state so that
/// the jump phenomenon shows. The first point starts from `y0` (or the static state).
pub fn sweep(
    scene: &Scene,
    file: &str,
    omega_ratios: &[f64],
    opts: &RunOptions,
    y0: Option<&[f64]>,
    progress: &Progress,
) -> Result<Vec<SweepPoint>, DynamicsError> {
    let d = scene.derived(file)?;
    let mut state: Option<Vec<f64>> = y0.map(<[f64]>::to_vec);
    let mut out = Vec::with_capacity(omega_ratios.len());
    for &om in omega_ratios {
        if !(om.is_finite() && om > 0.0) {
            return Err(DynamicsError::BadOption {
                name: "omega_ratio",
                value: om.to_string(),
                expected: "a positive frequency ratio",
            });
        }
        let mut s = scene.clone();
        s.operating.n1_rpm =
            om * d.omega_n_rad_s * 60.0 / (2.0 * std::f64::consts::PI * scene.gears.z1 as f64);
        let (model, _) = s.build(file)?;
        let y = state.clone().unwrap_or_else(|| static_state(&model, 1e-6));
        let run = simulate(&model, &y, opts, &Progress::none())?;
        let b = model.mesh.backlash.map_or(0.0, |b| b.b);
        let h = run.dte_harmonics(1);
        let loss = if b > 0.0 {
            run.dte_m.iter().filter(|d| d.abs() <= b).count() as f64 / run.dte_m.len() as f64
        } else {
            0.0
        };
        out.push(SweepPoint {
            n1_rpm: s.operating.n1_rpm,
            omega_ratio: om,
            dte_half_pp_m: run.dte_half_pp(),
            dte_mean_m: h[0],
            dte_first_harmonic_m: h[1],
            contact_loss_fraction: loss,
            steady: run.steady,
        });
        state = run.states.last().cloned();
        progress.advance(1);
    }
    Ok(out)
}

/// Contact-loss (jump-up) frequency ratio of the dimensionless backlash oscillator (docs/math/companion.md §B.7, §B.9-3):
/// the smallest Ω where the linear branch amplitude `Fe Ω²/sqrt((1−Ω²)² + (2ζΩ)²)` reaches the
/// mean load `Fm`, found by bisection to `tol`. `None` if it never does below Ω = 1.
#[must_use]
pub fn sdof_contact_loss_ratio(zeta: f64, fm: f64, fe: f64, tol: f64) -> Option<f64> {
    let g = |w: f64| fe * w * w / ((1.0 - w * w).powi(2) + (2.0 * zeta * w).powi(2)).sqrt() - fm;
    let (mut a, mut b) = (1e-6, 1.0);
    if !(tol > 0.0) || g(b) < 0.0 {
        return None;
    }
    while b - a > tol {
        let c = 0.5 * (a + b);
        if g(c) < 0.0 { a = c } else { b = c }
    }
    Some(0.5 * (a + b))
}
