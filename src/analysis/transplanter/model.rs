//! Exact perturbed kinematics (flank-line contact, see the module docs of
//! [`super`]) and the linear sensitivity model built from it by central finite differences.

use super::{
    ARM, BACKLASH, ErrorVector, N_COORDS, PIN_A, PIN_D, TransplanterError, clock_index, ecc_index,
};
use crate::geometry::assembly::{Assembly, Rebuilt};
use crate::geometry::pitch::PitchCurve;
use crate::math::Point;
use crate::math::periodic::wrap_pi;
use rayon::prelude::*;
use std::f64::consts::{FRAC_PI_2, PI, TAU};

/// The unit vector `(cos a, sin a)` at angle `a`, rad.
fn e(a: f64) -> Point {
    Point::unit(a)
}

/// State of the perturbed arm at one carrier angle (world frame, mm and rad).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrainState {
    /// Carrier angle φH, rad (world).
    pub phi_h_rad: f64,
    /// Intermediate centre D (with its pin error), mm.
    pub intermediate_center_mm: Point,
    /// Planet centre A (with its pin error), mm.
    pub planet_center_mm: Point,
    /// Intermediate orientation θ2, rad (world sense).
    pub intermediate_angle_rad: f64,
    /// Planet orientation θ3, rad (world sense).
    pub planet_angle_rad: f64,
    /// Needle direction β = θ3 + γ + Δγ, rad (world sense).
    pub needle_angle_rad: f64,
    /// Needle tip, mm.
    pub tip_mm: Point,
}

/// The exact model of one arm with errors: a configured solver (see [`ExactModel::new`]).
#[derive(Debug, Clone)]
pub struct ExactModel {
    rebuilt: Rebuilt,
    center: Point,
    a: f64,
    l3: f64,
    alpha: f64,
    side: f64,
}

/// The contact on a driver: pitch point, line-of-action direction, driver parameter.
struct Contact {
    w: Point,
    n_loa: Point,
    v: f64,
}

/// A driving gear placed in the train, as [`ExactModel::contact`] sees it.
struct Driver<'a> {
    /// Its pitch curve.
    curve: &'a PitchCurve,
    /// Its centre, mm (train frame).
    center: Point,
    /// Its turn, rad.
    theta: f64,
    /// Its clocking error, rad (body frame).
    kappa: f64,
    /// Its eccentricity, mm (body frame).
    eps: Point,
}

impl ExactModel {
    /// Sets up the model of `assembly` with pressure angle `pressure_angle_rad` (5°…45°) and the
    /// loaded flank `load_side` (±1) of the sun–intermediate mesh.
    pub fn new(
        assembly: &Assembly,
        pressure_angle_rad: f64,
        load_side: i8,
    ) -> Result<Self, TransplanterError> {
        if !(pressure_angle_rad.is_finite()
            && (5f64.to_radians() - 1e-12..=45f64.to_radians() + 1e-12)
                .contains(&pressure_angle_rad))
        {
            return Err(TransplanterError::BadOption {
                option: "pressure_angle_rad",
                message: format!("{pressure_angle_rad} rad; expected 5°…45° (in radians)"),
            });
        }
        if !(load_side == 1 || load_side == -1) {
            return Err(TransplanterError::BadOption {
                option: "load_side",
                message: format!("{load_side}; expected 1 or -1"),
            });
        }
        Ok(Self {
            rebuilt: assembly.rebuild(),
            center: assembly.center_mm,
            a: assembly.a_mm,
            l3: assembly.l3_mm,
            alpha: pressure_angle_rad,
            side: f64::from(load_side),
        })
    }

    /// The driver's pitch point on the ray from its centre `c` along `u`: body point
    /// `R(κ)(r(v)e(v)) + ε`, world `c + R(θ)·body`; Newton on `cross(q(v), u) = 0` from
    /// `v = arg u − θ − κ`, to `tol_rad`. `sigma` (±1) is the loaded flank.
    fn contact(&self, driver: &Driver<'_>, u: Point, sigma: f64, tol_rad: f64) -> Option<Contact> {
        let &Driver {
            curve,
            center: c,
            theta,
            kappa,
            eps,
        } = driver;
        let ecc = eps.rotate(theta);
        let q = |v: f64| {
            let g = curve.geometry(v);
            let dir = v + theta + kappa;
            let p = e(dir) * g.r_mm + ecc;
            let dp = e(dir) * g.dr_mm + e(dir + FRAC_PI_2) * g.r_mm;
            (p, dp)
        };
        let mut v = u.y.atan2(u.x) - theta - kappa;
        let mut converged = false;
        for _ in 0..50 {
            let (p, dp) = q(v);
            let f = p.cross(u);
            let df = dp.cross(u);
            if !(df.is_finite() && df != 0.0) {
                return None;
            }
            // Damped: at most 0.5 rad per step, so that the iteration stays on the branch of
            // the ray `u` it started from (the start is within a few mrad of the root).
            let step = (f / df).clamp(-0.5, 0.5);
            v -= step;
            if step.abs() <= tol_rad {
                converged = true;
                break;
            }
        }
        let (p, dp) = q(v);
        if !converged || p.dot(u) <= 0.0 {
            return None;
        }
        let t = dp * (1.0 / dp.hypot());
        let mut n = Point::new(-t.y, t.x);
        if n.dot(u) < 0.0 {
            n = -n;
        }
        let n_loa = t * (sigma * self.alpha.cos()) + n * self.alpha.sin();
        Some(Contact { w: c + p, n_loa, v })
    }

    /// Driven angle: `(C_b + R(θ)p − W_a)·N = j/2`, the root nearer the pitch point facing `-u`.
    fn driven_angle(cb: Point, p: Point, contact: &Contact, j: f64, u: Point) -> Option<f64> {
        let c = (cb - contact.w).dot(contact.n_loa) - 0.5 * j;
        let pn = p.hypot();
        let x = -c / pn;
        if x.is_nan() || x.abs() > 1.0 {
            return None;
        }
        let base = contact.n_loa.y.atan2(contact.n_loa.x) - p.y.atan2(p.x);
        let guess = (-u.y).atan2(-u.x) - p.y.atan2(p.x);
        let acos = x.acos();
        let near = |cand: f64| cand + TAU * ((guess - cand) / TAU).round();
        let (r1, r2) = (near(base + acos), near(base - acos));
        Some(if (r1 - guess).abs() <= (r2 - guess).abs() {
            r1
        } else {
            r2
        })
    }

    /// State of the arm at world carrier angle `phi_h_rad` with errors `x` (mm, rad; see
    /// [`super::COORD_NAMES`]).
    pub fn state(&self, phi_h_rad: f64, x: &ErrorVector) -> Result<TrainState, TransplanterError> {
        let r = &self.rebuilt;
        let s = r.sign();
        let phi = s * phi_h_rad;
        let [sun, mid, planet] = r.ccw_curves();
        let eps = |k: usize| Point::new(x[ecc_index(k)], x[ecc_index(k) + 1]);
        let kappa = |k: usize| x[clock_index(k)];
        let no_contact = |mesh: &'static str| TransplanterError::NoContact {
            mesh,
            carrier_deg: phi_h_rad.to_degrees(),
        };
        const TOL: f64 = 1e-14;
        // Mesh 1: sun (fixed, centre O) drives the intermediate, whose axis D sits at the idler
        // offset ε from the carrier line (its pin error radial and tangential to OD).
        let offset = r.ccw_idler_offset();
        let c2 =
            e(phi + offset) * (self.a + x[PIN_D[0]]) + e(phi + offset + FRAC_PI_2) * x[PIN_D[1]];
        let u12 = c2 * (1.0 / c2.hypot());
        let k1 = self
            .contact(
                &Driver {
                    curve: sun,
                    center: Point::ZERO,
                    theta: 0.0,
                    kappa: kappa(0),
                    eps: eps(0),
                },
                u12,
                self.side,
                TOL,
            )
            .ok_or_else(|| no_contact("sun–intermediate"))?;
        let w2 = r.ccw_sun_to_intermediate(k1.v);
        let p2 = e(w2 + kappa(1)) * mid.radius_mm(w2) + eps(1);
        let theta2 = Self::driven_angle(c2, p2, &k1, x[BACKLASH[0]], u12)
            .ok_or_else(|| no_contact("sun–intermediate"))?;
        // Mesh 2: intermediate drives the planet (opposite flank).
        let c3 = e(phi) * (r.l1_mm() + x[PIN_A[0]]) + e(phi + FRAC_PI_2) * x[PIN_A[1]];
        let d23 = c3 - c2;
        let u23 = d23 * (1.0 / d23.hypot());
        let k2 = self
            .contact(
                &Driver {
                    curve: mid,
                    center: c2,
                    theta: theta2,
                    kappa: kappa(1),
                    eps: eps(1),
                },
                u23,
                -self.side,
                TOL,
            )
            .ok_or_else(|| no_contact("intermediate–planet"))?;
        let w3 = r.ccw_intermediate_to_planet(k2.v);
        let p3 = e(w3 + kappa(2)) * planet.radius_mm(w3) + eps(2);
        let theta3 = Self::driven_angle(c3, p3, &k2, x[BACKLASH[1]], u23)
            .ok_or_else(|| no_contact("intermediate–planet"))?;
        let beta = theta3 + r.ccw_needle_angle() + x[ARM];
        let tip = c3 + e(beta) * self.l3;
        let o = self.center;
        let world = |p: Point| Point::new(o.x + p.x, o.y + s * p.y);
        let st = TrainState {
            phi_h_rad,
            intermediate_center_mm: world(c2),
            planet_center_mm: world(c3),
            intermediate_angle_rad: s * theta2,
            planet_angle_rad: s * theta3,
            needle_angle_rad: s * beta,
            tip_mm: world(tip),
        };
        if st.tip_mm.is_finite() && st.planet_angle_rad.is_finite() {
            Ok(st)
        } else {
            Err(TransplanterError::Numerical(format!(
                "non-finite state at carrier angle {:.3}°",
                phi_h_rad.to_degrees()
            )))
        }
    }

    /// World carrier angles of a uniform grid of `n` points over one turn, in travel order, rad.
    #[must_use]
    pub fn grid(&self, n: usize) -> Vec<f64> {
        let s = self.rebuilt.sign();
        (0..n).map(|k| s * TAU * k as f64 / n as f64).collect()
    }

    /// States at the carrier angles `phis` (rad).
    pub fn trace(
        &self,
        phis: &[f64],
        x: &ErrorVector,
    ) -> Result<Vec<TrainState>, TransplanterError> {
        phis.iter().map(|&p| self.state(p, x)).collect()
    }

    /// Tip deviations `B(φ; x) − B(φ; 0)` (mm, world) at `phis`.
    pub fn deviations(
        &self,
        phis: &[f64],
        x: &ErrorVector,
    ) -> Result<Vec<Point>, TransplanterError> {
        let zero = [0.0; N_COORDS];
        phis.iter()
            .map(|&p| {
                let a = self.state(p, x)?.tip_mm;
                let b = self.state(p, &zero)?.tip_mm;
                Ok(a - b)
            })
            .collect()
    }

    /// The carrier direction, ±1.
    #[must_use]
    pub fn sign(&self) -> f64 {
        self.rebuilt.sign()
    }

    /// The rebuilt nominal train.
    #[must_use]
    pub fn rebuilt(&self) -> &Rebuilt {
        &self.rebuilt
    }

    /// Half a turn in world angle, rad (arm 2 is arm 1 at φH + π).
    #[must_use]
    pub fn half_turn(&self) -> f64 {
        PI
    }
}

/// Finite-difference steps of the linear model; (de)serialised as
/// `{"length_mm": …, "angle_rad": …}` (a missing field takes its default, an unknown one is an
/// error).
#[derive(
    Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize, schemars::JsonSchema,
)]
#[serde(default, deny_unknown_fields)]
#[non_exhaustive]
pub struct FdSteps {
    /// Step of the length coordinates, mm (default 1e-3, 1 µm).
    pub length_mm: f64,
    /// Step of the angle coordinates, rad (default 1e-5).
    pub angle_rad: f64,
}

impl Default for FdSteps {
    fn default() -> Self {
        Self {
            length_mm: 1e-3,
            angle_rad: 1e-5,
        }
    }
}

/// `ΔB(φ) = Σ_j S_j(φ)·x_j`: the tip sensitivities (world mm per mm or per rad) on a φH grid.
#[derive(Debug, Clone)]
pub struct LinearModel {
    /// World carrier angles of the grid, rad.
    pub phis_rad: Vec<f64>,
    /// Nominal tip positions, mm.
    pub nominal_tips_mm: Vec<Point>,
    /// Per carrier angle, the column `S_j = ∂B/∂x_j` of every coordinate (mm per internal unit).
    pub jacobian: Vec<[Point; N_COORDS]>,
    /// Per carrier angle, `∂θ3/∂x_j`: the planet's angle error (the transmission error of
    /// docs/math/companion.md §C.6), rad per internal unit.
    pub planet_angle_jacobian: Vec<[f64; N_COORDS]>,
}

/// Nominal tip and sensitivity columns at one carrier angle.
type Row = (Point, [Point; N_COORDS], [f64; N_COORDS]);

fn is_angle(j: usize) -> bool {
    (6..9).contains(&j) || j == ARM
}

impl LinearModel {
    /// Central differences `S_j = (B(x_j = +h) − B(x_j = −h))/2h` of the exact model on `n`
    /// uniform carrier angles (parallel over the grid).
    pub fn build(model: &ExactModel, n: usize, steps: FdSteps) -> Result<Self, TransplanterError> {
        if n < 8 {
            return Err(TransplanterError::BadOption {
                option: "samples_per_turn",
                message: format!("{n}; at least 8"),
            });
        }
        if !(steps.length_mm > 0.0 && steps.angle_rad > 0.0) {
            return Err(TransplanterError::BadOption {
                option: "fd_steps",
                message: format!(
                    "length_mm = {}, angle_rad = {}: both must be positive",
                    steps.length_mm, steps.angle_rad
                ),
            });
        }
        let phis = model.grid(n);
        let rows: Result<Vec<Row>, TransplanterError> = phis
            .par_iter()
            .map(|&p| {
                let zero = [0.0; N_COORDS];
                let b0 = model.state(p, &zero)?.tip_mm;
                let mut cols = [Point::ZERO; N_COORDS];
                let mut ang = [0.0; N_COORDS];
                for (j, col) in cols.iter_mut().enumerate() {
                    let h = if is_angle(j) {
                        steps.angle_rad
                    } else {
                        steps.length_mm
                    };
                    let mut xp = zero;
                    xp[j] = h;
                    let mut xm = zero;
                    xm[j] = -h;
                    let sp = model.state(p, &xp)?;
                    let sm = model.state(p, &xm)?;
                    *col = (sp.tip_mm - sm.tip_mm) * (0.5 / h);
                    ang[j] = wrap_pi(sp.planet_angle_rad - sm.planet_angle_rad) * 0.5 / h;
                }
                Ok((b0, cols, ang))
            })
            .collect();
        let rows = rows?;
        Ok(Self {
            phis_rad: phis,
            nominal_tips_mm: rows.iter().map(|r| r.0).collect(),
            jacobian: rows.iter().map(|r| r.1).collect(),
            planet_angle_jacobian: rows.into_iter().map(|r| r.2).collect(),
        })
    }

    /// Tip deviation (mm, world) at grid point `i`.
    #[must_use]
    pub fn deviation_at(&self, i: usize, x: &ErrorVector) -> Point {
        let mut d = Point::ZERO;
        for (col, v) in self.jacobian[i].iter().zip(x) {
            d += *col * *v;
        }
        d
    }

    /// Tip deviations (mm) over the grid.
    #[must_use]
    pub fn deviations(&self, x: &ErrorVector) -> Vec<Point> {
        (0..self.phis_rad.len())
            .map(|i| self.deviation_at(i, x))
            .collect()
    }

    /// `max_φ |Δθ3(φ)|`: the planet's largest angle error over the grid, rad.
    #[must_use]
    pub fn max_planet_angle_error_rad(&self, x: &ErrorVector) -> f64 {
        self.planet_angle_jacobian
            .iter()
            .map(|row| row.iter().zip(x).map(|(s, v)| s * v).sum::<f64>().abs())
            .fold(0.0, f64::max)
    }

    /// `max_φ |ΔB(φ)|`, mm.
    #[must_use]
    pub fn max_deviation_mm(&self, x: &ErrorVector) -> f64 {
        (0..self.phis_rad.len())
            .map(|i| {
                let d = self.deviation_at(i, x);
                d.x.hypot(d.y)
            })
            .fold(0.0, f64::max)
    }
}
