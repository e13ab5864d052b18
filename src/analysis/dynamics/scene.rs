//! Scene files (TOML or JSON, spec B.10): every effect is off unless the scene names it. The
//! loader validates every value (key path + expected form in the error), prunes the DOF set and
//! builds the force-term list once.

use super::model::*;
use super::tvms::{PairGeometry, RectangularTvms};
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;
use std::path::Path;
use std::sync::Arc;

/// A scene error: file, key path and what was expected.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SceneError {
    /// The file could not be read.
    #[error("cannot read scene file {file}: {source}")]
    Io {
        /// File path.
        file: String,
        /// Cause.
        source: std::io::Error,
    },
    /// Syntax error, unknown key, missing key or wrong type (the parser names line and key).
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

/// `[scene]`.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct SceneMeta {
    /// Scene name.
    pub name: String,
    /// Model kind: only `spur_pair`.
    pub model: String,
    /// `auto` (prune DOFs, B.10) or `full` (keep every lateral DOF, e.g. for eigen-analysis).
    #[serde(default = "auto")]
    pub dofs: String,
}

fn auto() -> String {
    "auto".into()
}

/// `[gears]`: standard involute spur pair; masses default to solid steel discs.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct GearsSpec {
    /// Pinion teeth.
    pub z1: u32,
    /// Gear teeth.
    pub z2: u32,
    /// Module, mm.
    pub module_mm: f64,
    /// Pressure angle, degrees.
    pub pressure_angle_deg: f64,
    /// Face width, mm.
    pub face_width_mm: f64,
    /// Addendum coefficient h_a* (default 1).
    #[serde(default = "one")]
    pub addendum_coeff: f64,
    /// Density for the disc masses, kg/m³ (default 7850).
    #[serde(default = "steel")]
    pub density_kg_m3: f64,
    /// Override of the gear masses [m1, m2], kg.
    pub mass_kg: Option<[f64; 2]>,
    /// Override of the gear inertias [J1, J2], kg·m².
    pub inertia_kgm2: Option<[f64; 2]>,
}

fn one() -> f64 {
    1.0
}
fn steel() -> f64 {
    7850.0
}

/// `[operating]`.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)]
pub struct Operating {
    /// Pinion speed, rpm.
    pub n1_rpm: f64,
    /// Input torque on the pinion side, N·m.
    pub input_torque_Nm: f64,
}

/// `effects.mesh_stiffness` (required).
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct MeshSpec {
    /// `constant` | `fourier` | `rectangular` | `pairs`.
    pub kind: String,
    /// Double-contact stiffness, N/m (not for `constant`).
    pub kmax: Option<f64>,
    /// Single-contact stiffness, N/m (not for `constant`).
    pub kmin: Option<f64>,
    /// Constant stiffness, N/m (`constant` only).
    pub k: Option<f64>,
    /// Harmonics of the `fourier` kind (default 9).
    pub n: Option<u32>,
    /// Mesh damping ratio ζ_m: c_m = 2ζ_m sqrt(k_mean m_e).
    pub zeta: f64,
}

/// `effects.static_te`.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct SteSpec {
    /// Mean e0, µm.
    #[serde(default)]
    pub e0_um: f64,
    /// Amplitude er, µm.
    pub er_um: f64,
    /// Phase, degrees.
    #[serde(default)]
    pub phase_deg: f64,
}

/// `effects.backlash`.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct BacklashSpec {
    /// HALF of the backlash b, µm.
    pub half_gap_um: f64,
    /// Mesh damping also inside the gap (default true, Kahraman–Singh).
    #[serde(default = "yes")]
    pub damping_in_gap: bool,
    /// Clamp pulling forces (default false).
    #[serde(default)]
    pub no_tension: bool,
}

fn yes() -> bool {
    true
}

/// `effects.tip_relief`.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ReliefSpec {
    /// Δmax, µm.
    pub delta_max_um: f64,
    /// Relief length along the line of action, mm.
    pub length_mm: f64,
    /// Only `linear`.
    #[serde(default = "linear")]
    pub kind: String,
}

fn linear() -> String {
    "linear".into()
}

/// `effects.friction`.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct FrictionSpec {
    /// Coefficient μ.
    pub mu: f64,
    /// `pitch_switch` | `tanh`.
    pub direction: String,
    /// Velocity scale of `tanh`, m/s.
    pub v0: Option<f64>,
}

/// One gear's eccentricity.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct EccSpec {
    /// Mass-centre offset ρ, µm.
    pub rho_um: f64,
    /// Phase, degrees.
    #[serde(default)]
    pub phase_deg: f64,
    /// Only `unbalance` (the exact state-dependent mass matrix is not implemented).
    #[serde(default = "unbalance")]
    pub kind: String,
}

fn unbalance() -> String {
    "unbalance".into()
}

/// `effects.eccentricity`.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct EccentricitySpec {
    /// Pinion.
    pub pinion: Option<EccSpec>,
    /// Gear.
    pub gear: Option<EccSpec>,
}

/// `effects.gravity`.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct GravitySpec {
    /// Gravity in the model frame (x ⊥, y ∥ line of action), m/s².
    pub g: [f64; 2],
}

/// `effects.shafts`: torsion, bending, motor/load inertias and bearing masses.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ShaftSpec {
    /// Torsional stiffness [kt1, kt2], N·m/rad.
    pub kt: [f64; 2],
    /// Torsional damping [ct1, ct2], N·m·s/rad (default 0).
    #[serde(default)]
    pub ct: [f64; 2],
    /// Bending stiffness at the gear [ks1, ks2], N/m; absent = shafts rigid in bending (then
    /// only torsion is modelled and the bearings must be rigid).
    pub ks: Option<[f64; 2]>,
    /// Bending damping [cs1, cs2], N·s/m (default 0).
    #[serde(default)]
    pub cs: [f64; 2],
    /// Position coefficients [η1, η2, η3, η4].
    pub eta: [f64; 4],
    /// Motor and load inertias [Jp, Jq], kg·m².
    pub j_kgm2: [f64; 2],
    /// Bearing masses [mb1..mb4], kg (used when the bearings are not rigid).
    pub mb_kg: [f64; 4],
}

/// `effects.bearings`.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)]
pub struct BearingSpec {
    /// `rigid` | `linear` | `hertz`.
    pub law: String,
    /// Linear stiffness, N/m (`linear`).
    pub kb: Option<f64>,
    /// Damping, N·s/m (default 0).
    #[serde(default)]
    pub cb: f64,
    /// Hertz contact constant, N/m^p.
    pub Kc: Option<f64>,
    /// Rolling elements.
    pub Nb: Option<u32>,
    /// Radial clearance γ0, µm.
    pub clearance_um: Option<f64>,
    /// Load–deflection exponent (1.5 ball, 10/9 roller).
    pub exponent: Option<f64>,
    /// Inner-race radius r′, mm.
    pub r_in_mm: Option<f64>,
    /// Outer-race radius R′, mm.
    pub R_out_mm: Option<f64>,
}

/// `[effects]`: a key that is absent = that effect is OFF.
#[derive(Debug, Clone, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Effects {
    /// Mesh stiffness (required).
    pub mesh_stiffness: Option<MeshSpec>,
    /// Static transmission error.
    pub static_te: Option<SteSpec>,
    /// Backlash.
    pub backlash: Option<BacklashSpec>,
    /// Tip relief.
    pub tip_relief: Option<ReliefSpec>,
    /// Sliding friction.
    pub friction: Option<FrictionSpec>,
    /// Eccentricity.
    pub eccentricity: Option<EccentricitySpec>,
    /// Gravity.
    pub gravity: Option<GravitySpec>,
    /// Shafts.
    pub shafts: Option<ShaftSpec>,
    /// Bearings.
    pub bearings: Option<BearingSpec>,
}

/// `[solver]`.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct SolverSpec {
    /// `auto` | `dopri5` | `rk4` | `linear`.
    #[serde(default = "auto")]
    pub method: String,
    /// Relative tolerance.
    #[serde(default = "rtol")]
    pub rtol: f64,
    /// Absolute tolerance (m, rad, m/s units mixed; default 1e-12).
    #[serde(default = "atol")]
    pub atol: f64,
    /// Split the integration at the known switch times (default true).
    #[serde(default = "yes")]
    pub breakpoints: bool,
    /// Locate contact loss/re-contact events (default true).
    #[serde(default = "yes")]
    pub events: bool,
    /// RK4 steps per mesh period.
    #[serde(default = "steps")]
    pub rk4_steps_per_mesh: u32,
    /// Recorded window after the steady state, mesh periods.
    #[serde(default = "record")]
    pub record_mesh_periods: u32,
    /// Steady-state criterion.
    #[serde(default)]
    pub steady_state: SteadySpec,
}

impl Default for SolverSpec {
    fn default() -> Self {
        Self {
            method: auto(),
            rtol: rtol(),
            atol: atol(),
            breakpoints: true,
            events: true,
            rk4_steps_per_mesh: steps(),
            record_mesh_periods: record(),
            steady_state: SteadySpec::default(),
        }
    }
}

fn rtol() -> f64 {
    1e-6
}
fn atol() -> f64 {
    1e-12
}
fn steps() -> u32 {
    80
}
fn record() -> u32 {
    200
}

/// Poincaré steady-state criterion.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct SteadySpec {
    /// Relative change of the Poincaré sample below which the run is steady.
    #[serde(default = "ptol")]
    pub poincare_tol: f64,
    /// Maximal transient, Poincaré periods.
    #[serde(default = "maxp")]
    pub max_periods: u32,
}

impl Default for SteadySpec {
    fn default() -> Self {
        Self {
            poincare_tol: ptol(),
            max_periods: maxp(),
        }
    }
}

fn ptol() -> f64 {
    1e-7
}
fn maxp() -> u32 {
    2000
}

/// `[output]`.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct OutputSpec {
    /// Signals: `dte`, `mesh_force`, or DOF names.
    #[serde(default = "signals")]
    pub signals: Vec<String>,
    /// Samples per mesh period.
    #[serde(default = "spm")]
    pub samples_per_mesh: u32,
    /// Compute the DTE spectrum.
    #[serde(default = "yes")]
    pub spectrum: bool,
    /// Orbits: `pinion` and/or `gear`.
    #[serde(default)]
    pub orbit: Vec<String>,
}

impl Default for OutputSpec {
    fn default() -> Self {
        Self {
            signals: signals(),
            samples_per_mesh: spm(),
            spectrum: true,
            orbit: Vec::new(),
        }
    }
}

fn signals() -> Vec<String> {
    vec!["dte".into(), "mesh_force".into()]
}
fn spm() -> u32 {
    64
}

/// A whole scene file.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// `[scene]`.
    pub scene: SceneMeta,
    /// `[gears]`.
    pub gears: GearsSpec,
    /// `[operating]`.
    pub operating: Operating,
    /// `[effects]`.
    pub effects: Effects,
    /// `[solver]`.
    #[serde(default)]
    pub solver: SolverSpec,
    /// `[output]`.
    #[serde(default)]
    pub output: OutputSpec,
}

/// Derived physical parameters reported in the run log.
#[derive(Debug, Clone, Serialize)]
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
    /// Mesh damping, N·s/m.
    pub c_m: f64,
    /// ωn = sqrt(k_mean/m_e), rad/s.
    pub omega_n: f64,
    /// Mesh frequency ωe, rad/s.
    pub omega_e: f64,
    /// Mesh period, s.
    pub t_mesh_s: f64,
    /// F0 = T1/rb1, N.
    pub f0_n: f64,
}

impl Scene {
    /// Reads a `.toml` or `.json` scene (by extension; anything else is tried as TOML).
    pub fn from_path(path: &Path) -> Result<Self, SceneError> {
        let file = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|source| SceneError::Io {
            file: file.clone(),
            source,
        })?;
        let json = path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("json"));
        Self::from_str(&text, json, &file)
    }

    /// Parses scene text (`json` = true for JSON); `file` names the source in errors.
    pub fn from_str(text: &str, json: bool, file: &str) -> Result<Self, SceneError> {
        let parsed: Result<Self, String> = if json {
            serde_json::from_str(text).map_err(|e| e.to_string())
        } else {
            toml::from_str(text).map_err(|e| e.to_string())
        };
        let scene = parsed.map_err(|message| SceneError::Parse {
            file: file.into(),
            message,
        })?;
        scene.build_checked(file)?;
        Ok(scene)
    }

    fn build_checked(&self, file: &str) -> Result<(), SceneError> {
        self.build(file).map(|_| ())
    }

    /// Derived parameters (geometry, masses, m_e, k_mean, c_m, ωn, ωe).
    pub fn derived(&self, file: &str) -> Result<Derived, SceneError> {
        let bad = |key: &str, found: String, expected: &str| SceneError::Invalid {
            file: file.into(),
            key: key.into(),
            found,
            expected: expected.into(),
        };
        let g = &self.gears;
        pos(file, "gears.face_width_mm", g.face_width_mm)?;
        pos(file, "gears.density_kg_m3", g.density_kg_m3)?;
        let geom = PairGeometry::new(
            g.z1,
            g.z2,
            g.module_mm,
            g.pressure_angle_deg,
            g.addendum_coeff,
        )
        .ok_or_else(|| {
            bad(
                "gears",
                format!(
                    "z1 = {}, z2 = {}, module_mm = {}, pressure_angle_deg = {}",
                    g.z1, g.z2, g.module_mm, g.pressure_angle_deg
                ),
                "z ≥ 5, module > 0, 0 < α < 45°, and a contact ratio 1 < ε < 2",
            )
        })?;
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
        let [rb1, rb2] = geom.rb_m;
        let m_e = inertia[0] * inertia[1] / (inertia[0] * rb2 * rb2 + inertia[1] * rb1 * rb1);
        let ms = self
            .effects
            .mesh_stiffness
            .as_ref()
            .ok_or_else(|| bad("effects.mesh_stiffness", "missing".into(), "a table { kind = \"constant\" | \"fourier\" | \"rectangular\" | \"pairs\", ... , zeta = ... }"))?;
        let law = self.law(file, ms, geom.contact_ratio)?;
        let k_mean = match law {
            StiffnessLaw::Constant(k) => k,
            StiffnessLaw::Fourier(r, _) | StiffnessLaw::Rectangular(r) | StiffnessLaw::Pairs(r) => {
                r.mean()
            }
        };
        nonneg(file, "effects.mesh_stiffness.zeta", ms.zeta)?;
        let c_m = 2.0 * ms.zeta * (k_mean * m_e).sqrt();
        let n1 = self.operating.n1_rpm;
        if !(n1.is_finite() && n1 > 0.0) {
            return Err(bad(
                "operating.n1_rpm",
                n1.to_string(),
                "a positive speed in rpm",
            ));
        }
        let t1 = self.operating.input_torque_Nm;
        if !t1.is_finite() {
            return Err(bad(
                "operating.input_torque_Nm",
                t1.to_string(),
                "a finite torque in N·m",
            ));
        }
        let omega_e = 2.0 * PI * n1 * g.z1 as f64 / 60.0;
        let d = Derived {
            geometry: geom,
            mass_kg: mass,
            inertia_kgm2: inertia,
            m_e_kg: m_e,
            k_mean_n_per_m: k_mean,
            c_m,
            omega_n: (k_mean / m_e).sqrt(),
            omega_e,
            t_mesh_s: 2.0 * PI / omega_e,
            f0_n: t1 / rb1,
        };
        // Each input is finite, but extreme ones can still overflow a derived quantity: name the
        // inputs it comes from.
        // (value, name, input keys, whether it must be > 0)
        for (v, what, keys, positive) in [
            (
                d.m_e_kg,
                "m_e",
                "gears.inertia_kgm2 / gears.module_mm",
                true,
            ),
            (d.k_mean_n_per_m, "k_mean", "effects.mesh_stiffness", true),
            (d.omega_n, "ωn", "effects.mesh_stiffness / gears", true),
            (d.omega_e, "ωe", "operating.n1_rpm", true),
            (d.t_mesh_s, "T_mesh", "operating.n1_rpm", true),
            (d.c_m, "c_m", "effects.mesh_stiffness.zeta", false),
            (d.f0_n, "F0 = T1/rb1", "operating.input_torque_Nm", false),
        ] {
            let sign_ok = !positive || v > 0.0;
            if !(v.is_finite() && sign_ok) {
                return Err(bad(
                    keys,
                    format!("values giving {what} = {v:e}"),
                    "values of physical size (the derived quantity must be finite, and > 0 for masses, stiffnesses and frequencies)",
                ));
            }
        }
        Ok(d)
    }

    fn law(&self, file: &str, ms: &MeshSpec, eps: f64) -> Result<StiffnessLaw, SceneError> {
        let key = "effects.mesh_stiffness";
        let need = |name: &str, v: Option<f64>| -> Result<f64, SceneError> {
            let v = v.ok_or_else(|| SceneError::Invalid {
                file: file.into(),
                key: format!("{key}.{name}"),
                found: "missing".into(),
                expected: format!(
                    "a positive stiffness in N/m (required by kind = \"{}\")",
                    ms.kind
                ),
            })?;
            pos(file, &format!("{key}.{name}"), v)?;
            Ok(v)
        };
        let rect = || -> Result<RectangularTvms, SceneError> {
            let kmax = need("kmax", ms.kmax)?;
            let kmin = need("kmin", ms.kmin)?;
            if kmin > kmax {
                return Err(SceneError::Invalid {
                    file: file.into(),
                    key: format!("{key}.kmin"),
                    found: kmin.to_string(),
                    expected: format!("kmin ≤ kmax = {kmax}"),
                });
            }
            Ok(RectangularTvms { kmax, kmin, eps })
        };
        Ok(match ms.kind.as_str() {
            "constant" => StiffnessLaw::Constant(need("k", ms.k)?),
            "fourier" => StiffnessLaw::Fourier(rect()?, ms.n.unwrap_or(9)),
            "rectangular" => StiffnessLaw::Rectangular(rect()?),
            "pairs" => StiffnessLaw::Pairs(rect()?),
            other => {
                return Err(SceneError::Invalid {
                    file: file.into(),
                    key: format!("{key}.kind"),
                    found: format!("\"{other}\""),
                    expected: "\"constant\" | \"fourier\" | \"rectangular\" | \"pairs\"".into(),
                });
            }
        })
    }

    /// Builds the model: DOF pruning (16 / 6 / 4 / 2 / 1), term list, derived parameters.
    pub fn build(&self, file: &str) -> Result<(Model, Derived), SceneError> {
        let d = self.derived(file)?;
        let e = &self.effects;
        let bad = |key: &str, found: String, expected: &str| SceneError::Invalid {
            file: file.into(),
            key: key.into(),
            found,
            expected: expected.into(),
        };
        if self.scene.model != "spur_pair" {
            return Err(bad(
                "scene.model",
                format!("\"{}\"", self.scene.model),
                "\"spur_pair\" (planetary is not implemented)",
            ));
        }
        let full = match self.scene.dofs.as_str() {
            "auto" => false,
            "full" => true,
            o => return Err(bad("scene.dofs", format!("\"{o}\""), "\"auto\" | \"full\"")),
        };
        // bearings
        #[derive(PartialEq)]
        enum Law {
            Rigid,
            Linear(f64),
            Hertz {
                kc: f64,
                nb: u32,
                gamma0: f64,
                p: f64,
                ratio: f64,
            },
        }
        let (blaw, cb) = match &e.bearings {
            None => (Law::Rigid, 0.0),
            Some(b) => {
                nonneg(file, "effects.bearings.cb", b.cb)?;
                let law = match b.law.as_str() {
                    "rigid" => Law::Rigid,
                    "linear" => {
                        let kb = b.kb.ok_or_else(|| {
                            bad(
                                "effects.bearings.kb",
                                "missing".into(),
                                "a positive stiffness in N/m",
                            )
                        })?;
                        pos(file, "effects.bearings.kb", kb)?;
                        Law::Linear(kb)
                    }
                    "hertz" => {
                        let req =
                            |k: &str, v: Option<f64>, what: &str| -> Result<f64, SceneError> {
                                let v = v.ok_or_else(|| {
                                    bad(&format!("effects.bearings.{k}"), "missing".into(), what)
                                })?;
                                if !(v.is_finite() && v >= 0.0) {
                                    return Err(bad(
                                        &format!("effects.bearings.{k}"),
                                        v.to_string(),
                                        what,
                                    ));
                                }
                                Ok(v)
                            };
                        let kc = req("Kc", b.Kc, "a positive contact constant in N/m^p")?;
                        pos(file, "effects.bearings.Kc", kc)?;
                        let nb = b.Nb.ok_or_else(|| {
                            bad(
                                "effects.bearings.Nb",
                                "missing".into(),
                                "the number of rolling elements (≥ 3)",
                            )
                        })?;
                        if nb < 3 {
                            return Err(bad(
                                "effects.bearings.Nb",
                                nb.to_string(),
                                "the number of rolling elements (≥ 3)",
                            ));
                        }
                        let gamma0 = req(
                            "clearance_um",
                            b.clearance_um,
                            "a radial clearance ≥ 0 in µm",
                        )? * 1e-6;
                        let p = req("exponent", b.exponent, "1.5 (ball) or 1.111 (roller)")?;
                        if !(1.0..=2.0).contains(&p) {
                            return Err(bad(
                                "effects.bearings.exponent",
                                p.to_string(),
                                "1 ≤ p ≤ 2 (1.5 ball, 10/9 roller)",
                            ));
                        }
                        let ri = req("r_in_mm", b.r_in_mm, "the inner-race radius in mm (> 0)")?;
                        let ro = req(
                            "R_out_mm",
                            b.R_out_mm,
                            "the outer-race radius in mm (> r_in_mm)",
                        )?;
                        if !(ri > 0.0 && ro > ri) {
                            return Err(bad(
                                "effects.bearings.R_out_mm",
                                ro.to_string(),
                                "the outer-race radius in mm, greater than r_in_mm > 0",
                            ));
                        }
                        Law::Hertz {
                            kc,
                            nb,
                            gamma0,
                            p,
                            ratio: ri / (ri + ro),
                        }
                    }
                    o => {
                        return Err(bad(
                            "effects.bearings.law",
                            format!("\"{o}\""),
                            "\"rigid\" | \"linear\" | \"hertz\"",
                        ));
                    }
                };
                (law, b.cb)
            }
        };
        let shafts = e.shafts.as_ref();
        if let Some(s) = shafts {
            for i in 0..2 {
                pos(file, &format!("effects.shafts.kt[{i}]"), s.kt[i])?;
                if let Some(ks) = s.ks {
                    pos(file, &format!("effects.shafts.ks[{i}]"), ks[i])?;
                }
                pos(file, &format!("effects.shafts.j_kgm2[{i}]"), s.j_kgm2[i])?;
                nonneg(file, &format!("effects.shafts.ct[{i}]"), s.ct[i])?;
                nonneg(file, &format!("effects.shafts.cs[{i}]"), s.cs[i])?;
            }
            for i in 0..4 {
                pos(file, &format!("effects.shafts.mb_kg[{i}]"), s.mb_kg[i])?;
                if !(0.0..=1.0).contains(&s.eta[i]) {
                    return Err(bad(
                        &format!("effects.shafts.eta[{i}]"),
                        s.eta[i].to_string(),
                        "a position coefficient in [0, 1]",
                    ));
                }
            }
            for (a, b) in [(0, 1), (2, 3)] {
                if (s.eta[a] + s.eta[b] - 1.0).abs() > 1e-9 {
                    return Err(bad(
                        &format!("effects.shafts.eta[{a}]"),
                        format!("{} + {}", s.eta[a], s.eta[b]),
                        "η1 + η2 = 1 and η3 + η4 = 1 (η_i = l_bi / l)",
                    ));
                }
            }
        }
        let soft_bearings = blaw != Law::Rigid;
        if shafts.is_some_and(|s| s.ks.is_none()) && soft_bearings {
            return Err(bad(
                "effects.shafts.ks",
                "missing".into(),
                "bending stiffnesses [ks1, ks2] in N/m (required with non-rigid bearings)",
            ));
        }
        let bending = shafts.is_some_and(|s| s.ks.is_some());
        let lateral = bending || soft_bearings;
        let hertz = matches!(blaw, Law::Hertz { .. });
        let x_forced = e.friction.is_some()
            || e.eccentricity.is_some()
            || e.gravity.as_ref().is_some_and(|g| g.g[0] != 0.0)
            || hertz;
        if !lateral {
            if e.eccentricity.is_some() {
                return Err(bad(
                    "effects.eccentricity",
                    "set".into(),
                    "lateral DOFs: add effects.bearings (non-rigid) or effects.shafts",
                ));
            }
            if e.gravity.is_some() {
                return Err(bad(
                    "effects.gravity",
                    "set".into(),
                    "lateral DOFs: add effects.bearings (non-rigid) or effects.shafts",
                ));
            }
        }
        let with_x = lateral && (x_forced || full);
        let friction = e.friction.is_some();
        // DOF selection (indices into DOF_NAMES)
        let mut dofs: Vec<usize> = Vec::new();
        let sdof = !lateral && shafts.is_none() && !friction;
        let ks = shafts.and_then(|s| s.ks).unwrap_or([0.0; 2]);
        if sdof {
            dofs.push(16);
        } else {
            for (i, name) in DOF_NAMES.iter().enumerate().take(16) {
                let keep = match *name {
                    "theta_p" | "theta_q" => shafts.is_some(),
                    "theta1" | "theta2" => true,
                    "x1" | "x2" => with_x,
                    "y1" | "y2" => lateral,
                    n if n.starts_with("xb") => shafts.is_some() && soft_bearings && with_x,
                    n if n.starts_with("yb") => shafts.is_some() && soft_bearings,
                    _ => false,
                };
                if keep {
                    dofs.push(i);
                }
            }
        }
        let idx = |name: &str| dofs.iter().position(|&k| DOF_NAMES[k] == name);
        let [m1, m2] = d.mass_kg;
        let [j1, j2] = d.inertia_kgm2;
        let mass: Vec<f64> = dofs
            .iter()
            .map(|&k| match DOF_NAMES[k] {
                "theta_p" => shafts.map_or(0.0, |s| s.j_kgm2[0]),
                "theta_q" => shafts.map_or(0.0, |s| s.j_kgm2[1]),
                "x1" | "y1" => m1,
                "x2" | "y2" => m2,
                "theta1" => j1,
                "theta2" => j2,
                "u" => d.m_e_kg,
                n => {
                    let b: usize = n[2..].parse().unwrap_or(1);
                    shafts.map_or(1.0, |s| s.mb_kg[b - 1])
                }
            })
            .collect();
        let geom = d.geometry;
        let [rb1, rb2] = geom.rb_m;
        let coeffs: Vec<(usize, f64)> = if sdof {
            vec![(0, 1.0)]
        } else {
            [("y1", 1.0), ("y2", -1.0), ("theta1", rb1), ("theta2", -rb2)]
                .iter()
                .filter_map(|&(n, c)| idx(n).map(|i| (i, c)))
                .collect()
        };
        let ste = match &e.static_te {
            Some(s) => {
                nonneg(file, "effects.static_te.er_um", s.er_um)?;
                finite(file, "effects.static_te.e0_um", s.e0_um)?;
                finite(file, "effects.static_te.phase_deg", s.phase_deg)?;
                Some(Ste {
                    e0: s.e0_um * 1e-6,
                    er: s.er_um * 1e-6,
                    phase: s.phase_deg.to_radians(),
                })
            }
            None => None,
        };
        let backlash = match &e.backlash {
            Some(b) => {
                pos(file, "effects.backlash.half_gap_um", b.half_gap_um)?;
                Some(Backlash {
                    b: b.half_gap_um * 1e-6,
                    damping_in_gap: b.damping_in_gap,
                    no_tension: b.no_tension,
                })
            }
            None => None,
        };
        let pb = geom.base_pitch_m;
        let relief = match &e.tip_relief {
            Some(r) => {
                if r.kind != "linear" {
                    return Err(bad(
                        "effects.tip_relief.kind",
                        format!("\"{}\"", r.kind),
                        "\"linear\"",
                    ));
                }
                nonneg(file, "effects.tip_relief.delta_max_um", r.delta_max_um)?;
                let lmax = (geom.contact_ratio - 1.0) * pb * 1e3;
                if !(r.length_mm > 0.0 && r.length_mm <= lmax + 1e-12) {
                    return Err(bad(
                        "effects.tip_relief.length_mm",
                        r.length_mm.to_string(),
                        &format!(
                            "a relief length along the line of action in mm, 0 < L ≤ (ε−1)·pb = {lmax:.4}"
                        ),
                    ));
                }
                Some(Relief {
                    delta_max: r.delta_max_um * 1e-6,
                    length: r.length_mm * 1e-3,
                })
            }
            None => None,
        };
        let law = self.law(
            file,
            e.mesh_stiffness
                .as_ref()
                .ok_or_else(|| bad("effects.mesh_stiffness", "missing".into(), "a table"))?,
            geom.contact_ratio,
        )?;
        let omega1 = d.omega_e / self.gears.z1 as f64;
        let omega2 = d.omega_e / self.gears.z2 as f64;
        let core = Arc::new(MeshCore {
            coeffs,
            law,
            c_m: d.c_m,
            t0: d.t_mesh_s,
            eps: geom.contact_ratio,
            omega_e: d.omega_e,
            ste,
            backlash,
            relief,
            contact_length: geom.contact_ratio * pb,
            per_pair: relief.is_some() || friction || matches!(law, StiffnessLaw::Pairs(_)),
        });
        let mut terms: Vec<Box<dyn ForceTerm>> = vec![Box::new(MeshTerm { core: core.clone() })];
        // drive and load torques (static balance Mq = Mp rb2/rb1)
        let mp = self.operating.input_torque_Nm;
        let mq = mp * rb2 / rb1;
        if sdof {
            terms.push(Box::new(ConstantForce {
                label: format!("load(F0 = {:.4} N on u)", d.f0_n),
                forces: vec![(0, d.f0_n)],
            }));
        } else {
            let (a, b) = if shafts.is_some() {
                ("theta_p", "theta_q")
            } else {
                ("theta1", "theta2")
            };
            let forces = vec![(idx(a).unwrap_or(0), mp), (idx(b).unwrap_or(0), -mq)];
            terms.push(Box::new(ConstantForce {
                label: format!("torques(Mp = {mp} N·m on {a}, Mq = {mq:.4} N·m on {b})"),
                forces,
            }));
        }
        if let Some(f) = &e.friction {
            if !(f.mu.is_finite() && (0.0..1.0).contains(&f.mu)) {
                return Err(bad(
                    "effects.friction.mu",
                    f.mu.to_string(),
                    "a friction coefficient 0 ≤ μ < 1",
                ));
            }
            let direction = match (f.direction.as_str(), f.v0) {
                ("pitch_switch", _) => FrictionDirection::PitchSwitch,
                ("tanh", Some(v0)) if v0 > 0.0 => FrictionDirection::Tanh(v0),
                ("tanh", v) => {
                    return Err(bad(
                        "effects.friction.v0",
                        format!("{v:?}"),
                        "a positive velocity scale in m/s (required by direction = \"tanh\")",
                    ));
                }
                (o, _) => {
                    return Err(bad(
                        "effects.friction.direction",
                        format!("\"{o}\""),
                        "\"pitch_switch\" | \"tanh\"",
                    ));
                }
            };
            terms.push(Box::new(FrictionTerm {
                core: core.clone(),
                mu: f.mu,
                direction,
                geom,
                omega: [omega1, omega2],
                idx: [idx("x1"), idx("x2"), idx("theta1"), idx("theta2")],
            }));
        }
        if let Some(s) = shafts {
            terms.push(Box::new(LinearSpring {
                label: format!("shaft1 torsion(kt = {} N·m/rad)", s.kt[0]),
                coeffs: vec![
                    (idx("theta_p").unwrap_or(0), 1.0),
                    (idx("theta1").unwrap_or(0), -1.0),
                ],
                k: s.kt[0],
                c: s.ct[0],
            }));
            terms.push(Box::new(LinearSpring {
                label: format!("shaft2 torsion(kt = {} N·m/rad)", s.kt[1]),
                coeffs: vec![
                    (idx("theta2").unwrap_or(0), 1.0),
                    (idx("theta_q").unwrap_or(0), -1.0),
                ],
                k: s.kt[1],
                c: s.ct[1],
            }));
            // bending: δx1 = x1 − η2 xb1 − η1 xb2 ; δx2 = x2 − η4 xb3 − η3 xb4
            for (gear, shaft, bs, etas) in [
                (1, 0usize, [1, 2], [s.eta[1], s.eta[0]]),
                (2, 1, [3, 4], [s.eta[3], s.eta[2]]),
            ] {
                for ax in ["x", "y"] {
                    let Some(gi) = idx(&format!("{ax}{gear}")) else {
                        continue;
                    };
                    let mut coeffs = vec![(gi, 1.0)];
                    for (b, eta) in bs.iter().zip(etas) {
                        if let Some(bi) = idx(&format!("{ax}b{b}")) {
                            coeffs.push((bi, -eta));
                        }
                    }
                    terms.push(Box::new(LinearSpring {
                        label: format!("shaft{} bending {ax}(ks = {} N/m)", shaft + 1, ks[shaft]),
                        coeffs,
                        k: ks[shaft],
                        c: s.cs[shaft],
                    }));
                }
            }
        }
        // bearings act on bearing masses (with shafts) or directly on the gears
        let bearing_sites: Vec<(String, Option<usize>, Option<usize>, f64)> = if shafts.is_some() {
            (1..=4)
                .map(|b| {
                    (
                        format!("bearing{b}"),
                        idx(&format!("xb{b}")),
                        idx(&format!("yb{b}")),
                        if b <= 2 { omega1 } else { omega2 },
                    )
                })
                .collect()
        } else {
            vec![
                ("bearing(pinion)".into(), idx("x1"), idx("y1"), omega1),
                ("bearing(gear)".into(), idx("x2"), idx("y2"), omega2),
            ]
        };
        for (label, ix, iy, om) in bearing_sites {
            match blaw {
                Law::Rigid => {}
                Law::Linear(kb) => {
                    for (ax, i) in [("x", ix), ("y", iy)] {
                        if let Some(i) = i {
                            terms.push(Box::new(LinearSpring {
                                label: format!("{label} {ax} linear(kb = {kb} N/m)"),
                                coeffs: vec![(i, 1.0)],
                                k: kb,
                                c: cb,
                            }));
                        }
                    }
                }
                Law::Hertz {
                    kc,
                    nb,
                    gamma0,
                    p,
                    ratio,
                } => {
                    terms.push(Box::new(HertzBearing {
                        label: format!(
                            "{label} hertz(Kc = {kc:e}, Nb = {nb}, γ0 = {:.2} µm, p = {p})",
                            gamma0 * 1e6
                        ),
                        idx: [ix, iy],
                        kc,
                        nb,
                        gamma0,
                        p,
                        omega_cage: om * ratio,
                    }));
                    if cb > 0.0 {
                        for (ax, i) in [("x", ix), ("y", iy)] {
                            if let Some(i) = i {
                                terms.push(Box::new(LinearSpring {
                                    label: format!("{label} {ax} damper(cb = {cb})"),
                                    coeffs: vec![(i, 1.0)],
                                    k: 0.0,
                                    c: cb,
                                }));
                            }
                        }
                    }
                }
            }
        }
        if let Some(ecc) = &e.eccentricity {
            for (which, spec, m, om, g) in [
                ("pinion", &ecc.pinion, m1, omega1, 1),
                ("gear", &ecc.gear, m2, omega2, 2),
            ] {
                let Some(s) = spec else { continue };
                if s.kind != "unbalance" {
                    return Err(bad(
                        &format!("effects.eccentricity.{which}.kind"),
                        format!("\"{}\"", s.kind),
                        "\"unbalance\" (the exact mass-matrix form is not implemented)",
                    ));
                }
                nonneg(
                    file,
                    &format!("effects.eccentricity.{which}.rho_um"),
                    s.rho_um,
                )?;
                let (Some(ix), Some(iy)) = (idx(&format!("x{g}")), idx(&format!("y{g}"))) else {
                    continue;
                };
                terms.push(Box::new(UnbalanceTerm {
                    label: format!("unbalance {which}(ρ = {} µm)", s.rho_um),
                    idx: [ix, iy],
                    m_rho: m * s.rho_um * 1e-6,
                    omega: om,
                    phase: s.phase_deg.to_radians(),
                }));
            }
        }
        if let Some(gr) = &e.gravity {
            finite(file, "effects.gravity.g[0]", gr.g[0])?;
            finite(file, "effects.gravity.g[1]", gr.g[1])?;
            let forces: Vec<(usize, f64)> = dofs
                .iter()
                .enumerate()
                .filter_map(|(i, &k)| {
                    let n = DOF_NAMES[k];
                    if n.starts_with('x') {
                        Some((i, mass[i] * gr.g[0]))
                    } else if n.starts_with('y') {
                        Some((i, mass[i] * gr.g[1]))
                    } else {
                        None
                    }
                })
                .collect();
            terms.push(Box::new(ConstantForce {
                label: format!("gravity(g = [{}, {}] m/s²)", gr.g[0], gr.g[1]),
                forces,
            }));
        }
        let hunting = if e.eccentricity.is_some() {
            lcm(self.gears.z1, self.gears.z2) as f64
        } else {
            1.0
        };
        let max_step = match blaw {
            Law::Hertz { nb, ratio, .. } => 2.0 * PI / (nb as f64 * omega1 * ratio) / 20.0,
            _ => f64::INFINITY,
        };
        let model = Model {
            dofs,
            mass,
            terms,
            mesh: core,
            omega: [omega1, omega2],
            poincare_period: d.t_mesh_s * hunting,
            max_step,
        };
        Ok((model, d))
    }
}

fn gcd(a: u32, b: u32) -> u32 {
    if b == 0 { a } else { gcd(b, a % b) }
}

fn lcm(a: u32, b: u32) -> u32 {
    a / gcd(a, b) * b
}

fn pos(file: &str, key: &str, v: f64) -> Result<(), SceneError> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(SceneError::Invalid {
            file: file.into(),
            key: key.into(),
            found: v.to_string(),
            expected: "a positive finite number".into(),
        })
    }
}

fn nonneg(file: &str, key: &str, v: f64) -> Result<(), SceneError> {
    if v.is_finite() && v >= 0.0 {
        Ok(())
    } else {
        Err(SceneError::Invalid {
            file: file.into(),
            key: key.into(),
            found: v.to_string(),
            expected: "a finite number ≥ 0".into(),
        })
    }
}

fn finite(file: &str, key: &str, v: f64) -> Result<(), SceneError> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(SceneError::Invalid {
            file: file.into(),
            key: key.into(),
            found: v.to_string(),
            expected: "a finite number".into(),
        })
    }
}
