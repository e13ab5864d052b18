//! The toothed planetary train: teeth on the designed sun, intermediate and planet pitch curves
//! (`ncgear design --module M`), with the tooth count made an integer, the mating phases, the mesh
//! verification of both meshes and the round trip of the final, scaled mechanism.
//!
//! The mathematics: docs/math/teeth.md §12.1, §12.3, §12.4 (tooth count, mating phase, undercut) on the conventions
//! of docs/math/chain.md §2/§9 (the `design.json` conventions). Lengths in mm, angles in radians unless named `_deg`.
//!
//! # The two meshes as fixed-axis pairs
//! In the frame that turns with the carrier (x′ along O→D), at carrier angle φH:
//! - **sun → intermediate**: the sun (centre O, world orientation 0) turns by `φ = −φH`; the
//!   intermediate (centre D at `(a, 0)`) has orientation `θ2 − φH = −ψ`, so
//!   `ψ₁(φ) = φH − θ2(φH)` with `φH = −φ`;
//! - **intermediate → planet**: the intermediate (centre D) turns by `φ = θ2 − φH`; the planet
//!   (centre A at `(a, 0)` from D) has orientation `θ3 − φH`, so `ψ₂ = φH − θ3(φH)`.
//!
//! Both are the convention of [`crate::teeth::mesh::verify_mesh`] (driver CCW by φ, contact at
//! driver body angle −φ; driven CW by ψ, contact at driven body angle π + ψ).
//!
//! # Tooth count (docs/math/teeth.md §12.1)
//! The three pitch curves have the same perimeter L (equal tooth counts: one relative turn each per
//! carrier turn). `z` comes from `L/(πm)` with a [`ToothPolicy`]; the curves and the centre distance
//! are scaled by `s = zπm/L`. Uniform scaling keeps every ratio `r/(a − r)`, hence θ2(φH) and
//! θ3(φH); with `l3` and γ unchanged, every tip point moves radially by exactly `(s − 1)·l1`
//! (`l1 = 2a`) — the consequence reported as `radial_shift_mm`, and measured by the round trip.
//!
//! # Mating phase (docs/math/teeth.md §12.3)
//! Sun tooth 0 is centred on the contact with the intermediate at φH = 0 (sun body angle 0). For a
//! driver whose contact lies `δ` (arc, mm) ahead of a tooth centre, the driven tooth 0 is centred
//! at `s_n + δ + p/2` (`s_n` its contact arc position): a space faces the driver tooth. Every gear's
//! coast (smaller-s) flank is thinned by half the backlash, so the working flanks of both meshes
//! stay exactly conjugate.
mod amplitude;
mod build;
mod cut;
mod layout;
mod pending;
mod report;
mod shaper_relief;
mod sheet;
mod swept;

pub use amplitude::{AmplitudeFit, refit_needle_and_phase, rescale_ratio_amplitude};
pub use build::{TrainSource, tooth_train, tooth_train_staged};
pub use pending::PendingTrainMesh;
pub(crate) use report::teeth_json;
pub use report::{TrainMesh, TrainProcess, TrainRoundTrip, TrainTeethReport, TrainUndercut};
pub use sheet::{Gear, ToothedTrain};

use crate::geometry::pitch::PitchError;
use crate::teeth::mesh::MeshError;
use crate::teeth::{TeethError, ToothPolicy, ToothingOptions};
use serde::{Deserialize, Serialize};

/// Errors of [`tooth_train`].
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum TrainError {
    /// Teeth cannot be generated on one gear (undercut with the largest module that works,
    /// concave pitch arc, bad rack parameter).
    #[error("{gear}: {source}")]
    Teeth {
        /// `sun`, `intermediate` or `planet`.
        gear: &'static str,
        /// Cause.
        source: TeethError,
    },
    /// The mesh verification could not run.
    #[error("mesh {pair}: {source}")]
    Mesh {
        /// `sun-intermediate` or `intermediate-planet`.
        pair: &'static str,
        /// Cause.
        source: MeshError,
    },
    /// A scaled pitch curve is invalid.
    #[error(transparent)]
    Pitch(#[from] PitchError),
    /// The designed policy on a design made for no module or another one.
    #[error(
        "the design was made for {}, not for module {module_mm} mm: design with the module (DesignOptions::module_mm), or choose a policy that scales the finished design",
        designed_mm.map_or_else(|| "no module".to_string(), |d| format!("module {d} mm"))
    )]
    NotDesignedForModule {
        /// The module asked for, mm.
        module_mm: f64,
        /// The module the design was made for, mm.
        designed_mm: Option<f64>,
    },
    /// An option is out of range.
    #[error("invalid option `{name}` = {value}: {expected}")]
    InvalidOption {
        /// Name.
        name: &'static str,
        /// Value.
        value: f64,
        /// Expectation.
        expected: &'static str,
    },
}

/// How the tooth count is made an integer (docs/math/teeth.md §12.1).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[non_exhaustive]
pub enum TrainPolicy {
    /// Option 1: scale the centre distance (and `l1`) by `zπm/L`, z by the rounding rule; every tip
    /// point moves radially by `(s − 1)·l1`.
    ScaleCenterDistance(ToothPolicy),
    /// Option 2: keep `a`, rescale the ratio amplitude `i_λ = 1 + λ(i21 − 1)` so that `L(λ) = zπm`
    /// (z the achievable count nearest to `L/(πm)`); needs the designed mechanism
    /// ([`TrainSource::Design`]). The trajectory change is measured by the round trip.
    RatioAmplitude,
    /// Option 3: keep the gears, z = round(L/(πm)) and the module adjusted to `L/(zπ)` (a
    /// non-standard module; the trajectory is unchanged).
    AdjustModule,
    /// The design's own tooth count: a design made for this module
    /// ([`crate::design::DesignOptions::module_mm`]) has pitch perimeters of exactly `zπm`, so
    /// nothing is scaled and the toothed train traces the path the design states. Needs the
    /// design ([`TrainSource::Design`]); a design made for no module or another one is refused.
    Designed,
}

/// Options of [`tooth_train`]; [`TrainTeethOptions::new`] and [`Default`] fill the defaults named
/// on each field.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[non_exhaustive]
pub struct TrainTeethOptions {
    /// How z is made an integer. Default: scale the centre distance up
    /// (`ScaleCenterDistance(ScaleUp)`).
    pub policy: TrainPolicy,
    /// Module, basic rack, backlash of each mesh, chord tolerances and verified carrier positions
    /// per mesh (0 skips the verification). Default [`ToothingOptions::new`] at the module with
    /// 72 verified positions (every 5°): 20° rack (ha* 1, c* 0.25, ρf* 0.38), backlash 0.04·m,
    /// chord 1e-3·m (exports) and 1e-6·m (verification).
    #[serde(flatten)]
    pub toothing: ToothingOptions,
    /// Carrier positions of the round trip of the scaled mechanism. Default 3600.
    pub roundtrip_samples: usize,
    /// Sweep a gear that no cutter fits by its cut neighbours (wire EDM or printing,
    /// [`crate::teeth::conjugate`]). Default false: such a gear is refused, naming its tightest
    /// concave radius (a design within the gear limits never needs it).
    #[serde(default)]
    pub wire_edm: bool,
    /// Accuracy of the perimeter equation `L(λ) = zπm` of [`TrainPolicy::RatioAmplitude`], mm.
    /// Default `None`: 1e-9 of the design's centre distance.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub accuracy_mm: Option<f64>,
}

crate::builder::with_fields!(TrainTeethOptions {
    with_policy => policy: TrainPolicy,
    with_toothing => toothing: ToothingOptions,
    with_roundtrip_samples => roundtrip_samples: usize,
    with_wire_edm => wire_edm: bool,
    with_accuracy_mm => accuracy_mm: Option<f64>,
});

impl TrainTeethOptions {
    /// Defaults at `module_mm`: 20° rack (ha* 1, c* 0.25, ρf* 0.38), scale the centre distance
    /// up, backlash 0.04·m, chord 1e-3·m (exports) and 1e-6·m (verification), 72 verified
    /// positions (every 5°), 3600 round-trip samples.
    #[must_use]
    pub fn new(module_mm: f64) -> Self {
        let mut toothing = ToothingOptions::new(module_mm);
        toothing.verify_steps = 72;
        Self {
            policy: TrainPolicy::ScaleCenterDistance(ToothPolicy::ScaleUp),
            toothing,
            roundtrip_samples: 3600,
            wire_edm: false,
            accuracy_mm: None,
        }
    }
}

impl Default for TrainTeethOptions {
    /// [`TrainTeethOptions::new`] at a module of 2 mm.
    fn default() -> Self {
        Self::new(2.0)
    }
}
