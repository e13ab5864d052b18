//! The agronomic features of one carrier turn (definitions in [`crate::simulate`]) and the
//! distance of a traced path from its target, mm, deg, mm/s.

use super::{SimulateError, Simulation, TwoArms};
use crate::math::Point;
use serde::{Deserialize, Serialize};
use std::f64::consts::TAU;

/// Inputs of the agronomic features. (De)serialisable (a missing field takes its default, an unknown one is an error) and
/// built with `with_*`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
#[non_exhaustive]
pub struct FeatureOptions {
    /// Carrier speed, rpm. Default 300.
    pub rpm: f64,
    /// Forward speed of the machine, mm/s (≥ 0). Default 1000.
    pub forward_mm_s: f64,
    /// Planting depth d, mm: the soil surface is taken at `min y + d`. Default 30.
    pub planting_depth_mm: f64,
    /// Taking level y_t (mm), or the highest point (default `None`).
    pub take_level_mm: Option<f64>,
    /// Planting level y_p (mm), or the lowest point (default `None`).
    pub plant_level_mm: Option<f64>,
    /// Samples per turn. Default 3600.
    pub samples: usize,
}

crate::builder::with_fields!(FeatureOptions {
    with_rpm => rpm: f64,
    with_forward_mm_s => forward_mm_s: f64,
    with_planting_depth_mm => planting_depth_mm: f64,
    with_take_level_mm => take_level_mm: Option<f64>,
    with_plant_level_mm => plant_level_mm: Option<f64>,
    with_samples => samples: usize,
});

impl Default for FeatureOptions {
    fn default() -> Self {
        Self {
            rpm: 300.0,
            forward_mm_s: 1000.0,
            planting_depth_mm: 30.0,
            take_level_mm: None,
            plant_level_mm: None,
            samples: 3600,
        }
    }
}

impl FeatureOptions {
    /// Forward speed (mm/s) that gives plant spacing `s` mm with two arms: one plant per half turn.
    #[must_use]
    pub fn forward_for_spacing(spacing_mm: f64, rpm: f64) -> f64 {
        2.0 * spacing_mm * rpm / 60.0
    }
}

/// Agronomic features of a mechanism (definitions in [`crate::simulate`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Features {
    /// Trajectory height H, mm.
    pub height_mm: f64,
    /// Static trajectory bounding box `[xmin, xmax, ymin, ymax]`, mm.
    pub bbox_mm: [f64; 4],
    /// Largest and smallest tip distance from O, mm.
    pub rho_range_mm: [f64; 2],
    /// Carrier angle of the taking instant, deg (world).
    pub take_carrier_deg: f64,
    /// Needle angle at taking, deg.
    pub needle_angle_take_deg: f64,
    /// Carrier angle of the planting instant, deg (world).
    pub plant_carrier_deg: f64,
    /// Needle angle at planting, deg.
    pub needle_angle_plant_deg: f64,
    /// Taking angle α_T: the needle's angle to the horizontal at taking, deg, > 0 when the tip
    /// points below the horizontal ([`angle_to_horizontal`]; 取秧角).
    pub take_angle_deg: f64,
    /// Pushing (planting) angle α_P: the needle's angle to the horizontal at planting, deg
    /// ([`angle_to_horizontal`]; 推秧角). The angle difference is `α_P − α_T`.
    pub push_angle_deg: f64,
    /// Static loop width at the planting depth, mm.
    pub static_width_at_depth_mm: f64,
    /// Hole width (dynamic trajectory) at the planting depth, mm.
    pub hole_width_mm: f64,
    /// Max tip speed on the static path, mm/s.
    pub max_tip_speed_mm_s: f64,
    /// Tip speed on the static path at planting, mm/s.
    pub tip_speed_at_plant_mm_s: f64,
    /// Max tip speed on the dynamic path, mm/s.
    pub max_dynamic_tip_speed_mm_s: f64,
    /// Minimum distance between the two needles over a turn, mm.
    pub min_arm_clearance_mm: f64,
    /// Plant spacing for the given speeds (two plants per turn), mm.
    pub plant_spacing_mm: f64,
}

fn seg_seg(p1: Point, p2: Point, q1: Point, q2: Point) -> f64 {
    let pd = crate::math::polyline::seg_dist;
    let cross =
        |o: Point, a: Point, b: Point| (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
    let (d1, d2, d3, d4) = (
        cross(q1, q2, p1),
        cross(q1, q2, p2),
        cross(p1, p2, q1),
        cross(p1, p2, q2),
    );
    if d1 * d2 < 0.0 && d3 * d4 < 0.0 {
        return 0.0;
    }
    pd(p1, q1, q2)
        .min(pd(p2, q1, q2))
        .min(pd(q1, p1, p2))
        .min(pd(q2, p1, p2))
}

/// The angle of a needle of world direction `direction_rad` (planet axis → tip) to the
/// horizontal: `α = atan2(−u_y, |u_x|)`, `u = (cos, sin)` of the direction, rad in (−π/2, π/2],
/// positive when the tip points below the horizontal — the convention of the taking and pushing
/// angles in the transplanter literature (the needle's side, left or right, does not count).
///
/// ```
/// use ncgear::simulate::angle_to_horizontal;
/// let deg = |d: f64| angle_to_horizontal(d.to_radians()).to_degrees();
/// assert!((deg(-90.0) - 90.0).abs() < 1e-12); // straight down
/// assert!((deg(-104.0) - 76.0).abs() < 1e-12); // down and to the left
/// assert!((deg(20.0) + 20.0).abs() < 1e-12); // above the horizontal
/// ```
#[must_use]
pub fn angle_to_horizontal(direction_rad: f64) -> f64 {
    (-direction_rad.sin()).atan2(direction_rad.cos().abs())
}

/// Horizontal extent of the points below level `y`, or 0.
fn width_below(pts: &[Point], y: f64) -> f64 {
    let xs: Vec<f64> = pts.iter().filter(|p| p.y <= y).map(|p| p.x).collect();
    if xs.is_empty() {
        return 0.0;
    }
    xs.iter().fold(f64::MIN, |a, b| a.max(*b)) - xs.iter().fold(f64::MAX, |a, b| a.min(*b))
}

/// Computes the agronomic features.
pub fn features(sim: &Simulation, opts: &FeatureOptions) -> Result<Features, SimulateError> {
    let n = opts.samples.max(360);
    features_of_turn(
        &sim.turn(n),
        sim.assembly.center_mm,
        sim.assembly.direction,
        opts,
    )
}

/// The agronomic features of one carrier turn given as poses of both arms at `turn.len()` (≥ 8)
/// instants uniform in time (carrier angle `direction·2πk/n`, rad), e.g. a perturbed train
/// ([`crate::analysis::transplanter`]); `center_mm` is the carrier axis O (mm). `opts.samples` is
/// not used (the turn sets the sampling).
pub fn features_of_turn(
    turn: &[TwoArms],
    center_mm: Point,
    direction: i8,
    opts: &FeatureOptions,
) -> Result<Features, SimulateError> {
    let n = turn.len();
    check_options(n, opts)?;
    let angle_at = |f: f64| f64::from(direction.signum()) * TAU * f;
    let tips: Vec<Point> = turn.iter().map(|p| p.arm1.tip_mm).collect();
    let ext = Extremes::of(&tips);
    let (ymin, ymax) = (ext.bbox[2], ext.bbox[3]);
    let o = center_mm;
    let rho: Vec<f64> = tips.iter().map(|p| p.distance(o)).collect();
    let j_take = ext.level_crossing(&tips, opts.take_level_mm, ext.jlo, ext.jhi)?;
    let j_plant = ext.level_crossing(&tips, opts.plant_level_mm, ext.jhi, ext.jlo)?;
    let omega = TAU * opts.rpm / 60.0; // rad/s
    let v = opts.forward_mm_s;
    let speed = |j: usize| tip_speed(&tips, j, omega, None);
    let dyn_speed = |j: usize| tip_speed(&tips, j, omega, Some(v));
    let depth_level = ymin + opts.planting_depth_mm;
    let period = 60.0 / opts.rpm;
    let stroke = planting_stroke(&tips, ext.jlo, v, period);
    let deg = |x: f64| x.to_degrees();
    let carrier_deg = |j: usize| deg(angle_at(j as f64 / n as f64)).rem_euclid(360.0);
    Ok(Features {
        height_mm: ymax - ymin,
        bbox_mm: ext.bbox,
        rho_range_mm: [
            rho.iter().fold(f64::MIN, |a, b| a.max(*b)),
            rho.iter().fold(f64::MAX, |a, b| a.min(*b)),
        ],
        take_carrier_deg: carrier_deg(j_take),
        needle_angle_take_deg: deg(Simulation::needle_angle(&turn[j_take].arm1)),
        plant_carrier_deg: carrier_deg(j_plant),
        needle_angle_plant_deg: deg(Simulation::needle_angle(&turn[j_plant].arm1)),
        take_angle_deg: deg(angle_to_horizontal(Simulation::needle_angle(
            &turn[j_take].arm1,
        ))),
        push_angle_deg: deg(angle_to_horizontal(Simulation::needle_angle(
            &turn[j_plant].arm1,
        ))),
        static_width_at_depth_mm: width_below(&tips, depth_level),
        hole_width_mm: width_below(&stroke, depth_level),
        max_tip_speed_mm_s: (0..n).map(speed).fold(0.0, f64::max),
        tip_speed_at_plant_mm_s: speed(j_plant),
        max_dynamic_tip_speed_mm_s: (0..n).map(dyn_speed).fold(0.0, f64::max),
        min_arm_clearance_mm: arm_clearance(turn),
        plant_spacing_mm: v * period / 2.0,
    })
}

/// Refuses fewer than 8 poses per turn, a non-positive speed, a negative forward speed and a
/// non-positive planting depth.
fn check_options(n: usize, opts: &FeatureOptions) -> Result<(), SimulateError> {
    if n < 8 {
        return Err(SimulateError::BadOption {
            option: "samples",
            message: format!("{n} poses per turn; at least 8 are needed"),
        });
    }
    if !(opts.rpm.is_finite() && opts.rpm > 0.0) {
        return Err(SimulateError::BadOption {
            option: "rpm",
            message: format!("{} must be a positive carrier speed in rpm", opts.rpm),
        });
    }
    if !(opts.forward_mm_s.is_finite() && opts.forward_mm_s >= 0.0) {
        return Err(SimulateError::BadOption {
            option: "forward speed",
            message: "must be ≥ 0".into(),
        });
    }
    if !(opts.planting_depth_mm.is_finite() && opts.planting_depth_mm > 0.0) {
        return Err(SimulateError::BadOption {
            option: "depth",
            message: "must be a positive depth in mm".into(),
        });
    }
    Ok(())
}

/// The extent of the traced tip path.
struct Extremes {
    /// `[x_min, x_max, y_min, y_max]`, mm.
    bbox: [f64; 4],
    /// Index of the (first) lowest and highest tip position.
    jlo: usize,
    jhi: usize,
}

impl Extremes {
    fn of(tips: &[Point]) -> Self {
        let (mut xmin, mut xmax, mut ymin, mut ymax) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
        let (mut jlo, mut jhi) = (0, 0);
        for (j, p) in tips.iter().enumerate() {
            xmin = xmin.min(p.x);
            xmax = xmax.max(p.x);
            if p.y < ymin {
                ymin = p.y;
                jlo = j;
            }
            if p.y > ymax {
                ymax = p.y;
                jhi = j;
            }
        }
        Extremes {
            bbox: [xmin, xmax, ymin, ymax],
            jlo,
            jhi,
        }
    }

    /// The first index from `from` where the tip crosses `level` (mm) downwards, or `default`
    /// without a level; a level outside the path's height is refused.
    fn level_crossing(
        &self,
        tips: &[Point],
        level: Option<f64>,
        from: usize,
        default: usize,
    ) -> Result<usize, SimulateError> {
        let n = tips.len();
        let (ymin, ymax) = (self.bbox[2], self.bbox[3]);
        let Some(y) = level else { return Ok(default) };
        if !(y > ymin && y < ymax) {
            return Err(SimulateError::BadOption {
                option: "level",
                message: format!(
                    "level {y} mm is outside the trajectory's height [{ymin:.3}, {ymax:.3}] mm"
                ),
            });
        }
        (0..n)
            .map(|k| (from + k) % n)
            .find(|&j| tips[j].y >= y && tips[(j + 1) % n].y < y)
            .ok_or(SimulateError::BadOption {
                option: "level",
                message: format!("the tip never crosses y = {y} mm downwards"),
            })
    }
}

/// Tip speed (mm/s) at sample `j` by central differences at carrier speed `omega` (rad/s):
/// relative to the carrier axis, or, with a forward speed `v` (mm/s), relative to the soil.
fn tip_speed(tips: &[Point], j: usize, omega: f64, forward: Option<f64>) -> f64 {
    let n = tips.len();
    let dphi = TAU / n as f64;
    let (a, b) = (tips[(j + n - 1) % n], tips[(j + 1) % n]);
    match forward {
        None => b.distance(a) / (2.0 * dphi) * omega,
        Some(v) => {
            let vx = (b.x - a.x) / (2.0 * dphi) * omega - v;
            let vy = (b.y - a.y) / (2.0 * dphi) * omega;
            vx.hypot(vy)
        }
    }
}

/// One planting stroke of the dynamic path: half a turn centred on the lowest point `jlo`,
/// the tips shifted back by the machine's advance at forward speed `v` (mm/s) over the carrier
/// period `period` (s), mm.
fn planting_stroke(tips: &[Point], jlo: usize, v: f64, period: f64) -> Vec<Point> {
    let n = tips.len();
    (0..n)
        .map(|k| {
            let j = (jlo + n - n / 2 + k) % n;
            let steps = k as f64 - (n / 2) as f64;
            Point::new(tips[j].x - v * steps / n as f64 * period, tips[j].y)
        })
        .collect()
}

/// The smallest distance between the two needles (planet axis → tip segments) over the turn, mm.
fn arm_clearance(turn: &[TwoArms]) -> f64 {
    turn.iter()
        .map(|p| {
            seg_seg(
                p.arm1.planet_center_mm,
                p.arm1.tip_mm,
                p.arm2.planet_center_mm,
                p.arm2.tip_mm,
            )
        })
        .fold(f64::INFINITY, f64::min)
}

/// Distance from each point to a closed polyline, mm.
#[must_use]
pub fn deviation_along(points: &[Point], target: &[Point]) -> Vec<f64> {
    crate::math::polyline::distances_to_polyline(points, target)
}
