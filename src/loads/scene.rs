//! The loads scene (`ncgear loads SCENE.toml`, `ncgear design --module auto --loads SCENE.toml`):
//! the design it names, how the machine runs it, and the effects it switches on — every table but
//! `[operation]` optional, every unknown key refused, every number checked against its range
//! before any work ([`Scene::validate`] → [`LoadCase`]).
//!
//! Files speak mm, degrees, kg, N, MPa and r/min, each unit in its key; the validated
//! [`LoadCase`] works in mm, rad, kg, N and rad/s.

use super::LoadsError;
use super::needle::{NeedleLoad, NeedleSpec};
use super::rating::{MaterialSpec, RatingOptions, RatingSpec};
use crate::math::Point;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// Standard gravity, m/s² (ISO 80000-3).
pub const STANDARD_GRAVITY_M_S2: f64 = 9.80665;

/// Most trains a carrier may carry.
pub const MAX_ARMS: u32 = 8;

/// Highest carrier speed a scene may ask for, r/min (ten times a fast transplanter's).
pub const MAX_CARRIER_RPM: f64 = 3000.0;

/// A whole scene file.
#[derive(Debug, Clone, Default, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// The design file, relative to the scene file (required by `ncgear loads`; the sizing of
    /// `ncgear design --module auto` designs its own).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub design: Option<PathBuf>,
    /// How the carrier turns.
    pub operation: Operation,
    /// The planting arm fixed to each planet gear; absent: the planet gear alone.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub arm: Option<ArmSpec>,
    /// The gear bodies; absent: massless gears (and no stresses).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gears: Option<GearsSpec>,
    /// The force of the soil and seedling on the needle tip; absent: none.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub needle: Option<NeedleSpec>,
    /// The gears' material: switches on the tooth stresses (a design with teeth).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub material: Option<MaterialSpec>,
    /// How the stresses are rated.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rating: Option<RatingSpec>,
    /// The rotor dynamics' `[effects]` (docs/dynamics.md, "The rotor"), with `rating.K_v =
    /// "dynamic"` only: the teeth are then rated on the dynamic mesh forces. Kept as written
    /// here; the dynamics check them (`ncgear::analysis::dynamics::rotor::rating`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub effects: Option<serde_json::Value>,
    /// The rotor dynamics' `[solver]`, with `[effects]` (default: the dynamics' defaults).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub solver: Option<serde_json::Value>,
    /// The rotor dynamics' `[steady]`, with `[effects]` (default: the dynamics' defaults).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub steady: Option<serde_json::Value>,
}

/// `[operation]`.
#[derive(Debug, Clone, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Operation {
    /// Carrier speed, r/min, in `(0, 3000]`.
    pub carrier_rpm: f64,
    /// Trains on the carrier, evenly spaced, `1..=8` (default 1).
    #[serde(default = "one")]
    pub arms: u32,
    /// Unit direction of gravity in the trajectory frame; `[0, 0]` (the default) = off.
    #[serde(default)]
    pub gravity: [f64; 2],
}

impl Default for Operation {
    fn default() -> Self {
        Self {
            carrier_rpm: 300.0,
            arms: 1,
            gravity: [0.0, 0.0],
        }
    }
}

fn one() -> u32 {
    1
}

/// `[arm]`: the planting arm fixed to each planet gear.
#[derive(Debug, Clone, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ArmSpec {
    /// Mass, kg, `≥ 0`.
    pub mass_kg: f64,
    /// Centre of mass in the planet's body frame (the frame of `gears.planet.pitch`), mm.
    pub com_mm: [f64; 2],
    /// Moment of inertia about its own centre of mass, kg·mm², `≥ 0`.
    pub inertia_kg_mm2: f64,
}

/// A face width: a number of mm, or `"auto"` (the sizing picks it within 6…15·m).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(untagged)]
pub enum FaceWidthSpec {
    /// Face width, mm.
    Mm(f64),
    /// `"auto"`.
    Word(AutoWord),
}

/// The word `auto`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum AutoWord {
    /// `"auto"`.
    Auto,
}

/// `[gears]`: each gear body is its pitch curve extruded by the face width, less the bore.
#[derive(Debug, Clone, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct GearsSpec {
    /// Face width, mm, or `"auto"` (sizing only).
    pub face_width_mm: FaceWidthSpec,
    /// Density, kg/m³ (default 7850, steel).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub density_kg_m3: Option<f64>,
    /// Diameter of the central bore of every gear, mm (default 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bore_mm: Option<f64>,
    /// Pressure angle of the teeth, degrees, for a design without teeth (default 20; a design
    /// with teeth uses its own rack's).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pressure_angle_deg: Option<f64>,
}

/// The face width of a validated case.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FaceWidth {
    /// Given, mm.
    Mm(f64),
    /// Chosen by the sizing within `[6, 15]·m`.
    Auto,
}

/// The gear bodies of a validated case (mm, kg/m³).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GearBodies {
    /// Face width.
    pub face_width: FaceWidth,
    /// Density, kg/m³.
    pub density_kg_m3: f64,
    /// Bore diameter, mm.
    pub bore_mm: f64,
}

/// The planting arm of a validated case (CCW-independent: the planet's body frame as in the
/// design file), kg and mm.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Arm {
    /// Mass, kg.
    pub mass_kg: f64,
    /// Centre of mass in the planet's body frame, mm.
    pub com_mm: Point,
    /// Inertia about its own centre of mass, kg·mm².
    pub inertia_kg_mm2: f64,
}

/// A validated scene: what to compute and with which data (mm, rad, kg, N, rad/s).
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct LoadCase {
    /// Carrier speed, rad/s (> 0).
    pub omega_rad_s: f64,
    /// Trains on the carrier.
    pub arms: u32,
    /// Gravity, m/s², trajectory frame (zero vector = off).
    pub gravity_m_s2: Point,
    /// The planting arm, if any.
    pub arm: Option<Arm>,
    /// The gear bodies, if any (else massless gears).
    pub bodies: Option<GearBodies>,
    /// Pressure angle for a design without teeth, rad.
    pub pressure_angle_rad: f64,
    /// The needle load, if any.
    pub needle: Option<NeedleLoad>,
    /// The tooth rating, if the scene names a material.
    pub rating: Option<RatingOptions>,
    /// Uniform samples of the carrier's travel over one turn (≥ 720, a multiple of `arms`).
    pub samples: usize,
}

impl Scene {
    /// Reads a scene file (TOML or JSON, [`crate::config`]).
    ///
    /// # Errors
    /// [`LoadsError::Scene`] naming the file and the key.
    pub fn from_path(path: &Path) -> Result<Self, LoadsError> {
        crate::config::load(path).map_err(|e| LoadsError::Scene(e.to_string()))
    }

    /// The design file the scene names, resolved against the scene file's folder.
    #[must_use]
    pub fn design_path(&self, scene_file: &Path) -> Option<PathBuf> {
        let d = self.design.as_ref()?;
        Some(if d.is_absolute() {
            d.clone()
        } else {
            scene_file.parent().unwrap_or(Path::new("")).join(d)
        })
    }

    /// Checks every number against its range (naming `file` and the key) and converts to
    /// library units.
    ///
    /// # Errors
    /// [`LoadsError::Field`] naming the key, its value and the range.
    pub fn validate(&self, file: &str) -> Result<LoadCase, LoadsError> {
        let field = |key: &str, message: String| LoadsError::Field {
            file: file.into(),
            key: key.into(),
            message,
        };
        let op = &self.operation;
        if !(op.carrier_rpm > 0.0 && op.carrier_rpm <= MAX_CARRIER_RPM) {
            return Err(field(
                "operation.carrier_rpm",
                format!(
                    "{} must be a speed in (0, {MAX_CARRIER_RPM}] r/min",
                    op.carrier_rpm
                ),
            ));
        }
        if !(1..=MAX_ARMS).contains(&op.arms) {
            return Err(field(
                "operation.arms",
                format!("{} must be a count of trains in 1..={MAX_ARMS}", op.arms),
            ));
        }
        let g = Point::from(op.gravity);
        let gravity_m_s2 = if g.x == 0.0 && g.y == 0.0 {
            Point::new(0.0, 0.0)
        } else if g.is_finite() && (g.norm() - 1.0).abs() <= 1e-3 {
            g * (STANDARD_GRAVITY_M_S2 / g.norm())
        } else {
            return Err(field(
                "operation.gravity",
                format!(
                    "[{}, {}] must be a unit direction (|g| = 1 within 1e-3; 9.80665 m/s² is \
                     applied along it) or [0, 0] for no gravity",
                    g.x, g.y
                ),
            ));
        };
        let arm = self
            .arm
            .as_ref()
            .map(|a| validate_arm(a, &field))
            .transpose()?;
        let bodies = self
            .gears
            .as_ref()
            .map(|g| validate_bodies(g, &field))
            .transpose()?;
        let pressure_angle_deg = self
            .gears
            .as_ref()
            .and_then(|g| g.pressure_angle_deg)
            .unwrap_or(20.0);
        if !(10.0..=35.0).contains(&pressure_angle_deg) {
            return Err(field(
                "gears.pressure_angle_deg",
                format!("{pressure_angle_deg} must be a pressure angle in [10, 35] degrees"),
            ));
        }
        let needle = self.needle.as_ref().map(|n| n.validate(file)).transpose()?;
        let rating = match (&self.material, &self.rating) {
            (Some(m), r) => Some(RatingOptions::from_spec(m, r.as_ref(), file)?),
            (None, Some(_)) => {
                return Err(field(
                    "rating",
                    "rates the teeth against a material, and the scene names none: add a \
                     [material] table (preset = \"steel\", …) or remove [rating]"
                        .into(),
                ));
            }
            (None, None) => None,
        };
        let dynamic = rating.as_ref().is_some_and(|r| r.on_dynamic_forces);
        if dynamic && self.effects.is_none() {
            return Err(field(
                "rating.K_v",
                "\"dynamic\" rates the teeth on the rotor dynamics' forces, and the scene names \
                 no [effects]: add [effects] (mesh_stiffness, and what else the motion should \
                 have: docs/dynamics.md), or give K_v a number"
                    .into(),
            ));
        }
        for (key, present) in [
            ("effects", self.effects.is_some()),
            ("solver", self.solver.is_some()),
            ("steady", self.steady.is_some()),
        ] {
            if present && !dynamic {
                return Err(field(
                    key,
                    format!(
                        "[{key}] belongs to the rotor dynamics, which a loads scene runs only to \
                         rate the teeth on its forces: set rating.K_v = \"dynamic\" (with a \
                         [material]), or run the dynamics from a rotor scene ([scene] model = \
                         \"rotor\", `ncgear dynamics`)"
                    ),
                ));
            }
        }
        if rating.is_none() && bodies.is_some_and(|b| b.face_width == FaceWidth::Auto) {
            return Err(field(
                "gears.face_width_mm",
                "\"auto\" is the narrowest face width whose teeth meet the rating's targets, and \
                 the scene rates nothing: add a [material], or give the face width in mm"
                    .into(),
            ));
        }
        if rating.is_some() && bodies.is_none() {
            return Err(field(
                "gears",
                "the tooth stresses need the face width: add [gears] with face_width_mm".into(),
            ));
        }
        let arms = op.arms as usize;
        let samples = 720usize.div_ceil(arms) * arms;
        Ok(LoadCase {
            omega_rad_s: op.carrier_rpm * std::f64::consts::TAU / 60.0,
            arms: op.arms,
            gravity_m_s2,
            arm,
            bodies,
            pressure_angle_rad: pressure_angle_deg.to_radians(),
            needle,
            rating,
            samples,
        })
    }
}

/// A finite, non-negative number, or the key's error.
fn non_negative(
    v: f64,
    key: &str,
    what: &str,
    field: &impl Fn(&str, String) -> LoadsError,
) -> Result<f64, LoadsError> {
    if v.is_finite() && v >= 0.0 {
        Ok(v)
    } else {
        Err(field(key, format!("{v} must be {what}")))
    }
}

fn validate_arm(
    a: &ArmSpec,
    field: &impl Fn(&str, String) -> LoadsError,
) -> Result<Arm, LoadsError> {
    let mass_kg = non_negative(a.mass_kg, "arm.mass_kg", "a mass ≥ 0 in kg", field)?;
    if mass_kg > 1000.0 {
        return Err(field(
            "arm.mass_kg",
            format!("{mass_kg} kg: a planting arm of at most 1000 kg"),
        ));
    }
    let inertia_kg_mm2 = non_negative(
        a.inertia_kg_mm2,
        "arm.inertia_kg_mm2",
        "an inertia ≥ 0 in kg·mm²",
        field,
    )?;
    let com_mm = Point::from(a.com_mm);
    if !(com_mm.is_finite() && com_mm.norm() <= 10_000.0) {
        return Err(field(
            "arm.com_mm",
            format!(
                "[{}, {}] must be a point within 10 m of the planet axis, mm",
                com_mm.x, com_mm.y
            ),
        ));
    }
    Ok(Arm {
        mass_kg,
        com_mm,
        inertia_kg_mm2,
    })
}

fn validate_bodies(
    g: &GearsSpec,
    field: &impl Fn(&str, String) -> LoadsError,
) -> Result<GearBodies, LoadsError> {
    let face_width = match g.face_width_mm {
        FaceWidthSpec::Word(AutoWord::Auto) => FaceWidth::Auto,
        FaceWidthSpec::Mm(b) if b.is_finite() && b > 0.0 && b <= 1000.0 => FaceWidth::Mm(b),
        FaceWidthSpec::Mm(b) => {
            return Err(field(
                "gears.face_width_mm",
                format!("{b} must be a face width in (0, 1000] mm, or \"auto\""),
            ));
        }
    };
    let density = g.density_kg_m3.unwrap_or(7850.0);
    if !(density.is_finite() && density > 0.0 && density <= 30_000.0) {
        return Err(field(
            "gears.density_kg_m3",
            format!("{density} must be a density in (0, 30000] kg/m³"),
        ));
    }
    let bore_mm = non_negative(
        g.bore_mm.unwrap_or(0.0),
        "gears.bore_mm",
        "a bore diameter ≥ 0 in mm",
        field,
    )?;
    Ok(GearBodies {
        face_width,
        density_kg_m3: density,
        bore_mm,
    })
}
