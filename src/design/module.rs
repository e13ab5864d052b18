//! Designing for a module: the tooth count as a constraint of the fit, not a scaling after it.
//!
//! `z` teeth of module `m` on a pitch curve of perimeter `L` need `L = zπm` exactly. Scaling a
//! finished design to that perimeter moves every tip point radially by `(s − 1)·l1` (0.5–4 % of
//! l1 for the usual `z`); instead the whole train is fitted again to the points with the
//! perimeter held at `zπm` — the centre distance then follows from the ratio, `a = zπm/L̂(i)`
//! ([`crate::geometry::perimeter`]), and `l3`, γ, the sun phase and the ratio take up what
//! the fixed size costs. Both neighbouring counts `⌊L/πm⌋` and `⌈L/πm⌉` are fitted (side by
//! side) and the closer train is kept. The gear limits hold throughout, as in every fit.

use super::error::DesignError;
use crate::design::fit::{FitOptions, Fitted, MEASURED_NOISE_MM, admitted, fit_points, minimax};
use crate::geometry::mechanism::Mechanism;
use crate::geometry::perimeter::unit_perimeter;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// Fewest teeth a designed pitch curve may have.
pub const MIN_TEETH: u32 = 8;

/// The design made for a module: the tooth count chosen and what the neighbours reached.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct ModuleSummary {
    /// Module, mm.
    pub module_mm: f64,
    /// Teeth on each of the three gears (equal perimeters).
    pub teeth: u32,
    /// Pitch perimeter `zπm`, mm.
    pub perimeter_mm: f64,
    /// Teeth the design had before the constraint, `L/(πm)` (not an integer).
    pub free_teeth: f64,
    /// Largest point distance from the traced path of the design before the constraint, mm.
    pub free_max_deviation_mm: f64,
    /// Each count tried: `[z, largest point distance mm, RMS point distance mm]`.
    pub candidates: Vec<[f64; 3]>,
}

/// The train refitted at the chosen tooth count.
pub(super) struct ForModule {
    pub mechanism: Mechanism,
    pub angles: Vec<f64>,
    pub summary: ModuleSummary,
}

/// Refuses a module that leaves fewer than [`MIN_TEETH`] − 1 teeth on `start`'s pitch curves,
/// or more than [`crate::bounds::MAX_TEETH`] (an early check on the patent route's train,
/// before any fit: the fit changes the perimeter by far less than a tooth).
pub(super) fn check_module(start: &Mechanism, module_mm: f64) -> Result<(), DesignError> {
    let perimeter = start.a_mm * unit_perimeter(&start.ratio);
    let teeth = perimeter / (PI * module_mm);
    if teeth > f64::from(crate::bounds::MAX_TEETH) + 1.0 {
        return Err(crate::bounds::OutOfBounds {
            quantity: "module_mm".into(),
            value: format!("{module_mm} mm"),
            range: format!(
                "≥ {:.4} mm for this trajectory",
                perimeter / (PI * f64::from(crate::bounds::MAX_TEETH))
            ),
            why: format!(
                "its pitch curves ({perimeter:.1} mm round) would carry {teeth:.0} teeth, more \
                 than the {} teeth a gear may have",
                crate::bounds::MAX_TEETH
            ),
        }
        .into());
    }
    if teeth < f64::from(MIN_TEETH) - 1.0 {
        return Err(DesignError::ModuleTooLarge {
            module_mm,
            perimeter_mm: perimeter,
            min_teeth: MIN_TEETH,
        });
    }
    Ok(())
}

/// Fits the train at the two tooth counts nearest to its free perimeter (module
/// documentation), from `start` (the free design), with the chain's fit options.
pub(super) fn design_for_module(
    points: &[[f64; 2]],
    start: &Mechanism,
    module_mm: f64,
    fit_opts: &FitOptions,
) -> Result<ForModule, DesignError> {
    let perimeter = start.a_mm * unit_perimeter(&start.ratio);
    let free = perimeter / (PI * module_mm);
    let lo = free.floor().max(f64::from(MIN_TEETH));
    let counts: Vec<u32> = [lo, lo + 1.0]
        .into_iter()
        .filter(|z| z.is_finite() && *z <= f64::from(crate::bounds::MAX_TEETH))
        .map(|z| z as u32)
        .collect();
    if free < f64::from(MIN_TEETH) - 1.0 || counts.is_empty() {
        return Err(DesignError::ModuleTooLarge {
            module_mm,
            perimeter_mm: perimeter,
            min_teeth: MIN_TEETH,
        });
    }
    let measured = fit_opts.noise_sigma_mm > MEASURED_NOISE_MM;
    let score = |f: &Fitted| {
        if measured {
            f.rms_mm
        } else {
            f.max_mm.max(f.coverage_mm)
        }
    };
    let free_fit = crate::design::fit::measure(points, start);
    let fits: Vec<(u32, Fitted)> = counts
        .par_iter()
        .filter_map(|&z| {
            let opts = FitOptions {
                perimeter_mm: Some(f64::from(z) * PI * module_mm),
                order: Some(start.ratio.order()),
                ..fit_opts.clone()
            };
            let f = fit_points(points, start, &opts).ok()?;
            if measured {
                return Some((z, f));
            }
            // The least-squares fit may trace farther (largest distance) than the free design
            // merely resized to the perimeter (the `nearest` scaling): the minimax finish starts
            // from the closer of the two, so the design for the module is never the worse.
            let resized = admitted(points, start, &opts);
            let f = if score(&resized) < score(&f) {
                resized
            } else {
                f
            };
            Some((z, minimax(points, f, &opts)))
        })
        .collect();
    let candidates = fits
        .iter()
        .map(|(z, f)| [f64::from(*z), f.max_mm, f.rms_mm])
        .collect();
    let (z, best) = fits
        .into_iter()
        .min_by(|a, b| score(&a.1).total_cmp(&score(&b.1)))
        .ok_or_else(|| DesignError::Internal("no tooth count could be fitted".into()))?;
    Ok(ForModule {
        summary: ModuleSummary {
            module_mm,
            teeth: z,
            perimeter_mm: f64::from(z) * PI * module_mm,
            free_teeth: free,
            free_max_deviation_mm: free_fit.max_mm,
            candidates,
        },
        angles: best.carrier_angles_rad,
        mechanism: best.mechanism,
    })
}
