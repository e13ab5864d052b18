//! The design-file reader: the subset of `design.json` needed to assemble the train (mm,
//! degrees), checked field by field into an [`Assembly`].

use super::SimulateError;
use crate::geometry::assembly::Assembly;
use crate::geometry::pitch::PitchCurve;
use crate::math::Point;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// The subset of `design.json` needed to assemble the train (mm, degrees).
#[derive(Debug, Clone, Serialize, Deserialize)]
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
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct TeethFile {
    /// Tooth count of each gear.
    pub z: u32,
    /// Module, mm.
    pub module_mm: f64,
    /// The options the teeth were made with (rack, backlash, cutters), when the file carries
    /// them; absent: the defaults at the module.
    #[serde(default)]
    pub options: Option<crate::design::train::TrainTeethOptions>,
}

/// `carrier` of a design file.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct CarrierFile {
    /// O, mm (`center` in files of schema version 1).
    #[serde(alias = "center")]
    pub center_mm: Point,
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
        let a = pos(self.center_distance_mm, "center_distance_mm")?;
        let l3 = pos(self.l3_mm, "l3_mm")?;
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
        let max_offset = crate::geometry::mechanism::MAX_IDLER_OFFSET_RAD.to_degrees();
        if !(self.idler_offset_deg.abs() <= max_offset) {
            return Err(bad(
                "idler_offset_deg",
                format!(
                    "{} must be an angle in degrees within ±{max_offset}",
                    self.idler_offset_deg
                ),
            ));
        }
        if !self.carrier.center_mm.is_finite() {
            return Err(bad(
                "carrier.center_mm",
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
            center_mm: self.carrier.center_mm,
            direction: self.carrier.direction,
            a_mm: a,
            idler_offset_rad: self.idler_offset_deg.to_radians(),
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
