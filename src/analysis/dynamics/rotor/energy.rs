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
//!
//! With a drive (docs/dynamics.md, "The drive") E adds the carrier's `½J_c·w²` and the shaft's `½k_s·ψ²` and
//! sums every arm; the drive's work is the motor's `∫ Ω·T_s dt`, the damping adds the shaft's
//! `c_s·(Ω − w)²`, and the sums run in the nominal time τ (each power times `dt/dτ = Ω/w`).

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

/// Mesh energy of every integrated arm at time `t` with the pair counts frozen at `at`'s, J.
fn mesh_energy(m: &RotorModel, t: f64, y: &[f64], at: f64) -> f64 {
    (0..m.gap_count() / 4)
        .map(|k| m.mesh_energy(t, &y[4 * k..4 * k + 4], m.pair_counts(at, k), k))
        .sum()
}

/// The train's energy at `(t, y)`, J (module docs).
fn energy(m: &RotorModel, t: f64, y: &[f64]) -> f64 {
    let Some(d) = &m.drive else {
        return m.instant(t, &y[..4]).energy_j;
    };
    let c = d.carrier(m, t, y);
    let (psi, w) = (y[d.twist_index()], y[d.twist_index() + 1]);
    let arms: f64 = (0..d.arms)
        .map(|k| {
            let phi = d.arm_phi(m.phi(t), k);
            m.instant_at(phi, k, w, c.accel_rad_s2, &y[4 * k..4 * k + 4])
                .0
                .energy_j
        })
        .sum();
    arms + 0.5 * d.drive.carrier_inertia_kg_m2 * w * w
        + 0.5 * d.drive.stiffness_nm_per_rad * psi * psi
}

/// `[drive, needle, damping]` powers at `(t, y)` per unit of the independent variable, W.
fn powers(m: &RotorModel, t: f64, y: &[f64]) -> [f64; 3] {
    let damp = |i: &super::instant::Instant| {
        i.mesh[0].damping_w + i.mesh[1].damping_w + i.vibration_damping_w
    };
    let Some(d) = &m.drive else {
        let i = m.instant(t, &y[..4]);
        return [m.omega * i.carrier_torque_nm, i.needle_w, damp(&i)];
    };
    let c = d.carrier(m, t, y);
    let w = y[d.twist_index() + 1];
    let scale = m.omega / w;
    let (mut needle, mut damping) = (0.0, d.drive.damping_nms_per_rad * (m.omega - w).powi(2));
    for k in 0..d.arms {
        let phi = d.arm_phi(m.phi(t), k);
        let i = m
            .instant_at(phi, k, w, c.accel_rad_s2, &y[4 * k..4 * k + 4])
            .0;
        needle += i.needle_w;
        damping += damp(&i);
    }
    [m.omega * c.shaft_torque_nm, needle, damping].map(|p| p * scale)
}

impl OdeSystem for Augmented<'_> {
    fn dim(&self) -> usize {
        self.0.state_len() + 4
    }
    fn rhs(&self, t: f64, y: &[f64], dy: &mut [f64]) {
        let m = self.0;
        let n = m.state_len();
        m.rhs(t, &y[..n], &mut dy[..n]);
        let [drive, needle, damping] = powers(m, t, &y[..n]);
        dy[n] = drive;
        dy[n + 1] = needle;
        dy[n + 2] = damping;
        let h = 1e-6 * m.period_s();
        dy[n + 3] =
            (mesh_energy(m, t + h, &y[..n], t) - mesh_energy(m, t - h, &y[..n], t)) / (2.0 * h);
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
    let n = model.state_len();
    let mut y = y0.to_vec();
    y.extend([0.0; 4]);
    let solver = Dopri5::new(rtol, atol)?;
    let dt0 = 1e-9 * model.period_s();
    let e0 = energy(model, t0 + dt0, &y[..n]);
    let gaps: Vec<GapFn<'_>> = if model.has_backlash() {
        (0..model.gap_count())
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
    let mut buf = vec![0.0; n + 4];
    for &tb in &knots {
        let mut on = |d: &crate::analysis::dynamics::ode::DenseStep| {
            d.eval(d.t_end(), &mut buf);
            pmax = pmax.max(powers(model, d.t_end(), &buf[..n])[0].abs());
        };
        solver.integrate(
            &OdeProblem::new(&aug, t, tb).with_events(&refs),
            &mut y,
            &mut on,
        )?;
        if tb < t1 {
            jumps += mesh_energy(model, tb, &y[..n], tb + dt0)
                - mesh_energy(model, tb, &y[..n], tb - dt0);
        }
        t = tb;
    }
    let delta = energy(model, t1 - dt0, &y[..n]) - e0;
    let (drive, needle, damping, param) = (y[n], y[n + 1], y[n + 2], y[n + 3]);
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
