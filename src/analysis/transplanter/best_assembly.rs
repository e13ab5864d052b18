//! Best assembly of the free runout orientations: greedy (docs/math/companion.md §C.3), joint (exhaustive over keyed
//! positions or multistart Nelder–Mead) and the random-assembly distribution to compare with.

use super::common::{TransplanterOptions, UM, exact_max, mc_error, rng_for};
use super::report::{AssemblyOptimum, GreedyChoice};
use super::{ExactModel, GEARS, Inventory, LinearModel, TransplanterError, ecc_index};
use crate::math::Point;
use crate::math::monte_carlo;
use crate::math::optimize::nelder_mead_starts;
use crate::progress::Progress;
use argmin::core::CostFunction;
use nalgebra::DVector;
use rand::RngExt;
use rayon::prelude::*;
use std::f64::consts::TAU;

/// `max_φ |base(φ) + Σ_k m_k (cos γ_k S_x + sin γ_k S_y)|` for the free gears.
struct Objective<'a> {
    lin: &'a LinearModel,
    base: Vec<Point>,
    free: Vec<usize>,
    magnitude: Vec<f64>,
}

impl<'a> Objective<'a> {
    /// The objective of the free gears `free` of `inv`: their eccentricities zeroed in the base
    /// deviations, their magnitudes (mm) kept for [`Objective::value`].
    fn new(lin: &'a LinearModel, inv: &Inventory, free: &[usize]) -> Self {
        let mut x0 = inv.nominal_vector();
        for &k in free {
            x0[ecc_index(k)] = 0.0;
            x0[ecc_index(k) + 1] = 0.0;
        }
        Objective {
            lin,
            base: lin.deviations(&x0),
            magnitude: free
                .iter()
                .map(|&k| inv.eccentricity[k].magnitude_mm)
                .collect(),
            free: free.to_vec(),
        }
    }

    /// Objective (mm) with the first `active` free gears at directions `gammas` (rad).
    fn value(&self, gammas: &[f64], active: usize) -> f64 {
        let cs: Vec<(f64, f64)> = gammas.iter().map(|g| (g.cos(), g.sin())).collect();
        self.base
            .iter()
            .zip(&self.lin.jacobian)
            .map(|(b, col)| {
                let mut d = *b;
                for (a, &k) in self.free.iter().enumerate().take(active) {
                    let (c, s) = cs[a];
                    let (sx, sy) = (col[ecc_index(k)], col[ecc_index(k) + 1]);
                    let m = self.magnitude[a];
                    d.x += m * (c * sx.x + s * sy.x);
                    d.y += m * (c * sx.y + s * sy.y);
                }
                d.hypot()
            })
            .fold(0.0, f64::max)
    }
}

impl CostFunction for Objective<'_> {
    type Param = DVector<f64>;
    type Output = f64;
    fn cost(&self, p: &DVector<f64>) -> Result<f64, argmin::core::Error> {
        Ok(self.value(p.as_slice(), self.free.len()))
    }
}

fn candidates(inv: &Inventory, k: usize, continuous_steps: usize) -> Vec<f64> {
    let e = &inv.eccentricity[k];
    let n = if e.keyed > 0 {
        e.keyed
    } else {
        continuous_steps
    };
    (0..n).map(|i| e.position_direction(i, n)).collect()
}

/// The best assembly of the free eccentricity directions (`None` when none is free); the
/// random-assembly Monte Carlo reports to `progress`.
pub(super) fn optimize_assembly(
    model: &ExactModel,
    lin: &LinearModel,
    inv: &Inventory,
    opts: &TransplanterOptions,
    progress: &Progress,
) -> Result<Option<AssemblyOptimum>, TransplanterError> {
    let free = inv.free_gears();
    if free.is_empty() {
        return Ok(None);
    }
    let obj = Objective::new(lin, inv, &free);
    let given: Vec<f64> = free
        .iter()
        .map(|&k| inv.eccentricity[k].direction_rad)
        .collect();
    let as_given = obj.value(&given, free.len());
    let (chosen, greedy) = greedy(&obj, inv);
    let greedy_val = obj.value(&chosen, free.len());
    // Joint: exhaustive over keyed positions when small, else multistart Nelder–Mead.
    let keyed: Vec<usize> = free.iter().map(|&k| inv.eccentricity[k].keyed).collect();
    let combos: usize = keyed.iter().map(|&n| n.max(1)).product();
    let (joint, method) = if keyed.iter().all(|&n| n > 0) && combos <= 100_000 {
        let fallback = (greedy_val, chosen.clone());
        (exhaustive(&obj, inv, combos, fallback), "exhaustive")
    } else {
        (
            multistart(&obj, inv, opts, (greedy_val, chosen)),
            "nelder-mead",
        )
    };
    let mut gammas = inv.eccentricity.map(|e| e.direction_rad);
    for (a, &k) in free.iter().enumerate() {
        gammas[k] = joint.1[a];
    }
    let best_x = inv.with_directions(&gammas);
    let joint_exact = exact_max(model, lin, &best_x)?;
    let joint_deviation_um = lin
        .deviations(&best_x)
        .iter()
        .map(|d| d.hypot() * UM)
        .collect();
    // Random assembly: free directions random, everything else as given.
    let (random, vals) = monte_carlo::run(
        &opts.mc,
        |rng, _| {
            let gs: Vec<f64> = free
                .iter()
                .map(|&k| inv.eccentricity[k].random_direction(rng))
                .collect();
            obj.value(&gs, free.len()) * UM
        },
        progress,
    )
    .map_err(mc_error("random assembly"))?;
    let p = vals.iter().filter(|v| **v <= joint.0 * UM).count() as f64 / vals.len().max(1) as f64;
    Ok(Some(AssemblyOptimum {
        free: free.iter().map(|&k| GEARS[k].to_string()).collect(),
        keyed_positions: keyed,
        as_given_um: as_given * UM,
        greedy,
        greedy_um: greedy_val * UM,
        joint_directions_deg: joint
            .1
            .iter()
            .map(|g| g.to_degrees().rem_euclid(360.0))
            .collect(),
        joint_um: joint.0 * UM,
        joint_exact_um: joint_exact * UM,
        joint_method: method.into(),
        gain_vs_random_mean_percent: if random.mean > 0.0 {
            100.0 * (1.0 - joint.0 * UM / random.mean)
        } else {
            0.0
        },
        random,
        p_random_beats_joint: p,
        joint_deviation_um,
    }))
}

/// Greedy (docs/math/companion.md §C.3): each free gear in order takes the best of its scan
/// positions (keyed, or 72 continuous steps) given the choices before it. Returns the chosen
/// directions (rad) and the per-gear record.
fn greedy(obj: &Objective, inv: &Inventory) -> (Vec<f64>, Vec<GreedyChoice>) {
    let mut chosen: Vec<f64> = Vec::new();
    let mut greedy = Vec::new();
    for (a, &k) in obj.free.iter().enumerate() {
        let mut best = (f64::INFINITY, 0.0);
        for g in candidates(inv, k, 72) {
            let mut gs = chosen.clone();
            gs.push(g);
            let v = obj.value(&gs, a + 1);
            if v < best.0 {
                best = (v, g);
            }
        }
        chosen.push(best.1);
        greedy.push(GreedyChoice {
            gear: GEARS[k].into(),
            direction_deg: best.1.to_degrees().rem_euclid(360.0),
            max_deviation_um: best.0 * UM,
        });
    }
    (chosen, greedy)
}

/// The best `(objective mm, directions rad)` over all `combos` combinations of keyed
/// positions (in parallel), or `fallback` when there is none.
fn exhaustive(
    obj: &Objective,
    inv: &Inventory,
    combos: usize,
    fallback: (f64, Vec<f64>),
) -> (f64, Vec<f64>) {
    let free = &obj.free;
    let lists: Vec<Vec<f64>> = free.iter().map(|&k| candidates(inv, k, 1)).collect();
    (0..combos)
        .into_par_iter()
        .map(|mut c| {
            let gs: Vec<f64> = lists
                .iter()
                .map(|l| {
                    let g = l[c % l.len()];
                    c /= l.len();
                    g
                })
                .collect();
            (obj.value(&gs, free.len()), gs)
        })
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .unwrap_or(fallback)
}

/// Multistart Nelder–Mead from the greedy choice `start` (objective mm, directions rad) and
/// `opts.starts` random directions, keyed gears snapped to their positions: the best
/// `(objective mm, directions rad)`, at worst `start`.
fn multistart(
    obj: &Objective,
    inv: &Inventory,
    opts: &TransplanterOptions,
    start: (f64, Vec<f64>),
) -> (f64, Vec<f64>) {
    let free = &obj.free;
    let d = free.len();
    let mut rng = rng_for(opts.mc.seed, 3, 0);
    let mut inits: Vec<Vec<f64>> = vec![start.1.clone()];
    for _ in 0..opts.starts {
        inits.push((0..d).map(|_| rng.random::<f64>() * TAU).collect());
    }
    let mut best = start;
    let make = || Objective {
        lin: obj.lin,
        base: obj.base.clone(),
        free: obj.free.clone(),
        magnitude: obj.magnitude.clone(),
    };
    for p in nelder_mead_starts(make, &inits, 0.4, 1e-12, 300) {
        // Snap keyed gears to their positions.
        let gs: Vec<f64> = p
            .iter()
            .zip(free)
            .map(|(g, &k)| {
                let e = &inv.eccentricity[k];
                if e.keyed > 0 {
                    let step = TAU / e.keyed as f64;
                    e.direction_rad + ((g - e.direction_rad) / step).round() * step
                } else {
                    *g
                }
            })
            .collect();
        let v = obj.value(&gs, d);
        if v < best.0 {
            best = (v, gs);
        }
    }
    best
}
