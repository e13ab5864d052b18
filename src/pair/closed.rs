//! The closed pair: the driven gear's turns per driver turn as a fraction p/q, the tooth counts
//! that make both gears whole, pitch curves scaled so that `L = zπm`, and the mesh
//! verification over the q driver turns of a cycle.
use super::design::{Cycle, PairDesign, PairOptions, PendingMesh, Toothed};
use super::{Law, Motion, PairError};
use crate::math::periodic::uniform_angles;
use crate::teeth::mate_motion::{MeshMotion, POSITIONS_PER_PITCH};
use crate::teeth::mesh::{MeshCheck, MeshSpan};
use std::f64::consts::{PI, TAU};

/// Largest change of ψ(φ) − kφ over the driven gear's period (rad) accepted as closing it: the
/// spline of the law reproduces a periodic excess to ≈ 1e-12 rad, a non-closing law misses by
/// its own amplitude.
const DRIVEN_CLOSURE_TOL_RAD: f64 = 1e-8;

/// The closed pair (module doc of [`super::entry`]): pitch curves scaled so that `L = zπm`,
/// outlines with the mating phase, the mesh verification over the q driver turns of a cycle.
pub(super) fn design_closed(
    law: &Law,
    opts: &PairOptions,
) -> Result<(PairDesign, Option<PendingMesh>), PairError> {
    let t = &opts.toothing;
    let m = t.module_mm;
    let motion = Motion::from_law_advancing(law, opts.samples, opts.centrode_advance_rad)?;
    let (p_turns, q_turns) = closing_turns(&motion, opts.samples)?;
    let a1 = motion.unit_center_distance;
    let (unit1, unit2) = motion.unit_pitch_radii(opts.samples);
    let (c1, _) = Motion::curves_at(&unit1, &unit2, a1)?;
    let l1 = c1.perimeter_mm(1e-12 * a1);
    let (z, z2) = closed_teeth(law, opts, l1, (p_turns, q_turns))?;
    let a = a1 * f64::from(z) * PI * m / l1;
    let (c1, c2) = Motion::curves_at(&unit1, &unit2, a)?;
    let span = TAU * f64::from(q_turns);
    let at = |u: f64| (span * u, motion.psi(span * u));
    let mesh_motion = MeshMotion {
        at: &at,
        a_mm: a,
        backlash_mm: t.backlash_mm,
        driver_pitch: &c1,
        module_mm: m,
    };
    let cycle = Cycle {
        motion: &mesh_motion,
        positions: z as usize * q_turns as usize * POSITIONS_PER_PITCH,
    };
    let mut g = Toothed::new(
        (c1.clone(), c2),
        motion.psi(0.0),
        [z, z2],
        None,
        Some(&cycle),
        opts,
    )?;
    // The fine outlines: for the mesh check, and for the tip relief of shaper-cut gears.
    let fine = if t.verify_steps > 0 || g.has_shaper() {
        let mut fine = g.fine_outlines(opts, Some(&cycle))?;
        g.relieve(opts, &mesh_motion, &mut fine, (z * q_turns) as usize)?;
        Some(fine)
    } else {
        None
    };
    let mesh = match fine {
        Some(fine) if t.verify_steps > 0 => {
            // The pair is back at its start after q driver turns: check them all,
            // `verify_steps` positions per driver turn.
            let check = MeshCheck {
                steps: t.verify_steps * q_turns as usize,
                span: MeshSpan::Turns(q_turns),
                backlash_mm: t.backlash_mm,
                ..MeshCheck::new(a, m)
            };
            Some((fine, check))
        }
        _ => None,
    };
    let ratios: Vec<f64> = uniform_angles(opts.samples)
        .iter()
        .map(|&f| motion.ratio(f))
        .collect();
    let design = g.into_design(
        [motion.psi(0.0), motion.advance_rad],
        a,
        None,
        &ratios,
        None,
    );
    let pending = mesh.map(|(outlines, check)| PendingMesh {
        outlines,
        psi: Box::new(move |phi| motion.psi(phi)),
        check,
        at_offset_deg: 0.0,
    });
    Ok((design, pending))
}

/// The driven gear's turns per driver turn as the fraction `(p, q)` (q ≤ 360) of a closed pair,
/// checked: ψ(φ) − (p/q)·φ repeats every 360°/p (to `DRIVEN_CLOSURE_TOL_RAD`, sampled at
/// `samples` angles).
fn closing_turns(motion: &Motion, samples: usize) -> Result<(u32, u32), PairError> {
    let (p_turns, q_turns) = motion.turn_fraction().ok_or_else(|| {
        PairError::Law(format!(
            "the driven gear advances {:.9} turns per driver turn, not a fraction p/q with q ≤ 360: \
             no closed pair has that ratio",
            motion.turn_ratio()
        ))
    })?;
    let defect = motion.driven_closure_defect_rad(p_turns, samples);
    if defect > DRIVEN_CLOSURE_TOL_RAD {
        return Err(PairError::Law(format!(
            "the driven gear does not close: it turns {p_turns}/{q_turns} per driver turn, so \
             ψ(φ) − {k:.6}·φ must repeat every {per:.4}°, but it changes by {defect:.3e} rad over \
             that shift",
            k = motion.turn_ratio(),
            per = 360.0 / f64::from(p_turns)
        )));
    }
    Ok((p_turns, q_turns))
}

/// The tooth counts `(driver, driven)` of a closed pair whose driven gear turns `p/q` per driver
/// turn (`turns`), the driver's pitch perimeter `l1` (mm) at the unit law's centre distance: the
/// driver's `opts.teeth`, or for a centrode the least count at the module that makes the driven
/// count whole; checked against the bounds of the tooth counts and of the mesh check.
fn closed_teeth(
    law: &Law,
    opts: &PairOptions,
    l1: f64,
    (p_turns, q_turns): (u32, u32),
) -> Result<(u32, u32), PairError> {
    let t = &opts.toothing;
    let m = t.module_mm;
    let z = match (opts.teeth, law) {
        (Some(z), _) => z,
        // The driven count z·q/p must be whole: z a multiple of p.
        (None, Law::Centrode(_)) => ((l1 / (PI * m)).ceil() as u32).div_ceil(p_turns) * p_turns,
        (None, _) => {
            return Err(PairError::InvalidParameter {
                name: "teeth",
                value: 0.0,
                expected: "a tooth count for a motion or table law",
            });
        }
    };
    crate::bounds::check_teeth("teeth", z)?;
    if z % p_turns != 0 {
        return Err(PairError::Law(format!(
            "with {z} driver teeth the driven gear would have {:.3} teeth (z·{q_turns}/{p_turns}): \
             give a driver tooth count that is a multiple of {p_turns}",
            f64::from(z) * f64::from(q_turns) / f64::from(p_turns)
        )));
    }
    let z2 = z / p_turns * q_turns;
    crate::bounds::check_teeth("teeth of the driven gear (z·q/p)", z2)?;
    // The check rolls through the q driver turns of a cycle, `verify_steps` per turn.
    crate::bounds::check_verify_steps(
        "verify_steps × driver turns per cycle",
        t.verify_steps * q_turns as usize,
    )?;
    Ok((z, z2))
}
