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
use super::outline::{Outline, report_on};
use super::shape::StarShape;
use super::{GearBlank, TeethError};
use crate::geometry::pitch::PitchCurve;
use rayon::prelude::*;
use std::f64::consts::{PI, TAU};

/// Largest spacing of the polar rays along the tip, in modules.
const RAY_SPACING: f64 = 2e-3;
/// Depth over which the root bottom is lowered from 0 to the bottom clearance, in modules.
const RAMP: f64 = 0.1;
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
const SUB: usize = 8;
/// Memory of the per-chunk copies of the rays, bytes (a large gear has ≈ 3·10⁵ rays).
const MAX_CHUNK_BYTES: usize = 256 << 20;
/// Simplification of the mate's outline before the sweep, in modules.
const TOOL_TOL: f64 = 1e-5;
/// Depth of the mate's tip region, in modules (module doc of [`TIP_REFINE`]).
const TIP_BAND: f64 = 0.35;

/// Vertex indices sorted by polar angle, for the vertices near a direction.
struct PolarIndex {
    theta: Vec<f64>,
    index: Vec<u32>,
}

impl PolarIndex {
    fn new(points: &[[f64; 2]], keep: impl Fn(usize) -> bool) -> Self {
        let mut v: Vec<(f64, u32)> = (0..points.len())
            .filter(|&i| keep(i))
            .map(|i| (points[i][1].atan2(points[i][0]), i as u32))
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

/// A rigid map of the mate's body frame into the gear's: `x ↦ R(angle)·x + shift` (mm, rad).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MatePose {
    /// Rotation, rad.
    pub angle_rad: f64,
    /// Translation, mm.
    pub shift_mm: [f64; 2],
}

impl MatePose {
    fn apply(&self, (s, c): (f64, f64), x: [f64; 2]) -> [f64; 2] {
        [
            c * x[0] - s * x[1] + self.shift_mm[0],
            s * x[0] + c * x[1] + self.shift_mm[1],
        ]
    }
}

/// The mate of a swept gear: its outline and pitch curve (its body frame, mm) and its motion.
#[derive(Clone, Copy)]
pub struct Mate<'a> {
    /// The mate's outline, CCW, mm.
    pub outline_mm: &'a [[f64; 2]],
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
pub struct SweepChecks {
    /// Narrowest tooth tip left by the sweep (arc along the tip), mm.
    pub min_tip_width_mm: f64,
    /// Polar rays used.
    pub rays: usize,
}

/// The outline of `blank`'s `z` teeth of module `module_mm` on its pitch curve, swept by its `mates`
/// (one, or two for the intermediate gear of a train)
/// (module doc), simplified to `blank.opts.chord_tol_mm`. The phase and the thinning are unused:
/// the mate's positions place and thin the teeth.
///
/// Errors: [`TeethError::Swept`] when the sweep consumes a tooth's tip (pointed teeth) or leaves
/// other than `z` teeth (the mate's positions do not match the gear).
pub fn generate_swept(
    blank: &GearBlank<'_>,
    mates: &[Mate<'_>],
) -> Result<(Outline, SweepChecks), TeethError> {
    let (frame, rack, z, opts) = (blank.frame, &blank.rack, blank.z, &blank.opts);
    let m = blank.module_mm;
    blank.validated_pitch_mm()?;
    let ha = rack.addendum() * m;
    let k_tip = (rack.straight_depth() * m / rack.alpha_rad().tan()).powi(2);
    // The blank: the addendum curve, as a polar table sampled every 0.05·m of pitch arc (chord
    // sag ≈ (0.05·m)²/(8ρ), below 1e-4·m for ρ ≥ 3·m).
    let nb = (frame.length_mm() / (0.05 * m)).ceil().max(720.0) as usize;
    let (pitch, tip): (Vec<[f64; 2]>, Vec<[f64; 2]>) = (0..nb)
        .map(|k| {
            let f = frame.at(frame.length_mm() * k as f64 / nb as f64);
            let h = ha + f.kappa.min(0.0) * k_tip;
            (f.p, [f.p[0] + h * f.n[0], f.p[1] + h * f.n[1]])
        })
        .unzip();
    let addendum = StarShape::new(&tip, "addendum curve").map_err(|_| TeethError::Swept {
        what: "the addendum curve is not star-shaped about the gear's centre".into(),
    })?;
    let r_tip = tip.iter().map(|p| p[0].hypot(p[1])).fold(0.0, f64::max);
    let rays = ((TAU * r_tip / (RAY_SPACING * m)).ceil() as usize).max(4096);
    let dth = TAU / rays as f64;
    let dir: Vec<(f64, f64)> = (0..rays).map(|j| (j as f64 * dth).sin_cos()).collect();
    let r_blank: Vec<f64> = (0..rays)
        .map(|j| addendum.radius_at(j as f64 * dth))
        .collect();

    // Every mate lowers the rays; the gear keeps what none of them reaches.
    let mut all: Swept = (r_blank.clone(), vec![(f64::INFINITY, 0.0); rays * SUB]);
    for mate in mates {
        let one = sweep_mate(
            mate,
            &Rays {
                dth,
                dir: &dir,
                r_blank: &r_blank,
            },
            ha,
            m,
            r_tip,
        )?;
        merge(&mut all, &one);
    }
    let (swept, gaps) = all;
    // Bottom clearance: the swept root is the mate's tip path, at depth ha·m; the rays deeper
    // than (ha* − RAMP)·m below the pitch curve (normal distance) are lowered radially by up to
    // c*·m, reaching the full clearance at depth ha·m. Only the root bottom moves: the flank
    // above that depth stays as the mate left it.
    let c = rack.clearance() * m;
    let grid = crate::math::polyline::SegmentGrid::new(&pitch);
    let curve = frame.curve();
    let r: Vec<f64> = swept
        .par_iter()
        .enumerate()
        .map(|(j, &rj)| {
            let th = j as f64 * dth;
            let rp = curve.radius_mm(th);
            if rj >= r_blank[j] || rj > rp - (ha - RAMP * m) {
                return rj;
            }
            let (sn, cs) = dir[j];
            let depth = grid.nearest([rj * cs, rj * sn]).distance_mm;
            let w = ((depth - (ha - RAMP * m)) / (RAMP * m)).clamp(0.0, 1.0);
            rj - c * w
        })
        .collect();
    // Teeth: the runs of rays that kept the blank (tips).
    let untouched: Vec<bool> = r.iter().zip(&r_blank).map(|(a, b)| a >= b).collect();
    let Some(start) = (0..rays).find(|&j| !untouched[j]) else {
        return Err(TeethError::Swept {
            what: "the mate's positions never reach the gear".into(),
        });
    };
    let mut widths = Vec::new();
    let mut run = 0usize;
    for k in 1..=rays {
        let j = (start + k) % rays;
        if untouched[j] {
            run += 1;
        } else if run > 0 {
            widths.push(run as f64 * dth * r_blank[j]);
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
    let min_tip = widths.iter().copied().fold(f64::INFINITY, f64::min);
    let ray_point = |j: usize| {
        let (sn, cs) = dir[j % rays];
        [r[j % rays] * cs, r[j % rays] * sn]
    };
    let mut pts: Vec<[f64; 2]> = Vec::with_capacity(rays + rays / 8);
    for j in 0..rays {
        let (a, b) = (ray_point(j), ray_point(j + 1));
        pts.push(a);
        // The lowest tool vertex of each sub-interval between the two rays, when it lies inside
        // the chord between them.
        for &(rho, t) in &gaps[j * SUB..(j + 1) * SUB] {
            if !rho.is_finite() {
                continue;
            }
            let (sn, cs) = t.sin_cos();
            let d = [b[0] - a[0], b[1] - a[1]];
            let uxd = cs * d[1] - sn * d[0];
            if uxd != 0.0 {
                let chord = (a[0] * d[1] - a[1] * d[0]) / uxd;
                if rho < chord {
                    pts.push([rho * cs, rho * sn]);
                }
            }
        }
    }
    let points_mm = crate::math::polyline::simplify_closed(&pts, opts.chord_tol_mm);
    let mut undercut = report_on(blank);
    // No cutter, no cutter undercut: the flanks are what the mate leaves.
    for f in &mut undercut.flanks {
        f.undercut = false;
        f.undercut_mm = 0.0;
        f.contact_ratio_loss = 0.0;
        f.form_depth_mm = f.flank_depth_mm;
    }
    undercut.summarise();
    Ok((
        Outline {
            points_mm,
            z,
            module_mm: m,
            undercut,
        },
        SweepChecks {
            min_tip_width_mm: min_tip,
            rays,
        },
    ))
}

/// The polar rays of a swept gear: spacing `dth` (rad), directions `(sin, cos)`, blank radii (mm).
struct Rays<'a> {
    dth: f64,
    dir: &'a [(f64, f64)],
    r_blank: &'a [f64],
}

/// The rays' radii (mm) after one mate's sweep (module doc); `ha`, `m` in mm, `r_tip` the largest
/// blank radius, mm.
fn sweep_mate(
    mate: &Mate<'_>,
    rays: &Rays<'_>,
    ha: f64,
    m: f64,
    r_tip: f64,
) -> Result<Swept, TeethError> {
    let (dth, dir, r_blank) = (rays.dth, rays.dir, rays.r_blank);
    let rays = dir.len();
    // The mate simplified to TOOL_TOL·m (its finest outlines carry far more vertices than the
    // sweep can resolve; the flank allowance of the positions covers the difference).
    let tool = &crate::math::polyline::simplify_closed(mate.outline_mm, TOOL_TOL * m);
    let nt = tool.len();

    // Each position lowers the rays its tool edges cross; the minimum is order-independent, so
    // the positions run side by side and the result is the same for any thread count.
    let tip_vertex =
        |v: [f64; 2]| v[0].hypot(v[1]) - mate.pitch.radius_mm(v[1].atan2(v[0])) > ha - TIP_BAND * m;
    let all = PolarIndex::new(tool, |_| true);
    let r_mate = tool.iter().map(|v| v[0].hypot(v[1])).fold(0.0, f64::max);
    // Tool edges farther than one module beyond the blank cannot reach it.
    let reach2 = (r_tip + m) * (r_tip + m);
    let tips = PolarIndex::new(tool, |i| tip_vertex(tool[i]));
    // Position k of the fine sequence (`TIP_REFINE` per base position, all offsets): the whole
    // outline at base positions, the tip region in between.
    let fine = mate.positions * TIP_REFINE;
    // Lowers the rays that the segment p → q (polar angles tp, tq) crosses to its crossing.
    let cross_rays = |r: &mut Vec<f64>, p: [f64; 2], q: [f64; 2], tp: f64, tq: f64| {
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
        let d = [q[0] - p[0], q[1] - p[1]];
        let pxd = p[0] * d[1] - p[1] * d[0];
        let j0 = (lo / dth).ceil() as i64;
        let j1 = (hi / dth).floor() as i64;
        for jj in j0..=j1 {
            let j = jj.rem_euclid(rays as i64) as usize;
            let (sn, cs) = dir[j];
            let uxd = cs * d[1] - sn * d[0];
            if uxd == 0.0 {
                continue;
            }
            let rho = pxd / uxd;
            if rho > 0.0 && rho < r[j] {
                r[j] = rho;
            }
        }
    };
    let tip_flag: Vec<bool> = (0..nt).map(|i| tip_vertex(tool[i])).collect();
    type Placed = (u32, [f64; 2], f64, f64);
    let sweep_one = |r: &mut Vec<f64>,
                     gaps: &mut Vec<(f64, f64)>,
                     edges: &mut Vec<usize>,
                     mark: &mut Vec<u32>,
                     cache: &mut Vec<Placed>,
                     k: usize| {
        let (step, set) = (k / mate.offsets, k % mate.offsets);
        let whole = step % TIP_REFINE == 0;
        let pose = &(mate.pose)(step as f64 / fine as f64, set);
        let sc = pose.angle_rad.sin_cos();
        // The gear's centre in the mate's frame: the contact lies towards it.
        let (s, c) = sc;
        let b0 = [
            -(c * pose.shift_mm[0] + s * pose.shift_mm[1]),
            s * pose.shift_mm[0] - c * pose.shift_mm[1],
        ];
        let toward = b0[1].atan2(b0[0]);
        // Every mate vertex that can come within `reach` of the gear's centre: at radius ≤ R
        // from the mate's centre, at distance d from the gear's, its angle β from the direction
        // of the gear's centre has cos β ≥ (d² + R² − reach²)/(2dR) (law of cosines). In a
        // concave hollow the mate's teeth reach in over several pitches on either side.
        let d = b0[0].hypot(b0[1]);
        let cos_w = (d * d + r_mate * r_mate - reach2) / (2.0 * d * r_mate);
        let w = if cos_w <= -1.0 {
            PI
        } else {
            cos_w.min(1.0).acos() + 0.01
        };
        edges.clear();
        let stamp = k as u32 + 1;
        let index = if whole { &all } else { &tips };
        index.near(toward, w, |j| {
            for e in [if j == 0 { nt - 1 } else { j - 1 }, j] {
                if mark[e] != stamp {
                    mark[e] = stamp;
                    edges.push(e);
                }
            }
        });
        // Each vertex is placed once per position (shared by its two edges); its polar angle only
        // when an edge of it can reach the gear.
        let mut vertex = |v: usize, with_angle: bool| {
            let c = &mut cache[v];
            if c.0 != stamp {
                let p = pose.apply(sc, tool[v]);
                *c = (stamp, p, p[0] * p[0] + p[1] * p[1], f64::NAN);
            }
            if with_angle && c.3.is_nan() {
                c.3 = c.1[1].atan2(c.1[0]);
            }
            (c.1, c.2, c.3)
        };
        for &e in edges.iter() {
            let e1 = if e + 1 == nt { 0 } else { e + 1 };
            let ((_, rp2, _), (_, rq2, _)) = (vertex(e, false), vertex(e1, false));
            if rp2.min(rq2) > reach2 {
                continue;
            }
            let ((p, _, tp), (q, _, tq)) = (vertex(e, true), vertex(e1, true));
            cross_rays(r, p, q, tp, tq);
        }
        // The tip vertices' paths to the next position, as edges too: a corner turning sharply
        // relative to the gear would otherwise leave scallops between two positions (measured
        // 1.2e-3·m deep on the lower flank of a strongly non-circular pair).
        let next = (mate.pose)((step + 1) as f64 / fine as f64, set);
        let sc_next = next.angle_rad.sin_cos();
        for &e in edges.iter() {
            if !tip_flag[e] {
                continue;
            }
            let (p, rp2, _) = vertex(e, false);
            let q = next.apply(sc_next, tool[e]);
            if rp2.min(q[0] * q[0] + q[1] * q[1]) > reach2 {
                continue;
            }
            cross_rays(r, p, q, p[1].atan2(p[0]), q[1].atan2(q[0]));
        }
        // The lowest tool vertex between two rays: a tool corner there (the mate's tip corner,
        // moving almost along a ray) would otherwise be cut off by the chord between the rays.
        for &e in edges.iter() {
            let (st, _, r2v, t) = cache[e];
            if st != stamp || t.is_nan() {
                continue;
            }
            let g =
                ((t / dth * SUB as f64).floor() as i64).rem_euclid((rays * SUB) as i64) as usize;
            let rho = r2v.sqrt();
            if rho < gaps[g].0 {
                gaps[g] = (rho, t);
            }
        }
    };
    let count = fine * mate.offsets;
    // Four chunks per thread, each with its own rays and sub-intervals (16·SUB + 8 bytes per ray),
    // at most MAX_CHUNK_BYTES in all: the minima merge in any order.
    let per_chunk = rays * (16 * SUB + 8);
    let chunks =
        (rayon::current_num_threads().max(1) * 4).min((MAX_CHUNK_BYTES / per_chunk).max(1));
    let chunk = count.div_ceil(chunks).max(1);
    let swept = (0..count)
        .collect::<Vec<_>>()
        .par_chunks(chunk)
        .map(|ks| {
            let mut r = r_blank.to_vec();
            let mut gaps = vec![(f64::INFINITY, 0.0); rays * SUB];
            let (mut edges, mut mark) = (Vec::new(), vec![0u32; nt]);
            let mut cache: Vec<Placed> = vec![(0, [0.0; 2], 0.0, f64::NAN); nt];
            for &k in ks {
                sweep_one(&mut r, &mut gaps, &mut edges, &mut mark, &mut cache, k);
            }
            (r, gaps)
        })
        .reduce(
            || (r_blank.to_vec(), vec![(f64::INFINITY, 0.0); rays * SUB]),
            |mut a, b| {
                merge(&mut a, &b);
                a
            },
        );
    Ok(swept)
}

/// The rays' radii and the lowest tool vertex `(ρ, θ)` of each of the `SUB` sub-intervals between
/// ray `j` and `j + 1`, mm and rad.
type Swept = (Vec<f64>, Vec<(f64, f64)>);

/// Merges `b` into `a`: the lower radius per ray, the lower vertex per gap (ties to the smaller
/// angle, so that the result does not depend on the order).
fn merge(a: &mut Swept, b: &Swept) {
    a.0.iter_mut().zip(&b.0).for_each(|(x, y)| *x = x.min(*y));
    a.1.iter_mut().zip(&b.1).for_each(|(x, y)| {
        if y.0 < x.0 || (y.0 == x.0 && y.1 < x.1) {
            *x = *y;
        }
    });
}
