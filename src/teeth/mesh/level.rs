//! One resolution of the mesh check: both outlines indexed, the candidate vertices near the
//! contact, per-vertex clearances at a driven offset, and the pruned root search on them.
use crate::teeth::shape::{MeshError, Shape};
use std::f64::consts::PI;

/// Driver angle `phi`, law angle `psi0` (rad) and centre distance `a` (mm) of one position.
pub(super) struct Pose {
    pub(super) phi: f64,
    pub(super) psi0: f64,
    pub(super) a: f64,
}

/// Both outlines at one resolution: exact shapes, a coarse copy for the first pruning, and the
/// Lipschitz constant of the clearances in δ.
pub(super) struct Level {
    pub(super) h1: Shape,
    pub(super) h2: Shape,
    pub(super) k1: Shape,
    pub(super) k2: Shape,
    pub(super) reach: f64,
    pub(super) lip: f64,
    pub(super) module_mm: f64,
    /// Bounding circles (body-frame centre, radius, mm) of the blocks of `block` consecutive
    /// polar entries of `h1`, `h2`.
    blocks1: Vec<([f64; 2], f64)>,
    blocks2: Vec<([f64; 2], f64)>,
    /// Polar entries per block (about 0.1·m of outline).
    block: usize,
    /// Copies simplified to `BOUND_TOL·m` (Douglas–Peucker), indexed at `reach`: their
    /// clearances bound the exact ones below for the bounded evaluation.
    b1: Shape,
    b2: Shape,
    /// Slack of a `b1`/`b2` clearance as a lower bound of the exact one, mm: 3× the Hausdorff
    /// distance of the two polylines (a point between them is within it of both), plus a
    /// rounding margin.
    slack: f64,
    /// Hausdorff bound of these polylines from the given outlines, mm (the simplification's
    /// largest vertex-to-chord distance; 0 when not simplified).
    pub(super) deviation_mm: f64,
}

/// Simplification of the bounding copies, in modules.
const BOUND_TOL: f64 = 2e-3;

/// Bounding circles of the blocks of `block` consecutive polar entries.
fn block_circles(g: &crate::teeth::shape::StarShape, block: usize) -> Vec<([f64; 2], f64)> {
    let n = g.r.len();
    (0..n.div_ceil(block))
        .map(|b| {
            let pts: Vec<[f64; 2]> = (b * block..((b + 1) * block).min(n))
                .map(|i| g.point(i))
                .collect();
            let (lo, hi) =
                pts.iter()
                    .fold(([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]), |(l, h), p| {
                        (
                            [l[0].min(p[0]), l[1].min(p[1])],
                            [h[0].max(p[0]), h[1].max(p[1])],
                        )
                    });
            let c = [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])];
            let r = pts
                .iter()
                .map(|p| (p[0] - c[0]).hypot(p[1] - c[1]))
                .fold(0.0, f64::max);
            (c, r)
        })
        .collect()
}

/// The outlines of one resolution: both polylines (mm) and their Hausdorff distance from the
/// given outlines (mm; 0 for the given outlines themselves).
pub(super) struct Polylines {
    pub(super) driver: Vec<[f64; 2]>,
    pub(super) driven: Vec<[f64; 2]>,
    pub(super) deviation_mm: f64,
}

impl Polylines {
    /// Both outlines simplified to `simplify_mm` (Douglas–Peucker, side by side; 0 = as given).
    pub(super) fn new(driver: &[[f64; 2]], driven: &[[f64; 2]], simplify_mm: f64) -> Self {
        let thin = |v: &[[f64; 2]]| {
            if simplify_mm > 0.0 {
                crate::math::polyline::simplify_closed_dev(v, simplify_mm)
            } else {
                (v.to_vec(), 0.0)
            }
        };
        let ((d1, e1), (d2, e2)) = rayon::join(|| thin(driver), || thin(driven));
        Self {
            driver: d1,
            driven: d2,
            deviation_mm: e1.max(e2),
        }
    }

    /// The copies the bounded evaluation bounds through: simplified to `BOUND_TOL·m − deviation`,
    /// so that they are within `BOUND_TOL·m` of the given outlines and of these polylines (a
    /// coarse simplification of an already simplified outline costs little).
    pub(super) fn bound_copies(&self, module_mm: f64) -> Polylines {
        // The medium copy's tolerance (1e-4·m) is far below BOUND_TOL·m.
        debug_assert!(self.deviation_mm < 0.5 * BOUND_TOL * module_mm);
        let tol = BOUND_TOL * module_mm - self.deviation_mm;
        let (b1, b2) = rayon::join(
            || crate::math::polyline::simplify_closed(&self.driver, tol),
            || crate::math::polyline::simplify_closed(&self.driven, tol),
        );
        Polylines {
            driver: b1,
            driven: b2,
            deviation_mm: BOUND_TOL * module_mm,
        }
    }
}

impl Level {
    /// One resolution of the check on `lines`, with the bounding copies `bounds` (within
    /// `BOUND_TOL·m` of `lines`, see [`Polylines::bound_copies`]), for teeth of `module_mm` with
    /// the pair's nominal backlash `backlash_mm`.
    pub(super) fn new(
        lines: &Polylines,
        bounds: &Polylines,
        cap: f64,
        module_mm: f64,
        backlash_mm: f64,
    ) -> Result<Self, MeshError> {
        let m = module_mm;
        let every = |v: &[[f64; 2]], k: usize| v.iter().step_by(k).copied().collect::<Vec<_>>();
        let (d1, d2) = (&lines.driver, &lines.driven);
        // The two gears' shapes are independent: built side by side at every stage.
        let (h1, h2) = rayon::join(
            || Shape::new(d1, cap, "driver"),
            || Shape::new(d2, cap, "driven"),
        );
        let (h1, h2) = (h1?, h2?);
        let rmax = h1
            .polar
            .r
            .iter()
            .chain(h2.polar.r.iter())
            .copied()
            .fold(0.0, f64::max);
        let r2min = h2
            .polar
            .r
            .iter()
            .copied()
            .fold(f64::INFINITY, f64::min)
            .max(m);
        let lip = rmax + 2.0 * m;
        let reach = 4.0 * backlash_mm / r2min * lip + 0.05 * m;
        // Coarse copies (every 16th vertex) index the initial pruning at a larger reach.
        // Douglas–Peucker keeps every removed vertex within the tolerance of its chord, so the
        // polylines are within it of each other both ways.
        let coarse_and_bound = |d: &[[f64; 2]], b: &[[f64; 2]], which| {
            rayon::join(
                || Shape::new(&every(d, 16), reach, which),
                || Shape::new(b, reach, which),
            )
        };
        let ((k1, b1), (k2, b2)) = rayon::join(
            || coarse_and_bound(d1, &bounds.driver, "driver"),
            || coarse_and_bound(d2, &bounds.driven, "driven"),
        );
        let (k1, b1, k2, b2) = (k1?, b1?, k2?, b2?);
        let slack = 3.0 * bounds.deviation_mm + 1e-6 * m;
        // Blocks of about 0.1·m of outline.
        let perimeter: f64 = (0..d1.len())
            .map(|i| {
                let (p, q) = (d1[i], d1[(i + 1) % d1.len()]);
                (q[0] - p[0]).hypot(q[1] - p[1])
            })
            .sum();
        let block = ((0.04 * m * d1.len() as f64 / perimeter).round() as usize).clamp(4, 256);
        Ok(Self {
            blocks1: block_circles(&h1.polar, block),
            blocks2: block_circles(&h2.polar, block),
            block,
            b1,
            b2,
            h1,
            h2,
            k1,
            k2,
            reach,
            lip,
            module_mm: m,
            slack,
            deviation_mm: lines.deviation_mm,
        })
    }

    /// Per-vertex clearances at driven offset δ (rad): gear-1 vertices `set1` against gear 2 and
    /// gear-2 vertices `set2` against gear 1 (polar indices), exact within `cap` — or, for a
    /// vertex whose clearance cannot matter, a lower bound of its unclipped signed distance that
    /// exceeds both `floor` and the minimum. The blocks of `self.block` polar entries are bounded
    /// below through `b1`/`b2` (minus the block radius and `slack`; bounds kept in `cache` and
    /// moved by the block's speed across δ) and evaluated exactly in the order of their bounds
    /// while the bound is ≤ `floor` or below the least exact value so far.
    ///
    /// The minimum is the exact one, bit for bit, and values ≤ `floor` are exact. A bounded value
    /// `b` stands for a clearance ≥ min(`cap`, `b`): a filter `c ≤ t` on the values keeps every
    /// vertex that can reach the minimum for `t` ≥ the minimum (a vertex it drops is at least
    /// `cap` or above `t`), and `c < floor` selects exactly the vertices within `floor` of the
    /// other outline when `floor` < `cap`, or a subset that drops only those farther than `floor`.
    pub(super) fn eval_bounded(
        &self,
        pose: &Pose,
        delta: f64,
        set1: &[usize],
        set2: &[usize],
        floor: f64,
        cache: &BoundCache,
    ) -> PerVertex {
        let (g1, g2) = (&self.h1.polar, &self.h2.polar);
        let (phi, a) = (pose.phi, pose.a);
        let ang2 = pose.psi0 + delta;
        let (sn1, co1) = phi.sin_cos();
        let (sn2, co2) = ang2.sin_cos();
        // Gear-2 body point → gear-1 body frame, and the reverse (the arithmetic of `eval_on`).
        let to1 = |b: [f64; 2]| {
            let w = [co2 * b[0] + sn2 * b[1] + a, -sn2 * b[0] + co2 * b[1]];
            [co1 * w[0] + sn1 * w[1], -sn1 * w[0] + co1 * w[1]]
        };
        let to2 = |b: [f64; 2]| {
            let w = [co1 * b[0] - sn1 * b[1] - a, sn1 * b[0] + co1 * b[1]];
            [co2 * w[0] - sn2 * w[1], sn2 * w[0] + co2 * w[1]]
        };
        // Runs of set entries in one block: (gear, first, end, cache key, bound, fresh). The
        // bound is the block's last one in `cache`, moved by its speed (the distance of its
        // centre from the driven centre, invariant under δ) times |Δδ|, or −∞.
        let mut cache = cache.0.borrow_mut();
        let mut runs: Vec<(u8, usize, usize, usize, f64, bool)> = Vec::new();
        for (gear, set) in [(0u8, set1), (1u8, set2)] {
            let mut s = 0;
            while s < set.len() {
                let b = set[s] / self.block;
                let mut e = s + 1;
                while e < set.len() && set[e] / self.block == b {
                    e += 1;
                }
                let key = if gear == 0 { b } else { self.blocks1.len() + b };
                let (at, lb, speed) = cache[key];
                let (moved, fresh) = if at.is_nan() {
                    (f64::NEG_INFINITY, false)
                } else if at == delta {
                    (lb, true)
                } else {
                    (lb - speed * (delta - at).abs(), false)
                };
                runs.push((gear, s, e, key, moved, fresh));
                s = e;
            }
        }
        runs.sort_by(|x, y| x.4.total_cmp(&y.4));
        let mut v1 = vec![0.0; set1.len()];
        let mut v2 = vec![0.0; set2.len()];
        let mut best = f64::INFINITY;
        let mut done = false;
        for &(gear, s, e, key, moved, fresh) in &runs {
            let v = if gear == 0 {
                &mut v1[s..e]
            } else {
                &mut v2[s..e]
            };
            // Sorted by the moved bounds: once one cannot matter, none of the rest can.
            done = done || (moved > floor && moved >= best);
            if done {
                v.fill(moved);
                continue;
            }
            if !fresh {
                let (lb, speed) = if gear == 0 {
                    let (c, r) = self.blocks1[key];
                    let p = to2(c);
                    (self.b2.clearance(p) - r, p[0].hypot(p[1]))
                } else {
                    let (c, r) = self.blocks2[key - self.blocks1.len()];
                    (self.b1.clearance(to1(c)) - r, c[0].hypot(c[1]))
                };
                let lb = lb - self.slack;
                cache[key] = (delta, lb, speed * (1.0 + 1e-9) + 1e-9 * self.module_mm);
                if lb > floor && lb >= best {
                    v.fill(lb);
                    continue;
                }
            }
            if gear == 0 {
                for (x, &i) in v.iter_mut().zip(&set1[s..e]) {
                    *x = self.h2.clearance(to2(g1.point(i)));
                    best = best.min(*x);
                }
            } else {
                for (x, &i) in v.iter_mut().zip(&set2[s..e]) {
                    *x = self.h1.clearance(to1(g2.point(i)));
                    best = best.min(*x);
                }
            }
        }
        (v1, v2)
    }

    /// An empty cache of block bounds for [`Self::eval_bounded`] at one pose.
    pub(super) fn bound_cache(&self) -> BoundCache {
        BoundCache(std::cell::RefCell::new(vec![
            (f64::NAN, 0.0, 0.0);
            self.blocks1.len()
                + self.blocks2.len()
        ]))
    }

    fn eval_on(
        &self,
        pose: &Pose,
        delta: f64,
        set1: &[usize],
        set2: &[usize],
        s1: &Shape,
        s2: &Shape,
    ) -> PerVertex {
        let (g1, g2) = (&self.h1.polar, &self.h2.polar);
        let (phi, a) = (pose.phi, pose.a);
        let ang2 = pose.psi0 + delta;
        let (sn1, co1) = phi.sin_cos();
        let (sn2, co2) = ang2.sin_cos();
        let v2: Vec<f64> = set2
            .iter()
            .map(|&i| {
                let b = g2.point(i);
                let w = [co2 * b[0] + sn2 * b[1] + a, -sn2 * b[0] + co2 * b[1]];
                s1.clearance([co1 * w[0] + sn1 * w[1], -sn1 * w[0] + co1 * w[1]])
            })
            .collect();
        let v1: Vec<f64> = set1
            .iter()
            .map(|&i| {
                let b = g1.point(i);
                let w = [co1 * b[0] - sn1 * b[1] - a, sn1 * b[0] + co1 * b[1]];
                s2.clearance([co2 * w[0] - sn2 * w[1], sn2 * w[0] + co2 * w[1]])
            })
            .collect();
        (v1, v2)
    }

    /// The vertices (polar indices of both gears) that can touch the other gear for δ in the
    /// backlash range: the contact windows (half-widths `w1`, `w2`, rad), pruned by the coarse
    /// copies (every 16th window vertex; its ±16 neighbours are kept when it is within reach).
    pub(super) fn candidates(&self, pose: &Pose, w1: f64, w2: f64) -> (Vec<usize>, Vec<usize>) {
        let m = self.module_mm;
        let c1 = self.h1.polar.window(-pose.phi, w1);
        let c2 = self.h2.polar.window(PI + pose.psi0, w2);
        let d1: Vec<usize> = c1.iter().step_by(16).copied().collect();
        let d2: Vec<usize> = c2.iter().step_by(16).copied().collect();
        let (p1, p2) = self.eval_on(pose, 0.0, &d1, &d2, &self.k1, &self.k2);
        let expand = |c: &[usize], p: &[f64]| {
            let mut flag = vec![false; c.len()];
            for (j, v) in p.iter().enumerate() {
                if *v < self.reach + 0.1 * m {
                    let lo = (j * 16).saturating_sub(16);
                    let hi = (j * 16 + 17).min(c.len());
                    flag[lo..hi].iter_mut().for_each(|f| *f = true);
                }
            }
            c.iter()
                .zip(flag)
                .filter(|(_, f)| *f)
                .map(|(i, _)| *i)
                .collect::<Vec<usize>>()
        };
        (expand(&c1, &p1), expand(&c2, &p2))
    }
}

/// The last lower bound of each block (driven offset δ, bound mm, speed mm/rad) at one pose:
/// a block's bound at another δ is that bound less speed × |Δδ|.
pub(super) struct BoundCache(std::cell::RefCell<Vec<(f64, f64, f64)>>);

/// Minimum of all per-vertex clearances, mm.
pub(super) fn min_of(v: &PerVertex) -> f64 {
    v.0.iter()
        .chain(v.1.iter())
        .copied()
        .fold(f64::INFINITY, f64::min)
}

pub(super) type PerVertex = (Vec<f64>, Vec<f64>);

/// Per-vertex clearances at a driven offset δ (rad) for two vertex sets.
type ClearanceFn<'a> = dyn Fn(f64, &[usize], &[usize]) -> PerVertex + 'a;

/// A driven offset whose minimum clearance is within this of 0 (mm) is a contact root: far below
/// the backlash and clearances reported (µm); about 2e-12 rad of transmission error at a clearance
/// slope of 6 mm/rad.
pub(super) const ROOT_VALUE_MM: f64 = 1e-11;

/// Root of the minimum clearance on `[lo, hi]` (Illinois regula falsi), to `tol`, pruning after
/// each evaluation the vertices that cannot be the minimiser anywhere in the bracket: a vertex's
/// clearance changes by at most `lip·|Δδ|`, so it is dropped when `c_i(x) > min c(x) + 2·lip·(hi − lo)`.
/// Returns the root and the secant slope (mm/rad) of the last two evaluations.
#[allow(clippy::too_many_arguments)]
pub(super) fn root_pruned(
    f: &ClearanceFn<'_>,
    k1: &[usize],
    k2: &[usize],
    mut lo: f64,
    mut hi: f64,
    lip: f64,
    tol: f64,
) -> Option<(f64, f64)> {
    let mut s1 = k1.to_vec();
    let mut s2 = k2.to_vec();
    let min = |v: &PerVertex| {
        v.0.iter()
            .chain(v.1.iter())
            .copied()
            .fold(f64::INFINITY, f64::min)
    };
    let (mut flo, mut fhi) = (min(&f(lo, &s1, &s2)), min(&f(hi, &s1, &s2)));
    if flo * fhi > 0.0 {
        return None;
    }
    // The last two evaluations (Illinois scales the bracket's values; these are the true ones).
    let mut last = [(lo, flo), (hi, fhi)];
    let slope = |l: &[(f64, f64); 2]| (l[1].1 - l[0].1) / (l[1].0 - l[0].0);
    let mut side = 0i8;
    for _ in 0..100 {
        let x = (lo * fhi - hi * flo) / (fhi - flo);
        let x = if x.is_finite() && x > lo && x < hi {
            x
        } else {
            0.5 * (lo + hi)
        };
        let v = f(x, &s1, &s2);
        let fx = min(&v);
        last = [last[1], (x, fx)];
        if fx * fhi > 0.0 {
            hi = x;
            fhi = fx;
            if side == 1 {
                flo *= 0.5;
            }
            side = 1;
        } else {
            lo = x;
            flo = fx;
            if side == -1 {
                fhi *= 0.5;
            }
            side = -1;
        }
        if hi - lo <= tol || fx.abs() <= ROOT_VALUE_MM {
            return Some((x, slope(&last)));
        }
        let thresh = fx + 2.0 * lip * (hi - lo);
        s1 = s1
            .iter()
            .zip(&v.0)
            .filter(|(_, c)| **c <= thresh)
            .map(|(i, _)| *i)
            .collect();
        s2 = s2
            .iter()
            .zip(&v.1)
            .filter(|(_, c)| **c <= thresh)
            .map(|(i, _)| *i)
            .collect();
    }
    Some((0.5 * (lo + hi), slope(&last)))
}
