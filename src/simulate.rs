//! Forward kinematics of a designed transplanting mechanism from its design file, both arms, the
//! dynamic trajectory and the agronomic features (spec §2).
//!
//! The design file is read through the documented `design.json` conventions only (see
//! [`crate::geometry::assembly`]), so files written by other tools work too: `l3`, `center_distance`,
//! `needle_angle_deg`, `carrier`, `gears.{sun,intermediate,planet}.pitch` and the two
//! `angle_at_zero_deg`. Unknown fields are ignored (design.json carries many report fields).
//!
//! Arm 2 (gears 4, 5; needle 8) is arm 1 half a turn later: at carrier angle φH its pose is arm 1's
//! pose at `φH + π` (spec §2), so both needles trace the same static path.
//!
//! ## Agronomic features (definitions)
//!
//! With `y` up and the static trajectory of one arm sampled over one carrier turn:
//! - **trajectory height** `H = max y − min y` of the static trajectory, mm;
//! - **planting level** `y_p` (default: the lowest point) and **taking level** `y_t` (default: the
//!   highest point). The *planting instant* is the carrier angle of the lowest point, or, with a
//!   level, the first crossing of `y_p` downwards after the highest point; the *taking instant* is
//!   that of the highest point, or the first crossing of `y_t` downwards after the lowest point;
//! - **needle angle** at an instant: the direction of the needle from A to the tip, measured from the
//!   +x axis (travel direction of the tip at the bottom of a CCW loop is −x), degrees in (−180, 180];
//! - **hole width at planting depth d**: the horizontal extent (max x − min x) of the part of one
//!   arm's dynamic trajectory (one planting stroke) that lies below `min y + d`, mm;
//! - **static loop width at depth d**: the same on the static trajectory, mm;
//! - **tip speed**: `|dB/dt|` along the static path at the given carrier speed, mm/s (max and at the
//!   planting instant), and along the dynamic path (forward travel added);
//! - **minimum clearance between the two arms**: the smallest distance over one turn between the
//!   needle segments `A1B1` and `A2B2`, mm.

use crate::geometry::assembly::{Assembly, Pose, Rebuilt};
use crate::geometry::pitch::PitchCurve;
use serde::{Deserialize, Serialize};
use std::f64::consts::{PI, TAU};
use std::path::Path;

/// Why a design file cannot be simulated.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SimulateError {
    /// The file cannot be read.
    #[error("{file}: cannot read the design file: {message}")]
    Unreadable {
        /// File.
        file: String,
        /// Message.
        message: String,
    },
    /// JSON syntax or schema error.
    #[error(
        "{file}: {message}; a design file is what `ncgear design` writes (design.json, see the README)"
    )]
    BadJson {
        /// File.
        file: String,
        /// Message.
        message: String,
    },
    /// A field has an impossible value.
    #[error("{file}: field `{field}`: {message}")]
    BadField {
        /// File.
        file: String,
        /// Field path.
        field: String,
        /// What is wrong and expected.
        message: String,
    },
    /// A bad simulation option.
    #[error("option `{option}`: {message}")]
    BadOption {
        /// Option.
        option: &'static str,
        /// What is expected.
        message: String,
    },
}

/// The subset of `design.json` needed to assemble the train (mm, degrees).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct DesignFile {
    /// Needle length, mm.
    pub l3: f64,
    /// Centre distance a, mm.
    pub center_distance: f64,
    /// Needle angle γ, degrees.
    pub needle_angle_deg: f64,
    /// Carrier.
    pub carrier: CarrierFile,
    /// Gears.
    pub gears: GearsFile,
    /// Target trajectory points (mm), when the file carries them.
    #[serde(default)]
    pub target_points: Vec<[f64; 2]>,
    /// The `teeth` block of `ncgear design --module` (only `z` and `module_mm` are read).
    #[serde(default)]
    pub teeth: Option<TeethFile>,
}

/// The part of `design.json`'s `teeth` block needed to regenerate the toothed outlines.
#[derive(Debug, Clone, Copy, Serialize, Deserialize)]
pub struct TeethFile {
    /// Tooth count of each gear.
    pub z: u32,
    /// Module, mm.
    pub module_mm: f64,
}

/// `carrier` of a design file.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct CarrierFile {
    /// O, mm.
    pub center: [f64; 2],
    /// +1 CCW, −1 CW.
    pub direction: i8,
}

/// `gears` of a design file.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct GearsFile {
    /// Sun.
    pub sun: GearFile,
    /// Intermediate.
    pub intermediate: GearFile,
    /// Planet.
    pub planet: GearFile,
}

/// One gear of a design file.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct GearFile {
    /// `[[theta_deg, r_mm], ...]`, uniform in θ from 0.
    pub pitch: Vec<[f64; 2]>,
    /// Orientation at φH = 0, degrees.
    #[serde(default)]
    pub angle_at_zero_deg: Option<f64>,
}

impl DesignFile {
    /// Reads and validates a design file.
    pub fn read(path: &Path) -> Result<(Self, Assembly), SimulateError> {
        let file = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|e| SimulateError::Unreadable {
            file: file.clone(),
            message: e.to_string(),
        })?;
        Self::parse(&text, &file)
    }

    /// Parses and validates design-file text; `file` names it in messages.
    pub fn parse(text: &str, file: &str) -> Result<(Self, Assembly), SimulateError> {
        let d: DesignFile = serde_json::from_str(text).map_err(|e| SimulateError::BadJson {
            file: file.into(),
            message: e.to_string(),
        })?;
        let asm = d.assembly(file)?;
        Ok((d, asm))
    }

    /// Builds the [`Assembly`], checking every field.
    pub fn assembly(&self, file: &str) -> Result<Assembly, SimulateError> {
        let bad = |field: &str, message: String| SimulateError::BadField {
            file: file.into(),
            field: field.into(),
            message,
        };
        let pos = |v: f64, field: &str| {
            if v.is_finite() && v > 0.0 {
                Ok(v)
            } else {
                Err(bad(field, format!("{v} must be a positive length in mm")))
            }
        };
        let a = pos(self.center_distance, "center_distance")?;
        let l3 = pos(self.l3, "l3")?;
        if !self.needle_angle_deg.is_finite() {
            return Err(bad(
                "needle_angle_deg",
                "must be a finite angle in degrees".into(),
            ));
        }
        if !(self.carrier.direction == 1 || self.carrier.direction == -1) {
            return Err(bad(
                "carrier.direction",
                format!("{} must be 1 (CCW) or -1 (CW)", self.carrier.direction),
            ));
        }
        if !self.carrier.center.iter().all(|v| v.is_finite()) {
            return Err(bad(
                "carrier.center",
                "must be two finite numbers [x, y] in mm".into(),
            ));
        }
        let curve = |g: &GearFile, name: &str| -> Result<PitchCurve, SimulateError> {
            let field = format!("gears.{name}.pitch");
            let n = g.pitch.len();
            if n < 8 {
                return Err(bad(
                    &field,
                    format!(
                        "{n} samples; at least 8 (720 recommended) uniform [theta_deg, r_mm] pairs are needed"
                    ),
                ));
            }
            for (k, p) in g.pitch.iter().enumerate() {
                let expect = 360.0 * k as f64 / n as f64;
                if (p[0] - expect).abs() > 1e-6 * 360.0 {
                    return Err(bad(
                        &format!("{field}[{k}]"),
                        format!(
                            "theta_deg = {} but a uniform table from 0 needs {expect}",
                            p[0]
                        ),
                    ));
                }
                if !(p[1].is_finite() && p[1] > 0.0 && p[1] < a) {
                    return Err(bad(
                        &format!("{field}[{k}]"),
                        format!("r_mm = {} must be in (0, center_distance = {a})", p[1]),
                    ));
                }
            }
            PitchCurve::from_uniform_radii(g.pitch.iter().map(|p| p[1]).collect())
                .map_err(|e| bad(&field, e.to_string()))
        };
        let angle = |g: &GearFile, name: &str| {
            g.angle_at_zero_deg
                .filter(|v| v.is_finite())
                .map(f64::to_radians)
                .ok_or_else(|| {
                    bad(
                        &format!("gears.{name}.angle_at_zero_deg"),
                        "missing or not a finite angle in degrees".into(),
                    )
                })
        };
        Ok(Assembly {
            center_mm: self.carrier.center,
            direction: self.carrier.direction,
            a_mm: a,
            l3_mm: l3,
            needle_angle_rad: self.needle_angle_deg.to_radians(),
            sun: curve(&self.gears.sun, "sun")?,
            intermediate: curve(&self.gears.intermediate, "intermediate")?,
            intermediate_angle_at_zero_rad: angle(&self.gears.intermediate, "intermediate")?,
            planet: curve(&self.gears.planet, "planet")?,
            planet_angle_at_zero_rad: angle(&self.gears.planet, "planet")?,
        })
    }
}

/// The mechanism in motion: both arms.
#[derive(Debug, Clone)]
pub struct Simulation {
    rebuilt: Rebuilt,
    /// The assembled train.
    pub assembly: Assembly,
    /// Toothed outlines (body frames, mm) of the sun, intermediate and planet, drawn instead of
    /// the pitch curves when present (see [`Simulation::toothed`]).
    pub outlines: Option<[Vec<[f64; 2]>; 3]>,
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
        (p.tip_mm[1] - p.planet_center_mm[1]).atan2(p.tip_mm[0] - p.planet_center_mm[0])
    }

    /// Dynamic trajectory of both arms over `turns` carrier turns, `n` samples per turn:
    /// `x_dyn = x_static − v·t`, `t = turn fraction · 60/rpm` (s); `forward_mm_s` > 0 moves the
    /// machine towards +x (the path shifts towards −x).
    #[must_use]
    pub fn dynamic(
        &self,
        rpm: f64,
        forward_mm_s: f64,
        turns: usize,
        n: usize,
    ) -> [Vec<[f64; 2]>; 2] {
        let period = 60.0 / rpm;
        let mut out = [Vec::new(), Vec::new()];
        for k in 0..=turns * n {
            let f = k as f64 / n as f64;
            let p = self.pose(self.angle_at(f));
            let dx = forward_mm_s * f * period;
            out[0].push([p.arm1.tip_mm[0] - dx, p.arm1.tip_mm[1]]);
            out[1].push([p.arm2.tip_mm[0] - dx, p.arm2.tip_mm[1]]);
        }
        out
    }
}

/// Inputs of the agronomic features.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FeatureOptions {
    /// Carrier speed, rpm.
    pub rpm: f64,
    /// Forward speed of the machine, mm/s (≥ 0).
    pub forward_mm_s: f64,
    /// Planting depth d, mm: the soil surface is taken at `min y + d`.
    pub planting_depth_mm: f64,
    /// Taking level y_t (mm), or the highest point.
    pub take_level_mm: Option<f64>,
    /// Planting level y_p (mm), or the lowest point.
    pub plant_level_mm: Option<f64>,
    /// Samples per turn.
    pub samples: usize,
}

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

/// Agronomic features of a mechanism (see the module docs for the definitions).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
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

fn seg_seg(p1: [f64; 2], p2: [f64; 2], q1: [f64; 2], q2: [f64; 2]) -> f64 {
    let pd = crate::math::polyline::seg_dist;
    let cross = |o: [f64; 2], a: [f64; 2], b: [f64; 2]| {
        (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
    };
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

/// Horizontal extent of the points below level `y`, or 0.
fn width_below(pts: &[[f64; 2]], y: f64) -> f64 {
    let xs: Vec<f64> = pts.iter().filter(|p| p[1] <= y).map(|p| p[0]).collect();
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
    center_mm: [f64; 2],
    direction: i8,
    opts: &FeatureOptions,
) -> Result<Features, SimulateError> {
    let n = turn.len();
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
    let angle_at = |f: f64| f64::from(direction.signum()) * TAU * f;
    let tips: Vec<[f64; 2]> = turn.iter().map(|p| p.arm1.tip_mm).collect();
    let (mut xmin, mut xmax, mut ymin, mut ymax) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    let (mut jlo, mut jhi) = (0, 0);
    for (j, p) in tips.iter().enumerate() {
        xmin = xmin.min(p[0]);
        xmax = xmax.max(p[0]);
        if p[1] < ymin {
            ymin = p[1];
            jlo = j;
        }
        if p[1] > ymax {
            ymax = p[1];
            jhi = j;
        }
    }
    let o = center_mm;
    let rho: Vec<f64> = tips
        .iter()
        .map(|p| (p[0] - o[0]).hypot(p[1] - o[1]))
        .collect();
    let level_crossing =
        |level: Option<f64>, from: usize, default: usize| -> Result<usize, SimulateError> {
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
                .find(|&j| tips[j][1] >= y && tips[(j + 1) % n][1] < y)
                .ok_or(SimulateError::BadOption {
                    option: "level",
                    message: format!("the tip never crosses y = {y} mm downwards"),
                })
        };
    let j_take = level_crossing(opts.take_level_mm, jlo, jhi)?;
    let j_plant = level_crossing(opts.plant_level_mm, jhi, jlo)?;
    let omega = TAU * opts.rpm / 60.0; // rad/s
    let dphi = TAU / n as f64;
    let speed = |j: usize| {
        let (a, b) = (tips[(j + n - 1) % n], tips[(j + 1) % n]);
        (b[0] - a[0]).hypot(b[1] - a[1]) / (2.0 * dphi) * omega
    };
    let v = opts.forward_mm_s;
    let dyn_speed = |j: usize| {
        let (a, b) = (tips[(j + n - 1) % n], tips[(j + 1) % n]);
        let vx = (b[0] - a[0]) / (2.0 * dphi) * omega - v;
        let vy = (b[1] - a[1]) / (2.0 * dphi) * omega;
        vx.hypot(vy)
    };
    let depth_level = ymin + opts.planting_depth_mm;
    // One planting stroke of the dynamic path: half a turn centred on the lowest point.
    let period = 60.0 / opts.rpm;
    let stroke: Vec<[f64; 2]> = (0..n)
        .map(|k| {
            let j = (jlo + n - n / 2 + k) % n;
            let steps = k as f64 - (n / 2) as f64;
            [tips[j][0] - v * steps / n as f64 * period, tips[j][1]]
        })
        .collect();
    let clearance = turn
        .iter()
        .map(|p| {
            seg_seg(
                p.arm1.planet_center_mm,
                p.arm1.tip_mm,
                p.arm2.planet_center_mm,
                p.arm2.tip_mm,
            )
        })
        .fold(f64::INFINITY, f64::min);
    let deg = |x: f64| x.to_degrees();
    let carrier_deg = |j: usize| deg(angle_at(j as f64 / n as f64)).rem_euclid(360.0);
    Ok(Features {
        height_mm: ymax - ymin,
        bbox_mm: [xmin, xmax, ymin, ymax],
        rho_range_mm: [
            rho.iter().fold(f64::MIN, |a, b| a.max(*b)),
            rho.iter().fold(f64::MAX, |a, b| a.min(*b)),
        ],
        take_carrier_deg: carrier_deg(j_take),
        needle_angle_take_deg: deg(Simulation::needle_angle(&turn[j_take].arm1)),
        plant_carrier_deg: carrier_deg(j_plant),
        needle_angle_plant_deg: deg(Simulation::needle_angle(&turn[j_plant].arm1)),
        static_width_at_depth_mm: width_below(&tips, depth_level),
        hole_width_mm: width_below(&stroke, depth_level),
        max_tip_speed_mm_s: (0..n).map(speed).fold(0.0, f64::max),
        tip_speed_at_plant_mm_s: speed(j_plant),
        max_dynamic_tip_speed_mm_s: (0..n).map(dyn_speed).fold(0.0, f64::max),
        min_arm_clearance_mm: clearance,
        plant_spacing_mm: v * period / 2.0,
    })
}

/// Distance from each point to a closed polyline, mm.
#[must_use]
pub fn deviation_along(points: &[[f64; 2]], target: &[[f64; 2]]) -> Vec<f64> {
    crate::math::polyline::distances_to_polyline(points, target)
}
