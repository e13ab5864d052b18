//! The mesh stiffness of a rotor mesh at one instant: a constant, or ISO 6336-1's on the local
//! equivalent pair ([`EquivalentPair`]).
//!
//! ISO 6336-1:2006 clause 9 (method B), spur gears, solid blanks, steel on steel:
//!
//! ```text
//! q′   = C1 + C2/z_n1 + C3/z_n2 + C4·x1 + C5·x1/z_n1 + C6·x2 + C7·x2/z_n2 + C8·x1² + C9·x2²   (mm·µm/N)
//!        C1…C9 = 0.04723, 0.15551, 0.25791, −0.00635, −0.11654, −0.00193, −0.24188, 0.00529, 0.00182
//! c′   = C_M·C_R·C_B·cos β / q′,   C_M = 0.8, C_R = 1, cos β = 1,
//!        C_B = [1 + 0.5·(1.2 − h_fP/m)]·[1 − 0.02·(20° − α)]                          (N/(mm·µm))
//! c_γα = c′·(0.75·ε_α + 0.25)                                                           (N/(mm·µm))
//! ```
//!
//! with `z_n = 2ρ/m` the local equivalent tooth count of each gear (ρ the pitch curve's radius of
//! curvature at the contact; a concave arc, an internal gear, has `1/z_n = 0`), no profile shift
//! (`x = 0`, the generated teeth's), and ε_α the local contact ratio. The tooth-pair alternation
//! is a two-level profile whose mean over a base pitch is c_γα: one pair `c′`, two pairs
//! `1.75·c′` (`c′(2 − ε) + 1.75·c′(ε − 1) = c_γα`). Mesh stiffness = c·b (face width b), N/m
//! = 1e9 × N/(mm·µm) × mm.

use crate::loads::rating::equivalent::EquivalentPair;

/// ISO 6336-1 Table 10's coefficients C1…C9.
const C: [f64; 9] = [
    0.04723, 0.15551, 0.25791, -0.00635, -0.11654, -0.00193, -0.24188, 0.00529, 0.00182,
];

/// Ratio of the two-pair stiffness to the one-pair stiffness `c′` (module docs).
pub const DOUBLE_PAIR_RATIO: f64 = 1.75;

/// `1/q′` of ISO 6336-1 for equivalent tooth counts `z_n1`, `z_n2` (infinite for a rack or an
/// internal gear) and no profile shift, N/(mm·µm).
#[must_use]
pub fn c_theoretical(z_n1: f64, z_n2: f64) -> f64 {
    let q = C[0] + C[1] / z_n1 + C[2] / z_n2;
    1.0 / q
}

/// The single-pair stiffness `c′` of the local equivalent pair, N/(mm·µm): `c′_th·C_M·C_B`
/// with the basic rack's dedendum `h_fP/m = dedendum_coeff` (module docs).
#[must_use]
pub fn single_pair(pair: &EquivalentPair, dedendum_coeff: f64) -> f64 {
    let zn = |rho: f64| {
        if rho > 0.0 {
            2.0 * rho / pair.module_mm
        } else {
            f64::INFINITY
        }
    };
    let c_th = c_theoretical(zn(pair.rho_mm[0]), zn(pair.rho_mm[1]));
    let c_b =
        (1.0 + 0.5 * (1.2 - dedendum_coeff)) * (1.0 - 0.02 * (20.0 - pair.alpha_rad.to_degrees()));
    c_th * 0.8 * c_b
}

/// The mean mesh stiffness `c_γα = c′·(0.75·ε_α + 0.25)`, N/(mm·µm).
#[must_use]
pub fn mean_mesh(c_single: f64, eps_alpha: f64) -> f64 {
    c_single * (0.75 * eps_alpha + 0.25)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 20/40 pair, module 4, α = 20°, h_fP = 1.25·m: q′ = 0.04723 + 0.15551/20 + 0.25791/40
    /// = 0.0614533 → c′_th = 16.2725, C_B = 0.975, c′ = 12.6926 N/(mm·µm); with ε_α = 1.63519
    /// (the loads' equivalent pair test), c_γα = 12.6926·1.47639 = 18.7392.
    #[test]
    fn the_iso_stiffness_of_a_spur_pair() {
        let p = EquivalentPair {
            rho_mm: [40.0, 80.0],
            alpha_rad: 20f64.to_radians(),
            module_mm: 4.0,
            addendum_mm: 4.0,
        };
        let c1 = single_pair(&p, 1.25);
        assert!((c1 - 12.69258).abs() < 1e-4, "{c1}");
        let cg = mean_mesh(c1, p.contact_ratio());
        assert!((cg - 18.73922).abs() < 1e-4, "{cg}");
        // internal gear: 1/z_n2 = 0
        assert!(
            (c_theoretical(20.0, f64::INFINITY) - 1.0 / (0.04723 + 0.15551 / 20.0)).abs() < 1e-12
        );
    }
}
