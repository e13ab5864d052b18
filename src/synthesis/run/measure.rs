//! A candidate train on its gears: its traced path through the design chain, then the poses and
//! the target bands measured on the gears it got.

use super::TRACE_POINTS;
use crate::design::trajectory::Trajectory;
use crate::design::{Design, DesignOptions, design};
use crate::geometry::mechanism::Mechanism;
use crate::math::Point;
use crate::simulate::{FeatureOptions, Features, Simulation, features};
use crate::synthesis::dyad::{Dyad, Pose};
use crate::synthesis::report::{Candidate, PoseResult, TargetResult};
use crate::synthesis::spec::Spec;
use crate::synthesis::targets::index_value;
use std::f64::consts::{PI, TAU};

/// The train `m` (solved frame) on arm `dyad` with carrier sense `direction`: its traced path
/// ([`TRACE_POINTS`] carrier angles) through the design chain, which makes its gears within the
/// gear limits; the poses and the target bands measured on those gears.
pub(super) fn on_gears(
    m: &Mechanism,
    dyad: Dyad,
    direction: i8,
    poses: &[Pose],
    spec: &Spec,
    fopts: &FeatureOptions,
    opts: &DesignOptions,
) -> (Candidate, Option<Designed>) {
    let s = f64::from(direction);
    let o = dyad.center_mm;
    let points: Vec<Point> = (0..TRACE_POINTS)
        .map(|j| {
            let b = m.tip(TAU * j as f64 / TRACE_POINTS as f64);
            Point::new(o.x + b.x, o.y + s * b.y)
        })
        .collect();
    let mut o_opts = opts.clone();
    o_opts.center_mm = o;
    let d = match Trajectory::from_points(points)
        .map_err(|e| e.to_string())
        .and_then(|t| design(&t, &o_opts).map_err(|e| e.to_string()))
    {
        Ok(d) => d,
        Err(e) => return (Candidate::refused(dyad, e), None),
    };
    let sim = Simulation::new(d.assembly.clone());
    let measured: Vec<PoseResult> = poses.iter().map(|p| on_design(&sim, p)).collect();
    // Bands that cannot be evaluated (no planting level on this path) are said so, not dropped.
    let targets = features(&sim, fopts)
        .map(|f| target_results(spec, &f))
        .map_err(|e| e.to_string());
    let cand = Candidate {
        dyad,
        max_pose_error_mm: Some(measured.iter().map(|p| p.error_mm).fold(0.0, f64::max)),
        max_pose_error_deg: Some(
            measured
                .iter()
                .map(|p| p.error_deg.abs())
                .fold(0.0, f64::max),
        ),
        targets_missed: targets.as_ref().map_or(spec.targets.bands().len(), |t| {
            t.iter().filter(|t| t.margin < 0.0).count()
        }),
        refused: None,
    };
    (cand, Some((d, direction, measured, targets)))
}

/// A candidate's design: the design, its carrier sense, the poses and bands measured on it.
pub(super) type Designed = (
    Design,
    i8,
    Vec<PoseResult>,
    Result<Vec<TargetResult>, String>,
);

/// `p` on the designed train: the closest tip over a turn (3600 instants, then golden-section
/// refinement) and the needle-direction error there.
fn on_design(sim: &Simulation, p: &Pose) -> PoseResult {
    let at = |phi: f64| {
        let a = sim.pose(phi).arm1;
        let d = a.tip_mm.distance(p.tip_mm);
        (d, a)
    };
    let n = 3600;
    let k = (0..n)
        .min_by(|&i, &j| {
            at(sim.angle_at(i as f64 / n as f64))
                .0
                .total_cmp(&at(sim.angle_at(j as f64 / n as f64)).0)
        })
        .unwrap_or(0);
    let (mut lo, mut hi) = (
        sim.angle_at((k as f64 - 1.0) / n as f64),
        sim.angle_at((k as f64 + 1.0) / n as f64),
    );
    let g = 0.5 * (5f64.sqrt() - 1.0);
    for _ in 0..60 {
        let (m1, m2) = (hi - g * (hi - lo), lo + g * (hi - lo));
        if at(m1).0 < at(m2).0 {
            hi = m2;
        } else {
            lo = m1;
        }
    }
    let phi = 0.5 * (lo + hi);
    let (d, a) = at(phi);
    let dir = (a.tip_mm - a.planet_center_mm).atan2();
    PoseResult {
        tip_mm: p.tip_mm,
        needle_deg: p.needle_rad.to_degrees(),
        carrier_deg: phi.to_degrees().rem_euclid(360.0),
        error_mm: d,
        error_deg: ((dir - p.needle_rad + PI).rem_euclid(TAU) - PI).to_degrees(),
    }
}

/// Each band of `spec` against the design's features.
fn target_results(spec: &Spec, f: &Features) -> Vec<TargetResult> {
    spec.targets
        .bands()
        .into_iter()
        .map(|(name, band)| {
            let value = index_value(name, f);
            TargetResult {
                index: name.into(),
                band,
                value,
                margin: (value - band[0]).min(band[1] - value),
            }
        })
        .collect()
}
