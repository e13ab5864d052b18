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
use super::report::{Candidate, Synthesis, SynthesisError, SynthesisReport};
use super::spec::{Spec, checked, max_tol_mm};
use super::targets::{AXIS_DISTANCE_L3, DEFAULT_L1_MM, DEFAULT_L3_MM, TargetProblem};
use super::timing::TimingError;
use crate::design::DesignOptions;
use crate::math::Point;
use crate::simulate::FeatureOptions;
use rayon::prelude::*;

mod measure;
mod stage_b;

use measure::{Designed, on_gears};
use stage_b::TimingStage;

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
/// (its `center_mm` is set from the arm: leave it at the origin, or at the spec's
/// `machine.center_mm`; another axis is refused rather than replaced).
///
/// A spec without poses is synthesised from its target bands alone ([`super::targets`]).
///
/// Errors: [`SynthesisError`] — a spec with neither poses nor bands, bad fields, bands that
/// contradict each other, no arm, poses out of travel order for every arm, no design.
pub fn synthesize(spec: &Spec, opts: &DesignOptions) -> Result<Synthesis, SynthesisError> {
    let (poses, tol_rad, sense, fopts) = checked(spec)?;
    opts.validate()
        .map_err(|e| SynthesisError::NoDesign(e.to_string()))?;
    own_axis(spec, opts)?;
    if poses.is_empty() {
        return from_targets(spec, opts, sense, fopts);
    }
    let dopts = DyadOptions {
        center_mm: spec.machine.center_mm,
        ..DyadOptions::default()
    };
    let (kind, dyads) = match solve_dyads_weighted(&poses, &pose_scales(spec), &dopts)? {
        DyadSolutions::Finite(v) => ("finite", v),
        DyadSolutions::Family(v) => ("family", v),
    };
    let pick = candidate_arms(kind, &dyads, &poses, spec);
    if pick.is_empty() {
        return Err(no_arm(kind, &dyads, &poses, spec, &dopts));
    }
    let stage = TimingStage {
        poses: &poses,
        tol_rad: &tol_rad,
        sense,
        fopts: &fopts,
        opts,
        limits: opts.limits_in_force(),
        bands: spec.targets.bands(),
    };
    let timings = stage.time_candidates(pick, kind == "family");
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
    let (tried, chosen) = chosen_or_error(results)?;
    Ok(finish(kind, &dyads, tried, chosen, spec))
}

/// The weight of each pose in the arm's least squares: an exact pose weighs as a position
/// tolerance of [`EXACT_POSE_MM`], an approximate one as its own, mm.
fn pose_scales(spec: &Spec) -> Vec<f64> {
    spec.poses
        .iter()
        .map(|p| {
            if p.approximate() {
                p.position_tolerance_mm()
            } else {
                EXACT_POSE_MM
            }
        })
        .collect()
}

/// The candidates tried, each with its design when it got gears.
type Tried = Vec<(Candidate, Option<Designed>)>;

/// The candidates tried and the index of the one chosen ([`choose`]); when none has gears:
/// the timing error when every arm was refused by Stage B's necessary conditions (the spec's
/// error, by name), else every refusal.
fn chosen_or_error(
    results: Vec<(Candidate, Option<Designed>, Option<TimingError>)>,
) -> Result<(Tried, usize), SynthesisError> {
    let timing_error = results
        .iter()
        .all(|r| r.2.is_some())
        .then(|| results.iter().find_map(|r| r.2.clone()))
        .flatten();
    let tried: Tried = results.into_iter().map(|(c, d, _)| (c, d)).collect();
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
    Ok((tried, chosen))
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
            .flat_map(|p| poses.iter().map(move |q| p.tip_mm.distance(q.tip_mm)))
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
        let scale = 1e-6 + poses.iter().map(|p| p.tip_mm.hypot()).fold(0.0, f64::max) * 1e-6;
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

/// The design options' carrier axis is the synthesis's to set: one that is neither the origin
/// (the default) nor the spec's `machine.center_mm` is refused, not silently replaced.
fn own_axis(spec: &Spec, opts: &DesignOptions) -> Result<(), SynthesisError> {
    let c = opts.center_mm;
    if c == Point::new(0.0, 0.0) || spec.machine.center_mm == Some(c) {
        return Ok(());
    }
    Err(SynthesisError::BadField {
        field: "design option center_mm".into(),
        value: format!("[{}, {}]", c.x, c.y),
        expected: "the synthesis sets the carrier axis (the spec's machine.center_mm, or the \
                   one it solves for): give the axis as machine.center_mm and leave this option \
                   at its default"
            .into(),
    })
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
    let center_mm = spec.machine.center_mm.unwrap_or(Point::new(0.0, 0.0));
    let direction = sense.unwrap_or(1);
    let problem = TargetProblem {
        bands: spec.targets.bands(),
        features: fopts,
        limits: opts.limits_in_force(),
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
