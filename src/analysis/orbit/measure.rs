//! Evaluation of sun-displacement sensor records (spec A.7–A.8).
//!
//! Pipeline of [`Extractor::extract`]:
//!
//! 1. **Frame** (A.7): the model lives in the carrier frame. Housing-fixed sensors on a rotating
//!    carrier are either de-rotated with the measured carrier angle, `z_c = e^{−iθ_c} z_r`
//!    ([`Frame::HousingDerotate`]), or analysed in the full (complex) spectrum of `z_r = x_r + i y_r`,
//!    reading Z₊ at the signed frequency `ω_c + ω_p` and Z₋ at `ω_c − ω_p`
//!    ([`Frame::HousingFullSpectrum`]).
//! 2. **Collision check**: every pair of analysed lines closer than `min_separation_bins / T_rec`
//!    (Hz) gives a warning; the least-squares fit refuses a condition number above `max_condition`
//!    ([`OrbitError::Collision`]).
//! 3. **Extraction** at the known planet frequency ([`Method`]): linear least squares with the
//!    regressors `[1, t, sin ω_k t, cos ω_k t …]` for the planet line(s) and every nuisance line
//!    (default; exact for any non-integer number of periods, with drift, and gives the covariance
//!    `σ̂² (MᵀM)⁻¹`), or the Hann-windowed DTFT at the exact frequency, or synchronous resampling to
//!    an integer number of planet revolutions, or — for contrast only — the nearest plain FFT bin.
//! 4. Ellipse, sense and filtered orbit from the resulting [`Orbit`] (A.6, A.8 step 6).
//!
//! The least-squares solve is a blocked (TSQR) Householder QR of the `N × p` regression matrix
//! augmented with the x and y columns: the record is cut into a fixed number of blocks (independent
//! of the thread count, so results are bit-identical for any number of threads), each block is
//! reduced to its `R` factor in chunks, and the block factors are stacked and reduced once more.

use super::model::{Line, LineKind};
use super::{C64, Orbit, OrbitError, invalid};
use nalgebra::DMatrix;
use rayon::prelude::*;
use std::f64::consts::{PI, TAU};
use std::path::Path;

/// Minimum number of samples of a record.
pub const MIN_SAMPLES: usize = 16;

/// Largest accepted |time| of a record sample, s (about 30 years).
pub const MAX_ABS_TIME_S: f64 = 1e9;

/// Largest accepted |displacement| of a record sample, µm (1 km; keeps sums of squares finite).
pub const MAX_ABS_DISPLACEMENT_UM: f64 = 1e9;

/// A sensor record: times and two orthogonal displacements, optionally the carrier angle.
#[derive(Debug, Clone, PartialEq)]
pub struct Record {
    t_s: Vec<f64>,
    x_um: Vec<f64>,
    y_um: Vec<f64>,
    carrier_angle_rad: Option<Vec<f64>>,
    tach_pulses_s: Option<Vec<f64>>,
}

impl Record {
    /// Validates and builds a record: equal lengths ≥ [`MIN_SAMPLES`], finite values, strictly
    /// increasing times (s, |t| ≤ [`MAX_ABS_TIME_S`]), displacements in µm (≤
    /// [`MAX_ABS_DISPLACEMENT_UM`]), carrier angle in rad.
    ///
    /// # Errors
    /// [`OrbitError::Record`] naming the first offending sample.
    pub fn new(
        t_s: Vec<f64>,
        x_um: Vec<f64>,
        y_um: Vec<f64>,
        carrier_angle_rad: Option<Vec<f64>>,
    ) -> Result<Self, OrbitError> {
        let n = t_s.len();
        if x_um.len() != n
            || y_um.len() != n
            || carrier_angle_rad.as_ref().is_some_and(|c| c.len() != n)
        {
            return Err(OrbitError::Record("columns differ in length".into()));
        }
        if n < MIN_SAMPLES {
            return Err(OrbitError::Record(format!(
                "need at least {MIN_SAMPLES} samples, got {n}"
            )));
        }
        for k in 0..n {
            let c_ok = carrier_angle_rad.as_ref().is_none_or(|c| c[k].is_finite());
            if !(t_s[k].is_finite() && x_um[k].is_finite() && y_um[k].is_finite() && c_ok) {
                return Err(OrbitError::Record(format!("sample {k}: non-finite value")));
            }
            if t_s[k].abs() > MAX_ABS_TIME_S
                || x_um[k].abs() > MAX_ABS_DISPLACEMENT_UM
                || y_um[k].abs() > MAX_ABS_DISPLACEMENT_UM
            {
                return Err(OrbitError::Record(format!(
                    "sample {k}: |t| must be ≤ {MAX_ABS_TIME_S:e} s and |x|, |y| ≤ \
                     {MAX_ABS_DISPLACEMENT_UM:e} µm (got t = {} s, x = {} µm, y = {} µm)",
                    t_s[k], x_um[k], y_um[k]
                )));
            }
            if k > 0 && t_s[k] <= t_s[k - 1] {
                return Err(OrbitError::Record(format!(
                    "sample {k}: time {} s not after {} s",
                    t_s[k],
                    t_s[k - 1]
                )));
            }
        }
        Ok(Self {
            t_s,
            x_um,
            y_um,
            carrier_angle_rad,
            tach_pulses_s: None,
        })
    }

    /// Reads a CSV file with a header row. Columns (any order, names exact): `t_s`, `x_um`, `y_um`
    /// and optionally `carrier_deg` (carrier angle, degrees). Lines starting with `#` are comments.
    ///
    /// # Errors
    /// [`OrbitError::Csv`] naming file, line and column; [`OrbitError::File`] when unreadable;
    /// [`OrbitError::Record`] for record-level problems.
    pub fn from_csv_path(path: &Path) -> Result<Self, OrbitError> {
        let file = path.display().to_string();
        let f = std::fs::File::open(path).map_err(|e| OrbitError::File {
            file: file.clone(),
            message: e.to_string(),
        })?;
        Self::from_csv_reader(std::io::BufReader::new(f), &file)
    }

    /// As [`Record::from_csv_path`] from any reader; `file` names the source in errors.
    ///
    /// # Errors
    /// As [`Record::from_csv_path`].
    pub fn from_csv_reader(reader: impl std::io::Read, file: &str) -> Result<Self, OrbitError> {
        let mut rdr = csv::ReaderBuilder::new()
            .comment(Some(b'#'))
            .trim(csv::Trim::All)
            .from_reader(reader);
        let csv_err = |line: u64, column: &str, message: String| OrbitError::Csv {
            file: file.to_string(),
            line,
            column: column.to_string(),
            message,
        };
        let headers = rdr
            .headers()
            .map_err(|e| csv_err(1, "header", e.to_string()))?
            .clone();
        let mut idx = [None; 5];
        const NAMES: [&str; 5] = ["t_s", "x_um", "y_um", "carrier_deg", "tach"];
        for (j, h) in headers.iter().enumerate() {
            match NAMES.iter().position(|n| *n == h) {
                Some(k) if idx[k].is_none() => idx[k] = Some(j),
                Some(_) => return Err(csv_err(1, h, "duplicate column".into())),
                None => {
                    return Err(csv_err(
                        1,
                        h,
                        format!(
                            "unknown column (expected t_s, x_um, y_um and optionally carrier_deg, tach; column {})",
                            j + 1
                        ),
                    ));
                }
            }
        }
        for k in 0..3 {
            if idx[k].is_none() {
                return Err(csv_err(
                    1,
                    NAMES[k],
                    "required column missing from the header".into(),
                ));
            }
        }
        let mut cols: [Vec<f64>; 5] = Default::default();
        for rec in rdr.records() {
            let rec = rec.map_err(|e| {
                let line = e.position().map_or(0, csv::Position::line);
                csv_err(line, "row", e.to_string())
            })?;
            let line = rec.position().map_or(0, csv::Position::line);
            for k in 0..5 {
                let Some(j) = idx[k] else { continue };
                let cell = rec.get(j).unwrap_or("");
                let v: f64 = cell.parse().map_err(|_| {
                    csv_err(line, NAMES[k], format!("expected a number, found {cell:?}"))
                })?;
                if !v.is_finite() {
                    return Err(csv_err(
                        line,
                        NAMES[k],
                        format!("expected a finite number, found {cell:?}"),
                    ));
                }
                if k == 0 && cols[0].last().is_some_and(|p| v <= *p) {
                    return Err(csv_err(
                        line,
                        NAMES[0],
                        format!("time {v} s is not after the previous row"),
                    ));
                }
                if k == 4 && v != 0.0 && v != 1.0 {
                    return Err(csv_err(
                        line,
                        NAMES[4],
                        format!("expected 0 or 1 (tach pulse flag), found {cell:?}"),
                    ));
                }
                cols[k].push(v);
            }
        }
        let [t, x, y, c, tach] = cols;
        // Tach pulses: rising edges 0 → 1 of the flag column.
        let pulses: Option<Vec<f64>> = idx[4].map(|_| {
            (1..tach.len())
                .filter(|&i| tach[i] == 1.0 && tach[i - 1] == 0.0)
                .map(|i| t[i])
                .collect()
        });
        let carrier = idx[3].map(|_| c.iter().map(|d| d.to_radians()).collect());
        let to_file = |e: OrbitError| match e {
            OrbitError::Record(m) => OrbitError::File {
                file: file.to_string(),
                message: m,
            },
            other => other,
        };
        let rec = Self::new(t, x, y, carrier).map_err(to_file)?;
        match pulses {
            Some(p) => rec.with_tach_pulses(p).map_err(to_file),
            None => Ok(rec),
        }
    }

    /// Attaches once-per-planet-revolution tach pulse times (s, strictly increasing, at least 2,
    /// inside the record) for [`Method::Synchronous`].
    ///
    /// # Errors
    /// [`OrbitError::Record`] naming the offending pulse.
    pub fn with_tach_pulses(mut self, pulses_s: Vec<f64>) -> Result<Self, OrbitError> {
        if pulses_s.len() < 2 {
            return Err(OrbitError::Record(format!(
                "need at least 2 tach pulses, got {}",
                pulses_s.len()
            )));
        }
        let (t0, t1) = (self.t_s[0], self.t_s[self.len() - 1]);
        for (k, p) in pulses_s.iter().enumerate() {
            if !(p.is_finite() && *p >= t0 && *p <= t1) {
                return Err(OrbitError::Record(format!(
                    "tach pulse {k} at {p} s is outside the record"
                )));
            }
            if k > 0 && *p <= pulses_s[k - 1] {
                return Err(OrbitError::Record(format!(
                    "tach pulse {k} at {p} s is not after the previous one"
                )));
            }
        }
        self.tach_pulses_s = Some(pulses_s);
        Ok(self)
    }

    /// Tach pulse times, s (if any).
    #[must_use]
    pub fn tach_pulses_s(&self) -> Option<&[f64]> {
        self.tach_pulses_s.as_deref()
    }

    /// Sample times, s.
    #[must_use]
    pub fn t_s(&self) -> &[f64] {
        &self.t_s
    }
    /// x displacement, µm.
    #[must_use]
    pub fn x_um(&self) -> &[f64] {
        &self.x_um
    }
    /// y displacement, µm.
    #[must_use]
    pub fn y_um(&self) -> &[f64] {
        &self.y_um
    }
    /// Carrier angle, rad (if recorded).
    #[must_use]
    pub fn carrier_angle_rad(&self) -> Option<&[f64]> {
        self.carrier_angle_rad.as_deref()
    }
    /// Number of samples.
    #[must_use]
    pub fn len(&self) -> usize {
        self.t_s.len()
    }
    /// Always `false` (a record has at least [`MIN_SAMPLES`] samples).
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.t_s.is_empty()
    }
    /// Record length `T_rec = N·Δt` (mean sample spacing times N), s.
    #[must_use]
    pub fn duration_s(&self) -> f64 {
        let n = self.len() as f64;
        (self.t_s[self.len() - 1] - self.t_s[0]) * n / (n - 1.0)
    }
    /// Mean sample spacing, s.
    #[must_use]
    pub fn mean_step_s(&self) -> f64 {
        (self.t_s[self.len() - 1] - self.t_s[0]) / (self.len() - 1) as f64
    }
    /// `true` when every step is within `rel_tol` of the mean step.
    #[must_use]
    pub fn is_uniform(&self, rel_tol: f64) -> bool {
        let dt = self.mean_step_s();
        self.t_s
            .windows(2)
            .all(|w| ((w[1] - w[0]) - dt).abs() <= rel_tol * dt)
    }

    /// Writes the record as CSV (`t_s,x_um,y_um[,carrier_deg]`).
    ///
    /// # Errors
    /// I/O errors as [`OrbitError::File`].
    pub fn write_csv(&self, path: &Path) -> Result<(), OrbitError> {
        let ferr = |e: &dyn std::fmt::Display| OrbitError::File {
            file: path.display().to_string(),
            message: e.to_string(),
        };
        let mut w = csv::Writer::from_path(path).map_err(|e| ferr(&e))?;
        let mut head = vec!["t_s", "x_um", "y_um"];
        if self.carrier_angle_rad.is_some() {
            head.push("carrier_deg");
        }
        w.write_record(&head).map_err(|e| ferr(&e))?;
        for k in 0..self.len() {
            let mut row = vec![
                format!("{}", self.t_s[k]),
                format!("{}", self.x_um[k]),
                format!("{}", self.y_um[k]),
            ];
            if let Some(c) = &self.carrier_angle_rad {
                row.push(format!("{}", c[k].to_degrees()));
            }
            w.write_record(&row).map_err(|e| ferr(&e))?;
        }
        w.flush().map_err(|e| ferr(&e))
    }
}

/// Frame of the sensors and how to get to the carrier frame (A.7).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Frame {
    /// Sensors fixed to the carrier, or carrier held (star arrangement / test rig).
    Carrier,
    /// Housing-fixed sensors, de-rotated with the recorded carrier angle (option a).
    HousingDerotate,
    /// Housing-fixed sensors, carrier at constant signed speed `carrier_rad_s`; Z± read in the
    /// complex spectrum at `ω_c ± ω_p` (option b).
    HousingFullSpectrum {
        /// Signed carrier speed ω_c, rad/s.
        carrier_rad_s: f64,
    },
}

/// Estimator of the planet-frequency components (A.8).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
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

/// Configured extractor; build with [`Extractor::builder`].
#[derive(Debug, Clone, PartialEq)]
pub struct Extractor {
    omega_p_rad_s: f64,
    frame: Frame,
    method: Method,
    drift: bool,
    nuisance: Vec<Line>,
    max_condition: f64,
    min_separation_bins: f64,
}

/// Builder of an [`Extractor`].
#[derive(Debug, Clone)]
pub struct ExtractorBuilder(Extractor);

impl Extractor {
    /// Starts a builder for the signed planet spin ω_p relative to the carrier, rad/s. Defaults:
    /// carrier frame, least squares, linear drift removed, no nuisance lines, refusal above
    /// condition number 1e6, separation warning below 3 DFT bins (A.7, A.8).
    #[must_use]
    pub fn builder(omega_p_rad_s: f64) -> ExtractorBuilder {
        ExtractorBuilder(Extractor {
            omega_p_rad_s,
            frame: Frame::Carrier,
            method: Method::LeastSquares,
            drift: true,
            nuisance: Vec::new(),
            max_condition: 1e6,
            min_separation_bins: 3.0,
        })
    }
}

impl ExtractorBuilder {
    /// Sensor frame.
    #[must_use]
    pub fn frame(mut self, frame: Frame) -> Self {
        self.0.frame = frame;
        self
    }
    /// Estimator.
    #[must_use]
    pub fn method(mut self, method: Method) -> Self {
        self.0.method = method;
        self
    }
    /// Remove a linear drift (`true`, default) or only the mean (`false`).
    #[must_use]
    pub fn drift(mut self, drift: bool) -> Self {
        self.0.drift = drift;
        self
    }
    /// Known interfering lines in the analysis frame (signed rad/s); lines of kind
    /// [`LineKind::Planet`] are ignored here (the planet lines follow from ω_p and the frame).
    #[must_use]
    pub fn nuisance(mut self, lines: Vec<Line>) -> Self {
        self.0.nuisance = lines
            .into_iter()
            .filter(|l| l.kind == LineKind::Nuisance)
            .collect();
        self
    }
    /// Refuse the least-squares fit above this condition number (default 1e6).
    #[must_use]
    pub fn max_condition(mut self, c: f64) -> Self {
        self.0.max_condition = c;
        self
    }
    /// Warn when two lines are closer than this many DFT bins `1/T_rec` (default 3).
    #[must_use]
    pub fn min_separation_bins(mut self, b: f64) -> Self {
        self.0.min_separation_bins = b;
        self
    }
    /// Validates the configuration.
    ///
    /// # Errors
    /// [`OrbitError::Invalid`] for a zero/non-finite ω_p or ω_c, non-finite lines, a condition limit
    /// ≤ 1, a negative separation, or synchronous resampling in the full-spectrum frame.
    pub fn build(self) -> Result<Extractor, OrbitError> {
        let e = self.0;
        if !(e.omega_p_rad_s.is_finite() && e.omega_p_rad_s != 0.0) {
            return Err(invalid("planet_speed", "must be finite and non-zero"));
        }
        if let Frame::HousingFullSpectrum { carrier_rad_s } = e.frame {
            if !(carrier_rad_s.is_finite() && carrier_rad_s != 0.0) {
                return Err(invalid(
                    "carrier_speed",
                    "must be finite and non-zero in the housing frame",
                ));
            }
            if e.method == Method::Synchronous {
                return Err(invalid(
                    "method",
                    "synchronous resampling needs the carrier frame (or de-rotation)",
                ));
            }
        }
        if let Some(l) = e.nuisance.iter().find(|l| !l.omega_rad_s.is_finite()) {
            return Err(invalid(
                format!("line `{}`", l.label),
                "frequency must be finite",
            ));
        }
        if e.max_condition.is_nan() || e.max_condition <= 1.0 {
            return Err(invalid("max_condition", "must exceed 1"));
        }
        if e.min_separation_bins.is_nan() || e.min_separation_bins < 0.0 {
            return Err(invalid("min_separation_bins", "must be ≥ 0"));
        }
        Ok(e)
    }
}

/// 1-σ uncertainties of an extraction (from the least-squares covariance `σ̂²(MᵀM)⁻¹`, x and y
/// noise taken independent).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
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

/// Number of independent blocks of the TSQR (fixed: results do not depend on the thread count).
const BLOCKS: usize = 64;
/// Rows per chunk inside a block.
const CHUNK: usize = 512;

impl Extractor {
    /// Signed ω_p, rad/s.
    #[must_use]
    pub fn omega_p_rad_s(&self) -> f64 {
        self.omega_p_rad_s
    }

    /// Sensor frame.
    #[must_use]
    pub fn frame(&self) -> Frame {
        self.frame
    }

    /// Whether a linear drift is removed (else only the mean).
    #[must_use]
    pub fn drift(&self) -> bool {
        self.drift
    }

    /// Estimator.
    #[must_use]
    pub fn method(&self) -> Method {
        self.method
    }

    /// Planet lines `(ω₊, ω₋)` of the analysis frame, signed rad/s.
    fn target_omegas(&self) -> (f64, f64) {
        let wc = match self.frame {
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
        match self.frame {
            Frame::HousingDerotate => {
                let c = rec.carrier_angle_rad().ok_or_else(|| {
                    OrbitError::Record(
                        "de-rotation needs a carrier angle column (carrier_deg)".into(),
                    )
                })?;
                // Sensor offsets and drift live in the housing frame: remove them there first.
                let (x, y) = detrend(rec.t_s(), &rec.x_um, &rec.y_um, self.drift);
                Ok(rotate(&x, &y, c, -1.0))
            }
            _ => Ok(detrend(rec.t_s(), &rec.x_um, &rec.y_um, self.drift)),
        }
    }

    /// Collision / aliasing warnings for the analysed lines.
    fn warnings(&self, rec: &Record, lines: &[Line]) -> Vec<String> {
        let mut w = Vec::new();
        let bin = TAU / rec.duration_s();
        let min_sep = self.min_separation_bins * bin;
        let nyq = PI / rec.mean_step_s();
        // The real least squares sees |ω|; the complex DFT methods see signed ω.
        let real = self.method == Method::LeastSquares;
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
                        self.min_separation_bins,
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
        lines.extend(self.nuisance.iter().cloned());
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
        match self.method {
            Method::LeastSquares if self.frame == Frame::HousingDerotate => {
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

    /// Least-squares fit; fills `m` and returns the fitted periodic part (all sinusoid columns,
    /// without mean and drift) as `(ω_k, x sine/cosine coefficients, y coefficients)`.
    fn least_squares(
        &self,
        t: &[f64],
        x: &[f64],
        y: &[f64],
        m: &mut Measurement,
    ) -> Result<PeriodicFit, OrbitError> {
        // Distinct real frequencies (columns): the planet lines first, merged with each other only.
        let (wp, wm) = self.target_omegas();
        let tiny = 1e-12 * (wp.abs().max(wm.abs()));
        let mut freqs: Vec<(f64, String)> = vec![(wp.abs(), "planet Z+".into())];
        if (wm.abs() - wp.abs()).abs() > tiny {
            freqs.push((wm.abs(), "planet Z-".into()));
        }
        let n_target = freqs.len();
        for l in &self.nuisance {
            let w = l.omega_rad_s.abs();
            if w <= tiny {
                continue; // DC is the mean column
            }
            let dup = freqs[n_target..].iter().any(|(f, _)| (f - w).abs() <= tiny);
            if !dup {
                freqs.push((w, l.label.clone()));
            }
        }
        let n0 = if self.drift { 2 } else { 1 };
        let p = n0 + 2 * freqs.len();
        let k = p + 2;
        let n = t.len();
        if n <= p + 1 {
            return Err(OrbitError::Record(format!(
                "{n} samples cannot fit {p} regressors"
            )));
        }
        let (t0, t1) = (t[0], t[n - 1]);
        let (tm, th) = (0.5 * (t0 + t1), 0.5 * (t1 - t0));
        let omegas: Vec<f64> = freqs.iter().map(|f| f.0).collect();
        let fill = |row: &mut [f64], i: usize| {
            row[0] = 1.0;
            if n0 == 2 {
                row[1] = (t[i] - tm) / th;
            }
            for (j, w) in omegas.iter().enumerate() {
                let (s, c) = (w * t[i]).sin_cos();
                row[n0 + 2 * j] = s;
                row[n0 + 2 * j + 1] = c;
            }
            row[p] = x[i];
            row[p + 1] = y[i];
        };
        let blocks = BLOCKS.min(n.div_ceil(CHUNK));
        let bounds: Vec<(usize, usize)> = (0..blocks)
            .map(|b| (b * n / blocks, (b + 1) * n / blocks))
            .collect();
        let rs: Vec<DMatrix<f64>> = bounds
            .par_iter()
            .map(|&(a, b)| block_r(a, b, k, &fill))
            .collect();
        let mut stack = DMatrix::zeros(k * rs.len(), k);
        for (b, r) in rs.iter().enumerate() {
            stack.view_mut((b * k, 0), (r.nrows(), k)).copy_from(r);
        }
        let r = qr_r(stack, k);
        let rp = r.view((0, 0), (p, p)).into_owned();
        // Condition number of the column-scaled matrix (singular values of R D⁻¹).
        let norms: Vec<f64> = (0..p).map(|j| rp.column(j).norm()).collect();
        let scaled = DMatrix::from_fn(p, p, |i, j| {
            if norms[j] > 0.0 {
                rp[(i, j)] / norms[j]
            } else {
                0.0
            }
        });
        let sv = scaled.singular_values();
        let (smax, smin) = (sv.max(), sv.min());
        let cond = if smin > 0.0 {
            smax / smin
        } else {
            f64::INFINITY
        };
        m.condition_number = Some(cond);
        if cond.is_nan() || cond > self.max_condition {
            let detail = closest_pair(&freqs, TAU / m.record_length_s);
            return Err(OrbitError::Collision {
                condition: cond,
                limit: self.max_condition,
                detail,
            });
        }
        let rinv = rp
            .clone()
            .try_inverse()
            .ok_or_else(|| OrbitError::Collision {
                condition: f64::INFINITY,
                limit: self.max_condition,
                detail: closest_pair(&freqs, TAU / m.record_length_s),
            })?;
        let qx = r.view((0, p), (p, 1)).into_owned();
        let qy = r.view((0, p + 1), (p, 1)).into_owned();
        let bx = &rinv * qx;
        let by = &rinv * qy;
        let rss_x = r[(p, p)].powi(2);
        let rss_y = r[(p, p + 1)].powi(2) + r[(p + 1, p + 1)].powi(2);
        let dof = (n - p) as f64;
        let (s2x, s2y) = (rss_x / dof, rss_y / dof);
        m.residual_rms_um = Some(((rss_x / n as f64).sqrt(), (rss_y / n as f64).sqrt()));
        let cov0 = &rinv * rinv.transpose(); // (RᵀR)⁻¹
        // Map coefficients → orbit (linear): x-coefficient at signed ω from the |ω| sine phasor.
        let to_orbit = |bx: &[f64], by: &[f64]| -> Orbit {
            let coef = |b: &[f64], w: f64| -> C64 {
                let idx = if (w.abs() - freqs[0].0).abs() <= tiny {
                    0
                } else {
                    1
                };
                let ph = C64::new(b[n0 + 2 * idx], b[n0 + 2 * idx + 1]) / C64::new(0.0, 2.0);
                if w > 0.0 { ph } else { ph.conj() }
            };
            let i = C64::i();
            Orbit {
                omega_p_rad_s: self.omega_p_rad_s,
                z_plus_um: coef(bx, wp) + i * coef(by, wp),
                z_minus_um: coef(bx, wm) + i * coef(by, wm),
            }
        };
        let (bxs, bys): (Vec<f64>, Vec<f64>) =
            (bx.iter().copied().collect(), by.iter().copied().collect());
        let orbit = to_orbit(&bxs, &bys);
        m.orbit = orbit;
        // Linear error propagation: outputs Re/Im of P_x, P_y, Z₊, Z₋.
        let outputs = |o: &Orbit| -> [f64; 8] {
            let (px, py) = o.sin_phasors();
            [
                px.re,
                px.im,
                py.re,
                py.im,
                o.z_plus_um.re,
                o.z_plus_um.im,
                o.z_minus_um.re,
                o.z_minus_um.im,
            ]
        };
        let zero = vec![0.0; p];
        let mut cov = [[0.0f64; 8]; 8];
        for (chan, s2) in [(0usize, s2x), (1, s2y)] {
            let mut jac = vec![[0.0f64; 8]; p];
            for (c, col) in jac.iter_mut().enumerate() {
                let mut e = zero.clone();
                e[c] = 1.0;
                let o = if chan == 0 {
                    to_orbit(&e, &zero)
                } else {
                    to_orbit(&zero, &e)
                };
                *col = outputs(&o);
            }
            for a in 0..8 {
                for b in 0..8 {
                    let mut s = 0.0;
                    for c in 0..p {
                        if jac[c][a] == 0.0 {
                            continue;
                        }
                        for d in 0..p {
                            s += jac[c][a] * cov0[(c, d)] * jac[d][b];
                        }
                    }
                    cov[a][b] += s2 * s;
                }
            }
        }
        let polar_sigma = |re: f64, im: f64, o: usize| -> (f64, f64) {
            let a = re.hypot(im);
            let (c00, c01, c11) = (cov[o][o], cov[o][o + 1], cov[o + 1][o + 1]);
            if a == 0.0 {
                // Zero amplitude: the phase is undefined.
                return (c00.max(c11).max(0.0).sqrt(), f64::INFINITY);
            }
            let va = (re * re * c00 + 2.0 * re * im * c01 + im * im * c11) / (a * a);
            let vp = (im * im * c00 - 2.0 * re * im * c01 + re * re * c11) / (a * a * a * a);
            (va.max(0.0).sqrt(), vp.max(0.0).sqrt())
        };
        let out = outputs(&orbit);
        let (sax, spx) = polar_sigma(out[0], out[1], 0);
        let (say, spy) = polar_sigma(out[2], out[3], 2);
        let (szp, _) = polar_sigma(out[4], out[5], 4);
        let (szm, _) = polar_sigma(out[6], out[7], 6);
        m.uncertainty = Some(Uncertainty {
            a_x_um: sax,
            phi_x_rad: spx,
            a_y_um: say,
            phi_y_rad: spy,
            z_plus_um: szp,
            z_minus_um: szm,
        });
        Ok(PeriodicFit {
            omegas,
            x: bxs[n0..].to_vec(),
            y: bys[n0..].to_vec(),
        })
    }

    /// Least squares on de-rotated data with the sensor offset and drift removed in the housing
    /// frame (where they live): alternate (i) fit in the carrier frame, (ii) rotate the fitted
    /// periodic part back to the housing frame and fit the mean/drift of the remainder there.
    /// The coupling is weak (≈ 1/number of carrier revolutions), so three passes suffice.
    fn least_squares_derotated(&self, rec: &Record, m: &mut Measurement) -> Result<(), OrbitError> {
        let c = rec.carrier_angle_rad().ok_or_else(|| {
            OrbitError::Record("de-rotation needs a carrier angle column (carrier_deg)".into())
        })?;
        let t = rec.t_s();
        let n = rec.len();
        let (mut xr, mut yr) = (rec.x_um.clone(), rec.y_um.clone());
        for pass in 0..DEROTATION_PASSES {
            let (xc, yc) = rotate(&xr, &yr, c, -1.0);
            let fit = self.least_squares(t, &xc, &yc, m)?;
            if pass + 1 == DEROTATION_PASSES {
                break;
            }
            let (mut px, mut py) = (vec![0.0; n], vec![0.0; n]);
            for i in 0..n {
                (px[i], py[i]) = fit.eval(t[i]);
            }
            let (hx, hy) = rotate(&px, &py, c, 1.0);
            let rx: Vec<f64> = (0..n).map(|i| rec.x_um[i] - hx[i]).collect();
            let ry: Vec<f64> = (0..n).map(|i| rec.y_um[i] - hy[i]).collect();
            let (dx, dy) = detrend(t, &rx, &ry, self.drift);
            // raw − trend, where trend = remainder − detrended remainder
            for i in 0..n {
                xr[i] = rec.x_um[i] - (rx[i] - dx[i]);
                yr[i] = rec.y_um[i] - (ry[i] - dy[i]);
            }
        }
        Ok(())
    }
}

/// Passes of the housing-trend / carrier-fit alternation of de-rotated least squares.
const DEROTATION_PASSES: usize = 3;

/// Fitted periodic part `Σ_k a_k sin ω_k t + b_k cos ω_k t` of x and y.
struct PeriodicFit {
    omegas: Vec<f64>,
    x: Vec<f64>,
    y: Vec<f64>,
}

impl PeriodicFit {
    fn eval(&self, t: f64) -> (f64, f64) {
        let (mut a, mut b) = (0.0, 0.0);
        for (k, w) in self.omegas.iter().enumerate() {
            let (s, c) = (w * t).sin_cos();
            a += self.x[2 * k] * s + self.x[2 * k + 1] * c;
            b += self.y[2 * k] * s + self.y[2 * k + 1] * c;
        }
        (a, b)
    }
}

/// Rotates `(x, y)` by `sign·θ_k` sample by sample (`sign = −1`: housing → carrier).
fn rotate(x: &[f64], y: &[f64], theta: &[f64], sign: f64) -> (Vec<f64>, Vec<f64>) {
    let mut ox = Vec::with_capacity(x.len());
    let mut oy = Vec::with_capacity(x.len());
    for k in 0..x.len() {
        let (s, c) = (sign * theta[k]).sin_cos();
        ox.push(c * x[k] - s * y[k]);
        oy.push(s * x[k] + c * y[k]);
    }
    (ox, oy)
}

/// Closest pair of fitted real frequencies, for the collision message.
fn closest_pair(freqs: &[(f64, String)], bin: f64) -> String {
    let mut best: Option<(f64, usize, usize)> = None;
    for i in 0..freqs.len() {
        for j in 0..i {
            let d = (freqs[i].0 - freqs[j].0).abs();
            if best.is_none_or(|b| d < b.0) {
                best = Some((d, i, j));
            }
        }
    }
    match best {
        Some((d, i, j)) => format!(
            "closest lines `{}` and `{}`, {:.4} bins apart, |f| = {:.6} / {:.6} Hz",
            freqs[i].1,
            freqs[j].1,
            d / bin,
            freqs[i].0 / TAU,
            freqs[j].0 / TAU
        ),
        None => "drift and mean columns".into(),
    }
}

/// Upper-triangular `R` (k×k) of rows `a..b` via chunked Householder QR.
fn block_r(
    a: usize,
    b: usize,
    k: usize,
    fill: &(dyn Fn(&mut [f64], usize) + Sync),
) -> DMatrix<f64> {
    let mut r: Option<DMatrix<f64>> = None;
    let mut row = vec![0.0; k];
    let mut start = a;
    while start < b {
        let end = (start + CHUNK).min(b);
        let top = r.as_ref().map_or(0, DMatrix::nrows);
        let mut s = DMatrix::zeros(top + end - start, k);
        if let Some(r) = &r {
            s.view_mut((0, 0), (top, k)).copy_from(r);
        }
        for i in start..end {
            fill(&mut row, i);
            for (j, v) in row.iter().enumerate() {
                s[(top + i - start, j)] = *v;
            }
        }
        r = Some(qr_r(s, k));
        start = end;
    }
    r.unwrap_or_else(|| DMatrix::zeros(0, k))
}

/// `R` factor of an m×k matrix, padded to k×k when m < k.
fn qr_r(s: DMatrix<f64>, k: usize) -> DMatrix<f64> {
    let r = s.qr().r();
    if r.nrows() == k {
        return r;
    }
    let mut full = DMatrix::zeros(k, k);
    full.view_mut((0, 0), (r.nrows(), k)).copy_from(&r);
    full
}

/// Removes the mean, and a least-squares line when `drift`.
fn detrend(t: &[f64], x: &[f64], y: &[f64], drift: bool) -> (Vec<f64>, Vec<f64>) {
    let n = t.len() as f64;
    let tm = t.iter().sum::<f64>() / n;
    let stt: f64 = t.iter().map(|v| (v - tm).powi(2)).sum();
    let one = |v: &[f64]| -> Vec<f64> {
        let m = v.iter().sum::<f64>() / n;
        let slope = if drift {
            t.iter()
                .zip(v)
                .map(|(a, b)| (a - tm) * (b - m))
                .sum::<f64>()
                / stt
        } else {
            0.0
        };
        t.iter()
            .zip(v)
            .map(|(a, b)| b - m - slope * (a - tm))
            .collect()
    };
    (one(x), one(y))
}

/// `Σ w_n z_n e^{−iωt_n} / Σ w_n` (rectangular window when `w` is `None`).
fn dtft(t: &[f64], z: &[C64], omega: f64, w: Option<&[f64]>) -> C64 {
    let mut acc = C64::new(0.0, 0.0);
    let mut ws = 0.0;
    for (k, (tk, zk)) in t.iter().zip(z).enumerate() {
        let wk = w.map_or(1.0, |w| w[k]);
        acc += zk * C64::from_polar(wk, -omega * tk);
        ws += wk;
    }
    acc / ws
}

/// Symmetric Hann window `w_k = ½ − ½ cos(2πk/(n−1))`, `n ≥ 2`.
fn hann(n: usize) -> Vec<f64> {
    (0..n)
        .map(|k| 0.5 - 0.5 * (TAU * k as f64 / (n - 1) as f64).cos())
        .collect()
}

/// Unnormalised FFT of the Hann-windowed `x + iy`, and the window sum `Σ w_k`.
fn hann_fft(x: &[f64], y: &[f64]) -> (Vec<rustfft::num_complex::Complex<f64>>, f64) {
    let n = x.len().min(y.len());
    let w = hann(n);
    let mut buf: Vec<rustfft::num_complex::Complex<f64>> = (0..n)
        .map(|k| rustfft::num_complex::Complex::new(x[k] * w[k], y[k] * w[k]))
        .collect();
    rustfft::FftPlanner::new()
        .plan_fft_forward(n)
        .process(&mut buf);
    (buf, w.iter().sum())
}

/// Hann-window DTFT at ω (coefficient estimate of `e^{iωt}`).
fn hann_dtft(t: &[f64], z: &[C64], omega: f64) -> C64 {
    dtft(t, z, omega, Some(&hann(t.len())))
}

/// Synchronous average: cubic (4-point Lagrange) resampling of z at M points per planet revolution
/// over the largest whole number K of revolutions, then the DFT bin at ±ω_p.
fn synchronous(rec: &Record, z: &[C64], omega_p: f64) -> Result<(C64, C64), OrbitError> {
    let t = rec.t_s();
    let n = t.len();
    let period = TAU / omega_p.abs();
    let span = t[n - 1] - t[0];
    let revs = (span / period).floor() as usize;
    if revs == 0 {
        return Err(OrbitError::Record(
            "synchronous resampling needs at least one whole planet revolution".into(),
        ));
    }
    let dt = rec.mean_step_s();
    let per_rev = ((period / dt).floor() as usize).max(8);
    let total = revs * per_rev;
    let h = period / per_rev as f64;
    let interp = |tt: f64| cubic_at(t[0], dt, z, tt);
    let (mut zp, mut zm) = (C64::new(0.0, 0.0), C64::new(0.0, 0.0));
    for j in 0..total {
        let tt = t[0] + h * j as f64;
        let v = interp(tt);
        let e = C64::from_polar(1.0, -omega_p * tt);
        zp += v * e;
        zm += v * e.conj();
    }
    Ok((zp / total as f64, zm / total as f64))
}

/// 4-point Lagrange (cubic) interpolation of uniformly sampled `z` (first sample at `t0`, step `dt`).
fn cubic_at(t0: f64, dt: f64, z: &[C64], tt: f64) -> C64 {
    let n = z.len();
    let u = (tt - t0) / dt;
    let i = (u.floor() as isize).clamp(1, n as isize - 3) as usize;
    let f = u - i as f64;
    let (a, b, c, d) = (z[i - 1], z[i], z[i + 1], z[i + 2]);
    a * (-f * (f - 1.0) * (f - 2.0) / 6.0)
        + b * ((f + 1.0) * (f - 1.0) * (f - 2.0) / 2.0)
        + c * (-(f + 1.0) * f * (f - 2.0) / 2.0)
        + d * ((f + 1.0) * f * (f - 1.0) / 6.0)
}

/// Tach-driven synchronous average (A.8 step 4): the planet angle is `sign·2π·(r + s)` between
/// pulses r and r+1 (linear in time within a revolution); z is resampled (cubic) at M points per
/// revolution over all whole revolutions and the DFT bin at ±1 order taken. The result refers to
/// the first pulse; it is moved to the time origin with the mean speed
/// `ω̄ = sign·2π·revs/(t_last − t_first)`: `Z₊ = Z₊,angle e^{−iω̄ t_first}`, `Z₋ = Z₋,angle e^{iω̄ t_first}`.
fn synchronous_tach(
    rec: &Record,
    z: &[C64],
    pulses: &[f64],
    sign: f64,
) -> Result<(C64, C64), OrbitError> {
    let t = rec.t_s();
    let dt = rec.mean_step_s();
    let revs = pulses.len() - 1;
    let span = pulses[revs] - pulses[0];
    let per_rev = ((span / revs as f64 / dt).floor() as usize).max(8);
    let (mut zp, mut zm) = (C64::new(0.0, 0.0), C64::new(0.0, 0.0));
    for r in 0..revs {
        let (a, b) = (pulses[r], pulses[r + 1]);
        for j in 0..per_rev {
            let s = j as f64 / per_rev as f64;
            let v = cubic_at(t[0], dt, z, a + (b - a) * s);
            let e = C64::from_polar(1.0, -sign * TAU * s);
            zp += v * e;
            zm += v * e.conj();
        }
    }
    let total = (revs * per_rev) as f64;
    let w_mean = sign * TAU * revs as f64 / span;
    let shift = C64::from_polar(1.0, -w_mean * pulses[0]);
    Ok((zp / total * shift, zm / total * shift.conj()))
}

/// Full (complex) spectrum of `z = x + i y` with a Hann window: `(signed frequency Hz, amplitude µm)`
/// sorted by frequency; amplitude-corrected so a line `Z e^{iωt}` on a bin shows `|Z|`. For
/// uniformly sampled data with step `dt_s`; pass detrended data (e.g. [`Extractor::analysis_signal`]).
#[must_use]
pub fn full_spectrum(dt_s: f64, x_um: &[f64], y_um: &[f64]) -> Vec<(f64, f64)> {
    let n = x_um.len().min(y_um.len());
    if n < 2 {
        return Vec::new();
    }
    let (buf, ws) = hann_fft(&x_um[..n], &y_um[..n]);
    let df = 1.0 / (n as f64 * dt_s);
    let mut out: Vec<(f64, f64)> = buf
        .iter()
        .enumerate()
        .map(|(k, c)| {
            let kk = if k <= n / 2 {
                k as f64
            } else {
                k as f64 - n as f64
            };
            (kk * df, c.norm() / ws)
        })
        .collect();
    out.sort_by(|a, b| a.0.total_cmp(&b.0));
    out
}

/// Measured-minus-model comparison (A.8 step 7).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Comparison {
    /// ΔR_L, µm.
    pub d_r_long_um: f64,
    /// ΔR_S, µm.
    pub d_r_short_um: f64,
    /// Δα_L wrapped to (−π/2, π/2], rad; `None` if either orbit is a circle.
    pub d_alpha_long_rad: Option<f64>,
    /// |Z₊,meas − Z₊,model|, µm.
    pub d_z_plus_um: f64,
    /// |Z₋,meas − Z₋,model|, µm.
    pub d_z_minus_um: f64,
}

impl Comparison {
    /// Compares a measured with a model orbit (both carrier frame, same time origin).
    #[must_use]
    pub fn new(measured: &Orbit, model: &Orbit) -> Self {
        let (a, b) = (measured.ellipse(), model.ellipse());
        Self {
            d_r_long_um: a.r_long_um - b.r_long_um,
            d_r_short_um: a.r_short_um - b.r_short_um,
            d_alpha_long_rad: a
                .alpha_long_rad
                .zip(b.alpha_long_rad)
                .map(|(x, y)| super::wrap_half_pi(x - y)),
            d_z_plus_um: (measured.z_plus_um - model.z_plus_um).norm(),
            d_z_minus_um: (measured.z_minus_um - model.z_minus_um).norm(),
        }
    }
}

/// Estimate of the planet frequency when it is only approximately known (A.8 step 3).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct FrequencyEstimate {
    /// Coarse estimate from the Hann-windowed complex spectrum with 3-point (Grandke)
    /// interpolation, signed rad/s.
    pub interpolated_rad_s: f64,
    /// Refined estimate minimising the least-squares residual over ω, signed rad/s.
    pub refined_rad_s: f64,
    /// Golden-section iterations of the refinement.
    pub iterations: u32,
}

impl Extractor {
    /// Estimates ω_p from the record when the configured ω_p is only approximate:
    /// (1) Hann-windowed FFT of the analysis-frame `z = x + iy`, strongest bin at ±|ω_p| within
    /// `±search_rel·|ω_p|`, Grandke interpolation `δ = ±(2a−1)/(a+1)`, `a` = larger-neighbour
    /// ratio; (2) golden-section minimisation of the residual sum of squares of this extractor's
    /// fit over `ω ∈ [ω̂ − 1 bin, ω̂ + 1 bin]` down to `tol_rad_s`. The sign of the configured ω_p is
    /// kept (the spectrum of the orbit alone cannot tell it). Carrier frame or de-rotation only;
    /// needs uniform sampling. `progress` receives the number of refinement iterations done (at most
    /// [`Extractor::frequency_iterations`]); each costs one least-squares fit.
    ///
    /// # Errors
    /// [`OrbitError::Invalid`] for bad `search_rel`/`tol_rad_s` or the full-spectrum frame,
    /// [`OrbitError::Record`] for non-uniform sampling or when the band holds no bin.
    pub fn estimate_frequency(
        &self,
        rec: &Record,
        search_rel: f64,
        tol_rad_s: f64,
        progress: &(dyn Fn(u64) + Sync),
    ) -> Result<FrequencyEstimate, OrbitError> {
        if !(search_rel > 0.0 && search_rel < 1.0) {
            return Err(invalid("search_rel", "must lie in (0, 1)"));
        }
        if !(tol_rad_s > 0.0 && tol_rad_s.is_finite()) {
            return Err(invalid("tol_rad_s", "must be positive and finite"));
        }
        if matches!(self.frame, Frame::HousingFullSpectrum { .. }) {
            return Err(invalid(
                "frame",
                "frequency estimation needs the carrier frame or de-rotation",
            ));
        }
        if !rec.is_uniform(1e-6) {
            return Err(OrbitError::Record(
                "frequency estimation needs uniformly sampled data".into(),
            ));
        }
        let (x, y) = self.analysis_signal(rec)?;
        let n = x.len();
        let (buf, _) = hann_fft(&x, &y);
        let bin = TAU / (n as f64 * rec.mean_step_s());
        let wp = self.omega_p_rad_s.abs();
        let kmin = (((1.0 - search_rel) * wp / bin).floor() as usize).max(1);
        let kmax = (((1.0 + search_rel) * wp / bin).ceil() as usize).min(n / 2 - 1);
        if kmin > kmax {
            return Err(OrbitError::Record(
                "no spectral bin in the search band".into(),
            ));
        }
        // Magnitude of bin k on the positive (+) or negative (−) side.
        let mag = |k: usize, neg: bool| {
            if neg {
                buf[(n - k) % n].norm()
            } else {
                buf[k].norm()
            }
        };
        let mut best = (0.0, kmin, false);
        for k in kmin..=kmax {
            for neg in [false, true] {
                if mag(k, neg) > best.0 {
                    best = (mag(k, neg), k, neg);
                }
            }
        }
        let (_, k, neg) = best;
        let (l, r, c) = (mag(k - 1, neg), mag(k + 1, neg), mag(k, neg));
        let delta = if r >= l {
            let a = r / c;
            (2.0 * a - 1.0) / (a + 1.0)
        } else {
            let a = l / c;
            -(2.0 * a - 1.0) / (a + 1.0)
        };
        let coarse = (k as f64 + delta) * bin;
        let rss = |om: f64| -> f64 {
            let mut e = self.clone();
            e.omega_p_rad_s = om.copysign(self.omega_p_rad_s);
            e.method = Method::LeastSquares;
            match e.extract(rec) {
                Ok(m) => m
                    .residual_rms_um
                    .map_or(f64::INFINITY, |(a, b)| a * a + b * b),
                Err(_) => f64::INFINITY,
            }
        };
        // Golden-section search.
        let g = 0.5 * (5f64.sqrt() - 1.0);
        let (mut a, mut b) = (coarse - bin, coarse + bin);
        let (mut c1, mut c2) = (b - g * (b - a), a + g * (b - a));
        let (mut f1, mut f2) = (rss(c1), rss(c2));
        let mut it = 0;
        while b - a > tol_rad_s && it < 200 {
            if f1 <= f2 {
                b = c2;
                c2 = c1;
                f2 = f1;
                c1 = b - g * (b - a);
                f1 = rss(c1);
            } else {
                a = c1;
                c1 = c2;
                f1 = f2;
                c2 = a + g * (b - a);
                f2 = rss(c2);
            }
            it += 1;
            progress(u64::from(it));
        }
        let sign = self.omega_p_rad_s.signum();
        Ok(FrequencyEstimate {
            interpolated_rad_s: sign * coarse,
            refined_rad_s: sign * 0.5 * (a + b),
            iterations: it,
        })
    }

    /// Upper bound of the golden-section iterations of [`Extractor::estimate_frequency`] for a
    /// record of length `record_s` (bracket 2 bins = `4π/T_rec`) and tolerance `tol_rad_s`.
    #[must_use]
    pub fn frequency_iterations(record_s: f64, tol_rad_s: f64) -> u64 {
        let bracket = 2.0 * TAU / record_s;
        let g = 0.5 * (5f64.sqrt() - 1.0);
        ((bracket / tol_rad_s).ln() / (1.0 / g).ln())
            .ceil()
            .clamp(0.0, 200.0) as u64
    }

    /// A copy of this extractor at another signed ω_p (e.g. an estimated one).
    ///
    /// # Errors
    /// [`OrbitError::Invalid`] for a zero or non-finite ω_p.
    pub fn with_omega_p(&self, omega_p_rad_s: f64) -> Result<Self, OrbitError> {
        ExtractorBuilder(Self {
            omega_p_rad_s,
            ..self.clone()
        })
        .build()
    }
}
