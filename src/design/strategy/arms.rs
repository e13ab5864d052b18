//! Trains on step 1's arms (`ArmTrains`): the mechanism a ratio and a sun phase make, its needle angle fitted.

use crate::design::inverse::Inversion;
use crate::design::options::DesignOptions;
use crate::geometry::fourier::SunRatio;
use crate::geometry::limits::GearLimits;
use crate::geometry::mechanism::Mechanism;

/// ArmTrains built on step 1's arms: a ratio and a sun phase give a mechanism whose needle angle γ
/// is fitted to the needle law, and its synchronous deviation (mm).
pub(in crate::design) struct ArmTrains<'a> {
    pub inv: &'a Inversion,
    pub opts: &'a DesignOptions,
    pub limits: GearLimits,
}

impl ArmTrains<'_> {
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
