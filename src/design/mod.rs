//! The whole design chain and its report (spec §3–§10).
//!
//! `trajectory → inverse → compat → segmented → fourier → refine → mechanism → assembly`:
//!
//! 1. [`crate::design::inverse`]: l1, l3, ψ3, i31 (step 1–2);
//! 2. [`crate::design::compat`]: half-closure origin τ and compatibility residual E_c (§6.4);
//! 3. [`crate::design::segmented`]: Fourier hypothesis, mirror/weight iteration (§7);
//! 4. [`crate::geometry::fourier`]: least-squares fit with exact closure, order fixed or adaptive (§8.1–8.2);
//! 5. [`crate::design::refine`]: direct fit of the tip motion when the patent route misses the tolerance (§8.3);
//! 6. pitch curves, assembly angles, checks C1–C12 and the round trip from the output tables (§9–10).
//!
//! ```no_run
//! use ncgear::design::{design, DesignOptions, trajectory::Trajectory};
//! let traj = Trajectory::read(std::path::Path::new("assets/trajectories/g1_ellipse.csv")).unwrap();
//! let d = design(&traj, &DesignOptions::default()).unwrap();
//! assert!(d.report.roundtrip.max_deviation_mm < 0.1);
//! ```

pub mod compat;
pub mod fit;
pub mod inverse;
pub mod refine;
pub mod segmented;
pub mod train;
pub mod trajectory;

use crate::design::compat::Compatibility;
use crate::design::fit::FitOptions;
use crate::design::inverse::{InverseError, InverseOptions, Inversion};
use crate::design::refine::RefineOptions;
use crate::design::segmented::{SegmentedError, SegmentedOptions};
use crate::design::trajectory::{ClosedSpline, Trajectory};
use crate::geometry::assembly::{Assembly, hausdorff_mm};
use crate::geometry::fourier::{RatioError, SunRatio};
use crate::geometry::mechanism::Mechanism;
use crate::geometry::pitch::{PitchCurve, PitchError};
use serde::{Deserialize, Serialize};
use std::f64::consts::{PI, TAU};
use std::time::Instant;

/// Orders tried by the adaptive order choice (spec §8.2).
pub const ADAPTIVE_ORDERS: [usize; 8] = [4, 6, 8, 12, 16, 24, 32, 40];

/// When to run the refinement of §8.3.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum RefineMode {
    /// Only when the patent route misses the tolerance (default).
    #[default]
    Auto,
    /// Always.
    On,
    /// Never.
    Off,
}

/// Every knob of the chain.
#[derive(Debug, Clone, PartialEq)]
pub struct DesignOptions {
    /// Carrier axis O in the trajectory's frame, mm.
    pub center_mm: [f64; 2],
    /// Step-1 accuracy knobs.
    pub inverse: InverseOptions,
    /// Smooth a measured/noisy trajectory to this many Fourier harmonics before step 1
    /// (deviations are still measured against the points as read).
    pub smoothing: Option<usize>,
    /// Patent-route knobs.
    pub segmented: SegmentedOptions,
    /// Fixed Fourier order K; `None` = adaptive to `tol_tip_mm`.
    pub order: Option<usize>,
    /// Target max synchronous tip deviation, mm. Default 0.05: the round-trip acceptance bound
    /// for exactly traceable targets (the spec suggests 0.1).
    pub tol_tip_mm: f64,
    /// Refinement policy.
    pub refine: RefineMode,
    /// Fit every parameter to the points as the last stage ([`crate::design::fit`]), when the chain's
    /// result is not within 0.2·`tol_tip_mm` of them, leaves the ratio bounds, or came from smoothed
    /// points (default true). Off: the chain's result (patent route, or §8.3 with `refine: On`).
    pub fit_to_points: bool,
    /// Refinement knobs (ratio bounds are shared with check C6).
    pub refine_options: RefineOptions,
    /// Fourier order used by the refinement when no fixed order is given.
    pub refine_order: usize,
    /// Samples per pitch curve in the outputs (≥ 720).
    pub curve_samples: usize,
    /// Carrier angles used to measure deviations.
    pub check_samples: usize,
    /// Rack pressure angle α used by the pressure-angle check C10, rad.
    pub pressure_angle_rad: f64,
    /// Limit on the effective pressure angle, rad (C10).
    pub pressure_angle_limit_rad: f64,
}

impl Default for DesignOptions {
    fn default() -> Self {
        Self {
            center_mm: [0.0, 0.0],
            inverse: InverseOptions::default(),
            smoothing: None,
            segmented: SegmentedOptions::default(),
            order: None,
            tol_tip_mm: 0.05,
            refine: RefineMode::Auto,
            fit_to_points: true,
            refine_options: RefineOptions::default(),
            refine_order: 12,
            curve_samples: 3600,
            check_samples: 2048,
            pressure_angle_rad: 20f64.to_radians(),
            pressure_angle_limit_rad: 45f64.to_radians(),
        }
    }
}

/// Why the chain stopped. Targets the train cannot trace exactly are *not* errors: they are
/// reported (compatibility residual, achieved deviation).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum DesignError {
    /// Step 1 failed: no constant-length arm traces the trajectory.
    #[error(transparent)]
    Inverse(#[from] InverseError),
    /// The hypothesis is invalid.
    #[error(transparent)]
    Segmented(#[from] SegmentedError),
    /// A bad option value.
    #[error("option `{option}` = {value}: {expected}")]
    BadOption {
        /// Option name.
        option: &'static str,
        /// Given value.
        value: String,
        /// What is expected.
        expected: &'static str,
    },
    /// The best ratio found leaves the admissible bounds.
    #[error(
        "the sun ratio i21 would span [{min:.3}, {max:.3}], outside the admissible bounds [{lo}, {hi}] (spec §14); with the refinement off nothing brings it back inside: let the fit to the points run (refine auto or on), which keeps every design within the bounds"
    )]
    RatioOutOfBounds {
        /// Smallest ratio.
        min: f64,
        /// Largest ratio.
        max: f64,
        /// Lower bound.
        lo: f64,
        /// Upper bound.
        hi: f64,
    },
    /// Internal failure building a ratio or curve.
    #[error("internal: {0}")]
    Internal(String),
}

impl From<RatioError> for DesignError {
    fn from(e: RatioError) -> Self {
        DesignError::Internal(e.to_string())
    }
}

impl From<PitchError> for DesignError {
    fn from(e: PitchError) -> Self {
        DesignError::Internal(e.to_string())
    }
}

/// `design.json`: everything a CAD pipeline or a reviewer needs, in mm and degrees.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[non_exhaustive]
pub struct DesignReport {
    /// Units of every length and angle below.
    pub units: Units,
    /// Carrier arm length `|OA|`, mm.
    pub l1: f64,
    /// Needle length `|AB|`, mm.
    pub l3: f64,
    /// Centre distance `a = l1/2`, mm.
    pub center_distance: f64,
    /// Needle angle γ relative to the planet's body +x axis, degrees.
    pub needle_angle_deg: f64,
    /// Carrier axis and sense.
    pub carrier: Carrier,
    /// Pitch tables and assembly angles.
    pub gears: Gears,
    /// Round trip from the output tables (C12).
    pub roundtrip: RoundTrip,
    /// Step-1 summary.
    pub trajectory: TrajectorySummary,
    /// Compatibility (§6.4, C11).
    pub compatibility: CompatSummary,
    /// The patent route's result.
    pub patent_route: RouteSummary,
    /// The refinement's result, when run.
    pub refinement: Option<RouteSummary>,
    /// The orthogonal-distance fit of the whole train to the points, when it ran.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fit: Option<FitSummary>,
    /// Which result the gears come from: "patent", "refined" (§8.3) or "fit".
    pub chosen: String,
    /// The final sun ratio `i21(u) = 1 + Σ a_k cos ku + b_k sin ku`, u = sun polar angle from the
    /// design reference ray, which points at world angle `sun_phase_deg`.
    pub fourier: FourierSummary,
    /// Checks C1–C12.
    pub checks: Vec<Check>,
    /// The target trajectory as read (world frame, mm, travel order).
    pub target_points: Vec<[f64; 2]>,
    /// Human-readable warnings.
    pub warnings: Vec<String>,
    /// Wall-clock time per stage, ms.
    pub timings_ms: Timings,
    /// Teeth of the final gears (`ncgear design --module M`): a
    /// [`crate::design::train::TrainTeethReport`] as JSON; absent without a module.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub teeth: Option<serde_json::Value>,
}

/// Units used in the report.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Units {
    /// "mm".
    pub length: String,
    /// "deg".
    pub angle: String,
}

/// The carrier.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Carrier {
    /// Carrier axis O, mm.
    pub center: [f64; 2],
    /// +1 CCW, −1 CW (the sense the trajectory is travelled).
    pub direction: i8,
}

/// The three gears.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Gears {
    /// Fixed sun gear; body frame = world frame.
    pub sun: Gear,
    /// Intermediate gear.
    pub intermediate: Gear,
    /// Planet gear (congruent to the sun, spec §6.1).
    pub planet: Gear,
}

/// One gear's pitch table.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Gear {
    /// `[theta_deg, r_mm]`, θ CCW in the body frame, uniform.
    pub pitch: Vec<[f64; 2]>,
    /// Orientation at φH = 0 (world angle of the body +x axis), degrees; absent for the sun.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub angle_at_zero_deg: Option<f64>,
    /// Perimeter, mm.
    pub perimeter_mm: f64,
    /// Smallest signed radius of curvature, mm (negative = concave).
    pub min_radius_of_curvature_mm: f64,
}

/// Round-trip result.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct RoundTrip {
    /// Max synchronous tip deviation `max_j |B_rebuilt(φ_j) − P_j|` over the target points, mm,
    /// where φ_j is the carrier angle at which the designed tip passes point j.
    pub max_deviation_mm: f64,
    /// RMS of the same deviations, mm.
    #[serde(default)]
    pub rms_deviation_mm: f64,
    /// Hausdorff distance between the traced path and the target curve through the points, mm
    /// (a periodic cubic spline through the points in the carrier angle at which the tip passes
    /// them; the chord-length spline when those angles are not monotone).
    pub hausdorff_mm: f64,
    /// Largest `|r_sun + ρ2 − a|` / `|r_planet + ρ2 − a|` seen, mm.
    pub max_mesh_error_mm: f64,
    /// Carrier angles simulated.
    pub samples: usize,
}

/// Step-1 summary.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct TrajectorySummary {
    /// Points read.
    pub points: usize,
    /// Largest tip distance from O, mm.
    pub rho_max_mm: f64,
    /// Smallest tip distance from O, mm.
    pub rho_min_mm: f64,
    /// Carrier angle at the ρmax instant (reference instant), degrees, file frame.
    pub reference_carrier_angle_deg: f64,
    /// Needle swing amplitude `max|ψ3 − t − mean|`, degrees.
    pub needle_swing_deg: f64,
    /// i31 range over the turn.
    pub i31_range: [f64; 2],
    /// Measurement noise σ estimated from the points (local cubic fits), mm.
    #[serde(default)]
    pub noise_sigma_mm: f64,
}

/// Compatibility summary.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct CompatSummary {
    /// Chosen half-closure origin τ, degrees after the reference instant.
    pub tau_deg: f64,
    /// E_c, rad.
    pub residual_rad: f64,
    /// `l3·E_c`, mm.
    pub tip_equivalent_mm: f64,
    /// `i31(τ)·i31(τ+π)`.
    pub endpoint_product: f64,
    /// All origins found, degrees after the reference instant.
    pub origins_deg: Vec<f64>,
}

/// Result of one route.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct RouteSummary {
    /// Fourier order K.
    pub order: usize,
    /// Max synchronous tip deviation of the forward model, mm.
    pub max_deviation_mm: f64,
    /// Junction mismatch J0 (patent route).
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub j0: Option<f64>,
    /// Junction slope mismatch J1 (patent route).
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub j1: Option<f64>,
    /// Mirror iterations (patent) or residual evaluations (refinement).
    pub iterations: usize,
    /// Solver note.
    pub note: String,
    /// Deviation at each order tried (patent route, adaptive): `[K, mm]`.
    #[serde(skip_serializing_if = "Vec::is_empty", default)]
    pub order_scan: Vec<[f64; 2]>,
}

/// The orthogonal-distance fit ([`crate::design::fit`]): distances of the target points from the curve the
/// fitted train traces (analytic model), mm.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct FitSummary {
    /// Fourier order K of the fitted sun ratio.
    pub order: usize,
    /// RMS point distance, mm (≈ the noise σ on measured points).
    pub rms_mm: f64,
    /// Largest point distance, mm.
    pub max_mm: f64,
    /// RMS point distance of the start (the chain's result before the fit), mm.
    pub start_rms_mm: f64,
    /// Largest point distance of the start, mm.
    pub start_max_mm: f64,
    /// Noise σ estimated from the points alone (local cubic fits), mm.
    pub noise_sigma_mm: f64,
    /// Harmonics of the smoothed copy the start was taken from (measured points), if any.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub start_smoothing_harmonics: Option<usize>,
    /// Levenberg–Marquardt iterations.
    pub iterations: usize,
    /// `[K, rms_mm, max_mm]` per order tried.
    pub order_scan: Vec<[f64; 3]>,
}

/// The final ratio's Fourier coefficients.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct FourierSummary {
    /// Order K.
    pub order: usize,
    /// Cosine coefficients a_1..a_K.
    pub a: Vec<f64>,
    /// Sine coefficients b_1..b_K.
    pub b: Vec<f64>,
    /// World angle of the design reference ray, degrees.
    pub sun_phase_deg: f64,
    /// i21 range.
    pub i21_range: [f64; 2],
}

/// One verification check (spec §10).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Check {
    /// "C1".."C12".
    pub id: String,
    /// What it checks.
    pub name: String,
    /// Measured value.
    pub value: f64,
    /// Limit.
    pub limit: f64,
    /// Whether it passes; report-only checks pass.
    pub pass: bool,
}

/// Stage timings, ms.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct Timings {
    /// Step 1.
    pub inverse: f64,
    /// Compatibility.
    pub compat: f64,
    /// Patent route incl. order choice.
    pub patent: f64,
    /// Refinement (§8.3).
    pub refine: f64,
    /// Fit to the points.
    #[serde(default)]
    pub fit: f64,
    /// Curves, checks and round trip.
    pub outputs: f64,
    /// Total.
    pub total: f64,
}

/// Everything the chain produced: the report plus the objects behind it.
#[derive(Debug, Clone)]
pub struct Design {
    /// The report (`design.json`).
    pub report: DesignReport,
    /// The chosen mechanism (solved frame: CCW, relative to O).
    pub mechanism: Mechanism,
    /// The assembled gears, world frame.
    pub assembly: Assembly,
    /// Step-1 result.
    pub inversion: Inversion,
    /// Traced tip path from the round trip, mm, world frame.
    pub traced_mm: Vec<[f64; 2]>,
}

fn ms(t: Instant) -> f64 {
    t.elapsed().as_secs_f64() * 1e3
}

/// Runs the whole chain on a trajectory.
pub fn design(traj: &Trajectory, opts: &DesignOptions) -> Result<Design, DesignError> {
    validate(opts)?;
    let t_all = Instant::now();
    let mut timings = Timings::default();
    let mut warnings = Vec::new();

    let t0 = Instant::now();
    let noise_sigma = traj.noise_sigma_mm();
    let (inv, start_smoothing) = invert_for_start(traj, opts, noise_sigma)?;
    timings.inverse = ms(t0);
    if let Some(h) = start_smoothing.filter(|_| opts.smoothing.is_none()) {
        warnings.push(format!(
            "measured points (estimated noise σ = {noise_sigma:.4} mm): the start of the design was taken from the loop smoothed to {h} harmonics; the gears are fitted to the points as read"
        ));
    }
    if inv.other_sense_traceable {
        warnings.push(format!(
            "both carrier senses can trace this path (the other one with the arm's elbow flipped); chose {} as the better-realisable law",
            if inv.direction > 0 { "CCW" } else { "CW" }
        ));
    }
    let law = &inv.law;
    let (l3, a) = (inv.l3_mm, 0.5 * inv.l1_mm);
    let n = opts.inverse.grid.max(64) / 2 * 2;

    let t0 = Instant::now();
    let compat: Compatibility = compat::analyse(law, n, 1e-13);
    timings.compat = ms(t0);
    let tau = compat.tau_rad;

    // Patent route: segmented hypothesis, then the Fourier fit at fixed or adaptive order.
    let t0 = Instant::now();
    let seg = segmented::design(law, tau, n, &opts.segmented)?;
    if !seg.converged {
        warnings.push(format!(
            "patent iteration did not close the junctions (J0 = {:.3e} after {} steps): the target is not compatible with the train (E_c·l3 = {:.3} mm)",
            seg.j0,
            seg.iterations,
            compat.residual_rad * l3
        ));
    }
    let beta = |p: f64| inv.beta(p);
    let mk = |ratio: SunRatio, tau_s: f64| {
        let mut m = Mechanism {
            a_mm: a,
            l3_mm: l3,
            ratio,
            sun_phase_rad: inv.phi_h0_rad + tau_s,
            needle_angle_rad: 0.0,
        };
        let phis: Vec<f64> = (0..opts.check_samples)
            .map(|k| TAU * k as f64 / opts.check_samples as f64)
            .collect();
        m.fit_needle_angle(&phis, beta);
        let dev = m.synchronous_deviation_mm(opts.check_samples, beta);
        (m, dev)
    };
    let orders: Vec<usize> = match opts.order {
        Some(k) => vec![k],
        None => ADAPTIVE_ORDERS
            .iter()
            .copied()
            .filter(|&k| 4 * k <= n)
            .collect(),
    };
    let mut scan = Vec::new();
    let mut patent: Option<(Mechanism, f64, usize)> = None;
    let mut out_of_bounds: Option<(Mechanism, usize)> = None;
    for &k in &orders {
        let ratio = match SunRatio::fit_uniform(&seg.samples, k) {
            Ok(r) => r,
            Err(_) => SunRatio::new_unchecked(vec![0.0; k], vec![0.0; k]),
        };
        let (lo, hi) = (
            ratio.sampled_extreme(4096, false).0,
            ratio.sampled_extreme(4096, true).0,
        );
        let [blo, bhi] = opts.refine_options.ratio_bounds;
        if lo < blo || hi > bhi {
            // Outside the admissible ratios (spec §14): not a candidate, but kept as the
            // refinement's last-resort start.
            if out_of_bounds.is_none() {
                out_of_bounds = Some((mk(ratio, tau).0, k));
            }
            continue;
        }
        let (m, dev) = mk(ratio, tau);
        scan.push([k as f64, dev]);
        let better = patent.as_ref().is_none_or(|p| dev < p.1);
        if better {
            patent = Some((m, dev, k));
        }
        if dev <= opts.tol_tip_mm {
            break;
        }
    }
    let (patent_m, patent_dev, patent_k) = match (patent, out_of_bounds) {
        (Some(p), _) => p,
        (None, Some((m, k))) => {
            warnings.push("no Fourier order of the patent route stays within the ratio bounds; the refinement (with its bound penalty) decides".into());
            (m, f64::INFINITY, k)
        }
        (None, None) => {
            return Err(DesignError::Internal(
                "no Fourier order was tried (grid too small)".into(),
            ));
        }
    };
    timings.patent = ms(t0);
    let patent_summary = RouteSummary {
        order: patent_k,
        max_deviation_mm: patent_dev,
        j0: Some(seg.j0),
        j1: Some(seg.j1),
        iterations: seg.iterations,
        note: format!(
            "route {:?}, w1 = {}, {}",
            opts.segmented.route,
            opts.segmented.w1,
            if seg.converged {
                "junctions closed"
            } else {
                "junctions not closed"
            }
        ),
        order_scan: if opts.order.is_none() {
            scan
        } else {
            Vec::new()
        },
    };

    // Refinement (§8.3).
    let t0 = Instant::now();
    let run_refine = match opts.refine {
        RefineMode::On => true,
        RefineMode::Off => false,
        // The fit to the points (below) is the default refinement; §8.3 runs when asked for.
        RefineMode::Auto => false,
    };
    let mut refined = None;
    if run_refine {
        let k = opts.order.unwrap_or(opts.refine_order);
        // The patent route's ratio made admissible (spec §14): the refinement starts inside the bounds.
        let start = SunRatio::fit_uniform_unchecked(&seg.samples, k)
            .admissible(opts.refine_options.ratio_bounds);
        let (m0, _) = mk(start.clone(), tau);
        // C = π + γ for the start.
        let c0 = PI + m0.needle_angle_rad;
        let r = refine::refine(law, l3, a, &start, tau, c0, &opts.refine_options);
        match SunRatio::new(
            r.ratio.cos_coefficients().to_vec(),
            r.ratio.sin_coefficients().to_vec(),
        ) {
            Ok(ratio) => {
                let (m, dev) = mk(ratio, r.tau_rad);
                refined = Some((m, dev, k, r.evaluations, r.termination));
            }
            Err(e) => warnings.push(format!(
                "refinement left the admissible ratios ({e}); kept the patent route"
            )),
        }
    }
    timings.refine = ms(t0);
    let refine_summary = refined.as_ref().map(|(_, dev, k, ev, term)| RouteSummary {
        order: *k,
        max_deviation_mm: *dev,
        j0: None,
        j1: None,
        iterations: *ev,
        note: format!("Levenberg–Marquardt: {term}"),
        order_scan: Vec::new(),
    });
    let (mut mech, mut chosen) = match refined {
        Some((m, dev, ..)) if dev < patent_dev => (m, "refined"),
        _ => (patent_m, "patent"),
    };

    // The final stage: every parameter fitted to the points themselves (orthogonal distances).
    let t0 = Instant::now();
    let [lo, hi] = opts.refine_options.ratio_bounds;
    let points = traj.relative_to(opts.center_mm, inv.direction < 0);
    let admissible = |m: &Mechanism| {
        let [rlo, rhi] = m.ratio.range();
        rlo >= lo && rhi <= hi
    };
    let start = fit::measure(&points, &mech);
    let (start_max, start_rms) = (start.max_mm, start.rms_mm);
    let mut angles = start.carrier_angles_rad;
    let run_fit = opts.fit_to_points
        && match opts.refine {
            RefineMode::Off => false,
            RefineMode::On => true,
            RefineMode::Auto => {
                start_smoothing.is_some()
                    || !admissible(&mech)
                    || start_max > FIT_TOL_FRACTION * opts.tol_tip_mm
            }
        };
    let mut fit_summary = None;
    if run_fit {
        let fit_opts = FitOptions {
            order: opts.order,
            ratio_bounds: opts.refine_options.ratio_bounds,
            tol_mm: FIT_TOL_FRACTION * opts.tol_tip_mm,
            noise_sigma_mm: noise_sigma,
            ..FitOptions::default()
        };
        let restarts = [2]
            .into_iter()
            .filter_map(|k| {
                SunRatio::fit_uniform(&seg.samples, k)
                    .or_else(|_| SunRatio::fit_uniform(&seg.samples, 1))
                    .ok()
                    .map(|r| mk(r.admissible(opts.refine_options.ratio_bounds), tau).0)
            })
            .collect();
        let f = fit_with_restarts(&points, &mech, restarts, &fit_opts, opts.tol_tip_mm)?;
        fit_summary = Some(FitSummary {
            order: f.mechanism.ratio.order(),
            rms_mm: f.rms_mm,
            max_mm: f.max_mm,
            start_rms_mm: start_rms,
            start_max_mm: start_max,
            noise_sigma_mm: noise_sigma,
            start_smoothing_harmonics: start_smoothing,
            iterations: f.iterations,
            order_scan: f.order_scan.clone(),
        });
        if f.rms_mm < start_rms || !admissible(&mech) {
            mech = f.mechanism;
            angles = f.carrier_angles_rad;
            chosen = "fit";
        }
    }
    timings.fit = ms(t0);
    let best_dev = fit_summary.as_ref().map_or_else(
        || {
            refine_summary
                .as_ref()
                .map_or(patent_dev, |r| r.max_deviation_mm.min(patent_dev))
        },
        |f| if chosen == "fit" { f.max_mm } else { start_max },
    );
    if best_dev > opts.tol_tip_mm && noise_sigma < FIT_TOL_FRACTION * opts.tol_tip_mm {
        warnings.push(format!(
            "the best design deviates {best_dev:.3} mm from the target (tolerance {} mm): no train of this type traces it exactly (E_c·l3 = {:.3} mm); this is the closest admissible design found",
            opts.tol_tip_mm,
            compat.residual_rad * l3
        ));
    }

    // Outputs, checks, round trip.
    let t0 = Instant::now();
    let [imin, imax] = mech.ratio.range();
    if imin < lo || imax > hi {
        return Err(DesignError::RatioOutOfBounds {
            min: imin,
            max: imax,
            lo,
            hi,
        });
    }
    let out = finish(traj, &inv, &compat, mech, &angles, opts, &mut warnings)?;
    timings.outputs = ms(t0);
    timings.total = ms(t_all);
    let (mechanism, assembly, traced, checks, roundtrip, gears) = out;
    let i31 = law.i31_samples();
    let swing = law
        .samples()
        .iter()
        .fold([f64::MAX, f64::MIN], |m, v| [m[0].min(*v), m[1].max(*v)]);
    let sign = f64::from(inv.direction);
    let report = DesignReport {
        units: Units {
            length: "mm".into(),
            angle: "deg".into(),
        },
        l1: mechanism.l1_mm(),
        l3: mechanism.l3_mm,
        center_distance: mechanism.a_mm,
        needle_angle_deg: sign * mechanism.needle_angle_rad.to_degrees(),
        carrier: Carrier {
            center: opts.center_mm,
            direction: inv.direction,
        },
        gears,
        roundtrip,
        trajectory: TrajectorySummary {
            points: traj.len(),
            rho_max_mm: inv.rho_max_mm,
            rho_min_mm: inv.rho_min_mm,
            reference_carrier_angle_deg: inv.file_angle_deg(inv.phi_h0_rad),
            needle_swing_deg: 0.5 * (swing[1] - swing[0]).to_degrees(),
            i31_range: i31
                .iter()
                .fold([f64::MAX, f64::MIN], |m, v| [m[0].min(*v), m[1].max(*v)]),
            noise_sigma_mm: noise_sigma,
        },
        compatibility: CompatSummary {
            tau_deg: compat.tau_rad.to_degrees(),
            residual_rad: compat.residual_rad,
            tip_equivalent_mm: compat.residual_rad * l3,
            endpoint_product: compat.endpoint_product,
            origins_deg: compat.origins_rad.iter().map(|t| t.to_degrees()).collect(),
        },
        patent_route: patent_summary,
        refinement: refine_summary,
        fit: fit_summary,
        chosen: chosen.into(),
        fourier: FourierSummary {
            order: mechanism.ratio.order(),
            a: mechanism.ratio.cos_coefficients().to_vec(),
            b: mechanism.ratio.sin_coefficients().to_vec(),
            sun_phase_deg: inv.file_angle_deg(mechanism.sun_phase_rad),
            i21_range: [imin, imax],
        },
        checks,
        target_points: traj.points().to_vec(),
        warnings,
        teeth: None,
        timings_ms: timings,
    };
    Ok(Design {
        report,
        mechanism,
        assembly,
        inversion: inv,
        traced_mm: traced,
    })
}

/// `n` points of the target curve through the points: a periodic cubic spline in the carrier
/// angle at which the designed tip passes each point (the mechanism's own time, in which the tip
/// moves smoothly even round a sharp, coarsely sampled nose), or, when those angles do not advance
/// monotonically, the chord-length spline of spec §3.1.
fn target_curve(points: &[[f64; 2]], angles: &[f64], n: usize) -> Vec<[f64; 2]> {
    let mut knots = Vec::with_capacity(angles.len());
    let mut acc = 0.0;
    for (j, &a) in angles.iter().enumerate() {
        if j > 0 {
            acc += (a - angles[j - 1]).rem_euclid(TAU);
        }
        knots.push(acc);
    }
    let closing = angles
        .last()
        .map_or(0.0, |&a| (angles[0] - a).rem_euclid(TAU));
    let monotone = knots.windows(2).all(|w| w[1] > w[0])
        && closing > 0.0
        && (acc + closing - TAU).abs() < 1e-6;
    let axis = |c: usize| {
        crate::math::periodic::PeriodicSpline::new(
            knots.clone(),
            points.iter().map(|p| p[c]).collect(),
            TAU,
        )
    };
    match (monotone, axis(0), axis(1)) {
        (true, Ok(x), Ok(y)) => (0..n)
            .map(|k| {
                let t = TAU * k as f64 / n as f64;
                [x.value(t), y.value(t)]
            })
            .collect(),
        _ => {
            let spline = ClosedSpline::through(points);
            (0..n)
                .map(|k| spline.point(spline.period() * k as f64 / n as f64))
                .collect()
        }
    }
}

/// The fit aims at this fraction of `tol_tip_mm` on the points, and runs (refine auto) when the
/// chain's result is farther: room for the table rebuild and for the curve between the points.
const FIT_TOL_FRACTION: f64 = 0.2;

/// The fit to the points from the chain's result. A target it does not reproduce (and noise does
/// not explain) may sit in another basin: restarts from `restarts` (the patent route at order 2)
/// and from the first fit with its ratio cut to order 2 are screened on a few points with a
/// short budget; the best is refitted on every point and kept if it beats the first fit —
/// by RMS on measured points, by `max(max, coverage)` (the Hausdorff distance to the points'
/// polyline) on clean ones, which then get the minimax finish.
fn fit_with_restarts(
    points: &[[f64; 2]],
    start: &Mechanism,
    restarts: Vec<Mechanism>,
    fit_opts: &FitOptions,
    tol_tip_mm: f64,
) -> Result<fit::Fitted, DesignError> {
    let internal = |e: fit::FitError| DesignError::Internal(e.to_string());
    let mut f = fit::fit_points(points, start, fit_opts).map_err(internal)?;
    let noise = fit_opts.noise_sigma_mm;
    if f.max_mm <= tol_tip_mm || f.rms_mm <= 2.0 * noise {
        return Ok(f);
    }
    let measured = noise > MEASURED_NOISE_MM;
    let score = |g: &fit::Fitted| {
        if measured {
            g.rms_mm
        } else {
            g.max_mm.max(g.coverage_mm)
        }
    };
    let screen = FitOptions {
        max_points: SCREEN_POINTS,
        max_iterations: SCREEN_ITERATIONS,
        max_order: f.mechanism.ratio.order(),
        ..fit_opts.clone()
    };
    let cut = |k: usize| Mechanism {
        ratio: f.mechanism.ratio.with_order(k),
        ..f.mechanism.clone()
    };
    let starts: Vec<Mechanism> = restarts.into_iter().chain([cut(2)]).collect();
    let screened = starts
        .iter()
        .filter_map(|s| fit::fit_points(points, s, &screen).ok())
        .min_by(|a, b| score(a).total_cmp(&score(b)));
    if let Some(g) = screened.filter(|g| score(g) < score(&f)) {
        // On every point, at the screened order, with the screening's iteration budget.
        let refit = FitOptions {
            order: Some(g.mechanism.ratio.order()),
            max_iterations: SCREEN_ITERATIONS,
            ..fit_opts.clone()
        };
        let g = fit::fit_points(points, &g.mechanism, &refit).unwrap_or(g);
        if score(&g) < score(&f) {
            f = g;
        }
    }
    // Not traceable (and clean): trade RMS for the largest deviation, which is what the user
    // sees. Never on measured points, where the largest distance is the noise's.
    if !measured {
        f = fit::minimax(points, f, fit_opts);
    }
    Ok(f)
}

/// Points and Levenberg–Marquardt iterations of a screening fit of a restart.
const SCREEN_POINTS: usize = 240;
const SCREEN_ITERATIONS: usize = 15;

fn rms(v: &[f64]) -> f64 {
    (v.iter().map(|d| d * d).sum::<f64>() / v.len().max(1) as f64).sqrt()
}

/// Noise σ (mm) above which points count as measured: the start is then taken from a smoothed copy.
const MEASURED_NOISE_MM: f64 = 0.002;

/// Smoothing harmonics tried, in order, for the start on measured points.
const START_SMOOTHING: [usize; 5] = [24, 32, 16, 48, 12];

/// Step 1 for the start of the design. With `--smooth` the smoothed loop is inverted; measured
/// points (estimated σ above [`MEASURED_NOISE_MM`]) and points whose raw inversion fails the
/// monotonicity tests are inverted from a smoothed copy (the fit later uses the points as read).
/// Returns the inversion and the smoothing used.
fn invert_for_start(
    traj: &Trajectory,
    opts: &DesignOptions,
    noise_sigma_mm: f64,
) -> Result<(Inversion, Option<usize>), DesignError> {
    let smoothed = |h: usize| {
        let mut o = opts.inverse;
        o.law_harmonics = o.law_harmonics.or(Some(h / 2));
        inverse::invert(&traj.smoothed(h), opts.center_mm, &o)
    };
    if let Some(h) = opts.smoothing {
        return Ok((smoothed(h)?, Some(h)));
    }
    let raw = inverse::invert(traj, opts.center_mm, &opts.inverse);
    let retry = match &raw {
        Ok(_) => noise_sigma_mm > MEASURED_NOISE_MM,
        Err(InverseError::NotMonotone { .. } | InverseError::NeedleReverses { .. }) => true,
        Err(_) => false,
    };
    if retry {
        for h in START_SMOOTHING {
            if let Ok(inv) = smoothed(h) {
                return Ok((inv, Some(h)));
            }
        }
    }
    Ok((raw?, None))
}

fn validate(opts: &DesignOptions) -> Result<(), DesignError> {
    let positive = |v: f64| v.is_finite() && v > 0.0;
    let angle = |v: f64| positive(v) && v < std::f64::consts::FRAC_PI_2;
    let (inv, seg, refine) = (&opts.inverse, &opts.segmented, &opts.refine_options);
    let [lo, hi] = refine.ratio_bounds;
    let [cx, cy] = opts.center_mm;
    let show = |v: Option<usize>| v.map_or_else(|| "none".into(), |k| k.to_string());
    // (valid, option, given value, what is expected), checked in this order.
    let rules: [(bool, &'static str, String, &'static str); 18] = [
        (
            opts.order.is_none_or(|k| (1..=64).contains(&k)),
            "order",
            show(opts.order),
            "an integer in 1..=64 (40 is the recommended cap, spec §8.2)",
        ),
        (
            opts.smoothing.is_none_or(|h| (4..=512).contains(&h)),
            "smooth",
            show(opts.smoothing),
            "a number of harmonics in 4..=512 (about 1/10 of the points for noisy data)",
        ),
        (
            positive(opts.tol_tip_mm),
            "tol-mm",
            opts.tol_tip_mm.to_string(),
            "a positive length in mm",
        ),
        (
            (64..=1 << 16).contains(&inv.grid),
            "grid",
            inv.grid.to_string(),
            "a grid size in 64..=65536",
        ),
        (
            opts.curve_samples >= 720,
            "samples",
            opts.curve_samples.to_string(),
            "at least 720 samples per pitch curve",
        ),
        (
            lo > 0.0 && hi > lo && hi.is_finite(),
            "ratio-bounds",
            format!("{lo},{hi}"),
            "0 < min < max",
        ),
        (
            cx.is_finite() && cy.is_finite(),
            "center",
            format!("{cx},{cy}"),
            "two finite coordinates in mm",
        ),
        (
            positive(inv.tol_relative) && inv.tol_relative < 1e-2,
            "inverse.tol_relative",
            inv.tol_relative.to_string(),
            "a relative tolerance in (0, 0.01)",
        ),
        (
            inv.dense_samples >= 64,
            "inverse.dense_samples",
            inv.dense_samples.to_string(),
            "at least 64 dense samples",
        ),
        (
            inv.law_harmonics != Some(0),
            "inverse.law_harmonics",
            show(inv.law_harmonics),
            "at least one harmonic (or none to keep the law as computed)",
        ),
        (
            positive(seg.tol_j),
            "segmented.tol_j",
            seg.tol_j.to_string(),
            "a positive junction tolerance",
        ),
        (
            seg.w1 > 0.0 && seg.w1 <= 1.0,
            "segmented.w1",
            seg.w1.to_string(),
            "a mirror weight in (0, 1]",
        ),
        (
            refine.smoothness.is_finite() && refine.smoothness >= 0.0,
            "refine.smoothness",
            refine.smoothness.to_string(),
            "a finite weight ≥ 0",
        ),
        (
            refine.samples >= 16,
            "refine.samples",
            refine.samples.to_string(),
            "at least 16 residual samples",
        ),
        (
            (1..=64).contains(&opts.refine_order),
            "refine_order",
            opts.refine_order.to_string(),
            "an integer in 1..=64",
        ),
        (
            opts.check_samples >= 16,
            "check_samples",
            opts.check_samples.to_string(),
            "at least 16 carrier angles",
        ),
        (
            angle(opts.pressure_angle_rad),
            "pressure-angle",
            format!("{} rad", opts.pressure_angle_rad),
            "an angle in (0°, 90°)",
        ),
        (
            angle(opts.pressure_angle_limit_rad),
            "pressure-angle-limit",
            format!("{} rad", opts.pressure_angle_limit_rad),
            "an angle in (0°, 90°)",
        ),
    ];
    match rules.into_iter().find(|r| !r.0) {
        Some((_, option, value, expected)) => Err(DesignError::BadOption {
            option,
            value,
            expected,
        }),
        None => Ok(()),
    }
}

type Finished = (
    Mechanism,
    Assembly,
    Vec<[f64; 2]>,
    Vec<Check>,
    RoundTrip,
    Gears,
);

/// Pitch curves, assembly, checks C1–C12 and the round trip from the output tables.
fn finish(
    traj: &Trajectory,
    inv: &Inversion,
    compat: &Compatibility,
    mech: Mechanism,
    angles: &[f64],
    opts: &DesignOptions,
    warnings: &mut Vec<String>,
) -> Result<Finished, DesignError> {
    let n = opts.curve_samples;
    let sign = f64::from(inv.direction);
    let assembly = Assembly::from_mechanism(&mech, opts.center_mm, inv.direction, n)?;
    let (sun, mid, planet) = (
        assembly.sun.clone(),
        assembly.intermediate.clone(),
        assembly.planet.clone(),
    );
    // Round trip from the tables only (C12), with mesh errors (C3, C4).
    let rebuilt = assembly.rebuild();
    let m = opts.check_samples;
    let mut mesh: [f64; 2] = [0.0, 0.0];
    let mut traced = Vec::with_capacity(m);
    for k in 0..m {
        let pose = rebuilt.pose(sign * TAU * k as f64 / m as f64);
        mesh[0] = mesh[0].max(pose.sun_mesh_error_mm.abs());
        mesh[1] = mesh[1].max(pose.planet_mesh_error_mm.abs());
        traced.push(pose.tip_mm);
    }
    // Synchronous deviation at every target point, at the carrier angle the tip passes it.
    let dev: Vec<f64> = traj
        .points()
        .iter()
        .zip(angles)
        .map(|(p, &phi)| {
            let tip = rebuilt.pose(sign * phi).tip_mm;
            (tip[0] - p[0]).hypot(tip[1] - p[1])
        })
        .collect();
    let sync = dev.iter().copied().fold(0.0, f64::max);
    let haus = hausdorff_mm(&traced, &target_curve(traj.points(), angles, 2 * m));
    let roundtrip = RoundTrip {
        max_deviation_mm: sync,
        rms_deviation_mm: rms(&dev),
        hausdorff_mm: haus,
        max_mesh_error_mm: mesh[0].max(mesh[1]),
        samples: m,
    };

    // Geometry checks.
    let acc = 1e-9 * mech.a_mm;
    let (ls, lm, lp) = (
        sun.perimeter_mm(acc),
        mid.perimeter_mm(acc),
        planet.perimeter_mm(acc),
    );
    let cs = sun.curvature_extremes(8 * n);
    let cm = mid.curvature_extremes(8 * n);
    let means = rebuilt.ratio_means();
    let [imin, imax] = mech.ratio.range();
    let i31_min = (0..4096)
        .map(|k| {
            let t = TAU * k as f64 / 4096.0;
            mech.ratio.value(t) / mech.ratio.value(mech.half_turn_map(t))
        })
        .fold(f64::INFINITY, f64::min);
    let min_conv = cs.min_convexity_mm2.min(cm.min_convexity_mm2);
    let min_rho = cs
        .min_radius_of_curvature_mm
        .min(cm.min_radius_of_curvature_mm);
    let max_dev_mu = cs
        .max_pressure_deviation_rad
        .max(cm.max_pressure_deviation_rad);
    let alpha = opts.pressure_angle_rad;
    let [lo, hi] = opts.refine_options.ratio_bounds;
    let check = |id: &str, name: String, value: f64, limit: f64, pass: bool| Check {
        id: id.into(),
        name,
        value,
        limit,
        pass,
    };
    let checks = vec![
        check("C1", "closure of the ratio |Φ(2π) − 2π|, rad".into(), (mech.ratio.integral(TAU) - TAU).abs(), 1e-12, (mech.ratio.integral(TAU) - TAU).abs() <= 1e-12),
        check("C2", "closure of the output tables: max |mean r/(a−r) − 1|·2π·a, mm".into(), (means[0] - 1.0).abs().max((means[1] - 1.0).abs()) * TAU * mech.a_mm, 1e-6, (means[0] - 1.0).abs().max((means[1] - 1.0).abs()) * TAU * mech.a_mm <= 1e-6),
        check("C3", "centre distance sun–intermediate max |r1 + ρ2 − a|, mm".into(), mesh[0], 1e-6 * mech.a_mm, mesh[0] <= 1e-6 * mech.a_mm),
        check("C4", "centre distance intermediate–planet max |r3 + ρ2 − a|, mm".into(), mesh[1], 1e-6 * mech.a_mm, mesh[1] <= 1e-6 * mech.a_mm),
        check("C5", "rolling without slip: max relative perimeter difference".into(), ((ls - lm).abs().max((ls - lp).abs())) / ls, 1e-7, ((ls - lm).abs().max((ls - lp).abs())) / ls <= 1e-7),
        check("C6", format!("ratio bounds: i21 in [{lo}, {hi}] (value: min i21), i31 > 0 (min i31 = {i31_min:.4})"), imin, lo, imin >= lo && imax <= hi && i31_min > 0.0),
        check("C7", "convexity: min Δ = r² + 2r′² − r r″ of sun and intermediate, mm²".into(), min_conv, 0.0, true),
        check("C8", format!("undercut: largest rack module ρc,min·sin²α/ha* at α = {:.1}°, ha* = 1, mm", alpha.to_degrees()), if min_conv > 0.0 { min_rho * alpha.sin().powi(2) } else { 0.0 }, 0.0, true),
        check("C9", "concave arcs (need a shaper cutter): fraction of the sun and intermediate that is concave".into(), cs.concave_fraction.max(cm.concave_fraction), 0.0, true),
        check("C10", "max effective pressure angle α + max|atan(r_θ/r)|, deg".into(), (alpha + max_dev_mu).to_degrees(), opts.pressure_angle_limit_rad.to_degrees(), alpha + max_dev_mu <= opts.pressure_angle_limit_rad),
        check("C11", "compatibility l3·E_c, mm (report)".into(), compat.residual_rad * mech.l3_mm, opts.tol_tip_mm, true),
        check("C12", "round trip from the output tables: max synchronous tip deviation, mm".into(), sync, opts.tol_tip_mm, sync <= opts.tol_tip_mm),
    ];
    if min_conv <= 0.0 {
        warnings.push(format!("a pitch curve is concave somewhere (min Δ = {min_conv:.3} mm²): a rack cannot cut it; a shaper cutter of radius below {:.2} mm is needed (C9)", min_rho.abs()));
    }
    for c in &checks {
        if !c.pass {
            warnings.push(format!(
                "check {} failed: {} = {:.4e} (limit {:.4e})",
                c.id, c.name, c.value, c.limit
            ));
        }
    }
    let table = |c: &PitchCurve| c.polar_table_deg(n);
    let gear = |c: &PitchCurve, angle: Option<f64>, perim: f64, rho: f64| Gear {
        pitch: table(c),
        angle_at_zero_deg: angle.map(|a| a.to_degrees().rem_euclid(360.0)),
        perimeter_mm: perim,
        min_radius_of_curvature_mm: rho,
    };
    let gears = Gears {
        sun: gear(&sun, None, ls, cs.min_radius_of_curvature_mm),
        intermediate: gear(
            &mid,
            Some(assembly.intermediate_angle_at_zero_rad),
            lm,
            cm.min_radius_of_curvature_mm,
        ),
        planet: gear(
            &planet,
            Some(assembly.planet_angle_at_zero_rad),
            lp,
            cs.min_radius_of_curvature_mm,
        ),
    };
    Ok((mech, assembly, traced, checks, roundtrip, gears))
}
