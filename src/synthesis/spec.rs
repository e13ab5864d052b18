//! The synthesis spec file (`ncgear synthesize SPEC.toml`): machine, key poses, target bands, and
//! its fields checked against their ranges before any work.
//! Files speak mm and degrees; every field's unit is in its name.

use super::dyad::Pose;
use super::report::SynthesisError;
use super::timing::POSE_TOL_RAD;
use crate::bounds::{Span, number};
use crate::math::Point;
use crate::simulate::FeatureOptions;
use serde::{Deserialize, Serialize};

/// A whole spec.
#[derive(Debug, Clone, Default, Serialize, Deserialize, schemars::JsonSchema)]
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
#[derive(Debug, Clone, Default, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Machine {
    /// Carrier axis O, mm; omitted: solved for.
    pub center_mm: Option<Point>,
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
    /// Targets only: the range `[min, max]` of the carrier arm `l1` searched, mm (default
    /// [`super::targets::DEFAULT_L1_MM`]).
    pub l1_mm: Option<[f64; 2]>,
    /// Targets only: the range `[min, max]` of the needle `l3` searched, mm (default
    /// [`super::targets::DEFAULT_L3_MM`]).
    pub l3_mm: Option<[f64; 2]>,
}

/// One key pose as written in the file.
#[derive(Debug, Clone, Serialize, Deserialize, schemars::JsonSchema)]
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
            tip_mm: Point::new(self.x_mm, self.y_mm),
            needle_rad: self.needle_deg.to_radians(),
        }
    }

    /// Position tolerance, mm: `tol_mm` of an approximate pose (default 0.5), 0 for an exact one.
    #[must_use]
    pub fn position_tolerance_mm(&self) -> f64 {
        if self.approximate() {
            self.tol_mm.unwrap_or(0.5)
        } else {
            0.0
        }
    }

    /// Direction tolerance, degrees: `tol_deg` of an approximate pose (default 0.5), 0 for an
    /// exact one.
    #[must_use]
    pub fn direction_tolerance_deg(&self) -> f64 {
        if self.approximate() {
            self.tol_deg.unwrap_or(0.5)
        } else {
            0.0
        }
    }

    /// Whether the pose is approximate (its tolerances then apply).
    #[must_use]
    pub fn approximate(&self) -> bool {
        self.kind.as_deref() == Some("approximate")
    }
}

/// Target bands `[min, max]` of the agronomic indices (definitions in [`crate::simulate`]).
#[derive(Debug, Clone, Default, Serialize, Deserialize, schemars::JsonSchema)]
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

/// The poses, their direction tolerances (rad), the sense asked for and the feature options.
pub(super) type Checked = (Vec<Pose>, Vec<f64>, Option<i8>, FeatureOptions);

/// Builds the error for a field out of its range.
fn bad(field: &str, value: String, expected: &str) -> SynthesisError {
    SynthesisError::BadField {
        field: field.into(),
        value,
        expected: expected.into(),
    }
}

/// The spec's fields checked against their ranges, naming the first out of range.
pub(super) fn checked(spec: &Spec) -> Result<Checked, SynthesisError> {
    if spec.poses.is_empty() && spec.targets.bands().is_empty() {
        return Err(bad(
            "pose",
            "none".into(),
            "[[pose]] tables (at least three; two with machine.center_mm), or [targets] bands to synthesise from alone",
        ));
    }
    check_numbers(spec)?;
    let tol = pose_tolerances(spec)?;
    let sense = match spec.machine.carrier.as_deref() {
        None => None,
        Some("ccw") => Some(1),
        Some("cw") => Some(-1),
        Some(v) => {
            return Err(bad(
                "machine.carrier",
                format!("\"{v}\""),
                "\"ccw\" or \"cw\"",
            ));
        }
    };
    let f = feature_options(spec)?;
    check_bands(&spec.targets)?;
    check_search_box(spec)?;
    Ok((spec.poses.iter().map(|p| p.pose()).collect(), tol, sense, f))
}

/// Each pose's direction tolerance, rad: exact poses [`POSE_TOL_RAD`], approximate ones their
/// own (with a positive position tolerance).
/// A coordinate of a pose or of the carrier centre, mm: 100 m from the origin.
pub const POSITION_MM: Span = Span::symmetric(1e5);
/// An angle of a pose, degrees: ten turns either way.
pub const ANGLE_DEG: Span = Span::symmetric(3600.0);
/// A length of the machine (the ends of the search boxes, the tolerance of an approximate pose,
/// the planting depth), mm: a planting arm is tens to hundreds of mm.
pub const LENGTH_MM: Span = Span::symmetric(5000.0);
/// An end of a target band, mm or degrees: ±1e9 stands for no limit (the band is then checked
/// against the index's own range).
pub const BAND_END: Span = Span::symmetric(1e9);
/// The carrier speed, r/min (the range of a loads scene's `operation.carrier_rpm`).
pub const RPM: Span = Span::positive(crate::loads::scene::MAX_CARRIER_RPM);
/// The forward speed, mm/s: 10 m/s, ten times a transplanter's.
pub const FORWARD_MM_S: Span = Span::closed(0.0, 1e4);

/// `v` finite and within `span`, or the error naming `field`.
fn ranged(field: &str, v: f64, span: Span, what: &str) -> Result<f64, SynthesisError> {
    span.check(v, what).map_err(|m| SynthesisError::BadField {
        field: field.into(),
        value: number(v),
        expected: m,
    })
}

/// Every number of the spec finite and within its range, before any other check.
fn check_numbers(spec: &Spec) -> Result<(), SynthesisError> {
    let m = &spec.machine;
    let coordinate = "a coordinate in mm (100 m from the origin at most)";
    let angle = "an angle in degrees (ten turns either way at most)";
    let length = "a length in mm (5 m at most)";
    if let Some(c) = m.center_mm {
        ranged("machine.center_mm.x", c.x, POSITION_MM, coordinate)?;
        ranged("machine.center_mm.y", c.y, POSITION_MM, coordinate)?;
    }
    for (field, v, span, what) in [
        ("machine.rpm", m.rpm, RPM, "a carrier speed in r/min"),
        ("machine.spacing_mm", m.spacing_mm, LENGTH_MM, length),
        (
            "machine.forward_speed_mm_s",
            m.forward_speed_mm_s,
            FORWARD_MM_S,
            "a forward speed in mm/s",
        ),
        ("machine.depth_mm", m.depth_mm, LENGTH_MM, length),
    ] {
        if let Some(v) = v {
            ranged(field, v, span, what)?;
        }
    }
    for (field, b) in [("machine.l1_mm", m.l1_mm), ("machine.l3_mm", m.l3_mm)] {
        for (k, v) in b.iter().flatten().enumerate() {
            ranged(&format!("{field}[{k}]"), *v, LENGTH_MM, length)?;
        }
    }
    for (k, p) in spec.poses.iter().enumerate() {
        ranged(&format!("pose[{k}].x_mm"), p.x_mm, POSITION_MM, coordinate)?;
        ranged(&format!("pose[{k}].y_mm"), p.y_mm, POSITION_MM, coordinate)?;
        ranged(
            &format!("pose[{k}].needle_deg"),
            p.needle_deg,
            ANGLE_DEG,
            angle,
        )?;
        if let Some(t) = p.tol_mm {
            ranged(&format!("pose[{k}].tol_mm"), t, LENGTH_MM, length)?;
        }
        if let Some(t) = p.tol_deg {
            ranged(&format!("pose[{k}].tol_deg"), t, ANGLE_DEG, angle)?;
        }
    }
    for (name, b) in spec.targets.bands() {
        for (k, v) in b.iter().enumerate() {
            ranged(
                &format!("targets.{name}[{k}]"),
                *v,
                BAND_END,
                "an end of a band, mm or degrees (1e9 stands for no limit)",
            )?;
        }
    }
    Ok(())
}

fn pose_tolerances(spec: &Spec) -> Result<Vec<f64>, SynthesisError> {
    let mut tol = Vec::new();
    for (k, p) in spec.poses.iter().enumerate() {
        match p.kind.as_deref() {
            None | Some("exact") => tol.push(POSE_TOL_RAD),
            Some("approximate") => {
                let d = p.position_tolerance_mm();
                if !(d > 0.0 && d.is_finite()) {
                    return Err(bad(
                        &format!("pose[{k}].tol_mm"),
                        d.to_string(),
                        "a positive length in mm",
                    ));
                }
                let t = p.direction_tolerance_deg();
                if !(t > 0.0 && t.is_finite()) {
                    return Err(bad(
                        &format!("pose[{k}].tol_deg"),
                        t.to_string(),
                        "a positive angle in degrees",
                    ));
                }
                tol.push(t.to_radians());
            }
            Some(v) => {
                return Err(bad(
                    &format!("pose[{k}].kind"),
                    format!("\"{v}\""),
                    "\"exact\" or \"approximate\"",
                ));
            }
        }
    }
    Ok(tol)
}

/// The planting features' options from the machine table: speed, spacing or forward speed,
/// depth.
fn feature_options(spec: &Spec) -> Result<FeatureOptions, SynthesisError> {
    let mut f = FeatureOptions::default();
    if let Some(r) = spec.machine.rpm {
        if !(r > 0.0 && r.is_finite()) {
            return Err(bad(
                "machine.rpm",
                r.to_string(),
                "a positive speed in r/min",
            ));
        }
        f.rpm = r;
    }
    match (spec.machine.spacing_mm, spec.machine.forward_speed_mm_s) {
        (Some(_), Some(_)) => {
            return Err(bad(
                "machine.spacing_mm",
                "with forward_speed_mm_s".into(),
                "one of spacing_mm and forward_speed_mm_s",
            ));
        }
        (Some(s), None) if s > 0.0 && s.is_finite() => {
            f.forward_mm_s = FeatureOptions::forward_for_spacing(s, f.rpm)
        }
        (Some(s), None) => {
            return Err(bad(
                "machine.spacing_mm",
                s.to_string(),
                "a positive plant spacing in mm",
            ));
        }
        (None, Some(v)) if v >= 0.0 && v.is_finite() => f.forward_mm_s = v,
        (None, Some(v)) => {
            return Err(bad(
                "machine.forward_speed_mm_s",
                v.to_string(),
                "a speed ≥ 0 in mm/s",
            ));
        }
        (None, None) => {}
    }
    if let Some(d) = spec.machine.depth_mm {
        if !(d >= 0.0 && d.is_finite()) {
            return Err(bad("machine.depth_mm", d.to_string(), "a depth ≥ 0 in mm"));
        }
        f.planting_depth_mm = d;
    }
    Ok(f)
}

/// Each target band ordered and within its quantity's range; the angle difference reachable
/// from the take and push bands.
fn check_bands(t: &Targets) -> Result<(), SynthesisError> {
    for (name, b) in t.bands() {
        if !(b[0].is_finite() && b[1].is_finite() && b[0] <= b[1]) {
            return Err(bad(
                &format!("targets.{name}"),
                format!("{b:?}"),
                "a band [min, max] with min ≤ max",
            ));
        }
        // Heights, widths and clearances are ≥ 0; the angles to the horizontal lie in (−90°, 90°].
        let (range, what) = if name.ends_with("_mm") {
            (
                [0.0, f64::INFINITY],
                "a length: the band must reach 0 mm or more",
            )
        } else if name == "angle_difference_deg" {
            (
                [-180.0, 180.0],
                "a difference of two angles to the horizontal: the band must meet [−180°, 180°]",
            )
        } else {
            (
                [-90.0, 90.0],
                "an angle to the horizontal: the band must meet [−90°, 90°]",
            )
        };
        if b[1] < range[0] || b[0] > range[1] {
            return Err(bad(&format!("targets.{name}"), format!("{b:?}"), what));
        }
    }
    if let (Some(take), Some(push), Some(diff)) =
        (t.take_angle_deg, t.push_angle_deg, t.angle_difference_deg)
    {
        let reach = [push[0] - take[1], push[1] - take[0]];
        if reach[1] < diff[0] || reach[0] > diff[1] {
            return Err(bad(
                "targets.angle_difference_deg",
                format!("{diff:?}"),
                &format!(
                    "a band that meets push_angle_deg − take_angle_deg = [{}, {}]: the three bands contradict each other",
                    reach[0], reach[1]
                ),
            ));
        }
    }
    Ok(())
}

/// The targets-only search box: positive and ordered, and not given with poses.
fn check_search_box(spec: &Spec) -> Result<(), SynthesisError> {
    for (field, b) in [
        ("machine.l1_mm", spec.machine.l1_mm),
        ("machine.l3_mm", spec.machine.l3_mm),
    ] {
        if b.is_some() && !spec.poses.is_empty() {
            return Err(bad(
                field,
                "given with poses".into(),
                "no search box: it bounds the targets-only search; with poses the arm follows from them",
            ));
        }
        if let Some(b) = b
            && !(b[0].is_finite() && b[1].is_finite() && b[0] > 0.0 && b[0] <= b[1])
        {
            return Err(bad(
                field,
                format!("{b:?}"),
                "a search box [min, max] in mm with 0 < min ≤ max",
            ));
        }
    }
    Ok(())
}

/// The largest position tolerance of the approximate poses, mm (0 when all are exact).
pub(super) fn max_tol_mm(spec: &Spec) -> f64 {
    spec.poses
        .iter()
        .filter(|p| p.approximate())
        .map(PoseSpec::position_tolerance_mm)
        .fold(0.0, f64::max)
}
