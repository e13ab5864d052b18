//! Plots written by `ncgear orbit`: the kinematic model's orbit (`orbit model --plot`), and of a
//! measured record (`orbit measure --plot-dir`) `orbit.svg` (the record, the filtered orbit, its
//! major axis and the model's orbit) and, of a uniformly sampled record, `spectrum.svg` (the full
//! spectrum of x + iy with the fitted planet lines). Plots are SVG or PNG.

use super::error::{OutputError, create_dir};
use super::plot::{ChartLabels, PlotFormat, Series, line_chart};
use crate::analysis::orbit::Orbit;
use crate::analysis::orbit::evaluate::Evaluation;
use crate::analysis::orbit::measure::{Measurement, Record, full_spectrum};
use crate::analysis::orbit::model::LineKind;
use crate::analysis::orbit::report::ModelReport;
use std::path::{Path, PathBuf};

/// Writes the model orbit of `report` to `path` (SVG, or PNG by extension): the sun's orbit in
/// the carrier frame and its major axis; returns the path written.
///
/// # Errors
/// [`OutputError::Plot`] when the plot cannot be drawn or written.
pub fn write_orbit_model_plot(
    report: &ModelReport,
    path: &Path,
) -> Result<Vec<PathBuf>, OutputError> {
    let o = report.orbit.orbit();
    let trace = o.trace_um(720);
    let mut series = vec![Series::line("sun orbit (carrier frame)", trace)];
    series.push(Series::line("major axis", axis_points(&o)));
    line_chart(
        path,
        &ChartLabels {
            title: "Sun orbit, kinematic model".into(),
            x: "x_s [µm]".into(),
            y: "y_s [µm]".into(),
            equal_aspect: true,
        },
        &series,
        (800, 800),
    )?;
    Ok(vec![path.to_path_buf()])
}

/// Writes the plots of the measurement `m` of the record `rec` (evaluated by `ev`) into `dir`
/// (created if needed): `orbit.EXT` always, `spectrum.EXT` when the record is uniformly
/// sampled; returns the paths written.
///
/// # Errors
/// [`OutputError::Orbit`] when the record cannot be brought into the analysis frame;
/// [`OutputError::Io`] or [`OutputError::Plot`] when a file cannot be written.
pub fn write_orbit_measure_plots(
    dir: &Path,
    rec: &Record,
    m: &Measurement,
    ev: &Evaluation,
    format: PlotFormat,
) -> Result<Vec<PathBuf>, OutputError> {
    let ext = format.ext();
    create_dir(dir)?;
    let mut written = Vec::new();
    let (x, y) = ev.extractor().analysis_signal(rec)?;
    let step = (x.len() / 4000).max(1);
    let raw: Vec<(f64, f64)> = x
        .iter()
        .zip(&y)
        .step_by(step)
        .map(|(a, b)| (*a, *b))
        .collect();
    let mut series = vec![
        Series::markers("raw (detrended)", raw),
        Series::line("filtered orbit / ellipse", m.orbit.trace_um(720)),
    ];
    let axis = axis_points(&m.orbit);
    if !axis.is_empty() {
        series.push(Series::line("major axis", axis));
    }
    if let Some(set) = ev.model() {
        series.push(Series::line("model", set.solve().orbit.trace_um(720)));
    }
    let labels = ChartLabels {
        title: "Sun orbit".into(),
        x: "x [µm]".into(),
        y: "y [µm]".into(),
        equal_aspect: true,
    };
    let orbit_path = dir.join(format!("orbit.{ext}"));
    line_chart(&orbit_path, &labels, &series, (800, 800))?;
    written.push(orbit_path);
    if rec.is_uniform(1e-6) {
        let spectrum_path = dir.join(format!("spectrum.{ext}"));
        spectrum_plot(&spectrum_path, rec, m, &x, &y)?;
        written.push(spectrum_path);
    }
    Ok(written)
}

/// The full spectrum of x + iy up to 1.5 times the highest analysed line, with the fitted
/// planet lines as markers.
fn spectrum_plot(
    path: &Path,
    rec: &Record,
    m: &Measurement,
    x: &[f64],
    y: &[f64],
) -> Result<(), OutputError> {
    let fmax = 1.5
        * m.lines
            .iter()
            .map(|l| l.omega_rad_s.abs())
            .fold(0.0, f64::max)
        / std::f64::consts::TAU;
    let spec: Vec<(f64, f64)> = full_spectrum(rec.mean_step_s(), x, y)
        .into_iter()
        .filter(|p| p.0.abs() <= fmax)
        .collect();
    let mut series = vec![Series::line("|Z(f)| (Hann, analysis frame)", spec)];
    for l in m.lines.iter().filter(|l| l.kind == LineKind::Planet) {
        let f = l.omega_rad_s / std::f64::consts::TAU;
        let a = if l.label.ends_with('+') {
            m.orbit.z_plus_um.norm()
        } else {
            m.orbit.z_minus_um.norm()
        };
        series.push(Series::markers(format!("{} (fit)", l.label), vec![(f, a)]));
    }
    let labels = ChartLabels {
        title: "Full spectrum of x + iy (forward f > 0, backward f < 0)".into(),
        x: "signed frequency [Hz]".into(),
        y: "amplitude [µm]".into(),
        equal_aspect: false,
    };
    Ok(line_chart(path, &labels, &series, (1000, 600))?)
}

/// Major-axis segment of an orbit (empty for a circle).
fn axis_points(o: &Orbit) -> Vec<(f64, f64)> {
    let e = o.ellipse();
    e.alpha_long_rad.map_or_else(Vec::new, |a| {
        let (s, c) = a.sin_cos();
        vec![
            (-e.r_long_um * c, -e.r_long_um * s),
            (e.r_long_um * c, e.r_long_um * s),
        ]
    })
}
