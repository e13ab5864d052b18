//! The keyword arguments of `ncgear.design`, `ncgear.teeth` and `ncgear.pair` (a dict the Python
//! wrapper builds from its signature, one item per argument) as library options.
use crate::errors::{arg_err, bounds_err, design_err, teeth_err};
use ncgear::design::DesignOptions;
use ncgear::design::hypothesis::segmented::Route;
use ncgear::design::train::TrainPolicy;
use ncgear::design::{IdlerOffset, RefineMode};
use ncgear::teeth::{RackParams, ToothPolicy, ToothingOptions};
use pyo3::prelude::*;

/// The value of enumerated argument `arg` named `given`, from `table` (name, value).
pub fn choice<T: Copy>(arg: &str, given: &str, table: &[(&str, T)]) -> PyResult<T> {
    match table.iter().find(|(name, _)| *name == given) {
        Some((_, v)) => Ok(*v),
        None => {
            let names: Vec<String> = table.iter().map(|(n, _)| format!("'{n}'")).collect();
            Err(arg_err(
                arg,
                format!("'{given}'"),
                format!("expected one of {}", names.join(", ")),
            ))
        }
    }
}

/// `ncgear.design`'s options (the CLI's `design` flags of the same names; lengths mm, angles
/// degrees).
#[derive(FromPyObject)]
#[pyo3(from_item_all)]
pub struct DesignArgs {
    center: (f64, f64),
    order: Option<usize>,
    sense: String,
    tol_mm: f64,
    refine: String,
    refine_order: usize,
    harmonics: Vec<(f64, f64)>,
    route: String,
    w1: f64,
    k_max: usize,
    grid: usize,
    dense: usize,
    samples: usize,
    ratio_bounds: (f64, f64),
    fit: bool,
    limits: bool,
    max_pressure_angle: f64,
    min_concave_radius: Option<f64>,
    min_convex_radius: Option<f64>,
    convexity: bool,
    smooth: Option<usize>,
    module: Option<f64>,
    idler_offset: String,
    alternatives: bool,
}

impl DesignArgs {
    /// The library's design options, checked (an error names the argument).
    pub fn options(&self) -> PyResult<DesignOptions> {
        let refine = choice(
            "refine",
            &self.refine,
            &[
                ("auto", RefineMode::Auto),
                ("on", RefineMode::On),
                ("off", RefineMode::Off),
            ],
        )?;
        let hypothesis = self
            .harmonics
            .iter()
            .map(|&(a, phi_deg)| (a, phi_deg.to_radians()))
            .collect();
        let route = choice(
            "route",
            &self.route,
            &[("ac", Route::Ac), ("bd", Route::Bd)],
        )?;
        let sense = choice(
            "sense",
            &self.sense,
            &[("auto", None), ("ccw", Some(1)), ("cw", Some(-1))],
        )?;
        let idler_offset = choice(
            "idler_offset",
            &self.idler_offset,
            &[
                ("auto", IdlerOffset::Auto),
                ("collinear", IdlerOffset::Collinear),
                ("free", IdlerOffset::Free),
            ],
        )?;
        let d = DesignOptions::default();
        let o = DesignOptions::default()
            .with_center_mm(self.center.into())
            .with_order(self.order)
            .with_tol_mm(self.tol_mm)
            .with_refine(refine)
            .with_refine_order(self.refine_order)
            .with_fit(self.fit)
            .with_smooth(self.smooth)
            .with_segmented(
                d.segmented
                    .with_hypothesis(hypothesis)
                    .with_route(route)
                    .with_w1(self.w1)
                    .with_k_max(self.k_max),
            )
            .with_inverse(
                d.inverse
                    .with_grid(self.grid)
                    .with_sense(sense)
                    .with_dense_samples(self.dense),
            )
            .with_samples(self.samples)
            .with_refine_options(
                d.refine_options
                    .with_ratio_bounds([self.ratio_bounds.0, self.ratio_bounds.1]),
            )
            .with_limits(self.limits)
            .with_max_pressure_angle_rad(self.max_pressure_angle.to_radians())
            .with_min_concave_radius_mm(self.concave_radius()?)
            .with_min_convex_radius_mm(self.min_convex_radius)
            .with_module_mm(self.module)
            .with_idler_offset(idler_offset)
            .with_alternatives(self.alternatives);
        o.validate().map_err(|e| design_err(&e))?;
        Ok(o)
    }

    /// The concave-radius limit, mm: `convexity` is an infinite one.
    fn concave_radius(&self) -> PyResult<Option<f64>> {
        match (self.convexity, self.min_concave_radius) {
            (false, r) => Ok(r),
            (true, None) => Ok(Some(f64::INFINITY)),
            (true, Some(r)) => Err(arg_err(
                "min_concave_radius",
                r,
                "not with convexity=True (convex pitch curves only: no concave radius)",
            )),
        }
    }
}

/// Rack, backlash, cutter and verification options of `ncgear.teeth` and `ncgear.pair` (the
/// CLI's flags of the same names; angles degrees, lengths mm).
#[derive(FromPyObject)]
#[pyo3(from_item_all)]
pub struct ToothArgs {
    verify_steps: usize,
    pressure_angle: f64,
    addendum: f64,
    clearance: f64,
    fillet: f64,
    backlash: Option<f64>,
    chord_tol: Option<f64>,
    cutter_teeth: Option<u32>,
    refuse_undercut: bool,
}

impl ToothArgs {
    /// Writes these options into `t` (its module set) and checks them.
    pub fn apply_to(&self, t: &mut ToothingOptions) -> PyResult<()> {
        t.rack = RackParams::new(
            self.pressure_angle.to_radians(),
            self.addendum,
            self.clearance,
            self.fillet,
        )
        .map_err(|e| teeth_err(&e))?;
        t.verify_steps = self.verify_steps;
        t.backlash_mm = self.backlash.unwrap_or(t.backlash_mm);
        t.chord_tol_mm = self.chord_tol.unwrap_or(t.chord_tol_mm);
        t.cutter_teeth = self.cutter_teeth;
        t.refuse_undercut = self.refuse_undercut;
        t.validate().map_err(|e| teeth_err(&e))
    }
}

/// The train's tooth policy: a given count `teeth`, else `policy` by its CLI name.
pub fn train_policy(policy: &str, teeth: Option<u32>) -> PyResult<TrainPolicy> {
    let scaled = TrainPolicy::ScaleCenterDistance;
    match teeth {
        Some(z) => {
            ncgear::bounds::check_teeth("teeth", z).map_err(|e| bounds_err(&e))?;
            Ok(scaled(ToothPolicy::Exact(z)))
        }
        None => choice(
            "tooth_policy",
            policy,
            &[
                ("design", TrainPolicy::Designed),
                ("scale-up", scaled(ToothPolicy::ScaleUp)),
                ("nearest", scaled(ToothPolicy::Nearest)),
                ("scale-down", scaled(ToothPolicy::ScaleDown)),
                ("ratio-amplitude", TrainPolicy::RatioAmplitude),
                ("adjust-module", TrainPolicy::AdjustModule),
            ],
        ),
    }
}
