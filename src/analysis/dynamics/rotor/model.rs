//! The rotor's equations of motion (docs/dynamics.md, "The rotor"): per train, the intermediate's
//! and the planet's rotations `Δθ2`, `Δθ3` away from the kinematic law, the carrier turning at the
//! scene's constant speed Ω (φ = Ωt). Each body obeys Newton–Euler about its moving axis C
//! (`a_C = −Ω²C`), with `θ = θ_kin(φ) + Δθ`, `θ̇ = Ωθ′ + Δθ̇`:
//!
//! ```text
//! J_D·θ̈2 + S2 × a_D = M_sun→int + M_planet→int + S2 × g
//! J_A·θ̈3 + S3 × a_A = M_int→planet + (B − A) × F_needle + S3 × g,     Δθ̈ = θ̈ − Ω²θ″
//! ```
//!
//! (`S = m·(G − C)` at the actual orientation, J about the axis; the mesh moments from
//! [`super::mesh`]). The trains of a carrier turning at a fixed speed do not interact: train 1
//! is integrated and train k is train 1 shifted by `2π(k−1)/arms`. With k → ∞ and no backlash the
//! mesh forces tend to the kinetostatic ones of `ncgear loads` (the same equations with Δθ ≡ 0).
//! The carrier's drive torque is `T = D × R_D + A × R_A` with the bearings' forces `R = m·a_G −
//! ΣF − m·g` (the loads' formula, here with the dynamic forces and accelerations).

use super::drive::{ArmModel, DriveModel};
use super::instant::Instant;
use super::law::{Contact, MeshLaw};
use super::lever_rate::LeverRates;
use super::mesh::{MeshGeometry, MeshState, mesh_state};
use crate::geometry::assembly::Rebuilt;
use crate::loads::kinetostatics::{Axis, TrainBodies};
use crate::loads::mass::MassProperties;
use crate::loads::motion::TrainMotion;
use crate::loads::needle::NeedleTable;
use crate::math::Point;
use std::cell::Cell;
use std::f64::consts::TAU;
use std::sync::atomic::{AtomicU64, Ordering};

/// The kinematics and the meshes' geometry at one carrier angle.
#[derive(Debug, Clone, Copy)]
struct Kinematics {
    motion: TrainMotion,
    geometry: [MeshGeometry; 2],
}

/// Slots of the kinematics' memo: one per arm (arms beyond share them).
const SLOTS: usize = 4;

thread_local! {
    /// The last kinematics computed on this thread for each arm slot, keyed by (model id, φ's
    /// bits): the four contact events are evaluated at the same instant, the last stage of a
    /// step at the instant the events then look at, so most lookups repeat the last one.
    static LAST: [Cell<Option<(u64, u64, Kinematics)>>; SLOTS] =
        const { [const { Cell::new(None) }; SLOTS] };
}

/// Ids of built models (a clone shares its model's id: the same train).
static NEXT_ID: AtomicU64 = AtomicU64::new(1);

/// A fresh model id.
pub(crate) fn new_model_id() -> u64 {
    NEXT_ID.fetch_add(1, Ordering::Relaxed)
}

/// A boxed contact event function `(t, y) → δ_s − b` (m).
pub(crate) type GapFn<'a> = Box<dyn Fn(f64, &[f64]) -> f64 + 'a>;

/// The model of one train (SI inside; the CCW frame of [`Rebuilt`]).
#[derive(Debug, Clone)]
pub struct RotorModel {
    pub(crate) rebuilt: Rebuilt,
    /// Carrier speed, rad/s.
    pub(crate) omega: f64,
    pub(crate) bodies: TrainBodies,
    /// Pressure angle, rad.
    pub(crate) alpha: f64,
    /// Gravity, m/s², CCW frame.
    pub(crate) gravity: Point,
    /// The needle load, world frame, N, by travel.
    pub(crate) needle: Option<NeedleTable>,
    pub(crate) laws: [MeshLaw; 2],
    /// Mesh damping, N·s/m.
    pub(crate) damping: [f64; 2],
    /// Half the normal backlash, m (0: none).
    pub(crate) half_gap_m: [f64; 2],
    /// Identifies the train for the kinematics' memo ([`new_model_id`]). The kinematics depend on
    /// `rebuilt` alone (not on Ω), so a clone with another speed may share the id; whoever gives
    /// a model another `rebuilt` must give it a fresh id.
    pub(crate) id: u64,
    /// Whether the kinematics repeat each turn (both gears' orientations by whole turns), so
    /// that the carrier angle is taken modulo 2π before they are computed.
    pub(crate) turn_periodic: bool,
    /// Vibration damping `[c_D, c_A]` of the intermediate and the planet, N·m·s/rad (0: none):
    /// a couple `−c·Δθ̇` from the carrier on the gear (module docs).
    pub(crate) vibration_damping: [f64; 2],
    /// The lever arms' rates, for the mesh damping (None: no mesh damping, the rates unused).
    pub(crate) lever_rates: Option<LeverRates>,
    /// The compliant drive (None: the carrier turns at exactly Ω and train 1 alone is
    /// integrated).
    pub(crate) drive: Option<DriveModel>,
}

impl RotorModel {
    /// Carrier angle at time `t` (s), rad.
    pub(crate) fn phi(&self, t: f64) -> f64 {
        self.omega * t
    }

    /// One turn, s.
    #[must_use]
    pub fn period_s(&self) -> f64 {
        TAU / self.omega
    }

    /// The needle force at travel `phi`, N (CCW frame).
    pub(crate) fn needle_n(&self, phi: f64) -> Point {
        let s = self.rebuilt.sign();
        self.needle.as_ref().map_or(Point::ZERO, |t| {
            let f = t.at(phi);
            Point::new(f.x, s * f.y)
        })
    }

    /// The kinematics at carrier angle `phi` (rad), remembered for the next call at the same
    /// angle on this thread (the result is the same either way).
    fn kinematics(&self, phi: f64, arm: usize) -> Kinematics {
        let key = (self.id, phi.to_bits());
        let slot = arm % SLOTS;
        if let Some((id, bits, k)) = LAST.with(|l| l[slot].get())
            && (id, bits) == key
        {
            return k;
        }
        let motion = if self.turn_periodic {
            let mut m = TrainMotion::at(&self.rebuilt, phi.rem_euclid(TAU));
            m.phi_rad = phi;
            m
        } else {
            TrainMotion::at(&self.rebuilt, phi)
        };
        let mut geometry = self.geometry(&motion);
        if let Some(rates) = &self.lever_rates {
            let r = rates.at(phi, &|p| self.geometry(&TrainMotion::at(&self.rebuilt, p)));
            for (g, r) in geometry.iter_mut().zip(r) {
                g.lever_rate_m = r;
            }
        }
        let k = Kinematics { motion, geometry };
        LAST.with(|l| l[slot].set(Some((key.0, key.1, k))));
        k
    }

    /// Whether the train's kinematics repeat after one turn: the orientations of both gears
    /// differ by whole turns (within 1e-9 rad) and the centres coincide.
    pub(crate) fn repeats_each_turn(rebuilt: &Rebuilt) -> bool {
        let (a, b) = (TrainMotion::at(rebuilt, 0.0), TrainMotion::at(rebuilt, TAU));
        let whole = |d: f64| (d - TAU * (d / TAU).round()).abs() < 1e-9;
        whole(b.theta2_rad - a.theta2_rad)
            && whole(b.theta3_rad - a.theta3_rad)
            && (b.tip_mm - a.tip_mm).norm() < 1e-9
    }

    /// The two meshes' geometry at the motion `m`.
    pub(crate) fn geometry(&self, m: &TrainMotion) -> [MeshGeometry; 2] {
        let d = m.d_mm * 1e-3;
        let a = m.a_mm * 1e-3;
        [
            MeshGeometry::new(&m.sun_mesh, Point::ZERO, d, self.alpha),
            MeshGeometry::new(&m.planet_mesh, d, a, self.alpha),
        ]
    }

    /// The mesh `j`'s contact at the motion `m`.
    fn contact<'a>(&'a self, m: &'a TrainMotion, j: usize) -> Contact<'a> {
        let [sun, mid, planet] = self.rebuilt.ccw_curves();
        if j == 0 {
            Contact {
                pitch: &m.sun_mesh,
                curves: [sun, mid],
            }
        } else {
            Contact {
                pitch: &m.planet_mesh,
                curves: [mid, planet],
            }
        }
    }

    /// Mesh stiffnesses at the motion `m`, N/m; `double` the pair counts (None: the law's).
    pub(crate) fn stiffness(&self, m: &TrainMotion, double: Option<[bool; 2]>) -> [f64; 2] {
        [0, 1].map(|j| {
            let d = double.map_or_else(|| self.laws[j].double(m.phi_rad), |d| d[j]);
            self.laws[j].stiffness(&self.contact(m, j), d)
        })
    }

    /// The mesh states at the motion `m` and state `y = [Δθ2, Δθ3, Δθ̇2, Δθ̇3]`.
    fn meshes(&self, g: &[MeshGeometry; 2], y: &[f64], k: [f64; 2], w: f64) -> [MeshState; 2] {
        [
            mesh_state(
                &g[0],
                [0.0, y[0]],
                [0.0, y[2]],
                w,
                [k[0], self.damping[0], self.half_gap_m[0]],
            ),
            mesh_state(
                &g[1],
                [y[0], y[1]],
                [y[2], y[3]],
                w,
                [k[1], self.damping[1], self.half_gap_m[1]],
            ),
        ]
    }

    /// Arm `arm`'s carrier angle at time `t` (train 1's without a drive), rad.
    fn arm_phi(&self, t: f64, arm: usize) -> f64 {
        self.drive
            .map_or(self.phi(t), |d| d.arm_phi(self.phi(t), arm))
    }

    /// Arm `arm`'s mesh energy at time `t`, its state `y`, with the pair counts `double`, J
    /// (for `∂V/∂t`).
    pub(crate) fn mesh_energy(&self, t: f64, y: &[f64], double: [bool; 2], arm: usize) -> f64 {
        let kin = self.kinematics(self.arm_phi(t, arm), arm);
        let k = self.stiffness(&kin.motion, Some(double));
        self.meshes(&kin.geometry, y, k, self.omega)
            .iter()
            .map(|s| s.energy_j)
            .sum()
    }

    /// Arm `arm`'s pair counts at time `t`.
    pub(crate) fn pair_counts(&self, t: f64, arm: usize) -> [bool; 2] {
        let phi = self.arm_phi(t, arm);
        [self.laws[0].double(phi), self.laws[1].double(phi)]
    }

    /// Everything at time `t` (s) and state `y` (train 1; with a drive, its carrier
    /// acceleration solved with every arm, [`super::drive`]).
    pub(crate) fn instant(&self, t: f64, y: &[f64]) -> Instant {
        match &self.drive {
            None => self.instant_at(self.phi(t), 0, self.omega, 0.0, y).0,
            Some(d) => d.instant(self, t, y),
        }
    }

    /// Everything for the arm `arm` (its memo slot) at carrier angle `phi` (rad), carrier speed
    /// `w` (rad/s) and acceleration `beta` (rad/s²), its state `y = [Δθ2, Δθ3, Δθ̇2, Δθ̇3]`;
    /// with the derivatives by `beta` of `[Δθ̈2, Δθ̈3, carrier torque]` (everything is affine in
    /// `beta`: the axes' accelerations `−w²·C + β·ẑ × C`, the gears' `θ′·β + θ″·w² + Δθ̈`).
    pub(crate) fn instant_at(
        &self,
        phi: f64,
        arm: usize,
        w: f64,
        beta: f64,
        y: &[f64],
    ) -> (Instant, [f64; 3]) {
        let kin = self.kinematics(phi, arm);
        let m = kin.motion;
        let stiffness = self.stiffness(&m, None);
        let mesh = self.meshes(&kin.geometry, y, stiffness, w);
        let g = self.gravity;
        let needle = self.needle_n(phi);
        let d = m.d_mm * 1e-3;
        let a = m.a_mm * 1e-3;
        let axis = |c: Point, theta: f64, rate: f64, dw: f64| Axis {
            c,
            theta,
            w: w * rate + dw,
            alpha: 0.0,
        };
        let ax_d = axis(d, m.theta2_rad + y[0], m.rates.intermediate[0], y[2]);
        let ax_a = axis(a, m.theta3_rad + y[1], m.rates.planet[0], y[3]);
        let tip_kin = m.tip_mm * 1e-3 - a;
        let tip = a + tip_kin.rotate(y[1]);
        // (α, m·a_G, S) of a body; its axis accelerates at −w²·C + b·ẑ × C
        let body_acc = |ax: &Axis, body: &MassProperties, moment_ext: f64, b: f64| {
            let (ma0, mom0, s) = ax.inertia_at(body, ax.c * (-w * w) + ax.c.perp() * b);
            let j = body.inertia_kg_mm2 * 1e-6;
            let alpha = (moment_ext + s.cross(g) - mom0) / j;
            (alpha, ma0 + s.perp() * alpha, s)
        };
        let couple = [0, 1].map(|i| -self.vibration_damping[i] * y[2 + i]);
        let m_int = mesh[0].moment_nm[1] + mesh[1].moment_nm[0] + couple[0];
        let m_pl = mesh[1].moment_nm[1] + (tip - a).cross(needle) + couple[1];
        let (f1, f2) = (mesh[0].force, mesh[1].force);
        let gm = [
            g * self.bodies.intermediate.mass_kg,
            g * self.bodies.planet.mass_kg,
        ];
        // Δθ̈ of both gears and the carrier torque at the carrier acceleration b
        let at = |b: f64| {
            let (al2, ma_d, s2) = body_acc(&ax_d, &self.bodies.intermediate, m_int, b);
            let (al3, ma_a, s3) = body_acc(&ax_a, &self.bodies.planet, m_pl, b);
            let acc = [
                al2 - w * w * m.rates.intermediate[1] - b * m.rates.intermediate[0],
                al3 - w * w * m.rates.planet[1] - b * m.rates.planet[0],
            ];
            let r_d = ma_d - f1 + f2 - gm[0];
            let r_a = ma_a - f2 - needle - gm[1];
            // the carrier takes the bearings' forces and the dampers' couples back
            let torque = d.cross(r_d) + a.cross(r_a) + couple[0] + couple[1];
            (acc, torque, s2, s3)
        };
        let (acc, carrier_torque_nm, s2, s3) = at(beta);
        let rate = if self.drive.is_some() {
            let (acc1, torque1, _, _) = at(beta + 1.0);
            [
                acc1[0] - acc[0],
                acc1[1] - acc[1],
                torque1 - carrier_torque_nm,
            ]
        } else {
            [0.0; 3]
        };
        let vibration_damping_w = -couple[0] * (ax_d.w - w) - couple[1] * (ax_a.w - w);
        let v_a = a.perp() * w;
        let v_tip = v_a + (tip - a).perp() * ax_a.w;
        let ke = |ax: &Axis, body: &MassProperties, s: Point| {
            let v_c = ax.c.perp() * w;
            0.5 * body.mass_kg * v_c.dot(v_c)
                + ax.w * v_c.dot(s.perp())
                + 0.5 * body.inertia_kg_mm2 * 1e-6 * ax.w * ax.w
                - g.dot(ax.c * body.mass_kg + s)
        };
        let energy_j = ke(&ax_d, &self.bodies.intermediate, s2)
            + ke(&ax_a, &self.bodies.planet, s3)
            + mesh[0].energy_j
            + mesh[1].energy_j;
        let instant = Instant {
            mesh,
            acc,
            tip_mm: tip * 1e3,
            carrier_torque_nm,
            needle_w: needle.dot(v_tip),
            energy_j,
            vibration_damping_w,
        };
        (instant, rate)
    }

    /// The quasi-static state of train 1 at carrier angle `phi` (rad): the deflections that
    /// carry the rigid forces `rigid_n` (N, on the loaded flanks `flank`), no velocity.
    pub(crate) fn quasi_static(&self, phi: f64, rigid_n: [f64; 2], flank: [i8; 2]) -> Vec<f64> {
        let m = TrainMotion::at(&self.rebuilt, phi);
        let k = self.stiffness(&m, None);
        let g = self.geometry(&m);
        let f = flank.map(|s| usize::from(s < 0));
        // δ1 = −ρ2·Δθ2 = F1/k1 + b;  δ2 = ρ1·Δθ2 − ρ2·Δθ3 = F2/k2 + b
        let d1 = rigid_n[0] / k[0] + self.half_gap_m[0];
        let th2 = -d1 / g[0].lever_m[f[0]][1];
        let d2 = rigid_n[1] / k[1] + self.half_gap_m[1];
        let th3 = (g[1].lever_m[f[1]][0] * th2 - d2) / g[1].lever_m[f[1]][1];
        vec![th2, th3, 0.0, 0.0]
    }

    /// The switch times of the stiffness and the needle table in `(t0, t1)`, s, sorted.
    pub(crate) fn breakpoints(&self, t0: f64, t1: f64) -> Vec<f64> {
        let mut angles: Vec<f64> = self
            .laws
            .iter()
            .flat_map(|l| l.switches().to_vec())
            .collect();
        if let Some(n) = &self.needle {
            angles.extend(n.knots_rad().into_iter().map(|a| a.rem_euclid(TAU)));
        }
        if let Some(d) = self.drive {
            // arm k at φ is train 1 at φ + 2πk/n: its switches come 2πk/n earlier
            let own = angles.clone();
            for k in 1..d.arms {
                let shift = d.arm_phi(0.0, k);
                angles.extend(own.iter().map(|a| (a - shift).rem_euclid(TAU)));
            }
        }
        let (p0, p1) = (self.phi(t0), self.phi(t1));
        let mut out = Vec::new();
        let mut turn = (p0 / TAU).floor();
        while turn * TAU < p1 {
            for &a in &angles {
                let p = turn * TAU + a;
                if p > p0 && p < p1 {
                    out.push(p / self.omega);
                }
            }
            turn += 1.0;
        }
        out.sort_by(f64::total_cmp);
        // Only exact duplicates go: the integrator steps onto each switch, and one closer than
        // its restart resolution (1e-13 of the span) is passed in the restart itself. Merging
        // switches up to 1e-12 s apart left the later one's jump inside a step, where no step
        // size could meet rtol 1e-10 (two meshes' switches 1e-13 s apart on G1).
        out.dedup();
        out
    }

    /// Whether contact can be lost (a backlash is modelled).
    pub(crate) fn has_backlash(&self) -> bool {
        self.half_gap_m.iter().any(|&b| b > 0.0)
    }

    /// The shaft's torsional frequency of a compliant drive, Hz (None without a drive): the
    /// carrier's and the arms' mean inertia on the shaft's stiffness.
    #[must_use]
    pub fn drive_frequency_hz(&self) -> Option<f64> {
        self.drive.map(|d| d.frequency_hz(self, 360))
    }

    /// Masses `[intermediate, planet with its arm]`, kg.
    #[must_use]
    pub fn masses_kg(&self) -> [f64; 2] {
        [self.bodies.intermediate.mass_kg, self.bodies.planet.mass_kg]
    }

    /// Whether the carrier is a degree of freedom on a compliant drive.
    #[must_use]
    pub fn has_drive(&self) -> bool {
        self.drive.is_some()
    }

    /// The contact events: four per integrated arm (`which` of [`Self::gap`]).
    pub(crate) fn gap_count(&self) -> usize {
        4 * self.drive.map_or(1, |d| d.arms)
    }

    /// The state's length: train 1's four, or every arm's and the drive's.
    pub(crate) fn state_len(&self) -> usize {
        self.drive.map_or(4, |d| d.dim())
    }

    /// The contact events' functions `δ_s − b` of (mesh, flank) `which` (0..4; with a drive,
    /// `4k..4k + 4` those of arm k).
    pub(crate) fn gap(&self, t: f64, y: &[f64], which: usize) -> f64 {
        let (arm, which) = (which / 4, which % 4);
        let phi = self.arm_phi(t, arm);
        let y = &y[4 * arm..];
        let g = self.kinematics(phi, arm).geometry;
        let (j, f) = (which / 2, which % 2);
        let d = if j == 0 {
            g[0].approach(f, [0.0, y[0]])
        } else {
            g[1].approach(f, [y[0], y[1]])
        };
        d - self.half_gap_m[j]
    }

    /// Mean lever arms of the flank +1 `[[ρ1, ρ2]; 2]` (m) and mean stiffnesses (N/m) over a
    /// turn of `n` samples.
    pub(crate) fn means(&self, n: usize) -> ([[f64; 2]; 2], [f64; 2]) {
        let mut lev = [[0.0; 2]; 2];
        let mut k = [0.0; 2];
        for i in 0..n {
            let m = TrainMotion::at(&self.rebuilt, TAU * i as f64 / n as f64);
            let g = self.geometry(&m);
            let ki = self.stiffness(&m, None);
            for ((lj, kj), (gj, kij)) in lev.iter_mut().zip(&mut k).zip(g.iter().zip(ki)) {
                for (l, arm) in lj.iter_mut().zip(gj.lever_m[0]) {
                    *l += arm.abs() / n as f64;
                }
                *kj += kij / n as f64;
            }
        }
        (lev, k)
    }

    /// Inertias `[J_D, J_A]` about the axes, kg·m².
    #[must_use]
    pub fn inertias_kg_m2(&self) -> [f64; 2] {
        [
            self.bodies.intermediate.inertia_kg_mm2 * 1e-6,
            self.bodies.planet.inertia_kg_mm2 * 1e-6,
        ]
    }

    /// The linearised train's natural frequencies at the mean stiffness, Hz, ascending: the
    /// eigenvalues of `M⁻¹K` with `M = diag(J_D, J_A)`, `K = Σ k̄_j·g_j·g_jᵀ`, `g_1 = (−ρ̄_D, 0)`,
    /// `g_2 = (ρ̄_D′, −ρ̄_A)` (mean lever arms of the sun mesh on the intermediate, of the planet
    /// mesh on the intermediate and on the planet; mesh stiffness only, the centrifugal and
    /// gravity stiffness left out).
    #[must_use]
    pub fn natural_frequencies_hz(&self) -> [f64; 2] {
        let (lev, k) = self.means(720);
        let [j2, j3] = self.inertias_kg_m2();
        let k11 = k[0] * lev[0][1].powi(2) + k[1] * lev[1][0].powi(2);
        let k12 = -k[1] * lev[1][0] * lev[1][1];
        let k22 = k[1] * lev[1][1].powi(2);
        // symmetric form M^{-1/2} K M^{-1/2}
        let (a, b, c) = (k11 / j2, k12 / (j2 * j3).sqrt(), k22 / j3);
        let mean = 0.5 * (a + c);
        let disc = (0.25 * (a - c).powi(2) + b * b).sqrt();
        [mean - disc, mean + disc].map(|l| l.max(0.0).sqrt() / TAU)
    }
}

impl crate::analysis::dynamics::ode::OdeSystem for RotorModel {
    fn dim(&self) -> usize {
        self.state_len()
    }
    fn rhs(&self, t: f64, y: &[f64], dy: &mut [f64]) {
        if let Some(d) = &self.drive {
            d.rhs(self, t, y, dy);
            return;
        }
        let i = self.instant(t, y);
        dy[0] = y[2];
        dy[1] = y[3];
        dy[2] = i.acc[0];
        dy[3] = i.acc[1];
    }
}

impl ArmModel for RotorModel {
    fn carrier_angle(&self, t: f64) -> f64 {
        self.phi(t)
    }
    fn nominal_speed(&self) -> f64 {
        self.omega
    }
    fn arm_at(&self, phi: f64, arm: usize, w: f64, beta: f64, y: &[f64]) -> (Instant, [f64; 3]) {
        self.instant_at(phi, arm, w, beta, y)
    }
}
