//! The compliant drive (docs/dynamics.md, "The drive"): a motor turning at the scene's constant
//! speed Ω drives the carrier through a torsional shaft, and the carrier becomes a degree of
//! freedom that every arm loads, so the arms are integrated together.
//!
//! With the carrier angle φ, the shaft's twist `ψ = Ω·t − φ` and the carrier's speed `w = φ̇`:
//!
//! ```text
//! J_c·φ̈ = T_s − Σ_arms T_k(φ̈),     T_s = k_s·ψ + c_s·(Ω − w)
//! ```
//!
//! `T_k` is arm k's carrier torque ([`super::model`]'s Newton–Euler torque: the bearings' forces
//! and the dampers' couples), affine in φ̈ (`T_k = T_k⁰ + T_k′·φ̈`, each gear's and axis's
//! acceleration being so), hence `φ̈ = (T_s − ΣT⁰)/(J_c + ΣT′)`; ΣT′ > 0 is the arms' inertia
//! as the carrier feels it.
//!
//! **The independent variable** is the nominal time `τ = φ/Ω`, not t: the pair switches and the
//! needle table are known in carrier angle, so they stay breakpoints known in advance, the
//! turns end at φ = 2πk (the Poincaré section) and the samples fall on the loads' travel angles.
//! The state is `[arm 1's Δθ2, Δθ3, Δθ̇2, Δθ̇3, …, arm n's, ψ, w]` and each rate is the time
//! rate times `dt/dτ = Ω/w`; `dψ/dτ = Ω·(Ω/w − 1)`. Without a drive `w ≡ Ω` and τ is t.
//! Arm k at carrier angle φ is train 1's model at `φ + 2π(k−1)/n` with its own state.

use super::instant::Instant;
use super::scene::Drive;
use std::f64::consts::TAU;

/// What the drive needs of a train's model (implemented by [`super::model::RotorModel`]).
pub(crate) trait ArmModel {
    /// The nominal carrier angle at nominal time `t` (s), rad.
    fn carrier_angle(&self, t: f64) -> f64;
    /// The motor's (nominal) speed Ω, rad/s.
    fn nominal_speed(&self) -> f64;
    /// Arm `arm` at carrier angle `phi` (rad), speed `w` (rad/s), acceleration `beta`
    /// (rad/s²), its state `y`: the instant and the derivatives by `beta` of
    /// `[Δθ̈2, Δθ̈3, carrier torque]`.
    fn arm_at(&self, phi: f64, arm: usize, w: f64, beta: f64, y: &[f64]) -> (Instant, [f64; 3]);
}

/// The drive of a model with `arms` arms (SI).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct DriveModel {
    /// The shaft, the carrier's inertia.
    pub drive: Drive,
    /// Arms on the carrier.
    pub arms: usize,
}

/// The carrier's motion at one instant.
#[derive(Debug, Clone, Copy)]
pub(crate) struct CarrierState {
    /// Shaft torque `T_s`, N·m.
    pub shaft_torque_nm: f64,
    /// Carrier acceleration φ̈, rad/s².
    pub accel_rad_s2: f64,
}

impl DriveModel {
    /// State length: four per arm, the twist and the carrier speed.
    pub(crate) fn dim(&self) -> usize {
        4 * self.arms + 2
    }

    /// Index of the twist ψ (the carrier speed w follows).
    pub(crate) fn twist_index(&self) -> usize {
        4 * self.arms
    }

    /// Arm `k`'s carrier angle at the nominal carrier angle `phi`, rad.
    pub(crate) fn arm_phi(&self, phi: f64, k: usize) -> f64 {
        phi + TAU * k as f64 / self.arms as f64
    }

    /// The arms' instants at carrier acceleration 0 with their derivatives by φ̈, and the
    /// carrier's motion solved (module docs).
    fn solve(
        &self,
        model: &impl ArmModel,
        t: f64,
        y: &[f64],
    ) -> (Vec<(Instant, [f64; 3])>, CarrierState) {
        let phi = model.carrier_angle(t);
        let (psi, w) = (y[self.twist_index()], y[self.twist_index() + 1]);
        let arms: Vec<(Instant, [f64; 3])> = (0..self.arms)
            .map(|k| model.arm_at(self.arm_phi(phi, k), k, w, 0.0, &y[4 * k..4 * k + 4]))
            .collect();
        let t0: f64 = arms.iter().map(|(i, _)| i.carrier_torque_nm).sum();
        let t1: f64 = arms.iter().map(|(_, r)| r[2]).sum();
        let d = &self.drive;
        let shaft =
            d.stiffness_nm_per_rad * psi + d.damping_nms_per_rad * (model.nominal_speed() - w);
        let beta = (shaft - t0) / (d.carrier_inertia_kg_m2 + t1);
        let state = CarrierState {
            shaft_torque_nm: shaft,
            accel_rad_s2: beta,
        };
        (arms, state)
    }

    /// The carrier's motion at nominal time `t` (s) and state `y`.
    pub(crate) fn carrier(&self, model: &impl ArmModel, t: f64, y: &[f64]) -> CarrierState {
        self.solve(model, t, y).1
    }

    /// Train 1's instant at nominal time `t` (s), with the carrier's acceleration solved.
    pub(crate) fn instant(&self, model: &impl ArmModel, t: f64, y: &[f64]) -> Instant {
        let beta = self.carrier(model, t, y).accel_rad_s2;
        let w = y[self.twist_index() + 1];
        model.arm_at(model.carrier_angle(t), 0, w, beta, &y[..4]).0
    }

    /// `dy/dτ` (module docs).
    pub(crate) fn rhs(&self, model: &impl ArmModel, t: f64, y: &[f64], dy: &mut [f64]) {
        let (arms, c) = self.solve(model, t, y);
        let w = y[self.twist_index() + 1];
        let scale = model.nominal_speed() / w;
        for (k, (inst, rate)) in arms.iter().enumerate() {
            let (yk, dk) = (&y[4 * k..4 * k + 4], &mut dy[4 * k..4 * k + 4]);
            dk[0] = yk[2] * scale;
            dk[1] = yk[3] * scale;
            dk[2] = (inst.acc[0] + rate[0] * c.accel_rad_s2) * scale;
            dk[3] = (inst.acc[1] + rate[1] * c.accel_rad_s2) * scale;
        }
        let i = self.twist_index();
        dy[i] = model.nominal_speed() * (scale - 1.0);
        dy[i + 1] = c.accel_rad_s2 * scale;
    }

    /// The shaft's torsional frequency with the carrier and the arms moving by the kinematic
    /// law (stiff meshes), Hz: `√(k_s/(J_c + J̄))/2π`, where `J̄` is the turn's mean of the
    /// arms' inertia as the carrier turns them, `J(φ) = 2·T_kin(φ)/w²` (T_kin their kinetic
    /// energy at the kinematic state, here `E(w = 1) − E(w = 0)`: the gravity part cancels).
    pub(crate) fn frequency_hz(&self, model: &impl ArmModel, n: usize) -> f64 {
        let mut j = 0.0;
        for s in 0..n {
            let phi = TAU * s as f64 / n as f64;
            for k in 0..self.arms {
                let e = |w: f64| {
                    model
                        .arm_at(self.arm_phi(phi, k), k, w, 0.0, &[0.0; 4])
                        .0
                        .energy_j
                };
                j += 2.0 * (e(1.0) - e(0.0));
            }
        }
        let j = self.drive.carrier_inertia_kg_m2 + j / n as f64;
        (self.drive.stiffness_nm_per_rad / j).sqrt() / TAU
    }
}
