//! The basic rack (docs/math/teeth.md §12.3): pressure angle α, addendum ha*, clearance c*, tip-fillet radius ρf*.
use super::TeethError;
use serde::{Deserialize, Serialize};

/// Basic rack profile, in units of the module (dimensionless factors) and radians.
///
/// Defaults (docs/math/teeth.md §12.3): α = 20°, ha* = 1, c* = 0.25, ρf* = 0.38.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(try_from = "RackFields")]
pub struct RackParams {
    alpha_rad: f64,
    addendum: f64,
    clearance: f64,
    fillet: f64,
}

impl Default for RackParams {
    fn default() -> Self {
        Self {
            alpha_rad: 20f64.to_radians(),
            addendum: 1.0,
            clearance: 0.25,
            fillet: 0.38,
        }
    }
}

/// Smallest non-zero tip fillet radius of the rack, in modules (ρf*).
pub const MIN_FILLET: f64 = 0.01;

/// [`RackParams`] as written, validated by [`RackParams::new`] when read.
#[derive(Deserialize, schemars::JsonSchema)]
struct RackFields {
    alpha_rad: f64,
    addendum: f64,
    clearance: f64,
    fillet: f64,
}

impl TryFrom<RackFields> for RackParams {
    type Error = TeethError;
    fn try_from(f: RackFields) -> Result<Self, TeethError> {
        Self::new(f.alpha_rad, f.addendum, f.clearance, f.fillet)
    }
}

fn check(
    name: &'static str,
    value: f64,
    ok: bool,
    expected: &'static str,
) -> Result<(), TeethError> {
    if ok && value.is_finite() {
        Ok(())
    } else {
        Err(TeethError::InvalidParameter {
            name,
            value,
            expected,
        })
    }
}

/// Smallest rack pressure angle, degrees: below it the undercut limit `2/sin²α` exceeds 66 teeth
/// and the rack cuts the flanks of a usual gear away.
pub const MIN_PRESSURE_ANGLE_DEG: f64 = 10.0;

impl RackParams {
    /// A validated rack. `alpha_rad` ∈ [10°, 45°] (`MIN_PRESSURE_ANGLE_DEG`); `addendum` ha* > 0;
    /// `clearance` c* ≥ 0;
    /// `fillet` ρf* ≥ 0 with the fillet fitting in the dedendum: `ρf*(1 − sin α) < ha* + c*`.
    pub fn new(
        alpha_rad: f64,
        addendum: f64,
        clearance: f64,
        fillet: f64,
    ) -> Result<Self, TeethError> {
        let alpha_deg = alpha_rad.to_degrees();
        check(
            "pressure_angle_deg",
            alpha_deg,
            (MIN_PRESSURE_ANGLE_DEG..=45.0).contains(&alpha_deg),
            "in [10°, 45°]: below 10° a rack undercuts every gear of fewer than 2/sin²α ≈ 66 \
             teeth so deeply that whole flanks vanish (standard racks: 14.5°–25°)",
        )?;
        check(
            "addendum",
            addendum,
            addendum > 0.0 && addendum <= 2.0,
            "ha* in (0, 2]",
        )?;
        check(
            "clearance",
            clearance,
            (0.0..=1.0).contains(&clearance),
            "c* in [0, 1]",
        )?;
        check(
            "fillet",
            fillet,
            // A fillet of a few µm per mm of module only slows the envelope (1e-6 ran for
            // minutes): 0 (a sharp corner) or at least MIN_FILLET.
            (fillet == 0.0 || fillet >= MIN_FILLET)
                && fillet * (1.0 - alpha_rad.sin()) < addendum + clearance
                && fillet <= addendum + clearance,
            "ρf* = 0 (sharp) or in [0.01, ha* + c*], fitting in the dedendum",
        )?;
        Ok(Self {
            alpha_rad,
            addendum,
            clearance,
            fillet,
        })
    }

    /// Pressure angle α, rad.
    #[must_use]
    pub fn alpha_rad(&self) -> f64 {
        self.alpha_rad
    }
    /// Addendum factor ha*.
    #[must_use]
    pub fn addendum(&self) -> f64 {
        self.addendum
    }
    /// Clearance factor c*.
    #[must_use]
    pub fn clearance(&self) -> f64 {
        self.clearance
    }
    /// Tip-fillet radius factor ρf*.
    #[must_use]
    pub fn fillet(&self) -> f64 {
        self.fillet
    }
    /// Depth of the straight flank below the pitch line `h_straight = (ha* + c* − ρf*(1 − sin α))`,
    /// in modules (docs/math/teeth.md §12.3).
    #[must_use]
    pub fn straight_depth(&self) -> f64 {
        self.addendum + self.clearance - self.fillet * (1.0 - self.alpha_rad.sin())
    }
    /// Radius of curvature of the pitch curve needed for no undercut: `h_straight·m / sin²α`, mm
    /// (docs/math/teeth.md §12.4, `ρc·sin²α ≥ ha*·m`; with the default rack `h_straight ≈ ha*`).
    #[must_use]
    pub fn undercut_limit_rho_mm(&self, module_mm: f64) -> f64 {
        self.straight_depth() * module_mm / self.alpha_rad.sin().powi(2)
    }
}
