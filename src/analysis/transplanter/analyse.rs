//! The analysis on top of the models: validation of the linear model, Monte Carlo, deviation
//! envelope, feature distributions, sensitivity ranking and the best assembly of the free
//! runout orientations (spec C.6 items 3, 4, 6).

use super::model::{ExactModel, FdSteps, LinearModel, TrainState};
use super::{
    ARM, BACKLASH, ErrorVector, GEARS, Inventory, N_COORDS, PIN_A, PIN_D, TransplanterError,
    clock_index, ecc_index,
};
use crate::analysis::montecarlo::{self, McError, McOptions, McStats};
use crate::analysis::tolerance::{ARCSEC_PER_RAD, nelder_mead_starts};
use crate::geometry::assembly::{Assembly, Pose};
use crate::math::periodic::wrap_pi;
use crate::simulate::{FeatureOptions, Features, TwoArms, features_of_turn};
use argmin::core::CostFunction;
use nalgebra::DVector;
use rand::rngs::ChaCha8Rng;
use rand::{RngExt, SeedableRng};
use rayon::prelude::*;
use serde::Serialize;
use std::f64::consts::TAU;

const UM: f64 = 1e3; // µm per mm

/// Options of [`analyse`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TransplanterOptions {
    /// Monte Carlo of random assembly (samples, seed, histogram bins).
    pub mc: McOptions,
    /// Samples at 3σ used to validate the linear model against the exact one (spec: 100).
    pub validation_samples: usize,
    /// Largest accepted relative error of the linear model; above it the Monte Carlo uses the
    /// exact model (spec: 0.05).
    pub linear_tolerance: f64,
    /// Exact-model samples of the agronomic-feature distributions (0: skip).
    pub feature_samples: usize,
    /// Random starts of the joint assembly optimiser (Nelder–Mead).
    pub starts: usize,
    /// Finite-difference steps of the linear model.
    pub fd_steps: FdSteps,
    /// Options of the agronomic features (speeds, planting depth).
    pub features: FeatureOptions,
}

impl Default for TransplanterOptions {
    fn default() -> Self {
        Self {
            mc: McOptions::default(),
            validation_samples: 100,
            linear_tolerance: 0.05,
            feature_samples: 200,
            starts: 16,
            fd_steps: FdSteps::default(),
            features: FeatureOptions::default(),
        }
    }
}

/// Linear vs exact model on samples at the 3σ tolerances.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Validation {
    /// Number of samples.
    pub samples: usize,
    /// Largest relative error `max_φ|ΔB_lin − ΔB_exact| / max_φ|ΔB_exact|` over the samples.
    pub max_relative_error: f64,
    /// Mean relative error.
    pub mean_relative_error: f64,
    /// Largest absolute error, µm.
    pub max_absolute_error_um: f64,
    /// Model used by the Monte Carlo: "linear" or "exact" (fallback).
    pub model_used: String,
}

/// The tip-deviation envelope at one carrier angle.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct EnvelopePoint {
    /// Carrier angle φH, degrees (world).
    pub carrier_deg: f64,
    /// Nominal tip, mm.
    pub nominal_tip_mm: [f64; 2],
    /// Mean tip deviation over random assembly, µm.
    pub mean_deviation_um: [f64; 2],
    /// `3·sqrt(λ_max)` of the deviation covariance, µm.
    pub three_sigma_um: f64,
    /// Envelope `|mean| + 3σ`, µm.
    pub envelope_um: f64,
    /// Deviation with the nominal (as-given) errors, linear model, µm.
    pub nominal_errors_um: f64,
    /// Unit normal of the nominal path (left of the travel direction), for drawing the band.
    pub normal: [f64; 2],
}

/// Distributions of the agronomic-feature deviations (perturbed − nominal), exact model.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FeatureDeviations {
    /// Samples (random assemblies).
    pub samples: usize,
    /// Features of the error-free train (same sampling).
    pub nominal: Features,
    /// Trajectory height, mm.
    pub height_mm: McStats,
    /// Hole width at the planting depth, mm.
    pub hole_width_mm: McStats,
    /// Static loop width at the planting depth, mm.
    pub static_width_at_depth_mm: McStats,
    /// Needle angle at taking, degrees.
    pub needle_angle_take_deg: McStats,
    /// Needle angle at planting, degrees.
    pub needle_angle_plant_deg: McStats,
    /// Lowest point (planting depth reference) `min y`, mm.
    pub lowest_point_mm: McStats,
}

/// Contribution of one error to `max_φ |ΔB|` at its 3σ value.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Contribution {
    /// Error name.
    pub error: String,
    /// Unit of the tolerance: "µm" or "deg".
    pub unit: String,
    /// `|nominal| + 3σ` (or + the half width; eccentricity `e + 3σ`).
    pub three_sigma: f64,
    /// `max_φ |S(φ)|` (µm of tip deviation per unit; worst direction for an eccentricity).
    pub sensitivity_um_per_unit: f64,
    /// Tip deviation at the 3σ value, µm.
    pub max_deviation_um: f64,
    /// Share of the sum of all contributions, %.
    pub share_percent: f64,
}

/// One step of the greedy assembly.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GreedyChoice {
    /// Gear whose runout direction is chosen.
    pub gear: String,
    /// Chosen direction, degrees (body frame).
    pub direction_deg: f64,
    /// `max_φ |ΔB|` with the gears placed so far, µm.
    pub max_deviation_um: f64,
}

/// Best assembly of the free runout orientations.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AssemblyOptimum {
    /// Gears with a free direction.
    pub free: Vec<String>,
    /// Keyed positions of each (0 = continuous).
    pub keyed_positions: Vec<usize>,
    /// `max_φ |ΔB|` with the directions as given in the file, µm.
    pub as_given_um: f64,
    /// Greedy sequential choice (C.3).
    pub greedy: Vec<GreedyChoice>,
    /// Greedy result, µm.
    pub greedy_um: f64,
    /// Joint optimum directions, degrees.
    pub joint_directions_deg: Vec<f64>,
    /// Joint optimum, µm (linear model).
    pub joint_um: f64,
    /// The joint optimum re-evaluated with the exact model, µm.
    pub joint_exact_um: f64,
    /// "exhaustive" (keyed positions) or "nelder-mead" (multistart).
    pub joint_method: String,
    /// `max_φ |ΔB|` over random directions (uniform / uniform over the keys), µm.
    pub random: McStats,
    /// Probability that a random assembly is at least as good as the joint optimum.
    pub p_random_beats_joint: f64,
    /// `1 − joint/mean(random)`, %.
    pub gain_vs_random_mean_percent: f64,
    /// `|ΔB(φH)|` of the joint optimum on the grid (linear model), µm.
    pub joint_deviation_um: Vec<f64>,
}

/// The report of `ncgear tolerance DESIGN.json --errors ERRORS`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TransplanterReport {
    /// Pressure angle, degrees.
    pub pressure_angle_deg: f64,
    /// Loaded flank of the sun–intermediate mesh.
    pub load_side: i8,
    /// Carrier angles per turn.
    pub samples_per_turn: usize,
    /// `max_φ |ΔB|` with the nominal (as-given) errors, exact model, µm.
    pub nominal_errors_exact_um: f64,
    /// The same with the linear model, µm.
    pub nominal_errors_linear_um: f64,
    /// Linear-model validation.
    pub validation: Validation,
    /// Monte Carlo seed.
    pub seed: u64,
    /// `max_φ |ΔB|` over random assemblies, µm.
    pub max_deviation_um: McStats,
    /// `max_φ |Δθ3|` of the planet (the transmission error of spec C) over the same random
    /// assemblies, arc seconds.
    pub planet_angle_error_arcsec: McStats,
    /// Deviation envelope along the trajectory.
    pub envelope: Vec<EnvelopePoint>,
    /// Largest envelope value, µm.
    pub envelope_max_um: f64,
    /// Agronomic-feature deviations.
    pub features: Option<FeatureDeviations>,
    /// Errors sorted by contribution (largest first).
    pub ranking: Vec<Contribution>,
    /// Best assembly of the free runout orientations, when any is free.
    pub assembly: Option<AssemblyOptimum>,
}

/// `max_φ |ΔB|` (mm) of the exact model against the linear model's nominal tips.
fn exact_max(
    model: &ExactModel,
    lin: &LinearModel,
    x: &ErrorVector,
) -> Result<f64, TransplanterError> {
    let mut m: f64 = 0.0;
    for (p, b0) in lin.phis_rad.iter().zip(&lin.nominal_tips_mm) {
        let b = model.state(*p, x)?.tip_mm;
        m = m.max((b[0] - b0[0]).hypot(b[1] - b0[1]));
    }
    Ok(m)
}

/// Maps a Monte Carlo failure of the named quantity to a [`TransplanterError`].
fn mc_error(what: &'static str) -> impl Fn(McError) -> TransplanterError {
    move |e| match e {
        McError::BadOption {
            name,
            value,
            expected,
        } => TransplanterError::BadOption {
            option: name,
            message: format!("{value}: expected {expected}"),
        },
        McError::NonFinite { index } => {
            TransplanterError::Numerical(format!("Monte Carlo sample {index} of the {what}"))
        }
    }
}

/// `max_φ |Δθ3|` (rad) of the exact model.
fn exact_max_angle(
    model: &ExactModel,
    lin: &LinearModel,
    x: &ErrorVector,
) -> Result<f64, TransplanterError> {
    let zero = [0.0; N_COORDS];
    let mut m: f64 = 0.0;
    for p in &lin.phis_rad {
        let a = model.state(*p, x)?.planet_angle_rad;
        let b = model.state(*p, &zero)?.planet_angle_rad;
        m = m.max(wrap_pi(a - b).abs());
    }
    Ok(m)
}

/// Relative error of the linear model on one sample: (relative, absolute mm).
fn linear_error(
    model: &ExactModel,
    lin: &LinearModel,
    x: &ErrorVector,
) -> Result<(f64, f64), TransplanterError> {
    let (mut worst, mut peak): (f64, f64) = (0.0, 0.0);
    for (i, (p, b0)) in lin.phis_rad.iter().zip(&lin.nominal_tips_mm).enumerate() {
        let b = model.state(*p, x)?.tip_mm;
        let d = [b[0] - b0[0], b[1] - b0[1]];
        let l = lin.deviation_at(i, x);
        worst = worst.max((l[0] - d[0]).hypot(l[1] - d[1]));
        peak = peak.max(d[0].hypot(d[1]));
    }
    Ok((if peak > 0.0 { worst / peak } else { 0.0 }, worst))
}

/// Sample `i` of a sub-analysis with its own seed stream family.
fn rng_for(seed: u64, family: u64, i: usize) -> ChaCha8Rng {
    let mut r = ChaCha8Rng::seed_from_u64(seed ^ family.wrapping_mul(0x9E37_79B9_7F4A_7C15));
    r.set_stream(i as u64);
    r
}

fn to_pose(s: &TrainState) -> Pose {
    Pose {
        phi_h_rad: s.phi_h_rad,
        intermediate_center_mm: s.intermediate_center_mm,
        planet_center_mm: s.planet_center_mm,
        intermediate_angle_rad: s.intermediate_angle_rad,
        planet_angle_rad: s.planet_angle_rad,
        tip_mm: s.tip_mm,
        sun_mesh_error_mm: 0.0,
        planet_mesh_error_mm: 0.0,
    }
}

/// Features of the perturbed train (both arms carry the same errors; arm 2 = arm 1 at φH + π).
pub(super) fn perturbed_features(
    model: &ExactModel,
    asm: &Assembly,
    phis: &[f64],
    x: &ErrorVector,
    opts: &FeatureOptions,
) -> Result<Features, TransplanterError> {
    let turn: Result<Vec<TwoArms>, TransplanterError> = phis
        .iter()
        .map(|&p| {
            Ok(TwoArms {
                arm1: to_pose(&model.state(p, x)?),
                arm2: to_pose(&model.state(p + model.half_turn(), x)?),
            })
        })
        .collect();
    features_of_turn(&turn?, asm.center_mm, asm.direction, opts)
        .map_err(|e| TransplanterError::Numerical(format!("features: {e}")))
}

/// The error items of the ranking: an eccentricity (gear k) or a scalar coordinate.
#[derive(Debug, Clone, Copy)]
enum Item {
    Ecc(usize),
    Scalar(usize, &'static str),
}

fn items() -> Vec<(Item, String)> {
    let mut v: Vec<(Item, String)> = (0..3)
        .map(|k| (Item::Ecc(k), format!("{} eccentricity", GEARS[k])))
        .collect();
    for (k, gear) in GEARS.iter().enumerate() {
        v.push((
            Item::Scalar(clock_index(k), "deg"),
            format!("{gear} clocking"),
        ));
    }
    for (i, n) in [
        (PIN_D[0], "pin D radial"),
        (PIN_D[1], "pin D tangential"),
        (PIN_A[0], "pin A radial"),
        (PIN_A[1], "pin A tangential"),
        (BACKLASH[0], "backlash sun-intermediate"),
        (BACKLASH[1], "backlash intermediate-planet"),
    ] {
        v.push((Item::Scalar(i, "µm"), n.to_string()));
    }
    v.push((Item::Scalar(ARM, "deg"), "arm mounting angle".into()));
    v
}

/// Largest singular value of the 2×2 matrix with columns `a`, `b`.
fn sigma_max(a: [f64; 2], b: [f64; 2]) -> f64 {
    let (p, q, r) = (
        a[0] * a[0] + a[1] * a[1],
        a[0] * b[0] + a[1] * b[1],
        b[0] * b[0] + b[1] * b[1],
    );
    (0.5 * (p + r) + (0.25 * (p - r) * (p - r) + q * q).sqrt())
        .max(0.0)
        .sqrt()
}

fn ranking(lin: &LinearModel, inv: &Inventory) -> Vec<Contribution> {
    let mut out: Vec<Contribution> = items()
        .into_iter()
        .map(|(item, name)| {
            let (tol, sens, unit) = match item {
                Item::Ecc(k) => {
                    let s = lin
                        .jacobian
                        .iter()
                        .map(|c| sigma_max(c[ecc_index(k)], c[ecc_index(k) + 1]))
                        .fold(0.0, f64::max);
                    (inv.three_sigma_eccentricity(k) * UM, s, "µm")
                }
                Item::Scalar(j, unit) => {
                    let s = lin
                        .jacobian
                        .iter()
                        .map(|c| c[j][0].hypot(c[j][1]))
                        .fold(0.0, f64::max);
                    let t = inv.nominal[j].abs() + inv.spread[j].three_sigma();
                    if unit == "deg" {
                        (t.to_degrees(), s * UM / 1f64.to_degrees(), unit)
                    } else {
                        (t * UM, s, unit)
                    }
                }
            };
            Contribution {
                error: name,
                unit: unit.into(),
                three_sigma: tol,
                sensitivity_um_per_unit: sens,
                max_deviation_um: tol * sens,
                share_percent: 0.0,
            }
        })
        .collect();
    let total: f64 = out.iter().map(|c| c.max_deviation_um).sum();
    for c in &mut out {
        c.share_percent = if total > 0.0 {
            100.0 * c.max_deviation_um / total
        } else {
            0.0
        };
    }
    out.sort_by(|a, b| b.max_deviation_um.total_cmp(&a.max_deviation_um));
    out
}

/// `max_φ |base(φ) + Σ_k m_k (cos γ_k S_x + sin γ_k S_y)|` for the free gears.
struct Objective<'a> {
    lin: &'a LinearModel,
    base: Vec<[f64; 2]>,
    free: Vec<usize>,
    magnitude: Vec<f64>,
}

impl Objective<'_> {
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
                    d[0] += m * (c * sx[0] + s * sy[0]);
                    d[1] += m * (c * sx[1] + s * sy[1]);
                }
                d[0].hypot(d[1])
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

#[allow(clippy::too_many_lines)]
fn optimise_assembly(
    model: &ExactModel,
    lin: &LinearModel,
    inv: &Inventory,
    opts: &TransplanterOptions,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Option<AssemblyOptimum>, TransplanterError> {
    let free = inv.free_gears();
    if free.is_empty() {
        return Ok(None);
    }
    let mut x0 = inv.nominal_vector();
    for &k in &free {
        x0[ecc_index(k)] = 0.0;
        x0[ecc_index(k) + 1] = 0.0;
    }
    let obj = Objective {
        lin,
        base: lin.deviations(&x0),
        magnitude: free
            .iter()
            .map(|&k| inv.eccentricity[k].magnitude_mm)
            .collect(),
        free: free.clone(),
    };
    let given: Vec<f64> = free
        .iter()
        .map(|&k| inv.eccentricity[k].direction_rad)
        .collect();
    let as_given = obj.value(&given, free.len());
    // Greedy (C.3): each free gear in order takes the best scan position.
    let mut chosen: Vec<f64> = Vec::new();
    let mut greedy = Vec::new();
    for (a, &k) in free.iter().enumerate() {
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
    let greedy_val = obj.value(&chosen, free.len());
    // Joint: exhaustive over keyed positions when small, else multistart Nelder–Mead.
    let keyed: Vec<usize> = free.iter().map(|&k| inv.eccentricity[k].keyed).collect();
    let combos: usize = keyed.iter().map(|&n| n.max(1)).product();
    let (joint, method) = if keyed.iter().all(|&n| n > 0) && combos <= 100_000 {
        let lists: Vec<Vec<f64>> = free.iter().map(|&k| candidates(inv, k, 1)).collect();
        let best = (0..combos)
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
            .unwrap_or((greedy_val, chosen.clone()));
        (best, "exhaustive")
    } else {
        let d = free.len();
        let mut rng = rng_for(opts.mc.seed, 3, 0);
        let mut inits: Vec<Vec<f64>> = vec![chosen.clone()];
        for _ in 0..opts.starts {
            inits.push((0..d).map(|_| rng.random::<f64>() * TAU).collect());
        }
        let mut best = (greedy_val, chosen.clone());
        let make = || Objective {
            lin,
            base: obj.base.clone(),
            free: obj.free.clone(),
            magnitude: obj.magnitude.clone(),
        };
        for p in nelder_mead_starts(make, &inits, 0.4, 1e-12, 300) {
            // Snap keyed gears to their positions.
            let gs: Vec<f64> = p
                .iter()
                .zip(&free)
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
        (best, "nelder-mead")
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
        .map(|d| d[0].hypot(d[1]) * UM)
        .collect();
    // Random assembly: free directions random, everything else as given.
    let (random, vals) = montecarlo::run(
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

fn envelope(lin: &LinearModel, inv: &Inventory) -> Vec<EnvelopePoint> {
    let (mean, var) = inv.moments();
    let given = inv.nominal_vector();
    let n = lin.phis_rad.len();
    (0..n)
        .map(|i| {
            let col = &lin.jacobian[i];
            let m = lin.deviation_at(i, &mean);
            let (mut cxx, mut cxy, mut cyy) = (0.0, 0.0, 0.0);
            for j in 0..N_COORDS {
                let s = col[j];
                cxx += var[j] * s[0] * s[0];
                cxy += var[j] * s[0] * s[1];
                cyy += var[j] * s[1] * s[1];
            }
            let lmax = 0.5 * (cxx + cyy) + (0.25 * (cxx - cyy).powi(2) + cxy * cxy).sqrt();
            let three = 3.0 * lmax.max(0.0).sqrt();
            let g = lin.deviation_at(i, &given);
            let (a, b) = (
                lin.nominal_tips_mm[(i + n - 1) % n],
                lin.nominal_tips_mm[(i + 1) % n],
            );
            let t = [b[0] - a[0], b[1] - a[1]];
            let tn = t[0].hypot(t[1]).max(f64::MIN_POSITIVE);
            EnvelopePoint {
                carrier_deg: lin.phis_rad[i].to_degrees(),
                nominal_tip_mm: lin.nominal_tips_mm[i],
                mean_deviation_um: [m[0] * UM, m[1] * UM],
                three_sigma_um: three * UM,
                envelope_um: (m[0].hypot(m[1]) + three) * UM,
                nominal_errors_um: g[0].hypot(g[1]) * UM,
                normal: [-t[1] / tn, t[0] / tn],
            }
        })
        .collect()
}

fn feature_deviations(
    model: &ExactModel,
    asm: &Assembly,
    lin: &LinearModel,
    inv: &Inventory,
    opts: &TransplanterOptions,
) -> Result<Option<FeatureDeviations>, TransplanterError> {
    if opts.feature_samples == 0 {
        return Ok(None);
    }
    let phis = &lin.phis_rad;
    let nominal = perturbed_features(model, asm, phis, &[0.0; N_COORDS], &opts.features)?;
    let feats: Result<Vec<Features>, TransplanterError> = (0..opts.feature_samples)
        .into_par_iter()
        .map(|i| {
            let mut rng = rng_for(opts.mc.seed, 2, i);
            let x = inv.draw(&mut rng);
            perturbed_features(model, asm, phis, &x, &opts.features)
        })
        .collect();
    let feats = feats?;
    let stats = |f: &dyn Fn(&Features) -> f64| {
        let v: Vec<f64> = feats.iter().map(|x| f(x) - f(&nominal)).collect();
        montecarlo::summarize(&v, opts.mc.bins).map_err(mc_error("feature"))
    };
    let wrap = |a: f64| (a + 180.0).rem_euclid(360.0) - 180.0;
    Ok(Some(FeatureDeviations {
        samples: feats.len(),
        height_mm: stats(&|f| f.height_mm)?,
        hole_width_mm: stats(&|f| f.hole_width_mm)?,
        static_width_at_depth_mm: stats(&|f| f.static_width_at_depth_mm)?,
        needle_angle_take_deg: stats(&|f| {
            wrap(f.needle_angle_take_deg - nominal.needle_angle_take_deg)
        })?,
        needle_angle_plant_deg: stats(&|f| {
            wrap(f.needle_angle_plant_deg - nominal.needle_angle_plant_deg)
        })?,
        lowest_point_mm: stats(&|f| f.bbox_mm[2])?,
        nominal,
    }))
}

/// Runs the transplanter tolerance analysis of one arm of `asm` with the error inventory `inv`.
/// `progress(done)` counts Monte Carlo samples (the random-assembly MC of the optimiser counts
/// again from 0).
pub fn analyse(
    asm: &Assembly,
    inv: &Inventory,
    opts: &TransplanterOptions,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<TransplanterReport, TransplanterError> {
    if opts.mc.samples < 2 {
        return Err(TransplanterError::BadOption {
            option: "samples",
            message: "at least 2 Monte Carlo samples".into(),
        });
    }
    if opts.linear_tolerance.is_nan() || opts.linear_tolerance <= 0.0 {
        return Err(TransplanterError::BadOption {
            option: "linear tolerance",
            message: "must be positive".into(),
        });
    }
    let model = ExactModel::new(asm, inv.pressure_angle_rad, inv.load_side)?;
    let lin = LinearModel::build(&model, inv.samples_per_turn, opts.fd_steps)?;
    // Validation at 3σ (spec C.6 item 3).
    let errs: Result<Vec<(f64, f64)>, TransplanterError> = (0..opts.validation_samples)
        .into_par_iter()
        .map(|i| {
            let mut rng = rng_for(opts.mc.seed, 1, i);
            linear_error(&model, &lin, &inv.draw_three_sigma(&mut rng))
        })
        .collect();
    let errs = errs?;
    let nv = errs.len().max(1) as f64;
    let max_rel = errs.iter().map(|e| e.0).fold(0.0, f64::max);
    let use_linear = max_rel <= opts.linear_tolerance;
    let validation = Validation {
        samples: errs.len(),
        max_relative_error: max_rel,
        mean_relative_error: errs.iter().map(|e| e.0).sum::<f64>() / nv,
        max_absolute_error_um: errs.iter().map(|e| e.1).fold(0.0, f64::max) * UM,
        model_used: if use_linear { "linear" } else { "exact" }.into(),
    };
    let given = inv.nominal_vector();
    // One metric of the random assemblies: the linear model's value, or the exact one's when
    // the validation failed. Both metrics use the same seed, hence the same samples.
    type Exact = fn(&ExactModel, &LinearModel, &ErrorVector) -> Result<f64, TransplanterError>;
    let distribution = |linear: fn(&LinearModel, &ErrorVector) -> f64,
                        exact: Exact,
                        scale: f64,
                        what: &'static str,
                        progress: &(dyn Fn(u64) + Sync)| {
        montecarlo::run(
            &opts.mc,
            |rng, _| {
                let x = inv.draw(rng);
                if use_linear {
                    linear(&lin, &x) * scale
                } else {
                    exact(&model, &lin, &x).map_or(f64::NAN, |v| v * scale)
                }
            },
            progress,
        )
        .map(|(stats, _)| stats)
        .map_err(mc_error(what))
    };
    let stats = distribution(
        LinearModel::max_deviation_mm,
        exact_max,
        UM,
        "tip deviation (the exact model found no contact: errors too large)",
        progress,
    )?;
    let te = distribution(
        LinearModel::max_planet_angle_error_rad,
        exact_max_angle,
        ARCSEC_PER_RAD,
        "planet angle error (the exact model found no contact)",
        &|_| {},
    )?;
    let env = envelope(&lin, inv);
    let envelope_max_um = env.iter().map(|p| p.envelope_um).fold(0.0, f64::max);
    Ok(TransplanterReport {
        pressure_angle_deg: inv.pressure_angle_rad.to_degrees(),
        load_side: inv.load_side,
        samples_per_turn: inv.samples_per_turn,
        nominal_errors_exact_um: exact_max(&model, &lin, &given)? * UM,
        nominal_errors_linear_um: lin.max_deviation_mm(&given) * UM,
        validation,
        seed: opts.mc.seed,
        max_deviation_um: stats,
        planet_angle_error_arcsec: te,
        envelope: env,
        envelope_max_um,
        features: feature_deviations(&model, asm, &lin, inv, opts)?,
        ranking: ranking(&lin, inv),
        assembly: optimise_assembly(&model, &lin, inv, opts, progress)?,
    })
}
