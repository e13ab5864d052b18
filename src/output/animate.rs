//! Animated SVG of the whole mechanism over one carrier turn (SMIL `animateTransform`: plays in a
//! browser with no script), and a static multi-frame sheet. 1 SVG user unit = 1 mm; the world
//! frame is drawn with y up (one `scale(1,−1)` group), so rotations are CCW-positive as in the
//! design file.

use crate::geometry::pitch::PitchCurve;
use crate::simulate::Simulation;
use std::f64::consts::TAU;
use std::fmt::Write as _;

/// Options of the animation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AnimationOptions {
    /// Key frames per turn (linear interpolation in between).
    pub frames: usize,
    /// Duration of one carrier turn, s.
    pub seconds: f64,
    /// Points per pitch-curve outline (toothed outlines are drawn as generated).
    pub outline_points: usize,
}

impl Default for AnimationOptions {
    fn default() -> Self {
        Self {
            frames: 360,
            seconds: 6.0,
            outline_points: 720,
        }
    }
}

fn body_path(curve: &PitchCurve, n: usize) -> String {
    let mut d = String::new();
    for k in 0..n {
        let th = TAU * k as f64 / n as f64;
        let r = curve.radius_mm(th);
        let _ = write!(
            d,
            "{}{:.3},{:.3} ",
            if k == 0 { "M" } else { "L" },
            r * th.cos(),
            r * th.sin()
        );
    }
    d.push('Z');
    d
}

fn polyline(pts: &[[f64; 2]], close: bool) -> String {
    let mut d = String::new();
    for (k, p) in pts.iter().enumerate() {
        let _ = write!(
            d,
            "{}{:.3},{:.3} ",
            if k == 0 { "M" } else { "L" },
            p[0],
            p[1]
        );
    }
    if close {
        d.push('Z');
    }
    d
}

/// Bounding box `[xmin, ymin, xmax, ymax]` of everything that moves over a turn, with margin.
fn extent(sim: &Simulation, target: &[[f64; 2]], n: usize) -> [f64; 4] {
    let mut b = [f64::MAX, f64::MAX, f64::MIN, f64::MIN];
    let mut add = |p: [f64; 2], r: f64| {
        b[0] = b[0].min(p[0] - r);
        b[1] = b[1].min(p[1] - r);
        b[2] = b[2].max(p[0] + r);
        b[3] = b[3].max(p[1] + r);
    };
    let a = sim.assembly.a_mm;
    for t in sim.turn(n) {
        for arm in [t.arm1, t.arm2] {
            add(arm.tip_mm, 2.0);
            add(arm.planet_center_mm, a);
            add(arm.intermediate_center_mm, a);
        }
    }
    for p in target {
        add(*p, 2.0);
    }
    add(sim.assembly.center_mm, a);
    let m = 5.0;
    [b[0] - m, b[1] - m, b[2] + m, b[3] + m]
}

fn header(s: &mut String, b: [f64; 4], scale: f64) {
    let (w, h) = (b[2] - b[0], b[3] - b[1]);
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink" width="{:.2}mm" height="{:.2}mm" viewBox="{:.3} {:.3} {w:.3} {h:.3}">"#,
        w * scale,
        h * scale,
        b[0],
        -b[3]
    );
    let _ = writeln!(
        s,
        r##"<rect x="{:.3}" y="{:.3}" width="{w:.3}" height="{h:.3}" fill="#ffffff"/>"##,
        b[0], -b[3]
    );
}

fn defs(s: &mut String, sim: &Simulation, n: usize) {
    let asm = &sim.assembly;
    let shape = |k: usize, c: &PitchCurve| match &sim.outlines {
        Some(o) => polyline(&o[k], true),
        None => body_path(c, n),
    };
    let _ = writeln!(s, "<defs>");
    let _ = writeln!(
        s,
        r##"<path id="sun" d="{}" fill="#dbe9f6" stroke="#1f77b4" stroke-width="0.5"/>"##,
        shape(0, &asm.sun)
    );
    let _ = writeln!(
        s,
        r##"<path id="intermediate" d="{}" fill="#dff2df" stroke="#2ca02c" stroke-width="0.5"/>"##,
        shape(1, &asm.intermediate)
    );
    // The planet carries the needle (A → B at the needle angle γ) and marks the tip.
    let g = asm.needle_angle_rad;
    let (bx, by) = (asm.l3_mm * g.cos(), asm.l3_mm * g.sin());
    let _ = writeln!(
        s,
        r##"<g id="planet"><path d="{}" fill="#ece2f4" stroke="#9467bd" stroke-width="0.5"/><path d="M0,0 L{bx:.3},{by:.3}" stroke="#ff7f0e" stroke-width="1.5"/><circle cx="{bx:.3}" cy="{by:.3}" r="1.8" fill="#d62728"/></g>"##,
        shape(2, &asm.planet)
    );
    let _ = writeln!(s, "</defs>");
}

fn static_layers(s: &mut String, target: &[[f64; 2]], traced: &[[f64; 2]]) {
    if !target.is_empty() {
        let _ = writeln!(
            s,
            r##"<path id="target" d="{}" fill="none" stroke="#888888" stroke-width="1.2"/>"##,
            polyline(target, true)
        );
    }
    let _ = writeln!(
        s,
        r##"<path id="traced" d="{}" fill="none" stroke="#d62728" stroke-width="0.4" stroke-dasharray="2 1"/>"##,
        polyline(traced, true)
    );
}

/// The animated SVG: carrier, sun, both intermediates and planets, needles, target and traced
/// paths, one carrier turn per `seconds`, looping.
#[must_use]
pub fn animated_svg(sim: &Simulation, target: &[[f64; 2]], opts: &AnimationOptions) -> String {
    let n = opts.frames.max(8);
    let turn: Vec<_> = (0..=n)
        .map(|k| sim.pose(sim.angle_at(k as f64 / n as f64)))
        .collect();
    let traced: Vec<[f64; 2]> = turn[..n].iter().map(|t| t.arm1.tip_mm).collect();
    let b = extent(sim, target, 90);
    let mut s = String::new();
    header(&mut s, b, 1.0);
    let _ = writeln!(s, r#"<g transform="scale(1,-1)">"#);
    defs(&mut s, sim, opts.outline_points);
    static_layers(&mut s, target, &traced);
    let o = sim.assembly.center_mm;
    let dur = format!("{:.3}s", opts.seconds);
    let anim = |kind: &str, values: String| {
        format!(
            r#"<animateTransform attributeName="transform" type="{kind}" values="{values}" dur="{dur}" repeatCount="indefinite" calcMode="linear"/>"#
        )
    };
    // Carrier: a bar through O along the two arms.
    let a2 = 2.0 * sim.assembly.a_mm;
    let phis: Vec<String> = turn
        .iter()
        .map(|t| {
            format!(
                "{:.4} {:.3} {:.3}",
                t.arm1.phi_h_rad.to_degrees(),
                o[0],
                o[1]
            )
        })
        .collect();
    let _ = writeln!(
        s,
        r##"<g id="carrier">{}<path d="M{:.3},{:.3} L{:.3},{:.3}" stroke="#444444" stroke-width="3" stroke-linecap="round" opacity="0.6"/></g>"##,
        anim("rotate", phis.join(";")),
        o[0] - a2,
        o[1],
        o[0] + a2,
        o[1]
    );
    let _ = writeln!(
        s,
        r##"<use xlink:href="#sun" href="#sun" transform="translate({:.3},{:.3})"/>"##,
        o[0], o[1]
    );
    for arm in 0..2 {
        let pose = |t: &crate::simulate::TwoArms| if arm == 0 { t.arm1 } else { t.arm2 };
        for (id, centre, angle) in [
            (
                "intermediate",
                turn.iter()
                    .map(|t| pose(t).intermediate_center_mm)
                    .collect::<Vec<_>>(),
                turn.iter()
                    .map(|t| pose(t).intermediate_angle_rad)
                    .collect::<Vec<_>>(),
            ),
            (
                "planet",
                turn.iter().map(|t| pose(t).planet_center_mm).collect(),
                turn.iter().map(|t| pose(t).planet_angle_rad).collect(),
            ),
        ] {
            let tr: Vec<String> = centre
                .iter()
                .map(|c| format!("{:.3},{:.3}", c[0], c[1]))
                .collect();
            let rot: Vec<String> = angle
                .iter()
                .map(|a| format!("{:.4}", a.to_degrees()))
                .collect();
            let _ = writeln!(
                s,
                r##"<g id="{id}{}">{}<g>{}<use xlink:href="#{id}" href="#{id}"/></g></g>"##,
                arm + 1,
                anim("translate", tr.join(";")),
                anim("rotate", rot.join(";"))
            );
        }
    }
    let _ = writeln!(
        s,
        r##"<circle cx="{:.3}" cy="{:.3}" r="1.5" fill="#000000"/>"##,
        o[0], o[1]
    );
    let _ = writeln!(s, "</g>");
    s.push_str("</svg>\n");
    s
}

/// A static sheet of `cols × rows` frames at equal carrier-angle steps, each with both arms.
#[must_use]
pub fn frame_sheet(
    sim: &Simulation,
    target: &[[f64; 2]],
    cols: usize,
    rows: usize,
    outline_points: usize,
) -> String {
    let frames = (cols * rows).max(1);
    let traced: Vec<[f64; 2]> = sim.turn(720).iter().map(|t| t.arm1.tip_mm).collect();
    let b = extent(sim, target, 90);
    let (w, h) = (b[2] - b[0], b[3] - b[1]);
    let sheet = [b[0], b[1], b[0] + w * cols as f64, b[1] + h * rows as f64];
    let mut s = String::new();
    header(&mut s, sheet, 0.5);
    let _ = writeln!(s, r#"<g transform="scale(1,-1)">"#);
    defs(&mut s, sim, outline_points);
    for k in 0..frames {
        let (c, r) = (k % cols, k / cols);
        let dx = c as f64 * w;
        let dy = (rows - 1 - r) as f64 * h;
        let f = k as f64 / frames as f64;
        let t = sim.pose(sim.angle_at(f));
        let _ = writeln!(s, r#"<g transform="translate({dx:.3},{dy:.3})">"#);
        static_layers(&mut s, target, &traced);
        let o = sim.assembly.center_mm;
        let _ = writeln!(
            s,
            r##"<use xlink:href="#sun" href="#sun" transform="translate({:.3},{:.3})"/>"##,
            o[0], o[1]
        );
        for p in [t.arm1, t.arm2] {
            let _ = writeln!(
                s,
                r##"<path d="M{:.3},{:.3} L{:.3},{:.3}" stroke="#444444" stroke-width="3" opacity="0.6"/>"##,
                o[0], o[1], p.planet_center_mm[0], p.planet_center_mm[1]
            );
            for (id, c, a) in [
                (
                    "intermediate",
                    p.intermediate_center_mm,
                    p.intermediate_angle_rad,
                ),
                ("planet", p.planet_center_mm, p.planet_angle_rad),
            ] {
                let _ = writeln!(
                    s,
                    r##"<use xlink:href="#{id}" href="#{id}" transform="translate({:.3},{:.3}) rotate({:.4})"/>"##,
                    c[0],
                    c[1],
                    a.to_degrees()
                );
            }
        }
        let _ = writeln!(
            s,
            r##"<g transform="scale(1,-1)"><text x="{:.3}" y="{:.3}" font-family="sans-serif" font-size="8" fill="#222222">φH = {:.0}°</text></g>"##,
            b[0] + 4.0,
            -(b[3] - 10.0),
            sim.angle_at(f).to_degrees()
        );
        let _ = writeln!(s, "</g>");
    }
    let _ = writeln!(s, "</g>");
    s.push_str("</svg>\n");
    s
}
