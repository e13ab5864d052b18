//! One resolution of the mesh check: both outlines indexed, the candidate vertices near the
//! contact, per-vertex clearances at a driven offset, and the pruned root search on them.
use super::root::{PerVertex, VertexSets};
use crate::math::Point;
use crate::teeth::shape::{MeshError, Shape};
use std::f64::consts::PI;

/// Driver angle `phi`, law angle `psi0` (rad) and centre distance `a` (mm) of one position.
pub(super) struct Pose {
    pub(super) phi: f64,
    pub(super) psi0: f64,
    pub(super) a: f64,
}

/// Both outlines at one resolution: exact shapes, the candidates' first pruning, and the
/// Lipschitz constant of the clearances in δ.
pub(super) struct Level {
    pub(super) h1: Shape,
    pub(super) h2: Shape,
    /// Coarse copies (every 16th vertex) for the candidates' pruning, when the blocks are too
    /// large to prune with (`None`: the blocks' bounds prune, see [`Self::candidates`]).
    coarse: Option<(Shape, Shape)>,
    pub(super) reach: f64,
    pub(super) lip: f64,
    pub(super) module_mm: f64,
    /// Bounding circles (body-frame centre, radius, mm) of the blocks of `block` consecutive
    /// polar entries of `h1`, `h2`.
    blocks1: Vec<(Point, f64)>,
    blocks2: Vec<(Point, f64)>,
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

/// The candidates' reach beyond the farthest a vertex moves over the backlash range, in modules.
const REACH_MARGIN: f64 = 0.05;

/// Simplification of the bounding copies, in modules.
const BOUND_TOL: f64 = 2e-3;

/// Bounding circles of the blocks of `block` consecutive polar entries.
fn block_circles(g: &crate::teeth::shape::StarShape, block: usize) -> Vec<(Point, f64)> {
    let n = g.r.len();
    (0..n.div_ceil(block))
        .map(|b| {
            let pts: Vec<Point> = (b * block..((b + 1) * block).min(n))
                .map(|i| g.point(i))
                .collect();
            let [x0, y0, x1, y1] = crate::math::polyline::bbox(&pts);
            let c = Point::new(0.5 * (x0 + x1), 0.5 * (y0 + y1));
            let r = pts
                .iter()
                .map(|p| ((p.x - c.x).powi(2) + (p.y - c.y).powi(2)).sqrt())
                .fold(0.0, f64::max);
            (c, r)
        })
        .collect()
}

/// The outlines of one resolution: both polylines (mm) and their Hausdorff distance from the
/// given outlines (mm; 0 for the given outlines themselves).
pub(super) struct Polylines {
    pub(super) driver: Vec<Point>,
    pub(super) driven: Vec<Point>,
    pub(super) deviation_mm: f64,
}

impl Polylines {
    /// Both outlines simplified to `simplify_mm` (Douglas–Peucker, side by side; 0 = as given).
    pub(super) fn new(driver: &[Point], driven: &[Point], simplify_mm: f64) -> Self {
        let thin = |v: &[Point]| {
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

    /// The copies the bounded evaluation bounds through: simplified to `BOUND_TOL·m` less this
    /// copy's deviation and `other_mm`, so that they are within `BOUND_TOL·m` of the given
    /// outlines, of these polylines and of any copy within `other_mm` of these.
    pub(super) fn bound_copies(&self, module_mm: f64, other_mm: f64) -> Polylines {
        let tol = BOUND_TOL * module_mm - self.deviation_mm - other_mm;
        debug_assert!(tol > 0.5 * BOUND_TOL * module_mm);
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
        let every = |v: &[Point], k: usize| v.iter().step_by(k).copied().collect::<Vec<_>>();
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
        let reach = 4.0 * backlash_mm / r2min * lip + REACH_MARGIN * m;
        let bound_shapes = || {
            rayon::join(
                || Shape::new(&bounds.driver, reach, "driver"),
                || Shape::new(&bounds.driven, reach, "driven"),
            )
        };
        let slack = 3.0 * bounds.deviation_mm + 1e-6 * m;
        // Blocks of about 0.04·m of outline.
        let perimeter: f64 = (0..d1.len())
            .map(|i| {
                let (p, q) = (d1[i], d1[(i + 1) % d1.len()]);
                ((q.x - p.x).powi(2) + (q.y - p.y).powi(2)).sqrt()
            })
            .sum();
        let block = ((0.04 * m * d1.len() as f64 / perimeter).round() as usize).clamp(4, 256);
        let (blocks1, blocks2) = (
            block_circles(&h1.polar, block),
            block_circles(&h2.polar, block),
        );
        // Blocks narrower than the reach's margin (radius plus slack) can be dropped by their
        // bounds; wider ones are always kept (see `candidates`).
        let total = blocks1.len() + blocks2.len();
        let narrow = blocks1
            .iter()
            .chain(&blocks2)
            .filter(|b| b.1 + slack < REACH_MARGIN * m)
            .count();
        // The blocks prune the candidates when nearly all are narrow (the given outlines, dense
        // and even); otherwise coarse copies (every 16th vertex, indexed at the reach) do — a
        // simplified copy's blocks of four long chords are mostly wide, and kept.
        let ((b1, b2), coarse) = if narrow * 10 >= total * 9 {
            (bound_shapes(), None)
        } else {
            let coarse = || {
                rayon::join(
                    || Shape::new(&every(d1, 16), reach, "driver"),
                    || Shape::new(&every(d2, 16), reach, "driven"),
                )
            };
            let (b, (k1, k2)) = rayon::join(bound_shapes, coarse);
            (b, Some((k1?, k2?)))
        };
        let (b1, b2) = (b1?, b2?);
        Ok(Self {
            blocks1,
            blocks2,
            block,
            b1,
            b2,
            h1,
            h2,
            coarse,
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
        let fr = Frames::new(pose, delta);
        let mut cache = cache.0.borrow_mut();
        let runs = self.runs(delta, set1, set2, &cache);
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
                let lb = self.block_bound(key, &fr, delta, &mut cache);
                if lb > floor && lb >= best {
                    v.fill(lb);
                    continue;
                }
            }
            let idx = if gear == 0 { &set1[s..e] } else { &set2[s..e] };
            self.exact_block(gear, &fr, idx, v, &mut best, floor);
        }
        (v1, v2)
    }

    /// Runs of set entries in one block, sorted by their bounds: (gear, first, end, cache key,
    /// bound, fresh). The bound is the block's last one in `cache`, moved by its speed (the
    /// distance of its centre from the driven centre, invariant under δ) times |Δδ|, or −∞;
    /// fresh when it was computed at this δ.
    fn runs(
        &self,
        delta: f64,
        set1: &[usize],
        set2: &[usize],
        cache: &[(f64, f64, f64)],
    ) -> Vec<(u8, usize, usize, usize, f64, bool)> {
        let mut runs = Vec::new();
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
        runs.sort_unstable_by(|x, y| x.4.total_cmp(&y.4));
        runs
    }

    /// Whether some vertex of `set1` (gear 1) or `set2` (gear 2) has a clearance ≤ `t` (mm) at
    /// driven offset δ (rad): a decision, not a minimum — blocks whose bound exceeds `t` are not
    /// evaluated, and the search stops at the first such vertex.
    pub(super) fn any_at_most(
        &self,
        pose: &Pose,
        delta: f64,
        set1: &[usize],
        set2: &[usize],
        t: f64,
        cache: &BoundCache,
    ) -> bool {
        let fr = Frames::new(pose, delta);
        let mut cache = cache.0.borrow_mut();
        let mut best = f64::INFINITY;
        let mut v = Vec::new();
        for (gear, s, e, key, moved, fresh) in self.runs(delta, set1, set2, &cache) {
            // Sorted by the moved bounds: none of the rest can reach `t`.
            if moved > t {
                break;
            }
            let lb = if fresh {
                moved
            } else {
                self.block_bound(key, &fr, delta, &mut cache)
            };
            if lb > t {
                continue;
            }
            v.resize(e - s, 0.0);
            let idx = if gear == 0 { &set1[s..e] } else { &set2[s..e] };
            self.exact_block(gear, &fr, idx, &mut v, &mut best, t);
            if best <= t {
                return true;
            }
        }
        false
    }

    /// Clearances `out` of the polar entries `idx` of one block of gear `gear` (0: driver,
    /// against the driven gear; 1: the reverse) in the frames `fr`, exact or bounded above
    /// `floor` and `best` as [`exact_run`] tells; the bounds' rounding margin is 1e-12·m.
    fn exact_block(
        &self,
        gear: u8,
        fr: &Frames,
        idx: &[usize],
        out: &mut [f64],
        best: &mut f64,
        floor: f64,
    ) {
        let margin = 1e-12 * self.module_mm;
        if gear == 0 {
            let g = &self.h1.polar;
            let eval = |i: usize| self.h2.clearance(fr.to2(g.point(i)));
            exact_run(idx, g, eval, out, best, floor, margin);
        } else {
            let g = &self.h2.polar;
            let eval = |i: usize| self.h1.clearance(fr.to1(g.point(i)));
            exact_run(idx, g, eval, out, best, floor, margin);
        }
    }

    /// The lower bound of block `key` (gear 1's blocks, then gear 2's) at driven offset `delta`
    /// in the frames `fr`, mm: its centre's clearance on the bounding copy of the other gear less
    /// its radius and `slack`; kept in `cache` with its speed (the distance of its centre from the
    /// driven centre, invariant under δ, mm/rad).
    fn block_bound(
        &self,
        key: usize,
        fr: &Frames,
        delta: f64,
        cache: &mut [(f64, f64, f64)],
    ) -> f64 {
        let (lb, speed) = if key < self.blocks1.len() {
            let (c, r) = self.blocks1[key];
            let p = fr.to2(c);
            (self.b2.clearance(p) - r, p.hypot())
        } else {
            let (c, r) = self.blocks2[key - self.blocks1.len()];
            (self.b1.clearance(fr.to1(c)) - r, c.hypot())
        };
        let lb = lb - self.slack;
        cache[key] = (delta, lb, speed * (1.0 + 1e-9) + 1e-9 * self.module_mm);
        lb
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
        let fr = Frames::new(pose, delta);
        let v2 = set2.iter().map(|&i| s1.clearance(fr.to1(g2.point(i))));
        let v1 = set1.iter().map(|&i| s2.clearance(fr.to2(g1.point(i))));
        (v1.collect(), v2.collect())
    }

    /// The vertices (polar indices of both gears) that can touch the other gear for δ in the
    /// backlash range: the contact windows (half-widths `w1`, `w2`, rad), pruned at δ = 0.
    ///
    /// A vertex touches at δ only if its clearance at 0 is at most `lip·|δ|`, and the reach
    /// exceeds that by `REACH_MARGIN·m` over the whole range (−db … 3·db). With blocks narrower
    /// than that margin (radius plus slack), a block is dropped when its lower bound exceeds
    /// `reach − REACH_MARGIN·m` — its centre is beyond the reach of the bounding copy, which the
    /// copy's clip at the reach tells — and the bounds computed stay in `cache` for the
    /// evaluation at δ = 0. Otherwise the coarse copies prune: every 16th window vertex, its
    /// ±16 neighbours kept when it is within reach (plus 0.1·m for the copy's chords).
    pub(super) fn candidates(
        &self,
        pose: &Pose,
        w1: f64,
        w2: f64,
        cache: &BoundCache,
    ) -> VertexSets {
        let m = self.module_mm;
        let c1 = self.h1.polar.window(-pose.phi, w1);
        let c2 = self.h2.polar.window(PI + pose.psi0, w2);
        let Some((k1, k2)) = &self.coarse else {
            let fr = Frames::new(pose, 0.0);
            let limit = self.reach - REACH_MARGIN * m;
            let mut cache = cache.0.borrow_mut();
            // A block wider than the margin is kept: its bound is at most the clip at the reach
            // less its radius and slack, which is ≤ the limit.
            let mut keep = |c: &[usize], offset: usize| {
                let mut out = Vec::with_capacity(c.len());
                for run in c.chunk_by(|i, j| i / self.block == j / self.block) {
                    let key = offset + run[0] / self.block;
                    let lb = match cache[key] {
                        (0.0, lb, _) => lb,
                        _ => self.block_bound(key, &fr, 0.0, &mut cache),
                    };
                    if lb <= limit {
                        out.extend_from_slice(run);
                    }
                }
                out
            };
            return (keep(&c1, 0), keep(&c2, self.blocks1.len()));
        };
        let d1: Vec<usize> = c1.iter().step_by(16).copied().collect();
        let d2: Vec<usize> = c2.iter().step_by(16).copied().collect();
        let (p1, p2) = self.eval_on(pose, 0.0, &d1, &d2, k1, k2);
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

/// The two body frames at one pose and driven offset: the driver turned by φ about the origin,
/// the driven gear by `ψ₀ + δ` (clockwise) about `(a, 0)`.
struct Frames {
    sn1: f64,
    co1: f64,
    sn2: f64,
    co2: f64,
    a: f64,
}

impl Frames {
    fn new(pose: &Pose, delta: f64) -> Self {
        let (sn1, co1) = pose.phi.sin_cos();
        let (sn2, co2) = (pose.psi0 + delta).sin_cos();
        Self {
            sn1,
            co1,
            sn2,
            co2,
            a: pose.a,
        }
    }

    /// A gear-2 body point (mm) in gear 1's body frame.
    #[inline]
    fn to1(&self, b: Point) -> Point {
        let (sn1, co1, sn2, co2, a) = (self.sn1, self.co1, self.sn2, self.co2, self.a);
        let w = [co2 * b.x + sn2 * b.y + a, -sn2 * b.x + co2 * b.y];
        Point::new(co1 * w[0] + sn1 * w[1], -sn1 * w[0] + co1 * w[1])
    }

    /// A gear-1 body point (mm) in gear 2's body frame.
    #[inline]
    fn to2(&self, b: Point) -> Point {
        let (sn1, co1, sn2, co2, a) = (self.sn1, self.co1, self.sn2, self.co2, self.a);
        let w = [co1 * b.x - sn1 * b.y - a, sn1 * b.x + co1 * b.y];
        Point::new(co2 * w[0] - sn2 * w[1], sn2 * w[0] + co2 * w[1])
    }
}

/// Entries of a block evaluated first in [`exact_run`]: every `STRIDE`-th one.
const STRIDE: usize = 4;

/// Clearances `out` of the polar entries `idx` of one block of `g` (`eval` gives an entry's
/// clearance), exact — or, for an entry that cannot matter, a lower bound above `floor` and the
/// least value so far (`best`, updated). Every `STRIDE`-th entry and the last are evaluated
/// first; an entry between two of them takes the larger of their 1-Lipschitz bounds
/// `c_k − |p − p_k| − margin` (a signed distance, clipped or not, changes no faster than the
/// point moves; `margin` covers the rounding) when that exceeds `floor` and `best`, and is
/// evaluated otherwise. Near a contact most entries are then bounded by a neighbour within
/// `STRIDE/2` edges instead of evaluated.
fn exact_run(
    idx: &[usize],
    g: &crate::teeth::shape::StarShape,
    eval: impl Fn(usize) -> f64,
    out: &mut [f64],
    best: &mut f64,
    floor: f64,
    margin: f64,
) {
    let n = idx.len();
    let sampled = |k: usize| k.is_multiple_of(STRIDE) || k + 1 == n;
    for k in (0..n).filter(|&k| sampled(k)) {
        out[k] = eval(idx[k]);
        *best = best.min(out[k]);
    }
    for k in (0..n).filter(|&k| !sampled(k)) {
        let p = g.point(idx[k]);
        let from = |j: usize| {
            let q = g.point(idx[j]);
            out[j] - ((p.x - q.x).powi(2) + (p.y - q.y).powi(2)).sqrt() - margin
        };
        let lb = from(k - k % STRIDE).max(from(((k / STRIDE + 1) * STRIDE).min(n - 1)));
        out[k] = if lb > floor && lb >= *best {
            lb
        } else {
            let c = eval(idx[k]);
            *best = best.min(c);
            c
        };
    }
}

/// The last lower bound of each block (driven offset δ, bound mm, speed mm/rad) at one pose:
/// a block's bound at another δ is that bound less speed × |Δδ|.
pub(super) struct BoundCache(std::cell::RefCell<Vec<(f64, f64, f64)>>);
