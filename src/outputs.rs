//! Files written by `ncgear design`: `design.json`, pitch tables, the mechanism preview and the
//! ratio plot. All lengths in mm, angles in degrees; SVG user unit = 1 mm.

use crate::assembly::Assembly;
use crate::design::Design;
use crate::pitch::PitchCurve;
use crate::plot::{ChartLabels, Series, line_chart};
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
    Plot(#[from] crate::plot::PlotError),
}

fn write(path: &Path, text: &str) -> Result<(), OutputError> {
    std::fs::write(path, text).map_err(|e| OutputError::Io { path: path.display().to_string(), message: e.to_string() })
}

/// A pitch table as CSV: header `theta_deg,r_mm,x_mm,y_mm`, body frame, `n` uniform samples.
#[must_use]
pub fn pitch_csv(curve: &PitchCurve, n: usize) -> String {
    let mut s = String::from("theta_deg,r_mm,x_mm,y_mm\n");
    for k in 0..n {
        let th = TAU * k as f64 / n as f64;
        let r = curve.radius_mm(th);
        let _ = writeln!(s, "{:.6},{:.9},{:.9},{:.9}", th.to_degrees(), r, r * th.cos(), r * th.sin());
    }
    s
}

/// Writes every design output into `dir` (created if needed); returns the paths written.
pub fn write_design(design: &Design, dir: &Path) -> Result<Vec<PathBuf>, OutputError> {
    std::fs::create_dir_all(dir).map_err(|e| OutputError::Io { path: dir.display().to_string(), message: e.to_string() })?;
    let mut written = Vec::new();
    let json = serde_json::to_string_pretty(&design.report).map_err(|e| OutputError::Io { path: "design.json".into(), message: e.to_string() })?;
    let p = dir.join("design.json");
    write(&p, &json)?;
    written.push(p);
    let n = design.report.gears.sun.pitch.len();
    let asm = &design.assembly;
    for (name, curve) in [("sun", &asm.sun), ("intermediate", &asm.intermediate), ("planet", &asm.planet)] {
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
        .map(|q| [asm.center_mm[0] + q[0], asm.center_mm[1] + f64::from(asm.direction) * q[1]])
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
            [center[0] + r * (th + angle).cos(), center[1] + r * (th + angle).sin()]
        })
        .collect()
}

fn path_d(pts: &[[f64; 2]], close: bool) -> String {
    let mut d = String::new();
    for (k, p) in pts.iter().enumerate() {
        let _ = write!(d, "{}{:.4},{:.4} ", if k == 0 { "M" } else { "L" }, p[0], -p[1]);
    }
    if close {
        d.push('Z');
    }
    d
}

/// SVG preview (mm) of the mechanism at carrier angle `phi_h` (rad): the three pitch curves on
/// the carrier, the needle, the target and the traced trajectory. One group per layer.
#[must_use]
pub fn mechanism_svg(asm: &Assembly, target: &[[f64; 2]], traced: &[[f64; 2]], phi_h: f64) -> String {
    let pose = asm.rebuild().pose(phi_h);
    let o = asm.center_mm;
    let n = 720;
    let sun = placed(&asm.sun, o, 0.0, n);
    let mid = placed(&asm.intermediate, pose.intermediate_center_mm, pose.intermediate_angle_rad, n);
    let planet = placed(&asm.planet, pose.planet_center_mm, pose.planet_angle_rad, n);
    let all: Vec<[f64; 2]> = sun.iter().chain(&mid).chain(&planet).chain(target).chain(traced).copied().collect();
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
    let _ = writeln!(s, r##"<rect x="{:.3}" y="{:.3}" width="{w:.3}" height="{h:.3}" fill="#ffffff"/>"##, x0 - m, -y1 - m);
    let layer = |s: &mut String, id: &str, stroke: &str, width: f64, d: String| {
        let _ = writeln!(s, r#"<g id="{id}"><path d="{d}" fill="none" stroke="{stroke}" stroke-width="{width}"/></g>"#);
    };
    layer(&mut s, "target", "#999999", 1.2, path_d(target, true));
    layer(&mut s, "traced", "#d62728", 0.5, path_d(traced, true));
    layer(&mut s, "sun", "#1f77b4", 0.5, path_d(&sun, true));
    layer(&mut s, "intermediate", "#2ca02c", 0.5, path_d(&mid, true));
    layer(&mut s, "planet", "#9467bd", 0.5, path_d(&planet, true));
    let a = pose.planet_center_mm;
    layer(&mut s, "carrier", "#444444", 0.8, path_d(&[o, a], false));
    layer(&mut s, "needle", "#ff7f0e", 1.0, path_d(&[a, pose.tip_mm], false));
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
pub fn mechanism_chart(asm: &Assembly, target: &[[f64; 2]], traced: &[[f64; 2]], phi_h: f64, path: &Path) -> Result<(), OutputError> {
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
        Series::line("intermediate", closed(placed(&asm.intermediate, pose.intermediate_center_mm, pose.intermediate_angle_rad, n))),
        Series::line("planet", closed(placed(&asm.planet, pose.planet_center_mm, pose.planet_angle_rad, n))),
        Series::line("carrier + needle", vec![
            (asm.center_mm[0], asm.center_mm[1]),
            (pose.planet_center_mm[0], pose.planet_center_mm[1]),
            (pose.tip_mm[0], pose.tip_mm[1]),
        ]),
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
    let i21: Vec<(f64, f64)> = (0..=n).map(|k| {
        let t = TAU * k as f64 / n as f64;
        (t.to_degrees(), m.ratio.value(t))
    }).collect();
    let i31: Vec<(f64, f64)> = (0..=n).map(|k| {
        let t = TAU * k as f64 / n as f64;
        (t.to_degrees(), m.ratio.value(t) / m.ratio.value(m.half_turn_map(t)))
    }).collect();
    let target: Vec<(f64, f64)> = {
        let law = &design.inversion.law;
        let tau = m.sun_phase_rad - design.inversion.phi_h0_rad;
        (0..=n).map(|k| {
            let t = TAU * k as f64 / n as f64;
            (t.to_degrees(), law.i31(t + tau))
        }).collect()
    };
    line_chart(
        path,
        &ChartLabels {
            title: "Gear ratios over one turn".into(),
            x: "sun angle from the design reference ray (deg)".into(),
            y: "ratio (-)".into(),
            equal_aspect: false,
        },
        &[Series::line("i21 (sun → intermediate)", i21), Series::line("i31 (design)", i31), Series::line("i31 (target)", target)],
        (900, 500),
    )?;
    Ok(())
}
