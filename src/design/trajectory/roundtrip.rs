//! The round trip: how far a train rebuilt from its tables traces from the target points, the
//! tip passing each point at the carrier angle the design gives it (check C12's measure, for the
//! design and for its toothed train alike).

use crate::design::trajectory::ClosedSpline;
use crate::geometry::assembly::Rebuilt;
use crate::math::Point;
use crate::math::polyline::hausdorff_mm;
use rayon::prelude::*;
use std::f64::consts::TAU;

/// How far a train rebuilt from its tables (`rebuilt`, a toothed train's among them) traces from
/// `points`, measured as check C12 measures the design: its largest synchronous deviation at the
/// carrier angles `angles` (rad, solved frame) at which the designed tip passes the points, and
/// its Hausdorff distance to the target curve read between the points in those angles (`m` tip
/// positions over the turn), both mm.
pub(crate) fn deviations_as_designed(
    rebuilt: &Rebuilt,
    points: &[Point],
    angles: &[f64],
    m: usize,
) -> (f64, f64) {
    let sign = rebuilt.sign();
    let (max, (traced, _)) = rayon::join(
        || {
            tip_deviations(rebuilt, points, angles, sign)
                .into_iter()
                .fold(0.0, f64::max)
        },
        || trace(rebuilt, m, sign),
    );
    (max, target_hausdorff_mm(&traced, points, angles, 2 * m))
}

/// The tip path and the largest mesh errors `[sun, planet]` (mm) of the train rebuilt from the
/// tables, at `m` carrier angles (sense `sign`).
pub(crate) fn trace(rebuilt: &Rebuilt, m: usize, sign: f64) -> (Vec<Point>, [f64; 2]) {
    // The poses are independent: evaluated in parallel (same values in the same order).
    let poses: Vec<_> = (0..m)
        .into_par_iter()
        .map(|k| rebuilt.pose(sign * TAU * k as f64 / m as f64))
        .collect();
    let mut mesh: [f64; 2] = [0.0, 0.0];
    for pose in &poses {
        mesh[0] = mesh[0].max(pose.sun_mesh_error_mm.abs());
        mesh[1] = mesh[1].max(pose.planet_mesh_error_mm.abs());
    }
    (poses.iter().map(|p| p.tip_mm).collect(), mesh)
}

/// Synchronous deviation (mm) at every target point, at the carrier angle the tip passes it.
pub(crate) fn tip_deviations(
    rebuilt: &Rebuilt,
    points: &[Point],
    angles: &[f64],
    sign: f64,
) -> Vec<f64> {
    points
        .par_iter()
        .zip(angles)
        .map(|(p, &phi)| {
            let tip = rebuilt.pose(sign * phi).tip_mm;
            (tip - *p).norm()
        })
        .collect()
}
/// Hausdorff distance (mm) between the traced path and the target curve through the points,
/// sampled at `n` points. The target is known at its points only; between them it is read as the
/// closer of two smooth interpolations:
/// - a periodic cubic spline in the carrier angle at which the designed tip passes each point
///   (the mechanism's own time, in which the tip moves smoothly even round a sharp, coarsely
///   sampled nose), when those angles advance monotonically;
/// - the chord-length spline of docs/math/chain.md §3.1, which does not depend on the design:
///   where the tip of a train that cannot trace the target passes its points unevenly in time, a
///   spline in that time swings between them, and a path that follows the drawn curve would be
///   charged for the swing (docs/performance.md, "The round trip's target curve").
pub(crate) fn target_hausdorff_mm(
    traced: &[Point],
    points: &[Point],
    angles: &[f64],
    n: usize,
) -> f64 {
    let chord = || {
        let spline = ClosedSpline::through(points);
        let curve: Vec<Point> = (0..n)
            .map(|k| spline.point(spline.period() * k as f64 / n as f64))
            .collect();
        hausdorff_mm(traced, &curve)
    };
    let timed = || carrier_angle_curve(points, angles, n).map(|c| hausdorff_mm(traced, &c));
    let (h_chord, h_timed) = rayon::join(chord, timed);
    h_timed.map_or(h_chord, |h| h.min(h_chord))
}

/// `n` points of the periodic cubic spline through the points in the carrier angles at which the
/// tip passes them, or `None` when those angles do not advance monotonically.
fn carrier_angle_curve(points: &[Point], angles: &[f64], n: usize) -> Option<Vec<Point>> {
    let mut knots = Vec::with_capacity(angles.len());
    let mut acc = 0.0;
    for (j, &a) in angles.iter().enumerate() {
        if j > 0 {
            acc += (a - angles[j - 1]).rem_euclid(TAU);
        }
        knots.push(acc);
    }
    let closing = angles
        .last()
        .map_or(0.0, |&a| (angles[0] - a).rem_euclid(TAU));
    let monotone = knots.windows(2).all(|w| w[1] > w[0])
        && closing > 0.0
        && (acc + closing - TAU).abs() < 1e-6;
    if !monotone {
        return None;
    }
    let axis = |coordinate: fn(&Point) -> f64| {
        crate::math::periodic::PeriodicSpline::new(
            knots.clone(),
            points.iter().map(coordinate).collect(),
            TAU,
        )
        .ok()
    };
    let (x, y) = (axis(|p| p.x)?, axis(|p| p.y)?);
    Some(
        (0..n)
            .map(|k| {
                let t = TAU * k as f64 / n as f64;
                Point::new(x.value(t), y.value(t))
            })
            .collect(),
    )
}
