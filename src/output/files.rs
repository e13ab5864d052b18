//! Files written by `ncgear design`: `design.json`, pitch tables, the mechanism preview and the
//! ratio plot. All lengths in mm, angles in degrees; SVG user unit = 1 mm.

use crate::design::Design;
use crate::geometry::assembly::Assembly;
use crate::geometry::pitch::PitchCurve;
use crate::output::plot::{ChartLabels, Series, line_chart};
use std::f64::consts::TAU;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Why an output file could not be written.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum OutputError {
    /// File system error.
    #[error("cannot write {path}: {message}")]
    Io {
        /// Path.
        path: String,
        /// OS message.
        message: String,
    },
    /// Plotting failed.
    #[error(transparent)]
    Plot(#[from] crate::output::plot::PlotError),
    /// A CAD export failed.
    #[error(transparent)]
    Export(#[from] crate::export::ExportError),
}

fn write(path: &Path, text: &str) -> Result<(), OutputError> {
    std::fs::write(path, text).map_err(|e| OutputError::Io {
        path: path.display().to_string(),
        message: e.to_string(),
    })
}

/// A pitch table as CSV: header `theta_deg,r_mm,x_mm,y_mm`, body frame, `n` uniform samples.
#[must_use]
pub fn pitch_csv(curve: &PitchCurve, n: usize) -> String {
    let mut s = String::from("theta_deg,r_mm,x_mm,y_mm\n");
    for k in 0..n {
        let th = TAU * k as f64 / n as f64;
        let r = curve.radius_mm(th);
        let _ = writeln!(
            s,
            "{:.6},{:.9},{:.9},{:.9}",
            th.to_degrees(),
            r,
            r * th.cos(),
            r * th.sin()
        );
    }
    s
}

/// Writes every design output into `dir` (created if needed); returns the paths written.
pub fn write_design(design: &Design, dir: &Path) -> Result<Vec<PathBuf>, OutputError> {
    std::fs::create_dir_all(dir).map_err(|e| OutputError::Io {
        path: dir.display().to_string(),
        message: e.to_string(),
    })?;
    let mut written = Vec::new();
    let json = serde_json::to_string_pretty(&design.report).map_err(|e| OutputError::Io {
        path: "design.json".into(),
        message: e.to_string(),
    })?;
    let p = dir.join("design.json");
    write(&p, &json)?;
    written.push(p);
    let n = design.report.gears.sun.pitch.len();
    let asm = &design.assembly;
    for (name, curve) in [
        ("sun", &asm.sun),
        ("intermediate", &asm.intermediate),
        ("planet", &asm.planet),
    ] {
        let p = dir.join(format!("{name}.csv"));
        write(&p, &pitch_csv(curve, n))?;
        written.push(p);
    }
    let mut traced = String::from("x_mm,y_mm\n");
    for q in &design.traced_mm {
        let _ = writeln!(traced, "{:.9},{:.9}", q[0], q[1]);
    }
    let p = dir.join("traced.csv");
    write(&p, &traced)?;
    written.push(p);
    let target: Vec<[f64; 2]> = design
        .inversion
        .points
        .iter()
        .map(|q| {
            [
                asm.center_mm[0] + q[0],
                asm.center_mm[1] + f64::from(asm.direction) * q[1],
            ]
        })
        .collect();
    let p = dir.join("design.svg");
    write(&p, &mechanism_svg(asm, &target, &design.traced_mm, 0.0))?;
    written.push(p);
    let p = dir.join("design.png");
    mechanism_chart(asm, &target, &design.traced_mm, 0.0, &p)?;
    written.push(p);
    let p = dir.join("ratio.svg");
    ratio_plot(design, &p)?;
    written.push(p);
    Ok(written)
}

/// Polyline points of a pitch curve placed at `center` with orientation `angle` (rad), mm.
fn placed(curve: &PitchCurve, center: [f64; 2], angle: f64, n: usize) -> Vec<[f64; 2]> {
    (0..n)
        .map(|k| {
            let th = TAU * k as f64 / n as f64;
            let r = curve.radius_mm(th);
            [
                center[0] + r * (th + angle).cos(),
                center[1] + r * (th + angle).sin(),
            ]
        })
        .collect()
}

fn path_d(pts: &[[f64; 2]], close: bool) -> String {
    let mut d = String::new();
    for (k, p) in pts.iter().enumerate() {
        let _ = write!(
            d,
            "{}{:.4},{:.4} ",
            if k == 0 { "M" } else { "L" },
            p[0],
            -p[1]
        );
    }
    if close {
        d.push('Z');
    }
    d
}

/// SVG preview (mm) of the mechanism at carrier angle `phi_h` (rad): the three pitch curves on
/// the carrier, the needle, the target and the traced trajectory. One group per layer.
#[must_use]
pub fn mechanism_svg(
    asm: &Assembly,
    target: &[[f64; 2]],
    traced: &[[f64; 2]],
    phi_h: f64,
) -> String {
    let pose = asm.rebuild().pose(phi_h);
    let o = asm.center_mm;
    let n = 720;
    let sun = placed(&asm.sun, o, 0.0, n);
    let mid = placed(
        &asm.intermediate,
        pose.intermediate_center_mm,
        pose.intermediate_angle_rad,
        n,
    );
    let planet = placed(&asm.planet, pose.planet_center_mm, pose.planet_angle_rad, n);
    let all: Vec<[f64; 2]> = sun
        .iter()
        .chain(&mid)
        .chain(&planet)
        .chain(target)
        .chain(traced)
        .copied()
        .collect();
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for p in &all {
        x0 = x0.min(p[0]);
        x1 = x1.max(p[0]);
        y0 = y0.min(p[1]);
        y1 = y1.max(p[1]);
    }
    let m = 10.0;
    let (w, h) = (x1 - x0 + 2.0 * m, y1 - y0 + 2.0 * m);
    let mut s = String::new();
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w:.3}mm" height="{h:.3}mm" viewBox="{:.3} {:.3} {w:.3} {h:.3}">"#,
        x0 - m,
        -y1 - m
    );
    let _ = writeln!(
        s,
        r##"<rect x="{:.3}" y="{:.3}" width="{w:.3}" height="{h:.3}" fill="#ffffff"/>"##,
        x0 - m,
        -y1 - m
    );
    let layer = |s: &mut String, id: &str, stroke: &str, width: f64, d: String| {
        let _ = writeln!(
            s,
            r#"<g id="{id}"><path d="{d}" fill="none" stroke="{stroke}" stroke-width="{width}"/></g>"#
        );
    };
    layer(&mut s, "target", "#999999", 1.2, path_d(target, true));
    layer(&mut s, "traced", "#d62728", 0.5, path_d(traced, true));
    layer(&mut s, "sun", "#1f77b4", 0.5, path_d(&sun, true));
    layer(&mut s, "intermediate", "#2ca02c", 0.5, path_d(&mid, true));
    layer(&mut s, "planet", "#9467bd", 0.5, path_d(&planet, true));
    let a = pose.planet_center_mm;
    layer(&mut s, "carrier", "#444444", 0.8, path_d(&[o, a], false));
    layer(
        &mut s,
        "needle",
        "#ff7f0e",
        1.0,
        path_d(&[a, pose.tip_mm], false),
    );
    let _ = writeln!(s, r##"<g id="centres" fill="#000000">"##);
    for c in [o, pose.intermediate_center_mm, a] {
        let _ = writeln!(s, r#"<circle cx="{:.3}" cy="{:.3}" r="1.2"/>"#, c[0], -c[1]);
    }
    let _ = writeln!(s, "</g>");
    let _ = writeln!(
        s,
        r##"<g id="text" font-family="sans-serif" font-size="5" fill="#222222"><text x="{:.3}" y="{:.3}">ncgear design at carrier angle {:.1}° — grey: target, red: traced, blue: sun, green: intermediate, violet: planet</text></g>"##,
        x0 - m + 2.0,
        -y1 - m + 6.0,
        phi_h.to_degrees()
    );
    s.push_str("</svg>\n");
    s
}

/// The mechanism preview as a chart (PNG or SVG by extension, equal axes, mm).
pub fn mechanism_chart(
    asm: &Assembly,
    target: &[[f64; 2]],
    traced: &[[f64; 2]],
    phi_h: f64,
    path: &Path,
) -> Result<(), OutputError> {
    let pose = asm.rebuild().pose(phi_h);
    let closed = |mut v: Vec<[f64; 2]>| {
        if let Some(f) = v.first().copied() {
            v.push(f);
        }
        v.into_iter().map(|p| (p[0], p[1])).collect::<Vec<_>>()
    };
    let n = 720;
    let series = vec![
        Series::line("target", closed(target.to_vec())),
        Series::line("traced (round trip)", closed(traced.to_vec())),
        Series::line("sun", closed(placed(&asm.sun, asm.center_mm, 0.0, n))),
        Series::line(
            "intermediate",
            closed(placed(
                &asm.intermediate,
                pose.intermediate_center_mm,
                pose.intermediate_angle_rad,
                n,
            )),
        ),
        Series::line(
            "planet",
            closed(placed(
                &asm.planet,
                pose.planet_center_mm,
                pose.planet_angle_rad,
                n,
            )),
        ),
        Series::line(
            "carrier + needle",
            vec![
                (asm.center_mm[0], asm.center_mm[1]),
                (pose.planet_center_mm[0], pose.planet_center_mm[1]),
                (pose.tip_mm[0], pose.tip_mm[1]),
            ],
        ),
    ];
    line_chart(
        path,
        &ChartLabels {
            title: format!("Mechanism at carrier angle {:.0}°", phi_h.to_degrees()),
            x: "x (mm)".into(),
            y: "y (mm)".into(),
            equal_aspect: true,
        },
        &series,
        (900, 800),
    )?;
    Ok(())
}

/// Plot of i21 and i31 against the sun angle / carrier angle (degrees after the reference ray).
pub fn ratio_plot(design: &Design, path: &Path) -> Result<(), OutputError> {
    let m = &design.mechanism;
    let n = 720;
    let i21: Vec<(f64, f64)> = (0..=n)
        .map(|k| {
            let t = TAU * k as f64 / n as f64;
            (t.to_degrees(), m.ratio.value(t))
        })
        .collect();
    let i31: Vec<(f64, f64)> = (0..=n)
        .map(|k| {
            let t = TAU * k as f64 / n as f64;
            (
                t.to_degrees(),
                m.ratio.value(t) / m.ratio.value(m.half_turn_map(t)),
            )
        })
        .collect();
    let target: Vec<(f64, f64)> = {
        let law = &design.inversion.law;
        let tau = m.sun_phase_rad - design.inversion.phi_h0_rad;
        (0..=n)
            .map(|k| {
                let t = TAU * k as f64 / n as f64;
                (t.to_degrees(), law.i31(t + tau))
            })
            .collect()
    };
    line_chart(
        path,
        &ChartLabels {
            title: "Gear ratios over one turn".into(),
            x: "sun angle from the design reference ray (deg)".into(),
            y: "ratio (-)".into(),
            equal_aspect: false,
        },
        &[
            Series::line("i21 (sun → intermediate)", i21),
            Series::line("i31 (design)", i31),
            Series::line("i31 (target)", target),
        ],
        (900, 500),
    )?;
    Ok(())
}

/// Everything `ncgear simulate` reports besides the files.
#[derive(Debug, Clone, serde::Serialize)]
pub struct SimulationReport {
    /// Agronomic features.
    pub features: crate::simulate::Features,
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

/// Writes the simulation outputs into `dir`: traced.csv, dynamic.csv, animation.svg, frames.svg and
/// plots (PNG and SVG) of the deviation, the ratios, the pitch curves, curvature/pressure angle and
/// the dynamic trajectory. Returns the report.
pub fn write_simulation(
    sim: &crate::simulate::Simulation,
    target: &[[f64; 2]],
    feat_opts: &crate::simulate::FeatureOptions,
    anim: &crate::output::animate::AnimationOptions,
    dir: &Path,
) -> Result<SimulationReport, crate::simulate::SimulateError> {
    use crate::simulate::{SimulateError, deviation_along, features};
    let io = |e: OutputError| SimulateError::BadOption {
        option: "out",
        message: e.to_string(),
    };
    std::fs::create_dir_all(dir).map_err(|e| {
        io(OutputError::Io {
            path: dir.display().to_string(),
            message: e.to_string(),
        })
    })?;
    let features = features(sim, feat_opts)?;
    let n = feat_opts.samples.max(360);
    let turn = sim.turn(n);
    let arm1: Vec<[f64; 2]> = turn.iter().map(|t| t.arm1.tip_mm).collect();
    let arm2: Vec<[f64; 2]> = turn.iter().map(|t| t.arm2.tip_mm).collect();
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
            t.arm1.tip_mm[0],
            t.arm1.tip_mm[1],
            t.arm2.tip_mm[0],
            t.arm2.tip_mm[1],
            crate::simulate::Simulation::needle_angle(&t.arm1).to_degrees(),
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
            p1[0],
            p1[1],
            p2[0],
            p2[1]
        );
    }
    let p = dir.join("dynamic.csv");
    write(&p, &csv).map_err(io)?;
    written.push(p);
    let p = dir.join("animation.svg");
    write(&p, &crate::output::animate::animated_svg(sim, target, anim)).map_err(io)?;
    written.push(p);
    let p = dir.join("frames.svg");
    write(
        &p,
        &crate::output::animate::frame_sheet(sim, target, 4, 3, 360),
    )
    .map_err(io)?;
    written.push(p);
    // Plots.
    let deg = |k: usize| 360.0 * k as f64 / n as f64;
    let pts = |v: &[f64]| {
        v.iter()
            .enumerate()
            .map(|(k, y)| (deg(k), *y))
            .collect::<Vec<_>>()
    };
    (|| -> Result<(), OutputError> {
        if !dev.is_empty() {
            both(
                &dir.join("deviation"),
                &ChartLabels {
                    title: "Distance of the traced path from the target".into(),
                    x: "carrier turn (deg)".into(),
                    y: "deviation (mm)".into(),
                    equal_aspect: false,
                },
                &[Series::line("arm 1", pts(&dev))],
                (900, 450),
                &mut written,
            )?;
        }
        // Ratios from the kinematics (central differences of the continuous pose angles):
        // i21 = dθ2/dφ − 1, i3H = dθ3/dφ, i31 = 1 − i3H (φ in the direction of motion).
        let hf = 1e-4;
        let rate = |k: usize, f: &dyn Fn(&crate::geometry::assembly::Pose) -> f64| {
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
            &mut written,
        )?;
        let asm = &sim.assembly;
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
            &mut written,
        )?;
        let along = |c: &PitchCurve, f: &dyn Fn(crate::geometry::pitch::PolarGeometry) -> f64| {
            (0..=720)
                .map(|k| {
                    let t = TAU * k as f64 / 720.0;
                    (t.to_degrees(), f(c.geometry(t)))
                })
                .collect::<Vec<_>>()
        };
        let rho = |g: crate::geometry::pitch::PolarGeometry| g.radius_of_curvature_mm();
        let mu = |g: crate::geometry::pitch::PolarGeometry| g.pressure_deviation_rad().to_degrees();
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
            &mut written,
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
            &mut written,
        )?;
        let xy = |v: &[[f64; 2]]| v.iter().map(|p| (p[0], p[1])).collect::<Vec<_>>();
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
            &mut written,
        )?;
        // The agronomic features drawn on the static path: taking and planting instants with the
        // needle, the soil level at the planting depth, the hole width on the dynamic stroke.
        let f = &features;
        let at = |deg: f64| sim.pose(f64::from(sim.assembly.direction) * deg.to_radians()).arm1;
        let (take, plant) = (at(f.take_carrier_deg), at(f.plant_carrier_deg));
        let level = f.bbox_mm[2] + feat_opts.planting_depth_mm;
        both(
            &dir.join("features"),
            &ChartLabels {
                title: format!(
                    "H = {:.1} mm, hole {:.1} mm at {:.0} mm depth, needle {:.1}° taking / {:.1}° planting",
                    f.height_mm, f.hole_width_mm, feat_opts.planting_depth_mm, f.needle_angle_take_deg, f.needle_angle_plant_deg
                ),
                x: "x (mm)".into(),
                y: "y (mm)".into(),
                equal_aspect: true,
            },
            &[
                Series::line("static path", xy(&arm1)),
                Series::line("needle at taking", xy(&[take.planet_center_mm, take.tip_mm])),
                Series::line("needle at planting", xy(&[plant.planet_center_mm, plant.tip_mm])),
                Series::line("soil level (planting depth)", vec![(f.bbox_mm[0], level), (f.bbox_mm[1], level)]),
                Series::markers("taking / planting points", xy(&[take.tip_mm, plant.tip_mm])),
            ],
            (1000, 800),
            &mut written,
        )?;
        Ok(())
    })()
    .map_err(io)?;
    let stats = (!dev.is_empty()).then(|| {
        (
            dev.iter().fold(0.0, |a: f64, b| a.max(*b)),
            dev.iter().sum::<f64>() / dev.len() as f64,
        )
    });
    Ok(SimulationReport {
        features,
        deviation_max_mm: stats.map(|s| s.0),
        deviation_mean_mm: stats.map(|s| s.1),
        arm2_vs_arm1_mm: arm2_vs_arm1,
        rpm: feat_opts.rpm,
        forward_speed_mm_s: feat_opts.forward_mm_s,
        files: written.iter().map(|p| p.display().to_string()).collect(),
    })
}

/// CAD files of a toothed train (`ncgear design --module M`), under `dir/teeth/`:
/// - `train.svg`, `train.dxf`: the mechanism sheet, the whole train at φH = 0 (world frame);
/// - `<gear>.svg`, `<gear>.dxf`: each gear in its body frame (rotation centre at the origin);
/// - `<gear>_points/`: `points.csv` (`contour,index,x_mm,y_mm`) and a header-less `x y 0` TXT per
///   contour (`<gear>_outline.txt`, `<gear>_pitch.txt`), body frame, unsimplified.
///
/// DXF contours are simplified to `train.report.options.chord_tol_mm`; SVG and DXF in mm.
/// The written paths are also stored in `train.report.files`.
pub fn write_teeth(
    train: &mut crate::design::train::ToothedTrain,
    dir: &Path,
    dxf_version: crate::export::dxf::DxfVersion,
) -> Result<Vec<PathBuf>, OutputError> {
    use crate::export::{dxf::write_dxf, points::write_points, svg::write_svg};
    let dir = dir.join("teeth");
    std::fs::create_dir_all(&dir).map_err(|e| OutputError::Io {
        path: dir.display().to_string(),
        message: e.to_string(),
    })?;
    let tol = train.report.options.toothing.chord_tol_mm;
    let margin = 2.0 * train.report.module_mm;
    let mut written = Vec::new();
    let mut sheets = vec![("train".to_string(), train.sheet(0.0))];
    for g in crate::design::train::Gear::ALL {
        sheets.push((g.name().to_string(), train.gear_sheet(g)));
    }
    for (k, (name, sheet)) in sheets.iter().enumerate() {
        let svg = dir.join(format!("{name}.svg"));
        write_svg(sheet, &svg, margin)?;
        let dxf = dir.join(format!("{name}.dxf"));
        write_dxf(sheet, &dxf, dxf_version, tol)?;
        written.push(svg);
        written.push(dxf);
        if k > 0 {
            written.extend(write_points(
                sheet,
                &dir.join(format!("{name}_points")),
                "points",
            )?);
        }
    }
    train.report.files = written.iter().map(|p| p.display().to_string()).collect();
    Ok(written)
}
