//! Cutting the train's three gears on their arc frames: the export outlines by process (a gear
//! no cutter fits swept by its cut neighbours), then the fine outlines of the mesh check and the
//! tip relief of the meshes with a shaper-cut gear.
use super::TrainError;
use super::shaper_relief::relieve_gear;
use super::swept::{TrainMeshes, neighbours, sweep_gear, sweepable};
use crate::geometry::pitch::PitchCurve;
use crate::math::Point;
use crate::teeth::process::{GearProcess, Process, swept_process};
use crate::teeth::{
    ArcFrame, GearBlank, Generated, Generation, Outline, OutlineOptions, TeethError,
    ToothingOptions, generate,
};
use rayon::prelude::*;

/// The gears' names, in gear order.
const NAMES: [&str; 3] = ["sun", "intermediate", "planet"];

/// The error of a gear's teeth, naming the gear.
pub(super) fn teeth_err(gear: &'static str) -> impl Fn(TeethError) -> TrainError {
    move |source| TrainError::Teeth { gear, source }
}

/// Whether a gear is cut by a shaper.
fn shaped(p: &GearProcess) -> bool {
    p.process == Process::Shaper
}

/// What the three gears (sun, intermediate, planet) are cut on: the toothing, the arc frames and
/// pitch curves, the meshes over a carrier turn, the mating phases, the tooth count and module.
pub(super) struct Cutting<'a> {
    pub(super) toothing: &'a ToothingOptions,
    pub(super) wire_edm: bool,
    pub(super) frames: &'a [ArcFrame; 3],
    pub(super) pitches: [&'a PitchCurve; 3],
    pub(super) meshes: &'a TrainMeshes<'a>,
    pub(super) phases: [f64; 3],
    pub(super) z: u32,
    pub(super) module_mm: f64,
}

/// The cut gears: export outlines and processes in gear order, and which gears were swept.
pub(super) struct CutGears {
    pub(super) gears: [Outline; 3],
    pub(super) processes: [GearProcess; 3],
    pub(super) swept: [bool; 3],
}

impl Cutting<'_> {
    /// Gear `k`'s blank at chord tolerance `tol` (mm): its mating phase, the coast flank thinned
    /// by half the backlash.
    fn blank(&self, k: usize, tol: f64) -> GearBlank<'_> {
        let opts = OutlineOptions {
            phase_mm: self.phases[k],
            thin_left_mm: 0.5 * self.toothing.backlash_mm,
            thin_right_mm: 0.0,
            chord_tol_mm: tol,
            open_pitch_mm: None,
            refuse_undercut: self.toothing.refuse_undercut,
        };
        let rack = self.toothing.rack;
        GearBlank::new(&self.frames[k], rack, self.z, self.module_mm, opts)
    }

    /// Gear `k` swept by its neighbours' `outlines` (body frames, mm) at chord tolerance `tol`.
    fn sweep(&self, k: usize, outlines: [&[Point]; 3], tol: f64) -> Result<Generated, TeethError> {
        sweep_gear(k, outlines, self.pitches, self.meshes, &self.blank(k, tol))
    }

    /// The export outlines and processes: each gear by the cutter its curve takes, side by side;
    /// a gear no cutter fits is swept by its neighbours when they are cut (and `wire_edm`).
    pub(super) fn cut(&self) -> Result<CutGears, TrainError> {
        let tol = self.toothing.chord_tol_mm;
        let choice = self.toothing.cutter_choice();
        let mut results: Vec<_> = (0..3)
            .into_par_iter()
            .map(|k| generate(&self.blank(k, tol), Generation::Process(choice)))
            .collect();
        // A gear no cutter fits is swept by its neighbours when they are cut.
        let cut = [0, 1, 2].map(|k| results[k].is_ok());
        let swept = [0, 1, 2].map(|k| {
            self.wire_edm
                && matches!(results[k], Err(TeethError::NoCutter { .. }))
                && sweepable(k, cut)
        });
        for k in (0..3).filter(|&k| swept[k]) {
            let outlines = [0, 1, 2].map(|j| {
                results[j]
                    .as_ref()
                    .map_or(&[][..], |g| g.outline.points_mm.as_slice())
            });
            let made = self.sweep(k, outlines, tol);
            let placeholder = Err(TeethError::Swept {
                what: String::new(),
            });
            if let Err(no_cutter) = std::mem::replace(&mut results[k], placeholder) {
                results[k] = made.and_then(|g| {
                    let process = swept_process(no_cutter, g.process)?;
                    Ok(Generated { process, ..g })
                });
            }
        }
        let mut gears = results
            .into_iter()
            .enumerate()
            .map(|(k, r)| r.map_err(teeth_err(NAMES[k])));
        let sun = gears.next().expect("three gears")?;
        let intermediate = gears.next().expect("three gears")?;
        let planet = gears.next().expect("three gears")?;
        Ok(CutGears {
            gears: [sun.outline, intermediate.outline, planet.outline],
            processes: [sun.process, intermediate.process, planet.process],
            swept,
        })
    }

    /// The fine outlines: for the mesh check, and for the tip relief of shaper-cut gears (which
    /// updates `cut`); `None` when neither needs them.
    pub(super) fn fine(&self, cut: &mut CutGears) -> Result<Option<[Vec<Point>; 3]>, TrainError> {
        if !(self.toothing.verify_steps > 0 || cut.processes.iter().any(shaped)) {
            return Ok(None);
        }
        let mut fine = self.fine_outlines(cut)?;
        self.relieve(cut, &mut fine)?;
        Ok(Some(fine))
    }

    /// The unrelieved fine outlines at the verification's chord tolerance.
    fn fine_outlines(&self, cut: &CutGears) -> Result<[Vec<Point>; 3], TrainError> {
        // Built side by side (collected in gear order); the swept gears then from their
        // neighbours' fine outlines.
        let tol = self.toothing.verify_chord_tol_mm;
        let (gears, processes, swept) = (&cut.gears, &cut.processes, cut.swept);
        let mut fine: Vec<Outline> = (0..3)
            .into_par_iter()
            .map(|k| {
                if swept[k] {
                    Ok(Outline {
                        points_mm: Vec::new(),
                        ..gears[k].clone()
                    })
                } else {
                    // The same process and cutter as the export outline.
                    generate(&self.blank(k, tol), Generation::AsCut(&processes[k]))
                        .map(|g| g.outline)
                        .map_err(teeth_err(NAMES[k]))
                }
            })
            .collect::<Result<_, _>>()?;
        for k in (0..3).filter(|&k| swept[k]) {
            let outlines = [0, 1, 2].map(|j| fine[j].points_mm.as_slice());
            let g = self.sweep(k, outlines, tol).map_err(teeth_err(NAMES[k]))?;
            fine[k] = g.outline;
        }
        Ok(<[Outline; 3]>::try_from(fine)
            .unwrap_or_else(|_| unreachable!("three gears"))
            .map(|o| o.points_mm))
    }

    /// Tip relief of the cut gears of every mesh with a shaper-cut gear, against their
    /// neighbours, all found on the unrelieved outlines (a relief moves only tips, never a
    /// fillet); the meshes of two rack-cut (convex) gears keep their outlines.
    fn relieve(&self, cut: &mut CutGears, fine: &mut [Vec<Point>; 3]) -> Result<(), TrainError> {
        let (processes, swept) = (&cut.processes, cut.swept);
        let relieve = |k: usize| {
            let mesh_has_shaper = shaped(&processes[k])
                || neighbours(k)
                    .iter()
                    .any(|&(nb, _, _)| shaped(&processes[nb]));
            !swept[k] && mesh_has_shaper
        };
        let unrelieved = &*fine;
        let relieved = (0..3)
            .into_par_iter()
            .map(|k| {
                if !relieve(k) {
                    return Ok(None);
                }
                relieve_gear(
                    k,
                    unrelieved,
                    self.meshes,
                    &self.blank(k, self.toothing.chord_tol_mm),
                    &processes[k],
                    self.toothing.verify_chord_tol_mm,
                )
            })
            .collect::<Result<Vec<_>, _>>()?;
        for (k, r) in relieved.into_iter().enumerate() {
            if let Some(r) = r {
                cut.gears[k] = r.export;
                fine[k] = r.fine_mm;
                cut.processes[k].set_relief(&r.relief_mm, r.min_tip_width_mm);
            }
        }
        Ok(())
    }
}
