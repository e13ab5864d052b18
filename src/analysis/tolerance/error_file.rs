//! The error file of `ncgear tolerance` (terms `A·sin(ωt + φ)`, base circle) and its validation.

use super::ToleranceError;
use crate::bounds::{MAX_TEETH, MIN_TEETH, Span, number};
use crate::config::{self, Format};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// Most error terms in a file.
pub const MAX_TERMS: usize = 64;
/// Most steps of the phase scan (each step evaluates a certified peak per free term).
pub const MAX_SCAN_STEPS: usize = 100_000;
/// An amplitude, an end of its uniform range, µm: a line-of-action error of at most 1 m (a
/// 1e308 ran for minutes, its sums overflowing; the summary printed a 309-digit sum).
pub const AMPLITUDE_UM: Span = Span::symmetric(1e6);
/// The σ of a Rayleigh amplitude, µm.
pub const SIGMA_UM: Span = Span::positive(1e6);
/// An angular frequency, rad/s: 1e6 is a 160 kHz mesh, beyond any gear train's.
pub const OMEGA_RAD_S: Span = Span::closed(0.0, 1e6);
/// A phase, degrees: ten turns either way.
pub const PHASE_DEG: Span = Span::symmetric(3600.0);
/// A base radius, mm: a gear of at most 10 m.
pub const BASE_RADIUS_MM: Span = Span::positive(5000.0);
/// The module of a base circle, mm (the range of `ncgear design --module`).
pub const MODULE_MM: Span = Span::closed(0.05, 50.0);
/// The teeth of a base circle ([`MIN_TEETH`]..=[`MAX_TEETH`]).
pub const TEETH: Span = Span::closed(MIN_TEETH as f64, MAX_TEETH as f64);
/// The pressure angle of a base circle, degrees (the range of `--pressure-angle`).
pub const PRESSURE_ANGLE_DEG: Span = Span::closed(10.0, 45.0);

/// Amplitude distribution for Monte Carlo.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields, rename_all = "snake_case")]
pub enum AmplitudeDist {
    /// Uniform in `[lo, hi]` µm.
    UniformUm([f64; 2]),
    /// Magnitude of a 2-D Gaussian eccentricity vector (Rayleigh) with σ in µm.
    RayleighSigmaUm(f64),
}

/// One error term of the file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
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
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
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
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
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
        let bad = |key: String, message: String| ToleranceError::BadValue {
            file: file.into(),
            key,
            message,
        };
        // Each number finite and within its span, or the error naming its key.
        let ck = |key: String, v: f64, span: Span, what: &str| {
            span.check(v, what).map_err(|m| bad(key, m))
        };
        if self.terms.is_empty() {
            return Err(bad(
                "terms".into(),
                "at least one error term is needed".into(),
            ));
        }
        if self.terms.len() > MAX_TERMS {
            return Err(bad(
                "terms".into(),
                format!("{} terms; at most {MAX_TERMS}", self.terms.len()),
            ));
        }
        if !(1..=MAX_SCAN_STEPS).contains(&self.scan_steps) {
            return Err(bad(
                "scan_steps".into(),
                format!("{} is outside 1..={MAX_SCAN_STEPS}", self.scan_steps),
            ));
        }
        match (self.base_radius_mm, self.base_circle) {
            (Some(r), None) => {
                ck(
                    "base_radius_mm".into(),
                    r,
                    BASE_RADIUS_MM,
                    "a base radius in mm (a gear of at most 10 m)",
                )?;
            }
            (None, Some(b)) => {
                ck(
                    "base_circle.module_mm".into(),
                    b.module_mm,
                    MODULE_MM,
                    "a module in mm (the range of ncgear design --module)",
                )?;
                ck(
                    "base_circle.teeth".into(),
                    b.teeth,
                    TEETH,
                    "a tooth count (the range of a gear's teeth, docs/bounds.md)",
                )?;
                ck(
                    "base_circle.pressure_angle_deg".into(),
                    b.pressure_angle_deg,
                    PRESSURE_ANGLE_DEG,
                    "a pressure angle in degrees (the range of --pressure-angle)",
                )?;
            }
            (Some(_), Some(_)) => {
                return Err(bad(
                    "base_radius_mm".into(),
                    "give either base_radius_mm or base_circle, not both".into(),
                ));
            }
            (None, None) => {
                return Err(bad(
                    "base_radius_mm".into(),
                    "a positive base radius in mm (or base_circle = {module_mm, teeth, pressure_angle_deg})".into(),
                ));
            }
        }
        for (k, t) in self.terms.iter().enumerate() {
            let key = |f: &str| format!("terms[{k}].{f}");
            ck(
                key("amplitude_um"),
                t.amplitude_um,
                AMPLITUDE_UM,
                "a line-of-action error amplitude in µm (1 m at most)",
            )?;
            ck(
                key("omega_rad_s"),
                t.omega_rad_s,
                OMEGA_RAD_S,
                "an angular frequency in rad/s (1e6 rad/s: a 160 kHz mesh at most)",
            )?;
            ck(
                key("phase_deg"),
                t.phase_deg,
                PHASE_DEG,
                "a phase in degrees (ten turns either way at most)",
            )?;
            if !(t.sign == 1.0 || t.sign == -1.0) {
                return Err(bad(
                    key("sign"),
                    format!("{} must be 1 or -1", number(t.sign)),
                ));
            }
            match t.amplitude_dist {
                Some(AmplitudeDist::UniformUm([lo, hi])) => {
                    let what =
                        "an end of the amplitude's uniform range [lo, hi] in µm (1 m at most)";
                    let key = key("amplitude_dist.uniform_um");
                    ck(format!("{key}[0]"), lo, AMPLITUDE_UM, what)?;
                    ck(format!("{key}[1]"), hi, AMPLITUDE_UM, what)?;
                    if lo > hi {
                        return Err(bad(key, format!("[{lo}, {hi}]: lo must be ≤ hi, µm")));
                    }
                }
                Some(AmplitudeDist::RayleighSigmaUm(s)) => {
                    ck(
                        key("amplitude_dist.rayleigh_sigma_um"),
                        s,
                        SIGMA_UM,
                        "a σ > 0 in µm (1 m at most)",
                    )?;
                }
                None => {}
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
