//! Where the mate of a swept gear is ([`super::conjugate`]): a mesh's law rolled
//! through one whole cycle in the swept gear's body frame, once at the law's position less a
//! flank allowance (the working flanks) and once turned by the backlash towards its coast side
//! (the coast flanks, so that the mesh keeps its backlash).
use super::conjugate::MatePose;
use crate::geometry::pitch::PitchCurve;
use crate::math::Point;
use std::f64::consts::PI;

/// Flank allowance of a swept gear, in modules: the mate is swept turned by this much (as arc at
/// the contact) into each flank, so that the scallops between two positions and the rays' chords
/// stay inside the material the mate leaves free. It shows in the mesh as an offset of the driven
/// angle of at most `FLANK_MARGIN·m/r₂`.
pub const FLANK_MARGIN: f64 = 1e-4;

/// Whole-outline mate positions per tooth pitch (the mate's tip region gets 8× as many): the
/// flank scallops between two of them stay below the flank allowance — measured on a 24-tooth
/// pair forced to wire EDM, the transmission error falls to the allowance's 4.8e-4° at 96 (1.9e-3°
/// at 48).
pub const POSITIONS_PER_PITCH: usize = 96;

/// One mesh over its cycle, in the mesh check's convention (driver body → world `x ↦ R(φ)x`,
/// driven `x ↦ R(−(ψ + δ))x + (a, 0)`, its body angle `π + ψ` facing the driver).
#[derive(Clone, Copy)]
pub struct MeshMotion<'a> {
    /// Cycle fraction `u ∈ [0, 1)` ↦ (driver angle φ, law ψ(φ)), rad.
    pub at: &'a (dyn Fn(f64) -> (f64, f64) + Sync),
    /// Centre distance, mm.
    pub a_mm: f64,
    /// Circumferential backlash of the mesh, mm.
    pub backlash_mm: f64,
    /// The driver's pitch curve: the driven pitch radius at the contact is `a − r₁(−φ)`.
    pub driver_pitch: &'a PitchCurve,
    /// Module, mm.
    pub module_mm: f64,
}

impl MeshMotion<'_> {
    /// The mate in the body frame of the swept gear `swept` (0: the driver, swept by the driven
    /// gear; 1: the driven gear, swept by the driver) at cycle fraction `u`, at offset `set` 0 —
    /// the law's driven offset less the flank allowance, δ = −ε/r₂ — or 1 — δ = (j + ε)/r₂, the
    /// driven offset of the mesh check at which the coast flanks touch (r₂ = `a − r₁(−φ)`).
    #[must_use]
    pub fn mate_pose(&self, swept: usize, u: f64, set: usize) -> MatePose {
        let (phi, _) = (self.at)(u);
        let r2 = self.a_mm - self.driver_pitch.radius_mm(-phi);
        let margin = FLANK_MARGIN * self.module_mm;
        let delta = if set == 0 {
            -margin / r2
        } else {
            (self.backlash_mm + margin) / r2
        };
        self.pose_at(swept, u, delta)
    }

    /// The mate in the body frame of gear `gear` (0: the driver, 1: the driven gear) at cycle
    /// fraction `u`, at the law's position (driven offset δ = 0, where the working flanks touch).
    #[must_use]
    pub fn law_pose(&self, gear: usize, u: f64) -> MatePose {
        self.pose_at(gear, u, 0.0)
    }

    /// Body angle of gear `gear` (0: driver, 1: driven) at which it touches the mate on the line
    /// of centres at cycle fraction `u`, rad: `−φ` for the driver, `π + ψ` for the driven gear.
    #[must_use]
    pub fn contact_angle_rad(&self, gear: usize, u: f64) -> f64 {
        let (phi, psi) = (self.at)(u);
        if gear == 0 { -phi } else { PI + psi }
    }

    /// The mate in gear `gear`'s body frame at cycle fraction `u` with the driven gear turned by
    /// `delta` rad beyond the law.
    fn pose_at(&self, gear: usize, u: f64, delta: f64) -> MatePose {
        let a = self.a_mm;
        let (phi, psi) = (self.at)(u);
        let ang2 = psi + delta;
        if gear == 0 {
            // Driven body → driver body: R(−φ)(R(−ang2)x + (a, 0)).
            MatePose {
                angle_rad: -phi - ang2,
                shift_mm: Point::new(a * phi.cos(), -a * phi.sin()),
            }
        } else {
            // Driver body → driven body: R(ang2)(R(φ)x − (a, 0)).
            MatePose {
                angle_rad: phi + ang2,
                shift_mm: Point::new(-a * ang2.cos(), -a * ang2.sin()),
            }
        }
    }
}
