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
//!
//! With the intermediate axis on the carrier line, `l1 = 2a` moves with the count, and no ratio
//! can take that up: to first order the planet's swing holds only the odd harmonics of the sun's
//! law, and a change of `l1` is a circle (G1 at m = 2: 1.52 mm at every Fourier order). Turned
//! off the line by the idler offset ε, the arm is `l1 = 2a·cos ε`
//! ([`crate::geometry::mechanism`]): where the centre distance `a` exceeds half the start's arm,
//! the fit starts from `cos ε = l1/(2a)` — the start's arm kept — on either side, with ε free.
//! At [`IdlerOffset::Auto`] the start itself, the free design the chain makes before this stage,
//! is fitted with ε free too ([`IdlerOffset`]), and ε stays free wherever `a` exceeds half its
//! arm; [`IdlerOffset::Free`] frees it at both counts, [`IdlerOffset::Collinear`] nowhere. An
//! exact target is then traced exactly at a standard module (G1 at m = 2: z = 23, ε = 13.5°).

use crate::design::error::DesignError;
use crate::design::fit::{
    FitOptions, Fitted, Lawson, LawsonStart, MEASURED_NOISE_MM, MINIMAX_PASSES, admitted,
    fit_points, minimax_from_distances, race,
};
use crate::design::options::IdlerOffset;
use crate::design::strategy::offset_start::offset_start;
use crate::geometry::mechanism::Mechanism;
use crate::geometry::perimeter::unit_perimeter;
use crate::math::Point;
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
#[derive(Debug, Clone, Serialize, Deserialize, schemars::JsonSchema)]
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
    /// Each count tried: `[z, largest point distance mm, RMS point distance mm]` of its closest
    /// fit (for a count whose minimax finish fell behind in the race of the finishes, the fit of
    /// its first passes: docs/performance.md, "The race of the finishes").
    pub candidates: Vec<[f64; 3]>,
}

/// The train refitted at the chosen tooth count.
pub(in crate::design) struct ForModule {
    pub mechanism: Mechanism,
    pub angles: Vec<f64>,
    pub summary: ModuleSummary,
}

/// Refuses a module that leaves fewer than [`MIN_TEETH`] − 1 teeth on `start`'s pitch curves,
/// or more than [`crate::bounds::MAX_TEETH`] (an early check on the patent route's train,
/// before any fit: the fit changes the perimeter by far less than a tooth).
pub(in crate::design) fn check_module(
    start: &Mechanism,
    module_mm: f64,
) -> Result<(), DesignError> {
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
/// documentation), from `start` (the free design), with the chain's fit options and the idler
/// offset allowed by `offset`.
pub(in crate::design) fn design_for_module(
    points: &[Point],
    start: &Mechanism,
    module_mm: f64,
    fit_opts: &FitOptions,
    offset: IdlerOffset,
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
        .filter_map(|&z| {
            let size = Size {
                z,
                module_mm,
                offset,
            };
            Candidate::least_squares(points, start, size, fit_opts, judge)
        })
        .collect();
    // The finishes, side by side, of the counts whose least-squares fit is within FINISH_RANGE
    // of the closest.
    let closest = fits
        .iter()
        .map(|c| judge.score(&c.fit))
        .fold(f64::INFINITY, f64::min);
    // They race (`fit::race`): a finish far behind after the heat is not run to its end. The
    // count that wins gets a second finish from the same start (module documentation) when its
    // train is on the carrier line: the fixed size leaves it in a rugged landscape where the
    // two land in different basins. Off the line, ε takes up what the size fixes, and the
    // second finish was closer on 1 of 5 targets, by 3 %, for as long as the first. Which
    // count wins is known only once the first finishes end, so every on-line count's second
    // finish joins the race, and only the winner's is used.
    let to_finish: Vec<(usize, Fitted)> = fits
        .iter()
        .enumerate()
        .filter(|(_, c)| judge.score(&c.fit) <= FINISH_RANGE * closest)
        .filter_map(|(i, c)| Some((i, c.finish_start.clone()?)))
        .collect();
    let seconds: Vec<(usize, Fitted)> = to_finish
        .iter()
        .filter(|(_, f)| f.mechanism.idler_offset_rad == 0.0)
        .cloned()
        .collect();
    let opts: Vec<FitOptions> = fits.iter().map(|c| c.opts.clone()).collect();
    let racers = to_finish
        .iter()
        .map(|(i, f)| (i, f, LawsonStart::Uniform))
        .chain(seconds.iter().map(|(i, f)| (i, f, LawsonStart::Distances)))
        .map(|(&i, f, from)| Lawson::new(points, f.clone(), &opts[i], from))
        .collect();
    let mut raced = race(racers, MINIMAX_PASSES).into_iter();
    for ((i, _), finished) in to_finish.iter().zip(raced.by_ref()) {
        fits[*i].take_finish(finished, judge);
    }
    let mut second: Vec<(usize, Fitted)> = seconds.into_iter().map(|(i, _)| i).zip(raced).collect();
    if let Some((i, c)) = fits
        .iter_mut()
        .enumerate()
        .filter(|(_, c)| c.finished)
        .min_by(|a, b| judge.score(&a.1.fit).total_cmp(&judge.score(&b.1.fit)))
        .filter(|(_, c)| c.fit.mechanism.idler_offset_rad == 0.0)
    {
        match second.iter().position(|(j, _)| *j == i) {
            Some(k) => c.take_second(second.swap_remove(k).1, judge),
            None => c.second_finish(points, judge),
        }
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

/// The largest distance both ways of a fit, mm: the points' from the traced curve, and the
/// curve's from the points' polyline beyond what its chords explain
/// ([`Fitted::coverage_excess_mm`]; the whole distance would charge a train that traces an
/// exact target for the sharp nose its points do not sample).
fn far(f: &Fitted) -> f64 {
    f.max_mm.max(f.coverage_excess_mm)
}

/// One tooth count's fit, with the start of its minimax finish (absent when it needs none).
struct Candidate {
    z: u32,
    opts: FitOptions,
    fit: Fitted,
    finish_start: Option<Fitted>,
    /// The finish ran (the second one may follow).
    finished: bool,
}

/// Highest Fourier order the fit of a train carried off the carrier line climbs to: the exact
/// targets tried are traced within 0.003 mm at 8–24, and a finish at order 40 takes a second
/// where it gains nothing (noisy_050um at m = 1.5).
const OFFSET_MAX_ORDER: usize = 24;

/// Least-squares scores within this factor of the closest are finished: a count whose
/// least-squares fit is farther off than that has not overtaken the closest in its finish on
/// the targets tried (the finish gains 10–40 %), and its finish costs as much as the winner's.
const FINISH_RANGE: f64 = 1.5;

/// The size a candidate is fitted at: `z` teeth of module `module_mm` (mm), and where its
/// intermediate axis may sit.
#[derive(Clone, Copy)]
struct Size {
    z: u32,
    module_mm: f64,
    offset: IdlerOffset,
}

impl Size {
    /// The fit options at this size: the perimeter `zπm` held, the start's order, the idler
    /// offset free where the policy frees it (module documentation) — at [`IdlerOffset::Auto`]
    /// where the centre distance exceeds half the start's arm.
    fn options(self, start: &Mechanism, fit_opts: &FitOptions) -> FitOptions {
        let perimeter = f64::from(self.z) * PI * self.module_mm;
        let free = match self.offset {
            IdlerOffset::Collinear => false,
            IdlerOffset::Free => true,
            IdlerOffset::Auto => {
                2.0 * perimeter / unit_perimeter(&start.ratio) > start.l1_mm() * (1.0 + 1e-9)
            }
        };
        FitOptions {
            perimeter_mm: Some(perimeter),
            order: Some(start.ratio.order()),
            free_idler_offset: free,
            ..fit_opts.clone()
        }
    }
}

/// The starts of a fit at `opts.perimeter_mm`: `start` resized to it and made admissible, and,
/// where ε is free and the centre distance exceeds half the start's arm, the start carried off
/// the carrier line with its arm and needle motion kept ([`offset_start`]), to either side: the
/// side whose start traces closer is not always the side whose fit does (docs/performance.md,
/// "Both sides of the off-line start"). Neither
/// kind is the better start everywhere: the first keeps the ratio and moves the arm, the second
/// keeps the arm and changes the ratio.
fn sized_starts(points: &[Point], start: &Mechanism, opts: &FitOptions) -> Vec<Fitted> {
    let resized = admitted(points, start, opts);
    let perimeter = opts.perimeter_mm.unwrap_or(f64::NAN);
    if !opts.free_idler_offset {
        return vec![resized];
    }
    let bounds = opts.limits.ratio_bounds();
    let turned: Vec<Fitted> = [1.0, -1.0]
        .into_par_iter()
        .filter_map(|sign| offset_start(start, perimeter, sign, bounds))
        .map(|m| admitted(points, &m, opts))
        .collect();
    std::iter::once(resized).chain(turned).collect()
}

impl Candidate {
    /// The least-squares fit at `size` from its starts ([`sized_starts`]), and the start of its
    /// finish for the largest distance when `judge` asks for one.
    fn least_squares(
        points: &[Point],
        start: &Mechanism,
        size: Size,
        fit_opts: &FitOptions,
        judge: Judge,
    ) -> Option<Self> {
        let z = size.z;
        let opts = size.options(start, fit_opts);
        let starts = sized_starts(points, start, &opts);
        // Each start fitted (side by side); the closer fit goes on, with its start. The train
        // carried off the carrier line has a new ratio, which may need more harmonics than the
        // start's: its fit climbs the orders as the free design's does, to OFFSET_MAX_ORDER
        // (exact_three_harmonic at m = 1.5: 0.226 mm at the start's order 8, 0.002 mm at 24).
        let climbing = FitOptions {
            order: fit_opts.order,
            max_order: fit_opts.max_order.min(OFFSET_MAX_ORDER),
            ..opts.clone()
        };
        let (sized, f) = starts
            .into_par_iter()
            .filter_map(|s| {
                let o = if s.mechanism.idler_offset_rad == 0.0 {
                    &opts
                } else {
                    &climbing
                };
                fit_points(points, &s.mechanism, o).ok().map(|f| (s, f))
            })
            .min_by(|a, b| judge.score(&a.1).total_cmp(&judge.score(&b.1)))?;
        // The least-squares fit may trace farther (largest distance) than the free design
        // merely resized to the perimeter (the `nearest` scaling): the minimax finish starts
        // from the closer of the two, so the design for the module is never the worse.
        let f = if judge.systematic(&f) && far(&sized) < far(&f) {
            sized
        } else {
            f
        };
        // Within the tolerance already (an exact target), or judged by its RMS on measured
        // points: nothing to finish.
        let finish_start = (judge.systematic(&f) && far(&f) > opts.tol_mm).then(|| f.clone());
        Some(Self {
            z,
            opts,
            fit: f,
            finish_start,
            finished: false,
        })
    }

    /// The minimax finish from the least-squares fit (where the race dropped it, the best of
    /// its heat): it lowers the Hausdorff distance to the points' polyline, chords' sag and
    /// all, so the closer of the two by the module's measure is kept.
    fn take_finish(&mut self, finished: Fitted, judge: Judge) {
        if judge.score(&finished) < judge.score(&self.fit) {
            self.fit = finished;
        }
        self.finished = true;
    }

    /// The finish again from the same start with Lawson's weights started from its distances;
    /// the closer of the two is kept.
    fn second_finish(&mut self, points: &[Point], judge: Judge) {
        if let Some(f) = self.finish_start.take() {
            let other = minimax_from_distances(points, f, &self.opts);
            self.take_second(other, judge);
        }
    }

    /// The second finish's result (from the race, or [`Self::second_finish`]), kept when closer.
    fn take_second(&mut self, other: Fitted, judge: Judge) {
        if judge.score(&other) < judge.score(&self.fit) {
            self.fit = other;
        }
    }
}
