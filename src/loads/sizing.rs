//! The module sized by strength (`ncgear design TARGET --module auto --loads SCENE`): the target
//! designed for each standard module in turn, smallest first, toothed, its loads rated, and the
//! smallest module kept whose gears meet both safety targets — the face width the scene's, or
//! `auto`: the smallest within `[6, 15]·m` that meets them ([`super::analyse`]). The report is [`ModuleSizing`], one row per module tried
//! (the next smaller module's row says why it fails). A module whose design leaves the target
//! by more than [`SizingOptions::max_deviation_mm`] (its gear limits bind so hard that it is
//! another mechanism: G1 at 4 mm, 15 teeth, 14.8 mm off) is a failing row, not rated, and never
//! kept; within it a design that misses the target's tolerance is sized as any (its own verdict
//! fails: the closest admissible design at that module).

use super::analysis::{MeshForceSource, analyse_with};
use super::scene::{FaceWidth, LoadCase};
use super::{LoadsError, LoadsReport, Rotor};
use crate::design::report::sizing::{ModuleSizing, SizingRow};
use crate::design::train::{
    PendingTrainMesh, ToothedTrain, TrainPolicy, TrainTeethOptions, tooth_train_staged,
};
use crate::design::trajectory::Trajectory;
use crate::design::{Design, DesignOptions, design};
use crate::teeth::TeethError;
use serde::{Deserialize, Serialize};

/// The standard modules of ISO 54 (series I, and 1.25 of series I too), mm, tried in turn.
pub const STANDARD_MODULES_MM: [f64; 12] = [
    1.0, 1.25, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0, 6.0, 8.0, 10.0, 12.0,
];

/// Options of the sizing; [`Default`] fills the documented defaults.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
#[non_exhaustive]
pub struct SizingOptions {
    /// Modules tried, smallest first, mm. Default [`STANDARD_MODULES_MM`].
    pub modules_mm: Vec<f64>,
    /// Go on past the first module that passes (the trade-off's full table). Default false.
    pub all_modules: bool,
    /// Largest deviation from the target, mm, of a design the sizing rates and may keep.
    /// Default [`SIZING_MAX_DEVIATION_MM`].
    pub max_deviation_mm: f64,
}

/// The default [`SizingOptions::max_deviation_mm`], mm: a few times a planting hole's
/// tolerance, far above any design tolerance (0.05 mm by default).
pub const SIZING_MAX_DEVIATION_MM: f64 = 5.0;

impl Default for SizingOptions {
    fn default() -> Self {
        Self {
            modules_mm: STANDARD_MODULES_MM.to_vec(),
            all_modules: false,
            max_deviation_mm: SIZING_MAX_DEVIATION_MM,
        }
    }
}

crate::builder::with_fields!(SizingOptions {
    with_modules_mm => modules_mm: Vec<f64>,
    with_all_modules => all_modules: bool,
    with_max_deviation_mm => max_deviation_mm: f64,
});

/// The sized design: the table, and the kept module's design, teeth and loads (the best row's
/// when none passes, so that its files can be written and its verdict fail).
#[derive(Debug, Clone)]
pub struct Sized {
    /// The table.
    pub sizing: ModuleSizing,
    /// The design kept, its teeth and loads (absent when no module could be designed and rated).
    pub kept: Option<Kept>,
}

/// The module kept by the sizing: its design, the teeth that were rated, their mesh check still
/// to run ([`PendingTrainMesh::run`]; `None` when the tooth options ask for no check) and the
/// loads of those teeth — what `ncgear design --module auto` writes, without cutting again.
#[derive(Debug, Clone)]
pub struct Kept {
    /// The design made for the kept module.
    pub design: Design,
    /// Its teeth, cut with the sizing's tooth options at that module.
    pub train: ToothedTrain,
    /// The mesh check of those teeth, still to run.
    pub pending_mesh: Option<PendingTrainMesh>,
    /// The loads and rating of those teeth.
    pub loads: LoadsReport,
}

/// The tooth options the sizing cuts each module with when the caller has none of its own: the
/// defaults at module `module_mm` ([`TrainTeethOptions::new`]), the designed tooth count, no mesh
/// check (the rating does not read it).
///
/// # Errors
/// None today; the signature is the one [`size_module`] takes.
pub fn rating_teeth(module_mm: f64) -> Result<TrainTeethOptions, TeethError> {
    let mut t = TrainTeethOptions::new(module_mm).with_policy(TrainPolicy::Designed);
    t.toothing.verify_steps = 0;
    Ok(t)
}

/// Whether a report meets its targets, and the row's failure text when not.
fn judge(r: &LoadsReport) -> (bool, Option<String>) {
    let Some(rating) = &r.rating else {
        return (false, Some("no rating".into()));
    };
    let fails: Vec<String> = rating
        .shortfalls()
        .into_iter()
        .map(|(symbol, target, e)| {
            let at = if symbol == "S_H" {
                e.mesh.clone()
            } else {
                format!("{} root", e.gear)
            };
            format!("{symbol} {:.3} < {target} ({at})", e.value)
        })
        .collect();
    (
        fails.is_empty(),
        (!fails.is_empty()).then(|| fails.join("; ")),
    )
}

/// The row of a module whose design, teeth or rating failed.
fn failed_row(module_mm: f64, why: String) -> SizingRow {
    SizingRow {
        module_mm,
        fails: Some(why),
        ..SizingRow::default()
    }
}

/// Sizes the module of `target` (module docs): `design_opts` as for any design (the module
/// replaced by each one tried), `case` the scene's loads and rating, `teeth` the tooth options
/// at a module (mm; [`rating_teeth`], or the caller's rack, fillet and policy — the teeth rated
/// are the teeth kept); `dynamic` the forces of a `K_v = "dynamic"` rating ([`analyse_with`]);
/// `file` names the scene.
///
/// # Errors
/// [`LoadsError::Field`] when the scene rates nothing (no `[material]`) or has no gear bodies;
/// a design's own failure is a row of the table, not an error.
pub fn size_module(
    target: &Trajectory,
    design_opts: &DesignOptions,
    case: &LoadCase,
    opts: &SizingOptions,
    teeth: &dyn Fn(f64) -> Result<TrainTeethOptions, TeethError>,
    dynamic: Option<&MeshForceSource<'_>>,
    file: &str,
) -> Result<Sized, LoadsError> {
    let rating = case.rating.as_ref().ok_or_else(|| LoadsError::Field {
        file: file.into(),
        key: "material".into(),
        message: "sizing the module by strength needs a [material] (and [gears] with the face \
                  width or \"auto\")"
            .into(),
    })?;
    let targets = (rating.s_h_min, rating.s_f_min);
    let mut sizing = ModuleSizing {
        s_h_min: targets.0,
        s_f_min: targets.1,
        face_width: match case.bodies.map(|b| b.face_width) {
            Some(FaceWidth::Mm(b)) => format!("{b}"),
            _ => "auto".into(),
        },
        ..ModuleSizing::default()
    };
    let mut kept: Option<Kept> = None;
    let mut best_margin = f64::NEG_INFINITY;
    for &m in &opts.modules_mm {
        // A module's design inside the search: its failure is a row, not a reason to design
        // its alternatives.
        let module_opts = design_opts
            .clone()
            .with_module_mm(Some(m))
            .with_alternatives(false);
        let mut d = match design(target, &module_opts) {
            Ok(d) => d,
            Err(e) => {
                sizing.rows.push(failed_row(m, format!("design: {e}")));
                continue;
            }
        };
        let deviation_mm = d.report.roundtrip.max_deviation_mm;
        if deviation_mm > opts.max_deviation_mm {
            sizing.rows.push(SizingRow {
                max_deviation_mm: Some(deviation_mm),
                ..failed_row(
                    m,
                    format!(
                        "design: {deviation_mm:.3} mm from the target, more than the sizing \
                         accepts ({} mm): another mechanism, not rated",
                        opts.max_deviation_mm
                    ),
                )
            });
            continue;
        }
        let topts = match teeth(m) {
            Ok(t) => t,
            Err(e) => {
                sizing
                    .rows
                    .push(failed_row(m, format!("tooth options: {e}")));
                continue;
            }
        };
        let t0 = std::time::Instant::now();
        let cut = tooth_train_staged(&d, &topts);
        d.report.timings_ms.teeth = 1e3 * t0.elapsed().as_secs_f64();
        let (train, pending_mesh) = match cut {
            Ok(t) => t,
            Err(e) => {
                sizing.rows.push(failed_row(m, format!("teeth: {e}")));
                continue;
            }
        };
        let report = match analyse_with(&Rotor::toothed(&train), case, file, dynamic) {
            Ok(r) => r,
            Err(e) => {
                sizing.rows.push(failed_row(m, format!("loads: {e}")));
                continue;
            }
        };
        let (passed, fails) = judge(&report);
        let rr = report.rating.as_ref();
        let g = &report.gears;
        sizing.rows.push(SizingRow {
            module_mm: m,
            teeth: Some(train.report.z),
            face_width_mm: report.gears.face_width_mm,
            max_deviation_mm: Some(train.report.roundtrip.max_deviation_mm),
            s_h: rr.map(|r| r.min_s_h.value),
            s_f: rr.map(|r| r.min_s_f.value),
            gears_mass_kg: Some(
                g.sun.mass_kg + f64::from(case.arms) * (g.intermediate.mass_kg + g.planet.mass_kg),
            ),
            carrier_torque_peak_nm: Some(report.summary.carrier_torque_peak_nm),
            life_h: rr.map(|r| r.life_h),
            passed,
            fails,
        });
        let margin = rr.map_or(f64::NEG_INFINITY, |r| {
            (r.min_s_h.value / targets.0).min(r.min_s_f.value / targets.1)
        });
        if passed && sizing.chosen_module_mm.is_none() {
            sizing.chosen_module_mm = Some(m);
            kept = Some(Kept {
                design: d,
                train,
                pending_mesh,
                loads: report,
            });
            if !opts.all_modules {
                break;
            }
        } else if sizing.chosen_module_mm.is_none() && margin > best_margin {
            best_margin = margin;
            kept = Some(Kept {
                design: d,
                train,
                pending_mesh,
                loads: report,
            });
        }
    }
    Ok(Sized { sizing, kept })
}

impl Sized {
    /// The kept module's design carrying the table in its report (`report.sizing`, the verdict
    /// updated with the sizing's targets): what `ncgear design --module auto --loads SCENE`
    /// writes and `ncgear.design(points, module="auto", loads=scene)` returns. `Err(table)`
    /// when no module could be designed and rated.
    ///
    /// # Errors
    /// The table, when no module was kept.
    pub fn into_kept(self) -> Result<Kept, ModuleSizing> {
        match self.kept {
            Some(mut kept) => {
                kept.design.report.sizing = Some(self.sizing);
                kept.design.report.update_verdict();
                Ok(kept)
            }
            None => Err(self.sizing),
        }
    }
}
