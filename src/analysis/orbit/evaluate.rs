//! Setting up the evaluation of sensor records from a model file or given speeds: ω_p, the sensor
//! frame and the expected nuisance lines (docs/math/companion.md §A.7), the optional frequency refinement (docs/math/companion.md §A.8 step 3) and
//! the [`MeasureReport`].
//!
//! ```
//! use ncgear::analysis::orbit::evaluate::{Evaluation, MeasureOptions};
//! let opts = MeasureOptions::default().with_planet_speed_rpm(Some(-120.0));
//! let ev = Evaluation::new(None, &opts).unwrap();
//! assert!((ev.extractor().omega_p_rad_s() + 4.0 * std::f64::consts::PI).abs() < 1e-12);
//! ```

use super::measure::{
    ExtractOptions, Extractor, Frame, FrequencyEstimate, Measurement, Method, Record,
};
use super::model::{Line, LineKind, ModelParams, PlanetSet, rpm_to_rad_s};
use super::report::MeasureReport;
use super::{OrbitError, invalid};
use crate::progress::Progress;
use std::f64::consts::TAU;

/// Where the sensors sit; the carrier speed of [`Frame::HousingFullSpectrum`] is found by
/// [`Evaluation::new`].
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "snake_case")]
pub enum SensorFrame {
    /// Sensors on the carrier, or carrier held ([`Frame::Carrier`]).
    Carrier,
    /// Housing sensors de-rotated with the recorded carrier angle ([`Frame::HousingDerotate`]).
    Derotate,
    /// Housing sensors, constant carrier speed, full spectrum ([`Frame::HousingFullSpectrum`]).
    Housing,
}

/// How to evaluate records. Start from [`MeasureOptions::default`] and set the fields that differ
/// with `with_*`; (de)serialisable (a missing field takes its default, an unknown one is an
/// error).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
#[non_exhaustive]
pub struct MeasureOptions {
    /// Signed planet speed relative to the carrier, rpm; exclusive with a model, which gives ω_p.
    /// Default `None`.
    pub planet_speed_rpm: Option<f64>,
    /// Sensor frame. Default [`SensorFrame::Carrier`].
    pub frame: SensorFrame,
    /// Signed carrier speed, rpm, for [`SensorFrame::Housing`]; `None` takes it from the model's
    /// `[gears]`. Default `None`.
    pub carrier_speed_rpm: Option<f64>,
    /// Estimator. Default [`Method::LeastSquares`].
    pub method: Method,
    /// Extra nuisance lines, signed Hz in the analysis frame. Default none.
    pub line_hz: Vec<f64>,
    /// Mesh harmonics added as nuisance lines when the model has `[gears]`, at most
    /// [`MAX_MESH_HARMONICS`]. Default 2.
    pub mesh_harmonics: u32,
    /// Remove a linear drift (`true`) or only the mean (`false`). Default `true`.
    pub drift: bool,
    /// Treat ω_p as approximate and estimate it from the record (interpolated Hann spectrum within
    /// ±[`SEARCH_REL`]·|ω_p|, then least-squares refinement). Default `false`.
    pub estimate_frequency: bool,
    /// Refuse the least-squares fit above this condition number. Default 1e6.
    pub max_condition: f64,
}

crate::builder::with_fields!(MeasureOptions {
    with_planet_speed_rpm => planet_speed_rpm: Option<f64>,
    with_frame => frame: SensorFrame,
    with_carrier_speed_rpm => carrier_speed_rpm: Option<f64>,
    with_method => method: Method,
    with_line_hz => line_hz: Vec<f64>,
    with_mesh_harmonics => mesh_harmonics: u32,
    with_drift => drift: bool,
    with_estimate_frequency => estimate_frequency: bool,
    with_max_condition => max_condition: f64,
});

impl Default for MeasureOptions {
    fn default() -> Self {
        Self {
            planet_speed_rpm: None,
            frame: SensorFrame::Carrier,
            carrier_speed_rpm: None,
            method: Method::LeastSquares,
            line_hz: Vec::new(),
            mesh_harmonics: 2,
            drift: true,
            estimate_frequency: false,
            max_condition: 1e6,
        }
    }
}

/// Most mesh harmonics of [`MeasureOptions::mesh_harmonics`] (two nuisance lines each).
pub const MAX_MESH_HARMONICS: u32 = 32;

/// Relative half-width of the ω_p search band of the frequency estimate.
pub const SEARCH_REL: f64 = 0.1;

/// Tolerance of the ω_p refinement relative to |ω_p|.
pub const REFINE_TOL_REL: f64 = 1e-10;

/// A configured evaluation: the extractor (ω_p, frame, nuisance lines) and the model, if any.
#[derive(Debug, Clone)]
pub struct Evaluation {
    extractor: Extractor,
    estimate: bool,
    model: Option<PlanetSet>,
}

impl Evaluation {
    /// ω_p from `model` or `opts.planet_speed_rpm` (exactly one); the frame, with the carrier speed
    /// from `opts` or the model's `[gears]`; nuisance lines: the expected lines of `[gears]`
    /// ([`GearSpeeds::expected_lines`](super::model::GearSpeeds::expected_lines)) and
    /// `opts.line_hz`.
    ///
    /// # Errors
    /// [`OrbitError::Invalid`] naming the missing or conflicting field (`planet_speed_rpm`,
    /// `carrier_speed_rpm`), a bad model, or an invalid extractor ([`Extractor::new`]).
    pub fn new(model: Option<&ModelParams>, opts: &MeasureOptions) -> Result<Self, OrbitError> {
        if opts.mesh_harmonics > MAX_MESH_HARMONICS {
            return Err(invalid(
                "mesh_harmonics",
                "at most 32: each harmonic adds two nuisance lines to the least-squares fit, and \
                 harmonics beyond the first few lie above any record's bandwidth",
            ));
        }
        let model = model
            .map(|p| Ok::<_, OrbitError>((p.planet_set()?, p.gear_speeds()?)))
            .transpose()?;
        let speeds = model.as_ref().and_then(|m| m.1);
        let omega_p = match (&model, opts.planet_speed_rpm) {
            (Some(_), Some(_)) => {
                return Err(invalid(
                    "planet_speed_rpm",
                    "give either a model or planet_speed_rpm, not both",
                ));
            }
            (Some((set, _)), None) => set.omega_p_rad_s(),
            (None, Some(rpm)) => rpm_to_rad_s(rpm),
            (None, None) => {
                return Err(invalid(
                    "planet_speed_rpm",
                    "missing: give a model or planet_speed_rpm",
                ));
            }
        };
        let frame = match opts.frame {
            SensorFrame::Carrier => Frame::Carrier,
            SensorFrame::Derotate => Frame::HousingDerotate,
            SensorFrame::Housing => {
                let wc = match (opts.carrier_speed_rpm, speeds) {
                    (Some(rpm), _) => rpm_to_rad_s(rpm),
                    (None, Some(g)) => g.carrier_rad_s,
                    (None, None) => {
                        return Err(invalid(
                            "carrier_speed_rpm",
                            "missing: the housing frame needs carrier_speed_rpm or [gears] in \
                             the model",
                        ));
                    }
                };
                Frame::HousingFullSpectrum { carrier_rad_s: wc }
            }
        };
        let mut lines: Vec<Line> = speeds
            .map(|g| {
                g.expected_lines(
                    matches!(frame, Frame::HousingFullSpectrum { .. }),
                    opts.mesh_harmonics,
                )
            })
            .unwrap_or_default();
        lines.extend(
            opts.line_hz
                .iter()
                .map(|f| Line::new(format!("user {f} Hz"), f * TAU, LineKind::Nuisance)),
        );
        let ex = ExtractOptions {
            frame,
            method: opts.method,
            drift: opts.drift,
            nuisance: lines,
            max_condition: opts.max_condition,
            ..ExtractOptions::default()
        };
        Ok(Self {
            extractor: Extractor::new(omega_p, ex)?,
            estimate: opts.estimate_frequency,
            model: model.map(|m| m.0),
        })
    }

    /// The configured extractor (at the estimated ω_p after [`Evaluation::refine_frequency`]).
    #[must_use]
    pub fn extractor(&self) -> &Extractor {
        &self.extractor
    }

    /// The model's planet set, if a model was given.
    #[must_use]
    pub fn model(&self) -> Option<&PlanetSet> {
        self.model.as_ref()
    }

    /// Whether ω_p is estimated from the record.
    #[must_use]
    pub fn estimates_frequency(&self) -> bool {
        self.estimate
    }

    /// Upper bound of the refinement iterations of [`Evaluation::refine_frequency`] on `rec`
    /// (for a progress bar).
    #[must_use]
    pub fn refine_iterations(&self, rec: &Record) -> u64 {
        Extractor::frequency_iterations(rec.duration_s(), self.refine_tol_rad_s())
    }

    fn refine_tol_rad_s(&self) -> f64 {
        REFINE_TOL_REL * self.extractor.omega_p_rad_s().abs()
    }

    /// When the options ask for it, estimates ω_p from `rec`
    /// ([`Extractor::estimate_frequency`], band ±[`SEARCH_REL`], tolerance [`REFINE_TOL_REL`]·|ω_p|)
    /// and moves the extractor there; `progress` receives the iterations done. `None` otherwise.
    ///
    /// # Errors
    /// As [`Extractor::estimate_frequency`].
    pub fn refine_frequency(
        &mut self,
        rec: &Record,
        progress: &Progress,
    ) -> Result<Option<FrequencyEstimate>, OrbitError> {
        if !self.estimate {
            return Ok(None);
        }
        let tol = self.refine_tol_rad_s();
        let est = self
            .extractor
            .estimate_frequency(rec, SEARCH_REL, tol, progress)?;
        self.extractor = self.extractor.with_omega_p(est.refined_rad_s)?;
        Ok(Some(est))
    }

    /// Extracts the planet-frequency orbit of `rec` ([`Extractor::extract`]).
    ///
    /// # Errors
    /// As [`Extractor::extract`].
    pub fn extract(&self, rec: &Record) -> Result<Measurement, OrbitError> {
        self.extractor.extract(rec)
    }

    /// The report of `m` (taken by [`Evaluation::extract`]), compared with the model if any.
    #[must_use]
    pub fn report(&self, m: &Measurement) -> MeasureReport {
        MeasureReport::new(m, &self.extractor, self.estimate, self.model.as_ref())
    }
}
