//! Tooth outlines (docs/math/teeth.md §12): the chord tolerance of the generated polyline and the sampling of
//! the pitch curve. On a circle the rack generates an exact involute (docs/math/chain.md §11.5 (G5)), so the error is
//! measured against the closed form: the largest distance from densely sampled exact involute
//! flank points (tooth 0, right flank, pitch circle r = 24 mm, m = 2, α = 20°) to the polyline.
//! On the G1 sun (non-circular) the reference is a converged outline (chord 1e-6 mm from a
//! 28 800-sample pitch curve) and the error is the Hausdorff distance between the outlines
//! (the pitch-curve sample rows use chord 1e-5 mm, so their floor is ≈ 1e-5 mm).
use super::{Row, timed};
use ncgear::geometry::pitch::PitchCurve;
use ncgear::math::Point;
use ncgear::math::polyline::{distances_to_polyline, hausdorff_mm};
use ncgear::teeth::{
    ArcFrame, GearBlank, Generation, Outline, OutlineOptions, RackParams, ToothPolicy, generate,
    scale_curve, tooth_count,
};
use std::f64::consts::PI;

/// Exact right flank of tooth 0 on the circle r0 with z teeth: polar angle
/// `θ(r) = π/(2z) + inv(α) − inv(acos(rb/r))`, `rb = r0 cos α`, on the involute part.
fn involute_flank(r0: f64, z: u32, m: f64, n: usize) -> Vec<Point> {
    let alpha = 20f64.to_radians();
    let rb = r0 * alpha.cos();
    let inv = |a: f64| a.tan() - a;
    let (lo, hi) = ((rb * 1.01).max(r0 - m), r0 + 0.99 * m);
    (0..n)
        .map(|k| {
            let r = lo + (hi - lo) * k as f64 / (n - 1) as f64;
            let t = PI / (2.0 * f64::from(z)) + inv(alpha) - inv((rb / r).acos());
            Point::new(r * t.cos(), r * t.sin())
        })
        .collect()
}

fn g1_sun(samples: usize, module_mm: f64) -> (PitchCurve, u32) {
    let c = ncgear::geometry::golden::g1_mechanism()
        .sun_curve(samples)
        .expect("G1 sun");
    let tc = tooth_count(&c, module_mm, ToothPolicy::Nearest, 1e-10).expect("tooth count");
    (scale_curve(&c, tc.scale).expect("scaled"), tc.z)
}

fn outline(c: &PitchCurve, z: u32, m: f64, chord: f64) -> Outline {
    let frame = ArcFrame::new(c);
    let opts = OutlineOptions::new(0.0, chord);
    let blank = GearBlank::new(&frame, RackParams::default(), z, m, opts);
    generate(&blank, Generation::Rack).expect("outline").outline
}

/// The teeth rows.
pub fn rows() -> Vec<Row> {
    let mut rows = Vec::new();
    // 1. Chord tolerance on a circle vs the involute closed form.
    let (r0, z, m) = (24.0, 24u32, 2.0);
    let circle = PitchCurve::from_fn(256, |_| r0).expect("circle");
    let exact = involute_flank(r0, z, m, 4000);
    for chord in [1e-1, 3e-2, 1e-2, 3e-3, 1e-3, 1e-4, 1e-5] {
        let (ms, o) = timed(3, || outline(&circle, z, m, chord));
        let err = distances_to_polyline(&exact, &o.points_mm)
            .into_iter()
            .fold(0.0, f64::max);
        rows.push(Row::new(
            "tooth chord tolerance (circle; vs involute closed form)",
            format!("{chord:e} mm ({} vertices)", o.points_mm.len()),
            "max distance exact flank → polyline, mm",
            err,
            ms,
        ));
    }
    // 2. Chord tolerance and pitch-curve samples on the G1 sun vs a converged outline.
    let m = 2.0;
    let (fine, zf) = g1_sun(28_800, m);
    let reference = outline(&fine, zf, m, 1e-6);
    for chord in [1e-1, 1e-2, 1e-3, 1e-4] {
        let (c, z) = g1_sun(28_800, m);
        let (ms, o) = timed(3, || outline(&c, z, m, chord));
        rows.push(Row::new(
            "tooth chord tolerance (G1 sun; vs converged outline)",
            format!("{chord:e} mm ({} vertices)", o.points_mm.len()),
            "Hausdorff distance to the reference outline, mm",
            hausdorff_mm(&o.points_mm, &reference.points_mm),
            ms,
        ));
    }
    for samples in [12, 16, 24, 32, 48, 90, 360] {
        let (ms, o) = timed(3, || {
            let (c, z) = g1_sun(samples, m);
            outline(&c, z, m, 1e-5)
        });
        rows.push(Row::new(
            "pitch-curve samples for the teeth (G1 sun; vs converged outline)",
            samples,
            "Hausdorff distance to the reference outline, mm",
            hausdorff_mm(&o.points_mm, &reference.points_mm),
            ms,
        ));
    }
    rows
}
