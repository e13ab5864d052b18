//! The designer's edit both the wall-clock and the instruction benches time: a target moved by a
//! Gaussian bump of `amp_mm` (mm, peak) over about ten points around point 90, along (0.8, 0.6).

use ncgear::design::trajectory::Trajectory;
use ncgear::math::Point;

/// `t` moved by the bump.
pub fn bumped(t: &Trajectory, amp_mm: f64) -> Trajectory {
    let moved: Vec<Point> = t
        .points()
        .iter()
        .enumerate()
        .map(|(k, p)| {
            let w = amp_mm * (-((k as f64 - 90.0) / 10.0).powi(2)).exp();
            Point::new(p.x + 0.8 * w, p.y + 0.6 * w)
        })
        .collect();
    Trajectory::from_points(moved).expect("a bump keeps the points a trajectory")
}
