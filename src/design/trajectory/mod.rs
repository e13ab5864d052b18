//! Static needle-tip trajectories: reading, validating, and the periodic interpolant (docs/math/chain.md §3.1).
//!
//! A [`Trajectory`] is a closed polyline of at least [`MIN_POINTS`] finite points in travel order,
//! in mm, with no repeated end point and no duplicate consecutive points. Files:
//!
//! - CSV: optional header line, two columns `x, y` in mm separated by a comma, semicolon or
//!   whitespace; `#` starts a comment; blank lines are skipped.
//! - JSON: `{"units": "mm", "points": [[x, y], ...]}`.
//! - DXF and SVG drawings holding the loop as one closed curve ([`DrawingOptions`]; the
//!   formats, units and sampling: docs/drawings.md and the `drawing` module).
//!
//! ```
//! use ncgear::design::trajectory::Trajectory;
//! let text: String = (0..36)
//!     .map(|k| {
//!         let t = (k as f64).to_radians() * 10.0;
//!         format!("{},{}\n", 100.0 + 20.0 * t.cos(), 20.0 * t.sin())
//!     })
//!     .collect();
//! let traj = Trajectory::parse_csv(&text, "inline.csv").unwrap();
//! assert_eq!(traj.len(), 36);
//! ```

pub(in crate::design) mod roundtrip;

use crate::math::Point;
mod drawing;
mod dxf;
mod dxf_chain;
mod error;
mod flatten;
mod nurbs;
mod retrace;
mod screen;
mod spline;
mod svg;

pub use drawing::{DRAWING_SAMPLES, DrawingOptions, DrawingUnits, FLATNESS_MM, MAX_KEPT_VERTICES};
pub use error::{Origin, TrajectoryError};
pub use spline::ClosedSpline;

use screen::{difference_noise_mm, outlier};
use std::path::Path;

/// Fewest points accepted in a trajectory file.
pub const MIN_POINTS: usize = 20;

/// A closed needle-tip trajectory in travel order, mm.
#[derive(Debug, Clone, PartialEq)]
pub struct Trajectory {
    points: Vec<Point>,
}

impl Trajectory {
    /// Validates points (mm, travel order). `origins[k]` says where point k came from; `file` names
    /// the source in messages. A last point equal to the first is dropped.
    pub fn new(
        points: Vec<Point>,
        origins: &[Origin],
        file: &str,
    ) -> Result<Self, TrajectoryError> {
        let origin = |k: usize| origins.get(k).copied().unwrap_or(Origin::Index(k));
        let file_s = file.to_string();
        if let Some(k) = points
            .iter()
            .position(|p| !(p.x.is_finite() && p.y.is_finite()))
        {
            return Err(TrajectoryError::NotFinite {
                file: file_s,
                origin: origin(k),
            });
        }
        let mut points = points;
        while points.len() > 1 && points[0] == points[points.len() - 1] {
            points.pop();
        }
        if points.len() < MIN_POINTS {
            return Err(TrajectoryError::TooFewPoints {
                file: file_s,
                count: points.len(),
                min: MIN_POINTS,
            });
        }
        if let Some((k, jump, between, spacing)) = outlier(&points) {
            let Point { x, y } = points[k];
            return Err(TrajectoryError::Outlier {
                file: file_s,
                origin: origin(k),
                x,
                y,
                jump_mm: jump,
                neighbours_mm: between,
                spacing_mm: spacing,
            });
        }
        let mut max_step: f64 = 0.0;
        for k in 1..points.len() {
            let d = dist(points[k], points[k - 1]);
            if d == 0.0 {
                let Point { x, y } = points[k];
                return Err(TrajectoryError::DuplicatePoint {
                    file: file_s,
                    origin: origin(k),
                    x,
                    y,
                });
            }
            max_step = max_step.max(d);
        }
        let gap = dist(points[0], points[points.len() - 1]);
        if gap > 4.0 * max_step {
            return Err(TrajectoryError::Open {
                file: file_s,
                gap_mm: gap,
                spacing_mm: max_step,
            });
        }
        Ok(Self { points })
    }

    /// Points already in memory (mm, travel order), e.g. a CAD polyline; validated as a file
    /// would be, with point indices in messages.
    ///
    /// ```
    /// use ncgear::design::trajectory::Trajectory;
    /// use ncgear::math::Point;
    /// let pts: Vec<Point> = (0..40)
    ///     .map(|k| Point::new(100.0, 0.0) + Point::from_polar(20.0, std::f64::consts::TAU * k as f64 / 40.0))
    ///     .collect();
    /// assert_eq!(Trajectory::from_points(pts).unwrap().len(), 40);
    /// ```
    pub fn from_points(points: Vec<Point>) -> Result<Self, TrajectoryError> {
        Self::new(points, &[], "points")
    }

    /// Reads a trajectory file: a DXF or SVG drawing by its extension (`.dxf`, `.svg`; default
    /// [`DrawingOptions`]), else CSV or JSON (JSON when the extension is `.json` or the content
    /// starts with `{`).
    pub fn from_path(path: &Path) -> Result<Self, TrajectoryError> {
        Self::from_path_with(path, &DrawingOptions::default())
    }

    /// As [`Self::from_path`], a drawing read with `opts` (layer, id, units); the options do
    /// not apply to CSV or JSON files.
    pub fn from_path_with(path: &Path, opts: &DrawingOptions) -> Result<Self, TrajectoryError> {
        let file = path.display().to_string();
        let bytes = std::fs::read(path).map_err(|e| TrajectoryError::Unreadable {
            file: file.clone(),
            message: e.to_string(),
        })?;
        Self::from_bytes(&bytes, &file, opts)
    }

    /// The trajectory of a file's contents `bytes`, its format told by the extension of `file`
    /// as [`Self::from_path_with`] tells it (a DXF or SVG drawing read with `opts`, else JSON or
    /// CSV); `file` also names the source in messages. An upload's bytes are read as the file
    /// would be.
    pub fn from_bytes(
        bytes: &[u8],
        file: &str,
        opts: &DrawingOptions,
    ) -> Result<Self, TrajectoryError> {
        let ext = Path::new(file)
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase)
            .unwrap_or_default();
        if ext == "dxf" {
            return Self::from_dxf(bytes, opts, file);
        }
        let text = std::str::from_utf8(bytes).map_err(|e| TrajectoryError::Unreadable {
            file: file.to_string(),
            message: format!("not UTF-8 text ({e})"),
        })?;
        match ext.as_str() {
            "svg" => Self::from_svg(text, opts, file),
            "json" => Self::parse_json(text, file),
            _ => Self::parse(text, file),
        }
    }

    /// Reads the loop of a DXF drawing (text or binary DXF; the `dxf` module docs), resampled
    /// at [`DRAWING_SAMPLES`] points uniform in arc length; `file` names the source in messages.
    pub fn from_dxf(
        bytes: &[u8],
        opts: &DrawingOptions,
        file: &str,
    ) -> Result<Self, TrajectoryError> {
        dxf::read(bytes, opts, file)
    }

    /// Reads the loop of an SVG drawing (the `svg` module docs), y flipped so that up is +y,
    /// resampled at [`DRAWING_SAMPLES`] points uniform in arc length.
    pub fn from_svg(
        text: &str,
        opts: &DrawingOptions,
        file: &str,
    ) -> Result<Self, TrajectoryError> {
        svg::read(text, opts, file)
    }

    /// Parses trajectory text: JSON when it starts with `{`, CSV otherwise; `file` names the
    /// source in messages.
    pub fn parse(text: &str, file: &str) -> Result<Self, TrajectoryError> {
        if text.trim_start().starts_with('{') {
            Self::parse_json(text, file)
        } else {
            Self::parse_csv(text, file)
        }
    }

    /// Parses CSV text (see the module docs); `file` names the source in messages.
    pub fn parse_csv(text: &str, file: &str) -> Result<Self, TrajectoryError> {
        let mut points = Vec::new();
        let mut origins = Vec::new();
        let mut header_seen = false;
        for (i, raw) in text.lines().enumerate() {
            let line = raw.split('#').next().unwrap_or("").trim();
            if line.is_empty() {
                continue;
            }
            let fields: Vec<&str> = line
                .split(|c: char| c == ',' || c == ';' || c.is_whitespace())
                .filter(|s| !s.is_empty())
                .collect();
            let parsed: Option<Vec<f64>> = fields.iter().map(|s| s.parse::<f64>().ok()).collect();
            match parsed {
                Some(v) if v.len() == 2 => {
                    points.push(Point::new(v[0], v[1]));
                    origins.push(Origin::Line(i + 1));
                }
                // One header line is allowed before the first data line.
                None if !header_seen && points.is_empty() => header_seen = true,
                _ => {
                    return Err(TrajectoryError::BadLine {
                        file: file.to_string(),
                        origin: Origin::Line(i + 1),
                        found: line.chars().take(60).collect(),
                    });
                }
            }
        }
        if points.is_empty() {
            return Err(TrajectoryError::TooFewPoints {
                file: file.to_string(),
                count: 0,
                min: MIN_POINTS,
            });
        }
        Self::new(points, &origins, file)
    }

    /// Parses JSON text `{"units": "mm", "points": [[x, y], ...]}`.
    pub fn parse_json(text: &str, file: &str) -> Result<Self, TrajectoryError> {
        #[derive(serde::Deserialize)]
        #[serde(deny_unknown_fields)]
        struct Doc {
            units: Option<String>,
            points: Vec<Point>,
        }
        let bad = |message: String| TrajectoryError::BadJson {
            file: file.to_string(),
            message,
        };
        let doc: Doc = serde_json::from_str(text).map_err(|e| bad(e.to_string()))?;
        if let Some(u) = doc.units.as_deref()
            && u != "mm"
        {
            return Err(bad(format!(
                "field `units` is \"{u}\", only \"mm\" is supported"
            )));
        }
        let origins: Vec<Origin> = (0..doc.points.len()).map(Origin::Index).collect();
        Self::new(doc.points, &origins, file)
    }

    /// Points in mm, travel order, no repeated end point.
    #[must_use]
    pub fn points(&self) -> &[Point] {
        &self.points
    }

    /// Number of points.
    #[must_use]
    pub fn len(&self) -> usize {
        self.points.len()
    }

    /// Always false (a trajectory has at least [`MIN_POINTS`] points).
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }

    /// Estimated measurement noise σ of the points, per coordinate, mm: the trimmed mean of the
    /// squared 4th differences in the point index, `σ² = mean min(|Δ⁴P_j|²/140, c·σ₀²)/(1 −
    /// e^(−c))` (formula and derivation: `screen::difference_noise_mm`; see the design report's
    /// `trajectory.noise_sigma_mm`). Near 0 (µm or less) for exact samples of a smooth curve.
    #[must_use]
    pub fn noise_sigma_mm(&self) -> f64 {
        difference_noise_mm(&self.points)
    }

    /// The same loop relative to `center` (mm), mirrored `y → −y` when `mirror` is set.
    #[must_use]
    pub fn relative_to(&self, center: Point, mirror: bool) -> Vec<Point> {
        let sy = if mirror { -1.0 } else { 1.0 };
        self.points
            .iter()
            .map(|p| Point::new(p.x - center.x, sy * (p.y - center.y)))
            .collect()
    }

    /// Smooths a measured or noisy loop (docs/math/chain.md §3.1, §14): the polyline is resampled at `4·harmonics`
    /// (at least as many as it has points) uniform chord-length positions and `x(s)`, `y(s)` are
    /// truncated to their first `harmonics` Fourier harmonics. The result has the same number of
    /// points as the input, in the same travel order, starting at the same place.
    #[must_use]
    pub fn smoothed(&self, harmonics: usize) -> Self {
        let pts = &self.points;
        let n = pts.len();
        let m = (4 * harmonics).max(n).max(8);
        let mut cum = Vec::with_capacity(n + 1);
        cum.push(0.0);
        for k in 0..n {
            let d = dist(pts[k], pts[(k + 1) % n]);
            cum.push(cum[k] + d);
        }
        let len = cum[n];
        let at = |s: f64| {
            let j = cum.partition_point(|&c| c <= s).clamp(1, n) - 1;
            let f = ((s - cum[j]) / (cum[j + 1] - cum[j])).clamp(0.0, 1.0);
            let (a, b) = (pts[j], pts[(j + 1) % n]);
            a.lerp(b, f)
        };
        let samples: Vec<Point> = (0..m).map(|k| at(len * k as f64 / m as f64)).collect();
        let filt = |coordinate: fn(&Point) -> f64| {
            let mut co = crate::math::periodic::fft_coefficients(
                &samples.iter().map(coordinate).collect::<Vec<_>>(),
            );
            for (k, v) in co.iter_mut().enumerate() {
                if k > harmonics {
                    *v = realfft::num_complex::Complex::new(0.0, 0.0);
                }
            }
            co
        };
        let (cx, cy) = (filt(|p| p.x), filt(|p| p.y));
        // Evaluate the truncated series at the original points' chord positions.
        let eval = |co: &[realfft::num_complex::Complex<f64>], s: f64| {
            let w = std::f64::consts::TAU * s / len;
            co.iter()
                .enumerate()
                .take(harmonics + 1)
                .map(|(k, c)| {
                    let f = if k == 0 { 1.0 } else { 2.0 };
                    f * (c.re * (k as f64 * w).cos() - c.im * (k as f64 * w).sin())
                })
                .sum::<f64>()
        };
        let points = (0..n)
            .map(|k| Point::new(eval(&cx, cum[k]), eval(&cy, cum[k])))
            .collect();
        Self { points }
    }

    /// Chord-length periodic cubic spline through the points (docs/math/chain.md §3.1).
    #[must_use]
    pub fn spline(points: &[Point]) -> ClosedSpline {
        ClosedSpline::through(points)
    }
}

fn dist(p: Point, q: Point) -> f64 {
    p.distance(q)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::{PI, TAU};

    fn circle_csv(n: usize) -> String {
        (0..n)
            .map(|k| {
                let t = std::f64::consts::TAU * k as f64 / n as f64;
                format!("{:.9} {:.9}\n", 150.0 + 40.0 * t.cos(), 40.0 * t.sin())
            })
            .collect()
    }

    #[test]
    fn a_typo_point_is_named_as_an_outlier() {
        let mut lines: Vec<String> = circle_csv(200).lines().map(String::from).collect();
        lines[57] = "7.6e19 12.0".into();
        match Trajectory::parse_csv(&lines.join("\n"), "t.csv") {
            Err(TrajectoryError::Outlier {
                origin, spacing_mm, ..
            }) => {
                assert_eq!(origin, Origin::Line(58));
                assert!((spacing_mm - 2.0 * 40.0 * (PI / 200.0).sin()).abs() < 1e-6);
            }
            other => panic!("expected Outlier, got {other:?}"),
        }
    }

    #[test]
    fn noise_estimate_is_near_zero_on_exact_points_and_near_sigma_on_noisy_ones() {
        let exact = Trajectory::parse_csv(&circle_csv(400), "c.csv").unwrap();
        assert!(exact.noise_sigma_mm() < 1e-5, "{}", exact.noise_sigma_mm());
        // Deterministic Gaussian noise σ = 0.03 mm (Box–Muller on a fixed LCG).
        let mut state = 12345u64;
        let mut uniform = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((state >> 11) as f64 + 0.5) / (1u64 << 53) as f64
        };
        let sigma = 0.03;
        let pts: Vec<Point> = exact
            .points()
            .iter()
            .map(|p| {
                let (u, v) = (uniform(), uniform());
                let r = (-2.0 * u.ln()).sqrt() * sigma;
                Point::new(p.x + r * (TAU * v).cos(), p.y + r * (TAU * v).sin())
            })
            .collect();
        let origins: Vec<Origin> = (0..pts.len()).map(Origin::Index).collect();
        let noisy = Trajectory::new(pts, &origins, "n").unwrap();
        let est = noisy.noise_sigma_mm();
        assert!((est / sigma - 1.0).abs() < 0.2, "{est}");
    }

    #[test]
    fn csv_with_header_comments_and_repeated_end() {
        let mut text = String::from("# tip path\nx_mm,y_mm\n");
        text.push_str(&circle_csv(40));
        let first = text.lines().nth(2).unwrap().to_string();
        text.push_str(&first);
        let t = Trajectory::parse_csv(&text, "a.csv").unwrap();
        assert_eq!(t.len(), 40);
    }

    #[test]
    fn errors_name_line_and_kind() {
        let mut text = circle_csv(40);
        text.push_str("1.0 abc\n");
        match Trajectory::parse_csv(&text, "b.csv") {
            Err(TrajectoryError::BadLine {
                origin: Origin::Line(41),
                ..
            }) => {}
            other => panic!("{other:?}"),
        }
        let dup = circle_csv(40).replacen(
            '\n',
            &format!("\n{}\n", circle_csv(40).lines().next().unwrap()),
            1,
        );
        let dup = format!("{}\n", dup.trim_end());
        assert!(matches!(
            Trajectory::parse_csv(&dup, "c.csv"),
            Err(TrajectoryError::DuplicatePoint {
                origin: Origin::Line(2),
                ..
            })
        ));
        let open: String = circle_csv(40)
            .lines()
            .take(30)
            .map(|l| format!("{l}\n"))
            .collect();
        assert!(matches!(
            Trajectory::parse_csv(&open, "d.csv"),
            Err(TrajectoryError::Open { .. })
        ));
        assert!(matches!(
            Trajectory::parse_csv("1 2\n3 4\n", "e.csv"),
            Err(TrajectoryError::TooFewPoints { count: 2, .. })
        ));
        assert!(matches!(
            Trajectory::parse_csv(&format!("NaN 1\n{}", circle_csv(40)), "f.csv"),
            Err(TrajectoryError::NotFinite {
                origin: Origin::Line(1),
                ..
            })
        ));
        assert!(matches!(
            Trajectory::parse_json(r#"{"units":"in","points":[]}"#, "g.json"),
            Err(TrajectoryError::BadJson { .. })
        ));
    }
}
