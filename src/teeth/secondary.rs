//! Secondary cutting: whether a shaper cutter's other teeth cut into the gear while it
//! rolls, which the envelope of the cutting tooth alone does not show. In a concave hollow whose
//! radius of curvature is close to the cutter's pitch radius the cutter nearly conforms to the
//! gear — an internal gear cut by a pinion with too small a tooth-count difference — and its
//! neighbouring teeth, or its root, gouge the neighbouring flanks and tips. Written by hand: it
//! is the generation's own check.
//!
//! **Check.** The whole cutter (its outline with every tooth, sampled with chords inside it)
//! is indexed as a [`Shape`] in its own frame and rolled along the pitch curve at 16 positions
//! per tooth pitch; at each, the generated outline's vertices within the cutter's reach are
//! mapped into the cutter's frame and their signed clearance taken. The true cut is the blank
//! less every cutter position, so a correctly generated outline is nowhere inside the cutter:
//! a vertex deeper than [`SECONDARY_TOL`]·m means the cutter removes material the outline keeps.
//! A vertex farther from the cutter's centre than its outermost point (plus the shape's exact
//! range) is outside it without a lookup.
//!
//! **Reach.** At arc distance `d` from the contact the cutter's pitch circle and the pitch curve
//! are `≈ d²·(1/r0 + κ)/2` apart (κ < 0 on a concave stretch, the cutter inside it); the teeth
//! (cutter `(ha* + c*)·m` tall, gear `ha*·m`) can meet while that is below their sum, so the
//! vertices within `d = √(2·(2ha* + c*)·m/(1/r0 + κ_min))` (κ_min the smallest curvature within
//! half a cutter turn) are checked, at most half the cutter's circumference.
use super::frame::ArcFrame;
use super::shape::Shape;
use super::shaper::Cutter;
use super::{RackParams, TeethError};
use crate::math::Point;
use rayon::prelude::*;
use std::f64::consts::PI;

/// Depth of a gear vertex inside the cutter that counts as secondary cutting, in modules (twice
/// the export chord tolerance: the outline's vertices lie on the cut boundary, the cutter's chords
/// inside it).
pub const SECONDARY_TOL: f64 = 2e-3;

/// Cutter positions per tooth pitch.
const POSITIONS_PER_PITCH: usize = 16;

/// Where the gear's space centres lie: tooth 0's centre `phase_mm`, pitch `p_mm`, the spaces
/// `w_mm` wide on the pitch curve and centred `shift_mm` past the mid-pitch (the backlash
/// thinning), mm.
#[derive(Debug, Clone, Copy)]
pub(super) struct Spaces {
    pub phase_mm: f64,
    pub p_mm: f64,
    pub w_mm: f64,
    pub shift_mm: f64,
}

/// The deepest a vertex of `outline` (body frame, mm) lies inside `cutter` rolled along `frame`
/// over the whole curve, mm (≤ 0 when the cutter never cuts into it; module doc), exact up to
/// 0.05·m (deeper cuts read as 0.05·m).
///
/// Errors: [`TeethError::Shaper`] when the cutter outline cannot be indexed (degenerate cutter).
pub(super) fn secondary_cut_depth(
    frame: &ArcFrame,
    rack: &RackParams,
    module_mm: f64,
    cutter: &Cutter,
    spaces: Spaces,
    outline: &[Point],
) -> Result<f64, TeethError> {
    let m = module_mm;
    let r0 = cutter.r0;
    let pts = cutter.outline(spaces.w_mm, 1e-4 * m);
    let cap = 0.05 * m;
    let shape = Shape::new(&pts, cap, "cutter").map_err(|_| TeethError::Shaper {
        cutter_teeth: cutter.z,
        what: "its outline cannot be indexed (degenerate cutter)",
    })?;
    // A vertex farther than `cap` beyond the cutter's outermost point is outside it by more
    // than the shape's exact range: its clearance is `cap` without the lookup.
    let r_out = pts.iter().map(|p| p.hypot()).fold(0.0, f64::max) + cap;
    let r_out2 = r_out * r_out;
    let l = frame.length_mm();
    let n = ((l / spaces.p_mm).round() as usize).max(1) * POSITIONS_PER_PITCH;
    // Curvature at the positions, and its sliding minimum over half a cutter turn each side.
    let kappa: Vec<f64> = (0..n)
        .map(|j| frame.at(l * j as f64 / n as f64).kappa)
        .collect();
    let half = (((PI * r0) / (l / n as f64)).ceil() as usize).min(n / 2);
    let k_min: Vec<f64> = (0..n)
        .map(|j| {
            (0..=2 * half)
                .map(|i| kappa[(j + n + i - half) % n])
                .fold(f64::INFINITY, f64::min)
        })
        .collect();
    let reach_sum = (2.0 * rack.addendum() + rack.clearance()) * m;
    // Vertices by polar angle, for the window of each position.
    let mut by_angle: Vec<(f64, Point)> = outline.iter().map(|p| (p.atan2(), *p)).collect();
    by_angle.sort_by(|a, b| a.0.total_cmp(&b.0));
    let center0 = spaces.phase_mm + 0.5 * spaces.p_mm + spaces.shift_mm;
    let deepest = (0..n)
        .into_par_iter()
        .map(|j| {
            let s = l * j as f64 / n as f64;
            let f = frame.at(s);
            // A cutter no smaller than the hollow (bend ≤ 0) reaches its whole half-turn: the
            // floor only keeps the square root finite before the cap at π·r0.
            let bend = (1.0 / r0 + k_min[j]).max(1e-12);
            let d = (2.0 * reach_sum / bend).sqrt().min(PI * r0) + m;
            let (px, py) = (f.p.x, f.p.y);
            let window = (d / px.hypot(py)).min(PI);
            let theta = py.atan2(px);
            let c = [px + r0 * f.n.x, py + r0 * f.n.y];
            let e1 = [-f.n.x, -f.n.y];
            let (sr, cr) = ((s - center0) / r0).sin_cos();
            let mut worst = f64::INFINITY;
            let mut visit = |lo: f64, hi: f64| {
                let a = by_angle.partition_point(|v| v.0 < lo);
                for &(_, x) in by_angle[a..].iter().take_while(|v| v.0 <= hi) {
                    let v = [x.x - c[0], x.y - c[1]];
                    if v[0] * v[0] + v[1] * v[1] > r_out2 {
                        worst = worst.min(cap);
                        continue;
                    }
                    let (a1, b1) = (v[0] * e1[0] + v[1] * e1[1], v[0] * f.t.x + v[1] * f.t.y);
                    let q = Point::new(a1, b1).rotate_sc(sr, cr);
                    worst = worst.min(shape.clearance(q));
                }
            };
            let (lo, hi) = (theta - window, theta + window);
            visit(lo.max(-PI), hi.min(PI));
            if lo < -PI {
                visit(lo + 2.0 * PI, PI);
            }
            if hi > PI {
                visit(-PI, hi - 2.0 * PI);
            }
            worst
        })
        .reduce(|| f64::INFINITY, f64::min);
    Ok(-deepest)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::pitch::PitchCurve;
    use crate::teeth::shaper::{cutter_pitch_radius_mm, generate_shaper};
    use crate::teeth::{GearBlank, OutlineOptions, ToothPolicy, scale_curve, tooth_count};

    /// A cutter larger than the tightest concave hollow cannot fit in it: rolled there, its
    /// pitch circle crosses the pitch curve and its teeth dig into the neighbouring teeth, deep
    /// beyond the tolerance; a cutter of less than half the hollow's radius cuts only the
    /// envelope (depth at the rounding level, the cutting tooth touching the outline).
    #[test]
    fn a_cutter_larger_than_the_hollow_cuts_secondary_a_small_one_does_not() {
        let m = 1.0;
        // r = R(1 + 0.3 cos 2θ): concave around θ = ±π/2, |ρ| ≈ 29 mm once scaled to whole teeth.
        let c = PitchCurve::from_fn(1024, |t| 30.0 * (1.0 + 0.3 * (2.0 * t).cos())).unwrap();
        let tc = tooth_count(&c, m, ToothPolicy::Nearest, 1e-9).unwrap();
        let c = scale_curve(&c, tc.scale).unwrap();
        let frame = ArcFrame::new(&c);
        let rho = -1.0 / frame_min_kappa(&frame);
        let rack = RackParams::default();
        let opts = OutlineOptions::new(0.0, 1e-3 * m);
        let p = frame.length_mm() / f64::from(tc.z);
        let spaces = Spaces {
            phase_mm: 0.0,
            p_mm: p,
            w_mm: 0.5 * p,
            shift_mm: 0.0,
        };
        let depth = |zc: u32| {
            let cutter = Cutter::new(zc, &rack, m).unwrap();
            let blank = GearBlank::new(&frame, rack, tc.z, m, opts);
            let (o, _) = generate_shaper(&blank, &cutter, &[]).unwrap();
            secondary_cut_depth(&frame, &rack, m, &cutter, spaces, &o.points_mm).unwrap()
        };
        let (big, small) = (80, 34);
        assert!(cutter_pitch_radius_mm(big, m) > rho + 5.0, "ρ = {rho}");
        assert!(cutter_pitch_radius_mm(small, m) < 0.7 * rho, "ρ = {rho}");
        let (d_big, d_small) = (depth(big), depth(small));
        // Clipped at the cutter shape's exact range, 0.05·m: at least that deep.
        assert!(d_big >= 0.05 * m - 1e-12, "{d_big}");
        assert!(d_small.abs() < 1e-3 * m, "{d_small}");
    }

    fn frame_min_kappa(f: &ArcFrame) -> f64 {
        (0..4096)
            .map(|j| f.at(f.length_mm() * f64::from(j) / 4096.0).kappa)
            .fold(f64::INFINITY, f64::min)
    }
}
