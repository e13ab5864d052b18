//! Serializable reports of the three orbit stages (model, measure, identify): exactly what
//! `ncgear orbit … --json` prints, for pipelines that call the library instead of the CLI.
//!
//! The CLI prints `serde_json::to_value(report)`, whose objects list their keys in alphabetical
//! order; the fields below are in reading order. Units as the field names say (µm, rad, deg, rad/s).

use super::identify::identify;
use super::measure::{Comparison, Extractor, Frame, Measurement, Method, Uncertainty};
use super::model::{GearSpeeds, Line, ModelParams, PlanetSet};
use super::{C64, Ellipse, Orbit, OrbitError, Whirl};
use serde::Serialize;

/// A complex amplitude in Cartesian and polar form, µm.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, schemars::JsonSchema)]
pub struct PhasorSummary {
    /// Real part, µm.
    pub re: f64,
    /// Imaginary part, µm.
    pub im: f64,
    /// Modulus `|z|`, µm.
    pub abs: f64,
    /// Argument `arg z`, rad in (−π, π].
    pub arg_rad: f64,
}

impl From<C64> for PhasorSummary {
    fn from(z: C64) -> Self {
        Self {
            re: z.re,
            im: z.im,
            abs: z.norm(),
            arg_rad: z.arg(),
        }
    }
}

/// An [`Ellipse`] with the major-axis angle also in degrees.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, schemars::JsonSchema)]
pub struct EllipseSummary {
    /// Semi-major axis R_L = |Z₊| + |Z₋|, µm.
    pub r_long_um: f64,
    /// Semi-minor axis R_S = ||Z₊| − |Z₋||, µm.
    pub r_short_um: f64,
    /// Major-axis angle α_L, rad in (−π/2, π/2]; `None` for a circle.
    pub alpha_long_rad: Option<f64>,
    /// α_L in degrees.
    pub alpha_long_deg: Option<f64>,
    /// Sense relative to ω_p.
    pub whirl: Whirl,
    /// Physical sense in the carrier frame (`None` for a straight line).
    pub counter_clockwise: Option<bool>,
}

impl From<&Ellipse> for EllipseSummary {
    fn from(e: &Ellipse) -> Self {
        Self {
            r_long_um: e.r_long_um,
            r_short_um: e.r_short_um,
            alpha_long_rad: e.alpha_long_rad,
            alpha_long_deg: e.alpha_long_rad.map(f64::to_degrees),
            whirl: e.whirl,
            counter_clockwise: e.counter_clockwise,
        }
    }
}

/// An [`Orbit`] with its sinusoids (docs/math/companion.md §A.5), phasors and ellipse (docs/math/companion.md §A.6–§A.8).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, schemars::JsonSchema)]
pub struct OrbitSummary {
    /// Signed planet spin relative to the carrier ω_p, rad/s.
    pub omega_p_rad_s: f64,
    /// A_sx in `x = A_sx sin(ω_p t + φ_sx)`, µm.
    pub a_sx_um: f64,
    /// φ_sx, rad.
    pub phi_sx_rad: f64,
    /// A_sy in `y = A_sy sin(ω_p t + φ_sy)`, µm.
    pub a_sy_um: f64,
    /// φ_sy, rad.
    pub phi_sy_rad: f64,
    /// Forward component Z₊, µm.
    pub z_plus_um: PhasorSummary,
    /// Backward component Z₋, µm.
    pub z_minus_um: PhasorSummary,
    /// The ellipse.
    pub ellipse: EllipseSummary,
}

impl From<&Orbit> for OrbitSummary {
    fn from(o: &Orbit) -> Self {
        let s = o.sin_pair();
        Self {
            omega_p_rad_s: o.omega_p_rad_s,
            a_sx_um: s.a_x_um,
            phi_sx_rad: s.phi_x_rad,
            a_sy_um: s.a_y_um,
            phi_sy_rad: s.phi_y_rad,
            z_plus_um: o.z_plus_um.into(),
            z_minus_um: o.z_minus_um.into(),
            ellipse: (&o.ellipse()).into(),
        }
    }
}

impl OrbitSummary {
    /// The summarized orbit (exact: rebuilt from the Cartesian parts of Z±).
    #[must_use]
    pub fn orbit(&self) -> Orbit {
        Orbit {
            omega_p_rad_s: self.omega_p_rad_s,
            z_plus_um: C64::new(self.z_plus_um.re, self.z_plus_um.im),
            z_minus_um: C64::new(self.z_minus_um.re, self.z_minus_um.im),
        }
    }
}

/// Common-mode (transmission-error) displacement `c = amplitude · sin(ω_p t + phase)`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, schemars::JsonSchema)]
pub struct CommonMode {
    /// |P_c|, µm.
    pub amplitude_um: f64,
    /// arg P_c, rad.
    pub phase_rad: f64,
}

/// Result of the kinematic model (docs/math/companion.md §A.3–§A.7) for a parameter file.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct ModelReport {
    /// Sun orbit in the carrier frame.
    pub orbit: OrbitSummary,
    /// Common mode along the lines of action, µm.
    pub common_mode_um: CommonMode,
    /// Whether the kinematic solution is the equal-stiffness one for any load (docs/math/companion.md §A.4).
    pub load_independent: bool,
    /// Gear speeds when the file has `[gears]`.
    pub gear_speeds: Option<GearSpeeds>,
    /// Line-of-action angles β_i, rad.
    pub line_of_action_angles_rad: Vec<f64>,
}

impl ModelReport {
    /// Solves the kinematic model of `params`.
    ///
    /// # Errors
    /// [`OrbitError::Invalid`] naming the offending key ([`ModelParams::planet_set`]).
    pub fn new(params: &ModelParams) -> Result<Self, OrbitError> {
        let set = params.planet_set()?;
        let speeds = params.gear_speeds()?;
        let sol = set.solve();
        let c = sol.common_mode_um;
        Ok(Self {
            orbit: (&sol.orbit).into(),
            common_mode_um: CommonMode {
                amplitude_um: c.norm(),
                phase_rad: c.arg(),
            },
            load_independent: sol.load_independent,
            gear_speeds: speeds,
            line_of_action_angles_rad: set.line_of_action_angles_rad(),
        })
    }
}

/// Residual RMS of the two channels after the fit, µm.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, schemars::JsonSchema)]
pub struct XyRms {
    /// x channel, µm.
    pub x: f64,
    /// y channel, µm.
    pub y: f64,
}

/// Result of evaluating a sensor record (docs/math/companion.md §A.7–§A.8), with the comparison to the model if any.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct MeasureReport {
    /// Estimator used.
    pub method: Method,
    /// Sensor frame.
    pub frame: Frame,
    /// Extracted orbit (carrier frame).
    pub orbit: OrbitSummary,
    /// 1-σ uncertainties (least squares only).
    pub uncertainty_1sigma: Option<Uncertainty>,
    /// Condition number of the column-scaled regression matrix (least squares only).
    pub condition_number: Option<f64>,
    /// Residual RMS after the fit (least squares only).
    pub residual_rms_um: Option<XyRms>,
    /// Analysed lines (signed rad/s, analysis frame).
    pub lines: Vec<Line>,
    /// Collision and sampling warnings.
    pub warnings: Vec<String>,
    /// ω_p of the extraction (the estimated one when `frequency_estimated`), rad/s.
    pub omega_p_rad_s: f64,
    /// Whether ω_p was estimated from the record.
    pub frequency_estimated: bool,
    /// Record length T_rec, s.
    pub record_length_s: f64,
    /// Number of samples.
    pub samples: usize,
    /// Measured minus model (docs/math/companion.md §A.8 step 7), when a model is given.
    pub comparison_with_model: Option<Comparison>,
}

impl MeasureReport {
    /// The report of measurement `m` taken by `extractor` (`frequency_estimated` when its ω_p came
    /// from the record), compared with `model` if given.
    #[must_use]
    pub fn new(
        m: &Measurement,
        extractor: &Extractor,
        frequency_estimated: bool,
        model: Option<&PlanetSet>,
    ) -> Self {
        Self {
            method: extractor.method(),
            frame: extractor.frame(),
            orbit: (&m.orbit).into(),
            uncertainty_1sigma: m.uncertainty,
            condition_number: m.condition_number,
            residual_rms_um: m.residual_rms_um.map(|(x, y)| XyRms { x, y }),
            lines: m.lines.clone(),
            warnings: m.warnings.clone(),
            omega_p_rad_s: extractor.omega_p_rad_s(),
            frequency_estimated,
            record_length_s: m.record_length_s,
            samples: m.samples,
            comparison_with_model: model.map(|set| Comparison::new(&m.orbit, &set.solve().orbit)),
        }
    }
}

/// One identified planet phasor `E_i = e_i e^{i(θ_p0+θ_pi)}`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, schemars::JsonSchema)]
pub struct PlanetPhasor {
    /// e_i = |E_i|, µm.
    pub eccentricity_um: f64,
    /// arg E_i, rad.
    pub phase_rad: f64,
    /// arg E_i, degrees.
    pub phase_deg: f64,
}

/// Result of the identification (docs/math/companion.md §A.9).
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct IdentifyReport {
    /// Minimum-norm planet phasors, in planet order.
    pub planets: Vec<PlanetPhasor>,
    /// Orthonormal basis of the unobservable directions (empty when fully identified).
    pub null_space: Vec<Vec<f64>>,
    /// Whether the common mode is observable (`null_space` empty).
    pub common_mode_observable: bool,
    /// Whether a transmission-error channel was used.
    pub used_transmission_error: bool,
    /// What is and is not observable.
    pub statement: String,
    /// The orbit identified from, at the model's ω_p.
    pub orbit: OrbitSummary,
}

impl IdentifyReport {
    /// Identifies the planet phasors of `set` from `orbit` and, optionally, the transmission-error
    /// sine phasor at ω_p (µm). The orbit's phasors are taken at the model's ω_p whatever its own
    /// (e.g. an estimated one): the model's map is linear in them.
    ///
    /// # Errors
    /// [`OrbitError::Invalid`] for non-finite data.
    pub fn new(
        set: &PlanetSet,
        orbit: &Orbit,
        transmission_error_um: Option<C64>,
    ) -> Result<Self, OrbitError> {
        let orbit = Orbit {
            omega_p_rad_s: set.omega_p_rad_s(),
            ..*orbit
        };
        let id = identify(&set.kinematic_map(), &orbit, transmission_error_um)?;
        Ok(Self {
            planets: id
                .phasors_um
                .iter()
                .map(|e| PlanetPhasor {
                    eccentricity_um: e.norm(),
                    phase_rad: e.arg(),
                    phase_deg: e.arg().to_degrees(),
                })
                .collect(),
            common_mode_observable: id.null_space.is_empty(),
            null_space: id.null_space,
            used_transmission_error: id.used_transmission_error,
            statement: id.statement,
            orbit: (&orbit).into(),
        })
    }
}
