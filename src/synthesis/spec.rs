//! The synthesis spec file (`ncgear synthesize SPEC.toml`): machine, key poses, target bands.
//! Files speak mm and degrees; every field's unit is in its name.

use super::dyad::Pose;
use serde::{Deserialize, Serialize};

/// A whole spec.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Spec {
    /// The machine (all optional).
    #[serde(default)]
    pub machine: Machine,
    /// The key poses, in travel order (`[[pose]]` tables).
    #[serde(default, rename = "pose")]
    pub poses: Vec<PoseSpec>,
    /// Agronomic target bands `[min, max]`, any subset.
    #[serde(default)]
    pub targets: Targets,
}

/// Machine data.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Machine {
    /// Carrier axis O, mm; omitted: solved for.
    pub center_mm: Option<[f64; 2]>,
    /// `"ccw"` or `"cw"`; omitted: the sense the poses run in.
    pub carrier: Option<String>,
    /// Carrier speed, r/min (default 300, as `ncgear simulate`).
    pub rpm: Option<f64>,
    /// Plant spacing, mm (two plants per carrier turn): sets the forward speed.
    pub spacing_mm: Option<f64>,
    /// Forward speed, mm/s (instead of `spacing_mm`).
    pub forward_speed_mm_s: Option<f64>,
    /// Planting depth below the lowest tip point, mm (default 30), for the hole width.
    pub depth_mm: Option<f64>,
}

/// One key pose as written in the file.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PoseSpec {
    /// Needle tip x, mm.
    pub x_mm: f64,
    /// Needle tip y, mm.
    pub y_mm: f64,
    /// World direction of the line planet axis → needle tip, degrees CCW from +x.
    pub needle_deg: f64,
    /// `"exact"` (default) or `"approximate"`.
    #[serde(default)]
    pub kind: Option<String>,
    /// Position tolerance of an approximate pose, mm.
    pub tol_mm: Option<f64>,
    /// Direction tolerance of an approximate pose, degrees.
    pub tol_deg: Option<f64>,
}

impl PoseSpec {
    /// The pose in library units (mm, rad).
    #[must_use]
    pub fn pose(&self) -> Pose {
        Pose {
            tip_mm: [self.x_mm, self.y_mm],
            needle_rad: self.needle_deg.to_radians(),
        }
    }

    /// Whether the pose is approximate (its tolerances then apply).
    #[must_use]
    pub fn approximate(&self) -> bool {
        self.kind.as_deref() == Some("approximate")
    }
}

/// Target bands `[min, max]` of the agronomic indices (definitions in [`crate::simulate`]).
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Targets {
    /// Needle angle at taking, degrees.
    pub take_angle_deg: Option<[f64; 2]>,
    /// Needle angle at pushing (planting), degrees.
    pub push_angle_deg: Option<[f64; 2]>,
    /// Pushing minus taking angle, degrees.
    pub angle_difference_deg: Option<[f64; 2]>,
    /// Trajectory height, mm.
    pub height_mm: Option<[f64; 2]>,
    /// Hole width at the planting depth, mm.
    pub hole_width_mm: Option<[f64; 2]>,
    /// Smallest distance between the two arms over a turn, mm.
    pub arm_clearance_mm: Option<[f64; 2]>,
}

impl Targets {
    /// `(name, band)` of every band given.
    #[must_use]
    pub fn bands(&self) -> Vec<(&'static str, [f64; 2])> {
        [
            ("take_angle_deg", self.take_angle_deg),
            ("push_angle_deg", self.push_angle_deg),
            ("angle_difference_deg", self.angle_difference_deg),
            ("height_mm", self.height_mm),
            ("hole_width_mm", self.hole_width_mm),
            ("arm_clearance_mm", self.arm_clearance_mm),
        ]
        .into_iter()
        .filter_map(|(n, b)| Some((n, b?)))
        .collect()
    }
}
