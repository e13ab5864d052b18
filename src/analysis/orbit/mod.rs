//! Floating sun-gear orbit under planet eccentricity (docs/math/companion.md §A).
//!
//! Three stages, one submodule each:
//!
//! * [`model`] — kinematic model (docs/math/companion.md §A.3–§A.6): planet eccentricity phasors → sun orbit in the carrier
//!   frame, its x/y sinusoids, the ellipse, forward/backward (full-spectrum) components, whirl
//!   sense and the common-mode (transmission-error) part; gear speeds and expected lines (docs/math/companion.md §A.7).
//! * [`measure`] — evaluation of sensor records (docs/math/companion.md §A.7–§A.8): detrend, frame conversion, collision
//!   check, least-squares extraction with nuisance lines (default), Hann-DTFT, plain FFT bin (for
//!   contrast only) and synchronous resampling; uncertainty from the fit.
//! * [`identify`] — planet eccentricity phasors from a measured orbit (docs/math/companion.md §A.9), up to the
//!   unobservable common mode unless a transmission-error channel is given.
//!
//! Two modules put the stages together as `ncgear orbit` does: [`evaluate`] derives ω_p, the frame
//! and the nuisance lines from a model file or given speeds ([`evaluate::MeasureOptions`]), and
//! [`report`] holds the serializable results ([`report::ModelReport`], [`report::MeasureReport`],
//! [`report::IdentifyReport`]) — exactly what the CLI prints with `--json`.
//!
//! The shared value type is [`Orbit`]: the planet-frequency sun motion written as
//! `z(t) = x + i y = Z₊ e^{iω_p t} + Z₋ e^{−iω_p t}` (carrier frame, µm).
//!
//! Units: displacements in µm (`_um`), angles in rad (`_rad`), angular speeds in rad/s
//! (`_rad_s`), time in s. Files use µm, degrees and rpm as their keys say.

pub mod evaluate;
pub mod identify;
pub mod measure;
pub mod model;
pub mod report;

pub use nalgebra::Complex;

/// Complex number with `f64` parts (`re + i·im`).
pub type C64 = Complex<f64>;

/// Relative size below which a whirl component counts as zero (circle / straight-line tests).
pub const ZERO_COMPONENT_REL: f64 = 1e-12;

/// Errors of the orbit analyses. Every message names the offending key, file position or
/// quantity and what was expected.
#[derive(Debug, thiserror::Error, miette::Diagnostic)]
#[non_exhaustive]
pub enum OrbitError {
    /// A parameter is out of range; `key` is its path (e.g. `planet[1].eccentricity_um`).
    #[error("invalid parameter `{key}`: {message}")]
    Invalid {
        /// Key path of the parameter.
        key: String,
        /// What was expected.
        message: String,
    },
    /// A sensor CSV cell could not be used.
    #[error("{file}:{line}: column `{column}`: {message}")]
    Csv {
        /// File path.
        file: String,
        /// 1-based line number.
        line: u64,
        /// Column name (or 1-based index when the header is missing).
        column: String,
        /// What was expected.
        message: String,
    },
    /// A file could not be read or parsed as a whole.
    #[error("{file}: {message}")]
    File {
        /// File path.
        file: String,
        /// What went wrong.
        message: String,
    },
    /// The regression matrix is too ill-conditioned: two analysed lines collide (docs/math/companion.md §A.7/§A.8).
    #[error(
        "colliding lines: least-squares condition number {condition:.3e} exceeds {limit:.1e} \
         ({detail}); separate the lines (longer record) or calibrate the interfering line away"
    )]
    Collision {
        /// 2-norm condition number of the column-scaled regression matrix.
        condition: f64,
        /// Refusal limit.
        limit: f64,
        /// The closest pair of lines.
        detail: String,
    },
    /// The record cannot be analysed with the chosen method.
    #[error("record: {0}")]
    Record(String),
}

/// Shorthand for an [`OrbitError::Invalid`].
pub(crate) fn invalid(key: impl Into<String>, message: impl Into<String>) -> OrbitError {
    OrbitError::Invalid {
        key: key.into(),
        message: message.into(),
    }
}

/// Whirl sense of an elliptical orbit relative to the planet's relative spin ω_p (docs/math/companion.md §A.8).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum Whirl {
    /// `|Z₊| > |Z₋|`: traversed in the same sense as ω_p.
    Forward,
    /// `|Z₋| > |Z₊|`: traversed against ω_p.
    Backward,
    /// `|Z₊| = |Z₋|` (relative [`ZERO_COMPONENT_REL`]): a straight line, no sense.
    Line,
}

/// One same-frequency sinusoid pair `x = A_x sin(ωt + φ_x)`, `y = A_y sin(ωt + φ_y)` (docs/math/companion.md §A.5).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, schemars::JsonSchema)]
pub struct SinPair {
    /// A_sx, µm.
    pub a_x_um: f64,
    /// φ_sx, rad in (−π, π].
    pub phi_x_rad: f64,
    /// A_sy, µm.
    pub a_y_um: f64,
    /// φ_sy, rad in (−π, π].
    pub phi_y_rad: f64,
}

/// Ellipse of an orbit (docs/math/companion.md §A.6–§A.8).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, schemars::JsonSchema)]
pub struct Ellipse {
    /// Semi-major axis R_L = |Z₊| + |Z₋|, µm.
    pub r_long_um: f64,
    /// Semi-minor axis R_S = ||Z₊| − |Z₋||, µm.
    pub r_short_um: f64,
    /// Major-axis angle α_L = (arg Z₊ + arg Z₋)/2, rad in (−π/2, π/2]; `None` for a circle.
    pub alpha_long_rad: Option<f64>,
    /// Sense relative to ω_p.
    pub whirl: Whirl,
    /// Physical sense in the carrier frame: `Some(true)` counter-clockwise
    /// (forward XOR ω_p < 0), `None` for a straight line.
    pub counter_clockwise: Option<bool>,
}

/// Sun motion at the planet frequency, carrier frame:
/// `z(t) = x + i y = Z₊ e^{iω_p t} + Z₋ e^{−iω_p t}` (docs/math/companion.md §A.8), in µm.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Orbit {
    /// Signed planet spin relative to the carrier ω_p, rad/s (non-zero).
    pub omega_p_rad_s: f64,
    /// Forward component Z₊ (coefficient of e^{iω_p t}), µm.
    pub z_plus_um: C64,
    /// Backward component Z₋ (coefficient of e^{−iω_p t}), µm.
    pub z_minus_um: C64,
}

pub(crate) use crate::math::periodic::wrap_pi;

/// Wraps an angle to (−π/2, π/2] (axis directions, defined mod π).
pub(crate) fn wrap_half_pi(a: f64) -> f64 {
    let w = a.rem_euclid(std::f64::consts::PI);
    if w > std::f64::consts::FRAC_PI_2 {
        w - std::f64::consts::PI
    } else {
        w
    }
}

impl Orbit {
    /// From the sine phasors `P_x`, `P_y` with `x(t) = Im(P_x e^{iω_p t}) = |P_x| sin(ω_p t + arg P_x)`:
    /// `X = P_x/(2i)`, `Y = P_y/(2i)`, `Z₊ = X + iY`, `Z₋ = X̄ + iȲ` (docs/math/companion.md §A.6 eq. A-8).
    #[must_use]
    pub fn from_sin_phasors(omega_p_rad_s: f64, p_x_um: C64, p_y_um: C64) -> Self {
        let two_i = C64::new(0.0, 2.0);
        let (x, y) = (p_x_um / two_i, p_y_um / two_i);
        let i = C64::i();
        Self {
            omega_p_rad_s,
            z_plus_um: x + i * y,
            z_minus_um: x.conj() + i * y.conj(),
        }
    }

    /// From `A_sx, φ_sx, A_sy, φ_sy` (docs/math/companion.md §A.6 eq. A-8 with `X = A_sx e^{iφ_sx}/(2i)`).
    #[must_use]
    pub fn from_sin_pair(omega_p_rad_s: f64, s: &SinPair) -> Self {
        Self::from_sin_phasors(
            omega_p_rad_s,
            C64::from_polar(s.a_x_um, s.phi_x_rad),
            C64::from_polar(s.a_y_um, s.phi_y_rad),
        )
    }

    /// Sine phasors `(P_x, P_y)`, µm: `x = Re z ⇒ X = (Z₊ + Z̄₋)/2`, `y = Im z ⇒
    /// Y = (Z₊ − Z̄₋)/(2i)`, and `P = 2iX`, so `P_x = i(Z₊ + Z̄₋)`, `P_y = Z₊ − Z̄₋`.
    #[must_use]
    pub fn sin_phasors(&self) -> (C64, C64) {
        let i = C64::i();
        let x = (self.z_plus_um + self.z_minus_um.conj()) * 0.5;
        let y = (self.z_plus_um - self.z_minus_um.conj()) / (2.0 * i);
        (2.0 * i * x, 2.0 * i * y)
    }

    /// The x/y sinusoids (docs/math/companion.md §A.5): `A = |P|`, `φ = arg P`.
    #[must_use]
    pub fn sin_pair(&self) -> SinPair {
        let (px, py) = self.sin_phasors();
        SinPair {
            a_x_um: px.norm(),
            phi_x_rad: px.arg(),
            a_y_um: py.norm(),
            phi_y_rad: py.arg(),
        }
    }

    /// Position `(x, y)` in µm at time `t_s`: `z = Z₊ e^{iω_p t} + Z₋ e^{−iω_p t}`.
    #[must_use]
    pub fn position_um(&self, t_s: f64) -> (f64, f64) {
        let e = C64::from_polar(1.0, self.omega_p_rad_s * t_s);
        let z = self.z_plus_um * e + self.z_minus_um * e.conj();
        (z.re, z.im)
    }

    /// One planet period of the filtered orbit, `n` points (docs/math/companion.md §A.8 step 6), µm.
    #[must_use]
    pub fn trace_um(&self, n: usize) -> Vec<(f64, f64)> {
        let period = std::f64::consts::TAU / self.omega_p_rad_s.abs();
        (0..=n)
            .map(|k| self.position_um(period * k as f64 / n.max(1) as f64))
            .collect()
    }

    /// Ellipse by the branch-free full-spectrum form (docs/math/companion.md §A.6 eq. A-8):
    /// `R_L = |Z₊|+|Z₋|`, `R_S = ||Z₊|−|Z₋||`, `α_L = (arg Z₊ + arg Z₋)/2 (mod π)`.
    /// A component below [`ZERO_COMPONENT_REL`]·R_L counts as zero (circle → `α_L = None`).
    #[must_use]
    pub fn ellipse(&self) -> Ellipse {
        let (p, m) = (self.z_plus_um.norm(), self.z_minus_um.norm());
        let r_long = p + m;
        let tiny = ZERO_COMPONENT_REL * r_long;
        let alpha = if p <= tiny || m <= tiny {
            None
        } else {
            Some(wrap_half_pi(
                0.5 * (self.z_plus_um.arg() + self.z_minus_um.arg()),
            ))
        };
        let whirl = if (p - m).abs() <= tiny {
            Whirl::Line
        } else if p > m {
            Whirl::Forward
        } else {
            Whirl::Backward
        };
        let ccw = match whirl {
            Whirl::Line => None,
            w => Some((w == Whirl::Forward) != (self.omega_p_rad_s < 0.0)),
        };
        Ellipse {
            r_long_um: r_long,
            r_short_um: (p - m).abs(),
            alpha_long_rad: alpha,
            whirl,
            counter_clockwise: ccw,
        }
    }

    /// Residual of the implicit ellipse equation (docs/math/companion.md §A.6 eq. A-6),
    /// `x²/A_x² − 2xy cosΔ/(A_x A_y) + y²/A_y² − sin²Δ`, at the point `(x, y)` µm (dimensionless);
    /// `None` when A_x or A_y is zero (the implicit form is undefined for a degenerate orbit).
    #[must_use]
    pub fn implicit_residual(&self, x_um: f64, y_um: f64) -> Option<f64> {
        let s = self.sin_pair();
        if s.a_x_um == 0.0 || s.a_y_um == 0.0 {
            return None;
        }
        let d = s.phi_y_rad - s.phi_x_rad;
        Some(
            x_um * x_um / (s.a_x_um * s.a_x_um)
                - 2.0 * x_um * y_um * d.cos() / (s.a_x_um * s.a_y_um)
                + y_um * y_um / (s.a_y_um * s.a_y_um)
                - d.sin().powi(2),
        )
    }
}

/// Semi-axes and orientation by the Group-8 closed form (docs/math/companion.md §A.6 eq. A-7), for cross-checking [`Orbit::ellipse`]:
/// `S = √((A_x²−A_y²)² + 4A_x²A_y²cos²Δ)`, `R_L = √((A_x²+A_y²+S)/2)`,
/// `R_S = √(max(0, (A_x²+A_y²−S)/2))`, `α_L = ½ atan2(2A_xA_y cosΔ, A_x²−A_y²)`; returns
/// `(R_L µm, R_S µm, α_L rad)`.
#[must_use]
pub fn ellipse_group8(s: &SinPair) -> (f64, f64, f64) {
    let (ax2, ay2) = (s.a_x_um * s.a_x_um, s.a_y_um * s.a_y_um);
    let cd = (s.phi_y_rad - s.phi_x_rad).cos();
    let big_s = ((ax2 - ay2).powi(2) + 4.0 * ax2 * ay2 * cd * cd).sqrt();
    let r_l = (0.5 * (ax2 + ay2 + big_s)).sqrt();
    let r_s = (0.5 * (ax2 + ay2 - big_s)).max(0.0).sqrt();
    let alpha = 0.5 * (2.0 * s.a_x_um * s.a_y_um * cd).atan2(ax2 - ay2);
    (r_l, r_s, alpha)
}
