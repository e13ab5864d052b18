//! Animated SVG of the whole mechanism over one carrier turn (SMIL `animateTransform`: plays in a
//! browser with no script), and a static multi-frame sheet. 1 SVG user unit = 1 mm; the world
//! frame is drawn with y up (one `scale(1,−1)` group), so rotations are CCW-positive as in the
//! design file. Documents are built with the `svg` crate; numbers are formatted here (mm with 3
//! decimals, degrees with 4) to keep the precision.

use crate::geometry::pitch::PitchCurve;
use crate::math::Point;
use crate::simulate::{Simulation, TwoArms};
use std::f64::consts::TAU;
use std::fmt::Write as _;
use svg::Document;
use svg::node::element::{
    AnimateTransform, Circle, Definitions, Group, Path as SvgPath, Rectangle, Text, Use,
};

/// Options of the animation; [`Default`] fills the defaults named on each field.
/// (De)serialisable (a missing field takes its default, an unknown one is an error) and built
/// with `with_*`.
#[derive(
    Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize, schemars::JsonSchema,
)]
#[serde(default, deny_unknown_fields)]
#[non_exhaustive]
pub struct AnimationOptions {
    /// Key frames per turn (linear interpolation in between). Default 360.
    pub frames: usize,
    /// Duration of one carrier turn, s. Default 6.
    pub seconds: f64,
    /// Points per pitch-curve outline (toothed outlines are drawn as generated). Default 720.
    pub outline_points: usize,
}

crate::builder::with_fields!(AnimationOptions {
    with_frames => frames: usize,
    with_seconds => seconds: f64,
    with_outline_points => outline_points: usize,
});

impl Default for AnimationOptions {
    fn default() -> Self {
        Self {
            frames: 360,
            seconds: 6.0,
            outline_points: 720,
        }
    }
}

/// SVG path data of a pitch curve in its body frame, `n` points uniform in θ, 3 decimals, mm.
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

/// SVG path data `M x,y L x,y … [Z]` of a polyline (y up, world or body frame), 3 decimals, mm.
fn polyline(pts: &[Point], close: bool) -> String {
    let mut d = String::new();
    for (k, p) in pts.iter().enumerate() {
        let _ = write!(
            d,
            "{}{:.3},{:.3} ",
            if k == 0 { "M" } else { "L" },
            p.x,
            p.y
        );
    }
    if close {
        d.push('Z');
    }
    d
}

/// Bounding box `[xmin, ymin, xmax, ymax]` of everything that moves over a turn, with margin.
fn extent(sim: &Simulation, target: &[Point], n: usize) -> [f64; 4] {
    let mut b = [f64::MAX, f64::MAX, f64::MIN, f64::MIN];
    let mut add = |p: Point, r: f64| {
        b[0] = b[0].min(p.x - r);
        b[1] = b[1].min(p.y - r);
        b[2] = b[2].max(p.x + r);
        b[3] = b[3].max(p.y + r);
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

/// The document: `width`/`height` = extent × `scale` (mm), a viewBox over `b` with y flipped
/// (`[xmin, ymin, xmax, ymax]`, mm, 3 decimals) and a white background.
fn document(b: [f64; 4], scale: f64) -> Document {
    let (w, h) = (b[2] - b[0], b[3] - b[1]);
    let (x, y) = (format!("{:.3}", b[0]), format!("{:.3}", -b[3]));
    Document::new()
        .set("xmlns:xlink", "http://www.w3.org/1999/xlink")
        .set("width", format!("{:.2}mm", w * scale))
        .set("height", format!("{:.2}mm", h * scale))
        .set("viewBox", format!("{x} {y} {w:.3} {h:.3}"))
        .add(
            Rectangle::new()
                .set("x", x)
                .set("y", y)
                .set("width", format!("{w:.3}"))
                .set("height", format!("{h:.3}"))
                .set("fill", "#ffffff"),
        )
}

/// A `<use>` of the definition `id` (both `xlink:href` and `href`, for old and new viewers).
fn use_of(id: &str) -> Use {
    Use::new()
        .set("xlink:href", format!("#{id}"))
        .set("href", format!("#{id}"))
}

/// The gear shapes (body frames, mm): `sun`, `intermediate` and `planet` (with the needle A → B
/// at the needle angle γ and the tip marked).
fn defs(sim: &Simulation, n: usize) -> Definitions {
    let asm = &sim.assembly;
    let shape = |k: usize, c: &PitchCurve| match &sim.outlines {
        Some(o) => polyline(&o[k], true),
        None => body_path(c, n),
    };
    let g = asm.needle_angle_rad;
    let (bx, by) = (
        format!("{:.3}", asm.l3_mm * g.cos()),
        format!("{:.3}", asm.l3_mm * g.sin()),
    );
    Definitions::new()
        .add(
            SvgPath::new()
                .set("id", "sun")
                .set("d", shape(0, &asm.sun))
                .set("fill", "#dbe9f6")
                .set("stroke", "#1f77b4")
                .set("stroke-width", "0.5"),
        )
        .add(
            SvgPath::new()
                .set("id", "intermediate")
                .set("d", shape(1, &asm.intermediate))
                .set("fill", "#dff2df")
                .set("stroke", "#2ca02c")
                .set("stroke-width", "0.5"),
        )
        .add(
            Group::new()
                .set("id", "planet")
                .add(
                    SvgPath::new()
                        .set("d", shape(2, &asm.planet))
                        .set("fill", "#ece2f4")
                        .set("stroke", "#9467bd")
                        .set("stroke-width", "0.5"),
                )
                .add(
                    SvgPath::new()
                        .set("d", format!("M0,0 L{bx},{by}"))
                        .set("stroke", "#ff7f0e")
                        .set("stroke-width", "1.5"),
                )
                .add(
                    Circle::new()
                        .set("cx", bx)
                        .set("cy", by)
                        .set("r", "1.8")
                        .set("fill", "#d62728"),
                ),
        )
}

/// The target (when given) and the traced path, world frame, mm.
fn static_layers(target: &[Point], traced: &[Point]) -> Vec<SvgPath> {
    let mut layers = Vec::new();
    if !target.is_empty() {
        layers.push(
            SvgPath::new()
                .set("id", "target")
                .set("d", polyline(target, true))
                .set("fill", "none")
                .set("stroke", "#888888")
                .set("stroke-width", "1.2"),
        );
    }
    layers.push(
        SvgPath::new()
            .set("id", "traced")
            .set("d", polyline(traced, true))
            .set("fill", "none")
            .set("stroke", "#d62728")
            .set("stroke-width", "0.4")
            .set("stroke-dasharray", "2 1"),
    );
    layers
}

/// The animated SVG: carrier, sun, both intermediates and planets, needles, target and traced
/// paths, one carrier turn per `seconds`, looping.
#[must_use]
pub fn animated_svg(sim: &Simulation, target: &[Point], opts: &AnimationOptions) -> String {
    let n = opts.frames.max(8);
    let turn: Vec<_> = (0..=n)
        .map(|k| sim.pose(sim.angle_at(k as f64 / n as f64)))
        .collect();
    let traced: Vec<Point> = turn[..n].iter().map(|t| t.arm1.tip_mm).collect();
    let b = extent(sim, target, 90);
    let mut world = Group::new()
        .set("transform", "scale(1,-1)")
        .add(defs(sim, opts.outline_points));
    for layer in static_layers(target, &traced) {
        world = world.add(layer);
    }
    let o = sim.assembly.center_mm;
    let anim = Looping {
        dur: format!("{:.3}s", opts.seconds),
    };
    world = world
        .add(carrier_group(&anim, &turn, o, sim.assembly.l1_mm()))
        .add(use_of("sun").set("transform", format!("translate({:.3},{:.3})", o.x, o.y)));
    for arm in 0..2 {
        for group in arm_groups(&anim, &turn, arm) {
            world = world.add(group);
        }
    }
    world = world.add(
        Circle::new()
            .set("cx", format!("{:.3}", o.x))
            .set("cy", format!("{:.3}", o.y))
            .set("r", "1.5")
            .set("fill", "#000000"),
    );
    format!("{}\n", document(b, 1.0).add(world))
}

/// The key-frame animation of one carrier turn, looping.
struct Looping {
    /// Duration of one turn, e.g. `"6.000s"`.
    dur: String,
}

impl Looping {
    /// Linear interpolation of the transform `kind` through `values` (key frames,
    /// `;`-separated) over one turn.
    fn transform(&self, kind: &str, values: String) -> AnimateTransform {
        AnimateTransform::new()
            .set("attributeName", "transform")
            .set("type", kind)
            .set("values", values)
            .set("dur", self.dur.as_str())
            .set("repeatCount", "indefinite")
            .set("calcMode", "linear")
    }
}

/// The carrier: a bar of half-length `a2` (mm) through O along the two arms, turning about O
/// (degrees) with the key frames `turn`.
fn carrier_group(anim: &Looping, turn: &[TwoArms], o: Point, a2: f64) -> Group {
    let phis: Vec<String> = turn
        .iter()
        .map(|t| format!("{:.4} {:.3} {:.3}", t.arm1.phi_h_rad.to_degrees(), o.x, o.y))
        .collect();
    Group::new()
        .set("id", "carrier")
        .add(anim.transform("rotate", phis.join(";")))
        .add(
            SvgPath::new()
                .set(
                    "d",
                    format!("M{:.3},{:.3} L{:.3},{:.3}", o.x - a2, o.y, o.x + a2, o.y),
                )
                .set("stroke", "#444444")
                .set("stroke-width", "3")
                .set("stroke-linecap", "round")
                .set("opacity", "0.6"),
        )
}

/// The intermediate and the planet of arm `arm` (0 or 1) over the key frames `turn`: centre
/// translation (mm) outside, body rotation (degrees) inside.
fn arm_groups(anim: &Looping, turn: &[TwoArms], arm: usize) -> Vec<Group> {
    let pose = |t: &TwoArms| if arm == 0 { t.arm1 } else { t.arm2 };
    let mut groups = Vec::new();
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
            .map(|c| format!("{:.3},{:.3}", c.x, c.y))
            .collect();
        let rot: Vec<String> = angle
            .iter()
            .map(|a| format!("{:.4}", a.to_degrees()))
            .collect();
        groups.push(
            Group::new()
                .set("id", format!("{id}{}", arm + 1))
                .add(anim.transform("translate", tr.join(";")))
                .add(
                    Group::new()
                        .add(anim.transform("rotate", rot.join(";")))
                        .add(use_of(id)),
                ),
        );
    }
    groups
}

/// A static sheet of `cols × rows` frames at equal carrier-angle steps, each with both arms.
#[must_use]
pub fn frame_sheet(
    sim: &Simulation,
    target: &[Point],
    cols: usize,
    rows: usize,
    outline_points: usize,
) -> String {
    let frames = (cols * rows).max(1);
    let traced: Vec<Point> = sim.turn(720).iter().map(|t| t.arm1.tip_mm).collect();
    let b = extent(sim, target, 90);
    let (w, h) = (b[2] - b[0], b[3] - b[1]);
    let sheet = [b[0], b[1], b[0] + w * cols as f64, b[1] + h * rows as f64];
    let mut world = Group::new()
        .set("transform", "scale(1,-1)")
        .add(defs(sim, outline_points));
    for k in 0..frames {
        let (c, r) = (k % cols, k / cols);
        let dx = c as f64 * w;
        let dy = (rows - 1 - r) as f64 * h;
        let f = k as f64 / frames as f64;
        let t = sim.pose(sim.angle_at(f));
        let mut frame = Group::new().set("transform", format!("translate({dx:.3},{dy:.3})"));
        for layer in static_layers(target, &traced) {
            frame = frame.add(layer);
        }
        let o = sim.assembly.center_mm;
        frame =
            frame.add(use_of("sun").set("transform", format!("translate({:.3},{:.3})", o.x, o.y)));
        for p in [t.arm1, t.arm2] {
            frame = frame.add(
                SvgPath::new()
                    .set(
                        "d",
                        format!(
                            "M{:.3},{:.3} L{:.3},{:.3}",
                            o.x, o.y, p.planet_center_mm.x, p.planet_center_mm.y
                        ),
                    )
                    .set("stroke", "#444444")
                    .set("stroke-width", "3")
                    .set("opacity", "0.6"),
            );
            for (id, c, a) in [
                (
                    "intermediate",
                    p.intermediate_center_mm,
                    p.intermediate_angle_rad,
                ),
                ("planet", p.planet_center_mm, p.planet_angle_rad),
            ] {
                frame = frame.add(use_of(id).set(
                    "transform",
                    format!(
                        "translate({:.3},{:.3}) rotate({:.4})",
                        c.x,
                        c.y,
                        a.to_degrees()
                    ),
                ));
            }
        }
        // The label, upright again (y down) in the frame's top-left corner.
        frame = frame.add(
            Group::new().set("transform", "scale(1,-1)").add(
                Text::new(format!("φH = {:.0}°", sim.angle_at(f).to_degrees()))
                    .set("x", format!("{:.3}", b[0] + 4.0))
                    .set("y", format!("{:.3}", -(b[3] - 10.0)))
                    .set("font-family", "sans-serif")
                    .set("font-size", "8")
                    .set("fill", "#222222"),
            ),
        );
        world = world.add(frame);
    }
    format!("{}\n", document(sheet, 0.5).add(world))
}
