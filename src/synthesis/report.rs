//! What a synthesis returns: `synthesis.json` ([`SynthesisReport`]), the chosen design, and why a
//! spec cannot be synthesised ([`SynthesisError`]). Files speak mm and degrees.

use super::dyad::{Dyad, DyadError};
use super::timing::TimingError;
use crate::design::Design;
use crate::math::Point;
use serde::{Deserialize, Serialize};

/// The synthesis report (`synthesis.json`).
#[derive(Debug, Clone, Serialize, Deserialize, schemars::JsonSchema)]
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
#[derive(Debug, Clone, Serialize, Deserialize, schemars::JsonSchema)]
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

impl Candidate {
    /// A candidate arm that gave no design, and why.
    pub(super) fn refused(dyad: Dyad, why: String) -> Self {
        Self {
            dyad,
            max_pose_error_mm: None,
            max_pose_error_deg: None,
            targets_missed: 0,
            refused: Some(why),
        }
    }
}

/// One pose on the chosen design.
#[derive(Debug, Clone, Serialize, Deserialize, schemars::JsonSchema)]
pub struct PoseResult {
    /// Pose tip, mm.
    pub tip_mm: Point,
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
#[derive(Debug, Clone, Serialize, Deserialize, schemars::JsonSchema)]
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
    /// The poses over-determine the arm and no arm reaches them all within their tolerance.
    #[error(
        "no arm reaches all {poses} poses within their tolerances: the best misses one by {residual_mm:.4} mm ({exact} exact poses; four or more over-determine the arm with the others): mark poses `kind = \"approximate\"` with a `tol_mm` of at least that, or remove one"
    )]
    NoExactArm {
        /// Poses given.
        poses: usize,
        /// Exact poses among them.
        exact: usize,
        /// The smallest largest residual of the arms found, mm.
        residual_mm: f64,
    },
    /// Every candidate was refused by the design chain.
    #[error("no candidate arm gave a design: {0}")]
    NoDesign(String),
}
