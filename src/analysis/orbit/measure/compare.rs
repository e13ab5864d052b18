//! Measured-minus-model comparison of two orbits (docs/math/companion.md §A.8 step 7).

use crate::analysis::orbit::{Orbit, wrap_half_pi};

/// Measured-minus-model comparison (docs/math/companion.md §A.8 step 7).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, schemars::JsonSchema)]
pub struct Comparison {
    /// ΔR_L, µm.
    pub d_r_long_um: f64,
    /// ΔR_S, µm.
    pub d_r_short_um: f64,
    /// Δα_L wrapped to (−π/2, π/2], rad; `None` if either orbit is a circle.
    pub d_alpha_long_rad: Option<f64>,
    /// |Z₊,meas − Z₊,model|, µm.
    pub d_z_plus_um: f64,
    /// |Z₋,meas − Z₋,model|, µm.
    pub d_z_minus_um: f64,
}

impl Comparison {
    /// Compares a measured with a model orbit (both carrier frame, same time origin).
    #[must_use]
    pub fn new(measured: &Orbit, model: &Orbit) -> Self {
        let (a, b) = (measured.ellipse(), model.ellipse());
        Self {
            d_r_long_um: a.r_long_um - b.r_long_um,
            d_r_short_um: a.r_short_um - b.r_short_um,
            d_alpha_long_rad: a
                .alpha_long_rad
                .zip(b.alpha_long_rad)
                .map(|(x, y)| wrap_half_pi(x - y)),
            d_z_plus_um: (measured.z_plus_um - model.z_plus_um).norm(),
            d_z_minus_um: (measured.z_minus_um - model.z_minus_um).norm(),
        }
    }
}
