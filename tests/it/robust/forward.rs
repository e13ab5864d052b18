//! An independent forward model of the planetary train with non-circular gears, and the seeded
//! case generator of the robustness suite.
//!
//! Shares no code with the crate (std + `rand` only). Physics, written from scratch:
//!
//! - The carrier turns about O, carrier angle φ = t (φ0 = 0). On the carrier: intermediate axis
//!   D = a·e(φ), planet axis A = 2a·e(φ).
//! - The fixed sun has the pitch curve r1(θ) in its body frame, rotated by φs in the world; the
//!   contact with the intermediate is on the ray O→D, at sun body angle u = φ − φs.
//! - Sun/intermediate mesh: i21(u) = r1(u)/(a − r1(u)); the intermediate turns relative to the
//!   carrier by ψ2 with dψ2/dt = i21(u) (CCW, opposite to the sun's apparent CW turn).
//!   Intermediate body angle of its sun-side contact: π − ψ2; radius there: a − r1(u). This is the
//!   intermediate's polar table (tabulated against u, inverted by Newton).
//! - Intermediate/planet mesh, integrated directly: the planet-side contact of the intermediate is
//!   its body point at angle −ψ2, i.e. the point that faced the sun half an intermediate turn
//!   away (ψ2' = ψ2 + π); its radius ρ comes from the table. The planet's contact polar angle χ
//!   advances with dχ/dt = ρ/(a − ρ)·dψ2/dt (rolling without slip). The state (ψ2, χ) is
//!   integrated with classical RK4.
//! - The planet is congruent to the sun: χ refers to the same r1 table (χ(0) is the sun angle
//!   whose point has the planet-side radius a − ρ(0)). Planet orientation θ3 = φ + π − χ.
//! - Needle tip B = O + 2a·e(φ) + l3·e(θ3 + γ [+ wobble(φ)]).
#![allow(dead_code)]

use ncgear::math::Point;

use rand::rngs::ChaCha8Rng;
use rand::{RngExt, SeedableRng};
use std::f64::consts::{PI, TAU};
use std::fmt::Write as _;

/// Carrier steps of the dense trace (one turn).
pub const DENSE_STEPS: usize = 36_000;
/// Points of the truth polyline (uniform in carrier angle).
pub const TRUTH_POINTS: usize = 3600;
/// Intervals of the intermediate table (against the sun contact angle u).
const TABLE_INTERVALS: usize = 4096;
/// Quadrature points used to solve the closure for `a`.
const CLOSURE_QUAD: usize = 8192;

/// 8-point Gauss–Legendre nodes (positive half) and weights on [−1, 1].
const GL_X: [f64; 4] = [
    0.183_434_642_495_649_8,
    0.525_532_409_916_329,
    0.796_666_477_413_626_7,
    0.960_289_856_497_536_3,
];
const GL_W: [f64; 4] = [
    0.362_683_783_378_362,
    0.313_706_645_877_887_3,
    0.222_381_034_453_374_5,
    0.101_228_536_290_376_3,
];

fn e(x: f64) -> [f64; 2] {
    [x.cos(), x.sin()]
}

/// The sun pitch law.
#[derive(Debug, Clone, PartialEq)]
pub enum SunLaw {
    /// `r1(θ) = R0·(1 + Σ a_k cos kθ + b_k sin kθ)`; the centre distance closes the train.
    Harmonic { r0: f64, a: Vec<f64>, b: Vec<f64> },
    /// Focus-pivoted ellipse, `i21(u) = (1 − e²)/(1 − 2e cos u + e²)`, at a given centre distance.
    FocusEllipse { e: f64 },
}

/// A sinusoidal perturbation of the needle direction: `β += c·sin(n·φ + phase)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Wobble {
    pub c: f64,
    pub n: f64,
    pub phase: f64,
}

/// One train: geometry plus the intermediate's table.
#[derive(Debug, Clone)]
pub struct Train {
    pub law: SunLaw,
    /// Centre distance a = |OD| = |DA|, mm (l1 = 2a).
    pub a: f64,
    /// Needle length, mm.
    pub l3: f64,
    /// World angle of the sun body frame, rad.
    pub sun_phase: f64,
    /// Needle mounting angle relative to the planet body frame, rad.
    pub gamma: f64,
    /// Optional needle-direction perturbation (the designer family; not traceable).
    pub wobble: Option<Wobble>,
    /// ψ2 at u_j = j·2π/N, j = 0..=N (composite 8-point Gauss–Legendre of i21).
    psi_tab: Vec<f64>,
}

impl Train {
    /// A harmonic sun; solves the closing centre distance.
    pub fn harmonic(
        r0: f64,
        a: Vec<f64>,
        b: Vec<f64>,
        l3: f64,
        sun_phase: f64,
        gamma: f64,
    ) -> Self {
        let law = SunLaw::Harmonic { r0, a, b };
        let mut t = Self {
            law,
            a: 0.0,
            l3,
            sun_phase,
            gamma,
            wobble: None,
            psi_tab: Vec::new(),
        };
        t.a = t.solve_closure();
        t.build_table();
        t
    }

    /// A focus-ellipse sun at centre distance `a`.
    pub fn ellipse(ecc: f64, a: f64, l3: f64, sun_phase: f64, gamma: f64) -> Self {
        let mut t = Self {
            law: SunLaw::FocusEllipse { e: ecc },
            a,
            l3,
            sun_phase,
            gamma,
            wobble: None,
            psi_tab: Vec::new(),
        };
        t.build_table();
        t
    }

    /// Sun pitch radius at sun body angle u, mm (needs `a` for the ellipse law).
    pub fn r1(&self, u: f64) -> f64 {
        match &self.law {
            SunLaw::Harmonic { r0, a, b } => {
                let (s1, c1) = u.sin_cos();
                let (mut s, mut c) = (s1, c1);
                let mut acc = 1.0;
                for k in 0..a.len() {
                    acc += a[k] * c + b[k] * s;
                    let (s2, c2) = (s * c1 + c * s1, c * c1 - s * s1);
                    s = s2;
                    c = c2;
                }
                r0 * acc
            }
            SunLaw::FocusEllipse { .. } => {
                let i = self.i21(u);
                self.a * i / (1.0 + i)
            }
        }
    }

    /// Sun → intermediate ratio at sun body angle u.
    pub fn i21(&self, u: f64) -> f64 {
        match &self.law {
            SunLaw::Harmonic { .. } => {
                let r = self.r1(u);
                r / (self.a - r)
            }
            SunLaw::FocusEllipse { e } => (1.0 - e * e) / (1.0 - 2.0 * e * u.cos() + e * e),
        }
    }

    /// How far the true gears are inside the default gear limits: `min` over 4096 angles of
    /// `1 − slope/tan 25°` (effective pressure angle ≤ 45°) and `1 − 10 mm/|ρ|` on concave arcs of
    /// sun and intermediate (`> 0`: within; the intermediate's polar derivatives from the
    /// sun's ratio by `r2 = a/(1+i)`, `dθ2 = i·du`). Derivatives of i21 by central differences.
    pub fn limit_margin(&self) -> f64 {
        let h = 1e-4;
        let mut margin = f64::INFINITY;
        for k in 0..4096 {
            let u = TAU * k as f64 / 4096.0;
            let (im, i, ip) = (self.i21(u - h), self.i21(u), self.i21(u + h));
            let (d, dd) = ((ip - im) / (2.0 * h), (ip - 2.0 * i + im) / (h * h));
            let s = 1.0 + i;
            margin = margin.min(1.0 - d.abs() / (i * s) / 25f64.to_radians().tan());
            let a = self.a;
            // Sun r1 = a i/s; intermediate against its own angle.
            let sun = [
                a * i / s,
                a * d / (s * s),
                a * (dd * s - 2.0 * d * d) / (s * s * s),
            ];
            let r2 = a / s;
            let r2u = -a * d / (s * s);
            let r2uu = -a * (dd * s - 2.0 * d * d) / (s * s * s);
            // θ2′ = i: r_θ = r_u/i, r_θθ = (r_uu − r_θ·i′)/i².
            let r2t = r2u / i;
            let mid = [r2, r2t, (r2uu - r2t * d) / (i * i)];
            for [r, r1, r2] in [sun, mid] {
                let delta = r * r + 2.0 * r1 * r1 - r * r2;
                if delta < 0.0 {
                    let rho = (r * r + r1 * r1).powf(1.5) / -delta;
                    margin = margin.min(1.0 - 10.0 / rho);
                }
            }
        }
        margin
    }

    /// (min, max) of i21 on `n` uniform samples.
    pub fn ratio_range(&self, n: usize) -> [f64; 2] {
        (0..n)
            .map(|k| self.i21(TAU * k as f64 / n as f64))
            .fold([f64::INFINITY, f64::NEG_INFINITY], |[lo, hi], v| {
                [lo.min(v), hi.max(v)]
            })
    }

    fn max_r1(&self) -> f64 {
        (0..CLOSURE_QUAD)
            .map(|k| self.r1(TAU * k as f64 / CLOSURE_QUAD as f64))
            .fold(0.0, f64::max)
    }

    /// Solves mean(r1/(a − r1)) = 1 for a > max r1 by bisection (trapezoid rule, spectrally exact).
    fn solve_closure(&self) -> f64 {
        let r: Vec<f64> = (0..CLOSURE_QUAD)
            .map(|k| self.r1(TAU * k as f64 / CLOSURE_QUAD as f64))
            .collect();
        let rmax = r.iter().copied().fold(0.0, f64::max);
        assert!(r.iter().all(|&x| x > 0.0), "sun radius must stay positive");
        let f = |a: f64| r.iter().map(|&x| x / (a - x)).sum::<f64>() / r.len() as f64 - 1.0;
        let (mut lo, mut hi) = (rmax * (1.0 + 1e-12), 2.0 * rmax);
        assert!(f(lo) > 0.0 && f(hi) <= 0.0);
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if f(mid) > 0.0 {
                lo = mid;
            } else {
                hi = mid;
            }
            if hi - lo <= 1e-15 * hi {
                break;
            }
        }
        0.5 * (lo + hi)
    }

    /// ∫_{u0}^{u1} i21 by one 8-point Gauss–Legendre panel (|u1 − u0| ≤ one table interval).
    fn gl(&self, u0: f64, u1: f64) -> f64 {
        let (m, h) = (0.5 * (u0 + u1), 0.5 * (u1 - u0));
        let mut s = 0.0;
        for k in 0..4 {
            s += GL_W[k] * (self.i21(m - h * GL_X[k]) + self.i21(m + h * GL_X[k]));
        }
        s * h
    }

    fn build_table(&mut self) {
        let h = TAU / TABLE_INTERVALS as f64;
        let mut tab = Vec::with_capacity(TABLE_INTERVALS + 1);
        let mut acc = 0.0;
        tab.push(0.0);
        for j in 0..TABLE_INTERVALS {
            acc += self.gl(j as f64 * h, (j + 1) as f64 * h);
            tab.push(acc);
        }
        self.psi_tab = tab;
    }

    /// ψ2 over one sun turn (2π when the train closes).
    pub fn psi_period(&self) -> f64 {
        self.psi_tab[TABLE_INTERVALS]
    }

    /// Intermediate rotation ψ2(u) = ∫_0^u i21 (any real u).
    pub fn psi2(&self, u: f64) -> f64 {
        let h = TAU / TABLE_INTERVALS as f64;
        let q = (u / TAU).floor();
        let ur = u - q * TAU;
        let j = ((ur / h) as usize).min(TABLE_INTERVALS - 1);
        self.psi_tab[j] + self.gl(j as f64 * h, ur) + q * self.psi_period()
    }

    /// The sun contact angle u with ψ2(u) = y (any real y): Newton inside the table interval.
    pub fn psi2_inverse(&self, y: f64) -> f64 {
        let h = TAU / TABLE_INTERVALS as f64;
        let p = self.psi_period();
        let q = (y / p).floor();
        let yr = y - q * p;
        let j = self.psi_tab[1..TABLE_INTERVALS].partition_point(|&v| v <= yr);
        let (u0, u1) = (j as f64 * h, (j + 1) as f64 * h);
        let (y0, y1) = (self.psi_tab[j], self.psi_tab[j + 1]);
        let mut u = u0 + h * ((yr - y0) / (y1 - y0)).clamp(0.0, 1.0);
        for _ in 0..6 {
            let f = y0 + self.gl(u0, u) - yr;
            let du = f / self.i21(u);
            u = (u - du).clamp(u0, u1);
            if du.abs() < 1e-15 {
                break;
            }
        }
        u + q * TAU
    }

    /// Radius of the intermediate at its planet-side contact when its rotation is ψ2: the body
    /// point at angle −ψ2, which faced the sun when the rotation was ψ2 + π (mod 2π).
    pub fn intermediate_far_radius(&self, psi2: f64) -> f64 {
        let u_far = self.psi2_inverse(psi2 + PI);
        self.a - self.r1(u_far)
    }

    /// d(ψ2, χ)/dt at carrier angle t.
    fn rhs(&self, t: f64, s: [f64; 2]) -> [f64; 2] {
        let w = self.i21(t - self.sun_phase);
        let rho = self.intermediate_far_radius(s[0]);
        [w, rho / (self.a - rho) * w]
    }

    fn rk4(&self, t: f64, s: [f64; 2], h: f64) -> [f64; 2] {
        let add = |s: [f64; 2], k: [f64; 2], f: f64| [s[0] + f * k[0], s[1] + f * k[1]];
        let k1 = self.rhs(t, s);
        let k2 = self.rhs(t + 0.5 * h, add(s, k1, 0.5 * h));
        let k3 = self.rhs(t + 0.5 * h, add(s, k2, 0.5 * h));
        let k4 = self.rhs(t + h, add(s, k3, h));
        [
            s[0] + h / 6.0 * (k1[0] + 2.0 * k2[0] + 2.0 * k3[0] + k4[0]),
            s[1] + h / 6.0 * (k1[1] + 2.0 * k2[1] + 2.0 * k3[1] + k4[1]),
        ]
    }

    /// Initial state at t = 0: ψ2 measured from the sun angle u = 0; χ(0) the sun-table angle
    /// whose radius equals the planet-side radius a − ρ(0).
    pub fn initial_state(&self) -> [f64; 2] {
        let psi0 = self.psi2(-self.sun_phase);
        [psi0, self.psi2_inverse(psi0 + PI)]
    }

    /// Integrates one carrier turn with `steps` RK4 steps.
    pub fn trace(&self, steps: usize) -> Trace<'_> {
        let h = TAU / steps as f64;
        let mut states = Vec::with_capacity(steps + 1);
        let mut s = self.initial_state();
        states.push(s);
        for k in 0..steps {
            s = self.rk4(k as f64 * h, s, h);
            states.push(s);
        }
        Trace {
            train: self,
            h,
            states,
        }
    }

    /// Needle direction at carrier angle t for the state s.
    pub fn beta(&self, t: f64, s: [f64; 2]) -> f64 {
        let w = self.wobble.map_or(0.0, |w| w.c * (w.n * t + w.phase).sin());
        t + PI - s[1] + self.gamma + w
    }

    /// Tip relative to O (CCW frame) at carrier angle t for the state s.
    pub fn tip(&self, t: f64, s: [f64; 2]) -> [f64; 2] {
        let [c, sn] = e(t);
        let [bc, bs] = e(self.beta(t, s));
        [
            2.0 * self.a * c + self.l3 * bc,
            2.0 * self.a * sn + self.l3 * bs,
        ]
    }
}

/// One integrated carrier turn.
pub struct Trace<'a> {
    pub train: &'a Train,
    pub h: f64,
    /// (ψ2, χ) at t_k = k·h, k = 0..=steps.
    pub states: Vec<[f64; 2]>,
}

impl Trace<'_> {
    pub fn steps(&self) -> usize {
        self.states.len() - 1
    }

    /// State at any carrier angle (one partial RK4 step from the grid).
    pub fn state_at(&self, t: f64) -> [f64; 2] {
        let tr = t.rem_euclid(TAU);
        let k = ((tr / self.h) as usize).min(self.steps() - 1);
        let t0 = k as f64 * self.h;
        let dt = tr - t0;
        let s = self.states[k];
        let s = if dt == 0.0 {
            s
        } else {
            self.train.rk4(t0, s, dt)
        };
        // the grid covers [0, 2π): a wrapped t keeps the continuous χ of the first turn,
        // which is what the tip needs (angles only).
        s
    }

    /// Tip relative to O at any carrier angle.
    pub fn tip_at(&self, t: f64) -> [f64; 2] {
        let tr = t.rem_euclid(TAU);
        self.train.tip(tr, self.state_at(tr))
    }

    /// Tips at the grid angles (closed: the last equals the first up to the closure error).
    pub fn tips(&self) -> Vec<[f64; 2]> {
        self.states
            .iter()
            .enumerate()
            .map(|(k, s)| self.train.tip(k as f64 * self.h, *s))
            .collect()
    }

    /// χ advance over the turn minus 2π.
    pub fn closure_error(&self) -> f64 {
        self.states[self.steps()][1] - self.states[0][1] - TAU
    }
}

// ---------------------------------------------------------------------------------------------
// Case generation
// ---------------------------------------------------------------------------------------------

/// Case families of the suite.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Family {
    Exact,
    Sparse,
    Noisy,
    Designer,
}

impl Family {
    pub fn name(self) -> &'static str {
        match self {
            Family::Exact => "exact",
            Family::Sparse => "sparse",
            Family::Noisy => "noisy",
            Family::Designer => "designer",
        }
    }
}

/// How the user's points are spaced.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Sampling {
    /// Uniform in arc length (chords of the dense trace).
    Arc,
    /// Uniform in carrier angle.
    Time,
}

/// Options drawn for one case (or set by hand).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SampleOptions {
    pub m: usize,
    pub sampling: Sampling,
    /// Start: carrier angle (Time) or arc-length fraction (Arc) in [0, 1) × 2π.
    pub start: f64,
    pub cw: bool,
    pub center: [f64; 2],
    pub sigma: f64,
}

/// A generated case: the user's points and the truth, both in the world frame.
#[derive(Debug, Clone)]
pub struct Case {
    pub family: Family,
    pub seed: u64,
    pub train: Train,
    pub opts: SampleOptions,
    pub points: Vec<Point>,
    pub truth: Vec<Point>,
    pub ratio_range: [f64; 2],
    pub closure_error: f64,
    /// Discretisation error of the truth polyline: largest distance of the dense-trace points
    /// from the truth chord they fall on, mm.
    pub truth_sag_mm: f64,
}

impl Case {
    /// One-line description for summaries and failure messages.
    pub fn describe(&self) -> String {
        let t = &self.train;
        let mut s = String::new();
        match &t.law {
            SunLaw::Harmonic { r0, a, b } => {
                let _ = write!(s, "R0={r0:.3} harm=[");
                for k in 0..a.len() {
                    let _ = write!(
                        s,
                        "{}({:.4},{:.4})",
                        if k > 0 { " " } else { "" },
                        a[k],
                        b[k]
                    );
                }
                s.push(']');
            }
            SunLaw::FocusEllipse { e } => {
                let _ = write!(s, "ellipse e={e:.4}");
            }
        }
        let _ = write!(
            s,
            " a={:.4} l3={:.3} phis={:.4} gamma={:.4} i21=[{:.3},{:.3}]",
            t.a, t.l3, t.sun_phase, t.gamma, self.ratio_range[0], self.ratio_range[1]
        );
        if let Some(w) = t.wobble {
            let _ = write!(s, " wobble=({:.4} sin({}t+{:.3}))", w.c, w.n, w.phase);
        }
        let o = &self.opts;
        let _ = write!(
            s,
            " M={} {:?} start={:.3} {} O=({:.3},{:.3}) sigma={:.4}",
            o.m,
            o.sampling,
            o.start,
            if o.cw { "CW" } else { "CCW" },
            o.center[0],
            o.center[1],
            o.sigma
        );
        s
    }

    /// The points as a CSV file (header `x_mm,y_mm`, 6 decimals, `#` comments).
    pub fn points_csv(&self) -> String {
        let mut s = format!(
            "# ncgear robust case: family {} seed {}\n# {}\n# center: {:.6},{:.6}\n",
            self.family.name(),
            self.seed,
            self.describe(),
            self.opts.center[0],
            self.opts.center[1]
        );
        s.push_str("x_mm,y_mm\n");
        for p in &self.points {
            let _ = writeln!(s, "{:.6},{:.6}", p.x, p.y);
        }
        s
    }

    /// The truth polyline as a CSV file.
    pub fn truth_csv(&self) -> String {
        let mut s = format!(
            "# truth ({} points uniform in carrier angle, clean, closed) for family {} seed {}\n# center: {:.6},{:.6}\nx_mm,y_mm\n",
            self.truth.len(),
            self.family.name(),
            self.seed,
            self.opts.center[0],
            self.opts.center[1]
        );
        for p in &self.truth {
            let _ = writeln!(s, "{:.6},{:.6}", p.x, p.y);
        }
        s
    }
}

/// Standard normal (Box–Muller).
fn gauss(rng: &mut ChaCha8Rng) -> f64 {
    let u1: f64 = 1.0 - rng.random::<f64>();
    let u2: f64 = rng.random::<f64>();
    (-2.0 * u1.ln()).sqrt() * (TAU * u2).cos()
}

fn to_world(p: [f64; 2], o: &SampleOptions) -> [f64; 2] {
    let y = if o.cw { -p[1] } else { p[1] };
    [p[0] + o.center[0], y + o.center[1]]
}

/// Winding number of a closed polyline around the origin.
fn winding(tips: &[[f64; 2]]) -> f64 {
    let mut acc = 0.0;
    for w in tips.windows(2) {
        let a0 = w[0][1].atan2(w[0][0]);
        let a1 = w[1][1].atan2(w[1][0]);
        acc += (a1 - a0 + PI).rem_euclid(TAU) - PI;
    }
    acc / TAU
}

/// Draws a harmonic sun and a needle; rejects ratio ranges outside [0.35, 3.0], tips closer than
/// 0.1·l3 to O and O inside the loop.
pub fn draw_harmonic_train(rng: &mut ChaCha8Rng) -> Train {
    loop {
        let r0 = rng.random_range(20.0..25.0);
        let nh = match rng.random::<f64>() {
            x if x < 0.4 => 1,
            x if x < 0.7 => 2,
            x if x < 0.9 => 3,
            _ => 4,
        };
        // mostly moderate amplitudes, about a quarter reaching toward the ratio bounds
        let amax = if rng.random_bool(0.25) { 0.2 } else { 0.1 };
        let (mut a, mut b) = (Vec::new(), Vec::new());
        for _ in 0..nh {
            let amp = rng.random_range(0.0..amax);
            let ph = rng.random_range(0.0..TAU);
            a.push(amp * ph.cos());
            b.push(amp * ph.sin());
        }
        let l3 = rng.random_range(150.0..190.0);
        let phis = rng.random_range(0.0..TAU);
        let gamma = rng.random_range(-PI..PI);
        // cheap pre-check of the radius before solving
        if (0..720).any(|k| {
            let th = TAU * k as f64 / 720.0;
            let mut acc = 1.0;
            for kk in 0..nh {
                let n = (kk + 1) as f64;
                acc += a[kk] * (n * th).cos() + b[kk] * (n * th).sin();
            }
            acc < 0.2
        }) {
            continue;
        }
        let train = Train::harmonic(r0, a, b, l3, phis, gamma);
        let [lo, hi] = train.ratio_range(4096);
        if lo < 0.35 || hi > 3.0 {
            continue;
        }
        // coarse trace for the geometric rejections
        let tips = train.trace(3600).tips();
        let rmin = tips
            .iter()
            .map(|p| p[0].hypot(p[1]))
            .fold(f64::INFINITY, f64::min);
        if rmin < 0.1 * l3 || winding(&tips).abs() > 0.5 {
            continue;
        }
        return train;
    }
}

/// Resamples M points from the trace (arc or time), in travel order, relative to O.
pub fn sample(trace: &Trace<'_>, o: &SampleOptions) -> Vec<[f64; 2]> {
    match o.sampling {
        Sampling::Time => (0..o.m)
            .map(|j| trace.tip_at(o.start + TAU * j as f64 / o.m as f64))
            .collect(),
        Sampling::Arc => {
            let tips = trace.tips();
            let mut cum = Vec::with_capacity(tips.len());
            cum.push(0.0);
            for w in tips.windows(2) {
                let d = (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1]);
                cum.push(cum.last().unwrap() + d);
            }
            let total = *cum.last().unwrap();
            let n = trace.steps();
            (0..o.m)
                .map(|j| {
                    let s = (o.start / TAU * total + total * j as f64 / o.m as f64) % total;
                    let k = (cum.partition_point(|&c| c <= s) - 1).min(n - 1);
                    let f = (s - cum[k]) / (cum[k + 1] - cum[k]);
                    trace.tip_at((k as f64 + f) * trace.h)
                })
                .collect()
        }
    }
}

/// Builds a case from a train and sampling options (noise drawn from `rng` when σ > 0).
pub fn build_case(
    family: Family,
    seed: u64,
    train: Train,
    opts: SampleOptions,
    rng: &mut ChaCha8Rng,
) -> Case {
    let trace = train.trace(DENSE_STEPS);
    let closure_error = trace.closure_error();
    let stride = DENSE_STEPS / TRUTH_POINTS;
    let dense = trace.tips();
    let truth: Vec<Point> = (0..TRUTH_POINTS)
        .map(|k| to_world(dense[k * stride], &opts).into())
        .collect();
    let mut points: Vec<Point> = sample(&trace, &opts)
        .into_iter()
        .map(|p| to_world(p, &opts).into())
        .collect();
    if opts.sigma > 0.0 {
        for p in &mut points {
            p.x += opts.sigma * gauss(rng);
            p.y += opts.sigma * gauss(rng);
        }
    }
    let ratio_range = train.ratio_range(4096);
    let mut truth_sag_mm: f64 = 0.0;
    for k in 0..TRUTH_POINTS {
        let (p, q) = (dense[k * stride], dense[(k + 1) * stride]);
        for j in 1..stride {
            truth_sag_mm = truth_sag_mm.max(seg_distance(dense[k * stride + j], p, q));
        }
    }
    drop(trace);
    Case {
        family,
        seed,
        train,
        opts,
        points,
        truth,
        ratio_range,
        closure_error,
        truth_sag_mm,
    }
}

fn seg_distance(x: [f64; 2], p: [f64; 2], q: [f64; 2]) -> f64 {
    let (dx, dy) = (q[0] - p[0], q[1] - p[1]);
    let l2 = dx * dx + dy * dy;
    let t = if l2 > 0.0 {
        (((x[0] - p[0]) * dx + (x[1] - p[1]) * dy) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (x[0] - p[0] - t * dx).hypot(x[1] - p[1] - t * dy)
}

/// The designer family's generating train: G1 (focus ellipse, a = 45, l3 = 170) with γ such that
/// β(0) = −70°, sun phase `phis`.
pub fn g1_like(ecc: f64, phis: f64) -> Train {
    let mut t = Train::ellipse(ecc, 45.0, 170.0, phis, 0.0);
    let s0 = t.initial_state();
    t.gamma = (-70f64).to_radians() - t.beta(0.0, s0);
    t
}

/// Generates the case of a family for a seed (deterministic).
pub fn generate(family: Family, seed: u64) -> Case {
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x6e63_6765_6172_0000);
    let sampling = if rng.random_bool(0.5) {
        Sampling::Arc
    } else {
        Sampling::Time
    };
    let start = rng.random_range(0.0..TAU);
    match family {
        Family::Designer => {
            let ecc = rng.random_range(0.1..0.2);
            let phis = rng.random_range(0.0..TAU);
            let mut train = g1_like(ecc, phis);
            train.wobble = Some(Wobble {
                c: rng.random_range(0.005..0.03),
                n: if rng.random_bool(0.5) { 2.0 } else { 3.0 },
                phase: rng.random_range(0.0..TAU),
            });
            let opts = SampleOptions {
                m: rng.random_range(300..1200),
                sampling,
                start,
                cw: false,
                center: [0.0, 0.0],
                sigma: 0.0,
            };
            build_case(family, seed, train, opts, &mut rng)
        }
        _ => {
            let m = match family {
                Family::Exact => {
                    // log-uniform in 200..3600
                    let x: f64 = rng.random_range((200f64).ln()..(3600f64).ln());
                    (x.exp() as usize).clamp(200, 3600)
                }
                Family::Sparse => rng.random_range(200..=300),
                _ => rng.random_range(300..=1200),
            };
            let cw = rng.random_bool(0.5);
            let center = if rng.random_bool(0.5) {
                [
                    rng.random_range(-300.0..300.0),
                    rng.random_range(-300.0..300.0),
                ]
            } else {
                [0.0, 0.0]
            };
            let sigma = if family == Family::Noisy {
                rng.random_range(0.005..0.05)
            } else {
                0.0
            };
            let train = draw_harmonic_train(&mut rng);
            let opts = SampleOptions {
                m,
                sampling,
                start,
                cw,
                center,
                sigma,
            };
            build_case(family, seed, train, opts, &mut rng)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Focus ellipse e = 0.15, a = 45, contact starting at the far vertex (u = 0): the planet's
    /// relative rotation is 2·atan2(k² sin(t/2), cos(t/2)), k² = ((1+e)/(1−e))².
    #[test]
    fn forward_model_matches_the_focus_ellipse_closed_form() {
        let train = Train::ellipse(0.15, 45.0, 170.0, 0.0, 0.0);
        assert!((train.i21(0.0) - 1.15 / 0.85).abs() < 1e-15);
        let trace = train.trace(DENSE_STEPS);
        let k2 = (1.15f64 / 0.85).powi(2);
        let chi0 = trace.states[0][1];
        let mut worst: f64 = 0.0;
        for d in (30..=330).step_by(30) {
            let t = (d as f64).to_radians();
            let k = DENSE_STEPS * d / 360;
            let psi3 = trace.states[k][1] - chi0;
            let exact = 2.0 * (k2 * (0.5 * t).sin()).atan2((0.5 * t).cos());
            worst = worst.max((psi3 - exact).abs());
            assert!(
                (psi3 - exact).abs() < 1e-7,
                "t = {d}°: ψ3 = {psi3}, closed form {exact}"
            );
        }
        eprintln!("focus ellipse: worst |ψ3 − closed form| = {worst:.3e} rad");
        assert!(trace.closure_error().abs() < 1e-7);
    }

    /// Random harmonic suns: the train closes (χ advances 2π per carrier turn) and so does the
    /// tip path; the planet-side radii agree with the congruent planet (a − ρ = r1(χ)).
    #[test]
    fn forward_model_closes_on_random_harmonic_suns() {
        for seed in 0..6u64 {
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            let train = draw_harmonic_train(&mut rng);
            let trace = train.trace(DENSE_STEPS);
            let err = trace.closure_error();
            assert!(err.abs() < 1e-7, "seed {seed}: χ closure error {err:e}");
            let tips = trace.tips();
            let (p0, p1) = (tips[0], tips[tips.len() - 1]);
            let gap = (p0[0] - p1[0]).hypot(p0[1] - p1[1]);
            assert!(gap < 1e-6, "seed {seed}: tip gap {gap:e} mm");
            // congruence: the planet radius at its contact equals r1(χ)
            for k in (0..DENSE_STEPS).step_by(997) {
                let s = trace.states[k];
                let rho = train.intermediate_far_radius(s[0]);
                let d = (train.a - rho - train.r1(s[1])).abs();
                assert!(
                    d < 1e-9,
                    "seed {seed}, step {k}: planet radius mismatch {d:e}"
                );
            }
            // step refinement: the 36 000-step tip agrees with a 72 000-step tip to 1e-5 mm
            let fine = train.trace(2 * DENSE_STEPS);
            let worst = (0..DENSE_STEPS)
                .step_by(101)
                .map(|k| {
                    let a = tips[k];
                    let b = train.tip(k as f64 * trace.h, fine.states[2 * k]);
                    (a[0] - b[0]).hypot(a[1] - b[1])
                })
                .fold(0.0, f64::max);
            assert!(
                worst < 1e-5,
                "seed {seed}: step-refinement change {worst:e} mm"
            );
            eprintln!(
                "seed {seed}: a = {:.6}, χ closure {err:.2e}, tip gap {gap:.2e}, refinement {worst:.2e}",
                train.a
            );
        }
    }
}
