//! Tooth stresses along the turn by the structure of ISO 6336-2/-3 on the local equivalent spur
//! pair of each mesh, their safety factors against the material, and the service life by Miner's
//! sum (docs/loads.md, "Rating").
//!
//! At every sample, for each mesh (normal force `F_n`, tangential `F_t = F_n·cos α`, face width
//! `b`, module `m`):
//!
//! ```text
//! σ_H = Z_B,D·Z_ε·√(K_A·K_v·K_Hβ·K_Hα) · Z_E·√(F_n/b·(1/ρ_f1 + 1/ρ_f2)),   ρ_fi = ρ_i·sin α
//! σ_F = F_t/(b·m)·Y_F·Y_S·Y_B · K_A·K_v·K_Fβ·K_Fα
//! S_H = σ_Hlim/σ_H,   S_F = Y_ST·Y_M·σ_Flim/σ_F
//! ```
//!
//! with ρ_i the pitch curves' signed radii of curvature at the contact (a concave flank enters
//! with its sign: internal contact). `Z_E·√(F_n/b·Σ1/ρ_f)` is Hertz's line-contact stress at the
//! pitch point, which is ISO's `Z_H·Z_E·√(F_t/(d1·b)·(u + 1)/u)` of a circular pair
//! ([`factors`] lists every factor, its choice and its source; `factors = "nominal"` sets the load
//! factors and Z_ε, Z_B, Z_D to 1).

pub mod equivalent;
pub mod factors;
pub mod life;
pub mod material;
mod mesh;
mod summary;
pub mod tooth_form;

use super::LoadsError;
use super::kinetostatics::TrainTurn;
use crate::design::train::ToothedTrain;
use crate::geometry::assembly::Rebuilt;
use crate::geometry::pitch::PitchCurve;
use crate::math::Point;
use crate::teeth::ArcFrame;
use crate::verdict::Verdict;
pub use factors::{FactorMode, Factors};
pub use material::Material;
use mesh::{MeshGear, MeshSample};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use summary::summarize;
use tooth_form::{Flank, GearTeeth};

/// `[material]` as written: a preset, and any of its values replaced.
#[derive(Debug, Clone, Default, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct MaterialSpec {
    /// `steel`, `case_hardened_steel`, `cast_iron`, `grey_iron` or `pom` ([`material`]); absent:
    /// all four values below are needed (S–N lines of steel).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub preset: Option<String>,
    /// Young's modulus, MPa.
    #[serde(default, rename = "E_MPa", skip_serializing_if = "Option::is_none")]
    pub e_mpa: Option<f64>,
    /// Poisson's ratio.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub poisson: Option<f64>,
    /// Contact endurance limit σ_Hlim, MPa.
    #[serde(
        default,
        rename = "sigma_Hlim_MPa",
        skip_serializing_if = "Option::is_none"
    )]
    pub sigma_hlim_mpa: Option<f64>,
    /// Bending stress number σ_Flim, MPa.
    #[serde(
        default,
        rename = "sigma_Flim_MPa",
        skip_serializing_if = "Option::is_none"
    )]
    pub sigma_flim_mpa: Option<f64>,
}

/// `[rating]` as written.
#[derive(Debug, Clone, Default, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RatingSpec {
    /// `"iso"` (default) or `"nominal"`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub factors: Option<FactorMode>,
    /// Application factor K_A (iso default 1.5).
    #[serde(default, rename = "K_A", skip_serializing_if = "Option::is_none")]
    pub k_a: Option<f64>,
    /// ISO accuracy grade 5..=12 (default 8).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub accuracy_grade: Option<u8>,
    /// Dynamic factor K_v instead of the formula, or `"dynamic"`: the teeth rated on the
    /// rotor dynamics' mesh forces (the scene's `[effects]`, docs/loads.md), K_v = 1.
    #[serde(default, rename = "K_v", skip_serializing_if = "Option::is_none")]
    pub k_v: Option<KvSpec>,
    /// Face load factor K_Hβ (iso default 1.15).
    #[serde(default, rename = "K_Hbeta", skip_serializing_if = "Option::is_none")]
    pub k_h_beta: Option<f64>,
    /// K_Fβ instead of `K_Hβ^N_F`.
    #[serde(default, rename = "K_Fbeta", skip_serializing_if = "Option::is_none")]
    pub k_f_beta: Option<f64>,
    /// K_Hα instead of the table.
    #[serde(default, rename = "K_Halpha", skip_serializing_if = "Option::is_none")]
    pub k_h_alpha: Option<f64>,
    /// K_Fα instead of the table.
    #[serde(default, rename = "K_Falpha", skip_serializing_if = "Option::is_none")]
    pub k_f_alpha: Option<f64>,
    /// Smallest pitting safety factor the gears must keep (default 1.0).
    #[serde(default, rename = "S_H_min", skip_serializing_if = "Option::is_none")]
    pub s_h_min: Option<f64>,
    /// Smallest bending safety factor the gears must keep (default 1.4).
    #[serde(default, rename = "S_F_min", skip_serializing_if = "Option::is_none")]
    pub s_f_min: Option<f64>,
}

/// `rating.K_v`: a factor, or the word `dynamic`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(untagged)]
pub enum KvSpec {
    /// K_v itself, in (0, 10].
    Factor(f64),
    /// `"dynamic"`.
    Word(DynamicWord),
}

/// The word `dynamic`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum DynamicWord {
    /// The rotor dynamics' forces.
    Dynamic,
}

/// A validated rating: material, factors, targets.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct RatingOptions {
    /// The gears' material.
    pub material: Material,
    /// The factors.
    pub factors: Factors,
    /// Target of the smallest pitting safety factor.
    #[serde(rename = "S_H_min")]
    pub s_h_min: f64,
    /// Target of the smallest bending safety factor.
    #[serde(rename = "S_F_min")]
    pub s_f_min: f64,
    /// The teeth are rated on the rotor dynamics' mesh forces (`K_v = "dynamic"`; then
    /// `factors.K_v` = 1): the loads' analysis needs a [`crate::loads::MeshForceSource`].
    pub on_dynamic_forces: bool,
}

impl RatingOptions {
    /// Checks the material and the rating tables of a scene (`file` names it in messages).
    ///
    /// # Errors
    /// [`LoadsError::Field`] naming the key and its range.
    pub fn from_spec(
        m: &MaterialSpec,
        r: Option<&RatingSpec>,
        file: &str,
    ) -> Result<Self, LoadsError> {
        let field = |key: &str, message: String| LoadsError::Field {
            file: file.into(),
            key: key.into(),
            message,
        };
        let mut material = match m.preset.as_deref() {
            Some(p) => Material::preset(p).ok_or_else(|| {
                field(
                    "material.preset",
                    format!(
                        "`{p}` is not a preset; one of {}",
                        material::PRESETS.join(", ")
                    ),
                )
            })?,
            None => {
                if m.e_mpa.is_none()
                    || m.poisson.is_none()
                    || m.sigma_hlim_mpa.is_none()
                    || m.sigma_flim_mpa.is_none()
                {
                    return Err(field(
                        "material",
                        format!(
                            "needs preset = one of {}, or all of E_MPa, poisson, sigma_Hlim_MPa \
                             and sigma_Flim_MPa",
                            material::PRESETS.join(", ")
                        ),
                    ));
                }
                let mut s = Material::preset("steel").expect("steel is a preset");
                s.name = "custom".into();
                s
            }
        };
        let in_range = |v: Option<f64>, key: &str, lo: f64, hi: f64, what: &str| match v {
            None => Ok(None),
            Some(x) if x.is_finite() && x > lo && x <= hi => Ok(Some(x)),
            Some(x) => Err(field(key, format!("{x} must be {what} in ({lo}, {hi}]"))),
        };
        if let Some(e) = in_range(m.e_mpa, "material.E_MPa", 0.0, 1e6, "a modulus in MPa")? {
            material.e_mpa = e;
        }
        if let Some(nu) = in_range(m.poisson, "material.poisson", 0.0, 0.5, "a Poisson's ratio")? {
            material.poisson = nu;
        }
        if let Some(s) = in_range(
            m.sigma_hlim_mpa,
            "material.sigma_Hlim_MPa",
            0.0,
            1e4,
            "a stress in MPa",
        )? {
            material.sigma_hlim_mpa = s;
        }
        if let Some(s) = in_range(
            m.sigma_flim_mpa,
            "material.sigma_Flim_MPa",
            0.0,
            1e4,
            "a stress in MPa",
        )? {
            material.sigma_flim_mpa = s;
        }
        let r = r.cloned().unwrap_or_default();
        let mut factors = Factors::new(r.factors.unwrap_or_default());
        let factor = |v: Option<f64>, key: &str| in_range(v, key, 0.0, 10.0, "a factor");
        if let Some(k) = factor(r.k_a, "rating.K_A")? {
            factors.k_a = k;
        }
        if let Some(g) = r.accuracy_grade {
            if !(5..=12).contains(&g) {
                return Err(field(
                    "rating.accuracy_grade",
                    format!("{g} must be an ISO 1328-1 accuracy grade in 5..=12"),
                ));
            }
            factors.accuracy_grade = g;
        }
        let on_dynamic_forces = matches!(r.k_v, Some(KvSpec::Word(DynamicWord::Dynamic)));
        factors.k_v = match r.k_v {
            None => None,
            Some(KvSpec::Factor(k)) => factor(Some(k), "rating.K_v")?,
            Some(KvSpec::Word(_)) => Some(1.0),
        };
        if let Some(k) = factor(r.k_h_beta, "rating.K_Hbeta")? {
            factors.k_h_beta = k;
        }
        factors.k_f_beta = factor(r.k_f_beta, "rating.K_Fbeta")?;
        factors.k_h_alpha = factor(r.k_h_alpha, "rating.K_Halpha")?;
        factors.k_f_alpha = factor(r.k_f_alpha, "rating.K_Falpha")?;
        let target = |v: Option<f64>, key: &str, default: f64| {
            in_range(v, key, 0.0, 100.0, "a safety factor").map(|x| x.unwrap_or(default))
        };
        Ok(Self {
            material,
            factors,
            s_h_min: target(r.s_h_min, "rating.S_H_min", 1.0)?,
            s_f_min: target(r.s_f_min, "rating.S_F_min", 1.4)?,
            on_dynamic_forces,
        })
    }
}

/// The smallest safety factor and where it occurs ([`f64::MAX`] when nothing is loaded).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Extreme {
    /// The value.
    pub value: f64,
    /// Travel angle, deg.
    pub travel_deg: f64,
    /// The mesh (`sun_intermediate`, `intermediate_planet`).
    pub mesh: String,
    /// The gear (bending), or the mesh's pinion (pitting).
    pub gear: String,
    /// The tooth of that gear.
    pub tooth: usize,
}

/// One gear's rating over the turn.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct GearRating {
    /// Smallest bending safety factor over the turn.
    #[serde(rename = "min_S_F")]
    pub min_s_f: Extreme,
    /// Largest root stress, MPa.
    #[serde(rename = "max_root_stress_MPa")]
    pub max_root_stress_mpa: f64,
    /// Teeth loaded on both flanks in a turn (alternating bending, Y_M).
    pub alternating_teeth: usize,
    /// Life against tooth breakage, h (Miner, the worst tooth).
    pub bending_life_h: f64,
    /// Life against pitting, h (Miner, the worst flank).
    pub pitting_life_h: f64,
    /// Smallest and largest Y_F·Y_S met.
    #[serde(rename = "Y_F_Y_S_range")]
    pub y_f_y_s_range: [f64; 2],
}

/// `rating` of `loads.json`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct RatingReport {
    /// What was rated with.
    pub options: RatingOptions,
    /// Face width, mm.
    pub face_width_mm: f64,
    /// Module, mm.
    pub module_mm: f64,
    /// Smallest pitting safety factor over the turn.
    #[serde(rename = "min_S_H")]
    pub min_s_h: Extreme,
    /// Smallest bending safety factor over the turn.
    #[serde(rename = "min_S_F")]
    pub min_s_f: Extreme,
    /// Shortest life, h ([`f64::MAX`]: unlimited).
    pub life_h: f64,
    /// The gear and mode of the shortest life.
    pub life_limited_by: String,
    /// Each gear.
    pub gears: BTreeMap<String, GearRating>,
    /// Where the ratings leave the standard's validity, and other remarks, one line each.
    pub notes: Vec<String>,
}

impl RatingReport {
    /// Failures of the targets.
    #[must_use]
    pub fn verdict(&self) -> Verdict {
        let f = self
            .shortfalls()
            .into_iter()
            .map(|(symbol, target, e)| {
                let (what, at) = if symbol == "S_H" {
                    ("pitting", e.mesh.clone())
                } else {
                    ("bending", format!("{} tooth {}", e.gear, e.tooth))
                };
                format!(
                    "{what} safety {symbol} = {:.3} < {target} ({at}, travel {:.1}°)",
                    e.value, e.travel_deg
                )
            })
            .collect();
        Verdict::from_failures(f)
    }

    /// The targets missed: `(symbol, target, the extreme that misses it)`, pitting first.
    #[must_use]
    pub fn shortfalls(&self) -> Vec<(&'static str, f64, &Extreme)> {
        [
            ("S_H", self.options.s_h_min, &self.min_s_h),
            ("S_F", self.options.s_f_min, &self.min_s_f),
        ]
        .into_iter()
        .filter(|(_, target, e)| e.value < *target)
        .collect()
    }
}

/// One gear of the train for the rating: its teeth and its `θ → s` map (world body frame).
struct RatedGear {
    teeth: GearTeeth,
    /// Arc length at uniform body angles, mm.
    arc: Vec<f64>,
}

impl RatedGear {
    /// Arc position (mm) of the world body angle `theta` (rad).
    fn arc_at(&self, theta: f64) -> f64 {
        let n = self.arc.len() - 1;
        let u = theta.rem_euclid(std::f64::consts::TAU) / std::f64::consts::TAU * n as f64;
        let j = (u as usize).min(n - 1);
        let t = u - j as f64;
        self.arc[j] + t * (self.arc[j + 1] - self.arc[j])
    }
}

/// Samples of `θ → s` per gear (linear between them: the arc length is smooth in θ).
const ARC_TABLE: usize = 16_384;

/// Gear `k` of the toothed train (world body frame): its teeth read off its outline.
fn rated_gear(train: &ToothedTrain, k: usize) -> Result<RatedGear, LoadsError> {
    let a = &train.assembly;
    let (name, curve, outline) = match k {
        0 => ("sun", &a.sun, &train.sun),
        1 => ("intermediate", &a.intermediate, &train.intermediate),
        _ => ("planet", &a.planet, &train.planet),
    };
    let frame = ArcFrame::new(curve);
    let teeth = GearTeeth::new(
        &outline.points_mm,
        &frame,
        train.report.z,
        train.report.module_mm,
        train.report.phase_mm[k],
        train.report.options.toothing.rack.alpha_rad(),
    )
    .map_err(|e| LoadsError::Teeth(format!("{name}: {e}")))?;
    // θ → s: the frame's s → θ on a fine uniform grid in s, inverted on a uniform grid in θ.
    let l = frame.length_mm();
    let m = 4 * ARC_TABLE;
    let thetas: Vec<f64> = (0..=m)
        .map(|j| frame.theta_at(l * j as f64 / m as f64))
        .collect();
    let arc = (0..=ARC_TABLE)
        .map(|i| {
            let th = std::f64::consts::TAU * i as f64 / ARC_TABLE as f64;
            let j = thetas.partition_point(|&t| t < th).clamp(1, m);
            let (t0, t1) = (thetas[j - 1], thetas[j]);
            let f = if t1 > t0 { (th - t0) / (t1 - t0) } else { 0.0 };
            l * ((j - 1) as f64 + f) / m as f64
        })
        .collect();
    Ok(RatedGear { teeth, arc })
}

/// The flank of a gear's tooth that a force `f` (CCW frame) pushes, at the gear's CCW-frame
/// body angle and orientation: a push towards larger arc length loads the flank facing smaller
/// arc length; a clockwise design's world arc runs against the CCW frame's (`sign < 0`).
fn loaded_flank(
    curve_ccw: &PitchCurve,
    body_angle: f64,
    orientation: f64,
    f: Point,
    sign: f64,
) -> Flank {
    let g = curve_ccw.geometry(body_angle);
    let e = Point::unit(body_angle);
    let t = (e * g.dr_mm + e.perp() * g.r_mm).rotate(orientation);
    if (f.dot(t) > 0.0) == (sign > 0.0) {
        Flank::Left
    } else {
        Flank::Right
    }
}

/// What the rating reads of the machine besides the turn and the teeth.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Machine {
    /// Trains on the carrier (the sun meshes with each of them in a turn).
    pub arms: u32,
    /// Carrier speed, rad/s.
    pub omega_rad_s: f64,
    /// Face width, mm.
    pub face_width_mm: f64,
    /// Bore diameter of the gears, mm (the rim factor Y_B).
    pub bore_mm: f64,
}

/// One mesh's rated series, per sample.
#[derive(Debug, Clone, PartialEq)]
pub struct RatedSeries {
    /// Flank radii at the pitch point `[driver, driven]`, mm (signed).
    pub flank_radius_mm: Vec<[f64; 2]>,
    /// Contact ratio of the local equivalent pair.
    pub contact_ratio: Vec<f64>,
    /// Contact stress, MPa.
    pub contact_stress_mpa: Vec<f64>,
    /// Root stress of each of the mesh's gears by name, MPa.
    pub root_stress_mpa: BTreeMap<String, Vec<f64>>,
}

/// The rating of a turn: both meshes' series (sun–intermediate, intermediate–planet) and the
/// report.
#[derive(Debug, Clone, PartialEq)]
pub struct Rated {
    /// `[sun–intermediate, intermediate–planet]`.
    pub meshes: [RatedSeries; 2],
    /// Safety factors, life, notes.
    pub report: RatingReport,
}

/// The pitch-line speeds of `[sun–intermediate, intermediate–planet]` relative to the carrier
/// at the motion `mo` and carrier speed `w` (rad/s), m/s: `ω·|P1|` (the sun is fixed) and
/// `ω·|θ2′ − 1|·|P2 − D|`.
#[must_use]
pub fn pitch_line_speeds_m_s(mo: &crate::loads::motion::TrainMotion, w: f64) -> [f64; 2] {
    [
        w * mo.sun_mesh.point_mm.norm() * 1e-3,
        w * (mo.rates.intermediate[0] - 1.0).abs()
            * (mo.planet_mesh.point_mm - mo.d_mm).norm()
            * 1e-3,
    ]
}

/// Rates both meshes of `turn` (train 1, CCW frame of `r`, samples uniform in travel over a
/// turn) on the teeth of `train` for `machine`.
///
/// # Errors
/// [`LoadsError::Teeth`] when a tooth's root cannot be read off the outline.
pub fn rate(
    turn: &TrainTurn,
    r: &Rebuilt,
    train: &ToothedTrain,
    opts: &RatingOptions,
    machine: &Machine,
) -> Result<Rated, LoadsError> {
    let gears: Vec<RatedGear> = (0..3usize)
        .into_par_iter()
        .map(|k| rated_gear(train, k))
        .collect::<Result<_, _>>()?;
    let rack = train.report.options.toothing.rack;
    let m = train.report.module_mm;
    let depth = (2.0 * rack.addendum() + rack.clearance()) * m;
    let sign = r.sign();
    let curves = r.ccw_curves();
    let names = ["sun", "intermediate", "planet"];
    let mesh_gears: Vec<MeshGear<'_>> = (0..3)
        .map(|k| {
            let root = curves[k]
                .radii_mm()
                .iter()
                .copied()
                .fold(f64::INFINITY, f64::min)
                - (rack.addendum() + rack.clearance()) * m;
            MeshGear {
                curve_ccw: curves[k],
                rated: &gears[k],
                y_b: mesh::rim_factor(root - 0.5 * machine.bore_mm, depth),
            }
        })
        .collect();
    let w = machine.omega_rad_s;
    let sun_samples: Vec<MeshSample<'_>> = turn
        .motion
        .iter()
        .zip(&turn.forces)
        .map(|(mo, fo)| MeshSample {
            pitch: &mo.sun_mesh,
            force: &fo.sun_mesh,
            orientation_rad: [0.0, mo.theta2_rad],
            speed_m_s: pitch_line_speeds_m_s(mo, w)[0],
        })
        .collect();
    let planet_samples: Vec<MeshSample<'_>> = turn
        .motion
        .iter()
        .zip(&turn.forces)
        .map(|(mo, fo)| MeshSample {
            pitch: &mo.planet_mesh,
            force: &fo.planet_mesh,
            orientation_rad: [mo.theta2_rad, mo.theta3_rad],
            speed_m_s: pitch_line_speeds_m_s(mo, w)[1],
        })
        .collect();
    let alpha = rack.alpha_rad();
    let ha = rack.addendum() * m;
    let b = machine.face_width_mm;
    let rate = |samples: &[MeshSample<'_>], pair: [usize; 2]| {
        mesh::rate_mesh(
            samples,
            [&mesh_gears[pair[0]], &mesh_gears[pair[1]]],
            opts,
            b,
            m,
            alpha,
            ha,
            depth,
            sign,
        )
    };
    let (m1, m2) = rayon::join(
        || rate(&sun_samples, [0, 1]),
        || rate(&planet_samples, [1, 2]),
    );
    let rated = [
        ("sun_intermediate", [0usize, 1usize], m1),
        ("intermediate_planet", [1, 2], m2),
    ];
    let report = summarize(&rated, turn, opts, m, machine);
    let meshes = rated.map(|(_, pair, mr)| {
        let [a, b] = mr.root_mpa;
        RatedSeries {
            flank_radius_mm: mr.flank_radius_mm,
            contact_ratio: mr.contact_ratio,
            contact_stress_mpa: mr.contact_mpa,
            root_stress_mpa: BTreeMap::from([
                (names[pair[0]].to_string(), a),
                (names[pair[1]].to_string(), b),
            ]),
        }
    });
    Ok(Rated { meshes, report })
}
