//! From the meshes' per-sample stresses to each gear's rating: the smallest safety factors and
//! where they occur, the teeth loaded on both flanks (alternating bending, Y_M), the life by
//! Miner's sum, and the remarks on the standard's validity.

use super::life::{Engagement, engagements, hours, worst_damage};
use super::mesh::MeshRating;
use super::{Extreme, GearRating, Machine, RatingOptions, RatingReport};
use crate::loads::kinetostatics::{MeshForce, TrainTurn};
use std::collections::{BTreeMap, BTreeSet};

/// Largest effective pressure angle ISO 6336's factors are validated for, deg.
pub const VALID_PRESSURE_ANGLE_DEG: f64 = 25.0;

/// The gear names in train order.
const NAMES: [&str; 3] = ["sun", "intermediate", "planet"];

/// A rated mesh: its name, its gears (indices into [`NAMES`]) and its per-sample rating.
pub(super) type RatedMesh = (&'static str, [usize; 2], MeshRating);

/// The rating report of both meshes.
pub(super) fn summarize(
    rated: &[RatedMesh; 2],
    turn: &TrainTurn,
    opts: &RatingOptions,
    module_mm: f64,
    machine: &Machine,
) -> RatingReport {
    let n = turn.motion.len();
    let travel: Vec<f64> = (0..n).map(|k| 360.0 * k as f64 / n as f64).collect();
    let mut gears = BTreeMap::new();
    let mut min_s_f = Extreme {
        value: f64::MAX,
        ..Extreme::default()
    };
    let mut life = (f64::MAX, String::new());
    for (g, name) in NAMES.iter().enumerate() {
        let rating = rate_gear(g, rated, &travel, opts, machine);
        for (h, mode) in [
            (rating.bending_life_h, "tooth breakage"),
            (rating.pitting_life_h, "pitting"),
        ] {
            if h < life.0 {
                life = (h, format!("{name}: {mode}"));
            }
        }
        if rating.min_s_f.value < min_s_f.value {
            min_s_f = rating.min_s_f.clone();
        }
        gears.insert((*name).to_string(), rating);
    }
    RatingReport {
        options: opts.clone(),
        face_width_mm: machine.face_width_mm,
        module_mm,
        min_s_h: min_pitting(rated, &travel, opts.material.sigma_hlim_mpa),
        min_s_f,
        life_h: life.0,
        life_limited_by: life.1,
        gears,
        notes: notes(rated, turn, &travel, opts),
    }
}

/// The teeth of gear `g`'s series loaded on both flanks over the turn (alternating bending).
fn alternating_teeth(series: &[(&str, usize, &MeshRating)]) -> BTreeSet<usize> {
    let mut flanks: BTreeMap<usize, BTreeSet<usize>> = BTreeMap::new();
    for (_, i, mr) in series {
        for (k, root) in mr.root_mpa[*i].iter().enumerate() {
            if *root > 0.0 {
                flanks
                    .entry(mr.tooth[*i][k])
                    .or_default()
                    .insert(mr.flank[*i][k]);
            }
        }
    }
    flanks
        .into_iter()
        .filter(|(_, f)| f.len() > 1)
        .map(|(t, _)| t)
        .collect()
}

/// Gear `g`'s rating over both its meshes: the smallest bending safety factor and where, the
/// largest root stress, the range of Y_F·Y_S, the teeth in alternating bending, the lives.
fn rate_gear(
    g: usize,
    rated: &[RatedMesh; 2],
    travel: &[f64],
    opts: &RatingOptions,
    machine: &Machine,
) -> GearRating {
    let mat = &opts.material;
    // The series of this gear: (mesh, its index in the mesh, the mesh's rating).
    let series: Vec<(&str, usize, &MeshRating)> = rated
        .iter()
        .filter_map(|(mesh, pair, mr)| pair.iter().position(|&p| p == g).map(|i| (*mesh, i, mr)))
        .collect();
    let alternating = alternating_teeth(&series);
    let limit_f = |tooth: usize| {
        let y_m = if alternating.contains(&tooth) {
            opts.factors.y_m
        } else {
            1.0
        };
        opts.factors.y_st * y_m * mat.sigma_flim_mpa
    };
    let mut rating = GearRating {
        min_s_f: Extreme {
            value: f64::MAX,
            ..Extreme::default()
        },
        y_f_y_s_range: [f64::INFINITY, 0.0],
        alternating_teeth: alternating.len(),
        ..GearRating::default()
    };
    let (mut bending, mut pitting): (Vec<Engagement>, Vec<Engagement>) = Default::default();
    for (mesh, i, mr) in &series {
        let root = &mr.root_mpa[*i];
        for (k, &sigma) in root.iter().enumerate().filter(|(_, s)| **s > 0.0) {
            let tooth = mr.tooth[*i][k];
            let s = limit_f(tooth) / sigma;
            rating.max_root_stress_mpa = rating.max_root_stress_mpa.max(sigma);
            let yfs = mr.y_fs[*i][k];
            rating.y_f_y_s_range = [
                rating.y_f_y_s_range[0].min(yfs),
                rating.y_f_y_s_range[1].max(yfs),
            ];
            if s < rating.min_s_f.value {
                rating.min_s_f = Extreme {
                    value: s,
                    travel_deg: travel[k],
                    mesh: (*mesh).into(),
                    gear: NAMES[g].into(),
                    tooth,
                };
            }
        }
        bending.extend(engagements(&mr.tooth[*i], &mr.flank[*i], root));
        pitting.extend(engagements(&mr.tooth[*i], &mr.flank[*i], &mr.contact_mpa));
    }
    if rating.y_f_y_s_range[0] > rating.y_f_y_s_range[1] {
        // No tooth of this gear carried a load.
        rating.y_f_y_s_range = [0.0, 0.0];
    }
    // The sun meets every arm's intermediate gear in a turn.
    let repeats = if g == 0 { f64::from(machine.arms) } else { 1.0 };
    let rpm = machine.omega_rad_s * 60.0 / std::f64::consts::TAU;
    let bending = worst_damage(&bending, limit_f, &mat.bending_sn, repeats, false);
    let pitting = worst_damage(
        &pitting,
        |_| mat.sigma_hlim_mpa,
        &mat.contact_sn,
        repeats,
        true,
    );
    rating.bending_life_h = hours(bending, rpm);
    rating.pitting_life_h = hours(pitting, rpm);
    rating
}

/// The smallest pitting safety factor over both meshes: at the sample, the mesh's pinion (the
/// gear of the smaller flank radius) and its tooth.
fn min_pitting(rated: &[RatedMesh; 2], travel: &[f64], sigma_hlim_mpa: f64) -> Extreme {
    let mut best = Extreme {
        value: f64::MAX,
        ..Extreme::default()
    };
    for (mesh, pair, mr) in rated {
        for (k, &sigma) in mr.contact_mpa.iter().enumerate() {
            if !(sigma > 0.0) {
                continue;
            }
            let s = sigma_hlim_mpa / sigma;
            if s < best.value {
                let [f1, f2] = mr.flank_radius_mm[k];
                let i = usize::from(f2.abs() < f1.abs() && f2 > 0.0 || f1 < 0.0);
                best = Extreme {
                    value: s,
                    travel_deg: travel[k],
                    mesh: (*mesh).into(),
                    gear: NAMES[pair[i]].into(),
                    tooth: mr.tooth[i][k],
                };
            }
        }
    }
    best
}

/// The remarks: where the rating leaves the standard's validity.
fn notes(
    rated: &[RatedMesh; 2],
    turn: &TrainTurn,
    travel: &[f64],
    opts: &RatingOptions,
) -> Vec<String> {
    let mut out = Vec::new();
    for (mesh, pair, mr) in rated {
        let force = |k: usize| -> &MeshForce {
            if *mesh == "sun_intermediate" {
                &turn.forces[k].sun_mesh
            } else {
                &turn.forces[k].planet_mesh
            }
        };
        let peak = (0..turn.forces.len())
            .map(force)
            .filter(|f| f.normal_force_n > 0.0)
            .map(|f| f.effective_pressure_angle_rad.to_degrees())
            .fold(0.0, f64::max);
        if peak > VALID_PRESSURE_ANGLE_DEG {
            out.push(format!(
                "{mesh}: effective pressure angle up to {peak:.1}° (ISO 6336 is validated up to \
                 about {VALID_PRESSURE_ANGLE_DEG}°; teeth at larger angles do not gain the \
                 strength its formulas give them: read the safety factors there as optimistic)"
            ));
        }
        if mr.concave > 0 {
            out.push(format!(
                "{mesh}: a concave flank carries the contact at {} of {} samples: rated as the \
                 local internal pair (Hertz with the concave radius, the 60° tangent at its root)",
                mr.concave,
                mr.contact_ratio.len()
            ));
        }
        if mr.q_s[0] < 1.0 || mr.q_s[1] >= 8.0 {
            out.push(format!(
                "{mesh}: the notch parameter q_s runs over {:.2}…{:.2}, outside ISO 6336-3's \
                 1 ≤ q_s < 8 for Y_S",
                mr.q_s[0], mr.q_s[1]
            ));
        }
        let (eps, k) = mr.min_contact_ratio;
        if eps < 1.0 {
            out.push(format!(
                "{mesh}: the local contact ratio falls to {eps:.3} < 1 at travel {:.1}° ({} and \
                 {}): one tooth pair at a time cannot keep the contact there",
                travel[k], NAMES[pair[0]], NAMES[pair[1]]
            ));
        }
    }
    if opts.material.name == "pom" {
        out.push(
            "material pom: ISO 6336 rates metal gears; a plastic gear rated by its structure \
             (VDI 2736 strength values) is a first estimate"
                .into(),
        );
    }
    out
}
