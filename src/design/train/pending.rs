//! The mesh verification of a toothed train, split off so that it can run beside the CAD exports
//! (they do not read it): [`super::tooth_train_staged`] returns the train and this pending
//! check; [`PendingTrainMesh::run`] gives the `mesh` block of the report.

use super::TrainError;
use super::report::TrainMesh;
use crate::geometry::assembly::Rebuilt;
use crate::math::Point;
use crate::math::roots::bracketed_root;
use crate::progress::Progress;
use crate::teeth::mesh::{MeshCheck, verify_mesh};

/// Both meshes of a toothed train still to verify: the fine outlines of the three gears (mm, body
/// frames), the train's kinematics and the check's parameters.
#[derive(Debug, Clone)]
pub struct PendingTrainMesh {
    pub(super) outlines: [Vec<Point>; 3],
    pub(super) rebuilt: Rebuilt,
    pub(super) check: MeshCheck,
}

impl PendingTrainMesh {
    /// The check's parameters (steps, backlash, centre distance, module).
    #[must_use]
    pub fn check(&self) -> &MeshCheck {
        &self.check
    }

    /// Verifies sun → intermediate (driver angle φ = −(φH + ε), the sun seen from its line of
    /// centres OD) and intermediate → planet (φ = θ2(φH) − (φH − ε), from DA) side by side, in the
    /// laws the train layout gives each mesh (docs/math/chain.md §6.5); `progress` told of each
    /// verified position, `2·steps` in all.
    ///
    /// # Errors
    /// [`TrainError::Mesh`]: an outline the check cannot index.
    pub fn run(&self, progress: &Progress) -> Result<TrainMesh, TrainError> {
        let rebuilt = &self.rebuilt;
        let eps = rebuilt.assembly().idler_offset_rad;
        let theta2 = |phi_h: f64| rebuilt.pose(phi_h).intermediate_angle_rad;
        let psi1 = |phi: f64| -phi - theta2(-phi - eps);
        // φ = θ2(φH) − φH + ε increases with φH: inverted by a bracketed root.
        let phi2 = |phi_h: f64| theta2(phi_h) - phi_h + eps;
        let phi2_0 = phi2(0.0);
        let psi2 = |phi: f64| {
            let guess = phi - phi2_0;
            let phi_h = bracketed_root(|x| phi2(x) - phi, guess - 16.0, guess + 16.0, 1e-15);
            phi_h - eps - rebuilt.pose(phi_h).planet_angle_rad
        };
        let [sun, mid, planet] = &self.outlines;
        // The two meshes are independent: checked side by side.
        let (sun_intermediate, intermediate_planet) = rayon::join(
            || verify_mesh(sun, mid, &psi1, &self.check, progress),
            || verify_mesh(mid, planet, &psi2, &self.check, progress),
        );
        Ok(TrainMesh {
            sun_intermediate: sun_intermediate.map_err(|source| TrainError::Mesh {
                pair: "sun-intermediate",
                source,
            })?,
            intermediate_planet: intermediate_planet.map_err(|source| TrainError::Mesh {
                pair: "intermediate-planet",
                source,
            })?,
        })
    }
}
