//! The planetary train as a forward model (docs/math/chain.md §2, §6, §9).
//!
//! A [`Mechanism`] is the design: centre distance `a` (so `l1 = 2a`), needle length `l3`, the sun
//! ratio `i21(u)` as a function of the sun's *design* polar angle `u`, the world angle `φ_ref` of the
//! sun's design reference ray, and the needle mounting angle γ. At carrier angle φH (rad, CCW):
//!
//! ```text
//! t′     = φH − φ_ref                       sun polar angle at the contact (design frame)
//! Φ(t′)  = ∫_0^t′ i21,   S(t′) = Φ⁻¹(Φ(t′) + π)
//! θ2     = φH + Φ(t′)                       intermediate orientation (world angle of body +x)
//! θ3     = φH + π − S(t′)                   planet orientation
//! D = a·e(φH),  A = 2a·e(φH),  B = A + l3·e(θ3 + γ)
//! ```
//!
//! Body frames (the JSON conventions of `design.json`): the sun's body frame is the world frame
//! (its curve is the design curve rotated by `φ_ref`); the planet's body frame is the design frame
//! (the planet is congruent to the sun, docs/math/chain.md §6.1); the intermediate's body frame is the one in which its
//! sun-side contact sits at `π − Φ(t′)`.

use crate::geometry::fourier::SunRatio;
use crate::geometry::pitch::{PitchCurve, PitchError};
use std::f64::consts::{PI, TAU};

/// Tolerance of the Φ⁻¹ solves, rad (docs/math/chain.md §13: 1e-13).
pub const INVERSE_TOL_RAD: f64 = 1e-13;

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
    /// Carrier arm length `l1 = 2a`, mm.
    #[must_use]
    pub fn l1_mm(&self) -> f64 {
        2.0 * self.a_mm
    }

    /// `S(t′)`, rad.
    #[must_use]
    pub fn half_turn_map(&self, t: f64) -> f64 {
        self.ratio.half_turn_map(t, INVERSE_TOL_RAD)
    }

    /// Planet relative rotation `ψ3(t′) = S(t′) − S(0)`, rad (docs/math/chain.md §2).
    #[must_use]
    pub fn psi3(&self, t: f64) -> f64 {
        self.half_turn_map(t) - self.half_turn_map(0.0)
    }

    /// Intermediate orientation θ2 at carrier angle φH, rad.
    #[must_use]
    pub fn intermediate_orientation(&self, phi_h: f64) -> f64 {
        phi_h + self.ratio.integral(phi_h - self.sun_phase_rad)
    }

    /// Planet orientation θ3 at carrier angle φH, rad.
    #[must_use]
    pub fn planet_orientation(&self, phi_h: f64) -> f64 {
        phi_h + PI - self.half_turn_map(phi_h - self.sun_phase_rad)
    }

    /// Needle direction `β = θ3 + γ`, rad.
    #[must_use]
    pub fn needle_direction(&self, phi_h: f64) -> f64 {
        self.planet_orientation(phi_h) + self.needle_angle_rad
    }

    /// Needle tip at carrier angle φH (rad), mm, relative to the carrier axis.
    #[must_use]
    pub fn tip(&self, phi_h: f64) -> [f64; 2] {
        let b = self.needle_direction(phi_h);
        let l1 = self.l1_mm();
        [
            l1 * phi_h.cos() + self.l3_mm * b.cos(),
            l1 * phi_h.sin() + self.l3_mm * b.sin(),
        ]
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
        let s = self
            .ratio
            .half_turn_map_uniform(-self.sun_phase_rad, n, INVERSE_TOL_RAD);
        s.iter()
            .enumerate()
            .map(|(k, s)| TAU * k as f64 / n as f64 + PI - s)
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
