//! Refinement beyond the patent: direct least-squares fit of the sun ratio to the target needle
//! motion (docs/math/chain.md §8.3).
//!
//! Parameters `q = (a_1..a_K, b_1..b_K, τ_s, C)`; residuals at `J` uniform carrier angles
//! `x_j` (rad from the reference instant):
//!
//! ```text
//! r_j = l3·( C − S(x_j − τ_s) + ψ3_target(x_j) )          (mm; = l3·Δβ, the tip error to first order)
//! ```
//!
//! with the planet contact map `S(t) = Φ⁻¹(Φ(t) + c)`, `c = π` on the carrier line (the patent's
//! train) or `π + 2ε` for an intermediate axis turned off it by ε (docs/math/chain.md §6.5).
//!
//! plus penalties: `w_b·dist(i21, [i_min, i_max])` at the same angles, optionally
//! `w_c·max(0, −Δ/a²)` for the convexity of the sun and the intermediate, and the smoothness term
//! `√λ·k²·(a_k, b_k)`. Solved by Levenberg–Marquardt (`levenberg-marquardt` crate) with a
//! forward-difference Jacobian, started from the patent route's fit.

use crate::design::inverse::needle_law::NeedleLaw;
use crate::geometry::fourier::SunRatio;
use crate::geometry::mechanism::{ContactGeometry, INVERSE_TOL_RAD};
use levenberg_marquardt::{LeastSquaresProblem, LevenbergMarquardt};
use nalgebra::{DMatrix, DVector, Dyn, Owned};
use rayon::prelude::*;
use std::f64::consts::{PI, TAU};

/// Options of the refinement (docs/math/chain.md §8.3).
#[derive(
    Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize, schemars::JsonSchema,
)]
#[serde(default, deny_unknown_fields)]
#[non_exhaustive]
pub struct RefineOptions {
    /// Residual samples `J` (at least 4K are used). Default 360.
    pub samples: usize,
    /// Ratio bounds `[i_min, i_max]` (dimensionless; docs/math/chain.md §14). Default [0.3, 3.3].
    pub ratio_bounds: [f64; 2],
    /// Penalise concave sun/intermediate arcs. Default false.
    pub convexity_penalty: bool,
    /// Smoothness weight √λ relative to l3 (dimensionless). Default 1e-4.
    pub smoothness: f64,
    /// Cap on residual evaluations, in multiples of (parameters + 1). Default 60.
    pub patience: usize,
}

crate::builder::with_fields!(RefineOptions {
    with_samples => samples: usize,
    with_ratio_bounds => ratio_bounds: [f64; 2],
    with_convexity_penalty => convexity_penalty: bool,
    with_smoothness => smoothness: f64,
    with_patience => patience: usize,
});

impl Default for RefineOptions {
    fn default() -> Self {
        Self {
            samples: 360,
            ratio_bounds: [0.3, 3.3],
            convexity_penalty: false,
            smoothness: 1e-4,
            patience: 60,
        }
    }
}

/// Outcome of a refinement.
#[derive(Debug, Clone)]
pub struct Refined {
    /// Fitted sun ratio.
    pub ratio: SunRatio,
    /// Sun phase τ_s, rad from the reference instant.
    pub tau_rad: f64,
    /// Offset `C = π + γ`, rad.
    pub offset_rad: f64,
    /// Residual evaluations used.
    pub evaluations: usize,
    /// Solver's termination reason.
    pub termination: String,
}

struct Problem<'a> {
    law: &'a NeedleLaw,
    /// The contact shift `c` of the planet contact map, rad.
    shift_rad: f64,
    l3: f64,
    a_mm: f64,
    order: usize,
    xs: Vec<f64>,
    targets: Vec<f64>,
    opts: RefineOptions,
    q: DVector<f64>,
}

impl Problem<'_> {
    fn residuals_at(&self, q: &DVector<f64>) -> DVector<f64> {
        let k = self.order;
        let ratio =
            SunRatio::new_unchecked(q.as_slice()[..k].to_vec(), q.as_slice()[k..2 * k].to_vec());
        let (tau, c) = (q[2 * k], q[2 * k + 1]);
        let j = self.xs.len();
        let nconv = if self.opts.convexity_penalty {
            2 * j
        } else {
            0
        };
        let mut r = DVector::zeros(2 * j + nconv + 2 * k);
        let wb = 10.0 * self.l3;
        let [lo, hi] = self.opts.ratio_bounds;
        for (idx, (&x, &target)) in self.xs.iter().zip(&self.targets).enumerate() {
            let s = ratio.contact_map(x - tau, self.shift_rad, INVERSE_TOL_RAD);
            r[idx] = self.l3 * (c - s + target);
            let g = ratio.eval3(x);
            r[j + idx] = wb * ((lo - g[0]).max(0.0) + (g[0] - hi).max(0.0));
            if self.opts.convexity_penalty {
                let cv = ContactGeometry::new(self.a_mm, g).convexity_mm2();
                let a2 = self.a_mm * self.a_mm;
                r[2 * j + 2 * idx] = wb * (-cv[0] / a2).max(0.0);
                r[2 * j + 2 * idx + 1] = wb * (-cv[1] / a2).max(0.0);
            }
        }
        let w = self.opts.smoothness * self.l3;
        for kk in 0..2 * k {
            let h = (kk % k + 1) as f64;
            r[2 * j + nconv + kk] = w * h * h * q[kk];
        }
        r
    }
}

impl LeastSquaresProblem<f64, Dyn, Dyn> for Problem<'_> {
    type ResidualStorage = Owned<f64, Dyn>;
    type JacobianStorage = Owned<f64, Dyn, Dyn>;
    type ParameterStorage = Owned<f64, Dyn>;

    fn set_params(&mut self, x: &DVector<f64>) {
        self.q.copy_from(x);
    }

    fn params(&self) -> DVector<f64> {
        self.q.clone()
    }

    fn residuals(&self) -> Option<DVector<f64>> {
        let r = self.residuals_at(&self.q);
        r.iter().all(|v| v.is_finite()).then_some(r)
    }

    fn jacobian(&self) -> Option<DMatrix<f64>> {
        let r0 = self.residuals_at(&self.q);
        let n = self.q.len();
        let cols: Vec<DVector<f64>> = (0..n)
            .into_par_iter()
            .map(|i| {
                let h = 1e-7 * self.q[i].abs().max(1.0);
                let mut qh = self.q.clone();
                qh[i] += h;
                (self.residuals_at(&qh) - &r0) / h
            })
            .collect();
        let jac = DMatrix::from_columns(&cols);
        jac.iter().all(|v| v.is_finite()).then_some(jac)
    }
}

/// Refines a starting ratio (τ-frame, origin `tau0` rad, offset `c0` rad) against the target law.
#[must_use]
pub fn refine(
    law: &NeedleLaw,
    l3_mm: f64,
    a_mm: f64,
    start: &SunRatio,
    tau0: f64,
    c0: f64,
    opts: &RefineOptions,
) -> Refined {
    refine_with_shift(law, PI, l3_mm, a_mm, start, [tau0, c0], opts)
}

/// [`refine`] for a train whose planet contact map shifts by `shift_rad` (`π + 2ε`; module
/// documentation), from `[τ0, C0]` (rad).
pub(crate) fn refine_with_shift(
    law: &NeedleLaw,
    shift_rad: f64,
    l3_mm: f64,
    a_mm: f64,
    start: &SunRatio,
    [tau0, c0]: [f64; 2],
    opts: &RefineOptions,
) -> Refined {
    let order = start.order();
    let j = opts.samples.max(4 * order).max(16);
    let xs: Vec<f64> = (0..j).map(|i| TAU * i as f64 / j as f64).collect();
    let targets = xs.iter().map(|&x| law.psi3(x)).collect();
    let mut q: Vec<f64> = start.cos_coefficients().to_vec();
    q.extend_from_slice(start.sin_coefficients());
    q.push(tau0);
    q.push(c0);
    let problem = Problem {
        law,
        shift_rad,
        l3: l3_mm,
        a_mm,
        order,
        xs,
        targets,
        opts: *opts,
        q: DVector::from_vec(q),
    };
    let _ = problem.law;
    let (done, report) = LevenbergMarquardt::new()
        .with_patience(opts.patience)
        .minimize(problem);
    let q = done.q;
    let ratio = SunRatio::new_unchecked(
        q.as_slice()[..order].to_vec(),
        q.as_slice()[order..2 * order].to_vec(),
    );
    Refined {
        ratio,
        tau_rad: q[2 * order],
        offset_rad: q[2 * order + 1],
        evaluations: report.number_of_evaluations,
        termination: format!("{:?}", report.termination),
    }
}
