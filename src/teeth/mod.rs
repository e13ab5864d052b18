//! Involute teeth on non-circular pitch curves, generated as the envelope of a basic rack rolling
//! on the pitch curve, plus tooth count, undercut detection and mesh verification.
//!
//! The mathematics: docs/math/teeth.md §12.1, §12.2, §12.3, §12.4 (tooth count, arc-length
//! frame, rack generation, undercut). Lengths in mm, angles in radians.
//!
//! Public vocabulary:
//! - [`RackParams`]: the basic rack (α, ha*, c*, ρf*), validated.
//! - [`ToothingOptions`]: module, rack, backlash and tolerances shared by toothed designs.
//! - [`tooth_count`] with a [`ToothPolicy`]: integer z and the scale factor applied to the curve.
//! - [`GearBlank`]: what a gear is cut from (pitch curve by arc length, rack, z, module, options).
//! - [`generate`] with a [`Generation`]: one simple closed CCW outline (mm, body frame) per gear
//!   and its process — the rack on convex curves, a shaper cutter (the largest that fits, or a
//!   given one) on curves with concave stretches, a gear cut again as it was cut (with a tip
//!   relief), or swept by its mates.
//! - [`undercut_report`]: per-tooth undercut / concavity diagnostics.
//! - [`mesh::verify_mesh`]: roll two outlines through a cycle (interference, backlash,
//!   transmission error).

mod blank;
mod cells;
pub mod conjugate;
mod crossing;
mod frame;
mod generate;
mod inside;
pub mod mate_motion;
pub mod mesh;
mod options;
pub mod overlap;
pub mod process;
mod rack;
pub mod secondary;
mod shape;
mod shaper;
pub mod tip_relief;
mod undercut;

pub use blank::GearBlank;
pub use frame::ArcFrame;
pub use generate::{Generated, Generation, generate};
pub mod outline;
pub use blank::OutlineOptions;
pub use options::ToothingOptions;
pub use outline::Outline;
pub use rack::RackParams;

use crate::geometry::pitch::PitchCurve;
use serde::{Deserialize, Serialize};

/// Errors of tooth generation.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum TeethError {
    /// A size of the work outside its admissible range ([`crate::bounds`]).
    #[error(transparent)]
    Bounds(#[from] crate::bounds::OutOfBounds),
    /// A parameter is out of range.
    #[error("invalid parameter `{name}` = {value}: {expected}")]
    InvalidParameter {
        /// Parameter name.
        name: &'static str,
        /// Given value.
        value: f64,
        /// What is expected.
        expected: &'static str,
    },
    /// The pitch curve is concave somewhere: a rack cannot cut a concave arc (docs/math/teeth.md §12.4).
    #[error(
        "pitch curve is concave near tooth {tooth} (min signed radius of curvature {min_rho_mm:.4} mm): \
         a rack cannot cut a concave arc: generate it with a shaper cutter (teeth::process)"
    )]
    Concave {
        /// First tooth index on a concave stretch.
        tooth: usize,
        /// Most negative radius of curvature, mm.
        min_rho_mm: f64,
    },
    /// Undercut on at least one tooth (docs/math/teeth.md §12.4: no undercut iff ρc·sin²α ≥ h·m).
    #[error(
        "undercut on {count} tooth flank(s) (worst: tooth {worst_tooth}, {depth_mm:.4} mm deep); \
         at this pitch-curve size the largest module without undercut is {max_module_mm:.4} mm; \
         at this module use at least {min_teeth} teeth"
    )]
    Undercut {
        /// Number of undercut flanks.
        count: usize,
        /// Tooth with the deepest undercut.
        worst_tooth: usize,
        /// Depth of the undercut below the cusp, mm.
        depth_mm: f64,
        /// Largest module without undercut at this pitch-curve curvature, mm.
        max_module_mm: f64,
        /// Smallest tooth count without undercut at this module (curve rescaled to `zπm`).
        min_teeth: u32,
    },
    /// Not enough tooth-space width for the rack tip (rack tip flat would be negative).
    #[error("rack tooth tip has no flat ({flat_mm:.4} mm): reduce ρf* or the backlash")]
    NoRackTipFlat {
        /// Width of the rack tip flat, mm (negative).
        flat_mm: f64,
    },
    /// A shaper cutter cannot cut this gear.
    #[error("shaper cutter with {cutter_teeth} teeth: {what}")]
    Shaper {
        /// Cutter tooth count z_c.
        cutter_teeth: u32,
        /// What fails.
        what: &'static str,
    },
    /// The shaper-cut flanks have an envelope cusp (undercut).
    #[error(
        "shaper cutter with {cutter_teeth} teeth undercuts {count} flank(s): use a larger \
         cutter (--cutter-teeth) or a smaller module"
    )]
    ShaperUndercut {
        /// Cutter tooth count z_c.
        cutter_teeth: u32,
        /// Undercut flanks.
        count: usize,
    },
    /// The shaper cutter's other teeth cut into the gear while it rolls (secondary cutting,
    /// [`secondary`]).
    #[error(
        "shaper cutter with {cutter_teeth} teeth cuts into the gear with its other teeth while it \
         rolls (secondary cutting at least {depth_mm:.4} mm deep, where a concave stretch nearly \
         matches its pitch radius): use a smaller cutter (--cutter-teeth) or a smaller module"
    )]
    SecondaryCut {
        /// Cutter tooth count z_c.
        cutter_teeth: u32,
        /// Deepest cut into the generated outline, mm (a lower bound beyond 0.05·m).
        depth_mm: f64,
    },
    /// The curve is concave and no shaper cutter fits. A pair whose mate is cut makes
    /// this gear by wire EDM or printing instead ([`conjugate`]); alone, or with a mate that
    /// needs the same, it is an error.
    #[error(
        "pitch curve is concave (tightest concave radius of curvature {min_concave_rho_mm:.4} mm) \
         and no shaper cutter fits ({tried}); without a cutter the gear is swept by its mate (wire \
         EDM or printing), which needs a mate that a rack or shaper can cut: use a smaller module \
         or a smoother pitch curve"
    )]
    NoCutter {
        /// Smallest |ρ| of the concave stretches, mm.
        min_concave_rho_mm: f64,
        /// The cutters tried and why each failed.
        tried: String,
    },
    /// A gear made without a cutter (wire EDM, printing) cannot be swept by its mate.
    #[error("wire EDM / printing outline swept by the mate: {what}")]
    Swept {
        /// What fails.
        what: String,
    },
    /// A trimming step failed (flank did not meet the addendum curve).
    #[error("could not trim tooth {tooth}: {what}")]
    Trim {
        /// Tooth index.
        tooth: usize,
        /// What failed.
        what: &'static str,
    },
}

/// How the tooth count is made an integer (docs/math/teeth.md §12.1, option 1: scale the centre distance).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[non_exhaustive]
pub enum ToothPolicy {
    /// `z = ⌈L/(πm)⌉`, curve scaled up (never increases undercut risk).
    ScaleUp,
    /// `z = round(L/(πm))`.
    Nearest,
    /// `z = ⌊L/(πm)⌋`, curve scaled down.
    ScaleDown,
    /// A given z (the curve is scaled to fit exactly).
    Exact(u32),
}

/// Result of [`tooth_count`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, schemars::JsonSchema)]
pub struct ToothCount {
    /// Integer tooth count.
    pub z: u32,
    /// Perimeter of the given curve, mm.
    pub perimeter_mm: f64,
    /// Non-integer tooth count `L/(πm)` before scaling.
    pub z_raw: f64,
    /// Scale factor `zπm/L` to apply to the curve (and to the centre distance and l1).
    pub scale: f64,
}

/// Tooth count of a pitch curve at `module_mm`: `L = z·π·m` (docs/math/teeth.md §12.1).
///
/// `accuracy_mm` is the perimeter accuracy. Errors if the module is not positive/finite or z < 3.
///
/// ```
/// use ncgear::geometry::pitch::PitchCurve;
/// use ncgear::teeth::{ToothPolicy, tooth_count};
/// // A circle of radius 22.5 mm at m = 2: L/(πm) = 22.5, scaled up to z = 23.
/// let circle = PitchCurve::from_uniform_radii(vec![22.5; 256]).unwrap();
/// let t = tooth_count(&circle, 2.0, ToothPolicy::ScaleUp, 1e-9).unwrap();
/// assert_eq!(t.z, 23);
/// assert!((t.z_raw - 22.5).abs() < 1e-9);
/// assert!((t.scale - 23.0 / 22.5).abs() < 1e-9);
/// assert!(tooth_count(&circle, 0.0, ToothPolicy::ScaleUp, 1e-9).is_err());
/// ```
pub fn tooth_count(
    curve: &PitchCurve,
    module_mm: f64,
    policy: ToothPolicy,
    accuracy_mm: f64,
) -> Result<ToothCount, TeethError> {
    if !(module_mm.is_finite() && module_mm > 0.0) {
        return Err(TeethError::InvalidParameter {
            name: "module_mm",
            value: module_mm,
            expected: "finite and > 0",
        });
    }
    let l = curve.perimeter_mm(accuracy_mm);
    let z_raw = l / (std::f64::consts::PI * module_mm);
    let z = match policy {
        ToothPolicy::ScaleUp => z_raw.ceil(),
        ToothPolicy::Nearest => z_raw.round(),
        ToothPolicy::ScaleDown => z_raw.floor(),
        ToothPolicy::Exact(z) => f64::from(z),
    };
    if !(3.0..=1.0e5).contains(&z) {
        return Err(TeethError::InvalidParameter {
            name: "z",
            value: z,
            expected: "a tooth count between 3 and 100000",
        });
    }
    Ok(ToothCount {
        z: z as u32,
        perimeter_mm: l,
        z_raw,
        scale: z / z_raw,
    })
}

/// Scales a pitch curve by `factor` (all radii), e.g. with [`ToothCount::scale`].
pub fn scale_curve(
    curve: &PitchCurve,
    factor: f64,
) -> Result<PitchCurve, crate::geometry::pitch::PitchError> {
    PitchCurve::from_uniform_radii(curve.radii_mm().iter().map(|r| r * factor).collect())
}

/// Undercut / concavity diagnostics of one tooth flank (docs/math/teeth.md §12.4).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, schemars::JsonSchema)]
pub struct FlankUndercut {
    /// Tooth index (tooth k is centred at `s_k = s0 + k·p`).
    pub tooth: usize,
    /// `"left"` (smaller arc length) or `"right"` flank.
    pub side: &'static str,
    /// Arc-length position of the flank's pitch point, mm.
    pub s_mm: f64,
    /// Minimum signed radius of curvature of the pitch curve over the generating range, mm.
    pub min_rho_mm: f64,
    /// Depth of the envelope cusp below the pitch curve `ρc·sin²α`, mm (∞ if concave-free & flat).
    pub cusp_depth_mm: f64,
    /// Depth generated by the straight rack flank `h_straight`, mm.
    pub flank_depth_mm: f64,
    /// Whether the envelope has a cusp within the straight-flank range (numerical sign test).
    pub undercut: bool,
    /// Undercut depth `max(0, h_straight − ρc·sin²α)`, mm.
    pub undercut_mm: f64,
    /// Whether the generating stretch is concave (κ < 0).
    pub concave: bool,
    /// Depth below the pitch curve where the generated flank ends, mm: `h_straight` without
    /// undercut; with undercut, the depth at which the rack tip's fillet trochoid cuts the flank
    /// (the real form point).
    pub form_depth_mm: f64,
    /// Loss of contact ratio against the basic rack: the flank's path of contact on the rack's
    /// line of action shortened by `(h_straight − form_depth)/sin α`, over the base pitch
    /// `πm·cos α`: `(h_straight − form_depth)/(πm·sin α·cos α)` (0 without undercut).
    pub contact_ratio_loss: f64,
    /// Tooth thickness at the root: the chord between the two flanks' form points of this
    /// tooth, mm (known once the outline is generated).
    pub root_thickness_mm: Option<f64>,
}

/// Per-tooth undercut report.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct UndercutReport {
    /// One entry per flank (2 per tooth).
    pub flanks: Vec<FlankUndercut>,
    /// Minimum radius of curvature of the pitch curve over all generating ranges, mm.
    pub min_rho_mm: f64,
    /// Required radius of curvature for no undercut, `h_straight / sin²α`, mm.
    pub required_rho_mm: f64,
    /// Largest module without undercut: `m·ρmin/required_rho`, mm.
    pub max_module_mm: f64,
    /// Number of undercut flanks.
    pub undercut_count: usize,
    /// Number of flanks on a concave stretch.
    pub concave_count: usize,
    /// Largest undercut depth over the flanks, mm (0: no undercut).
    #[serde(default)]
    pub max_undercut_mm: f64,
    /// Largest loss of contact ratio over the flanks ([`FlankUndercut::contact_ratio_loss`]).
    #[serde(default)]
    pub max_contact_ratio_loss: f64,
    /// Thinnest tooth root over the teeth, mm ([`FlankUndercut::root_thickness_mm`]).
    #[serde(default)]
    pub min_root_thickness_mm: Option<f64>,
}

impl UndercutReport {
    /// Recomputes the counts and extremes from the flanks (all but the rack's `required_rho_mm`
    /// and `max_module_mm`, which come from the whole curve).
    pub(crate) fn summarize(&mut self) {
        let f = &self.flanks;
        self.min_rho_mm = f.iter().map(|f| f.min_rho_mm).fold(f64::INFINITY, f64::min);
        self.undercut_count = f.iter().filter(|f| f.undercut).count();
        self.concave_count = f.iter().filter(|f| f.concave).count();
        self.max_undercut_mm = f.iter().map(|f| f.undercut_mm).fold(0.0, f64::max);
        self.max_contact_ratio_loss = f.iter().map(|f| f.contact_ratio_loss).fold(0.0, f64::max);
        self.min_root_thickness_mm = f
            .iter()
            .filter_map(|f| f.root_thickness_mm)
            .reduce(f64::min);
    }
}

pub use undercut::undercut_report;

/// [`FlankUndercut`] as written (its `side` owned), checked when read.
#[derive(Deserialize)]
struct FlankFields {
    tooth: usize,
    side: String,
    s_mm: f64,
    min_rho_mm: f64,
    cusp_depth_mm: f64,
    flank_depth_mm: f64,
    undercut: bool,
    undercut_mm: f64,
    concave: bool,
    #[serde(default)]
    form_depth_mm: f64,
    #[serde(default)]
    contact_ratio_loss: f64,
    #[serde(default)]
    root_thickness_mm: Option<f64>,
}

impl<'de> Deserialize<'de> for FlankUndercut {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        FlankFields::deserialize(d)?
            .try_into()
            .map_err(serde::de::Error::custom)
    }
}

impl TryFrom<FlankFields> for FlankUndercut {
    type Error = String;
    fn try_from(f: FlankFields) -> Result<Self, String> {
        let side = match f.side.as_str() {
            "left" => "left",
            "right" => "right",
            other => return Err(format!("flank side `{other}`: expected `left` or `right`")),
        };
        Ok(Self {
            tooth: f.tooth,
            side,
            s_mm: f.s_mm,
            min_rho_mm: f.min_rho_mm,
            cusp_depth_mm: f.cusp_depth_mm,
            flank_depth_mm: f.flank_depth_mm,
            undercut: f.undercut,
            undercut_mm: f.undercut_mm,
            concave: f.concave,
            form_depth_mm: f.form_depth_mm,
            contact_ratio_loss: f.contact_ratio_loss,
            root_thickness_mm: f.root_thickness_mm,
        })
    }
}
