//! Tolerance analysis of the non-circular planetary transplanting mechanism (docs/math/companion.md §C.6):
//! `ncgear tolerance DESIGN.json --errors ERRORS`.
//!
//! One arm (sun 1, intermediate 2, planet 3, needle) of a designed train ([`crate::geometry::assembly`]) is
//! rebuilt with manufacturing and assembly errors and solved **exactly** mesh by mesh
//! ([`model::ExactModel`]); a **linear sensitivity model** ([`model::LinearModel`]) is built from it
//! by central finite differences on a φH grid, validated against the exact model at 3σ and used
//! for a seeded Monte Carlo; the worst contributors are ranked and the free assembly choices
//! (runout orientations) are optimized ([`analyse`]).
//!
//! ## Error inventory (16 coordinates, internal units mm and rad)
//!
//! | coordinates | meaning |
//! |---|---|
//! | `ε_k = e_k·e(γ_k)`, k = sun, intermediate, planet | pitch-curve centre minus rotation centre, in the gear's body frame (the curve is translated) |
//! | `κ_k` | clocking: the pitch curve rotated in its body frame (about the rotation centre) |
//! | `Δr_D, Δt_D, Δr_A, Δt_A` | carrier pin-hole errors of D and A: radial (along OD, OA) and tangential (in the direction of carrier rotation) |
//! | `Δγ` | arm (needle) mounting angle about A |
//! | `j_12, j_23` | normal backlash of the sun–intermediate and intermediate–planet meshes |
//!
//! Angles (γ_k, κ_k, Δγ) count positive in the direction of carrier rotation, so a clockwise design
//! reads its error file exactly as a counter-clockwise one.
//!
//! ## Exact kinematics (flank-line contact model)
//!
//! Pure pitch-curve tangency cannot fix a gear angle: at a vertex of the pitch curve (r′ = 0) the
//! contact normal passes through the driven centre, and for circular gears a rotation does not
//! change the gap at all, so the circular special case (iii) would be undefined. Teeth transmit
//! along the **line of action**. The model, per mesh (driver a with known angle, driven b):
//!
//! 1. the meshing tooth: the driver parameter `v` whose perturbed pitch point `W_a(v)` lies on the
//!    (perturbed) line of centres `C_a C_b` (1-D Newton, so the contact point moves with the
//!    errors); the driven tooth is the nominal tooth correspondence `w = m(v)` (equal arc lengths,
//!    from the design tables: [`crate::geometry::assembly::Rebuilt::ccw_sun_to_intermediate`],
//!    [`crate::geometry::assembly::Rebuilt::ccw_intermediate_to_planet`]);
//! 2. line of action through `W_a`: `N = σ·cos α·t + sin α·n` (t the driver's pitch tangent, n the
//!    normal towards b, α the pressure angle, σ = ±1 the loaded flank);
//! 3. the driven angle θ_b solves the flank condition `(W_b(w; θ_b) − W_a)·N = j/2`: the two flanks,
//!    lines ⟂ N through the two pitch points, coincide up to half the normal backlash j (the driven
//!    gear sits on its loaded flank, the lost motion of a backlash j). With
//!    `W_b = C_b + R(θ_b)p_b` this is `c + |p_b| cos(θ_b + arg p_b − arg N) = 0`, solved in
//!    closed form (the root nearer the driven pitch point facing `C_a`).
//!
//! The idler passes the load on with the opposite flank: σ_23 = −σ_12 = −`load_side`, so both
//! backlashes add up in the planet's lost motion. For zero errors this reproduces the rolling
//! pitch curves exactly (the pitch points coincide on the line of centres); the flank is modelled
//! by its tangent at the pitch point (the neglected flank curvature enters at second order in the
//! µm-sized flank displacement). The first-order result is docs/math/companion.md §C.6's `Δθ_b = (ε·N)/ρ_b` with `ρ_b`
//! the moment arm of N about the driven centre; for circular gears `ρ_b = r·cos α = r_b` and the
//! planet error is the phasor sum of docs/math/companion.md §C.2 (tested).
//!
//! Needle tip: `B = C_A + l3·e(θ3 + γ + Δγ)`. Clocking the intermediate is invisible (an idler has
//! nothing keyed to it; tested); clocking the planet is the same as an arm mounting error of the
//! opposite sign (tested).
//!
//! ## Files
//!
//! `schema` ([`ErrorInventory`]: the error file and its validation), `inventory` ([`Inventory`]:
//! internal units, random draws, moments), `model` ([`ExactModel`], [`LinearModel`]), `analyse`
//! ([`analyse`]: validation, Monte Carlo, the report) with its parts `envelope`, `features`,
//! `ranking` and `best_assembly`, and `report` ([`TransplanterReport`] and its plot geometry).

mod analyse;
mod best_assembly;
mod common;
mod envelope;
mod features;
mod inventory;
mod model;
mod ranking;
mod report;
mod schema;

pub use analyse::analyse;
pub use common::TransplanterOptions;
pub use inventory::{Eccentricity, Inventory, Spread};
pub use model::{ExactModel, FdSteps, LinearModel, TrainState};
pub use report::{
    AssemblyOptimum, Contribution, EnvelopePoint, FeatureDeviations, GreedyChoice,
    TransplanterReport, Validation,
};
pub use schema::{
    AngleError, BacklashErrors, EccentricityError, ErrorInventory, GearErrors, LengthError,
    PinErrors,
};

use crate::analysis::tolerance::ToleranceError;
use crate::config::ConfigError;

/// Number of error coordinates.
pub const N_COORDS: usize = 16;

/// Names (with internal units) of the error coordinates, in order.
pub const COORD_NAMES: [&str; N_COORDS] = [
    "sun eccentricity x (mm, body)",
    "sun eccentricity y (mm, body)",
    "intermediate eccentricity x (mm, body)",
    "intermediate eccentricity y (mm, body)",
    "planet eccentricity x (mm, body)",
    "planet eccentricity y (mm, body)",
    "sun clocking (rad)",
    "intermediate clocking (rad)",
    "planet clocking (rad)",
    "pin D radial (mm)",
    "pin D tangential (mm)",
    "pin A radial (mm)",
    "pin A tangential (mm)",
    "arm mounting angle (rad)",
    "backlash sun-intermediate (mm)",
    "backlash intermediate-planet (mm)",
];

/// Index of the first eccentricity coordinate of gear `k` (0 sun, 1 intermediate, 2 planet).
#[must_use]
pub const fn ecc_index(k: usize) -> usize {
    2 * k
}
/// Index of the clocking coordinate of gear `k`.
#[must_use]
pub const fn clock_index(k: usize) -> usize {
    6 + k
}
/// Pin D radial, tangential.
pub const PIN_D: [usize; 2] = [9, 10];
/// Pin A radial, tangential.
pub const PIN_A: [usize; 2] = [11, 12];
/// Arm mounting angle.
pub const ARM: usize = 13;
/// Backlash of the two meshes.
pub const BACKLASH: [usize; 2] = [14, 15];

/// Gear names, in coordinate order.
pub const GEARS: [&str; 3] = ["sun", "intermediate", "planet"];

/// A vector of error values (mm and rad, see [`COORD_NAMES`]).
pub type ErrorVector = [f64; N_COORDS];

/// Why the transplanter tolerance analysis cannot run.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum TransplanterError {
    /// The error file cannot be read or parsed, or a value is impossible (names the key path).
    #[error(transparent)]
    File(#[from] ToleranceError),
    /// A bad option of the analysis.
    #[error("option `{option}`: {message}")]
    BadOption {
        /// Option.
        option: &'static str,
        /// What is expected.
        message: String,
    },
    /// The perturbed flanks cannot touch (errors far too large for the geometry).
    #[error(
        "{mesh} mesh at carrier angle {carrier_deg:.3}°: the perturbed gears cannot touch (errors too large)"
    )]
    NoContact {
        /// Which mesh.
        mesh: &'static str,
        /// Carrier angle, degrees.
        carrier_deg: f64,
    },
    /// A numerical failure (non-finite result).
    #[error("numerical failure: {0}")]
    Numerical(String),
}

impl From<ConfigError> for TransplanterError {
    fn from(e: ConfigError) -> Self {
        Self::File(e.into())
    }
}
