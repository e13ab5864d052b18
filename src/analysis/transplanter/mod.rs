//! Tolerance analysis of the non-circular planetary transplanting mechanism (companion spec C.6):
//! `ncgear tolerance DESIGN.json --errors ERRORS`.
//!
//! One arm (sun 1, intermediate 2, planet 3, needle) of a designed train ([`crate::geometry::assembly`]) is
//! rebuilt with manufacturing and assembly errors and solved **exactly** mesh by mesh
//! ([`model::ExactModel`]); a **linear sensitivity model** ([`model::LinearModel`]) is built from it
//! by central finite differences on a φH grid, validated against the exact model at 3σ and used
//! for a seeded Monte Carlo; the worst contributors are ranked and the free assembly choices
//! (runout orientations) are optimised ([`analyse`]).
//!
//! ## Error inventory (16 coordinates, internal units mm and rad)
//!
//! | coordinates | meaning |
//! |---|---|
//! | `ε_k = e_k·e(γ_k)`, k = sun, intermediate, planet | pitch-curve centre minus rotation centre, in the gear's body frame (the curve is translated) |
//! | `κ_k` | clocking: the pitch curve rotated in its body frame (about the rotation centre) |
//! | `Δr_D, Δt_D, Δr_A, Δt_A` | carrier pin-hole errors of D and A: radial (along OD, OA) and tangential (in the direction of carrier rotation) |
//! | `Δγ` | arm (needle) mounting angle about A |
//! | `j_12, j_23` | normal backlash of the sun–intermediate and intermediate–planet meshes |
//!
//! Angles (γ_k, κ_k, Δγ) count positive in the direction of carrier rotation, so a clockwise design
//! reads its error file exactly as a counter-clockwise one.
//!
//! ## Exact kinematics (flank-line contact model)
//!
//! Pure pitch-curve tangency cannot fix a gear angle: at a vertex of the pitch curve (r′ = 0) the
//! contact normal passes through the driven centre, and for circular gears a rotation does not
//! change the gap at all, so the circular special case (iii) would be undefined. Teeth transmit
//! along the **line of action**. The model, per mesh (driver a with known angle, driven b):
//!
//! 1. the meshing tooth: the driver parameter `v` whose perturbed pitch point `W_a(v)` lies on the
//!    (perturbed) line of centres `C_a C_b` (1-D Newton, so the contact point moves with the
//!    errors); the driven tooth is the nominal tooth correspondence `w = m(v)` (equal arc lengths,
//!    from the design tables: [`crate::geometry::assembly::Rebuilt::ccw_sun_to_intermediate`],
//!    [`crate::geometry::assembly::Rebuilt::ccw_intermediate_to_planet`]);
//! 2. line of action through `W_a`: `N = σ·cos α·t + sin α·n` (t the driver's pitch tangent, n the
//!    normal towards b, α the pressure angle, σ = ±1 the loaded flank);
//! 3. the driven angle θ_b solves the flank condition `(W_b(w; θ_b) − W_a)·N = j/2`: the two flanks,
//!    lines ⟂ N through the two pitch points, coincide up to half the normal backlash j (the driven
//!    gear sits on its loaded flank, the lost motion of a backlash j). With
//!    `W_b = C_b + R(θ_b)p_b` this is `c + |p_b| cos(θ_b + arg p_b − arg N) = 0`, solved in
//!    closed form (the root nearer the driven pitch point facing `C_a`).
//!
//! The idler passes the load on with the opposite flank: σ_23 = −σ_12 = −`load_side`, so both
//! backlashes add up in the planet's lost motion. For zero errors this reproduces the rolling
//! pitch curves exactly (the pitch points coincide on the line of centres); the flank is modelled
//! by its tangent at the pitch point (the neglected flank curvature enters at second order in the
//! µm-sized flank displacement). The first-order result is the spec's `Δθ_b = (ε·N)/ρ_b` with `ρ_b`
//! the moment arm of N about the driven centre; for circular gears `ρ_b = r·cos α = r_b` and the
//! planet error is the phasor sum of C.2 (tested).
//!
//! Needle tip: `B = C_A + l3·e(θ3 + γ + Δγ)`. Clocking the intermediate is invisible (an idler has
//! nothing keyed to it; tested); clocking the planet is the same as an arm mounting error of the
//! opposite sign (tested).

mod analyse;
mod model;

pub use analyse::{
    AssemblyOptimum, Contribution, EnvelopePoint, FeatureDeviations, GreedyChoice,
    TransplanterOptions, TransplanterReport, Validation, analyse,
};
pub use model::{ExactModel, FdSteps, LinearModel, TrainState};

use crate::analysis::tolerance::{ToleranceError, parse_config, read_config_text};
use rand::RngExt;
use rand::rngs::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};
use serde::{Deserialize, Serialize};
use std::f64::consts::TAU;
use std::path::Path;

/// Number of error coordinates.
pub const N_COORDS: usize = 16;

/// Names (with internal units) of the error coordinates, in order.
pub const COORD_NAMES: [&str; N_COORDS] = [
    "sun eccentricity x (mm, body)",
    "sun eccentricity y (mm, body)",
    "intermediate eccentricity x (mm, body)",
    "intermediate eccentricity y (mm, body)",
    "planet eccentricity x (mm, body)",
    "planet eccentricity y (mm, body)",
    "sun clocking (rad)",
    "intermediate clocking (rad)",
    "planet clocking (rad)",
    "pin D radial (mm)",
    "pin D tangential (mm)",
    "pin A radial (mm)",
    "pin A tangential (mm)",
    "arm mounting angle (rad)",
    "backlash sun-intermediate (mm)",
    "backlash intermediate-planet (mm)",
];

/// Index of the first eccentricity coordinate of gear `k` (0 sun, 1 intermediate, 2 planet).
#[must_use]
pub const fn ecc_index(k: usize) -> usize {
    2 * k
}
/// Index of the clocking coordinate of gear `k`.
#[must_use]
pub const fn clock_index(k: usize) -> usize {
    6 + k
}
/// Pin D radial, tangential.
pub const PIN_D: [usize; 2] = [9, 10];
/// Pin A radial, tangential.
pub const PIN_A: [usize; 2] = [11, 12];
/// Arm mounting angle.
pub const ARM: usize = 13;
/// Backlash of the two meshes.
pub const BACKLASH: [usize; 2] = [14, 15];

/// Gear names, in coordinate order.
pub const GEARS: [&str; 3] = ["sun", "intermediate", "planet"];

/// A vector of error values (mm and rad, see [`COORD_NAMES`]).
pub type ErrorVector = [f64; N_COORDS];

/// Why the transplanter tolerance analysis cannot run.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum TransplanterError {
    /// The error file cannot be read or parsed, or a value is impossible (names the key path).
    #[error(transparent)]
    File(#[from] ToleranceError),
    /// A bad option of the analysis.
    #[error("option `{option}`: {message}")]
    BadOption {
        /// Option.
        option: &'static str,
        /// What is expected.
        message: String,
    },
    /// The perturbed flanks cannot touch (errors far too large for the geometry).
    #[error(
        "{mesh} mesh at carrier angle {carrier_deg:.3}°: the perturbed gears cannot touch (errors too large)"
    )]
    NoContact {
        /// Which mesh.
        mesh: &'static str,
        /// Carrier angle, degrees.
        carrier_deg: f64,
    },
    /// A numerical failure (non-finite result).
    #[error("numerical failure: {0}")]
    Numerical(String),
}

/// A scalar length error (µm): nominal value and an optional distribution about it.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
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
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
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
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
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
    /// Carlo of random assembly, optimised in the best assembly.
    #[serde(default)]
    pub free_direction: bool,
    /// Number of keyed positions of a free direction (`γ = direction + 360°·i/n`); 0 = continuous.
    #[serde(default)]
    pub keyed_positions: usize,
}

/// Errors of one gear.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
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
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
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
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
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
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
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

/// Distribution of one scalar coordinate about its nominal value (internal units).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Spread {
    /// No spread.
    Fixed,
    /// Normal with this σ.
    Normal(f64),
    /// Uniform with this half width.
    Uniform(f64),
}

impl Spread {
    /// Variance.
    #[must_use]
    pub fn variance(&self) -> f64 {
        match *self {
            Spread::Fixed => 0.0,
            Spread::Normal(s) => s * s,
            Spread::Uniform(h) => h * h / 3.0,
        }
    }
    /// The 3σ bound (σ-based) or the half width.
    #[must_use]
    pub fn three_sigma(&self) -> f64 {
        match *self {
            Spread::Fixed => 0.0,
            Spread::Normal(s) => 3.0 * s,
            Spread::Uniform(h) => h,
        }
    }
    fn draw(&self, rng: &mut ChaCha8Rng) -> f64 {
        match *self {
            Spread::Fixed => 0.0,
            Spread::Normal(s) => {
                let z: f64 = StandardNormal.sample(rng);
                s * z
            }
            Spread::Uniform(h) => h * (2.0 * rng.random::<f64>() - 1.0),
        }
    }
}

/// A gear eccentricity in internal units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Eccentricity {
    /// Nominal magnitude, mm.
    pub magnitude_mm: f64,
    /// Nominal direction in the body frame, rad.
    pub direction_rad: f64,
    /// σ per component, mm (0: none).
    pub sigma_mm: f64,
    /// Free (assembly-choice) direction.
    pub free: bool,
    /// Keyed positions (0: continuous).
    pub keyed: usize,
}

impl Eccentricity {
    /// The eccentricity vector (mm) at direction `gamma` (rad) with the nominal magnitude.
    #[must_use]
    pub fn vector(&self, gamma: f64) -> [f64; 2] {
        [
            self.magnitude_mm * gamma.cos(),
            self.magnitude_mm * gamma.sin(),
        ]
    }
    /// Direction of position `i` of `n` equally spaced assembly positions starting at the
    /// nominal direction, `γ + 2πi/n`, rad.
    #[must_use]
    pub fn position_direction(&self, i: usize, n: usize) -> f64 {
        self.direction_rad + TAU * i as f64 / n as f64
    }
    /// A random admissible direction of a free eccentricity (uniform, or uniform over the keyed
    /// positions), rad.
    pub fn random_direction(&self, rng: &mut ChaCha8Rng) -> f64 {
        if self.keyed > 0 {
            let i = (rng.random::<f64>() * self.keyed as f64).floor() as usize;
            self.position_direction(i.min(self.keyed - 1), self.keyed)
        } else {
            rng.random::<f64>() * TAU
        }
    }
}

/// The validated error inventory in internal units (mm, rad).
#[derive(Debug, Clone, PartialEq)]
pub struct Inventory {
    /// Pressure angle α, rad.
    pub pressure_angle_rad: f64,
    /// Loaded flank of the sun–intermediate mesh, ±1.
    pub load_side: i8,
    /// Carrier angles per turn.
    pub samples_per_turn: usize,
    /// Eccentricities of sun, intermediate, planet.
    pub eccentricity: [Eccentricity; 3],
    /// Nominal values of the scalar coordinates (indices 6..16; the eccentricity slots are unused).
    pub nominal: ErrorVector,
    /// Spreads of the scalar coordinates (indices 6..16).
    pub spread: [Spread; N_COORDS],
}

impl ErrorInventory {
    /// Reads a TOML or JSON (`.json` extension or text starting with `{`) error file.
    pub fn read(path: &Path) -> Result<Inventory, TransplanterError> {
        let (text, file, json) = read_config_text(path)?;
        Self::parse(&text, &file, json)
    }

    /// Parses and validates error-file text; `file` names it in messages.
    pub fn parse(text: &str, file: &str, json: bool) -> Result<Inventory, TransplanterError> {
        let parsed: Self = parse_config(text, file, json)?;
        parsed.validate(file)
    }

    /// Checks every value and converts to internal units.
    pub fn validate(&self, file: &str) -> Result<Inventory, TransplanterError> {
        let bad = |key: &str, message: &str| {
            TransplanterError::File(ToleranceError::BadValue {
                file: file.into(),
                key: key.into(),
                message: message.into(),
            })
        };
        if !(self.pressure_angle_deg.is_finite()
            && self.pressure_angle_deg >= 5.0
            && self.pressure_angle_deg <= 45.0)
        {
            return Err(bad(
                "pressure_angle_deg",
                "a pressure angle in [5, 45] degrees",
            ));
        }
        if !(self.load_side == 1 || self.load_side == -1) {
            return Err(bad("load_side", "1 or -1 (the loaded flank)"));
        }
        if !(16..=100_000).contains(&self.samples_per_turn) {
            return Err(bad("samples_per_turn", "an integer in 16..=100000"));
        }
        let um = 1e-3;
        let spread =
            |key: &str, sigma: Option<f64>, half: Option<f64>, unit: &str, scale: f64| match (
                sigma, half,
            ) {
                (None, None) => Ok(Spread::Fixed),
                (Some(s), None) if s.is_finite() && s >= 0.0 => Ok(Spread::Normal(s * scale)),
                (None, Some(h)) if h.is_finite() && h >= 0.0 => Ok(Spread::Uniform(h * scale)),
                (Some(_), Some(_)) => Err(bad(
                    key,
                    "give either sigma or half_width (normal or uniform), not both",
                )),
                _ => Err(bad(key, &format!("a finite value ≥ 0 in {unit}"))),
            };
        let finite = |key: &str, v: f64, unit: &str| {
            if v.is_finite() {
                Ok(v)
            } else {
                Err(bad(key, &format!("a finite value in {unit}")))
            }
        };
        let length = |key: &str, e: &LengthError| -> Result<(f64, Spread), TransplanterError> {
            let n = finite(&format!("{key}.nominal_um"), e.nominal_um, "µm")?;
            let s = spread(
                &format!("{key}.sigma_um"),
                e.sigma_um,
                e.half_width_um,
                "µm",
                um,
            )?;
            Ok((n * um, s))
        };
        let angle = |key: &str, e: &AngleError| -> Result<(f64, Spread), TransplanterError> {
            let n = finite(&format!("{key}.nominal_deg"), e.nominal_deg, "degrees")?;
            if n.abs() > 10.0 {
                return Err(bad(
                    &format!("{key}.nominal_deg"),
                    "an assembly angle error within ±10 degrees",
                ));
            }
            let s = spread(
                &format!("{key}.sigma_deg"),
                e.sigma_deg,
                e.half_width_deg,
                "degrees",
                1f64.to_radians(),
            )?;
            Ok((n.to_radians(), s))
        };
        let gears = [&self.sun, &self.intermediate, &self.planet];
        let mut ecc = [Eccentricity {
            magnitude_mm: 0.0,
            direction_rad: 0.0,
            sigma_mm: 0.0,
            free: false,
            keyed: 0,
        }; 3];
        let mut nominal = [0.0; N_COORDS];
        let mut spreads = [Spread::Fixed; N_COORDS];
        for (k, g) in gears.iter().enumerate() {
            let key = format!("{}.eccentricity", GEARS[k]);
            let e = &g.eccentricity;
            if !(e.magnitude_um.is_finite() && e.magnitude_um >= 0.0) {
                return Err(bad(
                    &format!("{key}.magnitude_um"),
                    "a finite magnitude ≥ 0 in µm",
                ));
            }
            finite(&format!("{key}.direction_deg"), e.direction_deg, "degrees")?;
            let sigma = match e.sigma_um {
                None => 0.0,
                Some(s) if s.is_finite() && s >= 0.0 => s * um,
                Some(_) => return Err(bad(&format!("{key}.sigma_um"), "a finite σ ≥ 0 in µm")),
            };
            if e.keyed_positions > 0 && !e.free_direction {
                return Err(bad(
                    &format!("{key}.keyed_positions"),
                    "only a free direction (free_direction = true) has keyed positions",
                ));
            }
            if e.keyed_positions > 360 {
                return Err(bad(
                    &format!("{key}.keyed_positions"),
                    "at most 360 positions (0 = continuous)",
                ));
            }
            ecc[k] = Eccentricity {
                magnitude_mm: e.magnitude_um * um,
                direction_rad: e.direction_deg.to_radians(),
                sigma_mm: sigma,
                free: e.free_direction,
                keyed: e.keyed_positions,
            };
            let (n, s) = angle(&format!("{}.clocking", GEARS[k]), &g.clocking)?;
            nominal[clock_index(k)] = n;
            spreads[clock_index(k)] = s;
        }
        for (pin, idx, name) in [(&self.pin_d, PIN_D, "pin_d"), (&self.pin_a, PIN_A, "pin_a")] {
            for (e, i, part) in [
                (&pin.radial, idx[0], "radial"),
                (&pin.tangential, idx[1], "tangential"),
            ] {
                let (n, s) = length(&format!("{name}.{part}"), e)?;
                nominal[i] = n;
                spreads[i] = s;
            }
        }
        let (n, s) = angle("arm_mounting", &self.arm_mounting)?;
        nominal[ARM] = n;
        spreads[ARM] = s;
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
            let (n, s) = length(&format!("backlash.{part}"), e)?;
            if n < 0.0 {
                return Err(bad(
                    &format!("backlash.{part}.nominal_um"),
                    "a backlash ≥ 0 in µm",
                ));
            }
            nominal[i] = n;
            spreads[i] = s;
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
}

impl Inventory {
    /// An inventory without any error (pressure angle α in rad, loaded flank ±1).
    #[must_use]
    pub fn zero(pressure_angle_rad: f64, load_side: i8, samples_per_turn: usize) -> Self {
        Self {
            pressure_angle_rad,
            load_side,
            samples_per_turn,
            eccentricity: [Eccentricity {
                magnitude_mm: 0.0,
                direction_rad: 0.0,
                sigma_mm: 0.0,
                free: false,
                keyed: 0,
            }; 3],
            nominal: [0.0; N_COORDS],
            spread: [Spread::Fixed; N_COORDS],
        }
    }

    /// The nominal error vector: measured values, eccentricities at their nominal directions.
    #[must_use]
    pub fn nominal_vector(&self) -> ErrorVector {
        self.with_directions(&self.eccentricity.map(|e| e.direction_rad))
    }

    /// The nominal error vector with eccentricity directions `gammas` (rad).
    #[must_use]
    pub fn with_directions(&self, gammas: &[f64; 3]) -> ErrorVector {
        let mut x = self.nominal;
        for k in 0..3 {
            let v = self.eccentricity[k].vector(gammas[k]);
            x[ecc_index(k)] = v[0];
            x[ecc_index(k) + 1] = v[1];
        }
        x
    }

    /// One random realisation (a random assembly): scalar coordinates from their distributions,
    /// eccentricities = nominal vector (at a random direction when free) + 2-D Gaussian.
    pub fn draw(&self, rng: &mut ChaCha8Rng) -> ErrorVector {
        let mut x = self.nominal;
        for k in 0..3 {
            let e = &self.eccentricity[k];
            let g = if e.free {
                e.random_direction(rng)
            } else {
                e.direction_rad
            };
            let v = e.vector(g);
            let (zx, zy): (f64, f64) = if e.sigma_mm > 0.0 {
                (StandardNormal.sample(rng), StandardNormal.sample(rng))
            } else {
                (0.0, 0.0)
            };
            x[ecc_index(k)] = v[0] + e.sigma_mm * zx;
            x[ecc_index(k) + 1] = v[1] + e.sigma_mm * zy;
        }
        for (xi, sp) in x.iter_mut().zip(&self.spread).skip(6) {
            *xi += sp.draw(rng);
        }
        x
    }

    /// A sample at the 3σ tolerances: every scalar coordinate at `nominal ± 3σ` (or ± the half
    /// width; random sign), every eccentricity of magnitude `e + 3σ` at a random direction.
    pub fn draw_three_sigma(&self, rng: &mut ChaCha8Rng) -> ErrorVector {
        let mut x = self.nominal;
        for k in 0..3 {
            let m = self.three_sigma_eccentricity(k);
            let g = rng.random::<f64>() * TAU;
            x[ecc_index(k)] = m * g.cos();
            x[ecc_index(k) + 1] = m * g.sin();
        }
        for (xi, sp) in x.iter_mut().zip(&self.spread).skip(6) {
            let s = if rng.random::<bool>() { 1.0 } else { -1.0 };
            *xi += s * sp.three_sigma();
        }
        x
    }

    /// `e + 3σ` of gear `k`'s eccentricity, mm.
    #[must_use]
    pub fn three_sigma_eccentricity(&self, k: usize) -> f64 {
        self.eccentricity[k].magnitude_mm + 3.0 * self.eccentricity[k].sigma_mm
    }

    /// Mean and variance of every coordinate under [`Inventory::draw`] (coordinates independent;
    /// a free eccentricity has mean 0 and variance `e²/2 + σ²` per component).
    #[must_use]
    pub fn moments(&self) -> (ErrorVector, ErrorVector) {
        let mut mean = self.nominal;
        let mut var = [0.0; N_COORDS];
        for k in 0..3 {
            let e = &self.eccentricity[k];
            let s2 = e.sigma_mm * e.sigma_mm;
            if e.free {
                let (i0, i1) = (ecc_index(k), ecc_index(k) + 1);
                // Keyed positions: mean and variance of the discrete set of vectors.
                let (mut mx, mut my, mut vx, mut vy) = (0.0, 0.0, 0.0, 0.0);
                let n = e.keyed;
                if n > 0 {
                    let vs: Vec<[f64; 2]> = (0..n)
                        .map(|i| e.vector(e.position_direction(i, n)))
                        .collect();
                    for v in &vs {
                        mx += v[0] / n as f64;
                        my += v[1] / n as f64;
                    }
                    for v in &vs {
                        vx += (v[0] - mx).powi(2) / n as f64;
                        vy += (v[1] - my).powi(2) / n as f64;
                    }
                } else {
                    vx = 0.5 * e.magnitude_mm * e.magnitude_mm;
                    vy = vx;
                }
                mean[i0] = mx;
                mean[i1] = my;
                var[i0] = vx + s2;
                var[i1] = vy + s2;
            } else {
                let v = e.vector(e.direction_rad);
                mean[ecc_index(k)] = v[0];
                mean[ecc_index(k) + 1] = v[1];
                var[ecc_index(k)] = s2;
                var[ecc_index(k) + 1] = s2;
            }
        }
        for (v, sp) in var.iter_mut().zip(&self.spread).skip(6) {
            *v = sp.variance();
        }
        (mean, var)
    }

    /// The free eccentricities (gear indices).
    #[must_use]
    pub fn free_gears(&self) -> Vec<usize> {
        (0..3).filter(|&k| self.eccentricity[k].free).collect()
    }
}
