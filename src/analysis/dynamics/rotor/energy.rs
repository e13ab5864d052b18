//! The energy audit of a turn (docs/dynamics.md, "Energy"): the train's energy `E` (kinetic,
//! gravity, mesh) against the work of every source, integrated with the motion:
//!
//! ```text
//! E(t1) − E(t0) = W_drive + W_needle − W_damping + W_parametric + Σ ΔV_switch
//! W_drive = ∫ Ω·T dt,   W_needle = ∫ F_needle·v_tip dt,   W_damping = ∫ Σ c·v² dt,
//! W_parametric = ∫ ∂V/∂t dt   (the mesh energy's change at frozen deviations: the stiffness
//! and the lever arms varying with the travel),   ΔV_switch = V(t⁺) − V(t⁻) at a pair switch.
//! ```
//!
//! `T` is the Newton–Euler carrier torque ([`super::model`]), not derived from the energy, so the
//! audit checks the equations of motion against an independent balance.

use super::RotorError;
use super::model::{GapFn, RotorModel};
use crate::analysis::dynamics::ode::{Dopri5, EventFn, OdeProblem, OdeSystem};
use serde::Serialize;

/// The audit of one turn, J.
#[derive(Debug, Clone, Copy, Serialize, schemars::JsonSchema)]
pub struct EnergyAudit {
    /// `E(t1) − E(t0)`.
    pub delta_energy_j: f64,
    /// Work of the drive.
    pub drive_j: f64,
    /// Work of the needle force.
    pub needle_j: f64,
    /// Energy dissipated by the mesh damping (impacts included).
    pub damping_j: f64,
    /// `∫ ∂V/∂t`.
    pub parametric_j: f64,
    /// Mesh energy jumps at the pair switches.
    pub switch_jumps_j: f64,
    /// `ΔE − (W_drive + W_needle − W_damping + W_parametric + ΣΔV)`.
    pub residual_j: f64,
    /// Largest `|Ω·T|` met, W.
    pub max_drive_power_w: f64,
    /// The span, s.
    pub span_s: f64,
}

struct Augmented<'a>(&'a RotorModel);

impl OdeSystem for Augmented<'_> {
    fn dim(&self) -> usize {
        8
    }
    fn rhs(&self, t: f64, y: &[f64], dy: &mut [f64]) {
        let m = self.0;
        let i = m.instant(t, &y[..4]);
        dy[0] = y[2];
        dy[1] = y[3];
        dy[2] = i.acc[0];
        dy[3] = i.acc[1];
        dy[4] = m.omega * i.carrier_torque_nm;
        dy[5] = i.needle_w;
        dy[6] = i.mesh[0].damping_w + i.mesh[1].damping_w + i.vibration_damping_w;
        let pairs = m.pair_counts(t);
        let h = 1e-6 * m.period_s();
        dy[7] = (m.mesh_energy(t + h, &y[..4], pairs) - m.mesh_energy(t - h, &y[..4], pairs))
            / (2.0 * h);
    }
}

/// Audits `model` over `[t0, t1]` (s) from the state `y0` at `t0`, DOPRI5 at `rtol`, `atol`,
/// with the pair switches as breakpoints and the contact events.
///
/// # Errors
/// [`RotorError::Ode`].
pub fn energy_audit(
    model: &RotorModel,
    t0: f64,
    t1: f64,
    y0: &[f64],
    rtol: f64,
    atol: f64,
) -> Result<EnergyAudit, RotorError> {
    let aug = Augmented(model);
    let mut y = y0.to_vec();
    y.extend([0.0; 4]);
    let solver = Dopri5::new(rtol, atol)?;
    let dt0 = 1e-9 * model.period_s();
    let e = |t: f64, y: &[f64]| model.instant(t, &y[..4]).energy_j;
    let e0 = e(t0 + dt0, &y);
    let gaps: Vec<GapFn<'_>> = if model.has_backlash() {
        (0..4)
            .map(|w| Box::new(move |t: f64, y: &[f64]| model.gap(t, y, w)) as GapFn<'_>)
            .collect()
    } else {
        Vec::new()
    };
    let refs: Vec<EventFn<'_>> = gaps.iter().map(|b| b.as_ref() as EventFn<'_>).collect();
    let mut knots = model.breakpoints(t0, t1);
    knots.push(t1);
    let mut jumps = 0.0;
    let mut t = t0;
    let mut pmax = 0.0_f64;
    let mut buf = vec![0.0; 8];
    for &tb in &knots {
        let mut on = |d: &crate::analysis::dynamics::ode::DenseStep| {
            d.eval(d.t_end(), &mut buf);
            let p = model.omega * model.instant(d.t_end(), &buf[..4]).carrier_torque_nm;
            pmax = pmax.max(p.abs());
        };
        solver.integrate(
            &OdeProblem::new(&aug, t, tb).with_events(&refs),
            &mut y,
            &mut on,
        )?;
        if tb < t1 {
            let pairs_before = model.pair_counts(tb - dt0);
            let pairs_after = model.pair_counts(tb + dt0);
            jumps += model.mesh_energy(tb, &y[..4], pairs_after)
                - model.mesh_energy(tb, &y[..4], pairs_before);
        }
        t = tb;
    }
    let delta = e(t1 - dt0, &y) - e0;
    let (drive, needle, damping, param) = (y[4], y[5], y[6], y[7]);
    Ok(EnergyAudit {
        delta_energy_j: delta,
        drive_j: drive,
        needle_j: needle,
        damping_j: damping,
        parametric_j: param,
        switch_jumps_j: jumps,
        residual_j: delta - (drive + needle - damping + param + jumps),
        max_drive_power_w: pmax,
        span_s: t1 - t0,
    })
}
