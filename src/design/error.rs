//! Why the design chain stopped.

use crate::design::hypothesis::segmented::SegmentedError;
use crate::design::inverse::InverseError;
use crate::geometry::fourier::RatioError;
use crate::geometry::pitch::PitchError;

/// Why the chain stopped. Targets the train cannot trace exactly are *not* errors: they are
/// reported (compatibility residual, achieved deviation).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum DesignError {
    /// A size of the work outside its admissible range ([`crate::bounds`]).
    #[error(transparent)]
    Bounds(#[from] crate::bounds::OutOfBounds),
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
        "the sun ratio i21 would span [{min:.3}, {max:.3}], outside the admissible bounds [{lo}, {hi}] (docs/math/chain.md §14); with the refinement off nothing brings it back inside: let the fit to the points run (refine auto or on), which keeps every design within the bounds"
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
    /// The module leaves too few teeth on the pitch curves.
    #[error(
        "module {module_mm} mm leaves {:.1} teeth on pitch curves of perimeter {perimeter_mm:.2} mm; at least {min_teeth} are needed: choose a module of at most {:.3} mm",
        perimeter_mm / (std::f64::consts::PI * module_mm),
        perimeter_mm / (std::f64::consts::PI * f64::from(*min_teeth))
    )]
    ModuleTooLarge {
        /// Module, mm.
        module_mm: f64,
        /// Perimeter of the free design's pitch curves, mm.
        perimeter_mm: f64,
        /// Fewest teeth admitted.
        min_teeth: u32,
    },
    /// The convex-radius limit is beyond the flattest convex arc any train tracing the target
    /// can have ([`crate::geometry::limits::GearLimits::flattest_convex_radius_mm`]).
    #[error(
        "{} cannot be met: a train tracing this target turns its gears at a centre distance of at most {a_max_mm:.1} mm (from the arm l1, the intermediate axis at most 30° off the carrier line), where no pitch curve within the ratio bounds and the pressure-angle limit has a convex arc flatter than {flattest_mm:.1} mm (docs/limits.md); {}",
        match module_mm {
            Some(m) => format!("the undercut limit of module {m} mm (convex arcs of at least 7·m = {limit_mm} mm)"),
            None => format!("option `min_convex_radius_mm` = {limit_mm} mm"),
        },
        match module_mm {
            Some(_) => format!("choose a module of at most {:.3} mm", flattest_mm / crate::design::UNDERCUT_RADIUS_MODULES),
            None => format!("a limit above {flattest_mm:.1} mm leaves no design"),
        }
    )]
    ConvexLimitUnreachable {
        /// The convex-radius limit in force, mm.
        limit_mm: f64,
        /// The module it follows from (7·m), when not given itself.
        module_mm: Option<f64>,
        /// The flattest convex arc reachable, mm.
        flattest_mm: f64,
        /// The largest centre distance of a train tracing the target, mm.
        a_max_mm: f64,
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
