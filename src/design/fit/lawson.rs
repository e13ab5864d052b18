//! The minimax finish as a state that can stop and go on: Lawson's reweighting passes
//! ([`super::minimax`]) one at a time, and a race of several finishes that drops the ones far
//! behind after a few passes.
//!
//! Where the train cannot trace a target, the design finishes several least-squares fits
//! towards the minimax and keeps the closest (the first fit, the best restart, the
//! continuation in the gear limits; two tooth counts at a module). A finish is 12 passes of 10
//! Levenberg–Marquardt iterations each, and the one that ends closest is almost always clear
//! after a few: [`race`] runs [`RACE_HEAT_PASSES`] passes of each, side by side, then finishes
//! only those within [`RACE_KEEP_RATIO`] of the closest. A finish stopped after `p` passes and
//! taken on for `q` more is bit for bit the finish of `p + q` passes: the race changes the
//! outcome only where a finish that far behind would have overtaken the leader in its remaining
//! passes (docs/performance.md, "The race of the finishes").

use super::{
    FitOptions, Fitted, MINIMAX_ITERATIONS, curve, curve_evals, measure_from, solver, subsample,
};
use crate::geometry::mechanism::Mechanism;
use crate::math::Point;
use crate::math::polyline::SegmentGrid;
use rayon::prelude::*;
use solver::Lm;

/// Where [`Lawson`]'s weights start.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum LawsonStart {
    /// All 1: the first pass weighs by `|d_j|/max|d|` of the start.
    Uniform,
    /// `|d_j|/max|d|` of the start: one Lawson step further, the first pass weighs by its
    /// square, so it strays less far from the start towards the least-squares fit.
    Distances,
}

/// Passes of every finish before the race drops the ones far behind.
pub(crate) const RACE_HEAT_PASSES: usize = 3;

/// After the heat, a finish goes on only when its Hausdorff score `max(max_mm, coverage_mm)`
/// is within this factor of the closest one's.
pub(crate) const RACE_KEEP_RATIO: f64 = 1.25;

/// A minimax finish in progress: the best fit so far, the current iterate, and Lawson's
/// weights of the points and of the coverage samples.
pub(crate) struct Lawson<'a> {
    points: &'a [Point],
    opts: &'a FitOptions,
    /// The Fourier order of the finish (the start's).
    k: usize,
    /// Passes run.
    done: usize,
    best: Fitted,
    m: Mechanism,
    phis_all: Vec<f64>,
    dists: Vec<f64>,
    cover: Vec<f64>,
    weights: Vec<f64>,
    cover_weights: Vec<f64>,
}

impl<'a> Lawson<'a> {
    /// The finish of `fitted` on `points` with `opts`, no pass run yet.
    pub(crate) fn new(
        points: &'a [Point],
        fitted: Fitted,
        opts: &'a FitOptions,
        start: LawsonStart,
    ) -> Self {
        let (stride, sub) = subsample(points, opts);
        let grid = SegmentGrid::new(&sub);
        let m = fitted.mechanism.clone();
        let cover = coverage_distances(&m, &grid);
        let mut state = Self {
            points,
            opts,
            k: fitted.mechanism.ratio.order(),
            done: 0,
            phis_all: fitted.carrier_angles_rad.clone(),
            dists: fitted.distances_mm.clone(),
            best: fitted,
            m,
            cover,
            // Lawson's weights: each pass multiplies every point's weight by its distance
            // (normalised), so the weight gathers on the points that stay farthest — the
            // minimax fit's extremal set. The traced curve's samples are weighted alike by
            // their distance from the target: the Hausdorff distance the finish lowers has both
            // sides, and a bulge of the curve where no point is can be its largest term.
            weights: vec![1.0; sub.len()],
            cover_weights: Vec::new(),
        };
        state.cover_weights = vec![1.0; state.cover.len()];
        // Started from the start's distances, every pass is one Lawson step further on: the
        // first pass already weighs by (|d|/max|d|)², a step away from the least-squares fit.
        if start == LawsonStart::Distances {
            let sub_d: Vec<f64> = state.dists.iter().step_by(stride).copied().collect();
            lawson_step(
                &mut state.weights,
                &mut state.cover_weights,
                &sub_d,
                &state.cover,
            );
        }
        state
    }

    /// The Hausdorff score of the best fit so far, mm.
    pub(crate) fn score(&self) -> f64 {
        self.best.max_mm.max(self.best.coverage_mm)
    }

    /// Runs `passes` more reweighting passes.
    pub(crate) fn advance(&mut self, passes: usize) {
        let (stride, sub) = subsample(self.points, self.opts);
        let grid = SegmentGrid::new(&sub);
        let pass = FitOptions {
            max_iterations: self.opts.max_iterations.min(MINIMAX_ITERATIONS),
            ..self.opts.clone()
        };
        for _ in 0..passes {
            let sub_d: Vec<f64> = self.dists.iter().step_by(stride).copied().collect();
            lawson_step(
                &mut self.weights,
                &mut self.cover_weights,
                &sub_d,
                &self.cover,
            );
            let w: Vec<f64> = self.weights.iter().map(|w| w.sqrt()).collect();
            let wc: Vec<f64> = self.cover_weights.iter().map(|w| w.sqrt()).collect();
            let lm = Lm {
                pts: &sub,
                k: self.k,
                opts: &pass,
                weights: Some(&w),
                grid: &grid,
                coverage_weights: Some(&wc),
            };
            let mut phis: Vec<f64> = self.phis_all.iter().step_by(stride).copied().collect();
            let (next, it) = lm.run(self.m.clone(), &mut phis);
            let measured = measure_from(&next, self.points, Some(&self.phis_all));
            self.best.iterations += it;
            self.phis_all = measured.carrier_angles_rad.clone();
            self.dists = measured.distances_mm.clone();
            self.cover = coverage_distances(&next, &grid);
            if measured.max_mm.max(measured.coverage_mm) < self.score() {
                let scan = std::mem::take(&mut self.best.order_scan);
                self.best = Fitted::new(next.clone(), measured, self.best.iterations, scan);
            }
            self.m = next;
        }
        self.done += passes;
    }

    /// The best fit reached.
    pub(crate) fn into_best(self) -> Fitted {
        self.best
    }
}

/// The reweighting loop of [`super::minimax`] (its documentation): `passes` passes from `start`.
pub(crate) fn lawson(
    points: &[Point],
    fitted: Fitted,
    opts: &FitOptions,
    passes: usize,
    start: LawsonStart,
) -> Fitted {
    let mut state = Lawson::new(points, fitted, opts, start);
    state.advance(passes);
    state.into_best()
}

/// Finishes, side by side, to `passes` passes each (counting those a finish has run already);
/// after [`RACE_HEAT_PASSES`] only those within [`RACE_KEEP_RATIO`] of the closest (and the
/// closest) go on (module documentation). Returns each finish's best fit in the order given:
/// a dropped one's is the best of its heat, which is farther than the closest one's already,
/// so it never wins a choice of the closest.
pub(crate) fn race(finishes: Vec<Lawson<'_>>, passes: usize) -> Vec<Fitted> {
    let mut finishes = finishes;
    let heat = RACE_HEAT_PASSES.min(passes);
    finishes
        .par_iter_mut()
        .for_each(|f| f.advance(heat.saturating_sub(f.done)));
    let leader =
        (0..finishes.len()).min_by(|&i, &j| finishes[i].score().total_cmp(&finishes[j].score()));
    let closest = leader.map_or(f64::INFINITY, |i| finishes[i].score());
    finishes
        .par_iter_mut()
        .enumerate()
        .filter(|(j, f)| Some(*j) == leader || f.score() <= RACE_KEEP_RATIO * closest)
        .for_each(|(_, f)| f.advance(passes.saturating_sub(f.done)));
    finishes.into_iter().map(Lawson::into_best).collect()
}

/// One Lawson update: every weight times its distance over the largest distance of both sets
/// (`w ← w·|d|/max|d|`), normalised to a largest weight of 1 and floored at 1e-6 (a point that
/// reaches the curve keeps a voice).
fn lawson_step(weights: &mut [f64], cover_weights: &mut [f64], dists: &[f64], cover: &[f64]) {
    let dmax = dists.iter().chain(cover).copied().fold(1e-300, f64::max);
    for (w, d) in weights.iter_mut().zip(dists) {
        *w *= d / dmax;
    }
    for (w, d) in cover_weights.iter_mut().zip(cover) {
        *w *= d / dmax;
    }
    let wmax = weights
        .iter()
        .chain(cover_weights.iter())
        .copied()
        .fold(1e-300, f64::max);
    weights.iter_mut().for_each(|w| *w = (*w / wmax).max(1e-6));
    cover_weights
        .iter_mut()
        .for_each(|w| *w = (*w / wmax).max(1e-6));
}

/// Distance (mm) of the traced curve of `m` from the target polyline `grid` at the samples of
/// the solver's coverage rows.
fn coverage_distances(m: &Mechanism, grid: &SegmentGrid) -> Vec<f64> {
    curve_evals(m, solver::COVERAGE_SAMPLES)
        .par_iter()
        .map(|e| curve::coverage(grid, e).distance_mm)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::super::tests::mech;
    use super::super::{fit_points, minimax};
    use super::*;
    use std::f64::consts::TAU;

    /// Points of the fixture train with a bump the train cannot follow at order 3, and their
    /// least-squares fit at order 3: a target the finish has work on.
    fn untraceable() -> (Vec<Point>, FitOptions, Fitted) {
        let truth = mech();
        let pts: Vec<Point> = (0..400)
            .map(|k| {
                let t = TAU * k as f64 / 400.0;
                truth.tip(t) + Point::new(0.0, 0.8 * (-((t - 2.0) / 0.15).powi(2)).exp())
            })
            .collect();
        let opts = FitOptions {
            order: Some(3),
            max_iterations: 20,
            ..FitOptions::default()
        };
        let f = fit_points(&pts, &truth, &opts).unwrap();
        (pts, opts, f)
    }

    #[test]
    fn a_finish_stopped_and_taken_on_is_the_whole_finish_bit_for_bit() {
        let (pts, opts, f) = untraceable();
        let whole = minimax(&pts, f.clone(), &opts);
        let mut parts = Lawson::new(&pts, f.clone(), &opts, LawsonStart::Uniform);
        parts.advance(RACE_HEAT_PASSES);
        parts.advance(MINIMAX_PASSES_FOR_TEST - RACE_HEAT_PASSES);
        let parts = parts.into_best();
        assert_eq!(whole.max_mm.to_bits(), parts.max_mm.to_bits());
        assert_eq!(whole.coverage_mm.to_bits(), parts.coverage_mm.to_bits());
        assert_eq!(whole.iterations, parts.iterations);
        // And the finish does lower the Hausdorff score of the least-squares fit.
        assert!(whole.max_mm.max(whole.coverage_mm) < f.max_mm.max(f.coverage_mm));
    }

    #[test]
    fn the_race_finishes_the_leader_and_stops_a_finish_far_behind_after_its_heat() {
        let (pts, opts, f) = untraceable();
        // A start far behind: the train's ratio cut to one harmonic (a finish keeps its order).
        let mut far = f.mechanism.clone();
        far.ratio = far.ratio.with_order(1);
        let behind = super::super::admitted(&pts, &far, &opts);
        let out = race(
            vec![
                Lawson::new(&pts, f.clone(), &opts, LawsonStart::Uniform),
                Lawson::new(&pts, behind.clone(), &opts, LawsonStart::Uniform),
            ],
            MINIMAX_PASSES_FOR_TEST,
        );
        let f_heat = f.clone();
        let whole = minimax(&pts, f, &opts);
        assert_eq!(out[0].max_mm.to_bits(), whole.max_mm.to_bits());
        // The start behind ran its heat only: its best is the heat's, beyond the keep ratio of
        // the leader's heat.
        let mut heat_only = Lawson::new(&pts, behind, &opts, LawsonStart::Uniform);
        heat_only.advance(RACE_HEAT_PASSES);
        let mut leader_heat = Lawson::new(&pts, f_heat, &opts, LawsonStart::Uniform);
        leader_heat.advance(RACE_HEAT_PASSES);
        assert!(heat_only.score() > RACE_KEEP_RATIO * leader_heat.score());
        assert_eq!(
            out[1].max_mm.to_bits(),
            heat_only.into_best().max_mm.to_bits()
        );
    }

    const MINIMAX_PASSES_FOR_TEST: usize = super::super::MINIMAX_PASSES;
}
