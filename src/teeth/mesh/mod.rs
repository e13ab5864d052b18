//! Mesh verification of two toothed outlines: roll them through a full cycle of the motion law
//! and measure interference, backlash and transmission error.
//!
//! Setup: driver (gear 1) centre at the origin, rotated CCW by φ; driven (gear 2) centre at
//! `(a, 0)`, rotated CW by `ψ(φ) + δ` (so its body angle `π + ψ` faces the driver). The clearance of
//! a vertex of one outline against the other is its signed distance to the other polyline
//! (negative inside; exact within `cap = 0.02·m` via a segment grid, clipped to `±cap` beyond).
//! `f(δ)` is the minimum clearance over both outlines' vertices near the contact. Per φ:
//! - working contact `ε(φ)`: the root of `f` with the working (larger-s) flanks touching; the
//!   transmission error is `ε(φ)` (rad) — the driven angle error of the toothed pair;
//! - coast contact `δc(φ)`: the other root; backlash on the pitch curve `(δc − ε)·r₂`, mm;
//! - interference: `f < 0` for every δ (no free position), or penetration at `ε`; and the exact
//!   overlap area of the outlines at δ = 0 (the law's position), see [`super::overlap`].
//!
//! Cost: every evaluation is bounded — blocks of ≈ 0.04·m of outline are bounded below through
//! copies simplified to 2e-3·m (clearance less the block radius and 3× the simplification), the
//! bounds are kept per position and moved by each block's speed across driven offsets, only the
//! blocks that can reach the minimum (or the overlap's edges) are evaluated, and within such a
//! block every 4th vertex first, the others only where its 1-Lipschitz bound in position does not
//! settle them: the minimum is exact, bit for bit. The candidates are the contact windows' blocks
//! whose bound at δ = 0 is within the backlash range's reach. The working contact is reached by
//! secant steps from δ = 0 (evaluated for the overlap anyway), the coast contact from one
//! evaluation a nominal backlash beyond it, both from the slope of a contact on the driven pitch
//! curve under a 20° pressure angle, with the vertices pruned by the Lipschitz bound of the
//! clearances in δ (`lip = r_max + 2m`); a free position is decided at the middle of the backlash
//! range. Where the steps miss (swept or far from conjugate teeth), both roots are bracketed on
//! copies simplified to 1e-4·m (built on first need) and polished on the given outlines within
//! ±η, η = 4·gap/(r₂/2) with `gap` the distance between the polylines (widened ×8 until it holds
//! a sign change). A root is a δ with |f| ≤ 1e-11 mm. About 1.2 ms per position (one core) for a
//! 24-tooth pair at 1e-6·m.
mod level;
mod root;

pub use super::shape::{MeshError, Shape, StarShape};

use super::overlap::inside_term;
use level::{Level, Polylines, Pose};
use nalgebra::{Isometry2, Vector2};
use rayon::prelude::*;
use root::{PerVertex, ROOT_VALUE_MM, VertexSets, keep, min_of, root_pruned};
use serde::{Deserialize, Serialize};
use std::f64::consts::{PI, TAU};

/// Simplification of the medium copy, in modules.
const MEDIUM_TOL: f64 = 1e-4;

/// The driver positions a mesh check rolls through.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[non_exhaustive]
pub enum MeshSpan {
    /// Whole driver turns from φ = 0 (a closed pair with turn ratio p/q is back at its start after
    /// q turns): positions `φ_k = 2π·turns·k/steps`.
    Turns(u32),
    /// An open sector's active driver interval, rad, both ends checked:
    /// `φ_k = start + (end − start)·k/(steps − 1)`.
    Interval {
        /// First driver angle, rad.
        start_rad: f64,
        /// Last driver angle, rad (> start).
        end_rad: f64,
    },
}

impl MeshSpan {
    /// Driver angle of position `k` of `steps`, rad.
    #[must_use]
    pub fn position_rad(&self, k: usize, steps: usize) -> f64 {
        match *self {
            Self::Turns(n) => TAU * f64::from(n) * k as f64 / steps as f64,
            Self::Interval { start_rad, end_rad } => {
                start_rad + (end_rad - start_rad) * k as f64 / (steps.max(2) - 1) as f64
            }
        }
    }
}

/// Parameters of [`verify_mesh`]; [`MeshCheck::new`] fills the defaults named on each field.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[non_exhaustive]
pub struct MeshCheck {
    /// Centre distance, mm (no default: given to [`MeshCheck::new`]).
    pub centre_distance_mm: f64,
    /// Number of driver positions over the span. Default 90 (every 4° of one turn).
    pub steps: usize,
    /// The driver positions rolled through. Default one turn, [`MeshSpan::Turns`]`(1)`.
    pub span: MeshSpan,
    /// Nominal circumferential backlash of the pair on the pitch curve, mm (> 0). Default 0.04·m.
    pub backlash_mm: f64,
    /// Module, mm (sets the contact window; no default: given to [`MeshCheck::new`]).
    pub module_mm: f64,
    /// Root-finding tolerance on δ, rad. Default 1e-13.
    pub angle_tol_rad: f64,
}

impl MeshCheck {
    /// A check of a pair at `centre_distance_mm` with teeth of `module_mm`; the other fields at
    /// their defaults.
    #[must_use]
    pub fn new(centre_distance_mm: f64, module_mm: f64) -> Self {
        Self {
            centre_distance_mm,
            steps: 90,
            span: MeshSpan::Turns(1),
            backlash_mm: 0.04 * module_mm,
            module_mm,
            angle_tol_rad: 1e-13,
        }
    }
}

/// Result of [`verify_mesh`] (all over the sampled cycle).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MeshReport {
    /// Driver positions checked.
    pub steps: usize,
    /// Positions with interference (no contact-free position of the driven gear).
    pub interference_steps: usize,
    /// Largest penetration found at the working contact position, mm (0 = none).
    pub max_penetration_mm: f64,
    /// Minimum clearance at the nominal position (ψ from the law), mm; ≈ 0 at the working contact.
    pub min_nominal_clearance_mm: f64,
    /// Minimum backlash on the pitch curve over the cycle, mm.
    pub min_backlash_mm: f64,
    /// Maximum backlash on the pitch curve over the cycle, mm.
    pub max_backlash_mm: f64,
    /// Largest overlap (interference) area of the two outlines at the motion law's position
    /// (driven angle `ψ(φ)`, no correction), over the teeth within ±1.75 pitches of the contact,
    /// mm² (0 = the outlines do not overlap; ~1e-9 mm² is the transmission error's touch).
    pub max_overlap_area_mm2: f64,
    /// Driver angle of the largest overlap, degrees (may exceed 360 when several turns are rolled).
    pub max_overlap_at_deg: f64,
    /// Maximum |transmission error| of the driven gear, degrees.
    pub max_transmission_error_deg: f64,
    /// Peak-to-peak transmission error, degrees.
    pub transmission_error_p2p_deg: f64,
}

impl MeshReport {
    /// One-line human summary (interference, overlap, backlash range, transmission error).
    #[must_use]
    pub fn summary(&self) -> String {
        format!(
            "{} interference steps of {}, max overlap {:.3e} mm², backlash {:.4}..{:.4} mm, \
             max transmission error {:.2e}°",
            self.interference_steps,
            self.steps,
            self.max_overlap_area_mm2,
            self.min_backlash_mm,
            self.max_backlash_mm,
            self.max_transmission_error_deg
        )
    }
}

struct Sample {
    overlap: f64,
    eps: f64,
    coast: f64,
    nominal: f64,
    r2: f64,
    interference: bool,
    penetration: f64,
}

impl Sample {
    /// A position without a contact-free driven angle.
    fn interference(overlap: f64, nominal: f64, r2: f64, penetration: f64) -> Self {
        Self {
            overlap,
            eps: 0.0,
            coast: 0.0,
            nominal,
            r2,
            interference: true,
            penetration,
        }
    }
}

/// Rolls `driver` (gear 1) and `driven` (gear 2) outlines (mm, CCW, body frames) through the
/// check's span (one driver turn by default) with the motion law `psi(φ)` (driven CW rotation,
/// rad).
///
/// `progress(1)` is called after each driver position.
///
/// Complexity: O(steps · window vertices · root iterations); parallel over steps (rayon),
/// deterministic.
pub fn verify_mesh(
    driver: &[[f64; 2]],
    driven: &[[f64; 2]],
    psi: &(dyn Fn(f64) -> f64 + Sync),
    check: &MeshCheck,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<MeshReport, MeshError> {
    for (name, v) in [
        ("centre_distance_mm", check.centre_distance_mm),
        ("backlash_mm", check.backlash_mm),
        ("module_mm", check.module_mm),
        ("angle_tol_rad", check.angle_tol_rad),
    ] {
        if !(v.is_finite() && v > 0.0) {
            return Err(MeshError::InvalidParameter {
                name,
                value: v,
                expected: "finite and > 0",
            });
        }
    }
    if check.steps == 0 {
        return Err(MeshError::InvalidParameter {
            name: "steps",
            value: 0.0,
            expected: "≥ 1",
        });
    }
    match check.span {
        MeshSpan::Turns(0) => {
            return Err(MeshError::InvalidParameter {
                name: "span",
                value: 0.0,
                expected: "at least one driver turn",
            });
        }
        MeshSpan::Interval { start_rad, end_rad }
            if !(start_rad.is_finite() && end_rad.is_finite() && end_rad > start_rad)
                || check.steps < 2 =>
        {
            return Err(MeshError::InvalidParameter {
                name: "span",
                value: end_rad - start_rad,
                expected: "a finite interval end > start, checked at ≥ 2 steps",
            });
        }
        _ => {}
    }
    let a = check.centre_distance_mm;
    let m = check.module_mm;
    let cap = 0.02 * m;
    // The given outlines, and the copies their blocks are bounded through (also within reach of
    // the medium copy, MEDIUM_TOL·m from the given outlines).
    let given = Polylines {
        driver: driver.to_vec(),
        driven: driven.to_vec(),
        deviation_mm: 0.0,
    };
    let bounds = given.bound_copies(m, MEDIUM_TOL * m);
    let fine = Level::new(&given, &bounds, cap, m, check.backlash_mm)?;
    // A copy simplified to MEDIUM_TOL·m brackets a contact where the secant steps on the given
    // outlines do not reach it; built on first need (most checks never need it). Its gap from
    // the given outlines bounds |f_fine − f_medium|. A copy that could not be indexed (fewer
    // than three vertices; not met from indexed given outlines) leaves the bracketed search to
    // the given outlines.
    let medium_level = std::sync::OnceLock::new();
    let medium = || {
        medium_level
            .get_or_init(|| {
                let lines = Polylines::new(driver, driven, MEDIUM_TOL * m);
                Level::new(&lines, &bounds, cap, m, check.backlash_mm).ok()
            })
            .as_ref()
    };
    let g1 = &fine.h1.polar;
    let lip = fine.lip;
    let sample = |k: usize| {
        let phi = check.span.position_rad(k, check.steps);
        let psi0 = psi(phi);
        let r1 = g1.radius_at(-phi);
        let r2 = (a - r1).max(m);
        // Candidate vertices near the contact (±1.75 pitches), pruned by the block bounds.
        let w1 = (1.75 * PI * m / r1).min(PI);
        let w2 = (1.75 * PI * m / r2).min(PI);
        let db = check.backlash_mm / r2;
        let pose = Pose { phi, psi0, a };
        // Block bounds of this pose, reused across the driven offsets.
        let fine_cache = fine.bound_cache();
        let sets = fine.candidates(&pose, w1, w2, &fine_cache);
        let f = |d: f64, s1: &[usize], s2: &[usize]| {
            fine.eval_bounded(&pose, d, s1, s2, f64::NEG_INFINITY, &fine_cache)
        };
        // The law's position δ = 0: every candidate's clearance (nominal clearance, overlap
        // edges, and the pruning of the working-contact search).
        // Exact below the longest edge (the overlap's edges), bounded above it: a vertex whose
        // distance exceeds the longest edge has both its edges outside the other outline.
        let edge = fine.h1.max_edge.max(fine.h2.max_edge);
        let v0 = fine.eval_bounded(&pose, 0.0, &sets.0, &sets.1, edge, &fine_cache);
        let nominal = min_of(&v0);
        // Overlap area at δ = 0 (world frame), over the edges that can reach into the other gear:
        // an edge with a point inside it has an end inside or within one edge length of it.
        let near_edges = |h: &Shape, set: &[usize], c: &[f64]| {
            let n = h.pts.len();
            let mut e: Vec<usize> = set
                .iter()
                .zip(c)
                .filter(|(_, c)| **c < h.max_edge)
                .flat_map(|(&i, _)| {
                    let j = h.polar.orig[i] as usize;
                    [(j + n - 1) % n, j]
                })
                .collect();
            e.sort_unstable();
            e.dedup();
            e
        };
        let to_world1 = Isometry2::new(Vector2::zeros(), phi);
        let to_world2 = Isometry2::new(Vector2::new(a, 0.0), -psi0);
        let overlap = inside_term(
            &fine.h1,
            &near_edges(&fine.h1, &sets.0, &v0.0),
            &(to_world2.inverse() * to_world1),
            &to_world1,
            &fine.h2,
        ) + inside_term(
            &fine.h2,
            &near_edges(&fine.h2, &sets.1, &v0.1),
            &(to_world1.inverse() * to_world2),
            &to_world2,
            &fine.h1,
        );
        // Is there a free position? The fine clearance at the middle of the backlash range,
        // decided by the block bounds (its value only when it is not positive).
        let mid = 0.5 * db;
        if fine.any_at_most(&pose, mid, &sets.0, &sets.1, 0.0, &fine_cache) {
            let fmid = min_of(&f(mid, &sets.0, &sets.1));
            return Sample::interference(overlap, nominal, r2, -fmid);
        }
        // The medium level of this pose, on first need: its candidates, bounds and clearances.
        let medium_pose = std::cell::OnceCell::new();
        let medium_pose = || {
            medium_pose
                .get_or_init(|| {
                    medium().map(|level| {
                        let cache = level.bound_cache();
                        let sets = level.candidates(&pose, w1, w2, &cache);
                        (level, sets, cache)
                    })
                })
                .as_ref()
        };
        let tol = check.angle_tol_rad;
        // Root on [lo, hi]: the medium root x, then the fine root within ±η of it (η from the
        // polylines' gap over a clearance slope ≥ r₂/2), widening ×8 when the bracket misses.
        // Vertices are pruned from a known evaluation (at 0, or at x) by the Lipschitz bound:
        // vertex i can be the minimiser on [l, h] only if c_i(x₀) ≤ min c(x₀) + 2·lip·max|y − x₀|.
        // Secant steps on the fine outlines from a known evaluation `v` at `x0` and a slope: each
        // point's minimum is exact on the vertices the Lipschitz bound keeps from `v` — or, for
        // a point no farther from `x0` than the last point whose set came from `v` (that set
        // holds every vertex `v` keeps for it), from that point's evaluation, a narrower set;
        // a point with |f| ≤ ROOT_VALUE_MM inside (lo, hi) is the root (as in `root_pruned`).
        // None when `steps` steps do not get there (the bracketed search then runs).
        let secant = |x0: f64, v: &PerVertex, slope: f64, lo: f64, hi: f64, steps: usize| {
            let (mut xa, mut fa) = (x0, min_of(v));
            let mut s = slope;
            let mut wide: Option<(f64, VertexSets, PerVertex)> = None;
            for _ in 0..steps {
                if !(s.is_finite() && s != 0.0) {
                    return None;
                }
                let xb = xa - fa / s;
                if !(xb > lo && xb < hi) {
                    return None;
                }
                let fb = match &wide {
                    Some((xw, sw, vw)) if (xb - x0).abs() <= (xw - x0).abs() => {
                        let thresh = min_of(vw) + 2.0 * lip * (xb - xw).abs();
                        let (s1, s2) = (keep(&sw.0, &vw.0, thresh), keep(&sw.1, &vw.1, thresh));
                        min_of(&f(xb, &s1, &s2))
                    }
                    _ => {
                        let thresh = min_of(v) + 2.0 * lip * (xb - x0).abs();
                        let set = (keep(&sets.0, &v.0, thresh), keep(&sets.1, &v.1, thresh));
                        let vb = f(xb, &set.0, &set.1);
                        let fb = min_of(&vb);
                        wide = Some((xb, set, vb));
                        fb
                    }
                };
                if fb.abs() <= ROOT_VALUE_MM {
                    return Some(xb);
                }
                s = (fb - fa) / (xb - xa);
                (xa, fa) = (xb, fb);
            }
            None
        };
        let polish = |lo: f64, hi: f64| -> Option<f64> {
            let medium_root = medium_pose().and_then(|(level, med_sets, cache)| {
                let fm = |d: f64, s1: &[usize], s2: &[usize]| {
                    level.eval_bounded(&pose, d, s1, s2, f64::NEG_INFINITY, cache)
                };
                let dev = level.deviation_mm;
                root_pruned(&fm, &med_sets.0, &med_sets.1, lo, hi, lip, 1e-3 * db)
                    .map(|(x, slope)| (x, slope, dev))
            });
            if let Some((x, slope, dev)) = medium_root {
                let mut eta = (4.0 * dev / (0.5 * r2)).max(1e-4 * db);
                // The fine evaluation to start from: δ = 0 (known) when x is that close to it.
                let near_zero = |l: f64, h: f64| l.abs().max(h.abs()) <= 2.0 * (h - l);
                let mut at_x: Option<PerVertex> = None;
                let (x0, v) = if near_zero((x - eta).max(lo), (x + eta).min(hi)) {
                    (0.0, &v0)
                } else {
                    (x, &*at_x.get_or_insert_with(|| f(x, &sets.0, &sets.1)))
                };
                if let Some(r) = secant(x0, v, slope, lo, hi, 3) {
                    return Some(r);
                }
                while eta < hi - lo {
                    let (l, h) = ((x - eta).max(lo), (x + eta).min(hi));
                    let (x0, v) = if near_zero(l, h) {
                        (0.0, &v0)
                    } else {
                        (x, &*at_x.get_or_insert_with(|| f(x, &sets.0, &sets.1)))
                    };
                    let thresh = min_of(v) + 2.0 * lip * (l - x0).abs().max((h - x0).abs());
                    let (s1, s2) = (keep(&sets.0, &v.0, thresh), keep(&sets.1, &v.1, thresh));
                    if let Some((r, _)) = root_pruned(&f, &s1, &s2, l, h, lip, tol) {
                        return Some(r);
                    }
                    eta *= 8.0;
                }
            }
            root_pruned(&f, &sets.0, &sets.1, lo, hi, lip, tol).map(|(r, _)| r)
        };
        // The contacts without the medium level's brackets where secant steps get there: the
        // working contact is within a rounding of the law's position on a conjugate pair, so
        // the steps start from δ = 0 (evaluated), and the coast contact about one nominal
        // backlash beyond it, with the slope of a contact on the driven pitch curve under a 20°
        // pressure angle (positive on the working flanks, negative on the coast ones).
        let slope = r2 * 20f64.to_radians().cos();
        // Six steps from a guessed slope (three from the medium level's measured one): enough
        // for a 2× slope error to converge to |f| ≤ 1e-11 mm on the bundled pairs; a miss falls
        // back to the bracketed search, so the count sets cost, not the verdict.
        let Some(eps) = secant(0.0, &v0, slope, -db, mid, 6).or_else(|| polish(-db, mid)) else {
            return Sample::interference(overlap, nominal, r2, 0.0);
        };
        let guess = eps + db;
        let coast = if guess > mid && guess < 3.0 * db {
            let v = f(guess, &sets.0, &sets.1);
            secant(guess, &v, -slope, mid, 3.0 * db, 6)
        } else {
            None
        };
        let (eps, coast) = match (Some(eps), coast.or_else(|| polish(mid, 3.0 * db))) {
            (Some(e), Some(c)) => (e, c),
            _ => return Sample::interference(overlap, nominal, r2, 0.0),
        };
        Sample {
            overlap,
            eps,
            coast,
            nominal,
            r2,
            interference: false,
            penetration: 0.0,
        }
    };
    let samples: Vec<Sample> = (0..check.steps)
        .into_par_iter()
        .map(|k| {
            let s = sample(k);
            progress(1);
            s
        })
        .collect();
    let ok: Vec<&Sample> = samples.iter().filter(|s| !s.interference).collect();
    let te: Vec<f64> = ok.iter().map(|s| s.eps).collect();
    let bl: Vec<f64> = ok.iter().map(|s| (s.coast - s.eps) * s.r2).collect();
    let max = |v: &[f64]| v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let min = |v: &[f64]| v.iter().copied().fold(f64::INFINITY, f64::min);
    let (k_max, max_overlap) = samples
        .iter()
        .enumerate()
        .fold((0, 0.0f64), |(kb, vb), (k, s)| {
            if s.overlap > vb {
                (k, s.overlap)
            } else {
                (kb, vb)
            }
        });
    Ok(MeshReport {
        steps: check.steps,
        max_overlap_area_mm2: max_overlap,
        max_overlap_at_deg: check.span.position_rad(k_max, check.steps).to_degrees(),
        interference_steps: samples.len() - ok.len(),
        max_penetration_mm: samples.iter().map(|s| s.penetration).fold(0.0, f64::max),
        min_nominal_clearance_mm: samples
            .iter()
            .map(|s| s.nominal)
            .fold(f64::INFINITY, f64::min),
        min_backlash_mm: min(&bl),
        max_backlash_mm: max(&bl),
        max_transmission_error_deg: te.iter().fold(0.0f64, |a, e| a.max(e.abs())).to_degrees(),
        transmission_error_p2p_deg: (max(&te) - min(&te)).max(0.0).to_degrees(),
    })
}
