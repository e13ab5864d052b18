//! The whole synthesis: poses → dyads → timing → the design chain's gears, each candidate arm
//! tried and the one that passes the poses best (then meets the target bands) kept.
//!
//! Each candidate dyad gets its timing ([`super::timing`]); the train's traced path (720 carrier
//! angles) goes through [`crate::design::design`], which makes its gears within the gear limits
//! and checks them; the poses are then measured on the gears themselves (the rebuilt train of the
//! design): each pose's distance from the traced path, and the needle-direction error at the
//! closest instant. The agronomic indices of the chosen design are those `ncgear simulate`
//! reports (one implementation), compared with the target bands: reported with their margins, and
//! used to choose between candidates that pass the poses equally well (then the most compact arm,
//! smallest `l1 + l3`); they are not yet optimised for. Candidates are evaluated side by side.

use super::dyad::{Dyad, DyadError, DyadOptions, DyadSolutions, Pose, solve_dyads};
use super::spec::Spec;
use super::timing::{POSE_TOL_RAD, TimingError, carrier_angles, fit_timing};
use crate::design::trajectory::Trajectory;
use crate::design::{Design, DesignOptions, design};
use crate::simulate::{FeatureOptions, Features, Simulation, features};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::f64::consts::{PI, TAU};

/// Candidates taken from a one-parameter family (three poses), evenly over its members of
/// [`FAMILY_L3_SPREADS`].
pub const FAMILY_CANDIDATES: usize = 16;

/// Needle lengths of the family members tried, in units of the poses' spread (the largest
/// distance between two pose tips).
pub const FAMILY_L3_SPREADS: [f64; 2] = [0.25, 2.5];

/// Finite solutions tried, best residual first.
pub const FINITE_CANDIDATES: usize = 4;

/// Fourier order of the timing's sun ratio.
pub const TIMING_ORDER: usize = 6;

/// Samples of the train's traced path handed to the design chain.
const TRACE_POINTS: usize = 720;

/// The synthesis report (`synthesis.json`).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct SynthesisReport {
    /// `"finite"`: finitely many arms; `"family"`: three poses, one arm per needle length.
    pub dyad_kind: String,
    /// The arms found (a family thinned to at most 200), best first for finite ones.
    pub dyads: Vec<Dyad>,
    /// Every candidate tried, in order.
    pub candidates: Vec<Candidate>,
    /// Index of the chosen candidate.
    pub chosen: usize,
    /// `"ccw"` or `"cw"`.
    pub carrier: String,
    /// Each pose, measured on the chosen design's gears.
    pub poses: Vec<PoseResult>,
    /// Each target band with the chosen design's value and margin.
    pub targets: Vec<TargetResult>,
    /// What binds: target bands missed, gear limits the design sits on.
    pub binding: Vec<String>,
}

/// One candidate arm and how its design passes the poses.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Candidate {
    /// The arm.
    pub dyad: Dyad,
    /// Largest pose distance from the designed gears' traced path, mm (`None`: refused).
    pub max_pose_error_mm: Option<f64>,
    /// Largest needle-direction error at the poses, degrees.
    pub max_pose_error_deg: Option<f64>,
    /// Target bands missed.
    pub targets_missed: usize,
    /// Why this candidate gave no design.
    pub refused: Option<String>,
}

/// One pose on the chosen design.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct PoseResult {
    /// Pose tip, mm.
    pub tip_mm: [f64; 2],
    /// Pose needle direction, degrees.
    pub needle_deg: f64,
    /// Carrier angle at which the design's tip is closest, degrees (world, file frame).
    pub carrier_deg: f64,
    /// Distance of the pose from the traced path, mm.
    pub error_mm: f64,
    /// Needle-direction error there, degrees.
    pub error_deg: f64,
}

/// One target band.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct TargetResult {
    /// Index name (the spec's key).
    pub index: String,
    /// Band `[min, max]`.
    pub band: [f64; 2],
    /// The design's value.
    pub value: f64,
    /// Distance inside the band (negative: outside by that much).
    pub margin: f64,
}

/// A synthesis: its report and the chosen design.
#[derive(Debug)]
pub struct Synthesis {
    /// `synthesis.json`.
    pub report: SynthesisReport,
    /// The chosen design (its `design.json` and files as `ncgear design` writes them).
    pub design: Design,
}

/// Why a spec cannot be synthesised.
#[derive(Debug, Clone, thiserror::Error)]
#[non_exhaustive]
pub enum SynthesisError {
    /// A spec field out of range.
    #[error("{field} = {value}: {expected}")]
    BadField {
        /// The spec key.
        field: String,
        /// Its value.
        value: String,
        /// What is admissible.
        expected: String,
    },
    /// Stage A failed.
    #[error(transparent)]
    Dyad(#[from] DyadError),
    /// Stage B's necessary conditions failed for every arm.
    #[error(transparent)]
    Timing(#[from] TimingError),
    /// No arm reaches the poses.
    #[error(
        "no arm O–A–B reaches these poses within {max_l3_mm} mm of needle: check the poses' directions (planet axis → tip, degrees CCW from +x)"
    )]
    NoArm {
        /// Longest needle searched, mm.
        max_l3_mm: f64,
    },
    /// Every candidate was refused by the design chain.
    #[error("no candidate arm gave a design: {0}")]
    NoDesign(String),
}

/// Synthesises the mechanism and its gears for `spec`, the design chain run with `opts`
/// (its `center_mm` is set from the arm).
///
/// Errors: [`SynthesisError`] — a spec without poses (targets alone are not synthesised yet),
/// bad fields, no arm, poses out of travel order for every arm, no design.
pub fn synthesize(spec: &Spec, opts: &DesignOptions) -> Result<Synthesis, SynthesisError> {
    let (poses, tol_rad, sense, fopts) = checked(spec)?;
    let dopts = DyadOptions {
        center_mm: spec.machine.center_mm,
        ..DyadOptions::default()
    };
    let (kind, dyads) = match solve_dyads(&poses, &dopts)? {
        DyadSolutions::Finite(v) => ("finite", v),
        DyadSolutions::Family(v) => ("family", v),
    };
    let pick: Vec<Dyad> = if kind == "family" {
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
                d.l3_mm >= FAMILY_L3_SPREADS[0] * spread && d.l3_mm <= FAMILY_L3_SPREADS[1] * spread
            })
            .copied()
            .collect();
        let members = if plausible.is_empty() {
            &dyads
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
    };
    if pick.is_empty() {
        return Err(SynthesisError::NoArm {
            max_l3_mm: dopts.max_l3_mm,
        });
    }
    // Each candidate on its own (side by side): its timing, its gears, the poses on them.
    let evaluate = |dyad: Dyad| -> (Candidate, Option<Designed>, Option<TimingError>) {
        let refused = |why: String| Candidate {
            dyad,
            max_pose_error_mm: None,
            max_pose_error_deg: None,
            targets_missed: 0,
            refused: Some(why),
        };
        let (direction, angles) = match carrier_angles(&poses, &dyad, sense) {
            Ok(v) => v,
            Err(e) => return (refused(e.to_string()), None, Some(e)),
        };
        let timing = fit_timing(&poses, &dyad, direction, &angles, TIMING_ORDER, &tol_rad);
        let s = f64::from(direction);
        let o = dyad.center_mm;
        let points: Vec<[f64; 2]> = (0..TRACE_POINTS)
            .map(|j| {
                let b = timing.mechanism.tip(TAU * j as f64 / TRACE_POINTS as f64);
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
            Err(e) => return (refused(e), None, None),
        };
        let sim = Simulation::new(d.assembly.clone());
        let measured: Vec<PoseResult> = poses.iter().map(|p| on_design(&sim, p)).collect();
        // Bands that cannot be evaluated (no planting level on this path) are said so, not dropped.
        let targets = features(&sim, &fopts)
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
        (cand, Some((d, direction, measured, targets)), None)
    };
    let results: Vec<(Candidate, Option<Designed>, Option<TimingError>)> =
        pick.into_par_iter().map(evaluate).collect();
    let first_timing_error = results.iter().find_map(|r| r.2.clone());
    let mut tried: Vec<(Candidate, Option<Designed>)> =
        results.into_iter().map(|(c, d, _)| (c, d)).collect();
    // Passes the poses best (to 1 µm), then misses the fewest bands, then the most compact arm
    // (smallest l1 + l3: the smaller gearbox and planting arm).
    let chosen = tried
        .iter()
        .enumerate()
        .filter_map(|(k, (c, r))| r.as_ref().map(|_| (k, c)))
        .min_by(|a, b| {
            let key = |c: &Candidate| {
                (
                    (c.max_pose_error_mm.unwrap_or(f64::INFINITY) * 1e3).round(),
                    c.targets_missed,
                    c.dyad.l1_mm + c.dyad.l3_mm,
                )
            };
            let (ka, kb) = (key(a.1), key(b.1));
            ka.0.total_cmp(&kb.0)
                .then(ka.1.cmp(&kb.1))
                .then(ka.2.total_cmp(&kb.2))
        })
        .map(|(k, _)| k);
    let Some(chosen) = chosen else {
        if let Some(e) = first_timing_error.filter(|_| {
            tried.iter().all(|(c, _)| {
                c.refused
                    .as_deref()
                    .is_some_and(|r| r.contains("travel order") || r.contains("carrier was set"))
            })
        }) {
            return Err(e.into());
        }
        let reasons: Vec<String> = tried
            .iter()
            .filter_map(|(c, _)| c.refused.clone())
            .collect();
        return Err(SynthesisError::NoDesign(reasons.join("; ")));
    };
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
    Ok(Synthesis {
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
    })
}

/// A candidate's design: the design, its carrier sense, the poses and bands measured on it.
type Designed = (
    Design,
    i8,
    Vec<PoseResult>,
    Result<Vec<TargetResult>, String>,
);

/// The poses, their direction tolerances (rad), the sense asked for and the feature options.
type Checked = (Vec<Pose>, Vec<f64>, Option<i8>, FeatureOptions);

/// The spec's fields checked against their ranges, naming the first out of range.
fn checked(spec: &Spec) -> Result<Checked, SynthesisError> {
    let bad = |field: &str, value: String, expected: &str| SynthesisError::BadField {
        field: field.into(),
        value,
        expected: expected.into(),
    };
    if spec.poses.is_empty() {
        return Err(bad(
            "pose",
            "none".into(),
            "at least three [[pose]] tables (two with machine.center_mm): synthesis from target bands alone is not available yet",
        ));
    }
    let mut tol = Vec::new();
    for (k, p) in spec.poses.iter().enumerate() {
        match p.kind.as_deref() {
            None | Some("exact") => tol.push(POSE_TOL_RAD),
            Some("approximate") => {
                let t = p.tol_deg.unwrap_or(0.5);
                if !(t > 0.0 && t.is_finite()) {
                    return Err(bad(
                        &format!("pose[{k}].tol_deg"),
                        t.to_string(),
                        "a positive angle in degrees",
                    ));
                }
                tol.push(t.to_radians());
            }
            Some(v) => {
                return Err(bad(
                    &format!("pose[{k}].kind"),
                    format!("\"{v}\""),
                    "\"exact\" or \"approximate\"",
                ));
            }
        }
    }
    let sense = match spec.machine.carrier.as_deref() {
        None => None,
        Some("ccw") => Some(1),
        Some("cw") => Some(-1),
        Some(v) => {
            return Err(bad(
                "machine.carrier",
                format!("\"{v}\""),
                "\"ccw\" or \"cw\"",
            ));
        }
    };
    let mut f = FeatureOptions::default();
    if let Some(r) = spec.machine.rpm {
        if !(r > 0.0 && r.is_finite()) {
            return Err(bad(
                "machine.rpm",
                r.to_string(),
                "a positive speed in r/min",
            ));
        }
        f.rpm = r;
    }
    match (spec.machine.spacing_mm, spec.machine.forward_speed_mm_s) {
        (Some(_), Some(_)) => {
            return Err(bad(
                "machine.spacing_mm",
                "with forward_speed_mm_s".into(),
                "one of spacing_mm and forward_speed_mm_s",
            ));
        }
        (Some(s), None) if s > 0.0 && s.is_finite() => {
            f.forward_mm_s = FeatureOptions::forward_for_spacing(s, f.rpm)
        }
        (Some(s), None) => {
            return Err(bad(
                "machine.spacing_mm",
                s.to_string(),
                "a positive plant spacing in mm",
            ));
        }
        (None, Some(v)) if v >= 0.0 && v.is_finite() => f.forward_mm_s = v,
        (None, Some(v)) => {
            return Err(bad(
                "machine.forward_speed_mm_s",
                v.to_string(),
                "a speed ≥ 0 in mm/s",
            ));
        }
        (None, None) => {}
    }
    if let Some(d) = spec.machine.depth_mm {
        if !(d >= 0.0 && d.is_finite()) {
            return Err(bad("machine.depth_mm", d.to_string(), "a depth ≥ 0 in mm"));
        }
        f.planting_depth_mm = d;
    }
    for (name, b) in spec.targets.bands() {
        if !(b[0].is_finite() && b[1].is_finite() && b[0] <= b[1]) {
            return Err(bad(
                &format!("targets.{name}"),
                format!("{b:?}"),
                "a band [min, max] with min ≤ max",
            ));
        }
    }
    Ok((spec.poses.iter().map(|p| p.pose()).collect(), tol, sense, f))
}

/// The largest position tolerance of the approximate poses, mm (0 when all are exact).
fn max_tol_mm(spec: &Spec) -> f64 {
    spec.poses
        .iter()
        .filter(|p| p.approximate())
        .map(|p| p.tol_mm.unwrap_or(0.5))
        .fold(0.0, f64::max)
}

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
            let value = match name {
                "take_angle_deg" => f.needle_angle_take_deg,
                "push_angle_deg" => f.needle_angle_plant_deg,
                "angle_difference_deg" => f.needle_angle_plant_deg - f.needle_angle_take_deg,
                "height_mm" => f.height_mm,
                "hole_width_mm" => f.hole_width_mm,
                _ => f.min_arm_clearance_mm,
            };
            TargetResult {
                index: name.into(),
                band,
                value,
                margin: (value - band[0]).min(band[1] - value),
            }
        })
        .collect()
}
