//! The force terms besides the mesh: constant forces, linear spring–dampers, sliding friction
//! (docs/math/companion.md §B.4), mass unbalance and Hertz rolling-element bearings (docs/math/companion.md §B.5).

use super::ForceTerm;
use super::mesh::{MeshCore, PairState, push_periodic};
use crate::analysis::dynamics::tvms::PairGeometry;
use nalgebra::DMatrix;
use std::f64::consts::PI;
use std::sync::Arc;

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

/// Friction direction law (docs/math/companion.md §B.4).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FrictionDirection {
    /// λ = +1 before the pitch point, −1 after (breakpoints at the pitch-point times).
    PitchSwitch,
    /// λ = −tanh(v_s / v0), v0 in m/s.
    Tanh(f64),
}

/// Sliding friction with friction arms (docs/math/companion.md §B.4, §B.4 eq. B-6, docs/math/companion.md §B.6 eq. B-7).
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

/// Mass unbalance forcing `m ρ ω² (cos Φ, sin Φ)`, Φ = ω t + φ (docs/math/companion.md §B.5, kind = unbalance).
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

/// Hertz rolling-element bearing (docs/math/companion.md §B.5): force on the inner ring `−(Fbx, Fby)`,
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
