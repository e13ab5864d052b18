//! The motion of one train at one carrier angle, in the counter-clockwise frame of
//! [`Rebuilt`]: the centres and orientations of the intermediate and the planet with their rates,
//! the two pitch points with the common tangents and normals of the pitch curves there, the
//! contact angles on each gear's body, and the needle tip (docs/math/chain.md §2, §6.5). Lengths
//! in mm, angles in rad, rates per radian of carrier travel.

use crate::geometry::assembly::{Rebuilt, TrainRates};
use crate::geometry::pitch::PitchCurve;
use crate::math::Point;
use std::f64::consts::PI;

/// One mesh's pitch point and frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PitchPoint {
    /// The pitch point, mm.
    pub point_mm: Point,
    /// Unit tangent of the pitch curves there, oriented CCW about the driven gear's centre
    /// (`(P − C) × t > 0`).
    pub tangent: Point,
    /// Unit normal towards the driven gear's centre: the side the separating force pushes it.
    pub normal: Point,
    /// Body angle of the contact on the driving gear (sun; intermediate), rad.
    pub driver_angle_rad: f64,
    /// Body angle of the contact on the driven gear (intermediate; planet), rad.
    pub driven_angle_rad: f64,
}

/// The train at one carrier angle (CCW frame).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrainMotion {
    /// Carrier angle φ (= the angle of travel), rad.
    pub phi_rad: f64,
    /// Intermediate centre D, mm.
    pub d_mm: Point,
    /// Planet centre A, mm.
    pub a_mm: Point,
    /// Intermediate orientation θ2, rad.
    pub theta2_rad: f64,
    /// Planet orientation θ3, rad.
    pub theta3_rad: f64,
    /// `dθ/dφ`, `d²θ/dφ²` of both gears.
    pub rates: TrainRates,
    /// Sun–intermediate mesh.
    pub sun_mesh: PitchPoint,
    /// Intermediate–planet mesh.
    pub planet_mesh: PitchPoint,
    /// Needle tip B, mm.
    pub tip_mm: Point,
}

/// World unit tangent of a polar curve at body angle `u`, the body turned by `theta`.
fn tangent(curve: &PitchCurve, u: f64, theta: f64) -> Point {
    let g = curve.geometry(u);
    let e = Point::unit(u);
    let t = e * g.dr_mm + e.perp() * g.r_mm;
    (t / t.norm()).rotate(theta)
}

/// A pitch point with its tangent and normal oriented about the driven centre `c`.
fn pitch_point(
    point_mm: Point,
    t: Point,
    c: Point,
    driver_angle_rad: f64,
    driven_angle_rad: f64,
) -> PitchPoint {
    let r = point_mm - c;
    let tangent = if r.cross(t) >= 0.0 { t } else { -t };
    let n = tangent.perp();
    let normal = if n.dot(c - point_mm) >= 0.0 { n } else { -n };
    PitchPoint {
        point_mm,
        tangent,
        normal,
        driver_angle_rad,
        driven_angle_rad,
    }
}

impl TrainMotion {
    /// The train of `r` at CCW-frame carrier angle `phi` (rad).
    #[must_use]
    pub fn at(r: &Rebuilt, phi: f64) -> Self {
        let a = r.assembly().a_mm;
        let eps = r.ccw_idler_offset();
        let l1 = r.l1_mm();
        let [sun, mid, _] = r.ccw_curves();
        let theta2 = r.ccw_intermediate_angle(phi);
        let (c2, c3) = r.ccw_planet_contact(phi);
        let theta3 = phi + PI - eps - c3;
        let d = Point::from_polar(a, phi + eps);
        let a_c = Point::from_polar(l1, phi);
        // Sun–intermediate: on O→D at the sun's body angle φ + ε (its body frame is the world's).
        let u1 = phi + eps;
        let c1 = u1 + PI - theta2;
        let p1 = Point::from_polar(sun.radius_mm(u1), u1);
        let sun_mesh = pitch_point(p1, tangent(sun, u1, 0.0), d, u1, c1);
        // Intermediate–planet: on D→A at the intermediate's body angle c2.
        let towards_a = (a_c - d) / a;
        let p2 = d + towards_a * mid.radius_mm(c2);
        let planet_mesh = pitch_point(p2, tangent(mid, c2, theta2), a_c, c2, c3);
        let tip = a_c + Point::from_polar(r.assembly().l3_mm, theta3 + r.ccw_needle_angle());
        Self {
            phi_rad: phi,
            d_mm: d,
            a_mm: a_c,
            theta2_rad: theta2,
            theta3_rad: theta3,
            rates: r.ccw_rates(phi),
            sun_mesh,
            planet_mesh,
            tip_mm: tip,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::assembly::Assembly;
    use crate::geometry::golden::g1_mechanism;

    /// The pitch points lie on the pitch curves of both gears of each mesh, the tangents of both
    /// curves agree there, and the tip is the rebuilt pose's.
    #[test]
    fn the_pitch_points_sit_on_both_curves_with_a_common_tangent() {
        let mut m = g1_mechanism();
        m.idler_offset_rad = 0.15;
        let r = Assembly::from_mechanism(&m, Point::ZERO, 1, 3600)
            .unwrap()
            .rebuild();
        let [_, mid, planet] = r.ccw_curves();
        for j in 0..20 {
            let phi = 0.31 * j as f64;
            let s = TrainMotion::at(&r, phi);
            let on = |curve: &PitchCurve, centre: Point, theta: f64, u: f64, p: Point| {
                let q = centre + curve.point_mm(u).rotate(theta);
                assert!(q.distance(p) < 1e-9, "{q:?} vs {p:?}");
            };
            on(
                mid,
                s.d_mm,
                s.theta2_rad,
                s.sun_mesh.driven_angle_rad,
                s.sun_mesh.point_mm,
            );
            on(
                mid,
                s.d_mm,
                s.theta2_rad,
                s.planet_mesh.driver_angle_rad,
                s.planet_mesh.point_mm,
            );
            on(
                planet,
                s.a_mm,
                s.theta3_rad,
                s.planet_mesh.driven_angle_rad,
                s.planet_mesh.point_mm,
            );
            let t_mid = tangent(mid, s.sun_mesh.driven_angle_rad, s.theta2_rad);
            assert!(t_mid.cross(s.sun_mesh.tangent).abs() < 1e-6);
            let t_planet = tangent(planet, s.planet_mesh.driven_angle_rad, s.theta3_rad);
            assert!(t_planet.cross(s.planet_mesh.tangent).abs() < 1e-6);
            assert!(s.tip_mm.distance(r.pose(phi).tip_mm) < 1e-9);
        }
    }
}
