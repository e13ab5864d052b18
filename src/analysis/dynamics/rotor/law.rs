//! The stiffness of each rotor mesh as the carrier turns: a constant, or ISO 6336-1's on the
//! local equivalent pair ([`super::stiffness`]) with the tooth pairs alternating.
//!
//! The teeth pass at the gears' own speed. On the driver's pitch curve (CCW frame), with `s` the
//! arc from its body angle 0 to the contact and `p = L/z` the circular pitch (L the perimeter),
//! tooth k's centre is at `s_k = φ₀ + k·p` (φ₀ the design's `teeth.phase_mm` of the driver,
//! negated for a clockwise design, whose CCW frame is the mirror image) and its flanks at
//! `s_k ± t/2`, `t = p/2 − j/2` the tooth's arc thickness on the pitch curve (j the nominal
//! circumferential backlash). The flank in contact is the one the rigid loads load at that
//! carrier angle: a force on the driven gear turning it CCW about its axis (`flank = +1`) pushes
//! the driver towards larger s, onto its flank at `s_k − t/2`; `flank = −1` onto `s_k + t/2`.
//! One pair carries the load while that flank passes the pitch point, so the single-pair zone is
//! centred there and the two-pair zone half a pitch away:
//!
//! `ξ′ = (s − φ₀ + flank·t/2)/p`, two pairs while `|frac(ξ′) − ½| < (ε_α(φ) − 1)/2`
//!
//! (ε_α the local contact ratio). The rigid flank is the sign of the rigid mesh force, linear
//! between the loads' samples, so its changes are known in advance. Simplified: during a backlash
//! flight, or while the dynamic force is on the other flank, the count still follows the rigid
//! flank; the outline's thinning (its left flanks by j/2) is taken as symmetric (a shift of j/4
//! along the arc, 0.3 % of a pitch on G1). The switch angles are where the count changes, found
//! once per turn (bisection to 1e-12 rad) and given to the integrator as breakpoints; the law
//! looks them up, so the right-hand side and the breakpoints agree exactly.

use super::spec::PairsMode;
use super::stiffness::{DOUBLE_PAIR_RATIO, mean_mesh, single_pair};
use crate::geometry::pitch::PitchCurve;
use crate::loads::motion::PitchPoint;
use crate::loads::rating::equivalent::EquivalentPair;
use std::f64::consts::TAU;

/// The teeth of a design, as the stiffness needs them (mm, rad).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ToothData {
    /// Module, mm.
    pub module_mm: f64,
    /// Teeth per gear (the three gears of a train have the same count).
    pub z: u32,
    /// Rack pressure angle, rad.
    pub alpha_rad: f64,
    /// Addendum coefficient h_a/m.
    pub addendum_coeff: f64,
    /// Dedendum coefficient h_f/m (addendum + clearance).
    pub dedendum_coeff: f64,
    /// Nominal circumferential backlash on the pitch curve, mm.
    pub backlash_mm: f64,
    /// Arc position of tooth 0's centre on each gear's pitch curve (sun, intermediate, planet),
    /// mm, in the design's own frame (`teeth.phase_mm`; zeros for a design file without it).
    pub phase_mm: [f64; 3],
}

impl ToothData {
    /// The teeth of `z` per gear at module `module_mm` (mm) cut with the rack and backlash of
    /// `o`, tooth 0 of each gear centred at the arc `phase_mm` (mm).
    #[must_use]
    pub fn of(
        o: &crate::design::train::TrainTeethOptions,
        module_mm: f64,
        z: u32,
        phase_mm: [f64; 3],
    ) -> Self {
        let rack = o.toothing.rack;
        Self {
            module_mm,
            z,
            alpha_rad: rack.alpha_rad(),
            addendum_coeff: rack.addendum(),
            dedendum_coeff: rack.addendum() + rack.clearance(),
            backlash_mm: o.toothing.backlash_mm,
            phase_mm,
        }
    }
}

/// Cumulative arc length of a pitch curve over body angle, on a uniform grid of one turn.
#[derive(Debug, Clone)]
struct ArcTable {
    s_mm: Vec<f64>,
    perimeter_mm: f64,
}

impl ArcTable {
    fn new(curve: &PitchCurve, n: usize) -> Self {
        let speed: Vec<f64> = (0..=n)
            .map(|k| curve.geometry(TAU * k as f64 / n as f64).speed_mm())
            .collect();
        let h = TAU / n as f64;
        let mut s_mm = vec![0.0; n + 1];
        for k in 0..n {
            s_mm[k + 1] = s_mm[k] + 0.5 * h * (speed[k] + speed[k + 1]);
        }
        let perimeter_mm = s_mm[n];
        Self { s_mm, perimeter_mm }
    }

    /// Arc from body angle 0 to `u` (any real), mm.
    fn at(&self, u: f64) -> f64 {
        let n = self.s_mm.len() - 1;
        let turns = (u / TAU).floor();
        let x = (u - turns * TAU) / TAU * n as f64;
        let k = (x.floor() as usize).min(n - 1);
        let t = x - k as f64;
        turns * self.perimeter_mm + self.s_mm[k] + t * (self.s_mm[k + 1] - self.s_mm[k])
    }
}

/// A mesh's stiffness law.
#[derive(Debug, Clone)]
pub(crate) enum MeshLaw {
    /// N/m.
    Constant(f64),
    /// ISO 6336-1 (module docs).
    Iso {
        /// Factor on ISO's stiffness.
        scale: f64,
        /// Alternating or mean.
        pairs: PairsMode,
        /// The teeth.
        teeth: ToothData,
        /// Face width, mm.
        face_mm: f64,
        /// Carrier angles in [0, 2π) where the pair count changes, rad, sorted.
        switches: Vec<f64>,
        /// Two pairs at φ = 0.
        double_at_zero: bool,
    },
}

/// The mesh at a carrier angle (rad), handed to a visitor.
pub(crate) type ContactAt<'a> = dyn Fn(f64, &mut dyn FnMut(&Contact<'_>)) + 'a;

/// What the law needs of the mesh at one instant: the pitch point and the curves
/// `[driver, driven]` (CCW frame).
pub(crate) struct Contact<'a> {
    pub pitch: &'a PitchPoint,
    pub curves: [&'a PitchCurve; 2],
}

impl Contact<'_> {
    /// The local equivalent pair.
    fn pair(&self, t: &ToothData) -> EquivalentPair {
        let angles = [self.pitch.driver_angle_rad, self.pitch.driven_angle_rad];
        EquivalentPair {
            rho_mm: [0, 1].map(|i| self.curves[i].geometry(angles[i]).radius_of_curvature_mm()),
            alpha_rad: t.alpha_rad,
            module_mm: t.module_mm,
            addendum_mm: t.addendum_coeff * t.module_mm,
        }
    }
}

impl MeshLaw {
    /// The ISO law; `contact(φ)` gives the mesh at carrier angle φ, `driver` the driving gear's
    /// pitch curve (CCW frame; its teeth count the passing), `phase_mm` its tooth 0's centre on
    /// that curve's arc (mm, CCW frame) and `flank(φ)` the rigid loads' flank at φ (module docs).
    // The driver's curve, phase and flank are three views of one gear; one crate-private caller.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn iso(
        scale: f64,
        pairs: PairsMode,
        teeth: ToothData,
        face_mm: f64,
        driver: &PitchCurve,
        phase_mm: f64,
        flank: &dyn Fn(f64) -> i8,
        contact: &ContactAt<'_>,
    ) -> Self {
        let mut law = Self::Iso {
            scale,
            pairs,
            teeth,
            face_mm,
            switches: Vec::new(),
            double_at_zero: false,
        };
        if pairs == PairsMode::Alternating {
            let arc = ArcTable::new(driver, 8192);
            let pitch = arc.perimeter_mm / f64::from(teeth.z);
            let thickness = 0.5 * pitch - 0.5 * teeth.backlash_mm;
            let double = |phi: f64| {
                let mut d = false;
                let side = if flank(phi) < 0 { -1.0 } else { 1.0 };
                contact(phi, &mut |c| {
                    let s = arc.at(c.pitch.driver_angle_rad);
                    let xi = (s - phase_mm + side * 0.5 * thickness) / pitch;
                    let eps = c.pair(&teeth).contact_ratio();
                    d = (xi - xi.floor() - 0.5).abs() < 0.5 * (eps - 1.0);
                });
                d
            };
            let n = 96 * teeth.z as usize;
            let grid: Vec<bool> = (0..=n).map(|k| double(TAU * k as f64 / n as f64)).collect();
            let mut switches = Vec::new();
            for k in 0..n {
                if grid[k] != grid[k + 1] {
                    let (mut a, mut b) =
                        (TAU * k as f64 / n as f64, TAU * (k + 1) as f64 / n as f64);
                    while b - a > 1e-12 {
                        let m = 0.5 * (a + b);
                        if double(m) == grid[k] {
                            a = m;
                        } else {
                            b = m;
                        }
                    }
                    switches.push(b);
                }
            }
            if let Self::Iso {
                switches: s,
                double_at_zero,
                ..
            } = &mut law
            {
                *s = switches;
                *double_at_zero = grid[0];
            }
        }
        law
    }

    /// The switch angles in [0, 2π), rad (none for a constant or mean law).
    pub(crate) fn switches(&self) -> &[f64] {
        match self {
            Self::Iso { switches, .. } => switches,
            Self::Constant(_) => &[],
        }
    }

    /// Two pairs in contact at carrier angle `phi` (rad).
    pub(crate) fn double(&self, phi: f64) -> bool {
        match self {
            Self::Iso {
                switches,
                double_at_zero,
                pairs: PairsMode::Alternating,
                ..
            } => {
                let x = phi.rem_euclid(TAU);
                let i = switches.partition_point(|&s| s <= x);
                double_at_zero ^ (i % 2 == 1)
            }
            _ => false,
        }
    }

    /// Stiffness at carrier angle `phi` (rad) for the mesh `contact`, N/m; `double` the pair
    /// count to use (from [`Self::double`], or frozen for a partial derivative).
    pub(crate) fn stiffness(&self, contact: &Contact<'_>, double: bool) -> f64 {
        match self {
            Self::Constant(k) => *k,
            Self::Iso {
                scale,
                pairs,
                teeth,
                face_mm,
                ..
            } => {
                let pair = contact.pair(teeth);
                let c1 = single_pair(&pair, teeth.dedendum_coeff);
                let c = match pairs {
                    PairsMode::Mean => mean_mesh(c1, pair.contact_ratio()),
                    PairsMode::Alternating if double => DOUBLE_PAIR_RATIO * c1,
                    PairsMode::Alternating => c1,
                };
                // N/(mm·µm) × mm = N/µm = 1e6 N/m
                scale * c * face_mm * 1e6
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Point;

    /// The double-contact intervals of a pair of equal circles (r = 25 mm, z = 25, m = 2, ε_α
    /// constant), the driver's contact at body angle φ: each centred half a pitch from the loaded
    /// driver flank, `s = φ₀ − flank·t/2 + (k + ½)·p` (φ₀ tooth 0's centre, t = p/2 − j/2),
    /// within 1e-6 of a pitch, and covering ε_α − 1 of the turn.
    #[test]
    fn double_contact_is_centred_half_a_pitch_from_the_loaded_flank() {
        let r_mm = 25.0;
        let circle = PitchCurve::from_fn(720, |_| r_mm).unwrap();
        let teeth = ToothData {
            module_mm: 2.0,
            z: 25,
            alpha_rad: 20f64.to_radians(),
            addendum_coeff: 1.0,
            dedendum_coeff: 1.25,
            backlash_mm: 0.08,
            phase_mm: [1.3, 0.0, 0.0],
        };
        let contact = |phi: f64, f: &mut dyn FnMut(&Contact<'_>)| {
            let pitch = PitchPoint {
                point_mm: Point::new(r_mm, 0.0),
                tangent: Point::new(0.0, -1.0),
                normal: Point::new(1.0, 0.0),
                driver_angle_rad: phi,
                driven_angle_rad: std::f64::consts::PI - phi,
            };
            f(&Contact {
                pitch: &pitch,
                curves: [&circle, &circle],
            });
        };
        let eps = {
            let mut e = 0.0;
            contact(0.0, &mut |c| e = c.pair(&teeth).contact_ratio());
            e
        };
        assert!(eps > 1.2 && eps < 2.0, "{eps}");
        let p = TAU * r_mm / 25.0;
        let t = 0.5 * p - 0.5 * teeth.backlash_mm;
        for flank in [1i8, -1] {
            let law = MeshLaw::iso(
                1.0,
                PairsMode::Alternating,
                teeth,
                20.0,
                &circle,
                teeth.phase_mm[0],
                &|_| flank,
                &contact,
            );
            let sw = law.switches();
            assert_eq!(sw.len(), 50, "{flank}: {sw:?}");
            let mut double_arc = 0.0;
            for k in 0..sw.len() {
                let (a, b) = (
                    sw[k],
                    if k + 1 < sw.len() {
                        sw[k + 1]
                    } else {
                        sw[0] + TAU
                    },
                );
                let mid = 0.5 * (a + b);
                if !law.double(mid) {
                    continue;
                }
                double_arc += b - a;
                // the interval's centre as an arc, against the nearest predicted centre
                let s = mid * r_mm;
                let x = (s - teeth.phase_mm[0] + f64::from(flank) * 0.5 * t) / p - 0.5;
                let off = x - x.round();
                assert!(off.abs() < 1e-6, "{flank}: centre off by {off} pitch");
            }
            let share = double_arc / TAU;
            assert!(
                (share - (eps - 1.0)).abs() < 1e-9,
                "{flank}: {share} vs {}",
                eps - 1.0
            );
        }
    }
}
