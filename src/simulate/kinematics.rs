//! Forward kinematics of both arms: poses over a carrier turn and the dynamic trajectory (the
//! static path shifted by the forward travel), mm and rad.

use crate::geometry::assembly::{Assembly, Pose, Rebuilt};
use crate::math::Point;
use std::f64::consts::{PI, TAU};

/// The mechanism in motion: both arms.
#[derive(Debug, Clone)]
pub struct Simulation {
    rebuilt: Rebuilt,
    /// The assembled train.
    pub assembly: Assembly,
    /// Toothed outlines (body frames, mm) of the sun, intermediate and planet, drawn instead of
    /// the pitch curves when present (see [`Simulation::toothed`]).
    pub outlines: Option<[Vec<Point>; 3]>,
}

/// Poses of both arms at one carrier angle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TwoArms {
    /// Arm 1 (gears 2, 3; needle 6).
    pub arm1: Pose,
    /// Arm 2 (gears 4, 5; needle 8), half a turn behind.
    pub arm2: Pose,
}

impl Simulation {
    /// Sets up the kinematics of an assembly.
    #[must_use]
    pub fn new(assembly: Assembly) -> Self {
        Self {
            rebuilt: assembly.rebuild(),
            assembly,
            outlines: None,
        }
    }

    /// The toothed train of [`crate::design::train::tooth_train`]: its (scaled) assembly, with the gear
    /// outlines drawn by the animation (simplified to a chord tolerance of 0.01·m).
    #[must_use]
    pub fn toothed(train: &crate::design::train::ToothedTrain) -> Self {
        let tol = 0.01 * train.report.module_mm;
        let simple =
            |o: &crate::teeth::Outline| crate::math::polyline::simplify_closed(&o.points_mm, tol);
        Self {
            outlines: Some([
                simple(&train.sun),
                simple(&train.intermediate),
                simple(&train.planet),
            ]),
            ..Self::new(train.assembly.clone())
        }
    }

    /// Both arms at carrier angle φH (rad, world; the carrier advances by `direction·dφ`).
    #[must_use]
    pub fn pose(&self, phi_h: f64) -> TwoArms {
        TwoArms {
            arm1: self.rebuilt.pose(phi_h),
            arm2: self.rebuilt.pose(phi_h + PI),
        }
    }

    /// Carrier angle (rad) after a fraction `f` of a turn in the direction of motion.
    #[must_use]
    pub fn angle_at(&self, f: f64) -> f64 {
        f64::from(self.assembly.direction) * TAU * f
    }

    /// Both arms at `n` instants over one turn (in time order).
    #[must_use]
    pub fn turn(&self, n: usize) -> Vec<TwoArms> {
        (0..n)
            .map(|k| self.pose(self.angle_at(k as f64 / n as f64)))
            .collect()
    }

    /// Needle direction (rad) of a pose: from A to B.
    #[must_use]
    pub fn needle_angle(p: &Pose) -> f64 {
        (p.tip_mm - p.planet_center_mm).atan2()
    }

    /// Dynamic trajectory of both arms over `turns` carrier turns, `n` samples per turn:
    /// `x_dyn = x_static − v·t`, `t = turn fraction · 60/rpm` (s); `forward_mm_s` > 0 moves the
    /// machine towards +x (the path shifts towards −x).
    #[must_use]
    pub fn dynamic(&self, rpm: f64, forward_mm_s: f64, turns: usize, n: usize) -> [Vec<Point>; 2] {
        let period = 60.0 / rpm;
        let mut out = [Vec::new(), Vec::new()];
        for k in 0..=turns * n {
            let f = k as f64 / n as f64;
            let p = self.pose(self.angle_at(f));
            let dx = forward_mm_s * f * period;
            out[0].push(Point::new(p.arm1.tip_mm.x - dx, p.arm1.tip_mm.y));
            out[1].push(Point::new(p.arm2.tip_mm.x - dx, p.arm2.tip_mm.y));
        }
        out
    }
}
