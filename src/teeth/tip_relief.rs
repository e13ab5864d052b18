//! Tip relief against the mate's fillets: the tooth tips of the gears of a mesh with a
//! shaper-cut gear are lowered, tooth by tooth, until no tip corner enters its mate at the law's
//! position anywhere in the mesh cycle.
//!
//! **Why.** The basic rack's straight flank ends exactly at the addendum depth
//! (`(ha* + c* − ρf*(1 − sin α))·m = ha*·m` for the ISO 53 profile A), so a gear's tip corner
//! meets its mate's flank at its form point with no margin when the gear's pitch curve is flat
//! there: a straight rack moves exactly like the rack that generated the mate, and its corner
//! traces the path of the generating rack's form point, which never enters the mate. A convex
//! gear's tips meet the mate's flank `ha²·cot²α/(2ρ)` short of the form point (a margin that
//! grows with its curvature); a concave stretch meets it beyond (the shaper's topping of concave
//! tips takes that back). Near an inflection, where a mixed convex/concave pitch
//! curve is nearly straight over a tooth while the mate is tightly curved (its radius of
//! curvature near the undercut limit `h·m/sin²α`), the corner's path departs from the generating
//! rack's at second order in the rolling — by `≈ Δs²/(2ρ)` over a roll `Δs` — and grazes the
//! mate's fillet trochoid: on random mixed convex/concave centrodes, some pairs show a
//! transmission error from such contacts where the others show none, and a uniform topping
//! does not remove them all (docs/performance.md, "Tip relief on mixed centrodes"). A
//! per-tooth check settles it instead of a formula. The rack-cut mate of a
//! shaper-cut gear is checked too (a small cutter's fillets can sit higher than a rack's); two
//! rack-cut gears keep their outlines (a convex tip keeps its margin).
//!
//! **Check.** For every mesh of the gear, the mate's outline (at the verification's chord
//! tolerance, indexed as a [`Shape`]) is placed at the law's position ([`MeshMotion::law_pose`])
//! at `positions` cycle fractions; at each, the tip corners of the teeth within two pitches of
//! the contact are mapped into the mate's frame and their signed clearance taken. A tooth whose
//! corner goes deeper than [`PENETRATION_TOL`]·m into a mate gets the next relief of
//! [`RELIEF_LADDER`] (its corners recomputed on the lowered tip), until none does or the ladder
//! ends (the mesh verification then shows what is left). Relief only shortens a tip: the
//! working flanks, the fillets and the mates are unchanged, so the meshes' checks are
//! independent and one pass suffices.
use super::blank::OutlineOptions;
use super::mate_motion::MeshMotion;
use super::outline::Outline;
use super::process::{GearProcess, tip_corners_as};
use super::shape::Shape;
use super::{GearBlank, Generation, TeethError, generate};
use crate::math::Point;
use rayon::prelude::*;
use std::f64::consts::{PI, TAU};

/// Tip reliefs tried, in modules, in order (a tooth moves to the next while a corner enters a
/// mate).
pub const RELIEF_LADDER: [f64; 7] = [0.0, 0.005, 0.01, 0.02, 0.04, 0.08, 0.16];

/// Depth a tip corner may reach into a mate, in modules: twice the verification's chord
/// tolerance (a corner on the mate's working flank touches it, within that tolerance). Measured:
/// a corner 9.5e-6·m deep in an undercut mate flank gave a transmission error of 2.5e-5°.
pub const PENETRATION_TOL: f64 = 2e-6;

/// Cycle positions per tooth pitch at which the corners are checked: the contacts this guards
/// against last about a quarter of a pitch (measured), so each is seen about ten times.
pub const POSITIONS_PER_PITCH: usize = 48;

/// The tip corners `[left, right]` of every tooth (body frame, mm) with tooth `k`'s tip lowered
/// by `relief[k]` (mm).
pub type TipCorners<'a> = dyn Fn(&[f64]) -> Result<Vec<[Point; 2]>, TeethError> + Sync + 'a;

/// One mesh of the relieved gear.
#[derive(Clone, Copy)]
pub struct ReliefMesh<'a> {
    /// The mate's outline at the verification's chord tolerance, indexed, its body frame, mm.
    pub mate: &'a Shape,
    /// The mesh's motion over its cycle.
    pub motion: &'a MeshMotion<'a>,
    /// Which gear of the mesh the relieved one is (0: driver, 1: driven).
    pub gear: usize,
    /// Positions over the cycle (use [`POSITIONS_PER_PITCH`] per pitch of the cycle).
    pub positions: usize,
}

/// The tip relief of each tooth, mm (module doc): `corners(relief)` gives the `[left, right]`
/// tip corners of every tooth (body frame, mm) with tooth `k`'s tip lowered by `relief[k]`.
///
/// Errors: those of `corners` (a relief that makes a tooth pointed).
pub fn tip_relief(
    corners: &TipCorners<'_>,
    meshes: &[ReliefMesh<'_>],
    module_mm: f64,
) -> Result<Vec<f64>, TeethError> {
    let mut c = corners(&[])?;
    let mut level = vec![0usize; c.len()];
    loop {
        let deepest = deepest_corners(&c, meshes, module_mm);
        let mut moved = false;
        for (l, d) in level.iter_mut().zip(&deepest) {
            if *d < -PENETRATION_TOL * module_mm && *l + 1 < RELIEF_LADDER.len() {
                *l += 1;
                moved = true;
            }
        }
        let relief: Vec<f64> = level
            .iter()
            .map(|&l| RELIEF_LADDER[l] * module_mm)
            .collect();
        if !moved {
            return Ok(relief);
        }
        c = corners(&relief)?;
    }
}

/// Smallest signed clearance of each tooth's corners in any mate over the cycles, mm (positive
/// far from every contact: clipped at the mate shapes' cap).
fn deepest_corners(corners: &[[Point; 2]], meshes: &[ReliefMesh<'_>], m: f64) -> Vec<f64> {
    let z = corners.len();
    // Polar angle and the window half-width (two pitches of arc at the corner's radius) of each
    // tooth, from its left corner.
    let teeth: Vec<(f64, f64)> = corners
        .iter()
        .map(|[l, _]| (l.atan2(), (2.0 * PI * m / l.hypot()).min(PI)))
        .collect();
    let per_mesh = |mesh: &ReliefMesh<'_>| {
        (0..mesh.positions)
            .into_par_iter()
            .fold(
                || vec![f64::INFINITY; z],
                |mut best, j| {
                    let u = j as f64 / mesh.positions as f64;
                    let theta = mesh.motion.contact_angle_rad(mesh.gear, u);
                    let pose = mesh.motion.law_pose(mesh.gear, u);
                    // Gear body → mate body: the inverse of x ↦ R(a)·x + t.
                    let (s, c) = pose.angle_rad.sin_cos();
                    let to_mate = |x: Point| (x - pose.shift_mm).rotate_sc(-s, c);
                    for (k, &(angle, half)) in teeth.iter().enumerate() {
                        let off = (angle - theta + PI).rem_euclid(TAU) - PI;
                        if off.abs() <= half {
                            for x in corners[k] {
                                best[k] = best[k].min(mesh.mate.clearance(to_mate(x)));
                            }
                        }
                    }
                    best
                },
            )
            .reduce(
                || vec![f64::INFINITY; z],
                |a, b| a.iter().zip(&b).map(|(x, y)| x.min(*y)).collect(),
            )
    };
    meshes
        .iter()
        .map(per_mesh)
        .fold(vec![f64::INFINITY; z], |a, b| {
            a.iter().zip(&b).map(|(x, y)| x.min(*y)).collect()
        })
}

/// A gear after its tip relief: the export and fine outlines regenerated.
#[derive(Debug, Clone)]
pub struct Relieved {
    /// The outline at the export chord tolerance.
    pub export: Outline,
    /// The outline at the verification's chord tolerance, mm.
    pub fine_mm: Vec<Point>,
    /// Tip relief of each tooth, mm.
    pub relief_mm: Vec<f64>,
    /// Narrowest tooth tip after the relief of a shaper-cut gear, mm of arc.
    pub min_tip_width_mm: Option<f64>,
}

/// The tip relief ([`tip_relief`]) of `blank` cut as `as_cut` records (rack or shaper), with
/// `blank.opts` (its export chord tolerance) and its outline regenerated at both tolerances; `None`
/// when no tooth needs one (the outlines stay as they are).
///
/// Errors: those of the generation with the relief (a tooth made pointed), and
/// [`TeethError::Swept`] for a swept gear (it has no cutter to relieve).
pub fn relieve_gear(
    blank: &GearBlank<'_>,
    as_cut: &GearProcess,
    fine_chord_tol_mm: f64,
    meshes: &[ReliefMesh<'_>],
) -> Result<Option<Relieved>, TeethError> {
    let corners = |r: &[f64]| tip_corners_as(blank, as_cut, r);
    let relief_mm = tip_relief(&corners, meshes, blank.module_mm)?;
    if relief_mm.iter().all(|r| *r == 0.0) {
        return Ok(None);
    }
    let fine = blank.with_opts(OutlineOptions {
        chord_tol_mm: fine_chord_tol_mm,
        ..blank.opts
    });
    let how = Generation::Relieved {
        as_cut,
        tip_relief_mm: &relief_mm,
    };
    let (export, fine) = (generate(blank, how)?, generate(&fine, how)?);
    Ok(Some(Relieved {
        export: export.outline,
        fine_mm: fine.outline.points_mm,
        min_tip_width_mm: export.process.min_tip_width_mm,
        relief_mm,
    }))
}
