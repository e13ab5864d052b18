//! The error file of `ncgear tolerance` (terms `A·sin(ωt + φ)`, base circle) and its validation.

use super::ToleranceError;
use crate::config::{self, Format};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// Amplitude distribution for Monte Carlo.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, rename_all = "snake_case")]
pub enum AmplitudeDist {
    /// Uniform in `[lo, hi]` µm.
    UniformUm([f64; 2]),
    /// Magnitude of a 2-D Gaussian eccentricity vector (Rayleigh) with σ in µm.
    RayleighSigmaUm(f64),
}

/// One error term of the file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ErrorTerm {
    /// Label.
    #[serde(default)]
    pub name: String,
    /// Amplitude A, µm (the sign is kept: `−A sin x = A sin(x + π)`).
    pub amplitude_um: f64,
    /// Angular frequency ω, rad/s (0 for a constant term).
    pub omega_rad_s: f64,
    /// Fixed phase, or the constant part `c` of a free phase, degrees.
    #[serde(default)]
    pub phase_deg: f64,
    /// Whether the phase is an assembly choice `φ = sign·β + phase`.
    #[serde(default)]
    pub free: bool,
    /// `s` in `φ = s·β + c` (±1).
    #[serde(default = "one")]
    pub sign: f64,
    /// Amplitude distribution for Monte Carlo (default: the nominal amplitude).
    #[serde(default)]
    pub amplitude_dist: Option<AmplitudeDist>,
}

fn one() -> f64 {
    1.0
}

/// Base circle given by gear data instead of a radius.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BaseCircle {
    /// Module, mm.
    pub module_mm: f64,
    /// Tooth count.
    pub teeth: f64,
    /// Pressure angle, degrees.
    pub pressure_angle_deg: f64,
}

/// An error file (JSON or TOML).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ErrorFile {
    /// Base radius r_b, mm (or give `base_circle`).
    #[serde(default)]
    pub base_radius_mm: Option<f64>,
    /// Base circle from module, teeth and pressure angle.
    #[serde(default)]
    pub base_circle: Option<BaseCircle>,
    /// Steps of the phase scan (the paper: 100).
    #[serde(default = "hundred")]
    pub scan_steps: usize,
    /// Error terms, in assembly order.
    pub terms: Vec<ErrorTerm>,
}

fn hundred() -> usize {
    100
}

impl ErrorFile {
    /// Reads a JSON or TOML error file ([`Format::detect`]) and validates it.
    ///
    /// # Errors
    /// [`ToleranceError`] naming the file, and the key of a bad value.
    pub fn from_path(path: &Path) -> Result<Self, ToleranceError> {
        let source = config::Source::from_path(path)?;
        Self::parse(&source.text, &source.file, source.format)
    }

    /// Parses error-file text in `format`; `file` names it in messages.
    ///
    /// # Errors
    /// [`ToleranceError::Parse`] (the parser names the key), [`ToleranceError::BadValue`].
    pub fn parse(text: &str, file: &str, format: Format) -> Result<Self, ToleranceError> {
        let parsed: Self = config::parse(text, file, format)?;
        parsed.validate(file)?;
        Ok(parsed)
    }

    fn validate(&self, file: &str) -> Result<(), ToleranceError> {
        let bad = |key: String, message: &str| {
            Err(ToleranceError::BadValue {
                file: file.into(),
                key,
                message: message.into(),
            })
        };
        if self.terms.is_empty() {
            return bad("terms".into(), "at least one error term is needed");
        }
        if self.terms.len() > 64 {
            return bad("terms".into(), "at most 64 terms");
        }
        if !(1..=100_000).contains(&self.scan_steps) {
            return bad("scan_steps".into(), "must be in 1..=100000");
        }
        match (self.base_radius_mm, self.base_circle) {
            (Some(r), None) if r.is_finite() && r > 0.0 => {}
            (None, Some(b))
                if b.module_mm > 0.0
                    && b.teeth > 0.0
                    && (0.0..90.0).contains(&b.pressure_angle_deg) => {}
            (Some(_), Some(_)) => {
                return bad(
                    "base_radius_mm".into(),
                    "give either base_radius_mm or base_circle, not both",
                );
            }
            _ => {
                return bad(
                    "base_radius_mm".into(),
                    "a positive base radius in mm (or base_circle = {module_mm, teeth, pressure_angle_deg})",
                );
            }
        }
        let rb = self.base_radius();
        if !(rb.is_finite() && rb > 0.0) {
            return bad(
                "base_circle".into(),
                "a finite positive base radius 0.5·module_mm·teeth·cos(pressure_angle_deg), mm",
            );
        }
        for (k, t) in self.terms.iter().enumerate() {
            let key = |f: &str| format!("terms[{k}].{f}");
            if !t.amplitude_um.is_finite() {
                return bad(key("amplitude_um"), "a finite amplitude in µm");
            }
            if !(t.omega_rad_s.is_finite() && t.omega_rad_s >= 0.0) {
                return bad(
                    key("omega_rad_s"),
                    "a finite angular frequency ≥ 0 in rad/s",
                );
            }
            if !t.phase_deg.is_finite() {
                return bad(key("phase_deg"), "a finite phase in degrees");
            }
            if !(t.sign == 1.0 || t.sign == -1.0) {
                return bad(key("sign"), "1 or -1");
            }
            match t.amplitude_dist {
                Some(AmplitudeDist::UniformUm([lo, hi]))
                    if !(lo.is_finite() && hi.is_finite() && lo <= hi) =>
                {
                    return bad(
                        key("amplitude_dist.uniform_um"),
                        "[lo, hi] with lo ≤ hi, µm",
                    );
                }
                Some(AmplitudeDist::RayleighSigmaUm(s)) if !(s.is_finite() && s > 0.0) => {
                    return bad(
                        key("amplitude_dist.rayleigh_sigma_um"),
                        "a positive σ in µm",
                    );
                }
                _ => {}
            }
        }
        Ok(())
    }

    /// Base radius r_b, mm.
    #[must_use]
    pub fn base_radius(&self) -> f64 {
        match (self.base_radius_mm, self.base_circle) {
            (Some(r), _) => r,
            (None, Some(b)) => {
                0.5 * b.module_mm * b.teeth * b.pressure_angle_deg.to_radians().cos()
            }
            (None, None) => f64::NAN,
        }
    }
}
