//! One mesh of the rotor at one instant: the two flanks' lines of action and lever arms, the
//! deflection along each, the dead zone of the backlash and the contact force (docs/dynamics.md,
//! "The rotor").
//!
//! For flank `s = ±1` with unit line of action `l_s = sin α·n + s·cos α·t` (the loads' line,
//! [`line_of_action`]) and the signed lever arms `ρ_i = (P − C_i) × l_s` (m) of the driver (i = 1)
//! and the driven gear (i = 2) about their axes, the approach of the flanks along the line is
//!
//! ```text
//! δ_s = ρ1·Δθ1 − ρ2·Δθ2,     v_s = ρ1·Δθ̇1 − ρ2·Δθ̇2           (m, m/s)
//! δ̇_s = v_s + φ̇·(ρ1′·Δθ1 − ρ2′·Δθ2)                          (m/s, ρ′ = dρ/dφ, φ̇ the carrier's speed)
//! F_s = k·(δ_s − b) + c·δ̇_s   while δ_s > b,  else 0            (N, on the driven gear along l_s)
//! ```
//!
//! with Δθ the rotations away from the kinematic law, b half the normal backlash (Kahraman &
//! Singh 1990's dead zone, on each flank), k the mesh stiffness and c its damping. The damper
//! acts on the rate of the deflection itself, δ̇_s (Kelvin–Voigt): `v_s` alone, the flanks'
//! relative speed, differs from it by the lever arms' change with the travel, and a damper on
//! `v_s` can hold δ_s at the dead zone's edge with both sides pushing onto it (a sliding chatter
//! of contacts and flights). The force's power on the gears is `F·v_s`, so the damper takes
//! `c·δ̇_s·v_s` (the elastic part's `k(δ_s − b)·v_s` is the energy's change less its explicit
//! change with the travel). The pitch point lies on the line of centres, so δ₊ and δ₋ are of
//! opposite sign: one flank at most is in contact.

use crate::loads::kinetostatics::line_of_action;
use crate::loads::motion::PitchPoint;
use crate::math::Point;

/// The geometry of one mesh at one instant (SI).
#[derive(Debug, Clone, Copy)]
pub(crate) struct MeshGeometry {
    /// Unit lines of action of the flanks `[+1, −1]`.
    pub line: [Point; 2],
    /// Lever arms `(P − C) × l_s` of `[driver, driven]` for the flanks `[+1, −1]`, m.
    pub lever_m: [[f64; 2]; 2],
    /// Their rates with the travel, `dρ/dφ`, m/rad (zero unless the model fills them in: only
    /// the damping needs them).
    pub lever_rate_m: [[f64; 2]; 2],
}

impl MeshGeometry {
    /// The mesh at pitch point `pp` (mm), driver axis `c_drv` and driven axis `c_drn` (m),
    /// pressure angle `alpha` (rad).
    pub(crate) fn new(pp: &PitchPoint, c_drv: Point, c_drn: Point, alpha: f64) -> Self {
        let p = pp.point_mm * 1e-3;
        let line = [1.0, -1.0].map(|s| line_of_action(pp, alpha, s));
        let lever_m = line.map(|l| [(p - c_drv).cross(l), (p - c_drn).cross(l)]);
        Self {
            line,
            lever_m,
            lever_rate_m: [[0.0; 2]; 2],
        }
    }

    /// Approach `δ_s` of flank `f` (0: +1, 1: −1) for the rotations `[driver, driven]`, m.
    pub(crate) fn approach(&self, f: usize, dtheta: [f64; 2]) -> f64 {
        self.lever_m[f][0] * dtheta[0] - self.lever_m[f][1] * dtheta[1]
    }
}

/// The state of one mesh at one instant (SI).
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct MeshState {
    /// Normal force on the driven gear along the contact flank's line, N (0 out of contact).
    pub force_n: f64,
    /// The flank in contact: `+1`, `−1`, or 0.
    pub flank: i8,
    /// Approach of flank +1, `δ₊`, m (negative: towards the −1 flank).
    pub approach_m: f64,
    /// Approach rate `δ̇_s` of the flank in contact (of +1 out of contact), m/s.
    pub speed_m_s: f64,
    /// The force vector on the driven gear, N.
    pub force: Point,
    /// Moments of the force on `[driver, driven]` about their axes, N·m (driver: `−F·ρ1`).
    pub moment_nm: [f64; 2],
    /// Potential energy of the contact, `½k(δ_s − b)²`, J.
    pub energy_j: f64,
    /// Damping power `c·δ̇_s·v_s`, W.
    pub damping_w: f64,
}

/// The force law of a mesh: stiffness k (N/m), damping c (N·s/m), half normal backlash b (m),
/// the carrier's speed `phi_dot` (rad/s, for the lever arms' rates).
pub(crate) fn mesh_state(
    g: &MeshGeometry,
    dtheta: [f64; 2],
    dspeed: [f64; 2],
    phi_dot: f64,
    [k, c, b]: [f64; 3],
) -> MeshState {
    let approach = [0, 1].map(|f| g.approach(f, dtheta));
    let relative = [0, 1].map(|f| g.approach(f, dspeed));
    let speed = [0, 1].map(|f| {
        let r = g.lever_rate_m[f];
        relative[f] + phi_dot * (r[0] * dtheta[0] - r[1] * dtheta[1])
    });
    let gap_m = approach.map(|d| d - b);
    let mut st = MeshState {
        approach_m: approach[0],
        speed_m_s: speed[0],
        ..MeshState::default()
    };
    if let Some(f) = (0..2).find(|&f| gap_m[f] > 0.0) {
        let force = k * gap_m[f] + c * speed[f];
        st.force_n = force;
        st.flank = if f == 0 { 1 } else { -1 };
        st.speed_m_s = speed[f];
        st.force = g.line[f] * force;
        st.moment_nm = [-force * g.lever_m[f][0], force * g.lever_m[f][1]];
        st.energy_j = 0.5 * k * gap_m[f] * gap_m[f];
        st.damping_w = c * speed[f] * relative[f];
    }
    st
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A circular external pair on the x axis (driver at the origin, driven at x = 2r): both
    /// flanks' lever arms are ±r·cos α, the approaches opposite, and the force does the work of
    /// its potential: `F_s·l_s` on the driven gear, moment `F·ρ2`.
    #[test]
    fn a_circular_mesh_has_base_radius_levers_and_one_flank() {
        let r = 0.02;
        let alpha = 20f64.to_radians();
        let pp = PitchPoint {
            point_mm: Point::new(r * 1e3, 0.0),
            tangent: Point::new(0.0, -1.0),
            normal: Point::new(1.0, 0.0),
            driver_angle_rad: 0.0,
            driven_angle_rad: 0.0,
        };
        let g = MeshGeometry::new(&pp, Point::ZERO, Point::new(2.0 * r, 0.0), alpha);
        for f in 0..2 {
            assert!((g.lever_m[f][0].abs() - r * alpha.cos()).abs() < 1e-15);
            assert!((g.lever_m[f][1].abs() - r * alpha.cos()).abs() < 1e-15);
        }
        let d = [1e-4, 0.0];
        assert!((g.approach(0, d) + g.approach(1, d)).abs() < 1e-18);
        let st = mesh_state(&g, d, [0.0; 2], 0.0, [1e8, 0.0, 0.0]);
        assert_eq!(st.flank.abs(), 1);
        assert!((st.force_n - 1e8 * 1e-4 * r * alpha.cos()).abs() < 1e-6);
        // −∂V/∂Δθ2 is the moment on the driven gear
        let h = 1e-9;
        let v = |d2: f64| mesh_state(&g, [1e-4, d2], [0.0; 2], 0.0, [1e8, 0.0, 0.0]).energy_j;
        let dv = (v(h) - v(-h)) / (2.0 * h);
        assert!((-dv - st.moment_nm[1]).abs() < 1e-6 * st.moment_nm[1].abs());
    }
}
