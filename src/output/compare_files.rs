//! Files written by `ncgear compare`: `compare_frames.csv` (every frame registered),
//! `compare.svg` (and `compare.png` on request, [`super::compare_plot`]) and `compare.json`
//! (the report, last).

use super::compare_plot::compare_chart;
use super::error::{OutputError, create_dir, remove_stale, write, write_json};
use crate::compare::{CompareReport, Comparison};
use std::fmt::Write as _;
use std::path::Path;

/// `compare_frames.csv`: per frame its line in the track file, time (s), carrier angle (deg,
/// unwrapped), registered tip (mm), deviation from the design tip at that angle (mm), the smooth
/// deviation `d(φ)` there (mm) and whether it is an outlier (0/1).
#[must_use]
pub fn compare_frames_csv(c: &Comparison) -> String {
    let mut s = String::from(
        "line,time_s,carrier_deg,x_mm,y_mm,dx_mm,dy_mm,deviation_mm,smooth_dx_mm,smooth_dy_mm,outlier\n",
    );
    for f in &c.frames {
        let _ = writeln!(
            s,
            "{},{:.6},{:.4},{:.4},{:.4},{:.4},{:.4},{:.4},{:.4},{:.4},{}",
            f.line,
            f.time_s,
            f.phi_rad.to_degrees(),
            f.q_mm.x,
            f.q_mm.y,
            f.residual_mm.x,
            f.residual_mm.y,
            f.residual_mm.norm(),
            f.smooth_mm.x,
            f.smooth_mm.y,
            u8::from(f.outlier)
        );
    }
    s
}

/// Writes the files of comparison `c` into `dir` (created if needed), `compare.json` last, and
/// returns the report with their names.
///
/// # Errors
/// [`OutputError`] when a file cannot be written or drawn.
pub fn write_compare(c: &Comparison, dir: &Path, png: bool) -> Result<CompareReport, OutputError> {
    create_dir(dir)?;
    let json = dir.join("compare.json");
    remove_stale(&json)?;
    let mut names = vec!["compare_frames.csv".to_string()];
    write(&dir.join(&names[0]), &compare_frames_csv(c))?;
    let exts: &[&str] = if png { &["svg", "png"] } else { &["svg"] };
    for ext in exts {
        let name = format!("compare.{ext}");
        compare_chart(c, &dir.join(&name))?;
        names.push(name);
    }
    let mut report = c.report.clone();
    report.files = names;
    write_json(&json, &report)?;
    Ok(report)
}
