//! Files written by `ncgear tolerance`: of an error file `tolerance.json` (the report, last) and,
//! with a Monte Carlo, `histogram.png`; of a transplanter `transplanter.json` (last), the 3σ
//! envelope along the trajectory (`envelope.png`, `envelope.svg`), the trajectory with its
//! deviation band (`band.png`) and the histogram of the largest deviation (`histogram.png`).

use super::error::{OutputError, create_dir, remove_stale, write_json};
use super::plot::{ChartLabels, Series, line_chart};
use crate::analysis::tolerance::ToleranceReport;
use crate::analysis::transplanter::TransplanterReport;
use std::path::{Path, PathBuf};

/// Writes the files of the error-file analysis `report` into `dir` (created if needed), the
/// report last; returns the paths written.
///
/// # Errors
/// [`OutputError`] when a file cannot be written or drawn.
pub fn write_tolerance(report: &ToleranceReport, dir: &Path) -> Result<Vec<PathBuf>, OutputError> {
    create_dir(dir)?;
    let json_path = dir.join("tolerance.json");
    remove_stale(&json_path)?;
    let mut written = Vec::new();
    if let Some(s) = &report.monte_carlo_arcsec {
        let path = dir.join("histogram.png");
        line_chart(
            &path,
            &ChartLabels {
                title: format!("Peak transmission error over {} random assemblies", s.n),
                x: "peak transmission error (arc seconds)".into(),
                y: "samples per bin".into(),
                equal_aspect: false,
            },
            &[
                Series::line("random assembly", s.step_outline()),
                Series::markers(
                    "greedy compensation",
                    vec![(report.greedy_peak_arcsec, 0.0)],
                ),
            ],
            (900, 500),
        )?;
        written.push(path);
    }
    write_json(&json_path, report)?;
    written.push(json_path);
    Ok(written)
}

/// Writes the files of the transplanter analysis `report` into `dir` (created if needed), the
/// report last; returns the paths written.
///
/// # Errors
/// [`OutputError`] when a file cannot be written or drawn.
pub fn write_transplanter(
    report: &TransplanterReport,
    dir: &Path,
) -> Result<Vec<PathBuf>, OutputError> {
    create_dir(dir)?;
    let json_path = dir.join("transplanter.json");
    remove_stale(&json_path)?;
    let mut written = envelope_plots(report, dir)?;
    written.push(band_plot(report, dir)?);
    written.push(histogram_plot(report, dir)?);
    write_json(&json_path, report)?;
    written.push(json_path);
    Ok(written)
}

/// The 3σ envelope of the tip deviation along the trajectory, the deviation of the errors as
/// given and of the best assembly (PNG and SVG).
fn envelope_plots(r: &TransplanterReport, dir: &Path) -> Result<Vec<PathBuf>, OutputError> {
    let n = r.envelope.len().max(1);
    let x = |i: usize| 360.0 * i as f64 / n as f64;
    let mut series = vec![
        Series::line(
            "3σ envelope |mean| + 3σ (random assembly)",
            r.envelope
                .iter()
                .enumerate()
                .map(|(i, p)| (x(i), p.envelope_um))
                .collect(),
        ),
        Series::line(
            "errors as given",
            r.envelope
                .iter()
                .enumerate()
                .map(|(i, p)| (x(i), p.nominal_errors_um))
                .collect(),
        ),
    ];
    if let Some(a) = &r.assembly {
        series.push(Series::line(
            "best assembly of the free runouts",
            a.joint_deviation_um
                .iter()
                .enumerate()
                .map(|(i, v)| (x(i), *v))
                .collect(),
        ));
    }
    let mut written = Vec::new();
    for ext in ["png", "svg"] {
        let path = dir.join(format!("envelope.{ext}"));
        line_chart(
            &path,
            &ChartLabels {
                title: "Needle-tip deviation along the trajectory".into(),
                x: "carrier angle from φH = 0 in the direction of rotation (deg)".into(),
                y: "|ΔB| (µm)".into(),
                equal_aspect: false,
            },
            &series,
            (900, 500),
        )?;
        written.push(path);
    }
    Ok(written)
}

/// The trajectory band: the nominal path ± the envelope (magnified) along the path normal.
fn band_plot(r: &TransplanterReport, dir: &Path) -> Result<PathBuf, OutputError> {
    let mag = r.band_magnification();
    let path = dir.join("band.png");
    line_chart(
        &path,
        &ChartLabels {
            title: format!("Needle-tip trajectory with the 3σ deviation band (band ×{mag:.0})"),
            x: "x (mm)".into(),
            y: "y (mm)".into(),
            equal_aspect: true,
        },
        &[
            Series::line("nominal", r.band(0.0, mag)),
            Series::line("outer band", r.band(1.0, mag)),
            Series::line("inner band", r.band(-1.0, mag)),
        ],
        (800, 700),
    )?;
    Ok(path)
}

/// The histogram of the largest deviation over one turn: all errors random, and with the free
/// runouts random and the best assembly marked.
fn histogram_plot(r: &TransplanterReport, dir: &Path) -> Result<PathBuf, OutputError> {
    let mut hist = vec![Series::line(
        "all errors random",
        r.max_deviation_um.step_outline(),
    )];
    if let Some(a) = &r.assembly {
        hist.push(Series::line(
            "random runout orientation, other errors as given",
            a.random.step_outline(),
        ));
        hist.push(Series::markers("best assembly", vec![(a.joint_um, 0.0)]));
    }
    let path = dir.join("histogram.png");
    line_chart(
        &path,
        &ChartLabels {
            title: format!(
                "max |ΔB| over one turn, {} random assemblies",
                r.max_deviation_um.n
            ),
            x: "max |ΔB| (µm)".into(),
            y: "samples per bin".into(),
            equal_aspect: false,
        },
        &hist,
        (900, 500),
    )?;
    Ok(path)
}
