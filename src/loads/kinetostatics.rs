//! Newton–Euler for one train at one instant, the motion given (kinetostatics): the mesh forces,
//! the bearing forces of the carrier on the gears and the train's share of the carrier torque.
//! SI inside (m, kg, N, s); the CCW frame of [`super::motion`].
//!
//! For a body turning about an axis C that moves on a circle at the constant carrier speed ω
//! (`a_C = −ω²·C`), with orientation rate `θ′` and `θ″` per radian of carrier travel (angular
//! velocity `ω·θ′`, acceleration `ω²·θ″`), first moment `S = m·(G − C)` and inertia `J_C`
//! about C:
//!
//! ```text
//! ΣF = m·a_C + (ω²θ″)·k × S − (ωθ′)²·S                    (m·a_G)
//! ΣM_C = J_C·ω²θ″ + S × a_C                               (moments about the moving axis)
//! ```
//!
//! **Planet + arm** (axis A): the intermediate's force `F2` at the pitch point P2 must give
//! `M2 = (P2 − A) × F2 = J_A·ω²θ3″ + S × a_A − (B − A) × F_needle − S × g`.
//! **Intermediate** (axis D): the sun's force `F1` at P1 must give
//! `M1 = (P1 − D) × F1 = J_D·ω²θ2″ + S × a_D − S × g + (P2 − D) × F2`.
//! Each mesh force acts along the line of action through the pitch point, at the pressure angle α
//! to the common tangent t and pushing the gears apart along the normal n:
//! `F = f·(sin α·n + s·cos α·t)`, `f ≥ 0`; the flank `s = ±1` is the one whose moment
//! `k_s = (P − C) × (sin α·n + s·cos α·t)` has the sign of the moment needed, and `f = M/k_s`.
//! `|k_s| = |P − C|·cos α_eff` defines the effective pressure angle α_eff (the angle between the
//! force and the direction the driven gear's pitch point moves). The bearings take the rest:
//! `R = m·a_G − ΣF_other − m·g`; the carrier, massless, needs `T = D × R_D + A × R_A`.

use super::mass::MassProperties;
use super::motion::{PitchPoint, TrainMotion};
use crate::math::Point;

/// The moving bodies of one train in their body frames (CCW frame, mm, kg).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrainBodies {
    /// The intermediate gear about its axis D.
    pub intermediate: MassProperties,
    /// The planet gear and the arm together, about the planet axis A.
    pub planet: MassProperties,
}

/// One mesh force at one instant (SI, CCW frame).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeshForce {
    /// The force on the driven gear, N.
    pub force_n: Point,
    /// Its magnitude along the line of action, N (≥ 0).
    pub normal_force_n: f64,
    /// `+1`: its tangential part turns the driven gear CCW about its axis; `−1` CW; `0` none.
    pub flank: i8,
    /// Effective pressure angle at the driven gear, rad.
    pub effective_pressure_angle_rad: f64,
}

/// The forces of one train at one instant (SI, CCW frame).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrainForces {
    /// The sun's force on the intermediate.
    pub sun_mesh: MeshForce,
    /// The intermediate's force on the planet.
    pub planet_mesh: MeshForce,
    /// Moment about A of the intermediate's force on the planet, N·m.
    pub planet_mesh_torque_nm: f64,
    /// Force of the carrier on the intermediate at D, N.
    pub bearing_d_n: Point,
    /// Force of the carrier on the planet at A, N.
    pub bearing_a_n: Point,
    /// The train's share of the carrier's drive torque, `D × R_D + A × R_A`, N·m.
    pub carrier_torque_nm: f64,
    /// Moment about O of the sun's force on the intermediate, `P1 × F1`, N·m: the frame holds
    /// the sun against it.
    pub sun_mesh_moment_nm: f64,
}

/// Why an instant cannot be solved.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SelfLocking {
    /// Which mesh: `sun-intermediate` or `intermediate-planet`.
    pub mesh: &'static str,
    /// Carrier angle, rad.
    pub phi_rad: f64,
}

/// A body's kinematics at one instant, SI: its axis, orientation rate and acceleration.
pub(crate) struct Axis {
    /// Axis position, m.
    pub(crate) c: Point,
    /// Orientation, rad.
    pub(crate) theta: f64,
    /// Angular velocity, rad/s.
    pub(crate) w: f64,
    /// Angular acceleration, rad/s².
    pub(crate) alpha: f64,
}

impl Axis {
    /// `m·a_G` and `S × a_C` of `body` (mm, kg) on this axis turning with the carrier at ω.
    pub(crate) fn inertia(&self, body: &MassProperties, omega: f64) -> (Point, f64, Point) {
        self.inertia_at(body, self.c * (-omega * omega))
    }

    /// `m·a_G` and `S × a_C` of `body` (mm, kg) on this axis, its acceleration `a_c` (m/s²).
    pub(crate) fn inertia_at(&self, body: &MassProperties, a_c: Point) -> (Point, f64, Point) {
        let s = body.first_moment_kg_mm().rotate(self.theta) * 1e-3; // kg·m
        let m_a = a_c * body.mass_kg + s.perp() * self.alpha - s * (self.w * self.w);
        let moment = body.inertia_kg_mm2 * 1e-6 * self.alpha + s.cross(a_c);
        (m_a, moment, s)
    }
}

/// The unit line of action of flank `s = ±1` at the pitch point `pp`, pressure angle `alpha`
/// (rad): `sin α·n + s·cos α·t` (module docs).
#[must_use]
pub fn line_of_action(pp: &PitchPoint, alpha: f64, s: f64) -> Point {
    let (sa, ca) = alpha.sin_cos();
    pp.normal * sa + pp.tangent * (s * ca)
}

/// The mesh force that gives the driven gear (axis `c`, m) the moment `m_req` (N·m) through
/// the pitch point `pp` at pressure angle `alpha` (rad).
fn mesh_force(m_req: f64, pp: &PitchPoint, c: Point, alpha: f64) -> Option<MeshForce> {
    let r = pp.point_mm * 1e-3 - c;
    let line = |s: f64| line_of_action(pp, alpha, s);
    let s = if m_req >= 0.0 { 1.0 } else { -1.0 };
    let k = r.cross(line(s));
    if !(k * s > 1e-9 * r.norm()) {
        return None;
    }
    let f = m_req / k;
    let cos_eff = (k.abs() / r.norm()).min(1.0);
    Some(MeshForce {
        force_n: line(s) * f,
        normal_force_n: f,
        flank: if m_req == 0.0 { 0 } else { s as i8 },
        effective_pressure_angle_rad: cos_eff.acos(),
    })
}

/// Solves one train at one instant: carrier speed `omega` (rad/s), gravity `g` (m/s², CCW
/// frame), the needle force on the tip `needle_n` (N, CCW frame), pressure angle `alpha` (rad).
///
/// # Errors
/// [`SelfLocking`] when a mesh cannot give the moment needed (effective pressure angle ≥ 90°).
pub fn solve(
    m: &TrainMotion,
    bodies: &TrainBodies,
    omega: f64,
    g: Point,
    needle_n: Point,
    alpha: f64,
) -> Result<TrainForces, SelfLocking> {
    let w2 = omega * omega;
    let si = |p: Point| p * 1e-3;
    let [rate2, acc2] = m.rates.intermediate;
    let [rate3, acc3] = m.rates.planet;
    let d = Axis {
        c: si(m.d_mm),
        theta: m.theta2_rad,
        w: omega * rate2,
        alpha: w2 * acc2,
    };
    let a = Axis {
        c: si(m.a_mm),
        theta: m.theta3_rad,
        w: omega * rate3,
        alpha: w2 * acc3,
    };
    // Planet + arm about A.
    let (ma_p, mom_p, s_p) = a.inertia(&bodies.planet, omega);
    let b = si(m.tip_mm);
    let m2 = mom_p - (b - a.c).cross(needle_n) - s_p.cross(g);
    let locking = |mesh| SelfLocking {
        mesh,
        phi_rad: m.phi_rad,
    };
    let f2 = mesh_force(m2, &m.planet_mesh, a.c, alpha).ok_or(locking("intermediate-planet"))?;
    let bearing_a = ma_p - f2.force_n - needle_n - g * bodies.planet.mass_kg;
    // Intermediate about D.
    let (ma_i, mom_i, s_i) = d.inertia(&bodies.intermediate, omega);
    let p2 = si(m.planet_mesh.point_mm);
    let m1 = mom_i - s_i.cross(g) + (p2 - d.c).cross(f2.force_n);
    let f1 = mesh_force(m1, &m.sun_mesh, d.c, alpha).ok_or(locking("sun-intermediate"))?;
    let bearing_d = ma_i - f1.force_n + f2.force_n - g * bodies.intermediate.mass_kg;
    let p1 = si(m.sun_mesh.point_mm);
    Ok(TrainForces {
        sun_mesh: f1,
        planet_mesh: f2,
        planet_mesh_torque_nm: m2,
        bearing_d_n: bearing_d,
        bearing_a_n: bearing_a,
        carrier_torque_nm: d.c.cross(bearing_d) + a.c.cross(bearing_a),
        sun_mesh_moment_nm: p1.cross(f1.force_n),
    })
}

/// The samples of train 1 over the turn: its motion and its forces (CCW frame).
#[derive(Debug, Clone)]
pub struct TrainTurn {
    /// Motion at each sample.
    pub motion: Vec<TrainMotion>,
    /// Forces at each sample (SI).
    pub forces: Vec<TrainForces>,
    /// The needle force on the tip at each sample, N (CCW frame).
    pub needle_n: Vec<Point>,
}
