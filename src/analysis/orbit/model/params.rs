//! The model parameter file (TOML or JSON, read with [`crate::config`]) and its conversion to a
//! validated [`PlanetSet`] and [`GearSpeeds`].

use super::{GearSpeeds, Planet, PlanetSet, rpm_to_rad_s};
use crate::analysis::orbit::model::Hand;
use crate::analysis::orbit::{OrbitError, invalid};
use crate::bounds::Span;
use crate::config::{self, ConfigError, Format, Source};
use serde::Deserialize;

/// An angle (positions, phases, θ_p0), degrees: ten turns either way.
pub const ANGLE_DEG: Span = Span::symmetric(3600.0);
/// A speed, r/min: 1e6 either way, beyond any gear drive.
pub const SPEED_RPM: Span = Span::symmetric(1e6);
/// Most planets of a model.
pub const MAX_PLANETS: usize = 64;

/// A [`ConfigError`] as [`OrbitError::File`] (`{file}: {message}`, the message as before the
/// shared loader).
fn file_error(e: ConfigError) -> OrbitError {
    match e {
        ConfigError::Unreadable { file, message } | ConfigError::Parse { file, message } => {
            OrbitError::File { file, message }
        }
    }
}

/// Model parameter file (TOML or JSON). Units as the keys say.
///
/// ```toml
/// pressure_angle_deg = 20.0
/// sun_rotation = "ccw"         # h = +1 ("cw": h = −1)
/// theta_p0_deg = 0.0
/// planet_speed_rpm = 30.0      # signed, relative to the carrier; or give [gears]
/// [[planet]]
/// position_deg = 0.0
/// eccentricity_um = 10.0
/// phase_deg = 0.0
/// ```
#[derive(Debug, Clone, Deserialize, serde::Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ModelParams {
    /// Working pressure angle α, degrees.
    pub pressure_angle_deg: f64,
    /// Sun rotation sense.
    pub sun_rotation: Hand,
    /// Common phase θ_p0, degrees (default 0).
    #[serde(default)]
    pub theta_p0_deg: f64,
    /// Signed planet speed relative to the carrier, rpm (exclusive with `gears`).
    #[serde(default)]
    pub planet_speed_rpm: Option<f64>,
    /// Fixed-ring tooth numbers and sun speed; gives ω_p and the expected lines (docs/math/companion.md §A.7).
    #[serde(default)]
    pub gears: Option<GearParams>,
    /// The planets (≥ 3).
    pub planet: Vec<PlanetParams>,
}

/// `[gears]` table of [`ModelParams`].
#[derive(Debug, Clone, Copy, Deserialize, serde::Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct GearParams {
    /// Sun teeth z_s.
    pub sun_teeth: u32,
    /// Planet teeth z_p.
    pub planet_teeth: u32,
    /// Ring teeth z_r.
    pub ring_teeth: u32,
    /// Signed sun speed, rpm.
    pub sun_speed_rpm: f64,
}

/// `[[planet]]` entry of [`ModelParams`].
#[derive(Debug, Clone, Copy, Deserialize, serde::Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PlanetParams {
    /// Position angle φ_i, degrees.
    pub position_deg: f64,
    /// Eccentricity e_pi, µm.
    pub eccentricity_um: f64,
    /// Eccentricity phase θ_pi, degrees.
    pub phase_deg: f64,
}

impl ModelParams {
    /// Reads a parameter file, TOML or JSON by [`Format::detect`] (extension `.toml`/`.json`, else
    /// JSON when the text starts with `{`).
    ///
    /// # Errors
    /// [`OrbitError::File`] naming the file, with the system's or the parser's line/key message.
    pub fn from_path(path: &std::path::Path) -> Result<Self, OrbitError> {
        let src = Source::from_path(path).map_err(file_error)?;
        Self::parse(&src.text, &src.file, src.format)
    }

    /// Parses parameter text in `format`; `file` names the source in messages.
    ///
    /// # Errors
    /// [`OrbitError::File`] with the parser's line/key message.
    pub fn parse(text: &str, file: &str, format: Format) -> Result<Self, OrbitError> {
        let p: Self = config::parse(text, file, format).map_err(file_error)?;
        p.check_ranges(file)?;
        Ok(p)
    }

    /// Every number of the file finite and within its range (docs/bounds.md, "Ranges inside
    /// input files"), before any work.
    ///
    /// # Errors
    /// [`OrbitError::File`] naming the file, the key, the value and the range.
    pub fn check_ranges(&self, file: &str) -> Result<(), OrbitError> {
        let ck = |key: &str, v: f64, span: Span, what: &str| {
            span.check(v, what).map(drop).map_err(|m| OrbitError::File {
                file: file.into(),
                message: format!("`{key}`: {m}"),
            })
        };
        let angle = "an angle in degrees (ten turns either way at most)";
        let speed = "a speed in r/min (1e6 at most either way)";
        ck(
            "pressure_angle_deg",
            self.pressure_angle_deg,
            Span::closed(5.0, 45.0),
            "a pressure angle in degrees",
        )?;
        ck("theta_p0_deg", self.theta_p0_deg, ANGLE_DEG, angle)?;
        if let Some(v) = self.planet_speed_rpm {
            ck("planet_speed_rpm", v, SPEED_RPM, speed)?;
        }
        if let Some(g) = &self.gears {
            for (key, z) in [
                ("gears.sun_teeth", g.sun_teeth),
                ("gears.planet_teeth", g.planet_teeth),
                ("gears.ring_teeth", g.ring_teeth),
            ] {
                crate::bounds::check_teeth(key, z).map_err(|e| OrbitError::File {
                    file: file.into(),
                    message: format!("`{key}`: {e}"),
                })?;
            }
            ck("gears.sun_speed_rpm", g.sun_speed_rpm, SPEED_RPM, speed)?;
        }
        if self.planet.len() > MAX_PLANETS {
            return Err(OrbitError::File {
                file: file.into(),
                message: format!(
                    "`planet`: {} planets; at most {MAX_PLANETS}",
                    self.planet.len()
                ),
            });
        }
        for (k, p) in self.planet.iter().enumerate() {
            ck(
                &format!("planet[{k}].position_deg"),
                p.position_deg,
                ANGLE_DEG,
                angle,
            )?;
            ck(
                &format!("planet[{k}].eccentricity_um"),
                p.eccentricity_um,
                Span::closed(0.0, super::MAX_ECCENTRICITY_UM),
                "an eccentricity in µm (1 m at most)",
            )?;
            ck(
                &format!("planet[{k}].phase_deg"),
                p.phase_deg,
                ANGLE_DEG,
                angle,
            )?;
        }
        Ok(())
    }

    /// Gear speeds when `[gears]` is given.
    ///
    /// # Errors
    /// [`OrbitError::Invalid`] for bad gear data.
    pub fn gear_speeds(&self) -> Result<Option<GearSpeeds>, OrbitError> {
        self.gears
            .map(|g| {
                GearSpeeds::fixed_ring(
                    g.sun_teeth,
                    g.planet_teeth,
                    g.ring_teeth,
                    rpm_to_rad_s(g.sun_speed_rpm),
                )
            })
            .transpose()
    }

    /// Validated planet set.
    ///
    /// # Errors
    /// [`OrbitError::Invalid`] naming the key (exactly one of `planet_speed_rpm` / `gears` is required).
    pub fn planet_set(&self) -> Result<PlanetSet, OrbitError> {
        let omega_p = match (self.planet_speed_rpm, self.gear_speeds()?) {
            (Some(_), Some(_)) => {
                return Err(invalid(
                    "planet_speed_rpm",
                    "give either planet_speed_rpm or [gears], not both",
                ));
            }
            (Some(rpm), None) => rpm_to_rad_s(rpm),
            (None, Some(g)) => g.planet_rad_s,
            (None, None) => {
                return Err(invalid(
                    "planet_speed_rpm",
                    "missing: give planet_speed_rpm or [gears]",
                ));
            }
        };
        let planets = self
            .planet
            .iter()
            .map(|p| Planet {
                position_rad: p.position_deg.to_radians(),
                eccentricity_um: p.eccentricity_um,
                phase_rad: p.phase_deg.to_radians(),
            })
            .collect();
        PlanetSet::new(
            self.pressure_angle_deg.to_radians(),
            self.sun_rotation,
            self.theta_p0_deg.to_radians(),
            omega_p,
            planets,
        )
        .map_err(|e| match e {
            OrbitError::Invalid { key, message } if key == "pressure_angle" => {
                invalid("pressure_angle_deg", message)
            }
            OrbitError::Invalid { key, message } if key == "theta_p0" => {
                invalid("theta_p0_deg", message)
            }
            other => other,
        })
    }
}
