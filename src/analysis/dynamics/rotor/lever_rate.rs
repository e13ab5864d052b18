//! The meshes' lever arms' rates with the travel, `dρ/dφ` (m/rad), for the damping on the
//! deflection's rate `δ̇ = v_s + φ̇·(ρ1′·Δθ1 − ρ2′·Δθ2)` ([`super::mesh`]).
//!
//! A train whose kinematics repeat each turn gets a table of one turn: the lever arms sampled at
//! `N` carrier angles, their central differences `(ρ_{k+1} − ρ_{k−1})/(2h)` (periodic, error
//! `h²·ρ‴/6`, h = 2π/N), read by linear interpolation. Any other train takes the central
//! difference at the instant (two more kinematics per instant, exact to `h²`).

use super::mesh::MeshGeometry;
use std::f64::consts::TAU;
use std::sync::Arc;

/// `dρ/dφ` of `[mesh][flank][driver, driven]`, m/rad.
pub(crate) type Rates = [[[f64; 2]; 2]; 2];

/// Samples a turn.
const N: usize = 2048;

/// Step of the central difference at an instant, rad.
const H_RAD: f64 = 1e-4;

/// The lever arms' rates of a train.
#[derive(Debug, Clone)]
pub(crate) enum LeverRates {
    /// One turn, on a uniform grid (`N` points, from φ = 0).
    Turn(Arc<Vec<Rates>>),
    /// Central differences at the instant.
    AtInstant,
}

impl LeverRates {
    /// The rates of a train whose geometry at carrier angle φ (rad) is `geometry(φ)`;
    /// `periodic` when it repeats each turn.
    pub(crate) fn new(periodic: bool, geometry: &dyn Fn(f64) -> [MeshGeometry; 2]) -> Self {
        if !periodic {
            return Self::AtInstant;
        }
        let h = TAU / N as f64;
        let levers: Vec<[MeshGeometry; 2]> = (0..N).map(|k| geometry(h * k as f64)).collect();
        let table = (0..N)
            .map(|k| difference(&levers[(k + 1) % N], &levers[(k + N - 1) % N], 2.0 * h))
            .collect();
        Self::Turn(Arc::new(table))
    }

    /// The rates at carrier angle `phi` (rad).
    pub(crate) fn at(&self, phi: f64, geometry: &dyn Fn(f64) -> [MeshGeometry; 2]) -> Rates {
        match self {
            Self::Turn(t) => {
                let x = phi.rem_euclid(TAU) / TAU * N as f64;
                let k = (x.floor() as usize).min(N - 1);
                let w = x - k as f64;
                let (a, b) = (&t[k], &t[(k + 1) % N]);
                each(|j, f, i| a[j][f][i] + w * (b[j][f][i] - a[j][f][i]))
            }
            Self::AtInstant => {
                difference(&geometry(phi + H_RAD), &geometry(phi - H_RAD), 2.0 * H_RAD)
            }
        }
    }
}

/// `(after − before)/span` of every lever arm.
fn difference(after: &[MeshGeometry; 2], before: &[MeshGeometry; 2], span: f64) -> Rates {
    each(|j, f, i| (after[j].lever_m[f][i] - before[j].lever_m[f][i]) / span)
}

/// The rates of `[mesh j][flank f][gear i]` from `v(j, f, i)`.
fn each(v: impl Fn(usize, usize, usize) -> f64) -> Rates {
    std::array::from_fn(|j| std::array::from_fn(|f| std::array::from_fn(|i| v(j, f, i))))
}
