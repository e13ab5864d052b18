//! Open (incomplete) sector pairs: teeth only where the law is given, over the
//! driver interval `[φs, φe]`, with clean sector ends and the verification over that interval.
//!
//! Method (written by hand: it is the sector geometry of our field, no crate does it):
//! 1. **Padding.** The law is used on `[u0, u1] = [φs − pad, φe + pad]`, `pad = 2.5` mean pitches
//!    of driver angle (`2.5·(φe − φs)/z`), so that the ±1.75-pitch window of the mesh check sees
//!    whole teeth at both ends of the active interval.
//! 2. **Carrier.** The padded law is closed into one driver turn: on the rest of the turn,
//!    `t ∈ [W, 2π]` (`t = φ − u0`, `W = u1 − u0`), the ratio is the quintic Hermite blend of
//!    `i, i', i''` at the two ends plus `c·64τ³(1 − τ)³` (`τ = (t − W)/(2π − W)`), with `c`
//!    chosen so that `∫ i dt = 2π/q` over the turn: the driven carrier closes after q driver
//!    turns and holds q copies of the sector, `q ≈ W/Δψ` so that the closing stretch turns at
//!    about the sector's mean ratio. The carrier is C² in the ratio, so its pitch curves are
//!    smooth and the ordinary machinery (rack or shaper process, undercut, mating phase)
//!    generates its teeth.
//! 3. **Scale.** The centre distance puts exactly `z` pitches `πm` on the active driver arc;
//!    each carrier takes as many whole teeth as fit, the last space absorbing the remainder
//!    ([`crate::teeth::OutlineOptions::open_pitch_mm`]) — it lies on the closing stretch and is
//!    trimmed away.
//! 4. **Trim.** Each outline keeps the teeth of the padded interval and is cut at two space
//!    centres (root, where the outline's polar angle is monotone), closed by radial lines and a
//!    hub circle one module below the lowest kept root: a star-shaped simple outline.
//! 5. **Check.** The trimmed fine outlines are rolled over the active interval
//!    ([`MeshSpan::Interval`]), both ends included.
use super::design::{PairDesign, PairOptions, PendingMesh, SectorReport, Toothed};
use super::{Expr, PairError};
use crate::geometry::pitch::PitchCurve;
use crate::math::Point;
use crate::math::roots::invert_increasing;
use crate::teeth::UndercutReport;
use crate::teeth::mesh::{MeshCheck, MeshSpan};
use std::f64::consts::{PI, TAU};

/// Padding beyond each end of the active interval, in mean pitches of driver angle.
const PAD_PITCHES: f64 = 2.5;
/// Smallest closing stretch of the carrier (driver and driven), rad: the padded sector may span
/// at most 2π − 45° of either gear.
const MIN_GAP_RAD: f64 = PI / 4.0;
/// Driver positions where the padded law's ratio is checked (> 0, finite), and where the
/// active interval's ratio range is sampled for the report.
const RATIO_CHECKS: u32 = 2048;
const RATIO_RANGE_SAMPLES: u32 = 512;
/// Gauss–Legendre pieces of the driver's arc-length integral (5 points each: the smooth speed is
/// integrated to rounding).
const ARC_PIECES: u32 = 256;

/// The padded law of an open sector in `t = φ − u0 ∈ [0, W]`: ψ̃(t) = ψ(u0 + t) − ψ(u0) and its
/// ratio with two derivatives.
struct Padded {
    psi: Expr,
    d1: Expr,
    d2: Expr,
    d3: Expr,
    u0: f64,
    width: f64,
    dpsi: f64,
}

impl Padded {
    /// Pads `[start, end]` (rad) by [`PAD_PITCHES`] mean pitches of `z` teeth and checks the
    /// spans and the ratio (module doc, step 1).
    fn new(e: &Expr, start: f64, end: f64, z: u32) -> Result<Self, PairError> {
        if !(start.is_finite() && end.is_finite() && end > start) {
            return Err(PairError::InvalidParameter {
                name: "open_sector_rad",
                value: end - start,
                expected: "a finite driver interval with end > start",
            });
        }
        let d1 = e.derivative();
        let d2 = d1.derivative();
        let d3 = d2.derivative();
        let pad = PAD_PITCHES * (end - start) / f64::from(z);
        let (u0, u1) = (start - pad, end + pad);
        let width = u1 - u0;
        let dpsi = e.eval(u1) - e.eval(u0);
        if width > TAU - MIN_GAP_RAD || !(dpsi > 0.0 && dpsi <= TAU - MIN_GAP_RAD) {
            return Err(PairError::Law(format!(
                "the open sector with its padding of {PAD_PITCHES} pitches at each end spans \
                 {:.2}° of the driver and {:.2}° of the driven gear; each must be > 0 and at \
                 most {:.0}°: shorten the interval or give more teeth",
                width.to_degrees(),
                dpsi.to_degrees(),
                (TAU - MIN_GAP_RAD).to_degrees()
            )));
        }
        for j in 0..=RATIO_CHECKS {
            let f = u0 + width * f64::from(j) / f64::from(RATIO_CHECKS);
            let i = d1.eval(f);
            if !(i.is_finite() && i > 0.0) {
                return Err(PairError::Law(format!(
                    "dψ/dφ = {i} at φ = {:.4}° (open sector with padding): it must be finite \
                     and > 0",
                    f.to_degrees()
                )));
            }
        }
        Ok(Self {
            psi: e.clone(),
            d1,
            d2,
            d3,
            u0,
            width,
            dpsi,
        })
    }

    /// ψ̃(t), rad.
    fn psi(&self, t: f64) -> f64 {
        self.psi.eval(self.u0 + t) - self.psi.eval(self.u0)
    }

    /// `[i, i', i'']` at `t`.
    fn ratio(&self, t: f64) -> [f64; 3] {
        let f = self.u0 + t;
        [self.d1.eval(f), self.d2.eval(f), self.d3.eval(f)]
    }

    /// The driver's pitch radius at the contact of `t` with `r`, `dr/dθ`, `d²r/dθ²` (body angle
    /// θ = −t), at unit centre distance: `r = i/(1 + i)`.
    fn driver_radius(&self, t: f64) -> [f64; 3] {
        let [i, i1, i2] = self.ratio(t);
        let u = 1.0 + i;
        [
            i / u,
            -i1 / (u * u),
            i2 / (u * u) - 2.0 * i1 * i1 / (u * u * u),
        ]
    }

    /// The driven pitch radius at the contact of `t` with `dr/dθ₂`, `d²r/dθ₂²` (body angle
    /// θ₂ = π + ψ̃), unit centre distance: `r = 1/(1 + i)`, `dθ₂/dt = i`.
    fn driven_radius(&self, t: f64) -> [f64; 3] {
        let [i, i1, i2] = self.ratio(t);
        let u = 1.0 + i;
        let g = -i1 / (i * u * u);
        let dg = -(i2 * i * u * u - i1 * i1 * u * (1.0 + 3.0 * i)) / (i * i * u.powi(4));
        [1.0 / u, g, dg / i]
    }

    /// Arc of the driver between the contacts of `t0` and `t1` (rad), unit centre distance:
    /// `ARC_PIECES` five-point Gauss pieces of `√(r² + r'²)`.
    fn driver_arc(&self, t0: f64, t1: f64) -> f64 {
        let speed = |t: f64| {
            let [r, dr, _] = self.driver_radius(t);
            r.hypot(dr)
        };
        let k = ARC_PIECES;
        let h = (t1 - t0) / f64::from(k);
        (0..k)
            .map(|j| gauss5(&speed, t0 + h * f64::from(j), t0 + h * f64::from(j + 1)))
            .sum::<f64>()
    }

    /// The closed carriers (driver, driven) at centre distance `a` (mm) from `n` polar samples
    /// each: the driver's contact of t at body angle −t (its sector [−W, 0]), the driven's at
    /// π + ψ̃(t) (its sector [π, π + Δψ]).
    fn carriers(&self, a: f64, n: usize) -> Result<(PitchCurve, PitchCurve), PairError> {
        let (w, dpsi) = (self.width, self.dpsi);
        let scaled = |v: [f64; 3]| v.map(|x| a * x);
        let c1 = carrier_curve(
            n,
            -w,
            w,
            &|x| a * self.driver_radius(w - x)[0],
            [
                scaled(self.driver_radius(0.0)),
                scaled(self.driver_radius(w)),
            ],
        )?;
        let c2 = carrier_curve(
            n,
            PI,
            dpsi,
            &|x| a * self.driven_radius(self.t_of_driven(x))[0],
            [
                scaled(self.driven_radius(w)),
                scaled(self.driven_radius(0.0)),
            ],
        )?;
        Ok((c1, c2))
    }

    /// `t` of the driven contact at body angle `π + x` for `x ∈ [0, Δψ]`.
    fn t_of_driven(&self, x: f64) -> f64 {
        let f = |t: f64| (self.psi(t), self.ratio(t)[0]);
        invert_increasing(f, x, 0.0, self.width, x / self.dpsi * self.width, 1e-14)
    }
}

/// A closed pitch curve (unit centre distance) from `n` uniform polar samples: on the sector
/// `[θ0, θ0 + span]` the law's radius `on(θ − θ0)`, on the rest the quintic Hermite blend of
/// `r, r', r''` between the sector's two ends (C², module doc step 2).
fn carrier_curve(
    n: usize,
    theta0: f64,
    span: f64,
    on: &dyn Fn(f64) -> f64,
    ends: [[f64; 3]; 2],
) -> Result<PitchCurve, PairError> {
    let gap = TAU - span;
    let [a, b] = ends;
    let (y0, y1) = (
        [a[0], a[1] * gap, a[2] * gap * gap],
        [b[0], b[1] * gap, b[2] * gap * gap],
    );
    let hermite = |t: f64| {
        let (t2, t3) = (t * t, t * t * t);
        let (t4, t5) = (t3 * t, t3 * t2);
        y0[0] * (1.0 - 10.0 * t3 + 15.0 * t4 - 6.0 * t5)
            + y0[1] * (t - 6.0 * t3 + 8.0 * t4 - 3.0 * t5)
            + y0[2] * 0.5 * (t2 - 3.0 * t3 + 3.0 * t4 - t5)
            + y1[0] * (10.0 * t3 - 15.0 * t4 + 6.0 * t5)
            + y1[1] * (-4.0 * t3 + 7.0 * t4 - 3.0 * t5)
            + y1[2] * 0.5 * (t3 - 2.0 * t4 + t5)
    };
    let r: Vec<f64> = (0..n)
        .map(|j| {
            let x = (TAU * j as f64 / n as f64 - theta0).rem_euclid(TAU);
            if x <= span {
                on(x)
            } else {
                hermite((x - span) / gap)
            }
        })
        .collect();
    if let Some(v) = r.iter().find(|v| !(v.is_finite() && **v > 0.0)) {
        return Err(PairError::Law(format!(
            "the open sector's pitch curve cannot be closed smoothly (radius {v} on the closing \
             stretch): shorten the interval"
        )));
    }
    PitchCurve::from_uniform_radii(r).map_err(|e| PairError::Law(e.to_string()))
}

/// 5-point Gauss–Legendre quadrature of `f` over `[a, b]`.
fn gauss5(f: &dyn Fn(f64) -> f64, a: f64, b: f64) -> f64 {
    const X: [f64; 5] = [
        0.0,
        -0.538_469_310_105_683,
        0.538_469_310_105_683,
        -0.906_179_845_938_664,
        0.906_179_845_938_664,
    ];
    const W: [f64; 5] = [
        0.568_888_888_888_889,
        0.478_628_670_499_366,
        0.478_628_670_499_366,
        0.236_926_885_056_189,
        0.236_926_885_056_189,
    ];
    let (h, m) = (0.5 * (b - a), 0.5 * (a + b));
    h * X.iter().zip(W).map(|(x, w)| w * f(m + h * x)).sum::<f64>()
}

/// Designs the open sector pair of the motion law `e` over the driver interval `range` (rad),
/// The error of an open sector too narrow for its teeth: the `what` carrier (spanning `span`
/// rad with padding) would carry `teeth` on a whole turn.
fn carrier_too_large(what: &str, teeth: f64, span_rad: f64) -> crate::bounds::OutOfBounds {
    crate::bounds::OutOfBounds {
        quantity: format!("teeth on a whole turn of the {what} carrier"),
        value: format!("{teeth:.0}"),
        range: format!("≤ {}", crate::bounds::MAX_TEETH),
        why: format!(
            "the open sector spans {:.4e}° of the {what} with its padding, so its teeth repeated \
             round a turn make that many: widen the interval (--drive-start..--drive-end) or \
             give fewer teeth",
            span_rad.to_degrees()
        ),
    }
}

/// `opts.teeth` teeth on the active interval (module doc).
pub(super) fn design_open(
    e: &Expr,
    range: [f64; 2],
    opts: &PairOptions,
) -> Result<(PairDesign, Option<PendingMesh>), PairError> {
    let t = &opts.toothing;
    let m = t.module_mm;
    let z = opts.teeth.ok_or(PairError::InvalidParameter {
        name: "teeth",
        value: 0.0,
        expected: "the tooth count of the active interval of an open sector",
    })?;
    crate::bounds::check_teeth("teeth", z)?;
    let law = Padded::new(e, range[0], range[1], z)?;
    // Each carrier is a whole pitch curve with the sector's teeth on part of it: its tooth
    // count grows as the interval narrows (a 1e-9° interval would ask for ~1e13 teeth). An
    // estimate from the spans, before any curve is built; the exact count is checked below.
    for (what, span) in [("driver", law.width), ("driven", law.dpsi)] {
        let full = (f64::from(z) + 2.0 * PAD_PITCHES) * TAU / span;
        if !(full <= f64::from(crate::bounds::MAX_TEETH)) {
            return Err(carrier_too_large(what, full, span).into());
        }
    }
    let (ta, tb) = (range[0] - law.u0, range[1] - law.u0);
    let p = PI * m;
    // Exactly z pitches πm on the active driver arc.
    let a = f64::from(z) * p / law.driver_arc(ta, tb);
    let (c1, c2) = law.carriers(a, opts.samples)?;
    // Whole teeth that fit on each carrier (the remainder is the closing space, trimmed away).
    let fit = |c: &PitchCurve| (c.perimeter_mm(1e-12 * a) / p * (1.0 - 1e-12)).floor() as u32;
    let counts = [fit(&c1), fit(&c2)];
    for (what, n, span) in [
        ("driver", counts[0], law.width),
        ("driven", counts[1], law.dpsi),
    ] {
        if n > crate::bounds::MAX_TEETH {
            return Err(carrier_too_large(what, f64::from(n), span).into());
        }
    }
    let g = Toothed::new((c1, c2), 0.0, counts, Some(p), None, opts)?;
    let cuts = Cuts::new(&g, &law, a, m);
    let mesh = if t.verify_steps > 0 {
        let [v1, v2] = g.fine_outlines(opts, None)?;
        let tol = t.verify_chord_tol_mm;
        let v1 = sector_outline(&v1, cuts.driver, cuts.hubs[0], tol);
        let v2 = sector_outline(&v2, cuts.driven, cuts.hubs[1], tol);
        let check = MeshCheck {
            steps: ((t.verify_steps as f64 * (tb - ta) / TAU).ceil() as usize + 1).max(2),
            span: MeshSpan::Interval {
                start_rad: ta,
                end_rad: tb,
            },
            backlash_mm: t.backlash_mm,
            ..MeshCheck::new(a, m)
        };
        Some(([v1, v2], check))
    } else {
        None
    };
    let active_advance = e.eval(range[1]) - e.eval(range[0]);
    let ratios: Vec<f64> = (0..=RATIO_RANGE_SAMPLES)
        .map(|j| law.ratio(ta + (tb - ta) * f64::from(j) / f64::from(RATIO_RANGE_SAMPLES))[0])
        .collect();
    let n_teeth = g.z[0];
    let report = SectorReport {
        drive_deg: [range[0].to_degrees(), range[1].to_degrees()],
        driven_advance_deg: active_advance.to_degrees(),
        active_teeth: a * law.driver_arc(ta, tb) / p,
        kept_teeth: [cuts.k_end.saturating_sub(1), cuts.k_end],
        hub_radius_mm: cuts.hubs,
        assembly_at_deg: law.u0.to_degrees(),
    };
    let mut d = g.into_design([0.0, active_advance], a, None, &ratios, Some(report));
    cuts.trim(&mut d, n_teeth, t.chord_tol_mm);
    // The check runs in t = φ − u0; its report gives the driver angle φ.
    let at_offset_deg = law.u0.to_degrees();
    let pending = mesh.map(|(outlines, check)| PendingMesh {
        outlines,
        psi: Box::new(move |t| law.psi(t)),
        check,
        at_offset_deg,
    });
    Ok((d, pending))
}

/// Where an open pair's carriers are cut to their sectors: the driver's and the driven body
/// angles `[from, to]` (rad), the hub radii (mm) and the padded arc's pitch count `K`.
struct Cuts {
    driver: [f64; 2],
    driven: [f64; 2],
    hubs: [f64; 2],
    k_end: u32,
}

impl Cuts {
    /// The cuts of `g` (module `m`, centre distance `a`, mm). The driver's teeth are centred at
    /// s = −j·p (tooth N − 1 − j), the contacts of t > 0 lie at negative arc length, spaces at
    /// −(j + ½)p: kept j = 1..K−1 of the padded arc. The driven gear's spaces face driver teeth,
    /// so it is cut where driver teeth 0 and K touch.
    fn new(g: &Toothed, law: &Padded, a: f64, m: f64) -> Self {
        let p = PI * m;
        let k_end = (a * law.driver_arc(0.0, law.width) / p).floor() as u32;
        let f1 = &g.f[0];
        let driver = [
            f1.theta_at(-(f64::from(k_end) - 0.5) * p),
            f1.theta_at(-0.5 * p),
        ];
        let t_at = |s: f64| (-f1.theta_at(s)).rem_euclid(TAU);
        let driven = [PI, PI + law.psi(t_at(-f64::from(k_end) * p))];
        let hub = |pts: &[Point], cut: [f64; 2]| {
            let r = kept_min_radius(pts, cut);
            (r - m).max(0.5 * r)
        };
        let hubs = [
            hub(&g.driver.points_mm, driver),
            hub(&g.driven.points_mm, driven),
        ];
        Self {
            driver,
            driven,
            hubs,
            k_end,
        }
    }

    /// Trims the closed carriers' design `d` (driver of `n_teeth` teeth) to the sectors: the
    /// outlines (at chord tolerance `chord_mm`), the tooth counts, the flanks and the pitch
    /// curves kept.
    fn trim(&self, d: &mut PairDesign, n_teeth: u32, chord_mm: f64) {
        let kept_driver: Vec<usize> = (1..self.k_end)
            .map(|j| (n_teeth - 1 - j) as usize)
            .collect();
        let kept_driven: Vec<usize> = (0..self.k_end as usize).collect();
        d.driver.points_mm =
            sector_outline(&d.driver.points_mm, self.driver, self.hubs[0], chord_mm);
        d.driven.points_mm =
            sector_outline(&d.driven.points_mm, self.driven, self.hubs[1], chord_mm);
        d.z = kept_driver.len() as u32;
        d.z_driven = kept_driven.len() as u32;
        d.driver.z = d.z;
        d.driven.z = d.z_driven;
        keep_flanks(&mut d.driver_undercut, &kept_driver);
        keep_flanks(&mut d.driven_undercut, &kept_driven);
        d.driver.undercut = d.driver_undercut.clone();
        d.driven.undercut = d.driven_undercut.clone();
        d.driver_pitch_mm = within(&d.driver_pitch_mm, self.driver);
        d.driven_pitch_mm = within(&d.driven_pitch_mm, self.driven);
    }
}

/// `x` polar angle relative to `from`, in `[0, 2π)`.
fn rel_angle(p: Point, from: f64) -> f64 {
    (p.atan2() - from).rem_euclid(TAU)
}

/// Points of `pts` whose polar angle lies in the CCW interval `cut = [from, to]`.
fn within(pts: &[Point], cut: [f64; 2]) -> Vec<Point> {
    let w = (cut[1] - cut[0]).rem_euclid(TAU);
    pts.iter()
        .copied()
        .filter(|p| rel_angle(*p, cut[0]) <= w)
        .collect()
}

/// Smallest radius of the outline within the CCW polar interval `cut`, mm.
fn kept_min_radius(pts: &[Point], cut: [f64; 2]) -> f64 {
    within(pts, cut)
        .iter()
        .map(|p| p.hypot())
        .fold(f64::INFINITY, f64::min)
}

/// Keeps the flanks of the kept teeth and recounts the report.
fn keep_flanks(u: &mut UndercutReport, teeth: &[usize]) {
    u.flanks.retain(|f| teeth.contains(&f.tooth));
    u.summarize();
}

/// The sector outline: the run of the closed CCW star-shaped outline `pts` within the polar
/// interval `cut = [from, to]` (CCW), cut exactly on the two rays, closed by radial lines and the
/// hub circle of radius `hub_mm` (chord sag ≤ `chord_tol_mm`) around the rest of the turn.
fn sector_outline(pts: &[Point], cut: [f64; 2], hub_mm: f64, chord_tol_mm: f64) -> Vec<Point> {
    let n = pts.len();
    let w = (cut[1] - cut[0]).rem_euclid(TAU);
    let inside = |i: usize| rel_angle(pts[i % n], cut[0]) <= w;
    // First kept vertex: inside, its predecessor not.
    let Some(first) = (0..n).find(|&i| inside(i) && !inside(i + n - 1)) else {
        return pts.to_vec();
    };
    let on_ray = |a: Point, b: Point, th: f64| {
        let d = Point::new(th.cos(), th.sin());
        let den = (a - b).cross(d);
        let u = if den == 0.0 { 0.0 } else { a.cross(d) / den };
        a.lerp(b, u)
    };
    let mut out = vec![on_ray(pts[(first + n - 1) % n], pts[first], cut[0])];
    let mut i = first;
    while inside(i) && out.len() <= n {
        out.push(pts[i % n]);
        i += 1;
    }
    out.push(on_ray(pts[(i + n - 1) % n], pts[i % n], cut[1]));
    // Hub: from `to` CCW round to `from` + 2π, radial lines at both ends.
    let span = TAU - w;
    let steps = ((span / (8.0 * chord_tol_mm / hub_mm).sqrt()).ceil() as usize).max(2);
    for k in 0..=steps {
        let th = cut[1] + span * k as f64 / steps as f64;
        out.push(Point::new(hub_mm * th.cos(), hub_mm * th.sin()));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The radius derivatives of both carriers against central differences in their own body
    /// angle (driver θ = −t; driven θ₂ = π + ψ̃(t)).
    #[test]
    fn carrier_radius_derivatives_match_differences() {
        let e = Expr::parse("0.6*phi + 0.05*sin(phi) + 0.02*cos(3*phi)").unwrap();
        let law = Padded::new(&e, 0.5, 2.5, 10).unwrap();
        let h = 1e-4;
        for t in [0.3, 1.0, 2.0] {
            let d = |f: &dyn Fn(f64) -> f64, x: f64| (f(x + h) - f(x - h)) / (2.0 * h);
            let dd = |f: &dyn Fn(f64) -> f64, x: f64| (f(x + h) - 2.0 * f(x) + f(x - h)) / (h * h);
            let r1 = |th: f64| law.driver_radius(-th)[0];
            let v = law.driver_radius(t);
            assert!((v[1] - d(&r1, -t)).abs() < 1e-7, "{v:?}");
            assert!((v[2] - dd(&r1, -t)).abs() < 1e-5, "{v:?}");
            let r2 = |x: f64| law.driven_radius(law.t_of_driven(x))[0];
            let x = law.psi(t);
            let v = law.driven_radius(t);
            assert!((v[1] - d(&r2, x)).abs() < 1e-7, "{v:?} {}", d(&r2, x));
            assert!((v[2] - dd(&r2, x)).abs() < 1e-5, "{v:?} {}", dd(&r2, x));
        }
    }
}
