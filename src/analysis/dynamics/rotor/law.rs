//! The stiffness of each rotor mesh as the carrier turns: a constant, or ISO 6336-1's on the
//! local equivalent pair ([`super::stiffness`]) with the tooth pairs alternating.
//!
//! The teeth pass at the gears' own speed: the driver's pitch-curve arc from its body angle 0
//! to the contact, over the circular pitch `p = L/z` (L the perimeter), counts the teeth passed,
//! `ξ(φ)`. Two pairs are in contact while `frac(ξ) < ε_α(φ) − 1` (ε_α the local contact ratio):
//! the switch angles are where that changes, found once per turn (bisection to 1e-12 rad) and
//! given to the integrator as breakpoints; the law looks them up, so the right-hand side and the
//! breakpoints agree exactly.

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
}

impl ToothData {
    /// The teeth of `z` per gear at module `module_mm` (mm) cut with the rack and backlash of
    /// `o`.
    #[must_use]
    pub fn of(o: &crate::design::train::TrainTeethOptions, module_mm: f64, z: u32) -> Self {
        let rack = o.toothing.rack;
        Self {
            module_mm,
            z,
            alpha_rad: rack.alpha_rad(),
            addendum_coeff: rack.addendum(),
            dedendum_coeff: rack.addendum() + rack.clearance(),
            backlash_mm: o.toothing.backlash_mm,
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
    /// pitch curve (its teeth count the passing).
    pub(crate) fn iso(
        scale: f64,
        pairs: PairsMode,
        teeth: ToothData,
        face_mm: f64,
        driver: &PitchCurve,
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
            let double = |phi: f64| {
                let mut d = false;
                contact(phi, &mut |c| {
                    let xi = arc.at(c.pitch.driver_angle_rad) / pitch;
                    let eps = c.pair(&teeth).contact_ratio();
                    d = xi - xi.floor() < eps - 1.0;
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
