//! `compare.json`: the registration of a filmed track to its design, the deviation by carrier
//! angle, the agronomic figures on both, each turn and their spread (mm, degrees, s, rpm).

use crate::simulate::Features;
use serde::{Deserialize, Serialize};

/// The report of `ncgear compare`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CompareReport {
    /// Version of this report's layout.
    pub schema_version: u32,
    /// The track as read.
    pub track: TrackSummary,
    /// The registration: transform, timing, their standard errors, the outliers.
    pub registration: RegistrationReport,
    /// The deviation of the track from the design path.
    pub deviation: DeviationReport,
    /// The agronomic figures of `ncgear simulate` on the design path and on the track.
    pub features: FeaturesComparison,
    /// Each whole turn of the record.
    pub turns: Vec<TurnReport>,
    /// The spread (sample standard deviation) of the per-turn figures: repeatability; absent
    /// with one turn.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub spread: Option<TurnFigures>,
    /// The track against the train's dynamic path at the recorded speed (`--dynamics`); absent
    /// without a rotor scene.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dynamics: Option<DynamicsComparison>,
    /// Files written beside the report (names relative to its directory).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub files: Vec<String>,
}

/// The track against the dynamic path of a rotor scene (docs/compare.md, "Against the
/// dynamics"): the train's settled turn at the recorded mean speed, the track registered to it
/// as to the static path, and how much of the static deviation it explains.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct DynamicsComparison {
    /// The rotor scene's name.
    pub scene: String,
    /// The carrier speed it ran at (the track's mean), r/min.
    pub carrier_rpm: f64,
    /// Turns integrated to the steady state.
    pub turns: u32,
    /// Whether the motion settled (its periodic residual below the scene's tolerance).
    pub settled: bool,
    /// Largest distance of the dynamic tip from the static tip at the same carrier angle, mm.
    pub max_tip_departure_mm: f64,
    /// RMS of that distance over the turn, mm.
    pub rms_tip_departure_mm: f64,
    /// The smooth deviation of the track from the dynamic path (registered to it afresh):
    /// RMS of `|d(φ)|`, mm.
    pub rms_mm: f64,
    /// Its largest, mm.
    pub max_mm: f64,
    /// Carrier angle of the largest, deg.
    pub max_at_carrier_deg: f64,
    /// Hausdorff distance of the smooth track path from the dynamic path, mm.
    pub hausdorff_mm: f64,
    /// The same RMS against the static path (the report's `deviation.rms_mm`), mm.
    pub static_rms_mm: f64,
    /// Share of the static deviation's mean square that the dynamics explain,
    /// `1 − (rms_mm/static_rms_mm)²`: near 1 when the built train moves as modelled, near 0
    /// (or below: the model makes it worse) when the difference is elsewhere.
    pub explained: f64,
    /// Frame noise σ of the registration to the dynamic path, mm.
    pub noise_mm: f64,
}

/// What was read.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct TrackSummary {
    /// Track file.
    pub file: String,
    /// `plain`, `headerless`, `tracker` or `kinovea`.
    pub format: String,
    /// Frames read.
    pub frames: usize,
    /// Rows skipped for an empty x or y (frames the tracker lost).
    pub skipped_rows: usize,
    /// The file's length unit (`mm`, `cm`, `m`, `px`).
    pub unit: String,
    /// Whether y was taken pointing down (image coordinates) and flipped.
    pub y_down: bool,
    /// Whether a second marker (needle axis) was read.
    pub marker: bool,
    /// Whether an encoder column timed the frames (the carrier angle measured, not fitted).
    pub encoder: bool,
    /// Time from the first frame to the last, s.
    pub duration_s: f64,
    /// Median frame rate, frames/s.
    pub fps: f64,
}

/// A value and its standard error from the fit (`√diag((JᵀWJ)⁻¹)·σ̂`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Estimate {
    /// The value.
    pub value: f64,
    /// Its standard error (same unit); 0 when held fixed.
    pub se: f64,
}

/// The registration: design point `q = s·R(θ)·M·p + t` of a track point `p` (file units and
/// axes, y flipped when `y_down`, `M` the mirror `x → −x` when `mirrored`), and the carrier angle
/// of each frame `φ(t) = φ₀ + ω·(t − t_m) + Σ c_k·((t − t_m)/t_h)^k`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RegistrationReport {
    /// Rotation θ, deg (`se` 0 when given).
    pub rotation_deg: Estimate,
    /// Whether the rotation was given (`--rotation`), not fitted.
    pub rotation_given: bool,
    /// Translation t, x and y, mm (fixed with a carrier-axis datum).
    pub translation_mm: [Estimate; 2],
    /// Scale s, mm per track unit (`se` 0 when given).
    pub scale_mm_per_unit: Estimate,
    /// Whether the scale was fitted (`--fit-scale`).
    pub scale_fitted: bool,
    /// Whether the track was mirrored.
    pub mirrored: bool,
    /// The carrier axis as filmed (track units), when it pinned the translation.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub carrier_axis: Option<[f64; 2]>,
    /// Mid time t_m of the record, s.
    pub mid_time_s: f64,
    /// Carrier angle φ₀ at t_m, deg (world, in [0, 360)).
    pub phase_deg: Estimate,
    /// Carrier speed at t_m (|ω|), rpm; with an encoder, the mean (se 0).
    pub rpm: Estimate,
    /// Mean carrier speed over the record, rpm.
    pub mean_rpm: f64,
    /// Drift coefficients c_2…c_D of the timing, deg.
    pub drift_deg: Vec<Estimate>,
    /// Noise σ of a frame about the smooth deviation, per axis, mm.
    pub noise_mm: f64,
    /// Outlier frames (tracking glitches), excluded from every figure.
    pub outliers: usize,
    /// Line numbers of the outlier frames in the track file.
    pub outlier_lines: Vec<usize>,
    /// Levenberg–Marquardt iterations.
    pub iterations: usize,
    /// Whether the fit converged.
    pub converged: bool,
}

/// The deviation of the registered track from the design path.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct DeviationReport {
    /// RMS over the frames (outliers excluded) of `|q_i − B(φ_i)|`, mm: noise and deviation.
    pub frame_rms_mm: f64,
    /// Largest `|q_i − B(φ_i)|` over the frames (outliers excluded), mm.
    pub frame_max_mm: f64,
    /// Order K of the smooth deviation `d(φ)` (Fourier series fitted to the frames): the one
    /// given, or the one the Bayesian information criterion chose (docs/compare.md).
    pub smooth_order: usize,
    /// Standard error of `d(φ)` per axis from the noise, `σ·√((2K+1)/n)`, mm: deviations
    /// below a few of it are not resolved.
    pub noise_floor_mm: f64,
    /// RMS of `|d(φ)|` over the turn, mm.
    pub rms_mm: f64,
    /// Largest `|d(φ)|`, mm.
    pub max_mm: f64,
    /// Carrier angle of the largest, deg.
    pub max_at_carrier_deg: f64,
    /// Hausdorff distance between the smooth track path `B + d` and the design path, mm
    /// (timing left out).
    pub hausdorff_mm: f64,
    /// `d(φ)` every 5° of carrier angle.
    pub by_angle: Vec<AngleDeviation>,
}

/// The smooth deviation at one carrier angle.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct AngleDeviation {
    /// Carrier angle, deg.
    pub carrier_deg: f64,
    /// Design tip there, mm.
    pub design_mm: [f64; 2],
    /// `d(φ)`, mm.
    pub deviation_mm: [f64; 2],
    /// Along the path's left normal (direction of travel turned +90°), mm.
    pub normal_mm: f64,
    /// Along the direction of travel (the track ahead of the design: > 0), mm.
    pub tangential_mm: f64,
    /// Frames within ±2.5° of it.
    pub frames: usize,
}

/// The agronomic figures (definitions in `ncgear simulate`, docs/simulate.md) on both paths.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct FeaturesComparison {
    /// How the track's needle angle was measured: `marker` (the second marker) or `design`
    /// (from the design's planet centre A(φ) to the tracked tip).
    pub needle_from: String,
    /// On the design path.
    pub design: Features,
    /// On the track (its smooth path `B + d`).
    pub track: Features,
    /// Track − design of the main figures.
    pub difference: TurnFigures,
}

/// The main figures of one path.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct TurnFigures {
    /// Taking angle α_T, deg.
    pub take_angle_deg: f64,
    /// Pushing angle α_P, deg.
    pub push_angle_deg: f64,
    /// Hole width at the planting depth, mm.
    pub hole_width_mm: f64,
    /// Trajectory height, mm.
    pub height_mm: f64,
    /// Static loop width at the planting depth, mm.
    pub static_width_at_depth_mm: f64,
    /// RMS of the smooth deviation, mm.
    pub deviation_rms_mm: f64,
}

/// One whole turn of the record.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct TurnReport {
    /// Turn number (0 first).
    pub index: usize,
    /// Frames in it (outliers excluded).
    pub frames: usize,
    /// Time of its first frame, s.
    pub start_s: f64,
    /// Its mean carrier speed, rpm.
    pub rpm: f64,
    /// RMS of the frames' `|q_i − B(φ_i)|`, mm.
    pub frame_rms_mm: f64,
    /// Its figures (deviation fitted to its frames alone).
    pub figures: TurnFigures,
}
