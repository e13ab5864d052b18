//! Tip relief of the train's shaper-cut gears ([`crate::teeth::tip_relief`]): each is
//! checked against every neighbour it meshes with — the sun and the planet against the
//! intermediate gear, the intermediate gear against both — and relieved tooth by tooth.
use super::TrainError;
use super::swept::{TrainMeshes, neighbours};
use crate::math::Point;
use crate::teeth::GearBlank;
use crate::teeth::mesh::Shape;
use crate::teeth::process::GearProcess;
use crate::teeth::tip_relief::{self, ReliefMesh, Relieved};

/// Gear `k` (0 sun, 1 intermediate, 2 planet), `blank` cut as `as_cut` records, relieved
/// against its neighbours' `fine` outlines (body frames, mm) over one carrier turn (each mesh's
/// contact runs `z` pitches per turn), its fine outline regenerated at `verify_chord_tol_mm`;
/// `None` when no tooth needs it.
///
/// Errors: [`TrainError::Mesh`] (a neighbour's outline cannot be indexed),
/// [`TrainError::Teeth`] (the relieved gear cannot be generated).
pub(super) fn relieve_gear(
    k: usize,
    fine: &[Vec<Point>; 3],
    meshes: &TrainMeshes<'_>,
    blank: &GearBlank<'_>,
    as_cut: &GearProcess,
    verify_chord_tol_mm: f64,
) -> Result<Option<Relieved>, TrainError> {
    let (z, module_mm) = (blank.z, blank.module_mm);
    const NAMES: [&str; 3] = ["sun", "intermediate", "planet"];
    const MESHES: [&str; 2] = ["sun-intermediate", "intermediate-planet"];
    let shapes = neighbours(k)
        .iter()
        .map(|&(nb, mesh, _)| {
            Shape::new(&fine[nb], 0.02 * module_mm, NAMES[nb]).map_err(|source| TrainError::Mesh {
                pair: MESHES[mesh],
                source,
            })
        })
        .collect::<Result<Vec<_>, _>>()?;
    let checks: Vec<ReliefMesh<'_>> = neighbours(k)
        .iter()
        .zip(&shapes)
        .map(|(&(_, mesh, role), mate)| ReliefMesh {
            mate,
            motion: &meshes.motions[mesh],
            gear: role,
            positions: z as usize * tip_relief::POSITIONS_PER_PITCH,
        })
        .collect();
    tip_relief::relieve_gear(blank, as_cut, verify_chord_tol_mm, &checks).map_err(|source| {
        TrainError::Teeth {
            gear: NAMES[k],
            source,
        }
    })
}
