//! The validated error inventory in internal units (mm, rad): distributions, random assemblies,
//! samples at 3σ and the moments of every coordinate.

use super::{ErrorVector, N_COORDS, ecc_index};
use crate::math::Point;
use rand::RngExt;
use rand::rngs::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};
use std::f64::consts::TAU;

/// Distribution of one scalar coordinate about its nominal value (internal units).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Spread {
    /// No spread.
    Fixed,
    /// Normal with this σ.
    Normal(f64),
    /// Uniform with this half width.
    Uniform(f64),
}

impl Spread {
    /// Variance.
    #[must_use]
    pub fn variance(&self) -> f64 {
        match *self {
            Spread::Fixed => 0.0,
            Spread::Normal(s) => s * s,
            Spread::Uniform(h) => h * h / 3.0,
        }
    }
    /// The 3σ bound (σ-based) or the half width.
    #[must_use]
    pub fn three_sigma(&self) -> f64 {
        match *self {
            Spread::Fixed => 0.0,
            Spread::Normal(s) => 3.0 * s,
            Spread::Uniform(h) => h,
        }
    }
    fn draw(&self, rng: &mut ChaCha8Rng) -> f64 {
        match *self {
            Spread::Fixed => 0.0,
            Spread::Normal(s) => {
                let z: f64 = StandardNormal.sample(rng);
                s * z
            }
            Spread::Uniform(h) => h * (2.0 * rng.random::<f64>() - 1.0),
        }
    }
}

/// A gear eccentricity in internal units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Eccentricity {
    /// Nominal magnitude, mm.
    pub magnitude_mm: f64,
    /// Nominal direction in the body frame, rad.
    pub direction_rad: f64,
    /// σ per component, mm (0: none).
    pub sigma_mm: f64,
    /// Free (assembly-choice) direction.
    pub free: bool,
    /// Keyed positions (0: continuous).
    pub keyed: usize,
}

impl Eccentricity {
    /// The eccentricity vector (mm) at direction `gamma` (rad) with the nominal magnitude.
    #[must_use]
    pub fn vector(&self, gamma: f64) -> Point {
        Point::new(
            self.magnitude_mm * gamma.cos(),
            self.magnitude_mm * gamma.sin(),
        )
    }
    /// Direction of position `i` of `n` equally spaced assembly positions starting at the
    /// nominal direction, `γ + 2πi/n`, rad.
    #[must_use]
    pub fn position_direction(&self, i: usize, n: usize) -> f64 {
        self.direction_rad + TAU * i as f64 / n as f64
    }
    /// A random admissible direction of a free eccentricity (uniform, or uniform over the keyed
    /// positions), rad.
    pub fn random_direction(&self, rng: &mut ChaCha8Rng) -> f64 {
        if self.keyed > 0 {
            let i = (rng.random::<f64>() * self.keyed as f64).floor() as usize;
            self.position_direction(i.min(self.keyed - 1), self.keyed)
        } else {
            rng.random::<f64>() * TAU
        }
    }
}

/// The validated error inventory in internal units (mm, rad).
#[derive(Debug, Clone, PartialEq)]
pub struct Inventory {
    /// Pressure angle α, rad.
    pub pressure_angle_rad: f64,
    /// Loaded flank of the sun–intermediate mesh, ±1.
    pub load_side: i8,
    /// Carrier angles per turn.
    pub samples_per_turn: usize,
    /// Eccentricities of sun, intermediate, planet.
    pub eccentricity: [Eccentricity; 3],
    /// Nominal values of the scalar coordinates (indices 6..16; the eccentricity slots are unused).
    pub nominal: ErrorVector,
    /// Spreads of the scalar coordinates (indices 6..16).
    pub spread: [Spread; N_COORDS],
}

impl Inventory {
    /// An inventory without any error (pressure angle α in rad, loaded flank ±1).
    #[must_use]
    pub fn zero(pressure_angle_rad: f64, load_side: i8, samples_per_turn: usize) -> Self {
        Self {
            pressure_angle_rad,
            load_side,
            samples_per_turn,
            eccentricity: [Eccentricity {
                magnitude_mm: 0.0,
                direction_rad: 0.0,
                sigma_mm: 0.0,
                free: false,
                keyed: 0,
            }; 3],
            nominal: [0.0; N_COORDS],
            spread: [Spread::Fixed; N_COORDS],
        }
    }

    /// The nominal error vector: measured values, eccentricities at their nominal directions.
    #[must_use]
    pub fn nominal_vector(&self) -> ErrorVector {
        self.with_directions(&self.eccentricity.map(|e| e.direction_rad))
    }

    /// The nominal error vector with eccentricity directions `gammas` (rad).
    #[must_use]
    pub fn with_directions(&self, gammas: &[f64; 3]) -> ErrorVector {
        let mut x = self.nominal;
        for k in 0..3 {
            let v = self.eccentricity[k].vector(gammas[k]);
            x[ecc_index(k)] = v.x;
            x[ecc_index(k) + 1] = v.y;
        }
        x
    }

    /// One random realisation (a random assembly): scalar coordinates from their distributions,
    /// eccentricities = nominal vector (at a random direction when free) + 2-D Gaussian.
    pub fn draw(&self, rng: &mut ChaCha8Rng) -> ErrorVector {
        let mut x = self.nominal;
        for k in 0..3 {
            let e = &self.eccentricity[k];
            let g = if e.free {
                e.random_direction(rng)
            } else {
                e.direction_rad
            };
            let v = e.vector(g);
            let (zx, zy): (f64, f64) = if e.sigma_mm > 0.0 {
                (StandardNormal.sample(rng), StandardNormal.sample(rng))
            } else {
                (0.0, 0.0)
            };
            x[ecc_index(k)] = v.x + e.sigma_mm * zx;
            x[ecc_index(k) + 1] = v.y + e.sigma_mm * zy;
        }
        for (xi, sp) in x.iter_mut().zip(&self.spread).skip(6) {
            *xi += sp.draw(rng);
        }
        x
    }

    /// A sample at the 3σ tolerances: every scalar coordinate at `nominal ± 3σ` (or ± the half
    /// width; random sign), every eccentricity of magnitude `e + 3σ` at a random direction.
    pub fn draw_three_sigma(&self, rng: &mut ChaCha8Rng) -> ErrorVector {
        let mut x = self.nominal;
        for k in 0..3 {
            let m = self.three_sigma_eccentricity(k);
            let g = rng.random::<f64>() * TAU;
            x[ecc_index(k)] = m * g.cos();
            x[ecc_index(k) + 1] = m * g.sin();
        }
        for (xi, sp) in x.iter_mut().zip(&self.spread).skip(6) {
            let s = if rng.random::<bool>() { 1.0 } else { -1.0 };
            *xi += s * sp.three_sigma();
        }
        x
    }

    /// `e + 3σ` of gear `k`'s eccentricity, mm.
    #[must_use]
    pub fn three_sigma_eccentricity(&self, k: usize) -> f64 {
        self.eccentricity[k].magnitude_mm + 3.0 * self.eccentricity[k].sigma_mm
    }

    /// Mean and variance of every coordinate under [`Inventory::draw`] (coordinates independent;
    /// a free eccentricity has mean 0 and variance `e²/2 + σ²` per component).
    #[must_use]
    pub fn moments(&self) -> (ErrorVector, ErrorVector) {
        let mut mean = self.nominal;
        let mut var = [0.0; N_COORDS];
        for k in 0..3 {
            let e = &self.eccentricity[k];
            let s2 = e.sigma_mm * e.sigma_mm;
            if e.free {
                let (i0, i1) = (ecc_index(k), ecc_index(k) + 1);
                // Keyed positions: mean and variance of the discrete set of vectors.
                let (mut mx, mut my, mut vx, mut vy) = (0.0, 0.0, 0.0, 0.0);
                let n = e.keyed;
                if n > 0 {
                    let vs: Vec<Point> = (0..n)
                        .map(|i| e.vector(e.position_direction(i, n)))
                        .collect();
                    for v in &vs {
                        mx += v.x / n as f64;
                        my += v.y / n as f64;
                    }
                    for v in &vs {
                        vx += (v.x - mx).powi(2) / n as f64;
                        vy += (v.y - my).powi(2) / n as f64;
                    }
                } else {
                    vx = 0.5 * e.magnitude_mm * e.magnitude_mm;
                    vy = vx;
                }
                mean[i0] = mx;
                mean[i1] = my;
                var[i0] = vx + s2;
                var[i1] = vy + s2;
            } else {
                let v = e.vector(e.direction_rad);
                mean[ecc_index(k)] = v.x;
                mean[ecc_index(k) + 1] = v.y;
                var[ecc_index(k)] = s2;
                var[ecc_index(k) + 1] = s2;
            }
        }
        for (v, sp) in var.iter_mut().zip(&self.spread).skip(6) {
            *v = sp.variance();
        }
        (mean, var)
    }

    /// The free eccentricities (gear indices).
    #[must_use]
    pub fn free_gears(&self) -> Vec<usize> {
        (0..3).filter(|&k| self.eccentricity[k].free).collect()
    }
}
