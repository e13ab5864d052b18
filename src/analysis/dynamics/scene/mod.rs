//! Scene files (TOML or JSON, docs/math/companion.md §B.10): every effect is off unless the scene names it. The
//! loader validates every value (key path + expected form in the error), prunes the DOF set and
//! builds the force-term list once.
//!
//! [`schema`] holds the file's serde types ([`settings`] those of `[solver]` and `[output]`), [`Scene::derived`] (here) the derived physical
//! parameters, and `build` turns a scene into a [`Model`](super::model::Model): one function per
//! effect, in `mesh` (stiffness law, STE, backlash, tip relief) and `terms` (the other effects).

mod build;
mod layout;
mod mesh;
pub mod schema;
pub mod settings;
mod terms;

pub use schema::*;
pub use settings::*;

use super::model::StiffnessLaw;
use super::tvms::PairGeometry;
use crate::bounds::{Span, number};
use crate::config::{self, ConfigError, Format};
use serde::Serialize;
use std::f64::consts::PI;
use std::path::Path;

/// A scene error: file, key path and what was expected.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SceneError {
    /// The file could not be read.
    #[error("cannot read scene file {file}: {message}")]
    Io {
        /// File path.
        file: String,
        /// The operating system's message.
        message: String,
    },
    /// Syntax error, unknown key or kind, missing key or wrong type (the parser names line and
    /// key).
    #[error("{file}: {message}")]
    Parse {
        /// File path.
        file: String,
        /// Parser message (line/column, key).
        message: String,
    },
    /// A value outside its domain.
    #[error("{file}: `{key}` = {found}: expected {expected}")]
    Invalid {
        /// File path.
        file: String,
        /// Dotted key path.
        key: String,
        /// What was found.
        found: String,
        /// The expected form.
        expected: String,
    },
}

impl From<ConfigError> for SceneError {
    fn from(e: ConfigError) -> Self {
        match e {
            ConfigError::Unreadable { file, message } => Self::Io { file, message },
            ConfigError::Parse { file, message } => Self::Parse { file, message },
        }
    }
}

/// Derived physical parameters reported in the run log.
#[derive(Debug, Clone, Serialize, schemars::JsonSchema)]
pub struct Derived {
    /// Geometry.
    pub geometry: PairGeometry,
    /// Gear masses, kg.
    pub mass_kg: [f64; 2],
    /// Gear inertias, kg·m².
    pub inertia_kgm2: [f64; 2],
    /// Equivalent mass m_e = J1J2/(J1 rb2² + J2 rb1²), kg.
    pub m_e_kg: f64,
    /// Mean mesh stiffness, N/m.
    pub k_mean_n_per_m: f64,
    /// Mesh damping c_m, N·s/m.
    pub c_m_n_s_per_m: f64,
    /// ωn = sqrt(k_mean/m_e), rad/s.
    pub omega_n_rad_s: f64,
    /// Mesh frequency ωe, rad/s.
    pub omega_e_rad_s: f64,
    /// Mesh period, s.
    pub t_mesh_s: f64,
    /// F0 = T1/rb1, N.
    pub f0_n: f64,
}

impl Scene {
    /// Reads a `.toml` or `.json` scene ([`Format::detect`]: by extension, else by content) and
    /// validates it.
    ///
    /// # Errors
    /// [`SceneError::Io`], [`SceneError::Parse`], [`SceneError::Invalid`].
    pub fn from_path(path: &Path) -> Result<Self, SceneError> {
        let src = config::Source::from_path(path)?;
        Self::parse(&src.text, &src.file, src.format)
    }

    /// Parses scene text in `format` and validates it; `file` names the source in errors.
    ///
    /// # Errors
    /// [`SceneError::Parse`], [`SceneError::Invalid`].
    pub fn parse(text: &str, file: &str, format: Format) -> Result<Self, SceneError> {
        let scene: Self = config::parse(text, file, format)?;
        scene.build(file)?;
        Ok(scene)
    }

    /// Derived parameters (geometry, masses, m_e, k_mean, c_m, ωn, ωe).
    ///
    /// # Errors
    /// [`SceneError::Invalid`] naming the key.
    pub fn derived(&self, file: &str) -> Result<Derived, SceneError> {
        let geom = self.geometry(file)?;
        let (mass, inertia) = self.bodies(file, &geom)?;
        let [rb1, rb2] = geom.rb_m;
        let m_e = inertia[0] * inertia[1] / (inertia[0] * rb2 * rb2 + inertia[1] * rb1 * rb1);
        let ms = self.mesh_spec(file)?;
        let law = mesh::stiffness_law(file, ms, geom.contact_ratio)?;
        let k_mean = match law {
            StiffnessLaw::Constant(k) => k,
            StiffnessLaw::Fourier(r, _) | StiffnessLaw::Rectangular(r) | StiffnessLaw::Pairs(r) => {
                r.mean()
            }
        };
        ranged(
            file,
            "effects.mesh_stiffness.zeta",
            ms.zeta(),
            Span::closed(0.0, 10.0),
            "a damping ratio (1 is critical)",
        )?;
        let c_m = 2.0 * ms.zeta() * (k_mean * m_e).sqrt();
        let (n1, t1) = self.operating_point(file)?;
        let omega_e = 2.0 * PI * n1 * self.gears.z1 as f64 / 60.0;
        let d = Derived {
            geometry: geom,
            mass_kg: mass,
            inertia_kgm2: inertia,
            m_e_kg: m_e,
            k_mean_n_per_m: k_mean,
            c_m_n_s_per_m: c_m,
            omega_n_rad_s: (k_mean / m_e).sqrt(),
            omega_e_rad_s: omega_e,
            t_mesh_s: 2.0 * PI / omega_e,
            f0_n: t1 / rb1,
        };
        check_derived(file, &d)?;
        Ok(d)
    }

    /// The pair geometry of `[gears]` (face width and density checked first).
    fn geometry(&self, file: &str) -> Result<PairGeometry, SceneError> {
        let g = &self.gears;
        ranged(
            file,
            "gears.face_width_mm",
            g.face_width_mm,
            Span::positive(1000.0),
            "a positive face width in mm",
        )?;
        ranged(
            file,
            "gears.density_kg_m3",
            g.density_kg_m3,
            Span::positive(30_000.0),
            "a positive density in kg/m³ (osmium is 22 590)",
        )?;
        PairGeometry::new(
            g.z1,
            g.z2,
            g.module_mm,
            g.pressure_angle_deg,
            g.addendum_coeff,
        )
        .ok_or_else(|| {
            invalid(
                file,
                "gears",
                format!(
                    "z1 = {}, z2 = {}, module_mm = {}, pressure_angle_deg = {}",
                    g.z1, g.z2, g.module_mm, g.pressure_angle_deg
                ),
                "z ≥ 5, module > 0, 0 < α < 45°, and a contact ratio 1 < ε < 2",
            )
        })
    }

    /// Masses (kg) and polar inertias (kg·m²) of the two gears: as given, or of solid discs of
    /// the pitch radius, `m = π r² b ρ`, `J = m r²/2`.
    fn bodies(&self, file: &str, geom: &PairGeometry) -> Result<([f64; 2], [f64; 2]), SceneError> {
        let g = &self.gears;
        let b = g.face_width_mm * 1e-3;
        let disc = |r: f64| {
            let m = PI * r * r * b * g.density_kg_m3;
            (m, 0.5 * m * r * r)
        };
        let (m1, j1) = disc(geom.r_m[0]);
        let (m2, j2) = disc(geom.r_m[1]);
        let mass = g.mass_kg.unwrap_or([m1, m2]);
        let inertia = g.inertia_kgm2.unwrap_or([j1, j2]);
        for i in 0..2 {
            pos(file, &format!("gears.mass_kg[{i}]"), mass[i])?;
            pos(file, &format!("gears.inertia_kgm2[{i}]"), inertia[i])?;
        }
        Ok((mass, inertia))
    }

    /// The checked input speed (rpm) and torque (N·m) of `[operating]`.
    fn operating_point(&self, file: &str) -> Result<(f64, f64), SceneError> {
        let n1 = self.operating.n1_rpm;
        if !(n1.is_finite() && n1 > 0.0 && n1 <= MAX_SPEED_RPM) {
            return Err(invalid(
                file,
                "operating.n1_rpm",
                n1.to_string(),
                "a positive speed in rpm, at most 1e6 (no gear drive turns faster; from about 1e11 \
                 rpm the mesh period is below what the integrator can step, and at 1e200 it \
                 never finished)",
            ));
        }
        let t1 = ranged(
            file,
            "operating.input_torque_Nm",
            self.operating.input_torque_Nm,
            Span::symmetric(1e7),
            "a torque in N·m (1e7: a ship's main gear)",
        )?;
        Ok((n1, t1))
    }

    /// `effects.mesh_stiffness`, which every scene needs.
    fn mesh_spec(&self, file: &str) -> Result<&MeshSpec, SceneError> {
        self.effects.mesh_stiffness.as_ref().ok_or_else(|| {
            invalid(
                file,
                "effects.mesh_stiffness",
                "missing".into(),
                "a table { kind = \"constant\" | \"fourier\" | \"rectangular\" | \"pairs\", ... , zeta = ... }",
            )
        })
    }
}

/// Fastest pinion speed a scene may ask for, rpm: 1e6 is beyond any gear drive (turbo gears run
/// at up to about 1e5), and far below the speeds whose mesh period the integrator cannot step.
pub const MAX_SPEED_RPM: f64 = 1e6;

/// [`SceneError::Invalid`] for `key` in `file`.
fn invalid(file: &str, key: &str, found: String, expected: &str) -> SceneError {
    SceneError::Invalid {
        file: file.into(),
        key: key.into(),
        found,
        expected: expected.into(),
    }
}

/// The cap of a scene number without a range of its own (stiffnesses, damping, masses,
/// inertias in SI; radii in mm): a steel mesh is about 1e9 N/m, and no quantity of a gear pair
/// in its unit reaches 1e15, while the product of two such stays far from overflow.
pub const MAX_MAGNITUDE: f64 = 1e15;

/// An error, gap, relief, eccentricity or clearance, µm: 10 mm is a module of large gears;
/// beyond, the pair is not in mesh.
pub const ERROR_UM: Span = Span::symmetric(1e4);

/// A phase, degrees: ten turns either way.
pub const PHASE_DEG: Span = Span::symmetric(3600.0);

/// `v` finite and within `span`, or [`SceneError::Invalid`] naming `key`, the value and the span.
fn ranged(file: &str, key: &str, v: f64, span: Span, what: &str) -> Result<f64, SceneError> {
    span.check(v, what)
        .map_err(|m| invalid(file, key, number(v), &m))
}

/// `v` must be finite and in (0, [`MAX_MAGNITUDE`]].
fn pos(file: &str, key: &str, v: f64) -> Result<(), SceneError> {
    ranged(
        file,
        key,
        v,
        Span::positive(MAX_MAGNITUDE),
        "a positive number of physical size",
    )
    .map(drop)
}

/// `v` must be finite and in [0, [`MAX_MAGNITUDE`]].
fn nonneg(file: &str, key: &str, v: f64) -> Result<(), SceneError> {
    ranged(
        file,
        key,
        v,
        Span::closed(0.0, MAX_MAGNITUDE),
        "a number ≥ 0 of physical size",
    )
    .map(drop)
}

/// Each input is finite, but extreme ones can still overflow a derived quantity: refuses a
/// non-finite (or, for masses, stiffnesses and frequencies, non-positive) one, naming the inputs
/// it comes from.
fn check_derived(file: &str, d: &Derived) -> Result<(), SceneError> {
    // (value, name, input keys, whether it must be > 0)
    for (v, what, keys, positive) in [
        (
            d.m_e_kg,
            "m_e",
            "gears.inertia_kgm2 / gears.module_mm",
            true,
        ),
        (d.k_mean_n_per_m, "k_mean", "effects.mesh_stiffness", true),
        (
            d.omega_n_rad_s,
            "ωn",
            "effects.mesh_stiffness / gears",
            true,
        ),
        (d.omega_e_rad_s, "ωe", "operating.n1_rpm", true),
        (d.t_mesh_s, "T_mesh", "operating.n1_rpm", true),
        (d.c_m_n_s_per_m, "c_m", "effects.mesh_stiffness.zeta", false),
        (d.f0_n, "F0 = T1/rb1", "operating.input_torque_Nm", false),
    ] {
        let sign_ok = !positive || v > 0.0;
        if !(v.is_finite() && sign_ok) {
            return Err(invalid(
                file,
                keys,
                format!("values giving {what} = {v:e}"),
                "values of physical size (the derived quantity must be finite, and > 0 for masses, stiffnesses and frequencies)",
            ));
        }
    }
    Ok(())
}
