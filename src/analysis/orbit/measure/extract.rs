//! The configured extractor (frame, estimator, nuisance lines, limits) and its result: the
//! planet-frequency orbit of a record with uncertainty, condition number and warnings (docs/math/companion.md §A.7–§A.8).

use super::frame::{Frame, detrend, rotate};
use super::record::Record;
use super::spectrum::{dtft, hann_dtft, synchronous, synchronous_tach};
use crate::analysis::orbit::model::{Line, LineKind};
use crate::analysis::orbit::{C64, Orbit, OrbitError, invalid};
use std::f64::consts::{PI, TAU};

/// Estimator of the planet-frequency components (docs/math/companion.md §A.8).
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "snake_case")]
pub enum Method {
    /// Linear least squares at the known frequencies with nuisance lines and drift (default).
    LeastSquares,
    /// Hann-windowed DTFT evaluated at the exact known frequency (needs uniform sampling).
    HannDtft,
    /// Resampling to an integer number of planet revolutions (cubic interpolation) + one DFT bin
    /// (synchronous average); carrier frame or de-rotated only; needs uniform sampling.
    Synchronous,
    /// Rectangular window, nearest FFT bin: biased on non-integer records — for contrast only.
    PlainFft,
}

/// How an [`Extractor`] evaluates a record (docs/math/companion.md §A.7, §A.8). Start from
/// [`ExtractOptions::default`] and set the fields that differ with `with_*`; (de)serialisable (a
/// missing field takes its default, an unknown one is an error).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
#[non_exhaustive]
pub struct ExtractOptions {
    /// Sensor frame. Default [`Frame::Carrier`].
    pub frame: Frame,
    /// Estimator. Default [`Method::LeastSquares`].
    pub method: Method,
    /// Remove a linear drift (`true`) or only the mean (`false`). Default `true`.
    pub drift: bool,
    /// Known interfering lines in the analysis frame (signed rad/s); lines of kind
    /// [`LineKind::Planet`] are ignored (the planet lines follow from ω_p and the frame).
    /// Default none.
    pub nuisance: Vec<Line>,
    /// Refuse the least-squares fit above this condition number of the column-scaled regression
    /// matrix (must exceed 1). Default 1e6.
    pub max_condition: f64,
    /// Warn when two analysed lines are closer than this many DFT bins `1/T_rec` (≥ 0). Default 3.
    pub min_separation_bins: f64,
}

crate::builder::with_fields!(ExtractOptions {
    with_frame => frame: Frame,
    with_method => method: Method,
    with_drift => drift: bool,
    with_nuisance => nuisance: Vec<Line>,
    with_max_condition => max_condition: f64,
    with_min_separation_bins => min_separation_bins: f64,
});

impl Default for ExtractOptions {
    fn default() -> Self {
        Self {
            frame: Frame::Carrier,
            method: Method::LeastSquares,
            drift: true,
            nuisance: Vec::new(),
            max_condition: 1e6,
            min_separation_bins: 3.0,
        }
    }
}

/// A validated extractor of the planet-frequency orbit; see [`Extractor::new`].
#[derive(Debug, Clone, PartialEq)]
pub struct Extractor {
    /// Signed ω_p, rad/s (finite, non-zero).
    pub(super) omega_p_rad_s: f64,
    /// Validated options; `nuisance` holds only [`LineKind::Nuisance`] lines.
    pub(super) opts: ExtractOptions,
}

impl Extractor {
    /// An extractor for the signed planet spin ω_p relative to the carrier, rad/s, configured by
    /// `opts`.
    ///
    /// # Errors
    /// [`OrbitError::Invalid`] for a zero/non-finite ω_p or ω_c, non-finite lines, a condition limit
    /// ≤ 1, a negative separation, or synchronous resampling in the full-spectrum frame.
    pub fn new(omega_p_rad_s: f64, mut opts: ExtractOptions) -> Result<Self, OrbitError> {
        opts.nuisance.retain(|l| l.kind == LineKind::Nuisance);
        if !(omega_p_rad_s.is_finite() && omega_p_rad_s != 0.0) {
            return Err(invalid("planet_speed", "must be finite and non-zero"));
        }
        if let Frame::HousingFullSpectrum { carrier_rad_s } = opts.frame {
            if !(carrier_rad_s.is_finite() && carrier_rad_s != 0.0) {
                return Err(invalid(
                    "carrier_speed",
                    "must be finite and non-zero in the housing frame",
                ));
            }
            if opts.method == Method::Synchronous {
                return Err(invalid(
                    "method",
                    "synchronous resampling needs the carrier frame (or de-rotation)",
                ));
            }
        }
        if let Some(l) = opts.nuisance.iter().find(|l| !l.omega_rad_s.is_finite()) {
            return Err(invalid(
                format!("line `{}`", l.label),
                "frequency must be finite",
            ));
        }
        if opts.max_condition.is_nan() || opts.max_condition <= 1.0 {
            return Err(invalid("max_condition", "must exceed 1"));
        }
        if opts.min_separation_bins.is_nan() || opts.min_separation_bins < 0.0 {
            return Err(invalid("min_separation_bins", "must be ≥ 0"));
        }
        Ok(Self {
            omega_p_rad_s,
            opts,
        })
    }

    /// The validated options (nuisance lines of kind [`LineKind::Nuisance`] only).
    #[must_use]
    pub fn options(&self) -> &ExtractOptions {
        &self.opts
    }
}

/// 1-σ uncertainties of an extraction (from the least-squares covariance `σ̂²(MᵀM)⁻¹`, x and y
/// noise taken independent).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, schemars::JsonSchema)]
pub struct Uncertainty {
    /// σ(A_sx), µm.
    pub a_x_um: f64,
    /// σ(φ_sx), rad.
    pub phi_x_rad: f64,
    /// σ(A_sy), µm.
    pub a_y_um: f64,
    /// σ(φ_sy), rad.
    pub phi_y_rad: f64,
    /// σ(|Z₊|), µm.
    pub z_plus_um: f64,
    /// σ(|Z₋|), µm.
    pub z_minus_um: f64,
}

/// Result of [`Extractor::extract`].
#[derive(Debug, Clone, PartialEq)]
pub struct Measurement {
    /// Extracted orbit (carrier frame).
    pub orbit: Orbit,
    /// 1-σ uncertainties (least squares only).
    pub uncertainty: Option<Uncertainty>,
    /// Condition number of the column-scaled regression matrix (least squares only).
    pub condition_number: Option<f64>,
    /// Residual RMS of x and y after the fit, µm (least squares only).
    pub residual_rms_um: Option<(f64, f64)>,
    /// Analysed lines (signed rad/s, analysis frame).
    pub lines: Vec<Line>,
    /// Collision and sampling warnings.
    pub warnings: Vec<String>,
    /// Record length T_rec, s.
    pub record_length_s: f64,
    /// Number of samples.
    pub samples: usize,
}

impl Extractor {
    /// Signed ω_p, rad/s.
    #[must_use]
    pub fn omega_p_rad_s(&self) -> f64 {
        self.omega_p_rad_s
    }

    /// Sensor frame.
    #[must_use]
    pub fn frame(&self) -> Frame {
        self.opts.frame
    }

    /// Whether a linear drift is removed (else only the mean).
    #[must_use]
    pub fn drift(&self) -> bool {
        self.opts.drift
    }

    /// Estimator.
    #[must_use]
    pub fn method(&self) -> Method {
        self.opts.method
    }

    /// Planet lines `(ω₊, ω₋)` of the analysis frame, signed rad/s.
    pub(super) fn target_omegas(&self) -> (f64, f64) {
        let wc = match self.opts.frame {
            Frame::HousingFullSpectrum { carrier_rad_s } => carrier_rad_s,
            _ => 0.0,
        };
        (wc + self.omega_p_rad_s, wc - self.omega_p_rad_s)
    }

    /// The detrended (mean, and drift if configured, removed in the sensor frame) signal in the
    /// analysis frame (de-rotated for [`Frame::HousingDerotate`]), µm — e.g. for plotting the raw orbit.
    ///
    /// # Errors
    /// [`OrbitError::Record`] when de-rotation is asked without a carrier angle.
    pub fn analysis_signal(&self, rec: &Record) -> Result<(Vec<f64>, Vec<f64>), OrbitError> {
        match self.opts.frame {
            Frame::HousingDerotate => {
                let c = rec.carrier_angle_rad().ok_or_else(|| {
                    OrbitError::Record(
                        "de-rotation needs a carrier angle column (carrier_deg)".into(),
                    )
                })?;
                // Sensor offsets and drift live in the housing frame: remove them there first.
                let (x, y) = detrend(rec.t_s(), rec.x_um(), rec.y_um(), self.opts.drift);
                Ok(rotate(&x, &y, c, -1.0))
            }
            _ => Ok(detrend(rec.t_s(), rec.x_um(), rec.y_um(), self.opts.drift)),
        }
    }

    /// Collision / aliasing warnings for the analysed lines.
    fn warnings(&self, rec: &Record, lines: &[Line]) -> Vec<String> {
        let mut w = Vec::new();
        let bin = TAU / rec.duration_s();
        let min_sep = self.opts.min_separation_bins * bin;
        let nyq = PI / rec.mean_step_s();
        // The real least squares sees |ω|; the complex DFT methods see signed ω.
        let real = self.opts.method == Method::LeastSquares;
        let f = |l: &Line| {
            if real {
                l.omega_rad_s.abs()
            } else {
                l.omega_rad_s
            }
        };
        // In the real fit a line duplicating an earlier one of the same kind (same |ω|) is merged.
        let dup: Vec<bool> = (0..lines.len())
            .map(|j| {
                real && lines[..j].iter().any(|b| {
                    b.kind == lines[j].kind
                        && (f(b) - f(&lines[j])).abs() <= 1e-12 * f(b).max(f(&lines[j]))
                })
            })
            .collect();
        for (i, a) in lines.iter().enumerate() {
            if dup[i] {
                continue;
            }
            if a.omega_rad_s.abs() > nyq {
                w.push(format!(
                    "line `{}` at {:.6} Hz is above the Nyquist frequency {:.6} Hz (aliased)",
                    a.label,
                    a.omega_rad_s / TAU,
                    nyq / TAU
                ));
            }
            for (j, b) in lines[..i].iter().enumerate() {
                if dup[j] {
                    continue;
                }
                let d = (f(a) - f(b)).abs();
                if d < min_sep {
                    w.push(format!(
                        "lines `{}` ({:.6} Hz) and `{}` ({:.6} Hz) are {:.3} bins apart (< {} bins = {:.3e} Hz)",
                        a.label,
                        a.omega_rad_s / TAU,
                        b.label,
                        b.omega_rad_s / TAU,
                        d / bin,
                        self.opts.min_separation_bins,
                        min_sep / TAU
                    ));
                }
            }
        }
        w
    }

    /// Extracts the planet-frequency orbit from a record.
    ///
    /// # Errors
    /// [`OrbitError::Collision`] when the least-squares matrix is too ill-conditioned,
    /// [`OrbitError::Record`] when the method needs what the record lacks (carrier angle, uniform
    /// sampling, at least one whole planet revolution).
    pub fn extract(&self, rec: &Record) -> Result<Measurement, OrbitError> {
        let (wp, wm) = self.target_omegas();
        let mut lines = vec![
            Line::new("planet Z+", wp, LineKind::Planet),
            Line::new("planet Z-", wm, LineKind::Planet),
        ];
        lines.extend(self.opts.nuisance.iter().cloned());
        let warnings = self.warnings(rec, &lines);
        let mut m = Measurement {
            orbit: Orbit {
                omega_p_rad_s: self.omega_p_rad_s,
                z_plus_um: C64::new(0.0, 0.0),
                z_minus_um: C64::new(0.0, 0.0),
            },
            uncertainty: None,
            condition_number: None,
            residual_rms_um: None,
            lines,
            warnings,
            record_length_s: rec.duration_s(),
            samples: rec.len(),
        };
        match self.opts.method {
            Method::LeastSquares if self.opts.frame == Frame::HousingDerotate => {
                self.least_squares_derotated(rec, &mut m)?
            }
            Method::LeastSquares => {
                self.least_squares(rec.t_s(), rec.x_um(), rec.y_um(), &mut m)?;
            }
            other => {
                let (x, y) = self.analysis_signal(rec)?;
                if !rec.is_uniform(1e-6) {
                    return Err(OrbitError::Record(format!(
                        "{other:?} needs uniformly sampled data (steps within 1e-6)"
                    )));
                }
                let z: Vec<C64> = x.iter().zip(&y).map(|(a, b)| C64::new(*a, *b)).collect();
                let (zp, zm) = match other {
                    Method::HannDtft => {
                        (hann_dtft(rec.t_s(), &z, wp), hann_dtft(rec.t_s(), &z, wm))
                    }
                    Method::PlainFft => {
                        let bin = TAU / rec.duration_s();
                        let b = |w: f64| (w / bin).round() * bin;
                        (
                            dtft(rec.t_s(), &z, b(wp), None),
                            dtft(rec.t_s(), &z, b(wm), None),
                        )
                    }
                    _ => match rec.tach_pulses_s() {
                        Some(p) => synchronous_tach(rec, &z, p, self.omega_p_rad_s.signum())?,
                        None => synchronous(rec, &z, self.omega_p_rad_s)?,
                    },
                };
                m.orbit.z_plus_um = zp;
                m.orbit.z_minus_um = zm;
            }
        }
        let finite = [m.orbit.z_plus_um, m.orbit.z_minus_um]
            .iter()
            .all(|z| z.re.is_finite() && z.im.is_finite())
            && m.condition_number.is_none_or(f64::is_finite)
            && m.residual_rms_um
                .is_none_or(|(a, b)| a.is_finite() && b.is_finite());
        if !finite {
            return Err(OrbitError::Record(
                "the extraction gave a non-finite result (values too large or a degenerate \
                 time base)"
                    .into(),
            ));
        }
        Ok(m)
    }

    /// A copy of this extractor at another signed ω_p (e.g. an estimated one).
    ///
    /// # Errors
    /// [`OrbitError::Invalid`] for a zero or non-finite ω_p.
    pub fn with_omega_p(&self, omega_p_rad_s: f64) -> Result<Self, OrbitError> {
        Self::new(omega_p_rad_s, self.opts.clone())
    }
}
