//! The loads of a rotor over one turn: the motion and the Newton–Euler solve of train 1 at every
//! sample ([`super::kinetostatics`]), the other arms by their shift in travel, the rotor's sums,
//! and — with teeth and a material — the rating of both meshes ([`super::rating`]).
//!
//! Everything is solved in the counter-clockwise frame of [`Rebuilt`]; a clockwise design's
//! inputs (gravity, the needle force, the arm's centre of mass) are mirrored into it and every
//! vector of the report mirrored back. Torques about the carrier and the planet axis are then
//! positive in the carrier's sense of travel in both.

use super::kinetostatics::{MeshForce, TrainBodies, TrainForces, TrainTurn, solve};
use super::mass::MassProperties;
use super::motion::TrainMotion;
use super::needle::NeedleTable;
use super::rating::{Machine, rate};
use super::report::{Bearings, GearsReport, LoadsReport, Meshes, OperationReport, Summary};
use super::scene::{FaceWidth, LoadCase};
use super::{LoadsError, Rotor};
use crate::geometry::assembly::Rebuilt;
use crate::math::Point;
use rayon::prelude::*;
use std::f64::consts::TAU;

/// The mass properties of the three gears (CCW frame, about their axes) for a face width.
fn gear_masses(r: &Rebuilt, case: &LoadCase, face_width_mm: f64) -> [MassProperties; 3] {
    match case.bodies {
        Some(b) => r.ccw_curves().map(|c| {
            MassProperties::of_pitch_curve(c, face_width_mm, b.density_kg_m3 * 1e-9, b.bore_mm)
        }),
        None => [MassProperties::ZERO; 3],
    }
}

/// The range of an `"auto"` face width, in modules: from 6·m to 15·m.
pub const AUTO_FACE_WIDTH_MODULES: [f64; 2] = [6.0, 15.0];

/// The step of an `"auto"` face width, mm.
pub const AUTO_FACE_WIDTH_STEP_MM: f64 = 0.5;

/// The bore must leave every gear a rim: its radius below the smallest pitch radius less the
/// dedendum (1.25·m with teeth).
fn check_bore(
    r: &Rebuilt,
    case: &LoadCase,
    rotor: &Rotor<'_>,
    file: &str,
) -> Result<(), LoadsError> {
    let Some(b) = case.bodies else { return Ok(()) };
    let dedendum = rotor.teeth().map_or(0.0, |t| 1.25 * t.report.module_mm);
    for (name, c) in ["sun", "intermediate", "planet"]
        .into_iter()
        .zip(r.ccw_curves())
    {
        let root = c.radii_mm().iter().copied().fold(f64::INFINITY, f64::min) - dedendum;
        if !(0.5 * b.bore_mm < root) {
            return Err(LoadsError::Field {
                file: file.into(),
                key: "gears.bore_mm".into(),
                message: format!(
                    "a bore of {} mm does not fit inside the {name} gear (its smallest {} radius \
                     is {root:.3} mm): take a bore below {:.3} mm",
                    b.bore_mm,
                    if dedendum > 0.0 { "root" } else { "pitch" },
                    2.0 * root
                ),
            });
        }
    }
    Ok(())
}

/// The case's needle load as a table over the travel (world frame, N) on the tip path of
/// `motion` (train 1 at the case's samples), if the case has one.
pub(crate) fn needle_table(
    r: &Rebuilt,
    case: &LoadCase,
    motion: &[TrainMotion],
) -> Option<NeedleTable> {
    let load = case.needle.as_ref()?;
    let sign = r.sign();
    let o = r.assembly().center_mm;
    let tips: Vec<Point> = motion
        .iter()
        .map(|m| o + Point::new(m.tip_mm.x, sign * m.tip_mm.y))
        .collect();
    Some(load.table(&tips, case.gravity_m_s2))
}

/// Solves train 1 at every sample.
pub(crate) fn train_turn(
    r: &Rebuilt,
    case: &LoadCase,
    bodies: &TrainBodies,
    alpha: f64,
) -> Result<TrainTurn, LoadsError> {
    let n = case.samples;
    let sign = r.sign();
    let mirror = |p: Point| Point::new(p.x, sign * p.y);
    let motion: Vec<TrainMotion> = (0..n)
        .into_par_iter()
        .map(|k| TrainMotion::at(r, TAU * k as f64 / n as f64))
        .collect();
    let needle_n: Vec<Point> = match needle_table(r, case, &motion) {
        None => vec![Point::ZERO; n],
        Some(table) => (0..n)
            .map(|k| mirror(table.at(TAU * k as f64 / n as f64)))
            .collect(),
    };
    let g = mirror(case.gravity_m_s2);
    let forces = motion
        .par_iter()
        .zip(&needle_n)
        .map(|(m, &f)| solve(m, bodies, case.omega_rad_s, g, f, alpha))
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| LoadsError::SelfLocking {
            mesh: e.mesh,
            travel_deg: e.phi_rad.to_degrees(),
        })?;
    Ok(TrainTurn {
        motion,
        forces,
        needle_n,
    })
}

/// The rotor's sums over the arms (CCW frame, SI): the carrier torque, the torque the frame
/// holds on the sun (its weight's moment included), the carrier bearing at O and the frame force
/// (the sun's weight included).
struct RotorSums {
    carrier_nm: Vec<f64>,
    sun_nm: Vec<f64>,
    bearing_o_n: Vec<Point>,
    frame_n: Vec<Point>,
}

impl RotorSums {
    /// The sums of `turn` (train 1) over `arms` trains, the sun of mass properties `sun` under
    /// gravity `g` (m/s², CCW frame).
    fn new(turn: &TrainTurn, arms: usize, sun: &MassProperties, g: Point) -> Self {
        let f = &turn.forces;
        let sum =
            |q: &dyn Fn(&TrainForces) -> f64| over_arms(&f.iter().map(q).collect::<Vec<_>>(), arms);
        let sum_v = |q: &dyn Fn(&TrainForces) -> Point| {
            over_arms(&f.iter().map(q).collect::<Vec<_>>(), arms)
        };
        let sun_weight_moment = (sun.first_moment_kg_mm() * 1e-3).cross(g);
        Self {
            carrier_nm: sum(&|x| x.carrier_torque_nm),
            sun_nm: sum(&|x| x.sun_mesh_moment_nm)
                .into_iter()
                .map(|t| t - sun_weight_moment)
                .collect(),
            bearing_o_n: sum_v(&|x| x.bearing_d_n + x.bearing_a_n),
            frame_n: sum_v(&|x| x.bearing_d_n + x.bearing_a_n + x.sun_mesh.force_n)
                .into_iter()
                .map(|v| v - g * sun.mass_kg)
                .collect(),
        }
    }
}

/// Sum over the arms of a per-sample quantity of train 1: train j at sample k is train 1 at
/// sample `k + j·n/arms`.
pub(crate) fn over_arms<T: Copy + Default + std::ops::Add<Output = T>>(
    values: &[T],
    arms: usize,
) -> Vec<T> {
    let n = values.len();
    let step = n / arms;
    (0..n)
        .map(|k| (0..arms).fold(T::default(), |acc, j| acc + values[(k + j * step) % n]))
        .collect()
}

/// Mesh forces that a rating takes instead of the rigid ones (`rating.K_v = "dynamic"`): train
/// 1's forces at the case's samples.
#[derive(Debug, Clone, PartialEq)]
pub struct DynamicMeshForces {
    /// `[sun–intermediate, intermediate–planet]` at each sample (SI, the CCW frame of the
    /// rebuilt train, as [`TrainForces`]).
    pub forces: Vec<[MeshForce; 2]>,
    /// One line for the rating's notes: where the forces come from and how large they are.
    pub note: String,
}

/// Where a `K_v = "dynamic"` rating gets its forces: `(rotor, case, face width mm)` → the
/// forces of that rotor at that face width. The rotor dynamics give one
/// (`ncgear::analysis::dynamics::rotor::rating`); the loads know nothing of how they are made.
pub type MeshForceSource<'a> =
    dyn Fn(&Rotor<'_>, &LoadCase, f64) -> Result<DynamicMeshForces, LoadsError> + Sync + 'a;

/// The loads of `rotor` under `case` (module docs); `file` names the scene in messages. An
/// `"auto"` face width is the smallest on a 0.5 mm grid within `[6, 15]·m` whose rating meets
/// the case's safety targets (the stresses fall as the face widens: bisection), or `15·m` when
/// none does.
///
/// # Errors
/// [`LoadsError`]: an `"auto"` face width without teeth (no module), a bore larger than a gear,
/// a mesh that locks, a rating without teeth.
pub fn analyse(rotor: &Rotor<'_>, case: &LoadCase, file: &str) -> Result<LoadsReport, LoadsError> {
    analyse_with(rotor, case, file, None)
}

/// [`analyse`], the teeth rated on the forces of `dynamic` when the case asks for it
/// (`rating.K_v = "dynamic"`; the rest of the report stays the rigid loads').
///
/// # Errors
/// As [`analyse`]; [`LoadsError::Field`] on `rating.K_v` when the case rates on dynamic forces
/// and none are given; the source's own.
pub fn analyse_with(
    rotor: &Rotor<'_>,
    case: &LoadCase,
    file: &str,
    dynamic: Option<&MeshForceSource<'_>>,
) -> Result<LoadsReport, LoadsError> {
    match case.bodies.map(|b| b.face_width) {
        None => analyse_at(rotor, case, 0.0, file, dynamic),
        Some(FaceWidth::Mm(b)) => analyse_at(rotor, case, b, file, dynamic),
        Some(FaceWidth::Auto) => auto_face_width(rotor, case, file, dynamic),
    }
}

/// Whether a report meets its rating's targets (a report without a rating does).
#[must_use]
pub fn meets_targets(r: &LoadsReport) -> bool {
    r.verdict.passed
}

/// The `"auto"` face width (see [`analyse`]).
fn auto_face_width(
    rotor: &Rotor<'_>,
    case: &LoadCase,
    file: &str,
    dynamic: Option<&MeshForceSource<'_>>,
) -> Result<LoadsReport, LoadsError> {
    let Some(teeth) = rotor.teeth() else {
        return Err(LoadsError::Field {
            file: file.into(),
            key: "gears.face_width_mm".into(),
            message: "\"auto\" is chosen within 6…15·m of the module, and the design has no \
                      teeth: give the face width in mm, or rate a toothed train"
                .into(),
        });
    };
    let m = teeth.report.module_mm;
    let step = AUTO_FACE_WIDTH_STEP_MM;
    let [lo_m, hi_m] = AUTO_FACE_WIDTH_MODULES;
    let (lo, hi) = (
        (lo_m * m / step).ceil() * step,
        (hi_m * m / step).floor() * step,
    );
    let at = |b: f64| analyse_at(rotor, case, b, file, dynamic);
    let widest = at(hi)?;
    if !meets_targets(&widest) {
        return Ok(widest);
    }
    let narrowest = at(lo)?;
    if meets_targets(&narrowest) {
        return Ok(narrowest);
    }
    // Bisection on the step grid: `a` fails, `b` meets the targets.
    let (mut a, mut b, mut best) = (lo, hi, widest);
    while b - a > 1.5 * step {
        let mid = (0.5 * (a + b) / step).round() * step;
        let r = at(mid)?;
        if meets_targets(&r) {
            b = mid;
            best = r;
        } else {
            a = mid;
        }
    }
    Ok(best)
}

/// The rigid train of a case: the rebuilt kinematics, the three gears' mass properties (CCW
/// frame), the moving bodies (the planet with its arm) and the mesh pressure angle, rad.
pub(crate) struct RigidTrain {
    pub rebuilt: Rebuilt,
    pub masses: [MassProperties; 3],
    pub bodies: TrainBodies,
    pub alpha_rad: f64,
}

/// The rigid train of `rotor` under `case` at the face width `face_width_mm` (mm), its bore
/// checked.
pub(crate) fn rigid_train(
    rotor: &Rotor<'_>,
    case: &LoadCase,
    face_width_mm: f64,
    file: &str,
) -> Result<RigidTrain, LoadsError> {
    let r = rotor.assembly().rebuild();
    check_bore(&r, case, rotor, file)?;
    let masses = gear_masses(&r, case, face_width_mm);
    let sign = r.sign();
    let arm = case.arm.map(|a| {
        MassProperties::from_center_of_mass(
            a.mass_kg,
            Point::new(a.com_mm.x, sign * a.com_mm.y),
            a.inertia_kg_mm2,
        )
    });
    let bodies = TrainBodies {
        intermediate: masses[1],
        planet: masses[2].combined(arm.unwrap_or(MassProperties::ZERO)),
    };
    Ok(RigidTrain {
        alpha_rad: rotor.pressure_angle_rad(case),
        rebuilt: r,
        masses,
        bodies,
    })
}

/// [`analyse_with`] at the face width `face_width_mm` (mm).
pub(crate) fn analyse_at(
    rotor: &Rotor<'_>,
    case: &LoadCase,
    face_width_mm: f64,
    file: &str,
    dynamic: Option<&MeshForceSource<'_>>,
) -> Result<LoadsReport, LoadsError> {
    if case.rating.is_some() && rotor.teeth().is_none() {
        return Err(LoadsError::NoTeeth);
    }
    let RigidTrain {
        rebuilt: r,
        masses: [sun, mid, planet],
        bodies,
        alpha_rad: alpha,
    } = rigid_train(rotor, case, face_width_mm, file)?;
    let sign = r.sign();
    let mirror = |p: Point| Point::new(p.x, sign * p.y);
    let turn = train_turn(&r, case, &bodies, alpha)?;
    let g = mirror(case.gravity_m_s2);
    let sums = RotorSums::new(&turn, case.arms as usize, &sun, g);
    let n = case.samples;
    let travel_deg: Vec<f64> = (0..n).map(|k| 360.0 * k as f64 / n as f64).collect();
    let f = &turn.forces;
    let planet_torque: Vec<f64> = f.iter().map(|x| x.planet_mesh_torque_nm).collect();
    let meshes = Meshes::new(&turn, &r, rotor.assembly().center_mm, &travel_deg);
    let world = |v: Vec<Point>| v.into_iter().map(mirror).collect::<Vec<_>>();
    let summary = Summary::new(
        &travel_deg,
        &sums.carrier_nm,
        &planet_torque,
        &sums.frame_n,
        case.omega_rad_s,
    );
    let mut report = LoadsReport {
        operation: OperationReport::new(case, rotor.assembly().direction),
        travel_deg,
        carrier_torque_nm: sums.carrier_nm,
        sun_torque_nm: sums.sun_nm,
        planet_mesh_torque_nm: planet_torque,
        frame_force_n: world(sums.frame_n),
        needle_force_n: world(turn.needle_n.clone()),
        needle_table_n: needle_table(&r, case, &turn.motion).map_or_else(Vec::new, |t| {
            t.rows()
                .iter()
                .map(|(x, f)| [x.to_degrees(), f.x, f.y])
                .collect()
        }),
        bearings: Bearings {
            o_n: world(sums.bearing_o_n),
            d_n: world(f.iter().map(|x| x.bearing_d_n).collect()),
            a_n: world(f.iter().map(|x| x.bearing_a_n).collect()),
        },
        meshes,
        gears: GearsReport::new(case, face_width_mm, [sun, mid, planet], sign),
        summary,
        ..LoadsReport::default()
    };
    if let Some(opts) = &case.rating {
        let teeth = rotor.teeth().ok_or(LoadsError::NoTeeth)?;
        let machine = Machine {
            arms: case.arms,
            omega_rad_s: case.omega_rad_s,
            face_width_mm,
            bore_mm: case.bodies.map_or(0.0, |b| b.bore_mm),
        };
        let rated = if opts.on_dynamic_forces {
            let source = dynamic.ok_or_else(|| LoadsError::Field {
                file: file.into(),
                key: "rating.K_v".into(),
                message: "\"dynamic\" rates the teeth on the rotor dynamics' forces: run the \
                          scene through the dynamics (`ncgear loads`, or \
                          ncgear::analysis::dynamics::rotor::rating), or give K_v a number"
                    .into(),
            })?;
            let d = source(rotor, case, face_width_mm)?;
            if d.forces.len() != turn.forces.len() {
                return Err(LoadsError::Dynamics(format!(
                    "{} samples of dynamic forces for the turn's {}",
                    d.forces.len(),
                    turn.forces.len()
                )));
            }
            let mut on_dynamic = turn.clone();
            for (f, [sun, planet]) in on_dynamic.forces.iter_mut().zip(&d.forces) {
                f.sun_mesh = *sun;
                f.planet_mesh = *planet;
            }
            let mut rated = rate(&on_dynamic, &r, teeth, opts, &machine)?;
            rated.report.notes.insert(0, d.note);
            rated
        } else {
            rate(&turn, &r, teeth, opts, &machine)?
        };
        report.attach(rated);
    }
    report.finish();
    Ok(report)
}
