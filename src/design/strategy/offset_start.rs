//! A start off the carrier line: a train's needle motion carried over to an intermediate axis
//! turned by the idler offset ε (docs/math/chain.md §6.5), for the design for a module.
//!
//! At a tooth count above the free one the centre distance `a = zπm/L̂` exceeds half the arm,
//! and `cos ε = l1/(2a)` keeps the arm where it was. Turning the intermediate axis alone would
//! move the needle, though: the planet's contact map becomes `S(t) = Φ⁻¹(Φ(t) + π + 2ε)`, and the
//! needle turns by about 3ε, unevenly (over 100 mm at the tip for ε = 13°). The start keeps the
//! train's needle motion instead: the refinement of docs/math/chain.md §8.3, with the contact
//! shift `π + 2ε`, fits the sun ratio whose planet turns as the given train's does; the centre
//! distance then follows from the perimeter of the new ratio and ε from the arm again, for
//! [`ROUNDS`] rounds; the needle angle is fitted to the given train's needle direction last.
//! On an exact target this start is already on the target (G1 at z = 23, m = 2: 0.004 mm).

use crate::design::hypothesis::refine::{RefineOptions, refine_with_shift};
use crate::design::inverse::needle_law::NeedleLaw;
use crate::geometry::mechanism::Mechanism;
use crate::geometry::perimeter::unit_perimeter;
use std::f64::consts::PI;

/// Rounds of refinement and re-sizing (the second moves ε by the perimeter change of the first).
const ROUNDS: usize = 2;

/// Samples of the needle law carried over, and of the needle-angle fit.
const LAW_SAMPLES: usize = 1024;

/// The train `m0` carried over to perimeter `perimeter_mm` (mm) with its intermediate axis turned
/// off the carrier line to the side `sign` (±1), keeping its arm `l1` and its needle motion
/// (module documentation), its ratio within `ratio_bounds`; `None` where the perimeter leaves
/// the centre distance at or below half the arm (no offset keeps it).
pub(in crate::design) fn offset_start(
    m0: &Mechanism,
    perimeter_mm: f64,
    sign: f64,
    ratio_bounds: [f64; 2],
) -> Option<Mechanism> {
    let l1 = m0.l1_mm();
    let s0 = |x: f64| m0.contact_map(m0.contact_angle(x));
    let base = s0(0.0);
    let law = NeedleLaw::from_fn(LAW_SAMPLES, |x| s0(x) - base);
    let opts = RefineOptions::default().with_ratio_bounds(ratio_bounds);
    let offset = |ratio: &crate::geometry::fourier::SunRatio| {
        let a = perimeter_mm / unit_perimeter(ratio);
        let c = l1 / (2.0 * a);
        (c < 1.0).then(|| (a, sign * c.acos()))
    };
    // S1(x − τ) = S0(x + ε0 − φ_ref0) + C: from the given train, τ = φ_ref0 − ε0 and C = S0(0).
    let (mut ratio, mut tau, mut c) = (
        m0.ratio.clone(),
        m0.sun_phase_rad - m0.idler_offset_rad,
        base,
    );
    for _ in 0..ROUNDS {
        let (a, eps) = offset(&ratio)?;
        let r = refine_with_shift(&law, PI + 2.0 * eps, m0.l3_mm, a, &ratio, [tau, c], &opts);
        (ratio, tau, c) = (r.ratio, r.tau_rad, r.offset_rad);
    }
    let (a, eps) = offset(&ratio)?;
    let mut m = Mechanism {
        a_mm: a,
        l3_mm: m0.l3_mm,
        ratio,
        // The contact angle t′ = φ + ε − φ_ref is the refinement's x − τ.
        sun_phase_rad: tau + eps,
        needle_angle_rad: 0.0,
        idler_offset_rad: eps,
    };
    m.fit_needle_angle(LAW_SAMPLES, |phi| m0.needle_direction(phi));
    Some(m)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::golden::g1_mechanism;

    /// G1 carried to 23 teeth of module 2 (its free count is 22.38): the start off the line
    /// traces G1's own path, both ways round.
    #[test]
    fn g1_carried_to_a_larger_count_keeps_its_path() {
        let g1 = g1_mechanism();
        for sign in [1.0, -1.0] {
            let m = offset_start(&g1, 23.0 * PI * 2.0, sign, [0.3, 3.3]).unwrap();
            assert!((m.l1_mm() - g1.l1_mm()).abs() < 1e-9);
            assert!(sign * m.idler_offset_rad > 0.2, "{}", m.idler_offset_rad);
            let dev = (0..720)
                .map(|k| {
                    let phi = std::f64::consts::TAU * k as f64 / 720.0;
                    let (p, q) = (m.tip(phi), g1.tip(phi));
                    p.distance(q)
                })
                .fold(0.0, f64::max);
            assert!(dev < 0.01, "sign {sign}: {dev} mm");
        }
        // 22 teeth leave a below half the arm: no offset keeps it.
        assert!(offset_start(&g1, 22.0 * PI * 2.0, 1.0, [0.3, 3.3]).is_none());
    }
}
