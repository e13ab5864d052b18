//! Gears of the train that no cutter makes: swept by their cut neighbours instead
//! (wire EDM, printing; [`crate::teeth::conjugate`]) — the sun and the planet by the intermediate
//! gear, the intermediate gear by both.
use crate::geometry::pitch::PitchCurve;
use crate::math::Point;
use crate::teeth::conjugate::Mate;
use crate::teeth::mate_motion::MeshMotion;
use crate::teeth::{GearBlank, Generated, Generation, TeethError, generate};

/// The train's two meshes over a carrier turn: `[sun → intermediate, intermediate → planet]`
/// (driver first), and the whole-outline mate positions per turn.
pub(super) struct TrainMeshes<'a> {
    pub(super) motions: [MeshMotion<'a>; 2],
    pub(super) positions: usize,
}

/// The gears each gear meshes with: `(neighbour, mesh, this gear's role in that mesh)` with role
/// 0 = driver, 1 = driven.
pub(super) fn neighbours(k: usize) -> &'static [(usize, usize, usize)] {
    match k {
        0 => &[(1, 0, 0)],
        1 => &[(0, 0, 1), (2, 1, 0)],
        _ => &[(1, 1, 1)],
    }
}

/// Gear `k` (0 sun, 1 intermediate, 2 planet) swept by its neighbours' `outlines` (body frames,
/// mm), cut from `blank`, with its process (wire EDM).
pub(super) fn sweep_gear(
    k: usize,
    outlines: [&[Point]; 3],
    pitches: [&PitchCurve; 3],
    meshes: &TrainMeshes<'_>,
    blank: &GearBlank<'_>,
) -> Result<Generated, TeethError> {
    let poses: Vec<_> = neighbours(k)
        .iter()
        .map(|&(_, mesh, role)| {
            let motion = &meshes.motions[mesh];
            move |u: f64, set: usize| motion.mate_pose(role, u, set)
        })
        .collect();
    let mates: Vec<Mate<'_>> = neighbours(k)
        .iter()
        .zip(&poses)
        .map(|(&(other, _, _), pose)| Mate {
            outline_mm: outlines[other],
            pitch: pitches[other],
            pose,
            offsets: 2,
            positions: meshes.positions,
        })
        .collect();
    generate(blank, Generation::Swept(&mates))
}

/// Whether gear `k` can be swept: every neighbour is cut (not swept itself).
pub(super) fn sweepable(k: usize, cut: [bool; 3]) -> bool {
    neighbours(k).iter().all(|&(other, _, _)| cut[other])
}
