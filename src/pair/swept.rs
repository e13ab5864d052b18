//! The mate positions that sweep a gear no cutter can make (issue 18, [`crate::teeth::conjugate`]):
//! the cut gear of the pair rolled through one whole mesh cycle in the swept gear's body frame,
//! once at the law's position (the working flanks, exactly conjugate) and once turned by the
//! backlash towards its coast side (the coast flanks, so that the mesh keeps its backlash).
use crate::geometry::pitch::PitchCurve;
use crate::teeth::conjugate::MatePose;
use std::f64::consts::TAU;

/// Flank allowance of the swept gear, in modules: the mate is swept turned by this much (as arc
/// at the contact) into each flank, so that the scallops between two positions and the rays'
/// chords stay inside the material the mate leaves free. It shows in the mesh as a constant
/// offset of the driven angle, `FLANK_MARGIN·m/r₂` at most.
const FLANK_MARGIN: f64 = 1e-4;

/// Whole-outline mate positions per driver tooth pitch (the tip region gets 8× as many): the
/// flank scallops between two of them stay below the flank allowance — measured on a 24-tooth
/// pair forced to wire EDM, the transmission error falls to the allowance's 4.8e-4° at 96 (1.9e-3°
/// at 48).
const POSES_PER_PITCH: usize = 96;

/// The closed pair's motion over its cycle: the law ψ(φ) (rad, the driven gear's body angle
/// `π + ψ` faces the driver), the centre distance and the driver turns of a cycle.
#[derive(Clone, Copy)]
pub(super) struct PairMotion<'a> {
    /// ψ(φ), rad.
    pub(super) psi: &'a (dyn Fn(f64) -> f64 + Sync),
    /// Centre distance, mm.
    pub(super) a_mm: f64,
    /// Driver turns after which the pair is back at its start.
    pub(super) q_turns: u32,
    /// Circumferential backlash of the mesh, mm.
    pub(super) backlash_mm: f64,
}

/// Whole-outline mate positions per driver tooth pitch over the cycle ([`mate_pose`]).
pub(super) fn positions(motion: &PairMotion<'_>, z_driver: u32) -> usize {
    z_driver as usize * motion.q_turns as usize * POSES_PER_PITCH
}

/// The cut mate in the body frame of the swept gear `swept` (0: driver, 1: driven) at cycle
/// fraction `u` (driver angle φ = 2πq·u), at offset `set` 0 — the law's driven offset less the
/// flank allowance, δ = −ε/r₂ — or 1 — δ = (j + ε)/r₂, the driven offset of the mesh check at
/// which the coast flanks touch (r₂ the driven gear's pitch radius at the contact, `a − r₁(−φ)`).
///
/// Body → world maps, as in the mesh check: driver `x ↦ R(φ)x`, driven `x ↦ R(−(ψ+δ))x + (a, 0)`.
pub(super) fn mate_pose(
    motion: &PairMotion<'_>,
    driver_pitch: &PitchCurve,
    module_mm: f64,
    swept: usize,
    u: f64,
    set: usize,
) -> MatePose {
    let a = motion.a_mm;
    let phi = TAU * f64::from(motion.q_turns) * u;
    let r2 = a - driver_pitch.radius_mm(-phi);
    let margin = FLANK_MARGIN * module_mm;
    let delta = if set == 0 {
        -margin / r2
    } else {
        (motion.backlash_mm + margin) / r2
    };
    let ang2 = (motion.psi)(phi) + delta;
    if swept == 0 {
        // Driven body → driver body: R(−φ)(R(−ang2)x + (a, 0)).
        MatePose {
            angle_rad: -phi - ang2,
            shift_mm: [a * phi.cos(), -a * phi.sin()],
        }
    } else {
        // Driver body → driven body: R(ang2)(R(φ)x − (a, 0)).
        MatePose {
            angle_rad: phi + ang2,
            shift_mm: [-a * ang2.cos(), -a * ang2.sin()],
        }
    }
}
