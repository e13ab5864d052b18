//! Rack-envelope tooth outline (docs/math/teeth.md §12.3); its undercut report (docs/math/teeth.md §12.4) is in `teeth::undercut`.
//!
//! For tooth k centred at `s_k = s0 + k·p` (p = πm), the right (larger-s) flank crosses the pitch
//! curve at `s_r = s_k + p/4 − t_r` and the left at `s_l = s_k − p/4 + t_l` (`t_*` = thinning for
//! backlash). In rack coordinates relative to the rolling position `s` the generated pieces are
//! (normal-through-the-instant-centre rule, exact):
//! - right flank `Q − P = (s_r − s)cos α·(cos α, sin α)`, depth `η = (s_r − s) sin α cos α`;
//! - left flank `Q − P = (s_l − s)cos α·(cos α, −sin α)`;
//! - fillet of the rack tip circle, centre `C`, `F = C + ρf·(C − P)/|C − P|`;
//! - root `η = −hf` at `ξ = s`; tip: the addendum curve `P(u) + ha·N(u)`, trimmed at its
//!   intersection with the flanks (2-D Newton).
//!
//! Each point maps to the body frame by `P(s) + (ξ − s)T(s) + ηN(s)`.
use super::blank::OutlineOptions;
use super::crossing::cut_loops;
use super::frame::ArcFrame;
use super::undercut::report_on;
use super::{GearBlank, RackParams, TeethError, UndercutReport};
use crate::math::Point;
use serde::Serialize;

/// A generated gear outline: one simple closed CCW polyline in the gear body frame, mm
/// (no duplicated end vertex).
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct Outline {
    /// Vertices, mm, CCW, closed implicitly.
    pub points_mm: Vec<Point>,
    /// Tooth count.
    pub z: u32,
    /// Module, mm.
    pub module_mm: f64,
    /// Undercut/concavity diagnostics.
    pub undercut: UndercutReport,
}

struct Gen<'a> {
    frame: &'a ArcFrame,
    ha: f64,
    hf: f64,
    rho: f64,
    hs: f64,
    sa: f64,
    ca: f64,
}

impl Gen<'_> {
    fn map(&self, s: f64, xi: f64, eta: f64) -> Point {
        let f = self.frame.at(s);
        ArcFrame::rack_to_body(&f, s, xi, eta)
    }
    /// Flank point; `sign` = +1 right flank, −1 left flank.
    fn flank(&self, sf: f64, sign: f64, s: f64) -> Point {
        let d = (sf - s) * self.ca;
        self.map(s, s + d * self.ca, sign * d * self.sa)
    }
    fn fillet(&self, xc: f64, s: f64) -> Point {
        let ec = -(self.hf - self.rho);
        let (dx, dy) = (xc - s, ec);
        let l = dx.hypot(dy);
        self.map(s, xc + self.rho * dx / l, ec + self.rho * dy / l)
    }
    /// Addendum curve lowered by the tooth's tip relief `rel` (mm, [`super::tip_relief`]).
    fn tip(&self, u: f64, rel: f64) -> Point {
        let f = self.frame.at(u);
        let h = self.ha - rel;
        f.p + f.n * h
    }
    /// Solves flank(s) = tip(u) by Newton from the flat-rack guess.
    fn trim_tip(&self, sf: f64, sign: f64, rel: f64) -> Option<(f64, f64)> {
        let sc = self.sa * self.ca;
        let s = sf - sign * (self.ha - rel) / sc;
        let u = s + (sf - s) * self.ca * self.ca;
        meet(|s| self.flank(sf, sign, s), |u| self.tip(u, rel), s, u)
    }
    /// Appends the left side of the tooth whose left flank crosses the pitch curve at `sl` to
    /// `out`: the fillet from the root up, then the flank from η = −hs up to the tip at `s_tip`.
    /// An `undercut` side is walked from the root with its loops cut ([`cut_loops`]): what the
    /// fillet trochoid cuts away and the flank envelope's swallowtail go, the form point is the
    /// last jump onto the flank. Returns the form point (mm) and its depth below the pitch
    /// curve, mm.
    fn left_side(
        &self,
        w: &Walk,
        sl: f64,
        s_tip: f64,
        undercut: bool,
        out: &mut Vec<Point>,
    ) -> (Point, f64) {
        let xcl = sl - self.hs * w.ta - self.rho * self.ca;
        let mut wl = vec![self.fillet(xcl, xcl)];
        let nfl = push_piece(&mut wl, xcl, xcl - w.fillet_span, w.step_f, |s| {
            self.fillet(xcl, s)
        });
        let s_low = sl - self.hs / w.sc;
        let nl = push_piece(&mut wl, s_low, s_tip, w.step, |s| self.flank(sl, -1.0, s));
        if !undercut {
            out.extend_from_slice(&wl[1..]);
            return (wl[nfl], self.hs);
        }
        let (kept, jumps) = cut_loops(&wl);
        out.extend_from_slice(&kept[1..]);
        // Flank parameter u ∈ [0, nl] of the highest jump landing on the flank.
        match jumps.iter().rev().find(|j| j.to >= nfl as f64) {
            Some(j) => {
                let u = (j.to - nfl as f64) / nl as f64;
                (j.point, (sl - (s_low + (s_tip - s_low) * u)) * w.sc)
            }
            None => (wl[nfl], self.hs),
        }
    }

    /// Appends the right side of the tooth whose right flank crosses the pitch curve at `sr` to
    /// `out` (which ends at the tip corner): the flank from the tip at `s_tip` down to η = −hs,
    /// then the fillet down to the root. An `undercut` side is walked from the tip with its loops
    /// cut, the form point is the first jump off the flank. Returns the form point (mm) with its
    /// depth (mm), and the fillet centre's rack position `xcr`.
    fn right_side(
        &self,
        w: &Walk,
        sr: f64,
        s_tip: f64,
        undercut: bool,
        out: &mut Vec<Point>,
    ) -> ((Point, f64), f64) {
        let s_low = sr + self.hs / w.sc;
        let mut wr = vec![out[out.len() - 1]];
        let nr = push_piece(&mut wr, s_tip, s_low, w.step, |s| self.flank(sr, 1.0, s));
        let xcr = sr + self.hs * w.ta + self.rho * self.ca;
        push_piece(&mut wr, xcr + w.fillet_span, xcr, w.step_f, |s| {
            self.fillet(xcr, s)
        });
        if !undercut {
            out.extend_from_slice(&wr[1..]);
            return ((wr[nr], self.hs), xcr);
        }
        let (kept, jumps) = cut_loops(&wr);
        out.extend_from_slice(&kept[1..]);
        let form = match jumps.iter().find(|j| j.from <= nr as f64) {
            Some(j) => {
                let u = j.from / nr as f64;
                (j.point, (s_tip + (s_low - s_tip) * u - sr) * w.sc)
            }
            None => (wr[nr], self.hs),
        };
        (form, xcr)
    }

    /// Tooth `k`'s tip relief from `relief_mm` (mm), its flank crossings `(sl, sr)` and both
    /// flanks trimmed at its relieved tip: `(s_tip, u)` left and right. Errors:
    /// [`TeethError::Trim`].
    #[allow(clippy::type_complexity)]
    fn trim_tooth(
        &self,
        k: usize,
        p: f64,
        opts: &OutlineOptions,
        relief_mm: &[f64],
    ) -> Result<(f64, (f64, f64), (f64, f64), (f64, f64)), TeethError> {
        let rel = tooth_relief(relief_mm, k);
        let sk = opts.phase_mm + k as f64 * p;
        let sl = sk - 0.25 * p + opts.thin_left_mm;
        let sr = sk + 0.25 * p - opts.thin_right_mm;
        let left = self.trim_tip(sl, -1.0, rel).ok_or(TeethError::Trim {
            tooth: k,
            what: "left flank meets no tip",
        })?;
        let right = self.trim_tip(sr, 1.0, rel).ok_or(TeethError::Trim {
            tooth: k,
            what: "right flank meets no tip",
        })?;
        if right.1 <= left.1 {
            return Err(TeethError::Trim {
                tooth: k,
                what: "pointed tooth (tip width ≤ 0)",
            });
        }
        Ok((rel, (sl, sr), left, right))
    }
}

/// Tooth `k`'s tip relief in a per-tooth list, mm (0 where the list is shorter).
pub(super) fn tooth_relief(relief_mm: &[f64], k: usize) -> f64 {
    relief_mm.get(k).copied().unwrap_or(0.0)
}

/// The rack's generation parameters at module `m` on `frame`.
fn rack_gen<'a>(frame: &'a ArcFrame, rack: &RackParams, m: f64) -> Gen<'a> {
    let (sa, ca) = rack.alpha_rad().sin_cos();
    Gen {
        frame,
        ha: rack.addendum() * m,
        hf: (rack.addendum() + rack.clearance()) * m,
        rho: rack.fillet() * m,
        hs: rack.straight_depth() * m,
        sa,
        ca,
    }
}

/// The tip corners `[left, right]` of every tooth of [`generate_relieved_on`]'s outline with the
/// same arguments, body frame, mm.
pub(super) fn rack_tip_corners(
    blank: &GearBlank<'_>,
    relief_mm: &[f64],
) -> Result<Vec<[Point; 2]>, TeethError> {
    let p = blank.validated_pitch_mm()?;
    let (opts, g) = (
        &blank.opts,
        rack_gen(blank.frame, &blank.rack, blank.module_mm),
    );
    (0..blank.z as usize)
        .map(|k| {
            let (rel, _, (_, ul), (_, ur)) = g.trim_tooth(k, p, opts, relief_mm)?;
            Ok([g.tip(ul, rel), g.tip(ur, rel)])
        })
        .collect()
}

/// Solves `flank(s) = tip(u)` by 2-D Newton (forward-difference Jacobian, step 1e-6) from
/// `(s, u)`; `None` if it does not converge to 1e-9 mm.
pub(super) fn meet(
    flank: impl Fn(f64) -> Point,
    tip: impl Fn(f64) -> Point,
    mut s: f64,
    mut u: f64,
) -> Option<(f64, f64)> {
    for _ in 0..50 {
        let q = flank(s);
        let t = tip(u);
        let r = q - t;
        if r.hypot() < 1e-13 {
            return Some((s, u));
        }
        let h = 1e-6;
        let qs = flank(s + h);
        let tu = tip(u + h);
        let a = (qs - q) / h;
        let b = -(tu - t) / h;
        let det = a.cross(b);
        if det.abs() < 1e-300 {
            return None;
        }
        let ds = r.cross(b) / det;
        let du = a.cross(r) / det;
        s -= ds;
        u -= du;
        if !(s.is_finite() && u.is_finite()) {
            return None;
        }
    }
    let q = flank(s);
    let t = tip(u);
    (q.distance(t) < 1e-9).then_some((s, u))
}

/// Samples `f` on `(from, to]` with about `step_mm` between vertices into `out`; returns the
/// number of vertices pushed `n` (vertex k at parameter `from + (to − from)·k/n`).
pub(super) fn push_piece(
    out: &mut Vec<Point>,
    from: f64,
    to: f64,
    step_mm: f64,
    f: impl Fn(f64) -> Point,
) -> usize {
    // Estimate the spatial length with 8 chords, then sample uniformly in the parameter.
    let mut len = 0.0;
    let mut prev = f(from);
    for k in 1..=8 {
        let q = f(from + (to - from) * k as f64 / 8.0);
        len += q.distance(prev);
        prev = q;
    }
    let n = ((len / step_mm).ceil() as usize).clamp(2, 1_000_000);
    // Start vertex excluded: pieces join exactly, each piece emits (from, to].
    for k in 1..=n {
        out.push(f(from + (to - from) * k as f64 / n as f64));
    }
    n
}

/// The rack-generated outline of `blank`'s `z` teeth of module `module_mm`
/// (docs/math/teeth.md §12.3; [`super::Generation::Rack`]).
///
/// Requirements: `L = z·π·m` to within 1e-6 relative (scale the curve with
/// [`super::tooth_count`] first); the curve convex along every generating range; no undercut
/// when `refuse_undercut`. Otherwise a typed error: [`TeethError::Concave`] (a rack cannot cut a
/// concave arc) or [`TeethError::Undercut`] with the largest module that works.
///
/// Guarantees: the outline is the exact rack envelope sampled with chord sag ≤ `chord_tol_mm`
/// (for curvature radii ≥ m on flanks), closed, CCW, no duplicate end vertex.
/// Complexity: O(number of vertices).
pub(super) fn generate_on(blank: &GearBlank<'_>) -> Result<Outline, TeethError> {
    generate_relieved_on(blank, &[])
}

/// [`generate_on`] with tooth `k`'s tip lowered by `relief_mm[k]` along the pitch curve's normal
/// (mm; none where the slice is shorter): the relief that keeps each tip off its mates'
/// fillets ([`super::tip_relief`]).
pub(super) fn generate_relieved_on(
    blank: &GearBlank<'_>,
    relief_mm: &[f64],
) -> Result<Outline, TeethError> {
    let (z, m, opts) = (blank.z, blank.module_mm, &blank.opts);
    let p = blank.validated_pitch_mm()?;
    let mut report = report_on(blank);
    refuse_uncuttable(&report, z, m, opts.refuse_undercut)?;
    let g = rack_gen(blank.frame, &blank.rack, m);
    let walk = Walk::new(&g, opts.chord_tol_mm, m);
    // Rack tip flat between the two fillet centres.
    let flat = p
        - (p * 0.5 - opts.thin_left_mm - opts.thin_right_mm)
        - 2.0 * (g.hs * walk.ta + g.rho * g.ca);
    if flat <= 0.0 {
        return Err(TeethError::NoRackTipFlat { flat_mm: flat });
    }
    let mut out = Vec::new();
    for k in 0..z as usize {
        let sk = opts.phase_mm + k as f64 * p;
        let (rel, (sl, sr), (s_tip_l, ul), (s_tip_r, ur)) = g.trim_tooth(k, p, opts, relief_mm)?;
        let form_l = g.left_side(&walk, sl, s_tip_l, report.flanks[2 * k].undercut, &mut out);
        push_piece(&mut out, ul, ur, walk.step, |u| g.tip(u, rel));
        let undercut_r = report.flanks[2 * k + 1].undercut;
        let (form_r, xcr) = g.right_side(&walk, sr, s_tip_r, undercut_r, &mut out);
        let root = form_l.0.distance(form_r.0);
        for (f, depth) in [(2 * k, form_l.1), (2 * k + 1, form_r.1)] {
            let fl = &mut report.flanks[f];
            fl.form_depth_mm = depth;
            fl.contact_ratio_loss = (g.hs - depth).max(0.0) / (std::f64::consts::PI * m * walk.sc);
            fl.root_thickness_mm = Some(root);
        }
        let next_sl = sk + p - 0.25 * p + opts.thin_left_mm;
        let next_xcl = next_sl - g.hs * walk.ta - g.rho * g.ca;
        push_piece(&mut out, xcr, next_xcl, walk.step, |s| g.map(s, s, -g.hf));
    }
    close_outline(&mut out);
    report.summarize();
    Ok(Outline {
        points_mm: out,
        z,
        module_mm: m,
        undercut: report,
    })
}

/// [`TeethError::Concave`] when a flank's generating range is concave (a rack cannot cut it);
/// [`TeethError::Undercut`] when a flank is undercut and `refuse_undercut`, with the largest
/// module that works and the smallest tooth count at module `m` (mm) for `z` teeth.
fn refuse_uncuttable(
    report: &UndercutReport,
    z: u32,
    m: f64,
    refuse_undercut: bool,
) -> Result<(), TeethError> {
    if let Some(f) = report.flanks.iter().find(|f| f.concave) {
        return Err(TeethError::Concave {
            tooth: f.tooth,
            min_rho_mm: report.min_rho_mm,
        });
    }
    if report.undercut_count > 0 && refuse_undercut {
        let worst = report
            .flanks
            .iter()
            .max_by(|a, b| a.undercut_mm.total_cmp(&b.undercut_mm))
            .map_or((0, 0.0), |f| (f.tooth, f.undercut_mm));
        return Err(TeethError::Undercut {
            count: report.undercut_count,
            worst_tooth: worst.0,
            depth_mm: worst.1,
            max_module_mm: report.max_module_mm,
            min_teeth: (f64::from(z) * m / report.max_module_mm).ceil() as u32,
        });
    }
    Ok(())
}

/// How the rack's pieces are sampled: vertex spacing on flanks, root and tip (`step`) and on
/// the fillets (`step_f`) for chord sag ≤ the chord tolerance, mm; the fillet's span along the
/// rack, mm; `sin α cos α` and `tan α`.
struct Walk {
    step: f64,
    step_f: f64,
    fillet_span: f64,
    sc: f64,
    ta: f64,
}

/// The chord length whose sag on an arc of radius `radius_mm` is `chord_tol_mm`,
/// `√(8·tol·r)` (mm), the radius taken at least the tolerance: an arc tighter than that lies
/// within the tolerance of one chord, and a vanishing radius (a sharp cutter tip, ρf* → 0) must
/// not drive the step, and the number of points, towards zero and infinity.
pub(super) fn chord_step_mm(chord_tol_mm: f64, radius_mm: f64) -> f64 {
    (8.0 * chord_tol_mm * radius_mm.max(chord_tol_mm)).sqrt()
}

/// The chord step of a generated fillet or corner piece `f` over `[from, to]` (mm) made by a tool
/// corner of radius `rho_mm`: the fillet's radius of curvature is the tool's plus that of the
/// path the corner's centre rolls out, so the tool's radius is a lower bound; a corner near
/// sharp (ρ → 0, a cutter whose corner the rack's zero fillet leaves no room for) instead takes a
/// quarter of the tightest radius measured on 16 chords of the piece (a quarter: a margin for a
/// spot between the chords). Without the second bound a vanishing ρ asks for billions of points.
pub(super) fn fillet_step_mm(
    chord_tol_mm: f64,
    rho_mm: f64,
    from: f64,
    to: f64,
    f: impl Fn(f64) -> Point,
) -> f64 {
    let pts: Vec<Point> = (0..=16)
        .map(|k| f(from + (to - from) * f64::from(k) / 16.0))
        .collect();
    let tightest = pts
        .windows(3)
        .map(|w| circumradius_mm(w[0], w[1], w[2]))
        .fold(f64::INFINITY, f64::min);
    chord_step_mm(chord_tol_mm, rho_mm.max(0.25 * tightest).min(f64::MAX))
}

/// Radius of the circle through three points, mm (infinite when they are collinear or two
/// coincide): `|ab|·|bc|·|ca| / (2·|ab × ac|)`.
fn circumradius_mm(a: Point, b: Point, c: Point) -> f64 {
    let area2 = (b - a).cross(c - a).abs();
    if area2 == 0.0 {
        return f64::INFINITY;
    }
    a.distance(b) * b.distance(c) * c.distance(a) / (2.0 * area2)
}

impl Walk {
    fn new(g: &Gen<'_>, chord_tol_mm: f64, m: f64) -> Self {
        let ta = g.sa / g.ca;
        let step = chord_step_mm(chord_tol_mm, m);
        Self {
            step,
            step_f: if g.rho > 0.0 {
                chord_step_mm(chord_tol_mm, g.rho)
            } else {
                step
            },
            fillet_span: (g.hf - g.rho) / ta,
            sc: g.sa * g.ca,
            ta,
        }
    }
}

/// Drops exact duplicate vertices (and a last vertex equal to the first): the outline starts at
/// tooth 0's left fillet and closes implicitly.
pub(super) fn close_outline(out: &mut Vec<Point>) {
    out.dedup_by(|a, b| a.distance(*b) < 1e-12);
    if let (Some(f), Some(l)) = (out.first(), out.last())
        && f.distance(*l) < 1e-12
    {
        out.pop();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A corner piece is sampled at the radius it has: the tool's radius when that is the larger,
    /// else a quarter of the tightest radius measured on the piece — never the vanishing radius
    /// of a sharp tool; a straight piece takes one chord.
    #[test]
    fn a_fillet_piece_takes_the_step_of_its_own_curvature() {
        let tol = 1e-6;
        let arc = |t: f64| Point::from_polar(2.0, t);
        let sharp = fillet_step_mm(tol, 1e-15, 0.0, 1.0, arc);
        assert!((sharp - (8.0 * tol * 0.5_f64).sqrt()).abs() < 1e-9 * sharp);
        let round = fillet_step_mm(tol, 3.0, 0.0, 1.0, arc);
        assert!((round - (8.0 * tol * 3.0_f64).sqrt()).abs() < 1e-12);
        let line = fillet_step_mm(tol, 0.0, 0.0, 1.0, |t| Point::new(t, 2.0 * t));
        assert!(line > 1e100);
        assert!((chord_step_mm(tol, 0.0) - (8.0 * tol * tol).sqrt()).abs() < 1e-18);
    }
}
