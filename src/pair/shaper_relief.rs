//! Tip relief of a pair's shaper-cut gears ([`crate::teeth::tip_relief`]): each is checked
//! against its mate over the mesh cycle and relieved tooth by tooth.
use super::PairError;
use super::design::{PairOptions, Toothed};
use crate::math::Point;
use crate::teeth::mate_motion::MeshMotion;
use crate::teeth::mesh::Shape;
use crate::teeth::process::Process;
use crate::teeth::tip_relief::{self, ReliefMesh, Relieved, relieve_gear};

/// The pair's gears, as named in errors.
const GEAR_NAMES: [&str; 2] = ["driver", "driven"];

impl Toothed {
    /// Tip relief of both cut gears of a pair with a shaper-cut gear against their mate's fine
    /// outline ([`crate::teeth::tip_relief`]) over the mesh `motion`, whose cycle spans
    /// `cycle_pitches` driver pitches: the relieved gears' export and `fine` outlines are
    /// regenerated and their process reports record it. Both reliefs are found on the unrelieved
    /// outlines (a relief moves only tips, never a fillet). A pair of rack-cut (convex) gears is
    /// left as it is: a convex gear's tips keep a margin short of the mate's form point.
    pub(super) fn relieve(
        &mut self,
        opts: &PairOptions,
        motion: &MeshMotion<'_>,
        fine: &mut [Vec<Point>; 2],
        cycle_pitches: usize,
    ) -> Result<(), PairError> {
        let t = &opts.toothing;
        let m = t.module_mm;
        let procs = [&self.driver_process, &self.driven_process];
        let shaped = procs.iter().any(|p| p.process == Process::Shaper);
        let relieve = |k: usize| -> Result<Option<Relieved>, PairError> {
            if !shaped || procs[k].process == Process::WireEdm {
                return Ok(None);
            }
            let mate = Shape::new(&fine[1 - k], 0.02 * m, GEAR_NAMES[1 - k])?;
            let mesh = ReliefMesh {
                mate: &mate,
                motion,
                gear: k,
                positions: cycle_pitches * tip_relief::POSITIONS_PER_PITCH,
            };
            Ok(relieve_gear(
                &self.blank(k, t),
                procs[k],
                t.verify_chord_tol_mm,
                &[mesh],
            )?)
        };
        let (r0, r1) = rayon::join(|| relieve(0), || relieve(1));
        for (k, r) in [(0, r0?), (1, r1?)] {
            let Some(r) = r else { continue };
            let (outline, process) = if k == 0 {
                (&mut self.driver, &mut self.driver_process)
            } else {
                (&mut self.driven, &mut self.driven_process)
            };
            *outline = r.export;
            fine[k] = r.fine_mm;
            process.set_relief(&r.relief_mm, r.min_tip_width_mm);
        }
        Ok(())
    }

    /// Whether a gear is shaper-cut (it may need a tip relief).
    pub(super) fn has_shaper(&self) -> bool {
        [&self.driver_process, &self.driven_process]
            .iter()
            .any(|p| p.process == Process::Shaper)
    }
}
