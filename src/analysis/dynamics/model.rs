//! The assembled model: DOF set, diagonal mass, and the list of force terms built once from a
//! scene (spec B.6, B.10). The right-hand side loops over the terms; it never tests switches.

use super::ode::OdeSystem;
use super::tvms::{PairGeometry, RectangularTvms};
use nalgebra::DMatrix;
use std::f64::consts::PI;
use std::sync::Arc;

/// Names of the 16 generalized coordinates in the patent's order (B.1), plus `u`, the SDOF
/// relative coordinate `rb1 θ1 − rb2 θ2` (m) used when the model reduces to one DOF.
pub const DOF_NAMES: [&str; 17] = [
    "theta_p", "x1", "y1", "theta1", "x2", "y2", "theta2", "xb1", "yb1", "xb2", "yb2", "xb3",
    "yb3", "xb4", "yb4", "theta_q", "u",
];

/// A state-event function `g(t, q)` (q: coordinates); its zeros are kinks of a force law.
pub type StateEvent<'a> = Box<dyn Fn(f64, &[f64]) -> f64 + Send + Sync + 'a>;

/// A generalized force contribution (B.10 term list). `q`, `v`: coordinates (m or rad) and
/// velocities; forces in N or N·m.
pub trait ForceTerm: Send + Sync {
    /// Human-readable name for the run log.
    fn name(&self) -> String;
    /// Adds the term's generalized force at time `t` (s) to `f`.
    fn add_forces(&self, t: f64, q: &[f64], v: &[f64], f: &mut [f64]);
    /// Pushes the known switch times in `(t0, t1)` (s).
    fn breakpoints(&self, _t0: f64, _t1: f64, _out: &mut Vec<f64>) {}
    /// State-event functions `g(t, q)` whose zeros are kinks of the force law.
    fn events(&self) -> Vec<StateEvent<'_>> {
        Vec::new()
    }
    /// Potential energy (J) when the term is treated as conservative in the energy audit.
    fn potential(&self, _t: f64, _q: &[f64]) -> Option<f64> {
        None
    }
    /// Energy source rate (W): the term's power `Σ f_i v_i` plus `dV/dt` along the motion when it
    /// has a potential (= ∂V/∂t + non-conservative power).
    fn source_rate(&self, t: f64, q: &[f64], v: &[f64]) -> f64 {
        let mut f = vec![0.0; q.len()];
        self.add_forces(t, q, v, &mut f);
        f.iter().zip(v).map(|(a, b)| a * b).sum()
    }
    /// Adds the linear(ised, mean) stiffness and damping matrices; `false` if the term has no
    /// linear form (Hertz bearings).
    fn linear_matrices(&self, _k: &mut DMatrix<f64>, _c: &mut DMatrix<f64>) -> bool {
        true
    }
    /// True when the term makes the equations nonlinear or time-varying in the states.
    fn is_nonlinear(&self) -> bool {
        false
    }
}

/// Constant generalized forces (torques, gravity), N or N·m.
pub struct ConstantForce {
    /// Label.
    pub label: String,
    /// (DOF index, value).
    pub forces: Vec<(usize, f64)>,
}

impl ForceTerm for ConstantForce {
    fn name(&self) -> String {
        self.label.clone()
    }
    fn add_forces(&self, _t: f64, _q: &[f64], _v: &[f64], f: &mut [f64]) {
        for &(i, x) in &self.forces {
            f[i] += x;
        }
    }
}

/// Linear spring–damper on a linear combination `d = Σ c_i q_i`: force `−(k d + c ḋ) c_i` on DOF i.
pub struct LinearSpring {
    /// Label.
    pub label: String,
    /// (DOF index, coefficient).
    pub coeffs: Vec<(usize, f64)>,
    /// Stiffness, N/m or N·m/rad.
    pub k: f64,
    /// Damping, N·s/m or N·m·s/rad.
    pub c: f64,
}

impl LinearSpring {
    fn d(&self, q: &[f64]) -> f64 {
        self.coeffs.iter().map(|&(i, c)| c * q[i]).sum()
    }
}

impl ForceTerm for LinearSpring {
    fn name(&self) -> String {
        self.label.clone()
    }
    fn add_forces(&self, _t: f64, q: &[f64], v: &[f64], f: &mut [f64]) {
        let fm = self.k * self.d(q) + self.c * self.d(v);
        for &(i, c) in &self.coeffs {
            f[i] -= fm * c;
        }
    }
    fn potential(&self, _t: f64, q: &[f64]) -> Option<f64> {
        Some(0.5 * self.k * self.d(q).powi(2))
    }
    fn source_rate(&self, _t: f64, _q: &[f64], v: &[f64]) -> f64 {
        -self.c * self.d(v).powi(2)
    }
    fn linear_matrices(&self, k: &mut DMatrix<f64>, c: &mut DMatrix<f64>) -> bool {
        for &(i, a) in &self.coeffs {
            for &(j, b) in &self.coeffs {
                k[(i, j)] += self.k * a * b;
                c[(i, j)] += self.c * a * b;
            }
        }
        true
    }
}

/// How the mesh stiffness varies (B.2).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum StiffnessLaw {
    /// Constant k, N/m.
    Constant(f64),
    /// Truncated Fourier series of the rectangular wave with `n` harmonics.
    Fourier(RectangularTvms, u32),
    /// Exact rectangular wave (one mesh).
    Rectangular(RectangularTvms),
    /// Exact per-pair split (B-2).
    Pairs(RectangularTvms),
}

/// Static transmission error `e(t) = e0 + er sin(ωe t + φ)`, m.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ste {
    /// Mean, m.
    pub e0: f64,
    /// Amplitude, m.
    pub er: f64,
    /// Phase, rad.
    pub phase: f64,
}

/// Backlash dead zone (B-5).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Backlash {
    /// Half gap b, m.
    pub b: f64,
    /// Damping also acts inside the gap (Kahraman–Singh convention).
    pub damping_in_gap: bool,
    /// Clamp pulling mesh forces to zero.
    pub no_tension: bool,
}

/// Linear tip relief (B-4).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Relief {
    /// Δmax, m.
    pub delta_max: f64,
    /// Relief length along the line of action, m.
    pub length: f64,
}

/// Shared mesh kernel: per-pair deflections and forces (B-3..B-5).
pub struct MeshCore {
    /// Geometric deflection coefficients (DOF index, coefficient) of `(y1−y2) + rb1θ1 − rb2θ2`.
    pub coeffs: Vec<(usize, f64)>,
    /// Stiffness law.
    pub law: StiffnessLaw,
    /// Mesh damping c_m, N·s/m.
    pub c_m: f64,
    /// Mesh period t0, s.
    pub t0: f64,
    /// Contact ratio ε.
    pub eps: f64,
    /// Mesh frequency ωe, rad/s.
    pub omega_e: f64,
    /// Static TE.
    pub ste: Option<Ste>,
    /// Backlash.
    pub backlash: Option<Backlash>,
    /// Tip relief.
    pub relief: Option<Relief>,
    /// Contact length ε·pb, m.
    pub contact_length: f64,
    /// Split the mesh into the two tooth pairs (relief, friction, `pairs`).
    pub per_pair: bool,
}

/// State of one tooth pair at an instant.
#[derive(Debug, Clone, Copy, Default)]
pub struct PairState {
    /// In contact zone.
    pub active: bool,
    /// Local time since the pair entered, in mesh periods.
    pub s: f64,
    /// Stiffness k_j, N/m.
    pub k: f64,
    /// Deflection δ_j, m.
    pub delta: f64,
    /// Rate δ̇_j, m/s.
    pub delta_dot: f64,
    /// Mesh force F_mj, N.
    pub force: f64,
}

fn dead_zone(d: f64, b: f64) -> f64 {
    if d > b {
        d - b
    } else if d < -b {
        d + b
    } else {
        0.0
    }
}

impl MeshCore {
    /// Geometric deflection `(y1−y2) + rb1θ1 − rb2θ2` (or `u`), m.
    #[must_use]
    pub fn geometric(&self, q: &[f64]) -> f64 {
        self.coeffs.iter().map(|&(i, c)| c * q[i]).sum()
    }

    fn ste(&self, t: f64) -> (f64, f64) {
        match self.ste {
            Some(s) => {
                let a = self.omega_e * t + s.phase;
                (s.e0 + s.er * a.sin(), s.er * self.omega_e * a.cos())
            }
            None => (0.0, 0.0),
        }
    }

    /// Dynamic transmission error `δ = geometric − e(t)`, m (without relief).
    #[must_use]
    pub fn dte(&self, t: f64, q: &[f64]) -> f64 {
        self.geometric(q) - self.ste(t).0
    }

    fn phase(&self, t: f64) -> f64 {
        let s = (t / self.t0).rem_euclid(1.0);
        if s >= 1.0 { 0.0 } else { s }
    }

    fn rect(&self) -> Option<RectangularTvms> {
        match self.law {
            StiffnessLaw::Constant(_) => None,
            StiffnessLaw::Fourier(r, _) | StiffnessLaw::Rectangular(r) | StiffnessLaw::Pairs(r) => {
                Some(r)
            }
        }
    }

    fn total_k(&self, s: f64) -> (f64, f64) {
        match self.law {
            StiffnessLaw::Constant(k) => (k, 0.0),
            StiffnessLaw::Fourier(r, n) => (r.fourier(s, n), r.fourier_ds(s, n) / self.t0),
            StiffnessLaw::Rectangular(r) | StiffnessLaw::Pairs(r) => (r.at_phase(s), 0.0),
        }
    }

    /// Mean mesh stiffness, N/m.
    #[must_use]
    pub fn mean_k(&self) -> f64 {
        match self.law {
            StiffnessLaw::Constant(k) => k,
            StiffnessLaw::Fourier(r, _) | StiffnessLaw::Rectangular(r) | StiffnessLaw::Pairs(r) => {
                r.mean()
            }
        }
    }

    fn relief_at(&self, s_len: f64, v: f64) -> (f64, f64) {
        match self.relief {
            Some(r) if s_len < r.length => (
                r.delta_max * (r.length - s_len) / r.length,
                -r.delta_max * v / r.length,
            ),
            Some(r) if s_len > self.contact_length - r.length => (
                r.delta_max * (s_len - (self.contact_length - r.length)) / r.length,
                r.delta_max * v / r.length,
            ),
            _ => (0.0, 0.0),
        }
    }

    /// The (one or two) pair states and the time derivative of the stiffness part (for the
    /// energy audit: Σ k̇_j Φ(δ_j)).
    pub fn pairs(&self, t: f64, q: &[f64], v: &[f64], out: &mut [PairState; 2]) -> (usize, f64) {
        let g = self.geometric(q);
        let gd = self.geometric(v);
        let (e, ed) = self.ste(t);
        let s1 = self.phase(t);
        let (ktot, kdot) = self.total_k(s1);
        let b = self.backlash.map_or(0.0, |b| b.b);
        let mut kdot_phi = 0.0;
        let np = if self.per_pair { 2 } else { 1 };
        let vel = self.contact_length / (self.eps * self.t0);
        for (j, p) in out.iter_mut().enumerate().take(np) {
            let s = s1 + j as f64;
            let (k, kd, c) = if self.per_pair {
                let r = self.rect().unwrap_or(RectangularTvms {
                    kmax: 2.0 * ktot,
                    kmin: ktot,
                    eps: self.eps,
                });
                let share = r.pair(s) / r.at_phase(s1);
                (ktot * share, kdot * share, self.c_m * share)
            } else {
                (ktot, kdot, self.c_m)
            };
            let (rel, reld) = if self.per_pair {
                self.relief_at(s * self.t0 * vel, vel)
            } else {
                (0.0, 0.0)
            };
            let delta = g - e - rel;
            let dd = gd - ed - reld;
            let fd = dead_zone(delta, b);
            let in_contact = delta.abs() > b;
            let damp = match self.backlash {
                Some(bl) if !bl.damping_in_gap && !in_contact => 0.0,
                _ => c * dd,
            };
            let mut force = k * fd + damp;
            if self.backlash.is_some_and(|bl| bl.no_tension)
                && force * delta.signum() < 0.0
                && in_contact
            {
                force = 0.0;
            }
            if self.backlash.is_some_and(|bl| bl.no_tension) && !in_contact {
                force = 0.0;
            }
            kdot_phi += kd * 0.5 * fd * fd;
            *p = PairState {
                active: k > 0.0,
                s,
                k,
                delta,
                delta_dot: dd,
                force,
            };
        }
        (np, kdot_phi)
    }
}

/// Mesh force term (TVMS + STE + backlash + tip relief) acting along the line of action.
pub struct MeshTerm {
    /// Kernel shared with the friction term.
    pub core: Arc<MeshCore>,
}

impl ForceTerm for MeshTerm {
    fn name(&self) -> String {
        let c = &self.core;
        let mut s = match c.law {
            StiffnessLaw::Constant(k) => format!("mesh(constant k = {k:.4e} N/m"),
            StiffnessLaw::Fourier(r, n) => {
                format!("mesh(fourier n = {n}, mean {:.4e} N/m", r.mean())
            }
            StiffnessLaw::Rectangular(r) => format!("mesh(rectangular, mean {:.4e} N/m", r.mean()),
            StiffnessLaw::Pairs(r) => format!("mesh(pairs, mean {:.4e} N/m", r.mean()),
        };
        s += &format!(", c_m = {:.4} N·s/m", c.c_m);
        if c.per_pair {
            s += ", per tooth pair";
        }
        s += ")";
        if let Some(b) = c.backlash {
            s += &format!(" + backlash(b = {:.3} µm)", b.b * 1e6);
        }
        if let Some(e) = c.ste {
            s += &format!(" + static_te(er = {:.3} µm)", e.er * 1e6);
        }
        if let Some(r) = c.relief {
            s += &format!(
                " + tip_relief({:.3} µm over {:.3} mm)",
                r.delta_max * 1e6,
                r.length * 1e3
            );
        }
        s
    }
    fn add_forces(&self, t: f64, q: &[f64], v: &[f64], f: &mut [f64]) {
        let mut ps = [PairState::default(); 2];
        let (np, _) = self.core.pairs(t, q, v, &mut ps);
        let fm: f64 = ps[..np].iter().map(|p| p.force).sum();
        for &(i, c) in &self.core.coeffs {
            f[i] -= fm * c;
        }
    }
    fn breakpoints(&self, t0: f64, t1: f64, out: &mut Vec<f64>) {
        let c = &self.core;
        let mut offs = Vec::new();
        if matches!(c.law, StiffnessLaw::Rectangular(_) | StiffnessLaw::Pairs(_)) || c.per_pair {
            offs.extend([0.0, c.eps - 1.0]);
        }
        if let (Some(r), true) = (c.relief, c.per_pair) {
            let len = c.contact_length / c.eps; // = pb: distance per mesh period
            offs.push(r.length / len);
            offs.push((c.contact_length - r.length) / len - 1.0);
        }
        push_periodic(&offs, c.t0, t0, t1, out);
    }
    fn events(&self) -> Vec<StateEvent<'_>> {
        let Some(bl) = self.core.backlash else {
            return Vec::new();
        };
        let mut ev: Vec<StateEvent<'_>> = Vec::new();
        let np = if self.core.per_pair { 2 } else { 1 };
        for j in 0..np {
            for sign in [1.0, -1.0] {
                let core = &self.core;
                ev.push(Box::new(move |t: f64, q: &[f64]| {
                    let mut ps = [PairState::default(); 2];
                    let zeros = vec![0.0; q.len()];
                    core.pairs(t, q, &zeros, &mut ps);
                    ps[j].delta - sign * bl.b
                }));
            }
        }
        ev
    }
    fn potential(&self, t: f64, q: &[f64]) -> Option<f64> {
        let mut ps = [PairState::default(); 2];
        let zeros = vec![0.0; q.len()];
        let (np, _) = self.core.pairs(t, q, &zeros, &mut ps);
        let b = self.core.backlash.map_or(0.0, |b| b.b);
        Some(
            ps[..np]
                .iter()
                .map(|p| 0.5 * p.k * dead_zone(p.delta, b).powi(2))
                .sum(),
        )
    }
    fn source_rate(&self, t: f64, q: &[f64], v: &[f64]) -> f64 {
        // P + dV/dt = −F·ġ + Σ k f(δ) δ̇ + Σ k̇ Φ(δ)
        let mut ps = [PairState::default(); 2];
        let (np, kdot_phi) = self.core.pairs(t, q, v, &mut ps);
        let gd = self.core.geometric(v);
        let b = self.core.backlash.map_or(0.0, |b| b.b);
        ps[..np]
            .iter()
            .map(|p| -p.force * gd + p.k * dead_zone(p.delta, b) * p.delta_dot)
            .sum::<f64>()
            + kdot_phi
    }
    fn linear_matrices(&self, k: &mut DMatrix<f64>, c: &mut DMatrix<f64>) -> bool {
        let (km, cm) = (self.core.mean_k(), self.core.c_m);
        for &(i, a) in &self.core.coeffs {
            for &(j, b) in &self.core.coeffs {
                k[(i, j)] += km * a * b;
                c[(i, j)] += cm * a * b;
            }
        }
        true
    }
    fn is_nonlinear(&self) -> bool {
        let c = &self.core;
        c.backlash.is_some() || c.relief.is_some() || !matches!(c.law, StiffnessLaw::Constant(_))
    }
}

fn push_periodic(offsets: &[f64], period: f64, t0: f64, t1: f64, out: &mut Vec<f64>) {
    if offsets.is_empty() {
        return;
    }
    let j0 = (t0 / period).floor() as i64 - 1;
    let j1 = (t1 / period).ceil() as i64 + 1;
    for j in j0..=j1 {
        for &o in offsets {
            let t = (j as f64 + o) * period;
            if t > t0 && t < t1 {
                out.push(t);
            }
        }
    }
}

/// Friction direction law (B.4).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FrictionDirection {
    /// λ = +1 before the pitch point, −1 after (breakpoints at the pitch-point times).
    PitchSwitch,
    /// λ = −tanh(v_s / v0), v0 in m/s.
    Tanh(f64),
}

/// Sliding friction with friction arms (B.4, B-6, B-7).
pub struct FrictionTerm {
    /// Mesh kernel.
    pub core: Arc<MeshCore>,
    /// Coefficient μ.
    pub mu: f64,
    /// Direction law.
    pub direction: FrictionDirection,
    /// Contact geometry.
    pub geom: PairGeometry,
    /// Nominal speeds ω1, ω2, rad/s.
    pub omega: [f64; 2],
    /// DOF indices of x1, x2, θ1, θ2 (absent DOFs are rigid).
    pub idx: [Option<usize>; 4],
}

impl FrictionTerm {
    /// Per pair: (friction force F_fj along +x on the pinion, arm L_pj, arm L_gj, sliding velocity), N, m, m/s.
    pub fn pair_friction(&self, t: f64, q: &[f64], v: &[f64]) -> Vec<(f64, f64, f64, f64)> {
        let mut ps = [PairState::default(); 2];
        let (np, _) = self.core.pairs(t, q, v, &mut ps);
        let pb = self.geom.base_pitch_m;
        ps[..np]
            .iter()
            .filter(|p| p.active)
            .map(|p| {
                let s_len = p.s * pb;
                let lp = self.geom.n1a_m + s_len;
                let lg = self.geom.n1n2_m - lp;
                let vs = self.omega[0] * lp - self.omega[1] * lg;
                let lambda = match self.direction {
                    FrictionDirection::PitchSwitch => {
                        if s_len < self.geom.n1p_m - self.geom.n1a_m {
                            1.0
                        } else {
                            -1.0
                        }
                    }
                    FrictionDirection::Tanh(v0) => -(vs / v0).tanh(),
                };
                // tension (negative mesh force) means no contact: no friction
                (self.mu * lambda * p.force.max(0.0), lp, lg, vs)
            })
            .collect()
    }
}

impl ForceTerm for FrictionTerm {
    fn name(&self) -> String {
        match self.direction {
            FrictionDirection::PitchSwitch => format!("friction(mu = {}, pitch_switch)", self.mu),
            FrictionDirection::Tanh(v0) => {
                format!("friction(mu = {}, tanh v0 = {v0} m/s)", self.mu)
            }
        }
    }
    fn add_forces(&self, t: f64, q: &[f64], v: &[f64], f: &mut [f64]) {
        for (ff, lp, lg, _) in self.pair_friction(t, q, v) {
            if let Some(i) = self.idx[0] {
                f[i] += ff;
            }
            if let Some(i) = self.idx[1] {
                f[i] -= ff;
            }
            if let Some(i) = self.idx[2] {
                f[i] += ff * lp;
            }
            if let Some(i) = self.idx[3] {
                f[i] -= ff * lg;
            }
        }
    }
    fn breakpoints(&self, t0: f64, t1: f64, out: &mut Vec<f64>) {
        if self.direction == FrictionDirection::PitchSwitch {
            let tp = (self.geom.n1p_m - self.geom.n1a_m) / self.geom.base_pitch_m;
            push_periodic(&[tp, tp - 1.0], self.core.t0, t0, t1, out);
        }
    }
    fn linear_matrices(&self, _k: &mut DMatrix<f64>, _c: &mut DMatrix<f64>) -> bool {
        false
    }
    fn is_nonlinear(&self) -> bool {
        true
    }
}

/// Mass unbalance forcing `m ρ ω² (cos Φ, sin Φ)`, Φ = ω t + φ (B.5, kind = unbalance).
pub struct UnbalanceTerm {
    /// Label.
    pub label: String,
    /// DOF indices x, y.
    pub idx: [usize; 2],
    /// m ρ, kg·m.
    pub m_rho: f64,
    /// Shaft speed ω, rad/s.
    pub omega: f64,
    /// Phase φ, rad.
    pub phase: f64,
}

impl ForceTerm for UnbalanceTerm {
    fn name(&self) -> String {
        self.label.clone()
    }
    fn add_forces(&self, t: f64, _q: &[f64], _v: &[f64], f: &mut [f64]) {
        let a = self.omega * t + self.phase;
        let amp = self.m_rho * self.omega * self.omega;
        f[self.idx[0]] += amp * a.cos();
        f[self.idx[1]] += amp * a.sin();
    }
}

/// Hertz rolling-element bearing (B.5): force on the inner ring `−(Fbx, Fby)`,
/// `Fbx = Kc Σ max(δj,0)^p cos θj`, `δj = x cos θj + y sin θj − γ0`, `θj = ωb t + 2π(j−1)/Nb`.
pub struct HertzBearing {
    /// Label.
    pub label: String,
    /// DOF indices x (absent = rigid in x), y.
    pub idx: [Option<usize>; 2],
    /// Contact constant Kc, N/m^p.
    pub kc: f64,
    /// Number of rolling elements.
    pub nb: u32,
    /// Radial clearance γ0, m.
    pub gamma0: f64,
    /// Exponent p (3/2 ball, 10/9 roller).
    pub p: f64,
    /// Cage speed ωb = ω r′/(R′+r′), rad/s.
    pub omega_cage: f64,
}

impl HertzBearing {
    /// Restoring force (Fbx, Fby) exerted BY the rolling elements' deformation (the force on the
    /// inner ring is its negative), N.
    #[must_use]
    pub fn force(&self, t: f64, x: f64, y: f64) -> (f64, f64) {
        let (mut fx, mut fy) = (0.0, 0.0);
        for j in 0..self.nb {
            let th = self.omega_cage * t + 2.0 * PI * j as f64 / self.nb as f64;
            let (s, c) = th.sin_cos();
            let d = x * c + y * s - self.gamma0;
            if d > 0.0 {
                let fj = self.kc * d.powf(self.p);
                fx += fj * c;
                fy += fj * s;
            }
        }
        (fx, fy)
    }
}

impl ForceTerm for HertzBearing {
    fn name(&self) -> String {
        self.label.clone()
    }
    fn add_forces(&self, t: f64, q: &[f64], _v: &[f64], f: &mut [f64]) {
        let x = self.idx[0].map_or(0.0, |i| q[i]);
        let y = self.idx[1].map_or(0.0, |i| q[i]);
        let (fx, fy) = self.force(t, x, y);
        if let Some(i) = self.idx[0] {
            f[i] -= fx;
        }
        if let Some(i) = self.idx[1] {
            f[i] -= fy;
        }
    }
    fn linear_matrices(&self, _k: &mut DMatrix<f64>, _c: &mut DMatrix<f64>) -> bool {
        false
    }
    fn is_nonlinear(&self) -> bool {
        true
    }
}

/// The assembled equations of motion `M q̈ = Σ terms`, with `M` diagonal.
pub struct Model {
    /// Indices into [`DOF_NAMES`] of the retained DOFs, in order.
    pub dofs: Vec<usize>,
    /// Diagonal mass (kg or kg·m²).
    pub mass: Vec<f64>,
    /// The force terms.
    pub terms: Vec<Box<dyn ForceTerm>>,
    /// The mesh kernel (DTE, mesh force).
    pub mesh: Arc<MeshCore>,
    /// Nominal speeds ω1, ω2, rad/s.
    pub omega: [f64; 2],
    /// Period of the Poincaré map (mesh period × hunting factor when shaft-periodic forcing is
    /// present), s.
    pub poincare_period: f64,
    /// Maximal step hint (Hertz bearings: a fraction of the ball-pass period), s.
    pub max_step: f64,
}

impl Model {
    /// Number of DOFs.
    #[must_use]
    pub fn n(&self) -> usize {
        self.dofs.len()
    }

    /// DOF names in order.
    #[must_use]
    pub fn dof_names(&self) -> Vec<&'static str> {
        self.dofs.iter().map(|&d| DOF_NAMES[d]).collect()
    }

    /// Index of a named DOF.
    #[must_use]
    pub fn index_of(&self, name: &str) -> Option<usize> {
        self.dofs.iter().position(|&d| DOF_NAMES[d] == name)
    }

    /// All breakpoints of the enabled terms in `(t0, t1)`, sorted and de-duplicated, s.
    #[must_use]
    pub fn breakpoints(&self, t0: f64, t1: f64) -> Vec<f64> {
        let mut v = Vec::new();
        for term in &self.terms {
            term.breakpoints(t0, t1, &mut v);
        }
        v.sort_by(f64::total_cmp);
        v.dedup_by(|a, b| (*a - *b).abs() < 1e-12 * self.mesh.t0);
        v
    }

    /// True when no term is nonlinear or time-varying (linear fast path applies).
    #[must_use]
    pub fn is_linear(&self) -> bool {
        !self.terms.iter().any(|t| t.is_nonlinear())
    }

    /// Mechanical energy audit quantity `½vᵀMv + Σ V_terms`, J.
    #[must_use]
    pub fn energy(&self, t: f64, y: &[f64]) -> f64 {
        let n = self.n();
        let (q, v) = y.split_at(n);
        let ke: f64 = (0..n).map(|i| 0.5 * self.mass[i] * v[i] * v[i]).sum();
        ke + self
            .terms
            .iter()
            .filter_map(|term| term.potential(t, q))
            .sum::<f64>()
    }

    /// Total energy source rate Σ (P + dV/dt), W.
    #[must_use]
    pub fn source_rate(&self, t: f64, y: &[f64]) -> f64 {
        let n = self.n();
        let (q, v) = y.split_at(n);
        self.terms
            .iter()
            .map(|term| term.source_rate(t, q, v))
            .sum()
    }

    /// Linear (mean-stiffness) stiffness and damping matrices; `None` if a term has no linear form.
    #[must_use]
    pub fn linear_matrices(&self) -> Option<(DMatrix<f64>, DMatrix<f64>)> {
        let n = self.n();
        let (mut k, mut c) = (DMatrix::zeros(n, n), DMatrix::zeros(n, n));
        for term in &self.terms {
            if !term.linear_matrices(&mut k, &mut c) {
                return None;
            }
        }
        Some((k, c))
    }
}

impl OdeSystem for Model {
    fn dim(&self) -> usize {
        2 * self.n()
    }
    fn rhs(&self, t: f64, y: &[f64], dy: &mut [f64]) {
        let n = self.n();
        let (q, v) = y.split_at(n);
        let (dq, dv) = dy.split_at_mut(n);
        dq.copy_from_slice(v);
        dv.fill(0.0);
        for term in &self.terms {
            term.add_forces(t, q, v, dv);
        }
        for (a, m) in dv.iter_mut().zip(&self.mass) {
            *a /= m;
        }
    }
}

/// The model augmented with one state: the integrated energy source `∫ Σ (P + dV/dt) dt`, J.
pub struct EnergyAugmented<'a>(pub &'a Model);

impl OdeSystem for EnergyAugmented<'_> {
    fn dim(&self) -> usize {
        2 * self.0.n() + 1
    }
    fn rhs(&self, t: f64, y: &[f64], dy: &mut [f64]) {
        let m = 2 * self.0.n();
        self.0.rhs(t, &y[..m], &mut dy[..m]);
        dy[m] = self.0.source_rate(t, &y[..m]);
    }
}
