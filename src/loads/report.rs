//! `loads.json`: the loads of a rotor over one turn ([`LoadsReport`]), one type for the CLI, the
//! Python binding and a CAD pipeline. World frame (the trajectory's), mm, degrees, N, N·m, MPa;
//! torques positive in the carrier's sense of travel (docs/loads.md, "Conventions").

use super::kinetostatics::MeshForce;
use super::kinetostatics::TrainTurn;
use super::mass::MassProperties;
use super::motion::PitchPoint;
use super::rating::{Extreme, Rated, RatingReport};
use super::scene::LoadCase;
use crate::geometry::assembly::Rebuilt;
use crate::geometry::pitch::PitchCurve;
use crate::math::Point;
use crate::verdict::Verdict;
use serde::{Deserialize, Serialize};

/// Layout version of `loads.json`.
pub const LOADS_SCHEMA_VERSION: u32 = 1;

/// The whole report.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[non_exhaustive]
pub struct LoadsReport {
    /// [`LOADS_SCHEMA_VERSION`].
    pub schema_version: u32,
    /// The units of the file.
    pub units: Units,
    /// The design file the scene names, as given (absent when the caller passed a design).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub design: Option<String>,
    /// How the carrier turns.
    pub operation: OperationReport,
    /// Carrier angle of travel of each sample, deg (uniform on `[0, 360)`, from φH = 0).
    pub travel_deg: Vec<f64>,
    /// Drive torque of the carrier at constant speed, all arms, N·m.
    #[serde(rename = "carrier_torque_Nm")]
    pub carrier_torque_nm: Vec<f64>,
    /// Torque the frame holds on the fixed sun, N·m.
    #[serde(rename = "sun_torque_Nm")]
    pub sun_torque_nm: Vec<f64>,
    /// Moment about the first arm's planet axis of the intermediate's force on the planet, N·m.
    #[serde(rename = "planet_mesh_torque_Nm")]
    pub planet_mesh_torque_nm: Vec<f64>,
    /// Force of the frame on the rotor and the sun together, `[x, y]` N.
    #[serde(rename = "frame_force_N")]
    pub frame_force_n: Vec<Point>,
    /// The needle force on the first arm's tip, `[x, y]` N.
    #[serde(rename = "needle_force_N")]
    pub needle_force_n: Vec<Point>,
    /// The needle load as the table the loads use, rows `[travel_deg, Fx_N, Fy_N]` on the first
    /// arm's tip (world frame), linear between rows and from the last round to the first; absent
    /// without a needle.
    #[serde(
        rename = "needle_table_N",
        default,
        skip_serializing_if = "Vec::is_empty"
    )]
    pub needle_table_n: Vec<[f64; 3]>,
    /// Bearing forces, `[x, y]` N.
    pub bearings: Bearings,
    /// The two meshes of the first arm.
    pub meshes: Meshes,
    /// The mass properties used.
    pub gears: GearsReport,
    /// The tooth rating (a design with teeth and a `[material]`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rating: Option<RatingReport>,
    /// Peaks, means and the extremes.
    pub summary: Summary,
    /// Whether the safety factors meet their targets (passed without a rating).
    pub verdict: Verdict,
}

/// Units of `loads.json`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Units {
    /// `mm`.
    pub length: String,
    /// `deg`.
    pub angle: String,
    /// `N`.
    pub force: String,
    /// `N·m`.
    pub torque: String,
    /// `MPa`.
    pub stress: String,
}

impl Default for Units {
    fn default() -> Self {
        Self {
            length: "mm".into(),
            angle: "deg".into(),
            force: "N".into(),
            torque: "N·m".into(),
            stress: "MPa".into(),
        }
    }
}

/// `operation`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct OperationReport {
    /// Carrier speed, r/min.
    pub carrier_rpm: f64,
    /// Carrier speed, rad/s.
    pub omega_rad_s: f64,
    /// Trains on the carrier.
    pub arms: u32,
    /// +1 CCW carrier, −1 CW.
    pub direction: i8,
    /// Gravity, m/s², trajectory frame (`[0, 0]`: off).
    pub gravity_m_s2: Point,
    /// Samples over the turn.
    pub samples: usize,
}

impl OperationReport {
    /// The operation of a case on a carrier turning in `direction`.
    #[must_use]
    pub fn new(case: &LoadCase, direction: i8) -> Self {
        Self {
            carrier_rpm: case.omega_rad_s * 60.0 / std::f64::consts::TAU,
            omega_rad_s: case.omega_rad_s,
            arms: case.arms,
            direction,
            gravity_m_s2: case.gravity_m_s2,
            samples: case.samples,
        }
    }
}

/// `bearings`: forces, `[x, y]` N per sample.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Bearings {
    /// The frame on the carrier at O, all arms.
    #[serde(rename = "O_N")]
    pub o_n: Vec<Point>,
    /// The carrier on the first arm's intermediate gear at D.
    #[serde(rename = "D_N")]
    pub d_n: Vec<Point>,
    /// The carrier on the first arm's planet gear (and arm) at A.
    #[serde(rename = "A_N")]
    pub a_n: Vec<Point>,
}

/// `meshes`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Meshes {
    /// Sun (driver) – intermediate (driven).
    pub sun_intermediate: MeshLoads,
    /// Intermediate (driver) – planet (driven).
    pub intermediate_planet: MeshLoads,
}

impl Meshes {
    /// Both meshes of train 1 over the turn (`turn`, CCW frame of `r`), in the world frame about
    /// the carrier axis `o` (mm).
    #[must_use]
    pub fn new(turn: &TrainTurn, r: &Rebuilt, o: Point, travel_deg: &[f64]) -> Self {
        let [sun, mid, planet] = r.ccw_curves();
        let samples = turn.motion.iter().zip(&turn.forces);
        Self {
            sun_intermediate: MeshLoads::new(
                samples.clone().map(|(m, x)| (&m.sun_mesh, &x.sun_mesh)),
                [sun, mid],
                r.sign(),
                o,
                travel_deg,
            ),
            intermediate_planet: MeshLoads::new(
                samples.map(|(m, x)| (&m.planet_mesh, &x.planet_mesh)),
                [mid, planet],
                r.sign(),
                o,
                travel_deg,
            ),
        }
    }
}

/// One mesh over the turn.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[non_exhaustive]
pub struct MeshLoads {
    /// Force along the line of action, N (≥ 0).
    #[serde(rename = "normal_force_N")]
    pub normal_force_n: Vec<f64>,
    /// `+1`: the tangential force turns the driven gear in the sense of travel; `−1` against;
    /// `0` unloaded.
    pub flank: Vec<i8>,
    /// Travel angles where the flank changes (the teeth cross their backlash), deg.
    pub reversals_deg: Vec<f64>,
    /// The pitch point, world frame, mm.
    pub pitch_point_mm: Vec<Point>,
    /// Angle between the force and the direction the driven gear's pitch point moves, deg.
    pub effective_pressure_angle_deg: Vec<f64>,
    /// Signed radius of curvature of the pitch curves at the contact `[driver, driven]`, mm
    /// (negative: concave).
    pub pitch_radius_of_curvature_mm: Vec<[f64; 2]>,
    /// Signed radius of curvature of the flanks at the pitch point `[driver, driven]`,
    /// `ρ·sin α`, mm (with a rating).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub flank_radius_mm: Option<Vec<[f64; 2]>>,
    /// Transverse contact ratio ε_α of the local equivalent pair at each instant (with a rating).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub contact_ratio: Option<Vec<f64>>,
    /// Contact stress at each instant, MPa (with a rating).
    #[serde(
        default,
        rename = "contact_stress_MPa",
        skip_serializing_if = "Option::is_none"
    )]
    pub contact_stress_mpa: Option<Vec<f64>>,
    /// Root bending stress of each gear at each instant `{driver: [...], driven: [...]}` by
    /// gear name, MPa (with a rating).
    #[serde(
        default,
        rename = "root_stress_MPa",
        skip_serializing_if = "Option::is_none"
    )]
    pub root_stress_mpa: Option<std::collections::BTreeMap<String, Vec<f64>>>,
}

impl MeshLoads {
    /// The mesh's samples: pitch points and forces (CCW frame), the driver's and the driven
    /// gear's pitch curves (CCW frame), the world's `sign` and centre `o`.
    pub(crate) fn new<'a>(
        samples: impl Iterator<Item = (&'a PitchPoint, &'a MeshForce)>,
        curves: [&PitchCurve; 2],
        sign: f64,
        o: Point,
        travel_deg: &[f64],
    ) -> Self {
        let mut out = Self::default();
        for (p, f) in samples {
            out.normal_force_n.push(f.normal_force_n);
            out.flank.push(f.flank);
            out.pitch_point_mm
                .push(o + Point::new(p.point_mm.x, sign * p.point_mm.y));
            out.effective_pressure_angle_deg
                .push(f.effective_pressure_angle_rad.to_degrees());
            out.pitch_radius_of_curvature_mm.push([
                curves[0]
                    .geometry(p.driver_angle_rad)
                    .radius_of_curvature_mm(),
                curves[1]
                    .geometry(p.driven_angle_rad)
                    .radius_of_curvature_mm(),
            ]);
        }
        // The signed force (its flank's sign) crosses zero where the flank changes.
        let signed: Vec<f64> = out
            .flank
            .iter()
            .zip(&out.normal_force_n)
            .map(|(&s, f)| f64::from(s) * f)
            .collect();
        out.reversals_deg = sign_changes(travel_deg, &signed);
        out
    }
}

/// `gears`: the mass properties used.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct GearsReport {
    /// Face width, mm (absent: massless gears).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub face_width_mm: Option<f64>,
    /// Density, kg/m³.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub density_kg_m3: Option<f64>,
    /// Bore diameter, mm.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bore_mm: Option<f64>,
    /// The fixed sun.
    pub sun: GearMass,
    /// The intermediate gear.
    pub intermediate: GearMass,
    /// The planet gear (without the arm).
    pub planet: GearMass,
    /// The arm, as the scene gives it (inertia about its own centre of mass).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub arm: Option<GearMass>,
}

impl GearsReport {
    /// The bodies of `case` at face width `face_width_mm` (mm): the gears' mass properties
    /// `[sun, intermediate, planet]` computed in the CCW frame, reported in the design file's
    /// (`sign` −1: mirrored), the arm as the scene gives it.
    #[must_use]
    pub fn new(case: &LoadCase, face_width_mm: f64, gears: [MassProperties; 3], sign: f64) -> Self {
        let [sun, intermediate, planet] = gears.map(|g| GearMass::world(g, sign));
        Self {
            face_width_mm: case.bodies.map(|_| face_width_mm),
            density_kg_m3: case.bodies.map(|b| b.density_kg_m3),
            bore_mm: case.bodies.map(|b| b.bore_mm),
            sun,
            intermediate,
            planet,
            arm: case.arm.map(|a| GearMass {
                mass_kg: a.mass_kg,
                com_mm: a.com_mm,
                inertia_kg_mm2: a.inertia_kg_mm2,
            }),
        }
    }
}

/// Mass properties as reported.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct GearMass {
    /// Mass, kg.
    pub mass_kg: f64,
    /// Centre of mass in the body frame (the frame of the gear's pitch table), mm.
    pub com_mm: Point,
    /// Moment of inertia about the gear's own axis (the arm: about its centre of mass), kg·mm².
    pub inertia_kg_mm2: f64,
}

impl GearMass {
    /// A gear's properties computed in the CCW frame, in the design file's frame.
    #[must_use]
    pub fn world(p: MassProperties, sign: f64) -> Self {
        Self {
            mass_kg: p.mass_kg,
            com_mm: Point::new(p.com_mm.x, sign * p.com_mm.y),
            inertia_kg_mm2: p.inertia_kg_mm2,
        }
    }
}

/// `summary`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[non_exhaustive]
pub struct Summary {
    /// Largest |carrier torque|, N·m.
    #[serde(rename = "carrier_torque_peak_Nm")]
    pub carrier_torque_peak_nm: f64,
    /// Root mean square of the carrier torque, N·m.
    #[serde(rename = "carrier_torque_rms_Nm")]
    pub carrier_torque_rms_nm: f64,
    /// Mean carrier torque, N·m.
    #[serde(rename = "carrier_torque_mean_Nm")]
    pub carrier_torque_mean_nm: f64,
    /// Mean power into the carrier, mean torque × ω, W.
    #[serde(rename = "mean_power_W")]
    pub mean_power_w: f64,
    /// Largest |planet mesh torque|, N·m.
    #[serde(rename = "planet_mesh_torque_peak_Nm")]
    pub planet_mesh_torque_peak_nm: f64,
    /// Largest |frame force|, N.
    #[serde(rename = "frame_force_peak_N")]
    pub frame_force_peak_n: f64,
    /// Travel angles where the planet mesh torque changes sign (the teeth cross the backlash), deg.
    pub reversals_deg: Vec<f64>,
    /// The smallest pitting safety factor and where (with a rating).
    #[serde(default, rename = "min_S_H", skip_serializing_if = "Option::is_none")]
    pub min_s_h: Option<Extreme>,
    /// The smallest bending safety factor and where (with a rating).
    #[serde(default, rename = "min_S_F", skip_serializing_if = "Option::is_none")]
    pub min_s_f: Option<Extreme>,
    /// The shortest service life of the gears by Miner's sum, h (with a rating).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub life_h: Option<f64>,
}

impl Summary {
    /// The summary of the rotor's curves.
    #[must_use]
    pub fn new(
        travel_deg: &[f64],
        carrier_nm: &[f64],
        planet_nm: &[f64],
        frame_n: &[Point],
        omega_rad_s: f64,
    ) -> Self {
        let n = carrier_nm.len().max(1) as f64;
        let peak = |v: &[f64]| v.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        let mean = carrier_nm.iter().sum::<f64>() / n;
        Self {
            carrier_torque_peak_nm: peak(carrier_nm),
            carrier_torque_rms_nm: (carrier_nm.iter().map(|t| t * t).sum::<f64>() / n).sqrt(),
            carrier_torque_mean_nm: mean,
            mean_power_w: mean * omega_rad_s,
            planet_mesh_torque_peak_nm: peak(planet_nm),
            frame_force_peak_n: frame_n.iter().fold(0.0_f64, |m, f| m.max(f.norm())),
            reversals_deg: sign_changes(travel_deg, planet_nm),
            min_s_h: None,
            min_s_f: None,
            life_h: None,
        }
    }
}

/// Travel angles (deg) where `values`, sampled at `travel_deg` over one turn, changes sign:
/// linear between samples, round the turn. A run of zeros between opposite signs counts once, at
/// its middle; zeros between equal signs are no change.
#[must_use]
pub fn sign_changes(travel_deg: &[f64], values: &[f64]) -> Vec<f64> {
    let n = values.len();
    let signed: Vec<usize> = (0..n).filter(|&k| values[k] != 0.0).collect();
    let mut out = Vec::new();
    if signed.len() < 2 {
        return out;
    }
    let angle = |k: usize, wraps: f64| travel_deg[k] + 360.0 * wraps;
    for (j, &k) in signed.iter().enumerate() {
        let (next, wrap) = match signed.get(j + 1) {
            Some(&m) => (m, 0.0),
            None => (signed[0], 1.0),
        };
        let (a, b) = (values[k], values[next]);
        if a.signum() == b.signum() {
            continue;
        }
        let (xa, xb) = (angle(k, 0.0), angle(next, wrap));
        let x = if next == (k + 1) % n {
            xa + (xb - xa) * a / (a - b)
        } else {
            0.5 * (xa + xb)
        };
        out.push(x.rem_euclid(360.0));
    }
    out.sort_by(f64::total_cmp);
    out
}

impl LoadsReport {
    /// Records a rating: each mesh's series and the rating report, its extremes in the summary.
    pub(crate) fn attach(&mut self, rated: Rated) {
        let [s1, s2] = rated.meshes;
        for (loads, s) in [
            (&mut self.meshes.sun_intermediate, s1),
            (&mut self.meshes.intermediate_planet, s2),
        ] {
            loads.flank_radius_mm = Some(s.flank_radius_mm);
            loads.contact_ratio = Some(s.contact_ratio);
            loads.contact_stress_mpa = Some(s.contact_stress_mpa);
            loads.root_stress_mpa = Some(s.root_stress_mpa);
        }
        let r = rated.report;
        self.summary.min_s_h = Some(r.min_s_h.clone());
        self.summary.min_s_f = Some(r.min_s_f.clone());
        self.summary.life_h = Some(r.life_h);
        self.rating = Some(r);
    }

    /// Stamps the version and units and computes the verdict from the rating.
    pub(crate) fn finish(&mut self) {
        self.schema_version = LOADS_SCHEMA_VERSION;
        self.units = Units::default();
        self.verdict = self
            .rating
            .as_ref()
            .map_or_else(Verdict::default, RatingReport::verdict);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sign_changes_are_interpolated_round_the_turn() {
        let t: Vec<f64> = (0..8).map(|k| 45.0 * k as f64).collect();
        let v = [1.0, 1.0, -1.0, -3.0, -1.0, 1.0, 1.0, 1.0];
        assert_eq!(sign_changes(&t, &v), vec![67.5, 202.5]);
        // A change between the last sample and the first, and zeros in a run.
        let w = [-1.0, 1.0, 0.0, 0.0, -1.0, -1.0, -1.0, 1.0];
        assert_eq!(sign_changes(&t, &w), vec![22.5, 112.5, 292.5, 337.5]);
    }
}
