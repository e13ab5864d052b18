//! The sensor record: times, two orthogonal displacements, optional carrier angle and tach
//! pulses; validation, CSV reading and writing.

use crate::analysis::orbit::OrbitError;
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
    pub fn from_path(path: &Path) -> Result<Self, OrbitError> {
        let file = path.display().to_string();
        let f = std::fs::File::open(path).map_err(|e| OrbitError::File {
            file: file.clone(),
            message: e.to_string(),
        })?;
        Self::from_csv_reader(std::io::BufReader::new(f), &file)
    }

    /// As [`Record::from_path`] from any reader; `file` names the source in errors.
    ///
    /// # Errors
    /// As [`Record::from_path`].
    pub fn from_csv_reader(reader: impl std::io::Read, file: &str) -> Result<Self, OrbitError> {
        let mut rdr = csv::ReaderBuilder::new()
            .comment(Some(b'#'))
            .trim(csv::Trim::All)
            .from_reader(reader);
        let src = CsvSource { file };
        let headers = rdr
            .headers()
            .map_err(|e| src.err(1, "header", e.to_string()))?
            .clone();
        let idx = src.column_indices(&headers)?;
        let [t, x, y, c, tach] = src.read_columns(&mut rdr, &idx)?;
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
    /// inside the record) for [`Method::Synchronous`](super::Method::Synchronous).
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

/// The columns of a sensor CSV, in the order of [`CsvSource::read_columns`].
const NAMES: [&str; 5] = ["t_s", "x_um", "y_um", "carrier_deg", "tach"];

/// A sensor CSV being read: names the file in its errors.
struct CsvSource<'a> {
    file: &'a str,
}

impl CsvSource<'_> {
    /// The error at `line` (1-based) and `column` of this file.
    fn err(&self, line: u64, column: &str, message: String) -> OrbitError {
        OrbitError::Csv {
            file: self.file.to_string(),
            line,
            column: column.to_string(),
            message,
        }
    }

    /// The position of each of [`NAMES`] in the header (`None`: absent); refuses unknown and
    /// duplicate columns and a missing `t_s`, `x_um` or `y_um`.
    fn column_indices(
        &self,
        headers: &csv::StringRecord,
    ) -> Result<[Option<usize>; 5], OrbitError> {
        let mut idx = [None; 5];
        for (j, h) in headers.iter().enumerate() {
            match NAMES.iter().position(|n| *n == h) {
                Some(k) if idx[k].is_none() => idx[k] = Some(j),
                Some(_) => return Err(self.err(1, h, "duplicate column".into())),
                None => {
                    return Err(self.err(
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
                return Err(self.err(
                    1,
                    NAMES[k],
                    "required column missing from the header".into(),
                ));
            }
        }
        Ok(idx)
    }

    /// The values of the present columns, row by row: finite numbers, strictly increasing time,
    /// a tach flag of 0 or 1 (an absent column stays empty).
    fn read_columns(
        &self,
        rdr: &mut csv::Reader<impl std::io::Read>,
        idx: &[Option<usize>; 5],
    ) -> Result<[Vec<f64>; 5], OrbitError> {
        let mut cols: [Vec<f64>; 5] = Default::default();
        for rec in rdr.records() {
            let rec = rec.map_err(|e| {
                let line = e.position().map_or(0, csv::Position::line);
                self.err(line, "row", e.to_string())
            })?;
            let line = rec.position().map_or(0, csv::Position::line);
            for k in 0..5 {
                let Some(j) = idx[k] else { continue };
                let cell = rec.get(j).unwrap_or("");
                let v = self.cell_value(line, k, cell, cols[0].last().copied())?;
                cols[k].push(v);
            }
        }
        Ok(cols)
    }

    /// The value of `cell` in column `k` at `line`, checked against the previous time `prev_t`
    /// (s) for `t_s`.
    fn cell_value(
        &self,
        line: u64,
        k: usize,
        cell: &str,
        prev_t: Option<f64>,
    ) -> Result<f64, OrbitError> {
        let v: f64 = cell
            .parse()
            .map_err(|_| self.err(line, NAMES[k], format!("expected a number, found {cell:?}")))?;
        if !v.is_finite() {
            return Err(self.err(
                line,
                NAMES[k],
                format!("expected a finite number, found {cell:?}"),
            ));
        }
        if k == 0 && prev_t.is_some_and(|p| v <= p) {
            return Err(self.err(
                line,
                NAMES[0],
                format!("time {v} s is not after the previous row"),
            ));
        }
        if k == 4 && v != 0.0 && v != 1.0 {
            return Err(self.err(
                line,
                NAMES[4],
                format!("expected 0 or 1 (tach pulse flag), found {cell:?}"),
            ));
        }
        Ok(v)
    }
}
