//! Levenberg–Marquardt for small nonlinear least-squares problems whose trial points may be
//! inadmissible: the synthesis's arm (dyad) and timing fits.
//!
//! Minimises `‖r(x)‖²` over `x ∈ ℝⁿ`. Each iteration solves Marquardt's scaled normal equations
//!
//! ```text
//! (JᵀJ + λ·diag(JᵀJ)) δ = −Jᵀr
//! ```
//!
//! and accepts `x + δ` when its residuals exist (the problem may call a point inadmissible: a
//! ratio that leaves its bounds, a train that cannot be built) and lower the cost; then
//! `λ ← max(0.3·λ, λ_min)`, else `λ ← 10·λ` and the step is solved again. It stops when no
//! damping gives a better point, after an accepted step shorter than `step_tol`, or after
//! `max_iterations` (Marquardt, SIAM J. Appl. Math. 11(2), 1963; Nocedal & Wright, *Numerical
//! Optimization*, ch. 10.3). A parameter the residuals do not depend on (a zero column of `J`)
//! does not move.
//!
//! Hand-written rather than taken from a crate: argmin 0.11 has no Levenberg–Marquardt, and the
//! `levenberg-marquardt` crate (which the chain's refinement uses, its residuals always defined)
//! ends the run at the first residual it cannot evaluate, where these fits must reject the step
//! and damp it. The design chain's fit keeps its own solver
//! (`design::fit::solver`): its trial steps re-project the points and go through the gear-limit
//! continuation, which this small solver does not know.

use nalgebra::{DMatrix, DVector};

/// A least-squares problem: its residuals and, optionally, their Jacobian.
pub trait LeastSquares {
    /// The residual vector at `x`; `None` when `x` is inadmissible.
    fn residuals(&self, x: &[f64]) -> Option<DVector<f64>>;

    /// The Jacobian `∂r/∂x` at `x`, whose residuals are `r`; `None` when a point it needs is
    /// inadmissible. Default: forward differences with step `10⁻⁷·max(|x_c|, 1)`.
    fn jacobian(&self, x: &[f64], r: &DVector<f64>) -> Option<DMatrix<f64>> {
        let mut j = DMatrix::zeros(r.len(), x.len());
        let mut xp = x.to_vec();
        for c in 0..x.len() {
            let h = 1e-7 * x[c].abs().max(1.0);
            xp[c] = x[c] + h;
            let rp = self.residuals(&xp)?;
            j.set_column(c, &((rp - r) / h));
            xp[c] = x[c];
        }
        Some(j)
    }
}

/// A closure `x ↦ r(x)` (`None`: inadmissible) as a [`LeastSquares`] problem with the
/// forward-difference Jacobian.
pub struct Residuals<F>(pub F);

impl<F: Fn(&[f64]) -> Option<DVector<f64>>> LeastSquares for Residuals<F> {
    fn residuals(&self, x: &[f64]) -> Option<DVector<f64>> {
        (self.0)(x)
    }
}

/// Options of [`levenberg_marquardt()`].
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub struct LmOptions {
    /// Damping λ of the first step (default 1e-3).
    pub initial_damping: f64,
    /// Smallest damping after accepted steps (default 1e-15).
    pub min_damping: f64,
    /// Iterations (accepted steps) at most (default 200).
    pub max_iterations: usize,
    /// Damping increases tried per iteration before giving up (default 30).
    pub max_damping_steps: usize,
    /// The run stops after an accepted step whose Euclidean length is at most this, in the
    /// units of `x` (default 1e-14).
    pub step_tol: f64,
}

impl Default for LmOptions {
    fn default() -> Self {
        Self {
            initial_damping: 1e-3,
            min_damping: 1e-15,
            max_iterations: 200,
            max_damping_steps: 30,
            step_tol: 1e-14,
        }
    }
}

crate::builder::with_fields!(LmOptions {
    with_initial_damping => initial_damping: f64,
    with_min_damping => min_damping: f64,
    with_max_iterations => max_iterations: usize,
    with_max_damping_steps => max_damping_steps: usize,
    with_step_tol => step_tol: f64,
});

/// The point Levenberg–Marquardt reaches on `problem` from `x0` (see the module docs); `x0`
/// itself when its residuals do not exist or no step lowers the cost.
///
/// ```
/// use nalgebra::DVector;
/// use ncgear::math::least_squares::{LmOptions, Residuals, levenberg_marquardt};
/// // Rosenbrock's function as residuals (1 − x, 10(y − x²)): its minimum is (1, 1).
/// let p = Residuals(|x: &[f64]| Some(DVector::from_vec(vec![1.0 - x[0], 10.0 * (x[1] - x[0] * x[0])])));
/// let x = levenberg_marquardt(&p, vec![-1.2, 1.0], &LmOptions::default());
/// assert!((x[0] - 1.0).abs() < 1e-10 && (x[1] - 1.0).abs() < 1e-10);
/// ```
#[must_use]
pub fn levenberg_marquardt(
    problem: &impl LeastSquares,
    mut x: Vec<f64>,
    opts: &LmOptions,
) -> Vec<f64> {
    let Some(mut r) = problem.residuals(&x) else {
        return x;
    };
    let n = x.len();
    let mut lambda = opts.initial_damping;
    for _ in 0..opts.max_iterations {
        let Some(j) = problem.jacobian(&x, &r) else {
            break;
        };
        let jt = j.transpose();
        let (a, g) = (&jt * &j, &jt * &r);
        let mut accepted = false;
        for _ in 0..opts.max_damping_steps {
            let mut damped = a.clone();
            for i in 0..n {
                // A zero diagonal is a parameter nothing depends on: its step is 0.
                damped[(i, i)] = if a[(i, i)] == 0.0 {
                    1.0
                } else {
                    a[(i, i)] + lambda * a[(i, i)].max(1e-12)
                };
            }
            let Some(step) = damped.lu().solve(&(-&g)) else {
                lambda *= 10.0;
                continue;
            };
            let trial: Vec<f64> = x.iter().zip(step.iter()).map(|(a, b)| a + b).collect();
            if let Some(rt) = problem
                .residuals(&trial)
                .filter(|rt| rt.norm_squared() < r.norm_squared())
            {
                let small = step.norm() <= opts.step_tol;
                (x, r) = (trial, rt);
                lambda = (lambda * 0.3).max(opts.min_damping);
                accepted = !small;
                break;
            }
            lambda *= 10.0;
        }
        if !accepted {
            break;
        }
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A circle through three points: residuals |p_k − c| − ρ, the exact centre and radius known.
    #[test]
    fn fits_a_circle_and_keeps_a_parameter_nothing_depends_on() {
        let pts = [(3.0, 0.0), (-1.0, 4.0), (-1.0, -4.0)]; // on the circle about (−1, 0), ρ = 4
        let p = Residuals(|x: &[f64]| {
            Some(DVector::from_iterator(
                pts.len(),
                pts.iter().map(|&(u, v)| (u - x[0]).hypot(v - x[1]) - x[2]),
            ))
        });
        let x = levenberg_marquardt(&p, vec![0.5, 0.5, 1.0, 7.0], &LmOptions::default());
        assert!((x[0] + 1.0).abs() < 1e-12 && x[1].abs() < 1e-12 && (x[2] - 4.0).abs() < 1e-12);
        assert_eq!(x[3], 7.0, "a parameter no residual depends on stays");
    }

    /// Inadmissible points (x < 0) are rejected and damped, not the end of the run.
    #[test]
    fn rejects_inadmissible_trial_points() {
        let p = Residuals(|x: &[f64]| {
            (x[0] >= 0.0).then(|| DVector::from_vec(vec![x[0] * x[0] - 2.0]))
        });
        let x = levenberg_marquardt(
            &p,
            vec![0.1],
            &LmOptions::default().with_initial_damping(1e-9),
        );
        assert!((x[0] - 2f64.sqrt()).abs() < 1e-12);
        let none = Residuals(|_: &[f64]| None);
        assert_eq!(
            levenberg_marquardt(&none, vec![3.0], &LmOptions::default()),
            vec![3.0]
        );
    }
}
