//! Files written by `ncgear simulate`: the traced and dynamic paths (CSV, mm), the animation and
//! the frame sheet (SVG), the charts of [`super::simulation_plots`], and the report
//! (`simulate.json`, last).

use super::animate::{AnimationOptions, animated_svg, frame_sheet};
use super::error::{OutputError, create_dir, remove_stale, write, write_json};
use super::simulation_plots::{Traces, write_plots};
use crate::math::Point;
use crate::simulate::{
    FeatureOptions, Features, SimulateError, Simulation, deviation_along, features,
};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Everything `ncgear simulate` reports besides the files.
#[derive(Debug, Clone, serde::Serialize, schemars::JsonSchema)]
pub struct SimulationReport {
    /// Agronomic features.
    pub features: Features,
    /// Max / mean distance of the traced path from the target, mm (absent without a target).
    pub deviation_max_mm: Option<f64>,
    /// Mean distance from the target, mm.
    pub deviation_mean_mm: Option<f64>,
    /// Largest distance between arm 2's path and arm 1's path, mm (0: same static trajectory).
    pub arm2_vs_arm1_mm: f64,
    /// Carrier speed, rpm.
    pub rpm: f64,
    /// Forward speed, mm/s.
    pub forward_speed_mm_s: f64,
    /// Files written.
    pub files: Vec<String>,
}

/// Writes the simulation outputs into `dir`: traced.csv, dynamic.csv, animation.svg, frames.svg,
/// plots (PNG and SVG) of the deviation, the ratios, the pitch curves, curvature/pressure angle and
/// the dynamic trajectory, and last the report, simulate.json (an earlier run's removed before
/// the first file). Returns the report.
///
/// # Errors
/// [`SimulateError::BadOption`] (option `out`) when a file cannot be written; the features'
/// errors.
pub fn write_simulation(
    sim: &Simulation,
    target: &[Point],
    feat_opts: &FeatureOptions,
    anim: &AnimationOptions,
    dir: &Path,
) -> Result<SimulationReport, SimulateError> {
    let io = |e: OutputError| SimulateError::BadOption {
        option: "out",
        message: e.to_string(),
    };
    create_dir(dir).map_err(io)?;
    let json_path = dir.join("simulate.json");
    remove_stale(&json_path).map_err(io)?;
    let features = features(sim, feat_opts)?;
    let n = feat_opts.samples.max(360);
    let turn = sim.turn(n);
    let arm1: Vec<Point> = turn.iter().map(|t| t.arm1.tip_mm).collect();
    let arm2: Vec<Point> = turn.iter().map(|t| t.arm2.tip_mm).collect();
    let dev = if target.len() >= 3 {
        deviation_along(&arm1, target)
    } else {
        Vec::new()
    };
    let arm2_vs_arm1 = crate::math::polyline::hausdorff_mm(&arm2, &arm1);
    let mut written: Vec<PathBuf> = Vec::new();
    let mut csv = String::from(
        "carrier_deg,arm1_x_mm,arm1_y_mm,arm2_x_mm,arm2_y_mm,needle1_deg,deviation_mm\n",
    );
    for (k, t) in turn.iter().enumerate() {
        let _ = writeln!(
            csv,
            "{:.6},{:.9},{:.9},{:.9},{:.9},{:.6},{}",
            t.arm1.phi_h_rad.to_degrees(),
            t.arm1.tip_mm.x,
            t.arm1.tip_mm.y,
            t.arm2.tip_mm.x,
            t.arm2.tip_mm.y,
            Simulation::needle_angle(&t.arm1).to_degrees(),
            dev.get(k).map_or(String::new(), |d| format!("{d:.9}"))
        );
    }
    let p = dir.join("traced.csv");
    write(&p, &csv).map_err(io)?;
    written.push(p);
    let dynamic = sim.dynamic(feat_opts.rpm, feat_opts.forward_mm_s, 3, 720);
    let mut csv = String::from("turn_fraction,arm1_x_mm,arm1_y_mm,arm2_x_mm,arm2_y_mm\n");
    for (k, (p1, p2)) in dynamic[0].iter().zip(&dynamic[1]).enumerate() {
        let _ = writeln!(
            csv,
            "{:.6},{:.9},{:.9},{:.9},{:.9}",
            k as f64 / 720.0,
            p1.x,
            p1.y,
            p2.x,
            p2.y
        );
    }
    let p = dir.join("dynamic.csv");
    write(&p, &csv).map_err(io)?;
    written.push(p);
    let p = dir.join("animation.svg");
    write(&p, &animated_svg(sim, target, anim)).map_err(io)?;
    written.push(p);
    let p = dir.join("frames.svg");
    write(&p, &frame_sheet(sim, target, 4, 3, 360)).map_err(io)?;
    written.push(p);
    write_plots(
        sim,
        feat_opts,
        &features,
        &Traces {
            deviation_mm: &dev,
            arm1_mm: &arm1,
            dynamic_mm: &dynamic,
        },
        dir,
        &mut written,
    )
    .map_err(io)?;
    let stats = (!dev.is_empty()).then(|| {
        (
            dev.iter().fold(0.0, |a: f64, b| a.max(*b)),
            dev.iter().sum::<f64>() / dev.len() as f64,
        )
    });
    let report = SimulationReport {
        features,
        deviation_max_mm: stats.map(|s| s.0),
        deviation_mean_mm: stats.map(|s| s.1),
        arm2_vs_arm1_mm: arm2_vs_arm1,
        rpm: feat_opts.rpm,
        forward_speed_mm_s: feat_opts.forward_mm_s,
        files: written.iter().map(|p| p.display().to_string()).collect(),
    };
    write_json(&json_path, &report).map_err(io)?;
    Ok(report)
}
