//! Designing for a module: the tooth count as a constraint of the fit, not a scaling after it.
//!
//! `z` teeth of module `m` on a pitch curve of perimeter `L` need `L = zπm` exactly. Scaling a
//! finished design to that perimeter moves every tip point radially by `(s − 1)·l1` (0.5–4 % of
//! l1 for the usual `z`); instead the whole train is fitted again to the points with the
//! perimeter held at `zπm` — the centre distance then follows from the ratio, `a = zπm/L̂(i)`
//! ([`crate::geometry::perimeter`]), and `l3`, γ, the sun phase and the ratio take up what
//! the fixed size costs. Both neighbouring counts `⌊L/πm⌋` and `⌈L/πm⌉` are fitted (side by
//! side) and the closer train is kept. The gear limits hold throughout, as in every fit.
//!
//! Each count's fit is finished for its largest distance, and the count that wins a second
//! time, its Lawson weights started one step further ([`crate::design::fit::minimax_from_distances`]):
//! with the size held, the landscape is rugged and the two finishes land in different basins;
//! the closer is kept.
//! On measured points the fit is judged by its RMS, unless it misses them by more than
//! [`SYSTEMATIC_NOISE_FACTOR`] σ: then the error is the fixed size's, and it is finished and
//! judged as on exact points.

use super::error::DesignError;
use crate::design::fit::{
    FitOptions, Fitted, MEASURED_NOISE_MM, admitted, fit_points, minimax, minimax_from_distances,
};
use crate::geometry::mechanism::Mechanism;
use crate::geometry::perimeter::unit_perimeter;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// A module fit on measured points whose largest point distance exceeds this many noise σ
/// traces the curve under the points measurably off (Gaussian noise puts the largest of ~1000
/// points near 4σ): it gets the minimax finish, as on exact points.
const SYSTEMATIC_NOISE_FACTOR: f64 = 10.0;

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
    let judge = Judge {
        measured: fit_opts.noise_sigma_mm > MEASURED_NOISE_MM,
        sigma_mm: fit_opts.noise_sigma_mm,
    };
    let free_fit = crate::design::fit::measure(points, start);
    let mut fits: Vec<Candidate> = counts
        .par_iter()
        .filter_map(|&z| Candidate::fit(points, start, z, module_mm, fit_opts, judge))
        .collect();
    // The count that wins gets a second finish from the same start (module documentation): the
    // fixed size leaves the train in a rugged landscape where the two land in different basins.
    if let Some(c) = fits
        .iter_mut()
        .filter(|c| c.finish_start.is_some())
        .min_by(|a, b| judge.score(&a.fit).total_cmp(&judge.score(&b.fit)))
    {
        c.second_finish(points, judge);
    }
    let candidates = fits
        .iter()
        .map(|c| [f64::from(c.z), c.fit.max_mm, c.fit.rms_mm])
        .collect();
    let best = fits
        .into_iter()
        .min_by(|a, b| judge.score(&a.fit).total_cmp(&judge.score(&b.fit)))
        .ok_or_else(|| DesignError::Internal("no tooth count could be fitted".into()))?;
    Ok(ForModule {
        summary: ModuleSummary {
            module_mm,
            teeth: best.z,
            perimeter_mm: f64::from(best.z) * PI * module_mm,
            free_teeth: free,
            free_max_deviation_mm: free_fit.max_mm,
            candidates,
        },
        angles: best.fit.carrier_angles_rad,
        mechanism: best.fit.mechanism,
    })
}

/// How a module fit is judged: by its RMS on measured points (the largest distance follows the
/// noise), unless it misses them by more than [`SYSTEMATIC_NOISE_FACTOR`] σ — then the error is
/// the train's, not the points', and, as on exact points, by its largest distance both ways.
#[derive(Clone, Copy)]
struct Judge {
    measured: bool,
    sigma_mm: f64,
}

impl Judge {
    fn systematic(self, f: &Fitted) -> bool {
        !self.measured || f.max_mm > SYSTEMATIC_NOISE_FACTOR * self.sigma_mm
    }

    fn score(self, f: &Fitted) -> f64 {
        if self.systematic(f) { far(f) } else { f.rms_mm }
    }
}

/// The largest distance both ways (points from the traced curve, the curve from the points'
/// polyline) of a fit, mm.
fn far(f: &Fitted) -> f64 {
    f.max_mm.max(f.coverage_mm)
}

/// One tooth count's fit, with the start of its minimax finish (absent when it had none).
struct Candidate {
    z: u32,
    opts: FitOptions,
    fit: Fitted,
    finish_start: Option<Fitted>,
}

impl Candidate {
    /// The least-squares fit at perimeter `zπm`, finished for its largest distance when `judge`
    /// asks for it.
    fn fit(
        points: &[[f64; 2]],
        start: &Mechanism,
        z: u32,
        module_mm: f64,
        fit_opts: &FitOptions,
        judge: Judge,
    ) -> Option<Self> {
        let opts = FitOptions {
            perimeter_mm: Some(f64::from(z) * PI * module_mm),
            order: Some(start.ratio.order()),
            ..fit_opts.clone()
        };
        let f = fit_points(points, start, &opts).ok()?;
        if !judge.systematic(&f) {
            return Some(Self {
                z,
                opts,
                fit: f,
                finish_start: None,
            });
        }
        // The least-squares fit may trace farther (largest distance) than the free design
        // merely resized to the perimeter (the `nearest` scaling): the minimax finish starts
        // from the closer of the two, so the design for the module is never the worse.
        let resized = admitted(points, start, &opts);
        let f = if far(&resized) < far(&f) { resized } else { f };
        Some(Self {
            z,
            fit: minimax(points, f.clone(), &opts),
            opts,
            finish_start: Some(f),
        })
    }

    /// The finish again from the same start with Lawson's weights started from its distances;
    /// the closer of the two is kept.
    fn second_finish(&mut self, points: &[[f64; 2]], judge: Judge) {
        if let Some(f) = self.finish_start.take() {
            let other = minimax_from_distances(points, f, &self.opts);
            if judge.score(&other) < judge.score(&self.fit) {
                self.fit = other;
            }
        }
    }
}
