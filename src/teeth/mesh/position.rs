//! One driver position of the mesh check: the clearance levels it reads (the given outlines, and
//! the medium copy built on first need), the nominal clearance and overlap at the law's position,
//! and the working and coast contacts (secant steps, else the bracketed search).
use super::level::{BoundCache, Level, Polylines, Pose};
use super::root::{PerVertex, ROOT_VALUE_MM, VertexSets, keep, min_of, root_pruned};
use super::{MeshCheck, MeshError, Shape};
use crate::math::Point;
use crate::teeth::overlap::inside_term;
use nalgebra::{Isometry2, Vector2};
use std::cell::OnceCell;
use std::f64::consts::PI;
use std::sync::OnceLock;

/// Simplification of the medium copy, in modules.
const MEDIUM_TOL: f64 = 1e-4;

/// What one driver position gives the report.
pub(super) struct Sample {
    pub(super) overlap: f64,
    pub(super) eps: f64,
    pub(super) coast: f64,
    pub(super) nominal: f64,
    pub(super) r2: f64,
    pub(super) interference: bool,
    pub(super) penetration: f64,
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

/// The levels every position reads: the given outlines (with the copies their blocks are bounded
/// through) and the medium copy, built on first need.
pub(super) struct Levels<'a> {
    driver: &'a [Point],
    driven: &'a [Point],
    check: &'a MeshCheck,
    cap: f64,
    bounds: Polylines,
    fine: Level,
    medium: OnceLock<Option<Level>>,
}

impl<'a> Levels<'a> {
    /// Indexes the given outlines, and the copies their blocks are bounded through (also within
    /// reach of the medium copy, MEDIUM_TOL·m from the given outlines).
    pub(super) fn new(
        driver: &'a [Point],
        driven: &'a [Point],
        check: &'a MeshCheck,
    ) -> Result<Self, MeshError> {
        let m = check.module_mm;
        let cap = 0.02 * m;
        let given = Polylines {
            driver: driver.to_vec(),
            driven: driven.to_vec(),
            deviation_mm: 0.0,
        };
        let bounds = given.bound_copies(m, MEDIUM_TOL * m);
        let fine = Level::new(&given, &bounds, cap, m, check.backlash_mm)?;
        Ok(Self {
            driver,
            driven,
            check,
            cap,
            bounds,
            fine,
            medium: OnceLock::new(),
        })
    }

    /// A copy simplified to MEDIUM_TOL·m brackets a contact where the secant steps on the given
    /// outlines do not reach it; built on first need (most checks never need it). Its gap from
    /// the given outlines bounds |f_fine − f_medium|. A copy that could not be indexed (fewer
    /// than three vertices; not met from indexed given outlines) leaves the bracketed search to
    /// the given outlines.
    fn medium(&self) -> Option<&Level> {
        self.medium
            .get_or_init(|| {
                let m = self.check.module_mm;
                let lines = Polylines::new(self.driver, self.driven, MEDIUM_TOL * m);
                Level::new(&lines, &self.bounds, self.cap, m, self.check.backlash_mm).ok()
            })
            .as_ref()
    }

    /// Driver position `k` of the check's span under the law `psi`: the nominal clearance and
    /// overlap at δ = 0, then a free position and the working and coast contacts.
    pub(super) fn sample(&self, k: usize, psi: &(dyn Fn(f64) -> f64 + Sync)) -> Sample {
        let at = self.position(k, psi);
        let nominal = min_of(&at.v0);
        let overlap = at.overlap();
        // Is there a free position? The fine clearance at the middle of the backlash range,
        // decided by the block bounds (its value only when it is not positive).
        let mid = 0.5 * at.db;
        let (sets, cache) = (&at.sets, &at.cache);
        if self
            .fine
            .any_at_most(&at.pose, mid, &sets.0, &sets.1, 0.0, cache)
        {
            let fmid = min_of(&at.f(mid, &sets.0, &sets.1));
            return Sample::interference(overlap, nominal, at.r2, -fmid);
        }
        let Some((eps, coast)) = at.contacts(mid) else {
            return Sample::interference(overlap, nominal, at.r2, 0.0);
        };
        Sample {
            overlap,
            eps,
            coast,
            nominal,
            r2: at.r2,
            interference: false,
            penetration: 0.0,
        }
    }

    /// The pose of position `k`, its candidate vertices near the contact (±1.75 pitches, pruned
    /// by the block bounds) and every candidate's clearance at the law's position δ = 0.
    fn position(&self, k: usize, psi: &(dyn Fn(f64) -> f64 + Sync)) -> Position<'_> {
        let check = self.check;
        let (a, m) = (check.center_distance_mm, check.module_mm);
        let fine = &self.fine;
        let phi = check.span.position_rad(k, check.steps);
        let psi0 = psi(phi);
        let r1 = fine.h1.polar.radius_at(-phi);
        let r2 = (a - r1).max(m);
        // Candidate vertices near the contact (±1.75 pitches), pruned by the block bounds.
        let w1 = (1.75 * PI * m / r1).min(PI);
        let w2 = (1.75 * PI * m / r2).min(PI);
        let db = check.backlash_mm / r2;
        let pose = Pose { phi, psi0, a };
        // Block bounds of this pose, reused across the driven offsets.
        let cache = fine.bound_cache();
        let sets = fine.candidates(&pose, w1, w2, &cache);
        // The law's position δ = 0: every candidate's clearance (nominal clearance, overlap
        // edges, and the pruning of the working-contact search).
        // Exact below the longest edge (the overlap's edges), bounded above it: a vertex whose
        // distance exceeds the longest edge has both its edges outside the other outline.
        let edge = fine.h1.max_edge.max(fine.h2.max_edge);
        let v0 = fine.eval_bounded(&pose, 0.0, &sets.0, &sets.1, edge, &cache);
        Position {
            levels: self,
            pose,
            w1,
            w2,
            r2,
            db,
            cache,
            sets,
            v0,
            medium: OnceCell::new(),
        }
    }
}

/// The medium level of one pose: the level, its candidates and its block bounds.
type MediumPose<'a> = (&'a Level, VertexSets, BoundCache);

/// One driver position on the given outlines: its pose, candidates, block bounds and the
/// clearances at δ = 0; the medium level of this pose on first need.
struct Position<'a> {
    levels: &'a Levels<'a>,
    pose: Pose,
    w1: f64,
    w2: f64,
    r2: f64,
    db: f64,
    cache: BoundCache,
    sets: VertexSets,
    v0: PerVertex,
    medium: OnceCell<Option<MediumPose<'a>>>,
}

/// The edges of `h` that can reach into the other gear, from the clearances `c` of the vertices
/// `set`: an edge with a point inside it has an end inside or within one edge length of it.
fn near_edges(h: &Shape, set: &[usize], c: &[f64]) -> Vec<usize> {
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
}

impl<'a> Position<'a> {
    /// Per-vertex clearances on the given outlines at driven offset `d`, for the vertices `s1`,
    /// `s2`.
    fn f(&self, d: f64, s1: &[usize], s2: &[usize]) -> PerVertex {
        let fine = &self.levels.fine;
        fine.eval_bounded(&self.pose, d, s1, s2, f64::NEG_INFINITY, &self.cache)
    }

    /// Overlap area at δ = 0 (world frame), over the edges that can reach into the other gear.
    fn overlap(&self) -> f64 {
        let fine = &self.levels.fine;
        let Pose { phi, psi0, a } = self.pose;
        let to_world1 = Isometry2::new(Vector2::zeros(), phi);
        let to_world2 = Isometry2::new(Vector2::new(a, 0.0), -psi0);
        inside_term(
            &fine.h1,
            &near_edges(&fine.h1, &self.sets.0, &self.v0.0),
            &(to_world2.inverse() * to_world1),
            &to_world1,
            &fine.h2,
        ) + inside_term(
            &fine.h2,
            &near_edges(&fine.h2, &self.sets.1, &self.v0.1),
            &(to_world1.inverse() * to_world2),
            &to_world2,
            &fine.h1,
        )
    }

    /// The medium level of this pose, on first need: its candidates, bounds and clearances.
    fn medium_pose(&self) -> Option<&MediumPose<'a>> {
        self.medium
            .get_or_init(|| {
                self.levels.medium().map(|level| {
                    let cache = level.bound_cache();
                    let sets = level.candidates(&self.pose, self.w1, self.w2, &cache);
                    (level, sets, cache)
                })
            })
            .as_ref()
    }

    /// The contacts without the medium level's brackets where secant steps get there: the
    /// working contact ε and the coast contact beyond `mid`; `None` when either is missing.
    fn contacts(&self, mid: f64) -> Option<(f64, f64)> {
        let db = self.db;
        // The working contact is within a rounding of the law's position on a conjugate pair, so
        // the steps start from δ = 0 (evaluated), and the coast contact about one nominal
        // backlash beyond it, with the slope of a contact on the driven pitch curve under a 20°
        // pressure angle (positive on the working flanks, negative on the coast ones).
        let slope = self.r2 * 20f64.to_radians().cos();
        // Six steps from a guessed slope (three from the medium level's measured one): enough
        // for a 2× slope error to converge to |f| ≤ 1e-11 mm on the bundled pairs; a miss falls
        // back to the bracketed search, so the count sets cost, not the verdict.
        let eps = self
            .secant(0.0, &self.v0, slope, -db, mid, 6)
            .or_else(|| self.polish(-db, mid))?;
        let guess = eps + db;
        let coast = if guess > mid && guess < 3.0 * db {
            let v = self.f(guess, &self.sets.0, &self.sets.1);
            self.secant(guess, &v, -slope, mid, 3.0 * db, 6)
        } else {
            None
        };
        let coast = coast.or_else(|| self.polish(mid, 3.0 * db))?;
        Some((eps, coast))
    }

    /// Secant steps on the fine outlines from a known evaluation `v` at `x0` and a slope: each
    /// point's minimum is exact on the vertices the Lipschitz bound keeps from `v` — or, for
    /// a point no farther from `x0` than the last point whose set came from `v` (that set
    /// holds every vertex `v` keeps for it), from that point's evaluation, a narrower set;
    /// a point with |f| ≤ ROOT_VALUE_MM inside (lo, hi) is the root (as in `root_pruned`).
    /// None when `steps` steps do not get there (the bracketed search then runs).
    fn secant(
        &self,
        x0: f64,
        v: &PerVertex,
        slope: f64,
        lo: f64,
        hi: f64,
        steps: usize,
    ) -> Option<f64> {
        let (lip, sets) = (self.levels.fine.lip, &self.sets);
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
                    min_of(&self.f(xb, &s1, &s2))
                }
                _ => {
                    let thresh = min_of(v) + 2.0 * lip * (xb - x0).abs();
                    let set = (keep(&sets.0, &v.0, thresh), keep(&sets.1, &v.1, thresh));
                    let vb = self.f(xb, &set.0, &set.1);
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
    }

    /// Root on [lo, hi]: the medium root x, then the fine root within ±η of it (η from the
    /// polylines' gap over a clearance slope ≥ r₂/2), widening ×8 when the bracket misses.
    /// Vertices are pruned from a known evaluation (at 0, or at x) by the Lipschitz bound:
    /// vertex i can be the minimiser on [l, h] only if c_i(x₀) ≤ min c(x₀) + 2·lip·max|y − x₀|.
    fn polish(&self, lo: f64, hi: f64) -> Option<f64> {
        let (lip, db, sets) = (self.levels.fine.lip, self.db, &self.sets);
        let tol = self.levels.check.angle_tol_rad;
        let f = |d: f64, s1: &[usize], s2: &[usize]| self.f(d, s1, s2);
        let medium_root = self.medium_pose().and_then(|(level, med_sets, cache)| {
            let fm = |d: f64, s1: &[usize], s2: &[usize]| {
                level.eval_bounded(&self.pose, d, s1, s2, f64::NEG_INFINITY, cache)
            };
            let dev = level.deviation_mm;
            root_pruned(&fm, [&med_sets.0, &med_sets.1], [lo, hi], lip, 1e-3 * db)
                .map(|(x, slope)| (x, slope, dev))
        });
        if let Some((x, slope, dev)) = medium_root {
            let mut eta = (4.0 * dev / (0.5 * self.r2)).max(1e-4 * db);
            // The fine evaluation to start from: δ = 0 (known) when x is that close to it.
            let near_zero = |l: f64, h: f64| l.abs().max(h.abs()) <= 2.0 * (h - l);
            let mut at_x: Option<PerVertex> = None;
            let (x0, v) = if near_zero((x - eta).max(lo), (x + eta).min(hi)) {
                (0.0, &self.v0)
            } else {
                (x, &*at_x.get_or_insert_with(|| f(x, &sets.0, &sets.1)))
            };
            if let Some(r) = self.secant(x0, v, slope, lo, hi, 3) {
                return Some(r);
            }
            while eta < hi - lo {
                let (l, h) = ((x - eta).max(lo), (x + eta).min(hi));
                let (x0, v) = if near_zero(l, h) {
                    (0.0, &self.v0)
                } else {
                    (x, &*at_x.get_or_insert_with(|| f(x, &sets.0, &sets.1)))
                };
                let thresh = min_of(v) + 2.0 * lip * (l - x0).abs().max((h - x0).abs());
                let (s1, s2) = (keep(&sets.0, &v.0, thresh), keep(&sets.1, &v.1, thresh));
                if let Some((r, _)) = root_pruned(&f, [&s1, &s2], [l, h], lip, tol) {
                    return Some(r);
                }
                eta *= 8.0;
            }
        }
        root_pruned(&f, [&sets.0, &sets.1], [lo, hi], lip, tol).map(|(r, _)| r)
    }
}
