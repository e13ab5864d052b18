//! The assembled model: DOF set, diagonal mass, and the list of force terms built once from a
//! scene (docs/math/companion.md §B.6, §B.10). The right-hand side loops over the terms; it never tests switches.
//!
//! `mesh` holds the mesh kernel (stiffness law, STE, backlash, tip relief), `terms` the other
//! force terms (constant forces, springs, friction, unbalance, Hertz bearings).

mod mesh;
mod terms;

pub use mesh::*;
pub use terms::*;

use super::ode::OdeSystem;
use nalgebra::DMatrix;
use std::sync::Arc;

/// Names of the 16 generalized coordinates in the patent's order (docs/math/companion.md §B.1), plus `u`, the SDOF
/// relative coordinate `rb1 θ1 − rb2 θ2` (m) used when the model reduces to one DOF.
pub const DOF_NAMES: [&str; 17] = [
    "theta_p", "x1", "y1", "theta1", "x2", "y2", "theta2", "xb1", "yb1", "xb2", "yb2", "xb3",
    "yb3", "xb4", "yb4", "theta_q", "u",
];

/// A state-event function `g(t, q)` (q: coordinates); its zeros are kinks of a force law.
pub type StateEvent<'a> = Box<dyn Fn(f64, &[f64]) -> f64 + Send + Sync + 'a>;

/// A generalized force contribution (docs/math/companion.md §B.10 term list). `q`, `v`: coordinates (m or rad) and
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
