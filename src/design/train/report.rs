//! The `teeth` block of `design.json`: the train's report types, and how the design report
//! writes and reads them.
use super::TrainTeethOptions;
use crate::teeth::UndercutReport;
use crate::teeth::mesh::MeshReport;
use crate::teeth::process::GearProcess;
use serde::{Deserialize, Serialize};

/// Undercut reports of the three gears.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct TrainUndercut {
    /// Sun.
    pub sun: UndercutReport,
    /// Intermediate.
    pub intermediate: UndercutReport,
    /// Planet.
    pub planet: UndercutReport,
}

/// Mesh verification of both meshes over one carrier turn.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct TrainMesh {
    /// Sun → intermediate.
    pub sun_intermediate: MeshReport,
    /// Intermediate → planet.
    pub intermediate_planet: MeshReport,
}

/// Round trip of the final (scaled) mechanism against the target trajectory. On a train put on
/// a fresh design (`ncgear design --module`, [`super::tooth_train`]) the deviations are
/// measured as check C12 measures the design — the largest synchronous deviation at the carrier
/// angles where the designed tip passes the points, and the Hausdorff distance to the target
/// curve read between the points in those angles — except under the ratio-amplitude policy,
/// which re-times the train; there, and on a bare assembly ([`super::tooth_train`]), against the
/// points' polyline.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct TrainRoundTrip {
    /// Largest deviation of the traced tip from the target, mm (designed gears, before the
    /// tooth-count policy): the design's own C12 value where measured as it.
    pub before_max_deviation_mm: f64,
    /// Largest deviation of the traced tip from the target, mm (final gears).
    pub max_deviation_mm: f64,
    /// Hausdorff distance traced ↔ target, mm (final gears).
    pub hausdorff_mm: f64,
    /// Hausdorff distance traced ↔ target, mm (designed gears, before the tooth-count
    /// policy): equal to `hausdorff_mm` for a design made for the module.
    #[serde(default)]
    pub before_hausdorff_mm: f64,
    /// Max synchronous displacement of the tip by the tooth-count policy, mm (closed form
    /// `|s − 1|·l1` when scaling the centre distance).
    pub max_tip_shift_mm: f64,
}

/// The `teeth` block of `design.json`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct TrainTeethReport {
    /// Options used.
    pub options: TrainTeethOptions,
    /// Tooth count of each gear (sun, intermediate, planet).
    pub z: u32,
    /// Module of the teeth, mm (the requested one, or the adjusted one with
    /// [`super::TrainPolicy::AdjustModule`]).
    pub module_mm: f64,
    /// Ratio amplitude factor λ of [`super::TrainPolicy::RatioAmplitude`] (1 otherwise).
    pub ratio_amplitude: f64,
    /// With [`super::TrainPolicy::RatioAmplitude`]: the needle angle γ re-fitted to the rescaled
    /// ratio (relative to the planet's body +x axis, file frame, degrees), which replaces the
    /// design's `needle_angle_deg`; absent otherwise (the design's γ).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub needle_angle_deg: Option<f64>,
    /// With [`super::TrainPolicy::RatioAmplitude`]: the re-fitted world angle of the sun's design
    /// reference ray, degrees in [0, 360) (the sun table is drawn at it); absent otherwise.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sun_phase_deg: Option<f64>,
    /// What the tooth-count policy did to the trajectory when it moved the tip beyond the design
    /// tolerance.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<String>,
    /// `L/(πm)` before scaling.
    pub z_raw: f64,
    /// Scale factor `s = zπm/L` applied to the curves and the centre distance.
    pub scale: f64,
    /// Pitch-curve perimeter after scaling (= zπm), mm.
    pub perimeter_mm: f64,
    /// Centre distance after scaling, mm.
    pub center_distance_mm: f64,
    /// `l1 = 2a` after scaling, mm.
    pub l1_mm: f64,
    /// Radial displacement of every tip point by the scaling, `(s − 1)·l1`, mm.
    pub radial_shift_mm: f64,
    /// Round trip of the final gears.
    pub roundtrip: TrainRoundTrip,
    /// Arc-length position of tooth 0's centre on each gear (sun, intermediate, planet), mm.
    pub phase_mm: [f64; 3],
    /// Undercut and concavity per gear.
    pub undercut: TrainUndercut,
    /// Mesh verification (absent when `verify_steps` = 0).
    pub mesh: Option<TrainMesh>,
    /// Files written (filled by the writer).
    pub files: Vec<String>,
    /// How each gear is cut: rack, or shaper with the cutter chosen and the ones
    /// tried (absent in reports written before it existed).
    #[serde(default)]
    pub process: Option<TrainProcess>,
}

impl TrainTeethReport {
    /// The verdict of the toothed train: both meshes without interference, with a finite,
    /// non-negative backlash ([`crate::verdict::mesh_failures`]; passed when not verified).
    #[must_use]
    pub fn verdict(&self) -> crate::verdict::Verdict {
        let failures = self.mesh.as_ref().map_or_else(Vec::new, |m| {
            let mut f = crate::verdict::mesh_failures("sun-intermediate", &m.sun_intermediate);
            f.extend(crate::verdict::mesh_failures(
                "intermediate-planet",
                &m.intermediate_planet,
            ));
            f
        });
        crate::verdict::Verdict::from_failures(failures)
    }
}

/// Manufacturing process of the three gears.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct TrainProcess {
    /// Sun.
    pub sun: GearProcess,
    /// Intermediate.
    pub intermediate: GearProcess,
    /// Planet.
    pub planet: GearProcess,
}

/// (De)serialisation of [`crate::design::DesignReport::teeth`].
pub(crate) mod teeth_json {
    use super::TrainTeethReport;
    use serde::{Deserialize, Deserializer, Serialize, Serializer};

    /// Writes the block through a JSON value, i.e. with the keys of every object in sorted
    /// order (the layout `design.json` has always had).
    pub(crate) fn serialize<S: Serializer>(
        teeth: &Option<TrainTeethReport>,
        s: S,
    ) -> Result<S::Ok, S::Error> {
        serde_json::to_value(teeth)
            .map_err(serde::ser::Error::custom)?
            .serialize(s)
    }

    /// Reads the block; one that does not parse as a [`TrainTeethReport`] (e.g. a non-finite
    /// number written as `null`) reads as absent rather than failing the whole report.
    pub(crate) fn deserialize<'de, D: Deserializer<'de>>(
        d: D,
    ) -> Result<Option<TrainTeethReport>, D::Error> {
        let v = Option::<serde_json::Value>::deserialize(d)?;
        Ok(v.and_then(|v| TrainTeethReport::deserialize(v).ok()))
    }
}
