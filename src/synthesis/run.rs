//! The whole synthesis: poses → dyads → timing → the design chain's gears, each candidate arm
//! tried and the one that passes the poses best (then meets the target bands) kept.
//!
//! Each candidate dyad gets its timing ([`super::timing`]); the train's traced path (720 carrier
//! angles) goes through [`crate::design::design`], which makes its gears within the gear limits
//! and checks them; the poses are then measured on the gears themselves (the rebuilt train of the
//! design): each pose's distance from the traced path, and the needle-direction error at the
//! closest instant. The agronomic indices of the chosen design are those `ncgear simulate`
//! reports (one implementation), compared with the target bands: reported with their margins, and
//! used to choose between candidates that pass the poses (within [`POSE_PASSED`]; then the most
//! compact arm, smallest `l1 + l3`). Candidates are evaluated side by side.
//!
//! A spec of bands without poses goes to the targets-only search ([`super::targets`]); its best
//! trains go through the same design chain and are measured the same way.

use super::dyad::{Dyad, DyadOptions, DyadSolutions, Pose, solve_dyads_weighted};
use super::report::{
    Candidate, PoseResult, Synthesis, SynthesisError, SynthesisReport, TargetResult,
};
use super::spec::{Spec, checked, max_tol_mm};
use super::targets::{
    AXIS_DISTANCE_L3, DEFAULT_L1_MM, DEFAULT_L3_MM, SEARCH_SAMPLES, TargetProblem, band_shortfalls,
    index_value, turn_of,
};
use super::timing::{
    Timing, TimingError, TimingGoals, carrier_angles, check_planet_turns, fit_timing,
};
use crate::design::trajectory::Trajectory;
use crate::design::{Design, DesignOptions, design};
use crate::geometry::mechanism::Mechanism;
use crate::simulate::{FeatureOptions, Features, Simulation, features, features_of_turn};
use rayon::prelude::*;
use std::f64::consts::{PI, TAU};

/// Candidates taken from a one-parameter family (three poses), evenly over its members of
/// [`FAMILY_L3_SPREADS`].
pub const FAMILY_CANDIDATES: usize = 8;

/// Needle lengths of the family members tried, in units of the poses' spread (the largest
/// distance between two pose tips).
pub const FAMILY_L3_SPREADS: [f64; 2] = [0.25, 2.5];

/// Pose errors (mm, degrees) within which a candidate counts as passing every pose when one is
/// chosen: the target bands and the arm's size then decide.
pub const POSE_PASSED: (f64, f64) = (0.01, 0.01);

/// Family members (of the [`FAMILY_CANDIDATES`] timed) handed to the design chain.
pub const FAMILY_DESIGNED: usize = 4;

/// Position scale of an exact pose in the arm's least squares, mm (an approximate pose's is its
/// `tol_mm`).
pub const EXACT_POSE_MM: f64 = 1e-3;

/// Finite solutions tried, best residual first.
pub const FINITE_CANDIDATES: usize = 4;

/// Fourier order of the timing's sun ratio.
pub const TIMING_ORDER: usize = 6;

/// Samples of the train's traced path handed to the design chain.
const TRACE_POINTS: usize = 720;

/// Synthesises the mechanism and its gears for `spec`, the design chain run with `opts`
/// (its `center_mm` is set from the arm).
///
/// A spec without poses is synthesised from its target bands alone ([`super::targets`]).
///
/// Errors: [`SynthesisError`] — a spec with neither poses nor bands, bad fields, bands that
/// contradict each other, no arm, poses out of travel order for every arm, no design.
pub fn synthesize(spec: &Spec, opts: &DesignOptions) -> Result<Synthesis, SynthesisError> {
    let (poses, tol_rad, sense, fopts) = checked(spec)?;
    opts.validate()
        .map_err(|e| SynthesisError::NoDesign(e.to_string()))?;
    if poses.is_empty() {
        return from_targets(spec, opts, sense, fopts);
    }
    let limits = opts.limits();
    let dopts = DyadOptions {
        center_mm: spec.machine.center_mm,
        ..DyadOptions::default()
    };
    // An exact pose weighs as a position tolerance of 1 µm, an approximate one as its own.
    let scales: Vec<f64> = spec
        .poses
        .iter()
        .map(|p| {
            if p.approximate() {
                p.position_tolerance_mm()
            } else {
                EXACT_POSE_MM
            }
        })
        .collect();
    let (kind, dyads) = match solve_dyads_weighted(&poses, &scales, &dopts)? {
        DyadSolutions::Finite(v) => ("finite", v),
        DyadSolutions::Family(v) => ("family", v),
    };
    let pick = candidate_arms(kind, &dyads, &poses, spec);
    if pick.is_empty() {
        return Err(no_arm(kind, &dyads, &poses, spec, &dopts));
    }
    // Each candidate's timing on its own (side by side); a family's members first without the
    // gear-limit and band rows (cheaper), the ones kept then again with them when they break a
    // limit or there are bands.
    let bands = spec.targets.bands();
    let timed = |dyad: Dyad, full: bool| -> Result<Timing, TimingError> {
        let (direction, angles) = carrier_angles(&poses, &dyad, sense)?;
        check_planet_turns(&poses, direction, &angles, opts.refine_options.ratio_bounds)?;
        // The bands' rows: the indices of the train's two arms at SEARCH_SAMPLES instants.
        let o = dyad.center_mm;
        let band_rows = |m: &Mechanism| -> Vec<f64> {
            features_of_turn(
                &turn_of(m, o, direction, SEARCH_SAMPLES),
                o,
                direction,
                &fopts,
            )
            // Indices that cannot be evaluated (no planting level): each band 1000 units out.
            .map_or(vec![1e3; bands.len()], |f| band_shortfalls(&bands, &f))
        };
        let goals = TimingGoals {
            limits: full.then_some(&limits),
            bands: (full && !bands.is_empty()).then_some(&band_rows),
        };
        Ok(fit_timing(
            &poses,
            &dyad,
            direction,
            &angles,
            TIMING_ORDER,
            &tol_rad,
            &goals,
        ))
    };
    let family = kind == "family";
    let mut timings: Vec<(Dyad, Result<Timing, TimingError>)> = pick
        .into_par_iter()
        .map(|d| (d, timed(d, !family)))
        .collect();
    // The family's members that go on to the design chain: those whose timing passes the poses
    // best (to 1e-6 rad), then keeps within the gear limits, then the most compact arm.
    if family {
        rank_family(&mut timings, &limits);
        timings.truncate(FAMILY_DESIGNED);
        timings = timings
            .into_par_iter()
            .map(|(d, t)| match t {
                Ok(t)
                    if !limits.contains(&t.mechanism.ratio, t.mechanism.a_mm)
                        || !bands.is_empty() =>
                {
                    (d, timed(d, true))
                }
                t => (d, t),
            })
            .collect();
    }
    // Each candidate's gears on their own (side by side), the poses measured on them.
    let results: Vec<(Candidate, Option<Designed>, Option<TimingError>)> = timings
        .into_par_iter()
        .map(|(dyad, t)| match t {
            Err(e) => (Candidate::refused(dyad, e.to_string()), None, Some(e)),
            Ok(t) => {
                let (c, d) = on_gears(&t.mechanism, dyad, t.direction, &poses, spec, &fopts, opts);
                (c, d, None)
            }
        })
        .collect();
    // Every arm refused by Stage B's necessary conditions: the spec's error, by name.
    let timing_error = results
        .iter()
        .all(|r| r.2.is_some())
        .then(|| results.iter().find_map(|r| r.2.clone()))
        .flatten();
    let tried: Vec<(Candidate, Option<Designed>)> =
        results.into_iter().map(|(c, d, _)| (c, d)).collect();
    let Some(chosen) = choose(&tried) else {
        if let Some(e) = timing_error {
            return Err(e.into());
        }
        let reasons: Vec<String> = tried
            .iter()
            .filter_map(|(c, _)| c.refused.clone())
            .collect();
        return Err(SynthesisError::NoDesign(reasons.join("; ")));
    };
    Ok(finish(kind, &dyads, tried, chosen, spec))
}

/// The arms that go on to Stage B: a family's members of a planting arm's proportions, or the
/// finite arms that reach every pose (within 1e-6 of the poses' size, or the largest approximate
/// tolerance), at most [`FINITE_CANDIDATES`].
fn candidate_arms(kind: &str, dyads: &[Dyad], poses: &[Pose], spec: &Spec) -> Vec<Dyad> {
    if kind == "family" {
        // Members of a planting arm's proportions: needle between a quarter of the poses' spread
        // and two and a half times it (else the whole family), evenly.
        let spread = poses
            .iter()
            .flat_map(|p| {
                poses
                    .iter()
                    .map(move |q| (p.tip_mm[0] - q.tip_mm[0]).hypot(p.tip_mm[1] - q.tip_mm[1]))
            })
            .fold(0.0, f64::max);
        let plausible: Vec<Dyad> = dyads
            .iter()
            .filter(|d| {
                d.l3_mm >= FAMILY_L3_SPREADS[0] * spread
                    && d.l3_mm <= FAMILY_L3_SPREADS[1] * spread
                    && d.l1_mm <= (1.0 - AXIS_DISTANCE_L3) * d.l3_mm
            })
            .copied()
            .collect();
        let members: &[Dyad] = if plausible.is_empty() {
            dyads
        } else {
            &plausible
        };
        let n = members.len();
        (0..FAMILY_CANDIDATES.min(n))
            .map(|k| members[(2 * k + 1) * n / (2 * FAMILY_CANDIDATES.min(n))])
            .collect()
    } else {
        let scale = 1e-6
            + poses
                .iter()
                .map(|p| p.tip_mm[0].hypot(p.tip_mm[1]))
                .fold(0.0, f64::max)
                * 1e-6;
        dyads
            .iter()
            .filter(|d| d.max_residual_mm <= scale.max(max_tol_mm(spec)))
            .take(FINITE_CANDIDATES)
            .copied()
            .collect()
    }
}

/// Why no arm reaches the poses: the best finite arm's miss, or no arm within the search.
fn no_arm(
    kind: &str,
    dyads: &[Dyad],
    poses: &[Pose],
    spec: &Spec,
    dopts: &DyadOptions,
) -> SynthesisError {
    let best = dyads
        .iter()
        .map(|d| d.max_residual_mm)
        .fold(f64::INFINITY, f64::min);
    if kind == "finite" && best.is_finite() {
        SynthesisError::NoExactArm {
            poses: poses.len(),
            exact: spec.poses.iter().filter(|p| !p.approximate()).count(),
            residual_mm: best,
        }
    } else {
        SynthesisError::NoArm {
            max_l3_mm: dopts.max_l3_mm,
        }
    }
}

/// A family's timed members in the order they go on to the design chain: those whose timing
/// passes the poses best (to 1e-6 rad), then keeps within the gear limits, then the most compact
/// arm.
fn rank_family(
    timings: &mut [(Dyad, Result<Timing, TimingError>)],
    limits: &crate::geometry::limits::GearLimits,
) {
    let key = |(dyad, t): &(Dyad, Result<Timing, TimingError>)| match t {
        Ok(t) => (
            (t.residuals_rad.iter().map(|r| r.abs()).fold(0.0, f64::max) * 1e6).round(),
            !limits.contains(&t.mechanism.ratio, t.mechanism.a_mm),
            dyad.l1_mm + dyad.l3_mm,
        ),
        Err(_) => (f64::INFINITY, true, f64::INFINITY),
    };
    timings.sort_by(|a, b| {
        let (ka, kb) = (key(a), key(b));
        ka.0.total_cmp(&kb.0)
            .then(ka.1.cmp(&kb.1))
            .then(ka.2.total_cmp(&kb.2))
    });
}

/// The designed candidate kept: passes the poses (within [`POSE_PASSED`], else the smaller error
/// to 1 µm), then misses the fewest bands, then the most compact arm (smallest l1 + l3: the
/// smaller gearbox and arm).
fn choose(tried: &[(Candidate, Option<Designed>)]) -> Option<usize> {
    tried
        .iter()
        .enumerate()
        .filter_map(|(k, (c, r))| r.as_ref().map(|_| (k, c)))
        .min_by(|a, b| {
            let key = |c: &Candidate| {
                let (mm, deg) = (
                    c.max_pose_error_mm.unwrap_or(f64::INFINITY),
                    c.max_pose_error_deg.unwrap_or(f64::INFINITY),
                );
                (
                    if mm <= POSE_PASSED.0 && deg <= POSE_PASSED.1 {
                        0.0
                    } else {
                        (mm * 1e3).round().max(1.0)
                    },
                    c.targets_missed,
                    c.dyad.l1_mm + c.dyad.l3_mm,
                )
            };
            let (ka, kb) = (key(a.1), key(b.1));
            ka.0.total_cmp(&kb.0)
                .then(ka.1.cmp(&kb.1))
                .then(ka.2.total_cmp(&kb.2))
        })
        .map(|(k, _)| k)
}

/// Candidates of the targets-only search handed to the design chain.
pub const TARGET_CANDIDATES: usize = 3;

/// Targets only ([`super::targets`]): the trains found for the bands, each through the design
/// chain; kept: the one whose gears miss the fewest bands, then by the least total shortfall,
/// then the search's order.
fn from_targets(
    spec: &Spec,
    opts: &DesignOptions,
    sense: Option<i8>,
    fopts: FeatureOptions,
) -> Result<Synthesis, SynthesisError> {
    let center_mm = spec.machine.center_mm.unwrap_or([0.0, 0.0]);
    let direction = sense.unwrap_or(1);
    let problem = TargetProblem {
        bands: spec.targets.bands(),
        features: fopts,
        limits: opts.limits(),
        center_mm,
        direction,
        l1_mm: spec.machine.l1_mm.unwrap_or(DEFAULT_L1_MM),
        l3_mm: spec.machine.l3_mm.unwrap_or(DEFAULT_L3_MM),
    };
    let found = problem.search();
    let tried: Vec<(Candidate, Option<Designed>)> = found
        .par_iter()
        .take(TARGET_CANDIDATES)
        .map(|f| {
            let dyad = Dyad {
                center_mm,
                l1_mm: f.mechanism.l1_mm(),
                l3_mm: f.mechanism.l3_mm,
                max_residual_mm: 0.0,
            };
            on_gears(&f.mechanism, dyad, direction, &[], spec, &fopts, opts)
        })
        .collect();
    let shortfall = |d: &Designed| {
        d.3.as_ref().map_or(f64::INFINITY, |t| {
            t.iter().map(|t| (-t.margin).max(0.0)).sum::<f64>()
        })
    };
    let chosen = tried
        .iter()
        .enumerate()
        .filter_map(|(k, (c, d))| d.as_ref().map(|d| (k, c.targets_missed, shortfall(d))))
        .min_by(|a, b| a.1.cmp(&b.1).then(a.2.total_cmp(&b.2)).then(a.0.cmp(&b.0)))
        .map(|(k, ..)| k);
    let Some(chosen) = chosen else {
        let reasons: Vec<String> = tried
            .iter()
            .filter_map(|(c, _)| c.refused.clone())
            .collect();
        return Err(SynthesisError::NoDesign(if reasons.is_empty() {
            "the search found no train with these bands".into()
        } else {
            reasons.join("; ")
        }));
    };
    let dyads: Vec<Dyad> = tried.iter().map(|(c, _)| c.dyad).collect();
    let arm = dyads[chosen];
    let mut out = finish("targets", &dyads, tried, chosen, spec);
    for (name, key, v, r) in [
        ("l1", "machine.l1_mm", arm.l1_mm, problem.l1_mm),
        ("l3", "machine.l3_mm", arm.l3_mm, problem.l3_mm),
    ] {
        let edge = if v >= r[1] - 1e-3 * r[1] {
            "largest"
        } else if v <= r[0] + 1e-3 * r[0] {
            "smallest"
        } else {
            continue;
        };
        out.report.binding.push(format!(
            "search box: {name} = {v:.3} mm is the {edge} in {key} = [{}, {}]",
            r[0], r[1]
        ));
    }
    Ok(out)
}

/// The train `m` (solved frame) on arm `dyad` with carrier sense `direction`: its traced path
/// ([`TRACE_POINTS`] carrier angles) through the design chain, which makes its gears within the
/// gear limits; the poses and the target bands measured on those gears.
fn on_gears(
    m: &Mechanism,
    dyad: Dyad,
    direction: i8,
    poses: &[Pose],
    spec: &Spec,
    fopts: &FeatureOptions,
    opts: &DesignOptions,
) -> (Candidate, Option<Designed>) {
    let s = f64::from(direction);
    let o = dyad.center_mm;
    let points: Vec<[f64; 2]> = (0..TRACE_POINTS)
        .map(|j| {
            let b = m.tip(TAU * j as f64 / TRACE_POINTS as f64);
            [o[0] + b[0], o[1] + s * b[1]]
        })
        .collect();
    let mut o_opts = opts.clone();
    o_opts.center_mm = o;
    let d = match Trajectory::from_points(points)
        .map_err(|e| e.to_string())
        .and_then(|t| design(&t, &o_opts).map_err(|e| e.to_string()))
    {
        Ok(d) => d,
        Err(e) => return (Candidate::refused(dyad, e), None),
    };
    let sim = Simulation::new(d.assembly.clone());
    let measured: Vec<PoseResult> = poses.iter().map(|p| on_design(&sim, p)).collect();
    // Bands that cannot be evaluated (no planting level on this path) are said so, not dropped.
    let targets = features(&sim, fopts)
        .map(|f| target_results(spec, &f))
        .map_err(|e| e.to_string());
    let cand = Candidate {
        dyad,
        max_pose_error_mm: Some(measured.iter().map(|p| p.error_mm).fold(0.0, f64::max)),
        max_pose_error_deg: Some(
            measured
                .iter()
                .map(|p| p.error_deg.abs())
                .fold(0.0, f64::max),
        ),
        targets_missed: targets.as_ref().map_or(spec.targets.bands().len(), |t| {
            t.iter().filter(|t| t.margin < 0.0).count()
        }),
        refused: None,
    };
    (cand, Some((d, direction, measured, targets)))
}

/// The report of the chosen candidate among those `tried`.
fn finish(
    kind: &str,
    dyads: &[Dyad],
    mut tried: Vec<(Candidate, Option<Designed>)>,
    chosen: usize,
    spec: &Spec,
) -> Synthesis {
    let candidates: Vec<Candidate> = tried.iter().map(|(c, _)| c.clone()).collect();
    let (d, direction, measured, targets) =
        tried.swap_remove(chosen).1.expect("a designed candidate");
    let mut binding = Vec::new();
    let targets = targets.unwrap_or_else(|e| {
        if !spec.targets.bands().is_empty() {
            binding.push(format!("target bands not evaluated: {e}"));
        }
        Vec::new()
    });
    binding.extend(targets.iter().filter(|t| t.margin < 0.0).map(|t| {
        format!(
            "{} {:.3} outside [{}, {}] by {:.3}",
            t.index, t.value, t.band[0], t.band[1], -t.margin
        )
    }));
    binding.extend(
        d.report
            .limits
            .binding
            .iter()
            .map(|b| format!("gear limit: {b}")),
    );
    let thin = (dyads.len() / 200).max(1);
    Synthesis {
        report: SynthesisReport {
            dyad_kind: kind.into(),
            dyads: dyads
                .iter()
                .step_by(if kind == "family" { thin } else { 1 })
                .copied()
                .collect(),
            candidates,
            chosen,
            carrier: if direction > 0 { "ccw" } else { "cw" }.into(),
            poses: measured,
            targets,
            binding,
        },
        design: d,
    }
}

/// A candidate's design: the design, its carrier sense, the poses and bands measured on it.
type Designed = (
    Design,
    i8,
    Vec<PoseResult>,
    Result<Vec<TargetResult>, String>,
);

/// `p` on the designed train: the closest tip over a turn (3600 instants, then golden-section
/// refinement) and the needle-direction error there.
fn on_design(sim: &Simulation, p: &Pose) -> PoseResult {
    let at = |phi: f64| {
        let a = sim.pose(phi).arm1;
        let d = (a.tip_mm[0] - p.tip_mm[0]).hypot(a.tip_mm[1] - p.tip_mm[1]);
        (d, a)
    };
    let n = 3600;
    let k = (0..n)
        .min_by(|&i, &j| {
            at(sim.angle_at(i as f64 / n as f64))
                .0
                .total_cmp(&at(sim.angle_at(j as f64 / n as f64)).0)
        })
        .unwrap_or(0);
    let (mut lo, mut hi) = (
        sim.angle_at((k as f64 - 1.0) / n as f64),
        sim.angle_at((k as f64 + 1.0) / n as f64),
    );
    let g = 0.5 * (5f64.sqrt() - 1.0);
    for _ in 0..60 {
        let (m1, m2) = (hi - g * (hi - lo), lo + g * (hi - lo));
        if at(m1).0 < at(m2).0 {
            hi = m2;
        } else {
            lo = m1;
        }
    }
    let phi = 0.5 * (lo + hi);
    let (d, a) = at(phi);
    let dir = (a.tip_mm[1] - a.planet_center_mm[1]).atan2(a.tip_mm[0] - a.planet_center_mm[0]);
    PoseResult {
        tip_mm: p.tip_mm,
        needle_deg: p.needle_rad.to_degrees(),
        carrier_deg: phi.to_degrees().rem_euclid(360.0),
        error_mm: d,
        error_deg: ((dir - p.needle_rad + PI).rem_euclid(TAU) - PI).to_degrees(),
    }
}

/// Each band of `spec` against the design's features.
fn target_results(spec: &Spec, f: &Features) -> Vec<TargetResult> {
    spec.targets
        .bands()
        .into_iter()
        .map(|(name, band)| {
            let value = index_value(name, f);
            TargetResult {
                index: name.into(),
                band,
                value,
                margin: (value - band[0]).min(band[1] - value),
            }
        })
        .collect()
}
