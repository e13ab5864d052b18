//! Step 1 for the start of the design: the raw points, or a smoothed copy for measured points.

use crate::design::error::DesignError;
use crate::design::fit::MEASURED_NOISE_MM;
use crate::design::inverse;
use crate::design::inverse::{InverseError, Inversion};
use crate::design::options::DesignOptions;
use crate::design::trajectory::Trajectory;

/// Smoothing harmonics tried, in order, for the start on measured points.
const START_SMOOTHING: [usize; 5] = [24, 32, 16, 48, 12];

/// Step 1 for the start of the design. With `--smooth` the smoothed loop is inverted; measured
/// points (estimated σ above [`MEASURED_NOISE_MM`]) and points whose raw inversion fails the
/// monotonicity tests are inverted from a smoothed copy (the fit later uses the points as read).
/// Returns the inversion and the smoothing used.
pub(in crate::design) fn invert_for_start(
    traj: &Trajectory,
    opts: &DesignOptions,
    noise_sigma_mm: f64,
) -> Result<(Inversion, Option<usize>), DesignError> {
    let smoothed = |h: usize| {
        let mut o = opts.inverse;
        o.law_harmonics = o.law_harmonics.or(Some(h / 2));
        inverse::invert(&traj.smoothed(h), opts.center_mm, &o)
    };
    if let Some(h) = opts.smooth {
        return Ok((smoothed(h)?, Some(h)));
    }
    let raw = inverse::invert(traj, opts.center_mm, &opts.inverse);
    let retry = match &raw {
        Ok(_) => noise_sigma_mm > MEASURED_NOISE_MM,
        Err(InverseError::NotMonotone { .. } | InverseError::NeedleReverses { .. }) => true,
        Err(_) => false,
    };
    if retry {
        for h in START_SMOOTHING {
            if let Ok(inv) = smoothed(h) {
                return Ok((inv, Some(h)));
            }
        }
    }
    Ok((raw?, None))
}
