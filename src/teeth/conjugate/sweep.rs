//! One mate's sweep over the gear's polar rays: at every mate position, each tool edge that can
//! reach the gear lowers the rays it crosses to the crossing (parent module doc, **Sweep**).
//! Written by hand: the sweep is the core of the field, no geometry library does it.
use super::{Mate, MatePose, Rays};
use crate::math::Point;
use crate::teeth::TeethError;
use rayon::prelude::*;
use std::f64::consts::{PI, TAU};

/// The mate's tip region (its outline above `(ha* − TIP_BAND)·m` over its pitch curve) is swept at
/// this many times the positions: its corners move fastest relative to the gear and would leave
/// the largest scallops in the fillets (measured on a 24-tooth pair forced to wire EDM: 1.6e-2°
/// of transmission error at 48 positions per pitch for the whole outline, the tip corners touching
/// the scallops; 3.0e-3° at 192).
const TIP_REFINE: usize = 8;
/// Sub-intervals between two rays in which the lowest tool vertex is kept: a tool corner that
/// moves along a ray (the mate's tip corner beside a steep flank) is then located to 1/SUB of the
/// ray spacing instead of being cut off by the chord between the rays (measured: 1.2e-3·m of
/// penetration on a strongly non-circular pair without them).
pub(super) const SUB: usize = 8;
/// Memory of the per-chunk copies of the rays, bytes (a large gear has ≈ 3·10⁵ rays).
const MAX_CHUNK_BYTES: usize = 256 << 20;
/// Simplification of the mate's outline before the sweep, in modules.
const TOOL_TOL: f64 = 1e-5;
/// Depth of the mate's tip region, in modules (module doc of [`TIP_REFINE`]).
const TIP_BAND: f64 = 0.35;

/// The rays' radii and the lowest tool vertex `(ρ, θ)` of each of the `SUB` sub-intervals between
/// ray `j` and `j + 1`, mm and rad.
pub(super) type Swept = (Vec<f64>, Vec<(f64, f64)>);

/// The untouched sweep of `rays`: the blank's radii, no tool vertex in any gap.
pub(super) fn untouched(rays: &Rays<'_>) -> Swept {
    let n = rays.dir.len();
    (rays.r_blank.to_vec(), vec![(f64::INFINITY, 0.0); n * SUB])
}

/// Merges `b` into `a`: the lower radius per ray, the lower vertex per gap (ties to the smaller
/// angle, so that the result does not depend on the order).
pub(super) fn merge(a: &mut Swept, b: &Swept) {
    a.0.iter_mut().zip(&b.0).for_each(|(x, y)| *x = x.min(*y));
    a.1.iter_mut().zip(&b.1).for_each(|(x, y)| {
        if y.0 < x.0 || (y.0 == x.0 && y.1 < x.1) {
            *x = *y;
        }
    });
}

/// The rays' radii (mm) after one mate's sweep (parent module doc); `ha`, `m` in mm, `r_tip` the
/// largest blank radius, mm. Each position lowers the rays its tool edges cross; the minimum is
/// order-independent, so the positions run side by side and the result is the same for any
/// thread count.
pub(super) fn sweep_mate(
    mate: &Mate<'_>,
    rays: &Rays<'_>,
    ha: f64,
    m: f64,
    r_tip: f64,
) -> Result<Swept, TeethError> {
    let sweeper = Sweeper::new(mate, rays, ha, m, r_tip);
    let count = sweeper.fine * mate.offsets;
    // Four chunks per thread, each with its own rays and sub-intervals (16·SUB + 8 bytes per ray),
    // at most MAX_CHUNK_BYTES in all: the minima merge in any order.
    let per_chunk = rays.dir.len() * (16 * SUB + 8);
    let chunks =
        (rayon::current_num_threads().max(1) * 4).min((MAX_CHUNK_BYTES / per_chunk).max(1));
    let chunk = count.div_ceil(chunks).max(1);
    let swept = (0..count)
        .collect::<Vec<_>>()
        .par_chunks(chunk)
        .map(|ks| {
            let mut s = sweeper.scratch();
            for &k in ks {
                sweeper.position(&mut s, k);
            }
            s.swept
        })
        .reduce(
            || untouched(rays),
            |mut a, b| {
                merge(&mut a, &b);
                a
            },
        );
    Ok(swept)
}

/// Vertex indices sorted by polar angle, for the vertices near a direction.
struct PolarIndex {
    theta: Vec<f64>,
    index: Vec<u32>,
}

impl PolarIndex {
    fn new(points: &[Point], keep: impl Fn(usize) -> bool) -> Self {
        let mut v: Vec<(f64, u32)> = (0..points.len())
            .filter(|&i| keep(i))
            .map(|i| (points[i].atan2(), i as u32))
            .collect();
        v.sort_by(|a, b| a.0.total_cmp(&b.0));
        let (theta, index) = v.into_iter().unzip();
        Self { theta, index }
    }

    /// Calls `f` with the index of every vertex whose polar angle is within `w` of `t` (rad).
    fn near(&self, t: f64, w: f64, mut f: impl FnMut(usize)) {
        let n = self.theta.len();
        if n == 0 {
            return;
        }
        let mut visit = |lo: f64, hi: f64| {
            let a = self.theta.partition_point(|&x| x < lo);
            for k in a..n {
                if self.theta[k] > hi {
                    break;
                }
                f(self.index[k] as usize);
            }
        };
        let lo = (t - w + PI).rem_euclid(TAU) - PI;
        let hi = lo + 2.0 * w;
        visit(lo, hi.min(PI));
        if hi > PI {
            visit(-PI, hi - TAU);
        }
    }
}

/// A tool vertex placed at one position: `(stamp, point, |point|², polar angle or NaN)`, mm, mm²,
/// rad; valid while `stamp` is the position's.
type Placed = (u32, Point, f64, f64);

/// One mate position: its pose, the pose's `(sin, cos)` and its stamp (position index + 1).
struct At {
    pose: MatePose,
    sc: (f64, f64),
    stamp: u32,
}

/// What one chunk of positions works on: its sweep, the tool edges of the current position, the
/// stamps marking them, and the placed vertices.
struct Scratch {
    swept: Swept,
    edges: Vec<usize>,
    mark: Vec<u32>,
    cache: Vec<Placed>,
}

impl Scratch {
    /// Tool vertex `v` placed at `at` (once per position, shared by its two edges); its polar
    /// angle only when `with_angle` (an edge of it can reach the gear).
    fn vertex(&mut self, at: &At, tool: &[Point], v: usize, with_angle: bool) -> Placed {
        let c = &mut self.cache[v];
        if c.0 != at.stamp {
            let p = at.pose.apply(at.sc, tool[v]);
            *c = (at.stamp, p, p.dot(p), f64::NAN);
        }
        if with_angle && c.3.is_nan() {
            c.3 = c.1.atan2();
        }
        *c
    }
}

/// One mate's sweep: the simplified tool and its indices, and the reach of the gear.
struct Sweeper<'a> {
    mate: &'a Mate<'a>,
    rays: &'a Rays<'a>,
    /// The mate's outline simplified to `TOOL_TOL·m`, mm.
    tool: Vec<Point>,
    /// Whether each tool vertex lies in the mate's tip region.
    tip_flag: Vec<bool>,
    /// Every tool vertex, and the tip region's, by polar angle.
    all: PolarIndex,
    tips: PolarIndex,
    /// Largest radius of the tool, mm.
    r_mate: f64,
    /// Squared radius beyond which a tool edge cannot reach the blank, mm².
    reach2: f64,
    /// Positions of the fine sequence per offset (`TIP_REFINE` per base position).
    fine: usize,
}

impl<'a> Sweeper<'a> {
    fn new(mate: &'a Mate<'a>, rays: &'a Rays<'a>, ha: f64, m: f64, r_tip: f64) -> Self {
        // The mate simplified to TOOL_TOL·m (its finest outlines carry far more vertices than the
        // sweep can resolve; the flank allowance of the positions covers the difference).
        let tool = crate::math::polyline::simplify_closed(mate.outline_mm, TOOL_TOL * m);
        let tip_vertex = |v: Point| v.hypot() - mate.pitch.radius_mm(v.atan2()) > ha - TIP_BAND * m;
        let all = PolarIndex::new(&tool, |_| true);
        let r_mate = tool.iter().map(|v| v.hypot()).fold(0.0, f64::max);
        let tips = PolarIndex::new(&tool, |i| tip_vertex(tool[i]));
        let tip_flag = tool.iter().map(|&v| tip_vertex(v)).collect();
        Self {
            mate,
            rays,
            tip_flag,
            all,
            tips,
            r_mate,
            // Tool edges farther than one module beyond the blank cannot reach it.
            reach2: (r_tip + m) * (r_tip + m),
            // Position k of the fine sequence (`TIP_REFINE` per base position, all offsets): the
            // whole outline at base positions, the tip region in between.
            fine: mate.positions * TIP_REFINE,
            tool,
        }
    }

    /// A chunk's fresh working state.
    fn scratch(&self) -> Scratch {
        let nt = self.tool.len();
        Scratch {
            swept: untouched(self.rays),
            edges: Vec::new(),
            mark: vec![0u32; nt],
            cache: vec![(0, Point::ZERO, 0.0, f64::NAN); nt],
        }
    }

    /// Position `k` of the fine sequence (all offsets) lowers `s`'s rays: the tool edges near the
    /// gear, the tip vertices' paths to the next position, the lowest vertex of each gap.
    fn position(&self, s: &mut Scratch, k: usize) {
        let (step, set) = (k / self.mate.offsets, k % self.mate.offsets);
        let pose = (self.mate.pose)(step as f64 / self.fine as f64, set);
        let at = At {
            pose,
            sc: pose.angle_rad.sin_cos(),
            stamp: k as u32 + 1,
        };
        self.edges_near(s, &at, step % TIP_REFINE == 0);
        self.lower_by_edges(s, &at);
        self.lower_by_tip_paths(s, &at, step, set);
        self.keep_gap_vertices(s, &at);
    }

    /// Collects into `s.edges` every tool edge (of the whole outline, or of the tip region when
    /// not `whole`) whose vertices can come within reach of the gear's centre at `at`.
    fn edges_near(&self, s: &mut Scratch, at: &At, whole: bool) {
        // The gear's centre in the mate's frame: the contact lies towards it.
        let ((sn, c), shift) = (at.sc, at.pose.shift_mm);
        let b0 = [-(c * shift.x + sn * shift.y), sn * shift.x - c * shift.y];
        let toward = b0[1].atan2(b0[0]);
        // Every mate vertex that can come within `reach` of the gear's centre: at radius ≤ R
        // from the mate's centre, at distance d from the gear's, its angle β from the direction
        // of the gear's centre has cos β ≥ (d² + R² − reach²)/(2dR) (law of cosines). In a
        // concave hollow the mate's teeth reach in over several pitches on either side.
        let (d, r_mate) = (b0[0].hypot(b0[1]), self.r_mate);
        let cos_w = (d * d + r_mate * r_mate - self.reach2) / (2.0 * d * r_mate);
        let w = if cos_w <= -1.0 {
            PI
        } else {
            cos_w.min(1.0).acos() + 0.01
        };
        s.edges.clear();
        let nt = self.tool.len();
        let index = if whole { &self.all } else { &self.tips };
        let (edges, mark) = (&mut s.edges, &mut s.mark);
        index.near(toward, w, |j| {
            for e in [if j == 0 { nt - 1 } else { j - 1 }, j] {
                if mark[e] != at.stamp {
                    mark[e] = at.stamp;
                    edges.push(e);
                }
            }
        });
    }

    /// Each collected edge within reach lowers the rays it crosses.
    fn lower_by_edges(&self, s: &mut Scratch, at: &At) {
        let nt = self.tool.len();
        for i in 0..s.edges.len() {
            let e = s.edges[i];
            let e1 = if e + 1 == nt { 0 } else { e + 1 };
            let (rp2, rq2) = (
                s.vertex(at, &self.tool, e, false).2,
                s.vertex(at, &self.tool, e1, false).2,
            );
            if rp2.min(rq2) > self.reach2 {
                continue;
            }
            let (p, q) = (
                s.vertex(at, &self.tool, e, true),
                s.vertex(at, &self.tool, e1, true),
            );
            cross_rays(self.rays, &mut s.swept.0, p.1, q.1, p.3, q.3);
        }
    }

    /// The tip vertices' paths to the next position, as edges too: a corner turning sharply
    /// relative to the gear would otherwise leave scallops between two positions (measured
    /// 1.2e-3·m deep on the lower flank of a strongly non-circular pair).
    fn lower_by_tip_paths(&self, s: &mut Scratch, at: &At, step: usize, set: usize) {
        let next = (self.mate.pose)((step + 1) as f64 / self.fine as f64, set);
        let sc_next = next.angle_rad.sin_cos();
        for i in 0..s.edges.len() {
            let e = s.edges[i];
            if !self.tip_flag[e] {
                continue;
            }
            let (_, p, rp2, _) = s.vertex(at, &self.tool, e, false);
            let q = next.apply(sc_next, self.tool[e]);
            if rp2.min(q.dot(q)) > self.reach2 {
                continue;
            }
            let (tp, tq) = (p.atan2(), q.atan2());
            cross_rays(self.rays, &mut s.swept.0, p, q, tp, tq);
        }
    }

    /// The lowest tool vertex between two rays: a tool corner there (the mate's tip corner,
    /// moving almost along a ray) would otherwise be cut off by the chord between the rays.
    fn keep_gap_vertices(&self, s: &mut Scratch, at: &At) {
        let (dth, rays) = (self.rays.dth, self.rays.dir.len());
        for &e in &s.edges {
            let (st, _, r2v, t) = s.cache[e];
            if st != at.stamp || t.is_nan() {
                continue;
            }
            let g =
                ((t / dth * SUB as f64).floor() as i64).rem_euclid((rays * SUB) as i64) as usize;
            let rho = r2v.sqrt();
            let gap = &mut s.swept.1[g];
            if rho < gap.0 {
                *gap = (rho, t);
            }
        }
    }
}

/// Lowers the rays `r` (mm) that the segment p → q (mm; polar angles tp, tq, rad) crosses to its
/// crossing.
fn cross_rays(rays: &Rays<'_>, r: &mut [f64], p: Point, q: Point, tp: f64, tq: f64) {
    let (dth, dir, n) = (rays.dth, rays.dir, rays.dir.len());
    let mut span = tq - tp;
    if span > PI {
        span -= TAU;
    } else if span < -PI {
        span += TAU;
    }
    let (lo, hi) = if span >= 0.0 {
        (tp, tp + span)
    } else {
        (tp + span, tp)
    };
    let d = q - p;
    let pxd = p.cross(d);
    let j0 = (lo / dth).ceil() as i64;
    let j1 = (hi / dth).floor() as i64;
    for jj in j0..=j1 {
        let j = jj.rem_euclid(n as i64) as usize;
        let (sn, cs) = dir[j];
        let uxd = cs * d.y - sn * d.x;
        if uxd == 0.0 {
            continue;
        }
        let rho = pxd / uxd;
        if rho > 0.0 && rho < r[j] {
            r[j] = rho;
        }
    }
}
