//! Teeth made without a cutter (wire EDM, printing): the gear is its blank minus
//! everything its mate sweeps through in the mesh, so its flanks are the envelope of the mate's
//! teeth — the outline every mate position leaves free, whatever the curvature of the pitch curve.
//! Written by hand: the sweep is the core of the field, no geometry library does it.
//!
//! **Blank.** The addendum curve `P(u) + h(u)·N(u)` of the gear's pitch curve, `h = ha·m` topped
//! on concave stretches by `κ·h_s²·cot²α` as the shaper-cut tips are (module doc of the shaper).
//!
//! **Root.** The mate's tips sweep the root down to depth `ha·m`; the root bottom (normal depth
//! beyond `(ha* − RAMP)·m`) is then lowered radially by up to the bottom clearance `c*·m`, so that
//! the gear's root clears the mate's tips as a rack-cut root does. (Pushing the mate's tips out
//! instead would make a pinion-shaped cutter of the mate, whose longer tip corners loop into the
//! gear's flanks on strongly non-circular pairs: measured, notches 0.05·m deep near the pitch
//! curve.)
//!
//! **Sweep.** The gear is star-shaped about its centre: along each polar ray `θ_j` its material is
//! `[0, r_j]` with `r_j` the smallest radius at which the ray meets the blank or enters the tool
//! at one of the given mate positions (the first crossing of the ray with a tool edge). The rays
//! are `N` uniform angles (`2π·r_tip/N ≤ RAY_SPACING·m`), the positions those of one mesh cycle,
//! each given as the rigid map of the mate's body frame into the gear's. Backlash is the caller's:
//! a second set of positions with the mate turned by the backlash angle towards its coast side
//! thins the gear's coast flanks. The lowest tool vertex of each eighth of a ray interval is
//! kept too and inserted where it lies inside the chord between the rays, so a tool corner moving
//! along a ray is not cut off. Error: the chord between mate positions leaves scallops of height
//! ≈ Δs²/(8ρ_rel) on the flanks (Δs the contact's travel per position), the mate's tip region is
//! swept at 8× the positions and its vertices' paths between positions are swept as edges.
//!
//! **Status: experimental.** On an involute pair the swept flanks are the conjugate involutes
//! (`tests/it/swept.rs`), but on strongly non-circular pairs the swept gear does not yet mesh as a
//! cut one does (measured in docs/teeth.md: transmission error 0.1° where a shaper-cut gear gives
//! 4e-6°); the console says so, and the mesh verification shows the verdict.
//!
//! Checks: every one of the `z` teeth keeps a stretch of its tip (a tooth consumed by the sweep —
//! pointed — is an error); the narrowest tip is reported.
use super::outline::Outline;
use super::shape::StarShape;
use super::undercut::report_on;
use super::{GearBlank, TeethError};
use crate::geometry::pitch::PitchCurve;
use crate::math::Point;
use rayon::prelude::*;
use std::f64::consts::TAU;
use sweep::SUB;

mod sweep;

/// Largest spacing of the polar rays along the tip, in modules.
const RAY_SPACING: f64 = 2e-3;
/// Depth over which the root bottom is lowered from 0 to the bottom clearance, in modules.
const RAMP: f64 = 0.1;
/// A rigid map of the mate's body frame into the gear's: `x ↦ R(angle)·x + shift` (mm, rad).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MatePose {
    /// Rotation, rad.
    pub angle_rad: f64,
    /// Translation, mm.
    pub shift_mm: Point,
}

impl MatePose {
    fn apply(&self, (s, c): (f64, f64), x: Point) -> Point {
        Point::new(
            c * x.x - s * x.y + self.shift_mm.x,
            s * x.x + c * x.y + self.shift_mm.y,
        )
    }
}

/// The mate of a swept gear: its outline and pitch curve (its body frame, mm) and its motion.
#[derive(Clone, Copy)]
pub struct Mate<'a> {
    /// The mate's outline, CCW, mm.
    pub outline_mm: &'a [Point],
    /// The mate's pitch curve (its tip region is told by the height above it).
    pub pitch: &'a PitchCurve,
    /// The mate's position in the gear's body frame at cycle fraction `u ∈ [0, 1)`, for each of
    /// `offsets` driven offsets (the working and the coast flanks' positions).
    pub pose: &'a (dyn Fn(f64, usize) -> MatePose + Sync),
    /// Number of offsets.
    pub offsets: usize,
    /// Positions per cycle at which the whole outline is swept; the mate's tip region is swept
    /// at `TIP_REFINE` times as many.
    pub positions: usize,
}

/// What the sweep reports besides the outline.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct SweepChecks {
    /// Narrowest tooth tip left by the sweep (arc along the tip), mm.
    pub(super) min_tip_width_mm: f64,
}

/// The outline of `blank`'s `z` teeth of module `module_mm` on its pitch curve, swept by its
/// `mates` (one, or two for the intermediate gear of a train; module doc,
/// [`super::Generation::Swept`]), simplified to `blank.opts.chord_tol_mm`. The phase and the
/// thinning are unused: the mate's positions place and thin the teeth.
///
/// Errors: [`TeethError::Swept`] when the sweep consumes a tooth's tip (pointed teeth) or leaves
/// other than `z` teeth (the mate's positions do not match the gear).
pub(super) fn generate_swept(
    blank: &GearBlank<'_>,
    mates: &[Mate<'_>],
) -> Result<(Outline, SweepChecks), TeethError> {
    let m = blank.module_mm;
    blank.validated_pitch_mm()?;
    let ha = blank.rack.addendum() * m;
    let (pitch, tip) = addendum_table(blank, ha);
    let addendum = StarShape::new(&tip, "addendum curve").map_err(|_| TeethError::Swept {
        what: "the addendum curve is not star-shaped about the gear's centre".into(),
    })?;
    let r_tip = tip.iter().map(|p| p.hypot()).fold(0.0, f64::max);
    let n = ((TAU * r_tip / (RAY_SPACING * m)).ceil() as usize).max(4096);
    let dth = TAU / n as f64;
    let dir: Vec<(f64, f64)> = (0..n).map(|j| (j as f64 * dth).sin_cos()).collect();
    let r_blank: Vec<f64> = (0..n).map(|j| addendum.radius_at(j as f64 * dth)).collect();
    let rays = Rays {
        dth,
        dir: &dir,
        r_blank: &r_blank,
    };
    // Every mate lowers the rays; the gear keeps what none of them reaches.
    let mut all = sweep::untouched(&rays);
    for mate in mates {
        sweep::merge(&mut all, &sweep::sweep_mate(mate, &rays, ha, m, r_tip)?);
    }
    let (swept, gaps) = all;
    let r = with_root_clearance(blank, &rays, &pitch, &swept, ha);
    let min_tip = narrowest_tip_mm(&rays, &r, blank.z)?;
    let points_mm = crate::math::polyline::simplify_closed(
        &ray_outline(&rays, &r, &gaps),
        blank.opts.chord_tol_mm,
    );
    let mut undercut = report_on(blank);
    // No cutter, no cutter undercut: the flanks are what the mate leaves.
    for f in &mut undercut.flanks {
        f.undercut = false;
        f.undercut_mm = 0.0;
        f.contact_ratio_loss = 0.0;
        f.form_depth_mm = f.flank_depth_mm;
    }
    undercut.summarize();
    Ok((
        Outline {
            points_mm,
            z: blank.z,
            module_mm: m,
            undercut,
        },
        SweepChecks {
            min_tip_width_mm: min_tip,
        },
    ))
}

/// The blank's pitch curve and addendum curve (body frame, mm), sampled every 0.05·m of pitch
/// arc (chord sag ≈ (0.05·m)²/(8ρ), below 1e-4·m for ρ ≥ 3·m): the addendum `ha` (mm) over the
/// pitch curve, topped on concave stretches as a shaper-cut tip is (module doc).
fn addendum_table(blank: &GearBlank<'_>, ha: f64) -> (Vec<Point>, Vec<Point>) {
    let (frame, rack, m) = (blank.frame, &blank.rack, blank.module_mm);
    let k_tip = (rack.straight_depth() * m / rack.alpha_rad().tan()).powi(2);
    let nb = (frame.length_mm() / (0.05 * m)).ceil().max(720.0) as usize;
    (0..nb)
        .map(|k| {
            let f = frame.at(frame.length_mm() * k as f64 / nb as f64);
            let h = ha + f.kappa.min(0.0) * k_tip;
            (f.p, f.p + f.n * h)
        })
        .unzip()
}

/// The swept radii (mm) with the bottom clearance: the swept root is the mate's tip path, at
/// depth `ha` (mm); the rays deeper than (ha* − RAMP)·m below the pitch curve (normal distance
/// to `pitch`, its sampled points) are lowered radially by up to c*·m, reaching the full
/// clearance at depth ha·m. Only the root bottom moves: the flank above that depth stays as the
/// mate left it.
fn with_root_clearance(
    blank: &GearBlank<'_>,
    rays: &Rays<'_>,
    pitch: &[Point],
    swept: &[f64],
    ha: f64,
) -> Vec<f64> {
    let m = blank.module_mm;
    let c = blank.rack.clearance() * m;
    let grid = crate::math::polyline::SegmentGrid::new(pitch);
    let curve = blank.frame.curve();
    swept
        .par_iter()
        .enumerate()
        .map(|(j, &rj)| {
            let th = j as f64 * rays.dth;
            let rp = curve.radius_mm(th);
            if rj >= rays.r_blank[j] || rj > rp - (ha - RAMP * m) {
                return rj;
            }
            let (sn, cs) = rays.dir[j];
            let depth = grid.nearest(Point::new(rj * cs, rj * sn)).distance_mm;
            let w = ((depth - (ha - RAMP * m)) / (RAMP * m)).clamp(0.0, 1.0);
            rj - c * w
        })
        .collect()
}

/// The narrowest tooth tip (mm of arc): the runs of rays that kept the blank are the tips; an
/// error unless there are exactly `z`.
fn narrowest_tip_mm(rays: &Rays<'_>, r: &[f64], z: u32) -> Result<f64, TeethError> {
    let n = r.len();
    let untouched: Vec<bool> = r.iter().zip(rays.r_blank).map(|(a, b)| a >= b).collect();
    let Some(start) = (0..n).find(|&j| !untouched[j]) else {
        return Err(TeethError::Swept {
            what: "the mate's positions never reach the gear".into(),
        });
    };
    let mut widths = Vec::new();
    let mut run = 0usize;
    for k in 1..=n {
        let j = (start + k) % n;
        if untouched[j] {
            run += 1;
        } else if run > 0 {
            widths.push(run as f64 * rays.dth * rays.r_blank[j]);
            run = 0;
        }
    }
    if widths.len() != z as usize {
        return Err(TeethError::Swept {
            what: format!(
                "the sweep leaves {} tooth tips for {z} teeth (pointed or consumed teeth, or mate positions that do not match the gear)",
                widths.len()
            ),
        });
    }
    Ok(widths.iter().copied().fold(f64::INFINITY, f64::min))
}

/// The outline through the rays' ends `r` (mm), with the lowest tool vertex of each of the
/// `SUB` sub-intervals between two rays (`gaps`, `(ρ, θ)` in mm and rad) where it lies inside
/// the chord between them.
fn ray_outline(rays: &Rays<'_>, r: &[f64], gaps: &[(f64, f64)]) -> Vec<Point> {
    let n = r.len();
    let ray_point = |j: usize| {
        let (sn, cs) = rays.dir[j % n];
        Point::new(r[j % n] * cs, r[j % n] * sn)
    };
    let mut pts: Vec<Point> = Vec::with_capacity(n + n / 8);
    for j in 0..n {
        let (a, b) = (ray_point(j), ray_point(j + 1));
        pts.push(a);
        for &(rho, t) in &gaps[j * SUB..(j + 1) * SUB] {
            if !rho.is_finite() {
                continue;
            }
            let (sn, cs) = t.sin_cos();
            let d = b - a;
            let uxd = cs * d.y - sn * d.x;
            if uxd != 0.0 {
                let chord = (a.cross(d)) / uxd;
                if rho < chord {
                    pts.push(Point::new(rho * cs, rho * sn));
                }
            }
        }
    }
    pts
}

/// The polar rays of a swept gear: spacing `dth` (rad), directions `(sin, cos)`, blank radii (mm).
struct Rays<'a> {
    dth: f64,
    dir: &'a [(f64, f64)],
    r_blank: &'a [f64],
}
