//! The assembled train as a CAD pipeline sees it: three polar pitch tables, two assembly angles,
//! the needle angle and the carrier — exactly the content of `design.json` — and its kinematics
//! rebuilt **from those tables only** (the round trip, docs/math/chain.md §2 and check C12).
//!
//! Conventions (world frame = the trajectory's; angles CCW, rad inside, degrees in files): at
//! carrier angle φH the intermediate centre is `D = O + a·e(φH + ε)` (ε the idler offset, 0 in
//! the collinear train), the planet centre `A = O + l1·e(φH)` with `l1 = 2a·cos ε`; the sun (body
//! frame = world frame) touches the intermediate at its body angle `φH + ε`; the intermediate
//! touches the sun at its body angle `φH + ε + π − θ2` and the planet at `φH − ε − θ2`; the planet
//! touches the intermediate at `φH + π − ε − θ3`; the tip is `A + l3·e(θ3 + γ)`. For a clockwise
//! carrier (`direction = −1`) φH decreases in time; the tables and angles (ε among them) are the
//! mirror images of a CCW design, and the rebuild mirrors them back.
//!
//! Rebuild (CCW frame): with `i_s(θ) = r_s/(a − r_s)` and `g(θ) = ρ2/(a − ρ2)` integrated
//! spectrally on the tables' grids,
//!
//! ```text
//! θ2(φ) = θ2(0) + φ + ∫_ε^{φ+ε} i_s,     c2(φ) = φ − ε − θ2(φ)     (intermediate's planet-side contact)
//! c3(φ) = c3(0) − ∫_{c2(0)}^{c2(φ)} g,    θ3(φ) = φ + π − ε − c3(φ)   (planet rolls on the intermediate)
//! ```

use crate::geometry::mechanism::Mechanism;
use crate::geometry::pitch::{PitchCurve, PitchError};
use crate::math::Point;
use crate::math::periodic::{PeriodicSpline, spectral_integral};
use std::f64::consts::{PI, TAU};

/// The assembled gear train, world frame, mm and rad.
#[derive(Debug, Clone)]
pub struct Assembly {
    /// Carrier axis O, mm.
    pub center_mm: Point,
    /// +1 for a CCW carrier, −1 for CW.
    pub direction: i8,
    /// Centre distance `a`, mm.
    pub a_mm: f64,
    /// Idler offset ε: the angle at O from the carrier line OA to the intermediate axis OD, rad,
    /// CCW positive in the world frame (0: the collinear train,
    /// [`crate::geometry::mechanism`]).
    pub idler_offset_rad: f64,
    /// Needle length `l3`, mm.
    pub l3_mm: f64,
    /// Needle angle γ relative to the planet's body +x axis, rad.
    pub needle_angle_rad: f64,
    /// Sun pitch curve (body frame = world frame).
    pub sun: PitchCurve,
    /// Intermediate pitch curve, body frame.
    pub intermediate: PitchCurve,
    /// Intermediate orientation θ2 at φH = 0, rad.
    pub intermediate_angle_at_zero_rad: f64,
    /// Planet pitch curve, body frame.
    pub planet: PitchCurve,
    /// Planet orientation θ3 at φH = 0, rad.
    pub planet_angle_at_zero_rad: f64,
}

/// Kinematics rebuilt from an [`Assembly`] (CCW frame internally).
#[derive(Debug, Clone)]
pub struct Rebuilt {
    asm: Assembly,
    sign: f64,
    sun: PitchCurve,
    mid: PitchCurve,
    planet: PitchCurve,
    theta2_0: f64,
    theta3_0: f64,
    gamma: f64,
    /// Idler offset ε in the CCW frame, rad.
    eps: f64,
    /// `∫ i_s`: (mean, periodic part).
    sun_int: (f64, PeriodicSpline),
    /// `∫ g`: (mean, periodic part).
    mid_int: (f64, PeriodicSpline),
}

/// Pose of the train at one carrier angle (world frame, mm and rad).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pose {
    /// Carrier angle φH, rad.
    pub phi_h_rad: f64,
    /// Intermediate centre D, mm.
    pub intermediate_center_mm: Point,
    /// Planet centre A, mm.
    pub planet_center_mm: Point,
    /// Intermediate orientation θ2, rad.
    pub intermediate_angle_rad: f64,
    /// Planet orientation θ3, rad.
    pub planet_angle_rad: f64,
    /// Needle tip B, mm.
    pub tip_mm: Point,
    /// `r_sun + ρ2 − a` at the sun–intermediate contact, mm (0 for conjugate curves).
    pub sun_mesh_error_mm: f64,
    /// `r_planet + ρ2 − a` at the intermediate–planet contact, mm.
    pub planet_mesh_error_mm: f64,
}

/// The rates of the intermediate's and the planet's orientations with respect to the carrier
/// angle, CCW frame ([`Rebuilt::ccw_rates`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrainRates {
    /// `[dθ2/dφ, d²θ2/dφ²]`, rad/rad and rad/rad².
    pub intermediate: [f64; 2],
    /// `[dθ3/dφ, d²θ3/dφ²]`, rad/rad and rad/rad².
    pub planet: [f64; 2],
}

fn mirrored(c: &PitchCurve) -> PitchCurve {
    let r = c.radii_mm();
    let n = r.len();
    PitchCurve::from_uniform_radii((0..n).map(|k| r[(n - k) % n]).collect())
        .expect("mirror of a valid curve")
}

fn integral_of(curve: &PitchCurve, a: f64) -> (f64, PeriodicSpline) {
    let y: Vec<f64> = curve.radii_mm().iter().map(|r| r / (a - r)).collect();
    let (mean, f) = spectral_integral(&y);
    (
        mean,
        PeriodicSpline::uniform(0.0, f, TAU).expect("≥ 8 samples"),
    )
}

impl Assembly {
    /// Assembles a designed mechanism (solved CCW frame, relative to O) in the world frame:
    /// tables of `n` samples, mirrored when `direction = −1`.
    pub fn from_mechanism(
        m: &Mechanism,
        center_mm: Point,
        direction: i8,
        n: usize,
    ) -> Result<Self, PitchError> {
        let sign = if direction >= 0 { 1.0 } else { -1.0 };
        let world = |c: PitchCurve| {
            if direction >= 0 {
                Ok(c)
            } else {
                Ok(mirrored(&c))
            }
        };
        // The three tables are independent: sampled side by side.
        let (sun, (intermediate, planet)) = rayon::join(
            || m.sun_curve(n),
            || rayon::join(|| m.intermediate_curve(n), || m.planet_curve(n)),
        );
        Ok(Self {
            center_mm,
            direction: if direction >= 0 { 1 } else { -1 },
            a_mm: m.a_mm,
            idler_offset_rad: sign * m.idler_offset_rad,
            l3_mm: m.l3_mm,
            needle_angle_rad: sign * m.needle_angle_rad,
            sun: world(sun?)?,
            intermediate: world(intermediate?)?,
            intermediate_angle_at_zero_rad: sign * m.intermediate_orientation(0.0),
            planet: world(planet?)?,
            planet_angle_at_zero_rad: sign * m.planet_orientation(0.0),
        })
    }

    /// Carrier arm length `l1 = |OA| = 2a·cos ε`, mm.
    #[must_use]
    pub fn l1_mm(&self) -> f64 {
        2.0 * self.a_mm * self.idler_offset_rad.cos()
    }

    /// Rebuilds the kinematics from the tables (spectral integration on the tables' grids).
    #[must_use]
    pub fn rebuild(&self) -> Rebuilt {
        let ccw = self.direction >= 0;
        let (sun, mid, planet) = if ccw {
            (
                self.sun.clone(),
                self.intermediate.clone(),
                self.planet.clone(),
            )
        } else {
            (
                mirrored(&self.sun),
                mirrored(&self.intermediate),
                mirrored(&self.planet),
            )
        };
        let sign = if ccw { 1.0 } else { -1.0 };
        let (sun_int, mid_int) = rayon::join(
            || integral_of(&sun, self.a_mm),
            || integral_of(&mid, self.a_mm),
        );
        Rebuilt {
            asm: self.clone(),
            sign,
            sun,
            mid,
            planet,
            theta2_0: sign * self.intermediate_angle_at_zero_rad,
            theta3_0: sign * self.planet_angle_at_zero_rad,
            gamma: sign * self.needle_angle_rad,
            eps: sign * self.idler_offset_rad,
            sun_int,
            mid_int,
        }
    }
}

impl Rebuilt {
    /// The assembly whose tables were rebuilt.
    #[must_use]
    pub fn assembly(&self) -> &Assembly {
        &self.asm
    }

    /// Mean of `r/(a − r)` over the sun and the intermediate tables; both 1 for closed, conjugate
    /// curves (checks C1/C2 from the outputs).
    #[must_use]
    pub fn ratio_means(&self) -> [f64; 2] {
        [self.sun_int.0, self.mid_int.0]
    }

    fn sun_phi(&self, x: f64) -> f64 {
        self.sun_int.0 * x + self.sun_int.1.value(x)
    }

    fn mid_g(&self, x: f64) -> f64 {
        self.mid_int.0 * x + self.mid_int.1.value(x)
    }

    /// `+1` for a CCW carrier, `−1` for CW: world `y` = `sign·y` of the internal CCW frame, and a
    /// world carrier angle φH is the CCW-frame angle `sign·φH`.
    #[must_use]
    pub fn sign(&self) -> f64 {
        self.sign
    }

    /// Sun, intermediate and planet pitch curves in the CCW frame (mirrored for a CW design).
    #[must_use]
    pub fn ccw_curves(&self) -> [&PitchCurve; 3] {
        [&self.sun, &self.mid, &self.planet]
    }

    /// Needle angle γ in the CCW frame, rad.
    #[must_use]
    pub fn ccw_needle_angle(&self) -> f64 {
        self.gamma
    }

    /// Carrier arm length `l1 = 2a·cos ε`, mm.
    #[must_use]
    pub fn l1_mm(&self) -> f64 {
        self.asm.l1_mm()
    }

    /// Idler offset ε in the CCW frame, rad.
    #[must_use]
    pub fn ccw_idler_offset(&self) -> f64 {
        self.eps
    }

    /// Intermediate orientation `θ2(φ) = θ2(0) + φ + ∫_ε^{φ+ε} i_s` at CCW-frame carrier angle
    /// φ, rad.
    #[must_use]
    pub fn ccw_intermediate_angle(&self, phi: f64) -> f64 {
        self.theta2_0 + phi + self.sun_phi(phi + self.eps) - self.sun_phi(self.eps)
    }

    /// Tooth correspondence of the sun–intermediate mesh: the intermediate body angle that meets
    /// sun body angle `u` (CCW frame; at carrier angle `u − ε`), `u + π − θ2(u − ε)`, rad.
    #[must_use]
    pub fn ccw_sun_to_intermediate(&self, u: f64) -> f64 {
        u + PI - self.ccw_intermediate_angle(u - self.eps)
    }

    /// Tooth correspondence of the intermediate–planet mesh: the planet body angle
    /// `c3 = c3(0) − ∫_{c2(0)}^{c2} g` that meets intermediate body angle `c2` (CCW frame), rad.
    #[must_use]
    pub fn ccw_intermediate_to_planet(&self, c2: f64) -> f64 {
        let c2_0 = -self.eps - self.theta2_0;
        let c3_0 = PI - self.eps - self.theta3_0;
        c3_0 - (self.mid_g(c2) - self.mid_g(c2_0))
    }

    /// The intermediate's planet-side contact angle `c2 = φ − ε − θ2(φ)` and the planet's contact
    /// angle `c3` at CCW-frame carrier angle φ (body angles, rad).
    #[must_use]
    pub fn ccw_planet_contact(&self, phi: f64) -> (f64, f64) {
        let c2 = phi - self.eps - self.ccw_intermediate_angle(phi);
        (c2, self.ccw_intermediate_to_planet(c2))
    }

    /// The rates of the train at CCW-frame carrier angle φ: derivatives of the intermediate's and
    /// the planet's orientations with respect to the carrier angle, from the pitch curves'
    /// polar geometry at the contacts (docs/math/chain.md §5):
    ///
    /// ```text
    /// i_s = r_s/(a − r_s) at φ + ε,   g = ρ2/(a − ρ2) at c2,   i_s′ = a·r_s′/(a − r_s)²,   g′ = a·ρ2′/(a − ρ2)²
    /// θ2′ = 1 + i_s,   θ2″ = i_s′,   θ3′ = 1 − g·i_s,   θ3″ = g′·i_s² − g·i_s′
    /// ```
    ///
    /// (`c2′ = −i_s`, and the planet rolls on the intermediate: `c3′ = g·i_s`). Multiplied by
    /// the carrier speed ω (and ω²) they are the gears' angular velocities (accelerations).
    #[must_use]
    pub fn ccw_rates(&self, phi: f64) -> TrainRates {
        let a = self.asm.a_mm;
        let s = self.sun.geometry(phi + self.eps);
        let (c2, _) = self.ccw_planet_contact(phi);
        let m = self.mid.geometry(c2);
        let is = s.r_mm / (a - s.r_mm);
        let dis = a * s.dr_mm / ((a - s.r_mm) * (a - s.r_mm));
        let g = m.r_mm / (a - m.r_mm);
        let dg = a * m.dr_mm / ((a - m.r_mm) * (a - m.r_mm));
        TrainRates {
            intermediate: [1.0 + is, dis],
            planet: [1.0 - g * is, dg * is * is - g * dis],
        }
    }

    /// Pose at world carrier angle φH (rad).
    #[must_use]
    pub fn pose(&self, phi_h: f64) -> Pose {
        let (a, eps) = (self.asm.a_mm, self.eps);
        let phi = self.sign * phi_h; // CCW-frame carrier angle
        let theta2 = self.ccw_intermediate_angle(phi);
        let c2 = phi - eps - theta2;
        let c3 = self.ccw_intermediate_to_planet(c2);
        let theta3 = phi + PI - eps - c3;
        let b = theta3 + self.gamma;
        let l1 = self.l1_mm();
        let o = self.asm.center_mm;
        let s = self.sign;
        let world = |p: Point| Point::new(o.x + p.x, o.y + s * p.y);
        let d = phi + eps;
        let sun_err = self.sun.radius_mm(d) + self.mid.radius_mm(d + PI - theta2) - a;
        let planet_err = self.planet.radius_mm(c3) + self.mid.radius_mm(c2) - a;
        Pose {
            phi_h_rad: phi_h,
            intermediate_center_mm: world(Point::new(a * d.cos(), a * d.sin())),
            planet_center_mm: world(Point::new(l1 * phi.cos(), l1 * phi.sin())),
            intermediate_angle_rad: s * theta2,
            planet_angle_rad: s * theta3,
            tip_mm: world(Point::new(
                l1 * phi.cos() + self.asm.l3_mm * b.cos(),
                l1 * phi.sin() + self.asm.l3_mm * b.sin(),
            )),
            sun_mesh_error_mm: sun_err,
            planet_mesh_error_mm: planet_err,
        }
    }

    /// Tip positions (mm, world) at `n` uniform carrier angles over one turn, in travel order.
    #[must_use]
    pub fn traced(&self, n: usize) -> Vec<Point> {
        use rayon::prelude::*;
        // Independent poses: side by side, collected in order.
        (0..n)
            .into_par_iter()
            .map(|k| self.pose(self.sign * TAU * k as f64 / n as f64).tip_mm)
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::fourier::SunRatio;

    /// A generic train (three harmonics) with its intermediate axis `eps` (rad) off the line.
    fn offset_train(eps: f64) -> Mechanism {
        Mechanism {
            a_mm: 46.0,
            l3_mm: 170.0,
            ratio: SunRatio::new(vec![0.25, 0.04, -0.02], vec![0.05, -0.03, 0.01]).unwrap(),
            sun_phase_rad: 0.4,
            needle_angle_rad: -1.1,
            idler_offset_rad: eps,
        }
    }

    /// The tables of a train off the collinear layout rebuild its kinematics: centres,
    /// orientations and tip as the forward model has them, for either carrier sense (a CW
    /// design is the mirror image of the CCW one, ε included).
    #[test]
    fn an_offset_train_rebuilds_from_its_tables() {
        let m = offset_train(-0.25);
        let o = Point::new(10.0, -5.0);
        for direction in [1, -1] {
            let s = f64::from(direction);
            let r = Assembly::from_mechanism(&m, o, direction, 3600)
                .unwrap()
                .rebuild();
            for j in 0..36 {
                let phi = 0.17 * j as f64;
                let p = r.pose(s * phi);
                let world = |v: Point| Point::new(o.x + v.x, o.y + s * v.y);
                let close = |a: Point, b: Point, tol: f64| {
                    assert!(a.distance(b) < tol, "{a:?} vs {b:?} at {phi}");
                };
                close(p.tip_mm, world(m.tip(phi)), 1e-8);
                close(
                    p.intermediate_center_mm,
                    world(m.intermediate_center(phi)),
                    1e-12,
                );
                let l1 = m.l1_mm();
                close(
                    p.planet_center_mm,
                    world(Point::new(l1 * phi.cos(), l1 * phi.sin())),
                    1e-12,
                );
                let turn = |a: f64, b: f64| ((a - b + PI).rem_euclid(TAU) - PI).abs();
                assert!(turn(p.planet_angle_rad, s * m.planet_orientation(phi)) < 1e-10);
                assert!(
                    turn(
                        p.intermediate_angle_rad,
                        s * m.intermediate_orientation(phi)
                    ) < 1e-10
                );
                assert!(p.sun_mesh_error_mm.abs() < 1e-9 && p.planet_mesh_error_mm.abs() < 1e-9);
            }
        }
    }
    /// The rates are the derivatives of the rebuilt orientations: central differences of θ2 and
    /// θ3 agree with θ′ to O(h²) and with θ″ to O(h²), off the collinear layout too.
    #[test]
    fn the_rates_are_the_derivatives_of_the_orientations() {
        let m = offset_train(0.2);
        let r = Assembly::from_mechanism(&m, Point::ZERO, 1, 4096)
            .unwrap()
            .rebuild();
        let h = 1e-4;
        let theta3 = |phi: f64| phi + PI - r.ccw_idler_offset() - r.ccw_planet_contact(phi).1;
        for j in 0..24 {
            let phi = 0.26 * j as f64;
            let rates = r.ccw_rates(phi);
            let t2 = |x: f64| r.ccw_intermediate_angle(x);
            let d1 = (t2(phi + h) - t2(phi - h)) / (2.0 * h);
            let d2 = (t2(phi + h) - 2.0 * t2(phi) + t2(phi - h)) / (h * h);
            assert!((d1 - rates.intermediate[0]).abs() < 1e-6, "{d1} {rates:?}");
            assert!((d2 - rates.intermediate[1]).abs() < 2e-3, "{d2} {rates:?}");
            let e1 = (theta3(phi + h) - theta3(phi - h)) / (2.0 * h);
            let e2 = (theta3(phi + h) - 2.0 * theta3(phi) + theta3(phi - h)) / (h * h);
            assert!((e1 - rates.planet[0]).abs() < 1e-6, "{e1} {rates:?}");
            assert!((e2 - rates.planet[1]).abs() < 2e-3, "{e2} {rates:?}");
        }
    }
}
