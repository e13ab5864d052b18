//! The tooth form factor `Y_F` and the stress correction factor `Y_S` of ISO 6336-3 (method B),
//! read off a generated outline tooth by tooth — the real root of every tooth of a non-circular
//! gear, not the closed form of a circular one.
//!
//! Each tooth k is seen in its own frame: the origin at its centre on the pitch curve `P(s_k)`,
//! `x` along the tangent `T(s_k)`, `y` along the outward normal `N(s_k)` (the tooth's centre
//! line). Its two sides are the outline from the tip to the middle of the neighbouring spaces.
//!
//! - **Critical section** (ISO 6336-3, the 30° tangent rule; 60° for a concave stretch, which
//!   cuts like an internal gear): on each side, the point of the root fillet where the tangent
//!   makes the angle with the centre line, found on the polyline from the root up and placed on
//!   the circle through the three vertices around it, whose radius is the fillet radius `ρ_F`.
//!   `s_Fn` is the chord between the two points.
//! - **Load point**: on the loaded flank, at the height `h_en` above the pitch circle of the local
//!   equivalent gear where method B applies the load (the outer point of single pair contact,
//!   [`super::equivalent`]); heights are measured from the osculating circle of the pitch curve
//!   at the tooth centre, `h = sign(ρ)·(|Q − C| − |ρ|)`, `C = (0, −ρ)`. The force acts along the
//!   flank normal there, into the tooth; it meets the centre line at `y_int`, and
//!   `h_Fe = y_int − y_crit`, `cos α_Fen = |f_x|`.
//! - `Y_F = 6·(h_Fe/m)·cos α_Fen / ((s_Fn/m)²·cos α)`,
//!   `Y_S = (1.2 + 0.13·L)·q_s^(1/(1.21 + 2.3/L))`, `L = s_Fn/h_Fe`, `q_s = s_Fn/(2ρ_F)` (ρ_F of the
//!   loaded side, whose root is in tension); ISO gives Y_S for `1 ≤ q_s < 8`.

use crate::math::Point;
use crate::teeth::ArcFrame;

/// One side of a tooth, in the tooth's frame.
#[derive(Debug, Clone, PartialEq)]
struct Side {
    /// The outline from the tip down to the middle of the space, mm.
    profile: Vec<Point>,
    /// The critical point (the fillet's tangent at the critical angle), mm.
    critical: Point,
    /// Fillet radius there, mm.
    rho_f_mm: f64,
    /// +1 right (larger s), −1 left.
    hand: f64,
}

/// One tooth.
#[derive(Debug, Clone, PartialEq)]
struct Tooth {
    /// `[left, right]`.
    sides: [Side; 2],
    /// Signed radius of curvature of the pitch curve at the tooth centre, mm.
    rho_mm: f64,
}

/// Steepest inclination to the centre line of a step that counts as flank, rad (60°): the top
/// land and the tip corner are flatter.
const FLANK_INCLINATION_RAD: f64 = std::f64::consts::FRAC_PI_3;

/// Which flank carries the load.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Flank {
    /// The flank facing smaller arc lengths.
    Left,
    /// The flank facing larger arc lengths.
    Right,
}

/// The factors of one tooth under one load (mm, rad).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FormFactors {
    /// Tooth form factor Y_F.
    pub y_f: f64,
    /// Stress correction factor Y_S.
    pub y_s: f64,
    /// Root chord at the critical section, mm.
    pub s_fn_mm: f64,
    /// Bending moment arm, mm.
    pub h_fe_mm: f64,
    /// Fillet radius at the critical point of the loaded side, mm.
    pub rho_f_mm: f64,
    /// Load direction angle α_Fen, rad.
    pub alpha_fen_rad: f64,
    /// Notch parameter `q_s = s_Fn/(2ρ_F)`.
    pub q_s: f64,
}

/// The teeth of one gear, indexed by their centres on the pitch curve.
#[derive(Debug, Clone)]
pub struct GearTeeth {
    teeth: Vec<Tooth>,
    phase_mm: f64,
    pitch_mm: f64,
    module_mm: f64,
    alpha_rad: f64,
}

/// Circle through three points: centre and radius (`None` when they are collinear).
fn circle(a: Point, b: Point, c: Point) -> Option<(Point, f64)> {
    let (ab, ac) = (b - a, c - a);
    let d = 2.0 * ab.cross(ac);
    if d.abs() < 1e-14 * ab.norm_squared().max(ac.norm_squared()) {
        return None;
    }
    let centre = a + Point::new(
        ac.y * ab.norm_squared() - ab.y * ac.norm_squared(),
        ab.x * ac.norm_squared() - ac.x * ab.norm_squared(),
    ) / d;
    Some((centre, centre.distance(a)))
}

/// The angle of a root-to-tip step `d` with the centre line, rad (90° on a root floor, 0 on a
/// radial flank), on the side of `hand`.
fn inclination(d: Point, hand: f64) -> f64 {
    (-hand * d.x).atan2(d.y)
}

/// The critical point of one side's profile (tip → root) at the angle `crit` (rad).
fn critical_point(profile: &[Point], hand: f64, crit: f64) -> Option<(Point, f64)> {
    let n = profile.len();
    // From the root up: the first step whose inclination falls to the critical angle.
    let j = (0..n.saturating_sub(1))
        .rev()
        .find(|&j| inclination(profile[j] - profile[j + 1], hand) <= crit)?;
    // The crossing is at the vertex j + 1 between the steep step j and the flatter step j + 1.
    let mid = (j + 1).min(n - 2).max(1);
    let (a, b, c) = (profile[mid - 1], profile[mid], profile[mid + 1]);
    let (centre, radius) = circle(a, b, c)?;
    // On that circle, the point whose root-to-tip tangent has the critical inclination.
    let u = Point::new(crit.cos(), hand * crit.sin());
    let candidates = [centre + u * radius, centre - u * radius];
    let q = if candidates[0].distance(b) <= candidates[1].distance(b) {
        candidates[0]
    } else {
        candidates[1]
    };
    let reach = a.distance(b).max(b.distance(c)) * 2.0;
    if q.distance(b) <= reach {
        Some((q, radius))
    } else {
        Some((b, radius))
    }
}

impl GearTeeth {
    /// The teeth of an outline (`points_mm`, CCW, body frame) cut on `frame` with `z` teeth of
    /// module `module_mm`, tooth 0 centred at arc `phase_mm`, rack pressure angle `alpha_rad`.
    ///
    /// # Errors
    /// The tooth whose sides or critical section cannot be found, and why.
    pub fn new(
        points_mm: &[Point],
        frame: &ArcFrame,
        z: u32,
        module_mm: f64,
        phase_mm: f64,
        alpha_rad: f64,
    ) -> Result<Self, String> {
        let n = points_mm.len();
        let pitch = frame.length_mm() / f64::from(z);
        let mut by_angle: Vec<(f64, usize)> = points_mm
            .iter()
            .enumerate()
            .map(|(i, p)| (p.atan2(), i))
            .collect();
        by_angle.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut teeth = Vec::with_capacity(z as usize);
        for k in 0..z {
            let s = phase_mm + pitch * f64::from(k);
            let f = frame.at(s);
            let tip = f.p + f.n * module_mm;
            // The outline vertex nearest the tooth's tip centre, among those near its polar angle.
            let th = tip.atan2();
            let window = 0.5 * pitch / f.p.norm();
            let near = |a: f64| by_angle.partition_point(|v| v.0 < a);
            let mut best = (f64::INFINITY, usize::MAX);
            for wrap in [-std::f64::consts::TAU, 0.0, std::f64::consts::TAU] {
                let (lo, hi) = (near(th - window + wrap), near(th + window + wrap));
                for &(_, i) in &by_angle[lo..hi] {
                    let d = points_mm[i].distance(tip);
                    if d < best.0 {
                        best = (d, i);
                    }
                }
            }
            let start = best.1;
            if start == usize::MAX {
                return Err(format!("tooth {k}: no outline vertex near its tip"));
            }
            let local = |p: Point| Point::new((p - f.p).dot(f.t), (p - f.p).dot(f.n));
            let walk = |step: isize, hand: f64| -> Vec<Point> {
                let g = frame.at(s + hand * 0.5 * pitch);
                let mut out = Vec::new();
                let mut i = start as isize;
                for _ in 0..n {
                    let p = points_mm[i.rem_euclid(n as isize) as usize];
                    out.push(local(p));
                    if hand * (p - g.p).dot(g.t) >= 0.0 {
                        break;
                    }
                    i += step;
                }
                out
            };
            let crit = if f.kappa >= 0.0 { 30f64 } else { 60f64 }.to_radians();
            let side = |step: isize, hand: f64| -> Result<Side, String> {
                let profile = walk(step, hand);
                let (critical, rho_f_mm) =
                    critical_point(&profile, hand, crit).ok_or_else(|| {
                        format!(
                            "tooth {k}: no root fillet reaches the {:.0}° tangent on its {} side",
                            crit.to_degrees(),
                            if hand > 0.0 { "right" } else { "left" }
                        )
                    })?;
                Ok(Side {
                    profile,
                    critical,
                    rho_f_mm,
                    hand,
                })
            };
            let sides = [side(-1, -1.0)?, side(1, 1.0)?];
            let rho_mm = if f.kappa.abs() > 1e-12 {
                1.0 / f.kappa
            } else {
                1e12_f64.copysign(f.kappa)
            };
            teeth.push(Tooth { sides, rho_mm });
        }
        Ok(Self {
            teeth,
            phase_mm,
            pitch_mm: pitch,
            module_mm,
            alpha_rad,
        })
    }

    /// The tooth whose centre is nearest the arc position `s_mm` on the pitch curve.
    #[must_use]
    pub fn tooth_at(&self, s_mm: f64) -> usize {
        let z = self.teeth.len() as i64;
        let k = ((s_mm - self.phase_mm) / self.pitch_mm).round() as i64;
        k.rem_euclid(z) as usize
    }

    /// Tooth count.
    #[must_use]
    pub fn len(&self) -> usize {
        self.teeth.len()
    }

    /// No teeth (never, for a generated gear).
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.teeth.is_empty()
    }

    /// The factors of tooth `k` loaded on `flank` at the height `load_height_mm` above its local
    /// pitch circle (module docs; the tooth's top when the flank ends lower).
    #[must_use]
    pub fn form_factors(&self, k: usize, flank: Flank, load_height_mm: f64) -> FormFactors {
        let tooth = &self.teeth[k];
        let loaded = &tooth.sides[usize::from(flank == Flank::Right)];
        let rho = tooth.rho_mm;
        let height = |q: Point| {
            let d = (q.x * q.x + (q.y + rho) * (q.y + rho)).sqrt();
            rho.signum() * (q.x * q.x + q.y * q.y + 2.0 * q.y * rho) / (d + rho.abs())
        };
        let prof = &loaded.profile;
        // Past the top land and the tip corner: the first step steeper than 60°, then down the
        // flank to the load height.
        let steep = (0..prof.len() - 1)
            .find(|&j| inclination(prof[j] - prof[j + 1], loaded.hand) <= FLANK_INCLINATION_RAD)
            .unwrap_or(0);
        let j = (steep..prof.len() - 1)
            .find(|&j| height(prof[j + 1]) <= load_height_mm)
            .unwrap_or(prof.len() - 2);
        let (a, b) = (prof[j], prof[j + 1]);
        let (ha, hb) = (height(a), height(b));
        let t = if ha > hb {
            ((ha - load_height_mm) / (ha - hb)).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let load = a.lerp(b, t);
        let d = b - a;
        // The tooth frame (x along T, y along the outward N) is the body frame mirrored, so the
        // outline runs clockwise in it: the right side, walked with it from the tip down, has
        // the tooth on its right; the left side, walked against it, on its left.
        let outward = Point::new(-d.y, d.x) * loaded.hand / d.norm();
        let force = -outward;
        let [l, r] = &tooth.sides;
        let s_fn = l.critical.distance(r.critical);
        let y_crit = 0.5 * (l.critical.y + r.critical.y);
        let cos_fen = force.x.abs();
        let y_int = load.y - load.x * force.y / force.x;
        let h_fe = y_int - y_crit;
        let m = self.module_mm;
        let y_f = 6.0 * (h_fe / m) * cos_fen / ((s_fn / m).powi(2) * self.alpha_rad.cos());
        let big_l = s_fn / h_fe;
        let q_s = s_fn / (2.0 * loaded.rho_f_mm);
        let y_s = (1.2 + 0.13 * big_l) * q_s.powf(1.0 / (1.21 + 2.3 / big_l));
        FormFactors {
            y_f,
            y_s,
            s_fn_mm: s_fn,
            h_fe_mm: h_fe,
            rho_f_mm: loaded.rho_f_mm,
            alpha_fen_rad: cos_fen.min(1.0).acos(),
            q_s,
        }
    }
}
