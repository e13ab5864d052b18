//! Integration tests: shaper-cutter generation (issue 18) against closed forms — involutes on a
//! circle (external gear) and on a concave circular arc (internal gear), the basic-rack profile
//! on a straight stretch — and the process choice.
use ncgear::geometry::pitch::PitchCurve;
use ncgear::teeth::overlap::first_self_intersection;
use ncgear::teeth::process::{CutterChoice, Process, generate_by_process, generate_with_cutter};
use ncgear::teeth::{
    ArcFrame, OutlineOptions, RackParams, TeethError, ToothPolicy, generate_outline, scale_curve,
    tooth_count,
};

fn inv(a: f64) -> f64 {
    a.tan() - a
}

/// Range `[min, max]` of `inv(α_r) + sign·polar angle` about `centre` over the outline vertices
/// selected by `keep(radius, polar angle)`: a single value for an exact involute of the base
/// circle `rb` (the sign chooses the flank's hand). Returns (min, max, count).
fn involute_range(
    pts: &[[f64; 2]],
    centre: [f64; 2],
    rb: f64,
    sign: f64,
    keep: impl Fn(f64, f64) -> bool,
) -> (f64, f64, usize) {
    let vals: Vec<f64> = pts
        .iter()
        .filter_map(|p| {
            let (x, y) = (p[0] - centre[0], p[1] - centre[1]);
            let (r, t) = (x.hypot(y), y.atan2(x));
            keep(r, t).then(|| inv((rb / r).acos()) + sign * t)
        })
        .collect();
    let lo = vals.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = vals.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    (lo, hi, vals.len())
}

#[test]
fn shaper_on_a_circle_cuts_the_involute() {
    // Any involute cutter generates the involute of the gear's base circle r·cos α: the right
    // flank of tooth 0 crosses the pitch circle at θp = p/4/r = π/48, so its vertices satisfy
    // inv(α_r) + θ = θp + inv α (spec G5, the rack's closed form) — for every cutter size.
    let (r0, m, z) = (24.0, 2.0, 24);
    let c = PitchCurve::from_fn(256, |_| r0).unwrap();
    let frame = ArcFrame::new(&c);
    let alpha = 20f64.to_radians();
    let rb = r0 * alpha.cos();
    let want = std::f64::consts::PI / 48.0 + inv(alpha);
    for zc in [34, 50, 100] {
        let o = generate_with_cutter(
            &frame,
            &RackParams::default(),
            z,
            m,
            zc,
            &OutlineOptions::new(0.0, 1e-6),
        )
        .unwrap();
        assert_eq!(first_self_intersection(&o.points_mm).unwrap(), None);
        let (lo, hi, n) = involute_range(&o.points_mm, [0.0, 0.0], rb, 1.0, |r, t| {
            t > 0.0 && t < 0.13 && r > rb * 1.01 && r > r0 - m && r < r0 + 0.99 * m
        });
        assert!(n > 50, "z_c {zc}: {n}");
        assert!(
            (lo - want).abs() < 1e-9 && (hi - want).abs() < 1e-9,
            "z_c {zc}: [{lo}, {hi}] vs {want}"
        );
    }
    // A 12-tooth cutter would need its flank below its base circle to reach the 24-tooth gear's
    // tip (contact beyond the interference point of the line of action): refused, named.
    let err = generate_with_cutter(
        &frame,
        &RackParams::default(),
        z,
        m,
        12,
        &OutlineOptions::new(0.0, 1e-3),
    )
    .unwrap_err();
    assert!(
        matches!(
            err,
            TeethError::Shaper {
                cutter_teeth: 12,
                ..
            }
        ),
        "{err}"
    );
}
