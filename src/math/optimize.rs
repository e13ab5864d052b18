//! Multistart Nelder–Mead (argmin), shared by the phase compensation of `analysis::tolerance`,
//! the best assembly of `analysis::transplanter` and the target bands of `synthesis`.

use argmin::core::{CostFunction, Executor};
use argmin::solver::neldermead::NelderMead;
use nalgebra::DVector;
use rayon::prelude::*;

/// Multistart Nelder–Mead (argmin): from each start an axis-aligned simplex with edge `step`
/// (in the parameter's unit, e.g. rad), stopped when the simplex values' standard deviation falls
/// below `sd_tolerance` (the cost's unit) or after `max_iters` iterations. Returns the best
/// parameter of every start that ran (the caller projects it onto its domain and re-evaluates).
pub fn nelder_mead_starts<C>(
    make_cost: impl Fn() -> C + Sync,
    starts: &[Vec<f64>],
    step: f64,
    sd_tolerance: f64,
    max_iters: u64,
) -> Vec<Vec<f64>>
where
    C: CostFunction<Param = DVector<f64>, Output = f64>,
{
    // The starts are independent: run side by side (rayon), results in the starts' order.
    starts
        .par_iter()
        .filter_map(|x0| {
            let mut simplex = vec![DVector::from_vec(x0.clone())];
            for k in 0..x0.len() {
                let mut v = x0.clone();
                v[k] += step;
                simplex.push(DVector::from_vec(v));
            }
            let solver = NelderMead::new(simplex)
                .with_sd_tolerance(sd_tolerance)
                .ok()?;
            let r = Executor::new(make_cost(), solver)
                .configure(|s| s.max_iters(max_iters))
                .run()
                .ok()?;
            r.state().best_param.as_ref().map(|p| p.as_slice().to_vec())
        })
        .collect()
}
