//! The toothing options shared by every toothed design (the pair and the planetary train):
//! module, basic rack, backlash, export and verification tolerances.
use super::RackParams;
use serde::{Deserialize, Serialize};

/// How the teeth of a toothed design are cut, exported and verified; embedded in
/// [`crate::pair::PairOptions`] and [`crate::design::train::TrainTeethOptions`].
///
/// The length defaults scale with the module: [`ToothingOptions::new`] gives them at any module,
/// [`Default`] at 1 mm.
///
/// ```
/// use ncgear::teeth::ToothingOptions;
/// let t = ToothingOptions::new(2.0);
/// assert_eq!(t.backlash_mm, 0.08);
/// assert_eq!(t.chord_tol_mm, 2e-3);
/// assert_eq!(t.verify_steps, 90);
/// assert_eq!(t.cutter_teeth, None);
/// assert_eq!(ToothingOptions::default(), ToothingOptions::new(1.0));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[non_exhaustive]
pub struct ToothingOptions {
    /// Module, mm. Default 1.
    pub module_mm: f64,
    /// Basic rack (α, ha*, c*, ρf*). Default [`RackParams::default`]: 20°, 1, 0.25, 0.38.
    pub rack: RackParams,
    /// Circumferential backlash of each mesh on the pitch curve, mm: each gear's coast flank is
    /// thinned by half of it, the working flanks stay exactly conjugate. Default 0.04·m.
    pub backlash_mm: f64,
    /// Chord tolerance of the exported outlines, mm. Default 1e-3·m.
    pub chord_tol_mm: f64,
    /// Chord tolerance of the outlines used by the mesh verification, mm. Default 1e-6·m.
    pub verify_chord_tol_mm: f64,
    /// Driver (or carrier) positions of the mesh verification over one turn, per mesh; 0 skips
    /// it. Default 90 (every 4°); [`crate::design::train::TrainTeethOptions::new`] uses 72.
    pub verify_steps: usize,
    /// Tooth count of the shaper cutter for gears with concave pitch-curve stretches; `None`
    /// (default) tries [`crate::teeth::process::STANDARD_CUTTER_TEETH`] largest first. Convex
    /// gears are rack-generated either way.
    #[serde(default)]
    pub cutter_teeth: Option<u32>,
    /// Refuse undercut (the strict `--no-undercut`: a typed error naming the largest module
    /// that works) instead of cutting it. Default `false`: an undercut flank is cut as the rack
    /// cuts it and reported (depth, form depth, loss of contact ratio, root thickness).
    #[serde(default)]
    pub refuse_undercut: bool,
}

crate::builder::with_fields!(ToothingOptions {
    with_module_mm => module_mm: f64,
    with_rack => rack: RackParams,
    with_backlash_mm => backlash_mm: f64,
    with_chord_tol_mm => chord_tol_mm: f64,
    with_verify_chord_tol_mm => verify_chord_tol_mm: f64,
    with_verify_steps => verify_steps: usize,
    with_cutter_teeth => cutter_teeth: Option<u32>,
    with_refuse_undercut => refuse_undercut: bool,
});

impl ToothingOptions {
    /// The defaults (see each field) at `module_mm`.
    #[must_use]
    pub fn new(module_mm: f64) -> Self {
        Self {
            module_mm,
            rack: RackParams::default(),
            backlash_mm: 0.04 * module_mm,
            chord_tol_mm: 1e-3 * module_mm,
            verify_chord_tol_mm: 1e-6 * module_mm,
            verify_steps: 90,
            cutter_teeth: None,
            refuse_undercut: false,
        }
    }
}

impl ToothingOptions {
    /// Checks every field before any work: the module finite and > 0, the backlash finite and
    /// > 0, the export chord tolerance and the verification steps within [`crate::bounds`].
    ///
    /// # Errors
    /// [`super::TeethError::InvalidParameter`] or [`super::TeethError::Bounds`], naming the field.
    pub fn validate(&self) -> Result<(), super::TeethError> {
        let m = self.module_mm;
        for (name, value) in [("module_mm", m), ("backlash_mm", self.backlash_mm)] {
            if !(value.is_finite() && value > 0.0) {
                return Err(super::TeethError::InvalidParameter {
                    name,
                    value,
                    expected: "finite and > 0 mm",
                });
            }
        }
        crate::bounds::check_chord_tol("chord_tol_mm", self.chord_tol_mm, m)?;
        crate::bounds::check_verify_steps("verify_steps", self.verify_steps)?;
        if let Some(z) = self.cutter_teeth {
            crate::bounds::check_teeth("cutter_teeth", z)?;
        }
        Ok(())
    }
}

impl Default for ToothingOptions {
    /// [`ToothingOptions::new`] at a module of 1 mm.
    fn default() -> Self {
        Self::new(1.0)
    }
}

impl ToothingOptions {
    /// The cutter choice of [`Self::cutter_teeth`].
    #[must_use]
    pub fn cutter_choice(&self) -> crate::teeth::process::CutterChoice {
        self.cutter_teeth
            .map_or(crate::teeth::process::CutterChoice::Auto, |z| {
                crate::teeth::process::CutterChoice::Teeth(z)
            })
    }
}
