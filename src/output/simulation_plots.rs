//! The charts of `ncgear simulate`, each as PNG and SVG (plotters): deviation from the target,
//! ratios from the kinematics, pitch curves, radius of curvature, pressure-angle deviation, the
//! dynamic trajectory and the agronomic features drawn on the static path.

use super::error::OutputError;
use super::plot::{ChartLabels, Series, line_chart};
use crate::geometry::assembly::Pose;
use crate::geometry::pitch::{PitchCurve, PolarGeometry};
use crate::math::Point;
use crate::simulate::{FeatureOptions, Features, Simulation};
use std::f64::consts::TAU;
use std::path::{Path, PathBuf};

/// The sampled paths the charts draw (computed once by the caller).
pub(super) struct Traces<'a> {
    /// Distance of arm 1's tip from the target at each sample of the turn, mm (empty: no target).
    pub deviation_mm: &'a [f64],
    /// Arm 1's static path, `max(samples, 360)` instants over one turn, mm.
    pub arm1_mm: &'a [Point],
    /// Dynamic paths of arms 1 and 2, mm.
    pub dynamic_mm: &'a [Vec<Point>; 2],
}

/// Writes `path` with the extensions `png` and `svg`, appending both to `written`.
fn both(
    path: &Path,
    labels: &ChartLabels,
    series: &[Series],
    size: (u32, u32),
    written: &mut Vec<PathBuf>,
) -> Result<(), OutputError> {
    for ext in ["png", "svg"] {
        let p = path.with_extension(ext);
        line_chart(&p, labels, series, size)?;
        written.push(p);
    }
    Ok(())
}

/// Writes the charts into `dir` (deviation only with a target), appending the paths to `written`.
pub(super) fn write_plots(
    sim: &Simulation,
    feat_opts: &FeatureOptions,
    features: &Features,
    traces: &Traces,
    dir: &Path,
    written: &mut Vec<PathBuf>,
) -> Result<(), OutputError> {
    let (dev, arm1, dynamic) = (traces.deviation_mm, traces.arm1_mm, traces.dynamic_mm);
    let n = feat_opts.samples.max(360);
    let pts = |v: &[f64]| along_turn(v, n);
    if !dev.is_empty() {
        both(
            &dir.join("deviation"),
            &ChartLabels {
                title: "Distance of the traced path from the target".into(),
                x: "carrier turn (deg)".into(),
                y: "deviation (mm)".into(),
                equal_aspect: false,
            },
            &[Series::line("arm 1", pts(dev))],
            (900, 450),
            written,
        )?;
    }
    ratio_plot(sim, n, dir, written)?;
    pitch_plots(&sim.assembly, dir, written)?;
    let xy = |v: &[Point]| v.iter().map(|p| (p.x, p.y)).collect::<Vec<_>>();
    both(
        &dir.join("dynamic"),
        &ChartLabels {
            title: format!(
                "Dynamic trajectory at {:.0} rpm, {:.2} m/s",
                feat_opts.rpm,
                feat_opts.forward_mm_s / 1000.0
            ),
            x: "x (mm)".into(),
            y: "y (mm)".into(),
            equal_aspect: true,
        },
        &[
            Series::line("arm 1", xy(&dynamic[0])),
            Series::line("arm 2", xy(&dynamic[1])),
        ],
        (1100, 600),
        written,
    )?;
    features_plot(sim, feat_opts, features, arm1, dir, written)
}

/// Samples `v` of a turn of `n` instants as chart points `(carrier angle in degrees, value)`.
fn along_turn(v: &[f64], n: usize) -> Vec<(f64, f64)> {
    v.iter()
        .enumerate()
        .map(|(k, y)| (360.0 * k as f64 / n as f64, *y))
        .collect()
}

/// The ratios i21, i31, i3H along the carrier turn at `n` instants, from the kinematics.
fn ratio_plot(
    sim: &Simulation,
    n: usize,
    dir: &Path,
    written: &mut Vec<PathBuf>,
) -> Result<(), OutputError> {
    let pts = |v: &[f64]| along_turn(v, n);
    // Ratios from the kinematics (central differences of the continuous pose angles):
    // i21 = dθ2/dφ − 1, i3H = dθ3/dφ, i31 = 1 − i3H (φ in the direction of motion).
    let hf = 1e-4;
    let rate = |k: usize, f: &dyn Fn(&Pose) -> f64| {
        let x = k as f64 / n as f64;
        let (p, m) = (
            sim.pose(sim.angle_at(x + hf)).arm1,
            sim.pose(sim.angle_at(x - hf)).arm1,
        );
        (f(&p) - f(&m)) / (sim.angle_at(x + hf) - sim.angle_at(x - hf))
    };
    let i21: Vec<f64> = (0..n)
        .map(|k| rate(k, &|p| p.intermediate_angle_rad) - 1.0)
        .collect();
    let i3h: Vec<f64> = (0..n).map(|k| rate(k, &|p| p.planet_angle_rad)).collect();
    let i31: Vec<f64> = i3h.iter().map(|v| 1.0 - v).collect();
    both(
        &dir.join("ratios"),
        &ChartLabels {
            title: "Ratios along the carrier turn".into(),
            x: "carrier turn (deg)".into(),
            y: "ratio (-)".into(),
            equal_aspect: false,
        },
        &[
            Series::line("i21", pts(&i21)),
            Series::line("i31", pts(&i31)),
            Series::line("i3H", pts(&i3h)),
        ],
        (900, 450),
        written,
    )
}

/// The pitch curves in their body frames, and their radius of curvature and pressure-angle
/// deviation along the body polar angle.
fn pitch_plots(
    asm: &crate::geometry::assembly::Assembly,
    dir: &Path,
    written: &mut Vec<PathBuf>,
) -> Result<(), OutputError> {
    let curve_xy = |c: &PitchCurve| {
        (0..=720)
            .map(|k| {
                let t = TAU * k as f64 / 720.0;
                let r = c.radius_mm(t);
                (r * t.cos(), r * t.sin())
            })
            .collect::<Vec<_>>()
    };
    both(
        &dir.join("pitch"),
        &ChartLabels {
            title: "Pitch curves (body frames)".into(),
            x: "x (mm)".into(),
            y: "y (mm)".into(),
            equal_aspect: true,
        },
        &[
            Series::line("sun", curve_xy(&asm.sun)),
            Series::line("intermediate", curve_xy(&asm.intermediate)),
            Series::line("planet", curve_xy(&asm.planet)),
        ],
        (700, 700),
        written,
    )?;
    let along = |c: &PitchCurve, f: &dyn Fn(PolarGeometry) -> f64| {
        (0..=720)
            .map(|k| {
                let t = TAU * k as f64 / 720.0;
                (t.to_degrees(), f(c.geometry(t)))
            })
            .collect::<Vec<_>>()
    };
    let rho = |g: PolarGeometry| g.radius_of_curvature_mm();
    let mu = |g: PolarGeometry| g.pressure_deviation_rad().to_degrees();
    both(
        &dir.join("curvature"),
        &ChartLabels {
            title: "Radius of curvature along the pitch curves".into(),
            x: "body polar angle (deg)".into(),
            y: "radius of curvature (mm)".into(),
            equal_aspect: false,
        },
        &[
            Series::line("sun", along(&asm.sun, &rho)),
            Series::line("intermediate", along(&asm.intermediate, &rho)),
        ],
        (900, 450),
        written,
    )?;
    both(
        &dir.join("pressure_angle"),
        &ChartLabels {
            title: "Pressure-angle deviation atan(r'/r) along the pitch curves".into(),
            x: "body polar angle (deg)".into(),
            y: "deviation (deg)".into(),
            equal_aspect: false,
        },
        &[
            Series::line("sun", along(&asm.sun, &mu)),
            Series::line("intermediate", along(&asm.intermediate, &mu)),
        ],
        (900, 450),
        written,
    )?;
    Ok(())
}

/// The agronomic features drawn on the static path `arm1`: taking and planting instants with
/// the needle, the soil level at the planting depth, the hole width on the dynamic stroke.
fn features_plot(
    sim: &Simulation,
    feat_opts: &FeatureOptions,
    features: &Features,
    arm1: &[Point],
    dir: &Path,
    written: &mut Vec<PathBuf>,
) -> Result<(), OutputError> {
    let xy = |v: &[Point]| v.iter().map(|p| (p.x, p.y)).collect::<Vec<_>>();
    let f = features;
    let at = |deg: f64| {
        sim.pose(f64::from(sim.assembly.direction) * deg.to_radians())
            .arm1
    };
    let (take, plant) = (at(f.take_carrier_deg), at(f.plant_carrier_deg));
    let level = f.bbox_mm[2] + feat_opts.planting_depth_mm;
    both(
        &dir.join("features"),
        &ChartLabels {
            title: format!(
                "H = {:.1} mm, hole {:.1} mm at {:.0} mm depth, needle {:.1}° taking / {:.1}° planting",
                f.height_mm,
                f.hole_width_mm,
                feat_opts.planting_depth_mm,
                f.needle_angle_take_deg,
                f.needle_angle_plant_deg
            ),
            x: "x (mm)".into(),
            y: "y (mm)".into(),
            equal_aspect: true,
        },
        &[
            Series::line("static path", xy(arm1)),
            Series::line(
                "needle at taking",
                xy(&[take.planet_center_mm, take.tip_mm]),
            ),
            Series::line(
                "needle at planting",
                xy(&[plant.planet_center_mm, plant.tip_mm]),
            ),
            Series::line(
                "soil level (planting depth)",
                vec![(f.bbox_mm[0], level), (f.bbox_mm[1], level)],
            ),
            Series::markers("taking / planting points", xy(&[take.tip_mm, plant.tip_mm])),
        ],
        (1000, 800),
        written,
    )?;
    Ok(())
}
