//! The planetary train as a forward model (docs/math/chain.md §2, §6, §9).
//!
//! A [`Mechanism`] is the design: centre distance `a` (`|OD| = |DA| = a`), the idler offset ε
//! (the angle at O between the carrier line OA and the intermediate axis D; 0 in the patent's
//! collinear train, so `l1 = 2a`), needle length `l3`, the sun ratio `i21(u)` as a function of
//! the sun's *design* polar angle `u`, the world angle `φ_ref` of the sun's design reference ray,
//! and the needle mounting angle γ. At carrier angle φH (rad, CCW):
//!
//! ```text
//! D = a·e(φH + ε),   A = l1·e(φH),   l1 = 2a·cos ε       (OAD isosceles: |OD| = |DA| = a)
//! t′     = φH + ε − φ_ref                   sun polar angle at the contact (design frame)
//! Φ(t′)  = ∫_0^t′ i21,   S(t′) = Φ⁻¹(Φ(t′) + π + 2ε)
//! θ2     = φH + ε + Φ(t′)                   intermediate orientation (world angle of body +x)
//! θ3     = φH + π − ε − S(t′)               planet orientation
//! B = A + l3·e(θ3 + γ)
//! ```
//!
//! The intermediate gear meets the sun along D→O (world angle φH + ε + π) and the planet along
//! D→A (φH − ε): its two contacts are `π + 2ε` apart round it (docs/math/chain.md §6.5). The
//! pair intermediate–planet is the pair sun–intermediate turned about D by that angle, so the
//! planet is still the sun's copy, and its contact angle `S` solves `Φ(S) = Φ(t′) + π + 2ε`. With
//! ε = 0 this is the patent's train (`S` the half-turn map). With ε ≠ 0 the arm `l1 = 2a·cos ε`
//! no longer follows from the centre distance alone: a tooth count at a standard module fixes
//! `a`, and ε keeps `l1` where the target needs it (docs/math/chain.md §6.5).
//!
//! Body frames (the JSON conventions of `design.json`): the sun's body frame is the world frame
//! (its curve is the design curve rotated by `φ_ref`); the planet's body frame is the design frame
//! (the planet is congruent to the sun, docs/math/chain.md §6.1); the intermediate's body frame is the one in which its
//! sun-side contact sits at `π − Φ(t′)`.

use crate::geometry::fourier::SunRatio;
use crate::geometry::pitch::{PitchCurve, PitchError};
use crate::math::Point;
use std::f64::consts::{PI, TAU};

/// Tolerance of the Φ⁻¹ solves, rad (docs/math/chain.md §13: 1e-13).
pub const INVERSE_TOL_RAD: f64 = 1e-13;

/// Largest idler offset |ε| a train may have, rad (30°): the intermediate axis stays within a
/// third of a right angle of the carrier line. A tooth count one above the free count needs
/// `cos ε = z_free/z` (8° at 20 teeth, 27° at the fewest, 8), so this holds every offset a
/// standard module asks for, with the sun and planet well clear of each other (check C13).
pub const MAX_IDLER_OFFSET_RAD: f64 = PI / 6.0;

/// A designed planetary train with non-circular gears.
#[derive(Debug, Clone, PartialEq)]
pub struct Mechanism {
    /// Centre distance `a = |OD| = |DA|`, mm.
    pub a_mm: f64,
    /// Needle length `l3 = |AB|`, mm.
    pub l3_mm: f64,
    /// Sun ratio against the sun's design polar angle.
    pub ratio: SunRatio,
    /// World angle of the sun's design reference ray, rad.
    pub sun_phase_rad: f64,
    /// Needle mounting angle γ relative to the planet's body +x axis, rad.
    pub needle_angle_rad: f64,
    /// Idler offset ε: the angle from the carrier line OA to the intermediate axis OD, rad, CCW
    /// positive (module documentation); 0 = the patent's collinear train.
    pub idler_offset_rad: f64,
}

/// Pitch radius and its first two polar derivatives of the sun and the intermediate at one
/// contact, from `(i, i′, i″)` (docs/math/chain.md §5).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactGeometry {
    /// Sun `(r1, dr1/dθ1, d²r1/dθ1²)`, mm.
    pub sun: [f64; 3],
    /// Intermediate `(r2, dr2/dθ2, d²r2/dθ2²)` against its own polar angle, mm.
    pub intermediate: [f64; 3],
}

impl ContactGeometry {
    /// From the ratio and its derivatives at the contact and the centre distance `a` (mm).
    #[must_use]
    pub fn new(a: f64, [i, di, ddi]: [f64; 3]) -> Self {
        let s = 1.0 + i;
        let sun = [
            a * i / s,
            a * di / (s * s),
            a * (ddi * s - 2.0 * di * di) / (s * s * s),
        ];
        let r2 = a / s;
        let r2t = a * di / (i * s * s);
        let r2tt = -(a / i) * (ddi * i * s - di * di * s - 2.0 * i * di * di) / (i * i * s * s * s);
        Self {
            sun,
            intermediate: [r2, r2t, r2tt],
        }
    }

    /// Convexity `Δ = r² + 2r′² − r r″` (mm²) of the sun and the intermediate.
    #[must_use]
    pub fn convexity_mm2(&self) -> [f64; 2] {
        let d = |[r, r1, r2]: [f64; 3]| r * r + 2.0 * r1 * r1 - r * r2;
        [d(self.sun), d(self.intermediate)]
    }
}

impl Mechanism {
    /// The patent's collinear train (`ε = 0`) of centre distance `a_mm` (mm), needle length
    /// `l3_mm` (mm), sun ratio `ratio`, sun phase `sun_phase_rad` and needle angle
    /// `needle_angle_rad` (rad).
    #[must_use]
    pub fn collinear(
        a_mm: f64,
        l3_mm: f64,
        ratio: SunRatio,
        sun_phase_rad: f64,
        needle_angle_rad: f64,
    ) -> Self {
        Self {
            a_mm,
            l3_mm,
            ratio,
            sun_phase_rad,
            needle_angle_rad,
            idler_offset_rad: 0.0,
        }
    }

    /// Carrier arm length `l1 = 2a·cos ε`, mm.
    #[must_use]
    pub fn l1_mm(&self) -> f64 {
        2.0 * self.a_mm * self.idler_offset_rad.cos()
    }

    /// The angle round the intermediate gear from its sun contact to its planet contact,
    /// `c = π + 2ε`, rad.
    #[must_use]
    pub fn contact_shift_rad(&self) -> f64 {
        PI + 2.0 * self.idler_offset_rad
    }

    /// Sun design angle at the contact at carrier angle φH, `t′ = φH + ε − φ_ref`, rad.
    #[must_use]
    pub fn contact_angle(&self, phi_h: f64) -> f64 {
        phi_h + self.idler_offset_rad - self.sun_phase_rad
    }

    /// `S(t′) = Φ⁻¹(Φ(t′) + π + 2ε)`, rad.
    #[must_use]
    pub fn contact_map(&self, t: f64) -> f64 {
        self.ratio
            .contact_map(t, self.contact_shift_rad(), INVERSE_TOL_RAD)
    }

    /// Planet relative rotation `ψ3(t′) = S(t′) − S(0)`, rad (docs/math/chain.md §2).
    #[must_use]
    pub fn psi3(&self, t: f64) -> f64 {
        self.contact_map(t) - self.contact_map(0.0)
    }

    /// Intermediate axis D at carrier angle φH (rad), mm, relative to the carrier axis.
    #[must_use]
    pub fn intermediate_center(&self, phi_h: f64) -> Point {
        let d = phi_h + self.idler_offset_rad;
        Point::new(self.a_mm * d.cos(), self.a_mm * d.sin())
    }

    /// Intermediate orientation θ2 at carrier angle φH, rad.
    #[must_use]
    pub fn intermediate_orientation(&self, phi_h: f64) -> f64 {
        phi_h + self.idler_offset_rad + self.ratio.integral(self.contact_angle(phi_h))
    }

    /// Planet orientation θ3 at carrier angle φH, rad.
    #[must_use]
    pub fn planet_orientation(&self, phi_h: f64) -> f64 {
        phi_h + PI - self.idler_offset_rad - self.contact_map(self.contact_angle(phi_h))
    }

    /// Needle direction `β = θ3 + γ`, rad.
    #[must_use]
    pub fn needle_direction(&self, phi_h: f64) -> f64 {
        self.planet_orientation(phi_h) + self.needle_angle_rad
    }

    /// Needle tip at carrier angle φH (rad), mm, relative to the carrier axis.
    #[must_use]
    pub fn tip(&self, phi_h: f64) -> Point {
        let b = self.needle_direction(phi_h);
        let l1 = self.l1_mm();
        Point::new(
            l1 * phi_h.cos() + self.l3_mm * b.cos(),
            l1 * phi_h.sin() + self.l3_mm * b.sin(),
        )
    }

    /// Largest pitch radius of the sun and of its copy, the planet, `a·i_max/(1 + i_max)`, mm.
    #[must_use]
    pub fn sun_max_radius_mm(&self) -> f64 {
        let i = self.ratio.range()[1];
        self.a_mm * i / (1.0 + i)
    }

    /// The gap the sun and the planet leave between their pitch curves in the worst case, both
    /// at their largest radius facing each other across the carrier: `l1 − 2·r_max`, mm (the
    /// collinear train's is `2a/(1 + i_max)`, twice the intermediate gear's smallest radius;
    /// check C13).
    #[must_use]
    pub fn sun_planet_gap_mm(&self) -> f64 {
        self.l1_mm() - 2.0 * self.sun_max_radius_mm()
    }

    /// The largest idler offset |ε| (rad) that keeps [`Self::sun_planet_gap_mm`] at least
    /// `gap_mm` (mm) at this centre distance and ratio, `cos ε ≥ (2·r_max + gap)/(2a)`, and
    /// within [`MAX_IDLER_OFFSET_RAD`]; 0 when even the collinear train has less gap.
    #[must_use]
    pub fn max_idler_offset_rad(&self, gap_mm: f64) -> f64 {
        let c = (2.0 * self.sun_max_radius_mm() + gap_mm) / (2.0 * self.a_mm);
        if c >= 1.0 {
            0.0
        } else {
            c.acos().min(MAX_IDLER_OFFSET_RAD)
        }
    }

    /// Sun pitch radius against the design polar angle: `r1 = a·i/(1 + i)`, mm.
    #[must_use]
    pub fn sun_radius_mm(&self, u: f64) -> f64 {
        let i = self.ratio.value(u);
        self.a_mm * i / (1.0 + i)
    }

    /// Sun pitch curve in its body (= world) frame, `n` uniform samples.
    pub fn sun_curve(&self, n: usize) -> Result<PitchCurve, PitchError> {
        PitchCurve::from_fn(n, |th| self.sun_radius_mm(th - self.sun_phase_rad))
    }

    /// Planet pitch curve in its body (= the sun's design) frame, `n` uniform samples.
    pub fn planet_curve(&self, n: usize) -> Result<PitchCurve, PitchError> {
        PitchCurve::from_fn(n, |th| self.sun_radius_mm(th))
    }

    /// Intermediate pitch curve, `n` uniform samples: the point at body angle `θ = π − Φ(t′)` has
    /// radius `a/(1 + i21(t′))`, so `ρ2(θ) = a/(1 + i21(Φ⁻¹(π − θ)))` (docs/math/chain.md §9).
    pub fn intermediate_curve(&self, n: usize) -> Result<PitchCurve, PitchError> {
        let t = self.ratio.inverse_integral_along(
            n,
            |k| PI - TAU * k as f64 / n as f64,
            INVERSE_TOL_RAD,
        );
        PitchCurve::from_uniform_radii(
            t.iter()
                .map(|&t| self.a_mm / (1.0 + self.ratio.value(t)))
                .collect(),
        )
    }

    /// Contact geometry (radii and derivatives) at design sun angle `u`.
    #[must_use]
    pub fn contact_geometry(&self, u: f64) -> ContactGeometry {
        ContactGeometry::new(self.a_mm, self.ratio.eval3(u))
    }

    /// Planet orientations θ3 (rad) at the `n` uniform carrier angles `φ_k = 2πk/n`.
    #[must_use]
    pub fn planet_orientations_uniform(&self, n: usize) -> Vec<f64> {
        let s = self.ratio.contact_map_uniform(
            self.contact_angle(0.0),
            self.contact_shift_rad(),
            n,
            INVERSE_TOL_RAD,
        );
        s.iter()
            .enumerate()
            .map(|(k, s)| TAU * k as f64 / n as f64 + PI - self.idler_offset_rad - s)
            .collect()
    }

    /// Fits γ against a target needle direction `β_target(φ)` (rad) on `n` uniform carrier
    /// angles and returns the max synchronous tip deviation there (mm).
    ///
    /// γ is the circular mean of `d_k = β_target(φ_k) − θ3(φ_k)`, which minimises the deviation
    /// to first order; the deviation is `max_k 2·l3·|sin((γ − d_k)/2)|`.
    pub fn fit_needle_angle(&mut self, n: usize, beta_target: impl Fn(f64) -> f64) -> f64 {
        let theta3 = self.planet_orientations_uniform(n);
        let d: Vec<f64> = theta3
            .iter()
            .enumerate()
            .map(|(k, t3)| beta_target(TAU * k as f64 / n as f64) - t3)
            .collect();
        let (s, c) = d
            .iter()
            .fold((0.0, 0.0), |(s, c), d| (s + d.sin(), c + d.cos()));
        self.needle_angle_rad = s.atan2(c);
        let gamma = self.needle_angle_rad;
        d.iter()
            .map(|d| 2.0 * self.l3_mm * (0.5 * (gamma - d)).sin().abs())
            .fold(0.0, f64::max)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// docs/math/chain.md §11.1 (G1): focus ellipse ratio `i = (1−e²)/(1 − 2e cos θ + e²) = 1 + 2Σ eᵏ cos kθ`.
    fn g1() -> Mechanism {
        let e: f64 = 0.15;
        let a = (1..=30).map(|k| 2.0 * e.powi(k)).collect();
        Mechanism {
            a_mm: 45.0,
            l3_mm: 170.0,
            ratio: SunRatio::new(a, vec![0.0; 30]).unwrap(),
            sun_phase_rad: 0.0,
            needle_angle_rad: 0.0,
            idler_offset_rad: 0.0,
        }
    }

    #[test]
    fn g1_psi3_table_and_planet_closed_form() {
        let m = g1();
        let golden = [
            0.0, 52.252904, 93.164303, 122.703222, 144.987948, 163.343889, 180.0, 196.656111,
            215.012052, 237.296778, 266.835697, 307.747096, 360.0,
        ];
        let k2 = (1.15_f64 / 0.85).powi(2);
        for (j, g) in golden.iter().enumerate() {
            let t = (30.0 * j as f64).to_radians();
            assert!((m.psi3(t).to_degrees() - g).abs() < 1e-6, "t = {}", 30 * j);
            let closed = 2.0 * (k2 * (t / 2.0).sin()).atan2((t / 2.0).cos());
            assert!(
                (m.psi3(t) - closed.rem_euclid(TAU) - if j == 12 { TAU } else { 0.0 }).abs()
                    < 1e-12
            );
        }
        // The sun and intermediate of G1 are the same ellipse (docs/math/chain.md §11.1): ρ2(θ) = r1(θ).
        let sun = m.planet_curve(720).unwrap();
        let mid = m.intermediate_curve(720).unwrap();
        let dev = sun
            .radii_mm()
            .iter()
            .zip(mid.radii_mm())
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        assert!(dev < 1e-11, "{dev}");
    }

    /// A train off the collinear layout rolls: at every carrier angle both meshes touch on
    /// their lines of centres (`r + ρ = a` from the sampled pitch curves, placed by the
    /// orientations) and their pitch points move together (the relative turn rates in the
    /// inverse ratio of the radii, by central differences of the orientations).
    #[test]
    fn an_offset_train_meshes_and_rolls_on_both_contacts() {
        let m = Mechanism {
            ratio: SunRatio::new(vec![0.25, 0.04, -0.02], vec![0.05, -0.03, 0.01]).unwrap(),
            sun_phase_rad: 0.4,
            idler_offset_rad: 0.3,
            ..g1()
        };
        let n = 8192;
        let (sun, mid, planet) = (
            m.sun_curve(n).unwrap(),
            m.intermediate_curve(n).unwrap(),
            m.planet_curve(n).unwrap(),
        );
        let dir = |p: Point, q: Point| (q - p).atan2();
        let h = 1e-5;
        for j in 0..24 {
            let phi = 0.26 * j as f64;
            let d = m.intermediate_center(phi);
            let a = Point::new(m.l1_mm() * phi.cos(), m.l1_mm() * phi.sin());
            assert!((d.hypot() - m.a_mm).abs() < 1e-12);
            assert!((a.distance(d) - m.a_mm).abs() < 1e-12);
            let (t2, t3) = (m.intermediate_orientation(phi), m.planet_orientation(phi));
            let r_sun = sun.radius_mm(dir(Point::new(0.0, 0.0), d));
            let r_mid_sun = mid.radius_mm(dir(d, Point::new(0.0, 0.0)) - t2);
            let r_mid_planet = mid.radius_mm(dir(d, a) - t2);
            let r_planet = planet.radius_mm(dir(a, d) - t3);
            assert!(
                (r_sun + r_mid_sun - m.a_mm).abs() < 1e-7,
                "sun mesh at {phi}"
            );
            assert!(
                (r_planet + r_mid_planet - m.a_mm).abs() < 1e-7,
                "planet mesh at {phi}"
            );
            // Turn rates relative to the carrier: sun −1, intermediate θ2′ − 1, planet θ3′ − 1.
            let w2 = (m.intermediate_orientation(phi + h) - m.intermediate_orientation(phi - h))
                / (2.0 * h)
                - 1.0;
            let w3 =
                (m.planet_orientation(phi + h) - m.planet_orientation(phi - h)) / (2.0 * h) - 1.0;
            assert!(
                (r_sun - r_mid_sun * w2).abs() < 1e-6,
                "sun rolling at {phi}"
            );
            assert!(
                (r_mid_planet * w2 + r_planet * w3).abs() < 1e-6,
                "planet rolling at {phi}"
            );
        }
        // ε = 0 is the patent's train: l1 = 2a and the half-turn map.
        let c = g1();
        assert_eq!(c.l1_mm(), 2.0 * c.a_mm);
        assert_eq!(
            c.contact_map(0.7),
            c.ratio.half_turn_map(0.7, INVERSE_TOL_RAD)
        );
    }

    #[test]
    fn convexity_formulas_match_the_spline_geometry() {
        let m = g1();
        let sun = m.planet_curve(4096).unwrap();
        for j in 0..12 {
            let u = 0.5 * j as f64;
            let g = sun.geometry(u);
            let c = m.contact_geometry(u);
            assert!((g.convexity_mm2() - c.convexity_mm2()[0]).abs() < 1e-5 * g.r_mm * g.r_mm);
        }
    }
}
