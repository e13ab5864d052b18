//! Trains on step 1's arms: the mechanism a ratio and a sun phase make, its needle angle fitted.

use super::inverse::Inversion;
use super::options::DesignOptions;
use crate::geometry::fourier::SunRatio;
use crate::geometry::limits::GearLimits;
use crate::geometry::mechanism::Mechanism;

/// Trains built on step 1's arms: a ratio and a sun phase give a mechanism whose needle angle γ
/// is fitted to the needle law, and its synchronous deviation (mm).
pub(super) struct Trains<'a> {
    pub inv: &'a Inversion,
    pub opts: &'a DesignOptions,
    pub limits: GearLimits,
}

impl Trains<'_> {
    /// The train of `ratio` (made to satisfy the gear limits first) and sun phase `tau_s`.
    pub fn build(&self, ratio: SunRatio, tau_s: f64) -> (Mechanism, f64) {
        let inv = self.inv;
        let samples = self.opts.check_samples;
        let a_mm = 0.5 * inv.l1_mm;
        let mut m = Mechanism {
            a_mm,
            l3_mm: inv.l3_mm,
            ratio: self.limits.project(&ratio, a_mm),
            sun_phase_rad: inv.phi_h0_rad + tau_s,
            needle_angle_rad: 0.0,
            idler_offset_rad: 0.0,
        };
        let dev = m.fit_needle_angle(samples, |p| inv.beta(p));
        (m, dev)
    }
}
