//! The error inventory file of the transplanter analysis (TOML or JSON; µm and degrees) and its
//! validation into an [`Inventory`] in internal units.

use super::inventory::{Eccentricity, Inventory, Spread};
use super::{ARM, BACKLASH, GEARS, N_COORDS, PIN_A, PIN_D, TransplanterError, clock_index};
use crate::analysis::tolerance::ToleranceError;
use crate::bounds::Span;
use crate::config::{self, Format};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// A scalar length error (µm): nominal value and an optional distribution about it.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct LengthError {
    /// Nominal (measured or deterministic) value, µm.
    #[serde(default)]
    pub nominal_um: f64,
    /// Standard deviation of a normal distribution about the nominal value, µm.
    #[serde(default)]
    pub sigma_um: Option<f64>,
    /// Half width of a uniform distribution about the nominal value, µm.
    #[serde(default)]
    pub half_width_um: Option<f64>,
}

/// A scalar angle error (degrees): nominal value and an optional distribution about it.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct AngleError {
    /// Nominal value, degrees.
    #[serde(default)]
    pub nominal_deg: f64,
    /// Standard deviation of a normal distribution about the nominal value, degrees.
    #[serde(default)]
    pub sigma_deg: Option<f64>,
    /// Half width of a uniform distribution about the nominal value, degrees.
    #[serde(default)]
    pub half_width_deg: Option<f64>,
}

/// Eccentricity of a gear's pitch curve relative to its rotation centre.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct EccentricityError {
    /// Nominal (measured) magnitude e, µm.
    #[serde(default)]
    pub magnitude_um: f64,
    /// Direction γ in the body frame, degrees (positive in the direction of carrier rotation).
    #[serde(default)]
    pub direction_deg: f64,
    /// σ of a 2-D Gaussian added to the nominal vector (per component; Rayleigh magnitude), µm.
    #[serde(default)]
    pub sigma_um: Option<f64>,
    /// The direction is an assembly choice (bearing / bushing orientation): random in the Monte
    /// Carlo of random assembly, optimized in the best assembly.
    #[serde(default)]
    pub free_direction: bool,
    /// Number of keyed positions of a free direction (`γ = direction + 360°·i/n`); 0 = continuous.
    #[serde(default)]
    pub keyed_positions: usize,
}

/// Errors of one gear.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct GearErrors {
    /// Eccentricity.
    #[serde(default)]
    pub eccentricity: EccentricityError,
    /// Clocking (pitch curve rotated in the body frame).
    #[serde(default)]
    pub clocking: AngleError,
}

/// Pin-hole position errors of a carrier pin.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PinErrors {
    /// Along the carrier arm (away from O), µm.
    #[serde(default)]
    pub radial: LengthError,
    /// Perpendicular to the arm, in the direction of carrier rotation, µm.
    #[serde(default)]
    pub tangential: LengthError,
}

/// Normal backlash of the two meshes.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct BacklashErrors {
    /// Sun–intermediate mesh, µm.
    #[serde(default)]
    pub sun_intermediate: LengthError,
    /// Intermediate–planet mesh, µm.
    #[serde(default)]
    pub intermediate_planet: LengthError,
}

fn default_alpha() -> f64 {
    20.0
}
fn default_side() -> i8 {
    1
}
fn default_samples() -> usize {
    720
}

/// An error file of the transplanter analysis (TOML or JSON; µm and degrees).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ErrorInventory {
    /// Pressure angle α of the tooth flanks, degrees (default 20).
    #[serde(default = "default_alpha")]
    pub pressure_angle_deg: f64,
    /// Loaded flank of the sun–intermediate mesh, ±1 (the intermediate–planet mesh takes the
    /// opposite flank, so the lost motions add up).
    #[serde(default = "default_side")]
    pub load_side: i8,
    /// Carrier angles per turn of the deviation grid (default 720).
    #[serde(default = "default_samples")]
    pub samples_per_turn: usize,
    /// Sun gear (1).
    #[serde(default)]
    pub sun: GearErrors,
    /// Intermediate gear (2).
    #[serde(default)]
    pub intermediate: GearErrors,
    /// Planet gear (3).
    #[serde(default)]
    pub planet: GearErrors,
    /// Pin hole D (intermediate axis).
    #[serde(default)]
    pub pin_d: PinErrors,
    /// Pin hole A (planet axis).
    #[serde(default)]
    pub pin_a: PinErrors,
    /// Arm (needle) mounting angle about A.
    #[serde(default)]
    pub arm_mounting: AngleError,
    /// Backlash.
    #[serde(default)]
    pub backlash: BacklashErrors,
}

impl ErrorInventory {
    /// Reads a TOML or JSON error file ([`Format::detect`]) and validates it.
    ///
    /// # Errors
    /// [`TransplanterError::File`] naming the file, and the key of a bad value.
    pub fn from_path(path: &Path) -> Result<Inventory, TransplanterError> {
        let source = config::Source::from_path(path)?;
        Self::parse(&source.text, &source.file, source.format)
    }

    /// Parses and validates error-file text in `format`; `file` names it in messages.
    ///
    /// # Errors
    /// [`TransplanterError::File`]: the parser's message (names the key), or a bad value.
    pub fn parse(text: &str, file: &str, format: Format) -> Result<Inventory, TransplanterError> {
        let parsed: Self = config::parse(text, file, format).map_err(ToleranceError::from)?;
        parsed.validate(file)
    }

    /// Checks every value and converts to internal units.
    ///
    /// # Errors
    /// [`TransplanterError::File`] with [`ToleranceError::BadValue`] naming the key.
    pub fn validate(&self, file: &str) -> Result<Inventory, TransplanterError> {
        let ck = Checker { file };
        self.check_settings(&ck)?;
        let mut ecc = [Eccentricity {
            magnitude_mm: 0.0,
            direction_rad: 0.0,
            sigma_mm: 0.0,
            free: false,
            keyed: 0,
        }; 3];
        let mut nominal = [0.0; N_COORDS];
        let mut spreads = [Spread::Fixed; N_COORDS];
        let mut set = |i: usize, (n, s): (f64, Spread)| {
            nominal[i] = n;
            spreads[i] = s;
        };
        for (k, g) in [&self.sun, &self.intermediate, &self.planet]
            .iter()
            .enumerate()
        {
            ecc[k] = ck.eccentricity(&format!("{}.eccentricity", GEARS[k]), &g.eccentricity)?;
            set(
                clock_index(k),
                ck.angle(&format!("{}.clocking", GEARS[k]), &g.clocking)?,
            );
        }
        for (pin, idx, name) in [(&self.pin_d, PIN_D, "pin_d"), (&self.pin_a, PIN_A, "pin_a")] {
            for (e, i, part) in [
                (&pin.radial, idx[0], "radial"),
                (&pin.tangential, idx[1], "tangential"),
            ] {
                set(i, ck.length(&format!("{name}.{part}"), e)?);
            }
        }
        set(ARM, ck.angle("arm_mounting", &self.arm_mounting)?);
        for (e, i, part) in [
            (
                &self.backlash.sun_intermediate,
                BACKLASH[0],
                "sun_intermediate",
            ),
            (
                &self.backlash.intermediate_planet,
                BACKLASH[1],
                "intermediate_planet",
            ),
        ] {
            let (n, s) = ck.length(&format!("backlash.{part}"), e)?;
            ck.num(
                &format!("backlash.{part}.nominal_um"),
                e.nominal_um,
                Span::closed(0.0, LENGTH_ERROR_LIMIT_UM),
                "a backlash ≥ 0 in µm",
            )?;
            set(i, (n, s));
        }
        Ok(Inventory {
            pressure_angle_rad: self.pressure_angle_deg.to_radians(),
            load_side: self.load_side,
            samples_per_turn: self.samples_per_turn,
            eccentricity: ecc,
            nominal,
            spread: spreads,
        })
    }

    /// Checks the pressure angle (5…45°), the loaded flank (±1) and the samples per turn.
    fn check_settings(&self, ck: &Checker<'_>) -> Result<(), TransplanterError> {
        ck.num(
            "pressure_angle_deg",
            self.pressure_angle_deg,
            Span::closed(5.0, 45.0),
            "a pressure angle in degrees",
        )?;
        if !(self.load_side == 1 || self.load_side == -1) {
            return Err(ck.bad("load_side", "1 or -1 (the loaded flank)"));
        }
        if !(16..=100_000).contains(&self.samples_per_turn) {
            return Err(ck.bad("samples_per_turn", "an integer in 16..=100000"));
        }
        Ok(())
    }
}

/// One µm in mm.
const UM_IN_MM: f64 = 1e-3;

/// Largest assembly angle error (clocking, arm mounting), nominal and spread alike, degrees: an
/// assembly is off by a fraction of a degree, and beyond a few degrees the arm is mis-built.
const ASSEMBLY_ANGLE_LIMIT_DEG: f64 = 10.0;

/// Largest length error (a pin hole's offset, an eccentricity, a backlash, and their spreads),
/// µm: 2 mm is a module of the G1's gears; beyond, a mesh skips a tooth and the train is not
/// the design the analysis linearises about.
pub const LENGTH_ERROR_LIMIT_UM: f64 = 2000.0;

/// Why [`LENGTH_ERROR_LIMIT_UM`].
const LENGTH_ERROR_WHY: &str = "a length error in µm, at most 2000 (2 mm, a module of the \
                                G1's gears: beyond, a mesh skips a tooth)";

/// The checks of the values of one error file, each naming its key.
struct Checker<'a> {
    /// The file, for the messages.
    file: &'a str,
}

impl Checker<'_> {
    /// The error of a bad value at `key`: `message` says what is expected.
    fn bad(&self, key: &str, message: &str) -> TransplanterError {
        TransplanterError::File(ToleranceError::BadValue {
            file: self.file.into(),
            key: key.into(),
            message: message.into(),
        })
    }

    /// `v` when finite and within `span`, else the error naming `key`, the value and the span.
    fn num(&self, key: &str, v: f64, span: Span, what: &str) -> Result<f64, TransplanterError> {
        span.check(v, what).map_err(|m| self.bad(key, &m))
    }

    /// The spread from an optional σ (normal) or half-width (uniform) within `[0, limit]`, in
    /// the unit of the keys' `suffix` (`um`, `deg`), times `scale` into internal units; neither:
    /// fixed. `key` is the table's.
    fn spread(
        &self,
        key: &str,
        (sigma, half): (Option<f64>, Option<f64>),
        (suffix, limit): (&str, f64),
        scale: f64,
    ) -> Result<Spread, TransplanterError> {
        let span = Span::closed(0.0, limit);
        let what = format!("a spread ≥ 0 in {suffix}, at most {limit}");
        match (sigma, half) {
            (None, None) => Ok(Spread::Fixed),
            (Some(s), None) => {
                let s = self.num(&format!("{key}.sigma_{suffix}"), s, span, &what)?;
                Ok(Spread::Normal(s * scale))
            }
            (None, Some(h)) => {
                let h = self.num(&format!("{key}.half_width_{suffix}"), h, span, &what)?;
                Ok(Spread::Uniform(h * scale))
            }
            (Some(_), Some(_)) => Err(self.bad(
                &format!("{key}.sigma_{suffix}"),
                "give either sigma or half_width (normal or uniform), not both",
            )),
        }
    }

    /// A length error: nominal (mm) and spread, from µm, each within ±[`LENGTH_ERROR_LIMIT_UM`].
    fn length(&self, key: &str, e: &LengthError) -> Result<(f64, Spread), TransplanterError> {
        let n = self.num(
            &format!("{key}.nominal_um"),
            e.nominal_um,
            Span::symmetric(LENGTH_ERROR_LIMIT_UM),
            LENGTH_ERROR_WHY,
        )?;
        let s = self.spread(
            key,
            (e.sigma_um, e.half_width_um),
            ("um", LENGTH_ERROR_LIMIT_UM),
            UM_IN_MM,
        )?;
        Ok((n * UM_IN_MM, s))
    }

    /// An assembly angle error within ±[`ASSEMBLY_ANGLE_LIMIT_DEG`]: nominal (rad) and spread,
    /// from degrees.
    fn angle(&self, key: &str, e: &AngleError) -> Result<(f64, Spread), TransplanterError> {
        let n = self.num(
            &format!("{key}.nominal_deg"),
            e.nominal_deg,
            Span::symmetric(ASSEMBLY_ANGLE_LIMIT_DEG),
            "an assembly angle error in degrees",
        )?;
        // The spread within the same ±10° (a σ of 9e18° ran for minutes: every sample's angle
        // went through the trigonometry of a number with no digit left below a turn).
        let s = self.spread(
            key,
            (e.sigma_deg, e.half_width_deg),
            ("deg", ASSEMBLY_ANGLE_LIMIT_DEG),
            1f64.to_radians(),
        )?;
        Ok((n.to_radians(), s))
    }

    /// A gear's eccentricity (mm, rad), its σ and whether (and at how many keyed positions) its
    /// direction is an assembly choice.
    fn eccentricity(
        &self,
        key: &str,
        e: &EccentricityError,
    ) -> Result<Eccentricity, TransplanterError> {
        let error = Span::closed(0.0, LENGTH_ERROR_LIMIT_UM);
        self.num(
            &format!("{key}.magnitude_um"),
            e.magnitude_um,
            error,
            LENGTH_ERROR_WHY,
        )?;
        self.num(
            &format!("{key}.direction_deg"),
            e.direction_deg,
            Span::symmetric(3600.0),
            "a direction in degrees (ten turns either way at most)",
        )?;
        let sigma = match e.sigma_um {
            None => 0.0,
            Some(s) => self.num(&format!("{key}.sigma_um"), s, error, LENGTH_ERROR_WHY)? * UM_IN_MM,
        };
        if e.keyed_positions > 0 && !e.free_direction {
            return Err(self.bad(
                &format!("{key}.keyed_positions"),
                "only a free direction (free_direction = true) has keyed positions",
            ));
        }
        if e.keyed_positions > 360 {
            return Err(self.bad(
                &format!("{key}.keyed_positions"),
                "at most 360 positions (0 = continuous)",
            ));
        }
        Ok(Eccentricity {
            magnitude_mm: e.magnitude_um * UM_IN_MM,
            direction_rad: e.direction_deg.to_radians(),
            sigma_mm: sigma,
            free: e.free_direction,
            keyed: e.keyed_positions,
        })
    }
}
