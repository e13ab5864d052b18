//! The design-file reader: the subset of `design.json` needed to assemble the train (mm,
//! degrees), checked field by field into an [`Assembly`].

use super::SimulateError;
use crate::bounds::{Span, number};
use crate::geometry::assembly::Assembly;
use crate::geometry::pitch::PitchCurve;
use crate::math::Point;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// A length of the train (centre distance, needle), mm: a transplanter's are tens of mm.
pub const LENGTH_MM: Span = Span::positive(5000.0);
/// An angle (needle, orientations), degrees: ten turns either way.
pub const ANGLE_DEG: Span = Span::symmetric(3600.0);
/// A coordinate (the carrier centre, target points), mm: 100 m from the origin.
pub const POSITION_MM: Span = Span::symmetric(1e5);
/// The module of the teeth, mm (the range of `ncgear design --module`).
pub const MODULE_MM: Span = Span::closed(0.05, 50.0);
/// Fewest samples of a pitch table.
pub const MIN_PITCH_SAMPLES: usize = 8;
/// Most samples of a pitch table (the largest `ncgear design --samples`).
pub const MAX_PITCH_SAMPLES: usize = 262_144;
/// How far a table's partner may roll past a whole turn, mm: a design writes its tables to
/// 1e-12 mm and passes check C2 at 1e-6 mm; a table rounded to 6 decimals closes to about
/// 1e-5 mm.
pub const CLOSURE_TOL_MM: f64 = 1e-3;

/// The subset of `design.json` needed to assemble the train (mm, degrees).
#[derive(Debug, Clone, Serialize, Deserialize, schemars::JsonSchema)]
pub struct DesignFile {
    /// Needle length, mm (`l3` in files of schema version 1).
    #[serde(alias = "l3")]
    pub l3_mm: f64,
    /// Centre distance a, mm (`center_distance` in files of schema version 1).
    #[serde(alias = "center_distance")]
    pub center_distance_mm: f64,
    /// Idler offset ε, degrees (0, the collinear train, when absent).
    #[serde(default)]
    pub idler_offset_deg: f64,
    /// Needle angle γ, degrees.
    pub needle_angle_deg: f64,
    /// Carrier.
    pub carrier: CarrierFile,
    /// Gears.
    pub gears: GearsFile,
    /// Target trajectory points (mm), when the file carries them.
    #[serde(default)]
    pub target_points: Vec<Point>,
    /// The `teeth` block of `ncgear design --module` (only `z` and `module_mm` are read).
    #[serde(default)]
    pub teeth: Option<TeethFile>,
}

/// The part of `design.json`'s `teeth` block needed to regenerate the toothed outlines.
#[derive(Debug, Clone, Serialize, Deserialize, schemars::JsonSchema)]
pub struct TeethFile {
    /// Tooth count of each gear.
    pub z: u32,
    /// Module, mm.
    pub module_mm: f64,
    /// The options the teeth were made with (rack, backlash, cutters), when the file carries
    /// them; absent: the defaults at the module.
    #[serde(default)]
    pub options: Option<crate::design::train::TrainTeethOptions>,
    /// Arc position of tooth 0's centre on each gear (sun, intermediate, planet), mm, when the
    /// file carries it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub phase_mm: Option<[f64; 3]>,
}

/// `carrier` of a design file.
#[derive(Debug, Clone, Serialize, Deserialize, schemars::JsonSchema)]
pub struct CarrierFile {
    /// O, mm (`center` in files of schema version 1).
    #[serde(alias = "center")]
    pub center_mm: Point,
    /// +1 CCW, −1 CW.
    pub direction: i8,
}

/// `gears` of a design file.
#[derive(Debug, Clone, Serialize, Deserialize, schemars::JsonSchema)]
pub struct GearsFile {
    /// Sun.
    pub sun: GearFile,
    /// Intermediate.
    pub intermediate: GearFile,
    /// Planet.
    pub planet: GearFile,
}

/// One gear of a design file.
#[derive(Debug, Clone, Serialize, Deserialize, schemars::JsonSchema)]
pub struct GearFile {
    /// `[[theta_deg, r_mm], ...]`, uniform in θ from 0.
    pub pitch: Vec<[f64; 2]>,
    /// Orientation at φH = 0, degrees.
    #[serde(default)]
    pub angle_at_zero_deg: Option<f64>,
}

impl DesignFile {
    /// Reads and validates a design file.
    pub fn from_path(path: &Path) -> Result<(Self, Assembly), SimulateError> {
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

    /// Builds the [`Assembly`], checking every field against its range (docs/bounds.md, "Ranges
    /// inside input files") and that the sun and intermediate tables close.
    pub fn assembly(&self, file: &str) -> Result<Assembly, SimulateError> {
        let bad = |field: &str, message: String| SimulateError::BadField {
            file: file.into(),
            field: field.into(),
            message,
        };
        let ck = |field: &str, v: f64, span: Span, what: &str| {
            span.check(v, what).map_err(|m| bad(field, m))
        };
        let length = "a length in mm (5 m at most)";
        let a = ck(
            "center_distance_mm",
            self.center_distance_mm,
            LENGTH_MM,
            length,
        )?;
        let l3 = ck("l3_mm", self.l3_mm, LENGTH_MM, length)?;
        ck(
            "needle_angle_deg",
            self.needle_angle_deg,
            ANGLE_DEG,
            "an angle in degrees (ten turns either way at most)",
        )?;
        if !(self.carrier.direction == 1 || self.carrier.direction == -1) {
            return Err(bad(
                "carrier.direction",
                format!("{} must be 1 (CCW) or -1 (CW)", self.carrier.direction),
            ));
        }
        let max_offset = crate::geometry::mechanism::MAX_IDLER_OFFSET_RAD.to_degrees();
        ck(
            "idler_offset_deg",
            self.idler_offset_deg,
            Span::symmetric(max_offset),
            "an idler offset angle in degrees",
        )?;
        let o = self.carrier.center_mm;
        for (axis, v) in [("x", o.x), ("y", o.y)] {
            ck(
                &format!("carrier.center_mm.{axis}"),
                v,
                POSITION_MM,
                "a coordinate in mm (100 m from the origin at most)",
            )?;
        }
        for (k, p) in self.target_points.iter().enumerate() {
            for (axis, v) in [("x", p.x), ("y", p.y)] {
                ck(
                    &format!("target_points[{k}].{axis}"),
                    v,
                    POSITION_MM,
                    "a coordinate in mm (100 m from the origin at most)",
                )?;
            }
        }
        if let Some(t) = &self.teeth {
            crate::bounds::check_teeth("teeth.z", t.z)
                .map_err(|e| bad("teeth.z", e.to_string()))?;
            ck(
                "teeth.module_mm",
                t.module_mm,
                MODULE_MM,
                "a module in mm (the range of ncgear design --module)",
            )?;
        }
        let curve = |g: &GearFile, name: &str| -> Result<PitchCurve, SimulateError> {
            let field = format!("gears.{name}.pitch");
            let n = g.pitch.len();
            if !(MIN_PITCH_SAMPLES..=MAX_PITCH_SAMPLES).contains(&n) {
                return Err(bad(
                    &field,
                    format!(
                        "{n} samples; {MIN_PITCH_SAMPLES}..={MAX_PITCH_SAMPLES} uniform [theta_deg, r_mm] pairs are needed (720 recommended; the range of design --samples)"
                    ),
                ));
            }
            for (k, p) in g.pitch.iter().enumerate() {
                let expect = 360.0 * k as f64 / n as f64;
                if !((p[0] - expect).abs() <= 1e-6 * 360.0) {
                    return Err(bad(
                        &format!("{field}[{k}][0]"),
                        format!(
                            "theta_deg = {} but a uniform table from 0 needs {expect}",
                            number(p[0])
                        ),
                    ));
                }
                if !(p[1] > 0.0 && p[1] < a) {
                    return Err(bad(
                        &format!("{field}[{k}][1]"),
                        format!(
                            "r_mm = {} is outside (0, center_distance_mm = {a}): a radius in mm",
                            number(p[1])
                        ),
                    ));
                }
            }
            PitchCurve::from_uniform_radii(g.pitch.iter().map(|p| p[1]).collect())
                .map_err(|e| bad(&field, e.to_string()))
        };
        let angle = |g: &GearFile, name: &str| -> Result<f64, SimulateError> {
            let field = format!("gears.{name}.angle_at_zero_deg");
            let v = g
                .angle_at_zero_deg
                .ok_or_else(|| bad(&field, "missing: an angle in degrees".into()))?;
            ck(
                &field,
                v,
                ANGLE_DEG,
                "an angle in degrees (ten turns either way at most)",
            )
            .map(f64::to_radians)
        };
        let (sun, intermediate, planet) = (
            curve(&self.gears.sun, "sun")?,
            curve(&self.gears.intermediate, "intermediate")?,
            curve(&self.gears.planet, "planet")?,
        );
        // The sun and the intermediate roll on their partners over a whole turn: the mean of
        // r/(a − r) over each table is 1 (check C2 of the design, 1e-6 mm as written).
        for (name, g) in [
            ("sun", &self.gears.sun),
            ("intermediate", &self.gears.intermediate),
        ] {
            let n = g.pitch.len().max(1) as f64;
            let mean = g.pitch.iter().map(|p| p[1] / (a - p[1])).sum::<f64>() / n;
            let gap = (mean - 1.0).abs() * std::f64::consts::TAU * a;
            if !(gap <= CLOSURE_TOL_MM) {
                return Err(bad(
                    &format!("gears.{name}.pitch"),
                    format!(
                        "the table does not close: its partner rolls {} mm too far or short per \
                         turn (|mean r/(a − r) − 1|·2π·a; at most {CLOSURE_TOL_MM} mm): a radius \
                         was edited, or the table is of another centre distance",
                        number(gap)
                    ),
                ));
            }
        }
        Ok(Assembly {
            center_mm: self.carrier.center_mm,
            direction: self.carrier.direction,
            a_mm: a,
            idler_offset_rad: self.idler_offset_deg.to_radians(),
            l3_mm: l3,
            needle_angle_rad: self.needle_angle_deg.to_radians(),
            sun,
            intermediate,
            intermediate_angle_at_zero_rad: angle(&self.gears.intermediate, "intermediate")?,
            planet,
            planet_angle_at_zero_rad: angle(&self.gears.planet, "planet")?,
        })
    }
}
