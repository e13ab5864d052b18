//! The design's static needle-tip path by carrier angle, the reference of a comparison: the
//! tip `B(φ)` and its rate `dB/dφ` from periodic cubic splines through the rebuilt train's poses
//! at 4096 carrier angles (docs/math/chain.md §2), and the planet centre `A(φ) = O + l1·e(φ)`.
//! World frame, mm and rad.

use crate::geometry::assembly::{Pose, Rebuilt};
use crate::math::Point;
use crate::math::periodic::PeriodicSpline;
use std::f64::consts::TAU;

/// Samples of the splines over a turn: the interpolation error (`≈ h⁴·|B⁗|/384`,
/// `h = 2π/4096`) is far below a micrometre for a transplanter's path.
pub const SAMPLES: usize = 4096;

/// The design path `B(φ)` (world carrier angle φ, rad; mm).
#[derive(Debug, Clone)]
pub struct DesignPath {
    x: PeriodicSpline,
    y: PeriodicSpline,
    /// Carrier axis O, mm.
    pub center_mm: Point,
    /// Carrier arm `l1 = |OA|`, mm.
    pub l1_mm: f64,
    /// +1 CCW, −1 CW: the sense φ advances in time.
    pub direction: i8,
}

impl DesignPath {
    /// The path of a rebuilt train.
    #[must_use]
    pub fn new(rebuilt: &Rebuilt) -> Self {
        let tips: Vec<Point> = (0..SAMPLES)
            .map(|k| rebuilt.pose(TAU * k as f64 / SAMPLES as f64).tip_mm)
            .collect();
        let asm = rebuilt.assembly();
        Self::through(
            &tips,
            asm.center_mm,
            rebuilt.l1_mm(),
            asm.direction.signum(),
        )
    }

    /// The path of this train's tip moved to `tips_mm`, tip points at `n` instants of a turn
    /// evenly spaced in travel from carrier angle 0 (sample `k` at carrier angle
    /// `direction·2πk/n`; at least 8), e.g. a dynamic run's settled turn
    /// ([`crate::analysis::dynamics::rotor::RotorReport::tip_mm`]); the carrier axis, arm and
    /// sense are this path's. `None` with fewer than 8 samples.
    #[must_use]
    pub fn moved_to(&self, tips_mm: &[Point]) -> Option<Self> {
        let n = tips_mm.len();
        if n < 8 {
            return None;
        }
        // Sample j of the spline at carrier angle 2πj/n is travel sample (±j mod n).
        let tips: Vec<Point> = (0..n)
            .map(|j| tips_mm[if self.direction < 0 { (n - j) % n } else { j }])
            .collect();
        Some(Self::through(
            &tips,
            self.center_mm,
            self.l1_mm,
            self.direction,
        ))
    }

    /// Periodic splines through tips at `n` uniform carrier angles over `[0, 2π)`.
    fn through(tips: &[Point], center_mm: Point, l1_mm: f64, direction: i8) -> Self {
        let spline =
            |v: Vec<f64>| PeriodicSpline::uniform(0.0, v, TAU).expect("at least 8 samples");
        Self {
            x: spline(tips.iter().map(|p| p.x).collect()),
            y: spline(tips.iter().map(|p| p.y).collect()),
            center_mm,
            l1_mm,
            direction,
        }
    }

    /// Tip `B(φ)` and its rate `dB/dφ` (mm, mm/rad).
    #[must_use]
    #[inline]
    pub fn tip(&self, phi: f64) -> (Point, Point) {
        let (x, y) = (self.x.eval3(phi), self.y.eval3(phi));
        (Point::new(x[0], y[0]), Point::new(x[1], y[1]))
    }

    /// Planet centre `A(φ) = O + l1·e(φ)`, mm.
    #[must_use]
    pub fn planet_center(&self, phi: f64) -> Point {
        self.center_mm + Point::unit(phi) * self.l1_mm
    }

    /// Needle direction at φ: the angle of `B − A`, rad.
    #[must_use]
    pub fn needle_angle(&self, phi: f64) -> f64 {
        (self.tip(phi).0 - self.planet_center(phi)).atan2()
    }

    /// Tip points at `n` carrier angles over one turn in the direction of travel.
    #[must_use]
    pub fn turn(&self, n: usize) -> Vec<Point> {
        (0..n).map(|k| self.tip(self.angle_at(k, n)).0).collect()
    }

    /// The carrier angle of sample `k` of `n` over a turn in travel order, rad.
    #[must_use]
    pub fn angle_at(&self, k: usize, n: usize) -> f64 {
        f64::from(self.direction) * TAU * k as f64 / n as f64
    }
}

/// A pose with only what the agronomic features read: the planet centre `a_mm` and tip `b_mm`
/// at carrier angle `phi` (rad).
#[must_use]
pub fn feature_pose(phi: f64, a_mm: Point, b_mm: Point) -> Pose {
    Pose {
        phi_h_rad: phi,
        intermediate_center_mm: a_mm,
        planet_center_mm: a_mm,
        intermediate_angle_rad: 0.0,
        planet_angle_rad: 0.0,
        tip_mm: b_mm,
        sun_mesh_error_mm: 0.0,
        planet_mesh_error_mm: 0.0,
    }
}
