//! The mechanism preview at one carrier angle: the three pitch curves on the carrier, the needle,
//! the target and the traced path, as an SVG drawing (`svg` crate, 1 user unit = 1 mm, y up in the
//! world flipped to SVG's y down) or as a chart (PNG or SVG, mm).

use super::error::OutputError;
use super::fixed::Fixed;
use super::plot::{ChartLabels, Series, line_chart};
#[cfg(doc)]
use crate::geometry::assembly::Assembly;
use crate::geometry::assembly::Rebuilt;
use crate::geometry::pitch::PitchCurve;
use crate::math::Point;
use std::f64::consts::TAU;
use std::path::Path;
use svg::Document;
use svg::node::element::{Circle, Group, Path as SvgPath, Rectangle, Text};

/// Polyline points of a pitch curve placed at `center` with orientation `angle` (rad), mm.
fn placed(curve: &PitchCurve, center: Point, angle: f64, n: usize) -> Vec<Point> {
    (0..n)
        .map(|k| {
            let th = TAU * k as f64 / n as f64;
            let r = curve.radius_mm(th);
            Point::new(
                center.x + r * (th + angle).cos(),
                center.y + r * (th + angle).sin(),
            )
        })
        .collect()
}

/// SVG path data `M x,y L x,y … [Z]` of a polyline, y negated (SVG y down), 4 decimals, mm.
fn path_d(pts: &[Point], close: bool) -> String {
    let mut d = String::with_capacity(24 * pts.len() + 1);
    for (k, p) in pts.iter().enumerate() {
        d.push(if k == 0 { 'M' } else { 'L' });
        Fixed(p.x, 4).push_to(&mut d);
        d.push(',');
        Fixed(-p.y, 4).push_to(&mut d);
        d.push(' ');
    }
    if close {
        d.push('Z');
    }
    d
}

/// SVG preview (mm) of the mechanism rebuilt from its tables ([`Assembly::rebuild`]) at carrier
/// angle `phi_h` (rad): the three pitch curves on the carrier, the needle, the target and the
/// traced trajectory. One group per layer; coordinates with 3 decimals (path data 4), mm.
#[must_use]
pub fn mechanism_svg(rebuilt: &Rebuilt, target: &[Point], traced: &[Point], phi_h: f64) -> String {
    let (asm, pose) = (rebuilt.assembly(), rebuilt.pose(phi_h));
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
    let all: Vec<Point> = sun
        .iter()
        .chain(&mid)
        .chain(&planet)
        .chain(target)
        .chain(traced)
        .copied()
        .collect();
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for p in &all {
        x0 = x0.min(p.x);
        x1 = x1.max(p.x);
        y0 = y0.min(p.y);
        y1 = y1.max(p.y);
    }
    let m = 10.0;
    let (w, h) = (x1 - x0 + 2.0 * m, y1 - y0 + 2.0 * m);
    let (left, top) = (format!("{:.3}", x0 - m), format!("{:.3}", -y1 - m));
    let mut doc = Document::new()
        .set("width", format!("{w:.3}mm"))
        .set("height", format!("{h:.3}mm"))
        .set("viewBox", format!("{left} {top} {w:.3} {h:.3}"))
        .add(
            Rectangle::new()
                .set("x", left.as_str())
                .set("y", top.as_str())
                .set("width", format!("{w:.3}"))
                .set("height", format!("{h:.3}"))
                .set("fill", "#ffffff"),
        );
    let layer = |id: &str, stroke: &str, width: f64, d: String| {
        Group::new().set("id", id).add(
            SvgPath::new()
                .set("d", d)
                .set("fill", "none")
                .set("stroke", stroke)
                .set("stroke-width", width),
        )
    };
    let a = pose.planet_center_mm;
    for g in [
        layer("target", "#999999", 1.2, path_d(target, true)),
        layer("traced", "#d62728", 0.5, path_d(traced, true)),
        layer("sun", "#1f77b4", 0.5, path_d(&sun, true)),
        layer("intermediate", "#2ca02c", 0.5, path_d(&mid, true)),
        layer("planet", "#9467bd", 0.5, path_d(&planet, true)),
        layer("carrier", "#444444", 0.8, path_d(&[o, a], false)),
        layer("needle", "#ff7f0e", 1.0, path_d(&[a, pose.tip_mm], false)),
    ] {
        doc = doc.add(g);
    }
    let mut centres = Group::new().set("id", "centres").set("fill", "#000000");
    for c in [o, pose.intermediate_center_mm, a] {
        centres = centres.add(
            Circle::new()
                .set("cx", format!("{:.3}", c.x))
                .set("cy", format!("{:.3}", -c.y))
                .set("r", "1.2"),
        );
    }
    doc = doc.add(centres).add(
        Group::new()
            .set("id", "text")
            .set("font-family", "sans-serif")
            .set("font-size", "5")
            .set("fill", "#222222")
            .add(
                Text::new(format!(
                    "ncgear design at carrier angle {:.1}° — grey: target, red: traced, blue: sun, green: intermediate, violet: planet",
                    phi_h.to_degrees()
                ))
                .set("x", format!("{:.3}", x0 - m + 2.0))
                .set("y", format!("{:.3}", -y1 - m + 6.0)),
            ),
    );
    format!("{doc}\n")
}

/// The mechanism preview of [`mechanism_svg`] as a chart (PNG or SVG by extension, equal axes,
/// mm).
pub fn mechanism_chart(
    rebuilt: &Rebuilt,
    target: &[Point],
    traced: &[Point],
    phi_h: f64,
    path: &Path,
) -> Result<(), OutputError> {
    let (asm, pose) = (rebuilt.assembly(), rebuilt.pose(phi_h));
    let closed = |mut v: Vec<Point>| {
        if let Some(f) = v.first().copied() {
            v.push(f);
        }
        v.into_iter().map(|p| (p.x, p.y)).collect::<Vec<_>>()
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
                (asm.center_mm.x, asm.center_mm.y),
                (pose.planet_center_mm.x, pose.planet_center_mm.y),
                (pose.tip_mm.x, pose.tip_mm.y),
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
