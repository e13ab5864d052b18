//! The tip-deviation envelope `|mean| + 3σ` along the trajectory (linear model, moments of the
//! random assembly).

use super::common::UM;
use super::report::EnvelopePoint;
use super::{Inventory, LinearModel, N_COORDS};
use crate::math::Point;

/// The envelope on the linear model's grid: mean tip deviation, `3·sqrt(λ_max)` of the deviation
/// covariance and `|mean| + 3σ` (µm), the deviation with the as-given errors, and the path normal.
pub(super) fn envelope(lin: &LinearModel, inv: &Inventory) -> Vec<EnvelopePoint> {
    let (mean, var) = inv.moments();
    let given = inv.nominal_vector();
    let n = lin.phis_rad.len();
    (0..n)
        .map(|i| {
            let col = &lin.jacobian[i];
            let m = lin.deviation_at(i, &mean);
            let (mut cxx, mut cxy, mut cyy) = (0.0, 0.0, 0.0);
            for j in 0..N_COORDS {
                let s = col[j];
                cxx += var[j] * s.x * s.x;
                cxy += var[j] * s.x * s.y;
                cyy += var[j] * s.y * s.y;
            }
            let lmax = 0.5 * (cxx + cyy) + (0.25 * (cxx - cyy).powi(2) + cxy * cxy).sqrt();
            let three = 3.0 * lmax.max(0.0).sqrt();
            let g = lin.deviation_at(i, &given);
            let (a, b) = (
                lin.nominal_tips_mm[(i + n - 1) % n],
                lin.nominal_tips_mm[(i + 1) % n],
            );
            let t = b - a;
            let tn = t.hypot().max(f64::MIN_POSITIVE);
            EnvelopePoint {
                carrier_deg: lin.phis_rad[i].to_degrees(),
                nominal_tip_mm: lin.nominal_tips_mm[i],
                mean_deviation_um: m * UM,
                three_sigma_um: three * UM,
                envelope_um: (m.hypot() + three) * UM,
                nominal_errors_um: g.hypot() * UM,
                normal: Point::new(-t.y / tn, t.x / tn),
            }
        })
        .collect()
}
