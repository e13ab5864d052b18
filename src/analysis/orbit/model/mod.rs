//! Kinematic model of the floating sun under planet eccentricity (docs/math/companion.md §A.2–§A.7).
//!
//! Planet i sits at position angle φ_i in the carrier frame; its eccentricity vector, fixed in the
//! planet body, is `e_pi (cos ψ_i, sin ψ_i)` in the planet frame with `ψ_i = ω_p t + θ_p0 + θ_pi`
//! (docs/math/companion.md §A.2). The loaded flank normals `n_e = (sin α, h cos α)`, `n_i = (−sin α, h cos α)` (docs/math/companion.md §A.3) give
//! the mesh conditions
//!
//! `u_s · n_ei + c = q_i`, `q_i = e_pi · (n_ei + n_ii) = 2h cos α · e_pi sin ψ_i` (docs/math/companion.md §A.4 eq. A-1)
//!
//! in the unknowns sun translation `u_s = (x_s, y_s)` and common-mode (torsional / transmission-error)
//! displacement `c`, with `n_ei` at polar angle `β_i = φ_i + h(π/2 − α)`. With phasors
//! `E_i = e_pi e^{i(θ_p0+θ_pi)}`, `q_i = Im(2h cos α E_i e^{iω_p t})`, so the sine phasors of
//! `x_s, y_s, c` are the (least-squares, for N ≠ 3) solution of `[cos β_i, sin β_i, 1]·[P_x, P_y, P_c]ᵀ
//! = 2h cos α E_i`: a real 3×N [`KinematicMap`] applied to the complex vector E.
//!
//! Justification (docs/math/companion.md §A.4): a floating sun with three planets at 120° is only in force balance if the
//! three mesh forces are equal, so a static stiffness model with equal mesh springs reproduces this
//! kinematic solution for any stiffness. For N ≠ 3 or unequal spacing the least-squares form equals
//! the equal-stiffness elastic equilibrium only when `Σ n_ei = 0` (equally spaced planets); otherwise a
//! load-dependent term appears and [`KinematicSolution::load_independent`] is `false`.

mod params;
mod speeds;

pub use params::{GearParams, ModelParams, PlanetParams};
pub use speeds::{GearSpeeds, Line, LineKind, rpm_to_rad_s};

use super::{C64, Orbit, OrbitError, invalid};
use nalgebra::{DMatrix, Matrix3};
use serde::Deserialize;
use std::f64::consts::{FRAC_PI_2, TAU};

/// Rotation sense of the sun, `h` in docs/math/companion.md §A.3.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Deserialize, serde::Serialize, schemars::JsonSchema,
)]
#[serde(rename_all = "snake_case")]
pub enum Hand {
    /// Counter-clockwise sun, h = +1.
    Ccw,
    /// Clockwise sun, h = −1.
    Cw,
}

impl Hand {
    /// h = ±1.
    #[must_use]
    pub fn h(self) -> f64 {
        match self {
            Hand::Ccw => 1.0,
            Hand::Cw => -1.0,
        }
    }
}

/// One planet: position in the carrier and its eccentricity phasor.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Planet {
    /// Position angle φ_i in the carrier frame, rad (CCW from x_c).
    pub position_rad: f64,
    /// Eccentricity magnitude e_pi, µm (≥ 0).
    pub eccentricity_um: f64,
    /// Eccentricity phase θ_pi, rad.
    pub phase_rad: f64,
}

/// A validated planet set (N ≥ 3 distinct positions, 0 < α < 90°).
#[derive(Debug, Clone, PartialEq)]
pub struct PlanetSet {
    pressure_angle_rad: f64,
    hand: Hand,
    theta_p0_rad: f64,
    omega_p_rad_s: f64,
    planets: Vec<Planet>,
}

/// Two positions closer than this (rad) count as the same planet.
const MIN_POSITION_GAP_RAD: f64 = 1e-6;

/// Largest accepted planet eccentricity, µm (1 m: beyond any gear, and keeps every phasor
/// product finite).
pub const MAX_ECCENTRICITY_UM: f64 = 1e6;

impl PlanetSet {
    /// Validates and builds a planet set.
    ///
    /// * `pressure_angle_rad` — working pressure angle α, in (0, π/2).
    /// * `hand` — sun rotation sense (h).
    /// * `theta_p0_rad` — common phase θ_p0.
    /// * `omega_p_rad_s` — signed planet spin relative to the carrier (non-zero, finite).
    /// * `planets` — at least 3, distinct positions, finite, 0 ≤ e ≤ [`MAX_ECCENTRICITY_UM`].
    ///
    /// # Errors
    /// [`OrbitError::Invalid`] naming the offending parameter.
    pub fn new(
        pressure_angle_rad: f64,
        hand: Hand,
        theta_p0_rad: f64,
        omega_p_rad_s: f64,
        planets: Vec<Planet>,
    ) -> Result<Self, OrbitError> {
        if !(pressure_angle_rad > 0.0 && pressure_angle_rad < FRAC_PI_2) {
            return Err(invalid(
                "pressure_angle",
                "must lie strictly between 0° and 90°",
            ));
        }
        if !theta_p0_rad.is_finite() {
            return Err(invalid("theta_p0", "must be finite"));
        }
        if !(omega_p_rad_s.is_finite() && omega_p_rad_s != 0.0) {
            return Err(invalid(
                "planet_speed",
                "must be finite and non-zero (signed, relative to the carrier)",
            ));
        }
        if planets.len() < 3 {
            return Err(invalid(
                "planet",
                format!(
                    "need at least 3 planets (got {}): the model has 3 unknowns x_s, y_s, c",
                    planets.len()
                ),
            ));
        }
        for (k, p) in planets.iter().enumerate() {
            if !p.position_rad.is_finite() {
                return Err(invalid(format!("planet[{k}].position"), "must be finite"));
            }
            if !(p.eccentricity_um.is_finite()
                && (0.0..=MAX_ECCENTRICITY_UM).contains(&p.eccentricity_um))
            {
                return Err(invalid(
                    format!("planet[{k}].eccentricity_um"),
                    format!("must be finite, ≥ 0 and ≤ {MAX_ECCENTRICITY_UM:e} µm (1 m)"),
                ));
            }
            if !p.phase_rad.is_finite() {
                return Err(invalid(format!("planet[{k}].phase"), "must be finite"));
            }
            for (j, q) in planets.iter().enumerate().take(k) {
                let gap = super::wrap_pi(p.position_rad - q.position_rad).abs();
                if gap < MIN_POSITION_GAP_RAD {
                    return Err(invalid(
                        format!("planet[{k}].position"),
                        format!("coincides with planet[{j}]"),
                    ));
                }
            }
        }
        Ok(Self {
            pressure_angle_rad,
            hand,
            theta_p0_rad,
            omega_p_rad_s,
            planets,
        })
    }

    /// Three equally spaced planets at 0°, 120°, 240° with eccentricities `e_um` and phases
    /// `theta_rad` (the docs/math/companion.md §A.10 test configuration when α = 20°, h = +1).
    ///
    /// # Errors
    /// As [`PlanetSet::new`].
    pub fn equally_spaced(
        pressure_angle_rad: f64,
        hand: Hand,
        theta_p0_rad: f64,
        omega_p_rad_s: f64,
        e_um: &[f64],
        theta_rad: &[f64],
    ) -> Result<Self, OrbitError> {
        if e_um.len() != theta_rad.len() {
            return Err(invalid(
                "planet",
                "eccentricity and phase lists differ in length",
            ));
        }
        let n = e_um.len();
        let planets = (0..n)
            .map(|k| Planet {
                position_rad: TAU * k as f64 / n as f64,
                eccentricity_um: e_um[k],
                phase_rad: theta_rad[k],
            })
            .collect();
        Self::new(
            pressure_angle_rad,
            hand,
            theta_p0_rad,
            omega_p_rad_s,
            planets,
        )
    }

    /// Working pressure angle α, rad.
    #[must_use]
    pub fn pressure_angle_rad(&self) -> f64 {
        self.pressure_angle_rad
    }
    /// Sun rotation sense.
    #[must_use]
    pub fn hand(&self) -> Hand {
        self.hand
    }
    /// Signed planet spin relative to the carrier ω_p, rad/s.
    #[must_use]
    pub fn omega_p_rad_s(&self) -> f64 {
        self.omega_p_rad_s
    }
    /// The planets.
    #[must_use]
    pub fn planets(&self) -> &[Planet] {
        &self.planets
    }

    /// External line-of-action angles `β_i = φ_i + h(π/2 − α)` (docs/math/companion.md §A.3), rad.
    #[must_use]
    pub fn line_of_action_angles_rad(&self) -> Vec<f64> {
        let b0 = self.hand.h() * (FRAC_PI_2 - self.pressure_angle_rad);
        self.planets.iter().map(|p| p.position_rad + b0).collect()
    }

    /// Planet eccentricity phasors `E_i = e_pi e^{i(θ_p0+θ_pi)}`, µm.
    #[must_use]
    pub fn phasors_um(&self) -> Vec<C64> {
        self.planets
            .iter()
            .map(|p| C64::from_polar(p.eccentricity_um, self.theta_p0_rad + p.phase_rad))
            .collect()
    }

    /// The linear map E → (P_x, P_y, P_c) of this geometry.
    #[must_use]
    pub fn kinematic_map(&self) -> KinematicMap {
        KinematicMap::new(
            &self.line_of_action_angles_rad(),
            2.0 * self.hand.h() * self.pressure_angle_rad.cos(),
            self.omega_p_rad_s,
        )
    }

    /// Solves the kinematic model (docs/math/companion.md §A.4 eq., least squares for N ≠ 3).
    #[must_use]
    pub fn solve(&self) -> KinematicSolution {
        let map = self.kinematic_map();
        let e = self.phasors_um();
        let [px, py, pc] = map.apply(&e);
        let beta = self.line_of_action_angles_rad();
        let (sc, ss) = beta
            .iter()
            .fold((0.0, 0.0), |(c, s), b| (c + b.cos(), s + b.sin()));
        let n = beta.len() as f64;
        // Σ n_ei = 0 to round-off ⇔ the LS solution is the equal-stiffness elastic equilibrium.
        let load_independent = sc.hypot(ss) <= 1e-9 * n;
        KinematicSolution {
            orbit: Orbit::from_sin_phasors(self.omega_p_rad_s, px, py),
            common_mode_um: pc,
            load_independent,
        }
    }

    /// Closed form (docs/math/companion.md §A.4 eq. A-3), valid for three equally spaced planets:
    /// `z_s(t) = (4 cos α/3) · i · Σ e_pi sin ψ_i e^{i(φ_i − hα)}`, µm. For cross-checking
    /// [`PlanetSet::solve`].
    #[must_use]
    pub fn closed_form_position_um(&self, t_s: f64) -> (f64, f64) {
        let a = self.pressure_angle_rad;
        let h = self.hand.h();
        let z: C64 = self
            .planets
            .iter()
            .map(|p| {
                let psi = self.omega_p_rad_s * t_s + self.theta_p0_rad + p.phase_rad;
                C64::from_polar(p.eccentricity_um * psi.sin(), p.position_rad - h * a)
            })
            .sum::<C64>()
            * C64::new(0.0, 4.0 * a.cos() / 3.0);
        (z.re, z.im)
    }
}

/// The patent's letters (docs/math/companion.md §A.4 eq. A-4) for three planets: `a = cos β₂ − cos β₁`, `b = sin β₂ − sin β₁`,
/// `c = cos β₃ − cos β₁`, `d = sin β₃ − sin β₁`; returns `[a, b, c, d]` (dimensionless).
///
/// # Errors
/// [`OrbitError::Invalid`] unless the set has exactly 3 planets.
pub fn patent_abcd(set: &PlanetSet) -> Result<[f64; 4], OrbitError> {
    let b = set.line_of_action_angles_rad();
    if b.len() != 3 {
        return Err(invalid(
            "planet",
            "the patent's a, b, c, d exist for exactly 3 planets",
        ));
    }
    Ok([
        b[1].cos() - b[0].cos(),
        b[1].sin() - b[0].sin(),
        b[2].cos() - b[0].cos(),
        b[2].sin() - b[0].sin(),
    ])
}

/// Group-5 form (docs/math/companion.md §A.4 eq. A-4) of the sun position for three planets, µm:
/// `x_s = 2h cos α/(bc−ad) [(d−b) q̃₁ − d q̃₂ + b q̃₃]`, `y_s = 2h cos α/(bc−ad) [(a−c) q̃₁ + c q̃₂ − a q̃₃]`,
/// `q̃_i = e_pi sin ψ_i`.
///
/// # Errors
/// As [`patent_abcd`].
pub fn patent_position_um(set: &PlanetSet, t_s: f64) -> Result<(f64, f64), OrbitError> {
    let [a, b, c, d] = patent_abcd(set)?;
    let q: Vec<f64> = set
        .planets
        .iter()
        .map(|p| {
            p.eccentricity_um * (set.omega_p_rad_s * t_s + set.theta_p0_rad + p.phase_rad).sin()
        })
        .collect();
    let k = 2.0 * set.hand.h() * set.pressure_angle_rad.cos() / (b * c - a * d);
    Ok((
        k * ((d - b) * q[0] - d * q[1] + b * q[2]),
        k * ((a - c) * q[0] + c * q[1] - a * q[2]),
    ))
}

/// Result of the kinematic model.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KinematicSolution {
    /// Sun orbit in the carrier frame.
    pub orbit: Orbit,
    /// Sine phasor P_c of the common-mode displacement along the lines of action
    /// `c(t) = Im(P_c e^{iω_p t})` (transmission error as a displacement), µm.
    pub common_mode_um: C64,
    /// `true` iff `Σ n_ei = 0` (equally spaced planets): the kinematic solution equals the
    /// equal-stiffness elastic one for any load. `false`: a load-dependent term exists and a
    /// stiffness model is needed (docs/math/companion.md §A.4).
    pub load_independent: bool,
}

/// The real 3×N matrix `G` with `[P_x, P_y, P_c]ᵀ = G E` (docs/math/companion.md §A.4 eq. A-1 solved by least squares):
/// `G = 2h cos α · (AᵀA)⁻¹Aᵀ`, rows of `A` = `[cos β_i, sin β_i, 1]`.
#[derive(Debug, Clone, PartialEq)]
pub struct KinematicMap {
    g: DMatrix<f64>,
    omega_p_rad_s: f64,
}

impl KinematicMap {
    fn new(beta_rad: &[f64], two_h_cos_alpha: f64, omega_p_rad_s: f64) -> Self {
        let n = beta_rad.len();
        let a = DMatrix::from_fn(n, 3, |i, j| match j {
            0 => beta_rad[i].cos(),
            1 => beta_rad[i].sin(),
            _ => 1.0,
        });
        let ata: Matrix3<f64> = (a.transpose() * &a).fixed_view::<3, 3>(0, 0).into_owned();
        // Distinct positions (checked in PlanetSet::new) with N ≥ 3 make AᵀA positive definite.
        let inv = ata.try_inverse().unwrap_or_else(Matrix3::zeros);
        let inv = DMatrix::from_fn(3, 3, |i, j| inv[(i, j)]);
        Self {
            g: inv * a.transpose() * two_h_cos_alpha,
            omega_p_rad_s,
        }
    }

    /// The 3×N matrix G (rows x, y, c), µm per µm.
    #[must_use]
    pub fn matrix(&self) -> &DMatrix<f64> {
        &self.g
    }

    /// Signed planet spin ω_p, rad/s.
    #[must_use]
    pub fn omega_p_rad_s(&self) -> f64 {
        self.omega_p_rad_s
    }

    /// `[P_x, P_y, P_c] = G E`, µm.
    #[must_use]
    pub fn apply(&self, e_um: &[C64]) -> [C64; 3] {
        let mut out = [C64::new(0.0, 0.0); 3];
        for (r, o) in out.iter_mut().enumerate() {
            *o = e_um
                .iter()
                .enumerate()
                .map(|(i, e)| e * self.g[(r, i)])
                .sum();
        }
        out
    }
}
