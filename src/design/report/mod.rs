//! `design.json`: the design report and the design it describes (mm and degrees).

pub(in crate::design) mod checks;
pub mod sizing;

pub use crate::design::fit::FitSummary;
use crate::design::inverse::Inversion;
use crate::geometry::assembly::{Assembly, Rebuilt};
use crate::geometry::mechanism::Mechanism;
use crate::math::Point;
use serde::{Deserialize, Serialize};

/// The layout version of the JSON reports this library writes (`schema_version`): 2 since every
/// field names its unit and one spelling (`center`) holds throughout (docs/schemas.md).
pub const SCHEMA_VERSION: u32 = 2;

/// Files written before the layout carried a version.
fn schema_v1() -> u32 {
    1
}

/// `design.json`: everything a CAD pipeline or a reviewer needs, in mm and degrees.
#[derive(Debug, Clone, Serialize, Deserialize, schemars::JsonSchema)]
#[non_exhaustive]
pub struct DesignReport {
    /// Version of this file's layout, [`SCHEMA_VERSION`] when written by this library (a file
    /// without it is version 1: `l1`, `l3`, `center_distance` and `carrier.center` without
    /// their `_mm`; the readers take both).
    #[serde(default = "schema_v1")]
    pub schema_version: u32,
    /// Units of every length and angle below.
    pub units: Units,
    /// Carrier arm length `|OA|`, mm.
    #[serde(alias = "l1")]
    pub l1_mm: f64,
    /// Needle length `|AB|`, mm.
    #[serde(alias = "l3")]
    pub l3_mm: f64,
    /// Centre distance `a = |OD| = |DA|`, mm (`l1 = 2a·cos ε`).
    #[serde(alias = "center_distance")]
    pub center_distance_mm: f64,
    /// Idler offset ε: the angle at O from the carrier line OA to the intermediate axis OD,
    /// degrees, CCW positive in the file's frame; 0 in the patent's collinear train
    /// ([`crate::geometry::mechanism`]). Read as 0 when absent.
    #[serde(default)]
    pub idler_offset_deg: f64,
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
    /// Compatibility (docs/math/chain.md §6.4, C11).
    pub compatibility: CompatSummary,
    /// The patent route's result.
    pub patent_route: RouteSummary,
    /// The refinement's result, when run.
    pub refinement: Option<RouteSummary>,
    /// The orthogonal-distance fit of the whole train to the points, when it ran.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fit: Option<FitSummary>,
    /// Which result the gears come from: "patent", "refined" (docs/math/chain.md §8.3), "fit" or "module" (the
    /// fit at the module's tooth count).
    pub chosen: String,
    /// The final sun ratio `i21(u) = 1 + Σ a_k cos ku + b_k sin ku`, u = sun polar angle from the
    /// design reference ray, which points at world angle `sun_phase_deg`.
    pub fourier: FourierSummary,
    /// The design made for a module ([`crate::design::DesignOptions::module_mm`]): its tooth
    /// count and the neighbours tried; absent otherwise.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub module: Option<crate::design::ModuleSummary>,
    /// The gear limits and where the design stands against them.
    #[serde(default)]
    pub limits: LimitsSummary,
    /// Checks C1–C13.
    pub checks: Vec<Check>,
    /// The target trajectory as read (world frame, mm, travel order).
    pub target_points: Vec<Point>,
    /// Human-readable warnings.
    pub warnings: Vec<String>,
    /// Wall-clock time per stage, ms.
    pub timings_ms: Timings,
    /// Teeth of the final gears, filled by [`crate::design::train::ToothedTrain::record`]; absent
    /// without teeth. Written with sorted keys; a block that does not parse reads as absent.
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        serialize_with = "crate::design::train::teeth_json::serialize",
        deserialize_with = "crate::design::train::teeth_json::deserialize"
    )]
    pub teeth: Option<crate::design::train::TrainTeethReport>,
    /// A failed design's nearest alternatives with their figures (the other idler layout, a
    /// looser pressure-angle limit, a smaller module; [`crate::design::chain::alternatives`]), when
    /// [`crate::design::DesignOptions::alternatives`] asks for them; empty otherwise.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub alternatives: Vec<Alternative>,
    /// The module sized by strength (`ncgear design --module auto --loads`): the modules
    /// tried and the one kept; absent otherwise.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sizing: Option<crate::design::report::sizing::ModuleSizing>,
    /// Whether the design passed its verification: every check C1–C13, with teeth both
    /// meshes, and a sizing's targets ([`DesignReport::update_verdict`]).
    #[serde(default)]
    pub verdict: crate::verdict::Verdict,
}

impl DesignReport {
    /// Recomputes [`DesignReport::verdict`] from the checks and the teeth's mesh verification
    /// (called by the chain, and again when teeth are recorded).
    pub fn update_verdict(&mut self) {
        let mut failures: Vec<String> = self
            .checks
            .iter()
            .filter(|c| !c.pass)
            .map(|c| {
                format!(
                    "{}: {} = {:.4e} (limit {:.4e})",
                    c.id, c.name, c.value, c.limit
                )
            })
            .collect();
        if let Some(t) = &self.teeth {
            failures.extend(self.teeth_verdict(t).failures);
        }
        failures.extend(self.sizing.as_ref().and_then(|s| s.failure()));
        self.verdict = crate::verdict::Verdict::from_failures(failures);
    }

    /// The verdict of this design's toothed train `t`: both meshes
    /// ([`crate::design::train::TrainTeethReport::verdict`]) and the tooth-count policy judged
    /// as C12 judges the design. A policy that scales the finished design (or rescales its
    /// ratio) moves the tip synchronously by `max_tip_shift_mm`; beyond the C12 limit the
    /// toothed train no longer traces the target the design was verified on, whatever the
    /// design's own C12 says (not repeated when C12 itself failed; a design made for the
    /// module moves nothing, shift ≈ 0).
    #[must_use]
    pub fn teeth_verdict(
        &self,
        t: &crate::design::train::TrainTeethReport,
    ) -> crate::verdict::Verdict {
        let mut failures = t.verdict().failures;
        failures.extend(self.tooth_policy_failure(t));
        crate::verdict::Verdict::from_failures(failures)
    }

    fn tooth_policy_failure(&self, t: &crate::design::train::TrainTeethReport) -> Option<String> {
        let c12 = self.checks.iter().find(|c| c.id == "C12" && c.pass)?;
        let shift = t.roundtrip.max_tip_shift_mm;
        (shift > c12.limit).then(|| {
            format!(
                "teeth: the tooth-count policy moves the tip by {shift:.4} mm (C12 limit \
                 {:.4} mm); the toothed train traces {:.4} mm from the target",
                c12.limit, t.roundtrip.max_deviation_mm
            )
        })
    }
}

/// Units used in the report.
#[derive(Debug, Clone, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Units {
    /// "mm".
    pub length: String,
    /// "deg".
    pub angle: String,
}

impl Units {
    /// Lengths in mm, angles in degrees: the units of every file ncgear writes.
    pub(crate) fn mm_deg() -> Self {
        Self {
            length: "mm".into(),
            angle: "deg".into(),
        }
    }
}

/// The carrier.
#[derive(Debug, Clone, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Carrier {
    /// Carrier axis O, mm.
    #[serde(alias = "center")]
    pub center_mm: Point,
    /// +1 CCW, −1 CW (the sense the trajectory is travelled).
    pub direction: i8,
}

/// The three gears.
#[derive(Debug, Clone, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Gears {
    /// Fixed sun gear; body frame = world frame.
    pub sun: Gear,
    /// Intermediate gear.
    pub intermediate: Gear,
    /// Planet gear (congruent to the sun, docs/math/chain.md §6.1).
    pub planet: Gear,
}

/// One gear's pitch table.
#[derive(Debug, Clone, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Gear {
    /// `[theta_deg, r_mm]`, θ CCW in the body frame, uniform.
    pub pitch: Vec<[f64; 2]>,
    /// Orientation at φH = 0 (world angle of the body +x axis), degrees; absent for the sun.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub angle_at_zero_deg: Option<f64>,
    /// Perimeter, mm.
    pub perimeter_mm: f64,
    /// Smallest radius of curvature over the convex part of the curve, mm.
    pub min_radius_of_curvature_mm: f64,
    /// Tightest concave radius of curvature `|ρ|`, mm; absent (`null`) when the curve is convex.
    #[serde(default)]
    pub min_concave_radius_mm: Option<f64>,
    /// Fraction of the curve (in its polar angle) that is concave.
    #[serde(default)]
    pub concave_fraction: f64,
    /// Largest effective pressure angle `α + max|atan(r_θ/r)|` of the curve, degrees.
    #[serde(default)]
    pub max_pressure_angle_deg: f64,
}

/// The gear limits the design was made within, and where it stands against them (from the
/// output tables, as checks C6, C9 and C10 measure it).
#[derive(Debug, Clone, Default, Serialize, Deserialize, schemars::JsonSchema)]
pub struct LimitsSummary {
    /// Whether the pressure-angle and concave-radius limits constrained the design (false: the
    /// ratio bounds alone; C9 and C10 are checked either way).
    pub enabled: bool,
    /// Largest admissible effective pressure angle, degrees.
    pub max_pressure_angle_deg: f64,
    /// Smallest admissible concave radius of curvature, mm.
    pub min_concave_radius_mm: f64,
    /// Smallest admissible convex radius of curvature (the undercut limit of the module), mm;
    /// absent without a module.
    #[serde(default)]
    pub min_convex_radius_mm: Option<f64>,
    /// Admissible sun ratios `[i_min, i_max]`.
    pub ratio_bounds: [f64; 2],
    /// The design's largest effective pressure angle over the three gears, degrees.
    pub pressure_angle_deg: f64,
    /// The design's tightest concave radius of curvature over the three gears, mm; absent when
    /// every pitch curve is convex.
    pub tightest_concave_radius_mm: Option<f64>,
    /// The design's tightest convex radius of curvature over the three gears, mm.
    #[serde(default)]
    pub tightest_convex_radius_mm: f64,
    /// The design's sun ratio range `[min, max]`.
    pub ratio_range: [f64; 2],
    /// The limits the design sits on (within 1 % of the limit): `"pressure angle"`,
    /// `"concave radius"`, `"convex radius (undercut)"`, `"ratio bounds"`. A binding limit is what the design's deviation
    /// from the target is traded for.
    pub binding: Vec<String>,
}

/// Round-trip result.
#[derive(Debug, Clone, Serialize, Deserialize, schemars::JsonSchema)]
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
    /// On measured points (estimated noise σ above [`crate::design::fit::MEASURED_NOISE_MM`]):
    /// the estimated largest distance of the traced path from the curve under the noise, mm,
    /// `√(2 ln p)·√(σ²p/N + max(0, rms² − σ²(1 − p/N)))` with `p = 4 + 2K` fitted parameters
    /// ([`crate::design::fit::noise`]); check C12 judges it instead of `max_deviation_mm`. Absent on
    /// exact points.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub estimated_curve_deviation_mm: Option<f64>,
    /// Carrier angles simulated.
    pub samples: usize,
}

/// Step-1 summary.
#[derive(Debug, Clone, Serialize, Deserialize, schemars::JsonSchema)]
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
    /// Measurement noise σ per coordinate estimated from the points (4th differences in the point
    /// index, trimmed mean; [`crate::design::trajectory::Trajectory::noise_sigma_mm`]), mm.
    #[serde(default)]
    pub noise_sigma_mm: f64,
}

/// Compatibility summary.
#[derive(Debug, Clone, Serialize, Deserialize, schemars::JsonSchema)]
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
#[derive(Debug, Clone, Serialize, Deserialize, schemars::JsonSchema)]
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

/// The final ratio's Fourier coefficients.
#[derive(Debug, Clone, Serialize, Deserialize, schemars::JsonSchema)]
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

/// One verification check (docs/math/chain.md §10).
#[derive(Debug, Clone, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Check {
    /// "C1".."C13".
    pub id: String,
    /// What it checks.
    pub name: String,
    /// Measured value (infinite values, such as C9's radius of a convex curve, are written as
    /// `null` and read back as +∞).
    #[serde(deserialize_with = "null_as_infinity")]
    #[schemars(with = "Option<f64>")]
    pub value: f64,
    /// Limit.
    pub limit: f64,
    /// Whether it passes; report-only checks pass.
    pub pass: bool,
}

/// Milliseconds since `t`, the unit of [`Timings`].
pub(in crate::design) fn ms(t: std::time::Instant) -> f64 {
    t.elapsed().as_secs_f64() * 1e3
}

/// Stage timings, ms.
#[derive(Debug, Clone, Default, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Timings {
    /// Step 1.
    pub inverse: f64,
    /// Compatibility.
    pub compat: f64,
    /// Patent route incl. order choice.
    pub patent: f64,
    /// Refinement (docs/math/chain.md §8.3).
    pub refine: f64,
    /// Fit to the points.
    #[serde(default)]
    pub fit: f64,
    /// The fit at the module's tooth counts.
    #[serde(default)]
    pub module: f64,
    /// Curves, checks and round trip.
    pub outputs: f64,
    /// Total of the design stages above.
    pub total: f64,
    /// The alternatives of a failed design (0: none designed).
    #[serde(default)]
    pub alternatives: f64,
    /// Teeth on the three gears (cutting, relief), set by whoever cuts them (0: none).
    #[serde(default)]
    pub teeth: f64,
    /// The mesh verification of the toothed train (0: none; it may run beside `cad_files`).
    #[serde(default)]
    pub verification: f64,
    /// The teeth's CAD files (DXF, STEP, points).
    #[serde(default)]
    pub cad_files: f64,
    /// The whole command, from its start to the writing of this report (0 when the library was
    /// called directly).
    #[serde(default)]
    pub command: f64,
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
    /// The train's kinematics rebuilt from the pitch tables of `assembly` (the round trip of
    /// check C12): poses at any carrier angle without rebuilding.
    pub rebuilt: Rebuilt,
    /// Step-1 result.
    pub inversion: Inversion,
    /// Traced tip path from the round trip, mm, world frame.
    pub traced_mm: Vec<Point>,
    /// The carrier angle at which the tip passes each target point, rad, in the solved frame
    /// (CCW; the world angle is this times the carrier direction): where check C12 measures
    /// the synchronous deviation, and where a toothed train's is measured too.
    pub point_angles_rad: Vec<f64>,
}

/// A number, or `null` for +∞ (how JSON writes an infinite check value).
fn null_as_infinity<'de, D: serde::Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::INFINITY))
}

/// A failed design's alternative, designed ([`crate::design::chain::alternatives`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[non_exhaustive]
pub struct Alternative {
    /// What changes, in words: `off the carrier line, the same limits`.
    pub label: String,
    /// The flags that ask `ncgear design` for it: `--idler-offset free`.
    pub flags: String,
    /// Its largest distance from the target, mm (check C12's measure).
    pub max_deviation_mm: f64,
    /// Its largest effective pressure angle, deg.
    pub pressure_angle_deg: f64,
    /// Its idler offset, deg (0: on the carrier line).
    pub idler_offset_deg: f64,
    /// Whether it passes every check.
    pub passed: bool,
    /// What still fails, one line each (its verdict's failures; empty when `passed`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub failures: Vec<String>,
}

impl Alternative {
    /// One line: `off the carrier line, the same limits (--idler-offset free): traced within
    /// 0.0809 mm, every check passing` (or the first thing that still fails).
    #[must_use]
    pub fn line(&self) -> String {
        let outcome = match self.failures.first() {
            _ if self.passed => "every check passing".to_string(),
            Some(f) => format!("still failing {f}"),
            None => "still failing".to_string(),
        };
        format!(
            "{} ({}): traced within {:.4} mm, {outcome}",
            self.label, self.flags, self.max_deviation_mm,
        )
    }
}
