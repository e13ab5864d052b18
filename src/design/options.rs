//! Options of the design chain: every knob, its default and its validation.

use super::error::DesignError;
use crate::design::fit::FitOptions;
use crate::design::hypothesis::refine::RefineOptions;
use crate::design::hypothesis::segmented::SegmentedOptions;
use crate::design::inverse::InverseOptions;
use crate::geometry::limits::GearLimits;
use crate::math::Point;
use serde::{Deserialize, Serialize};

/// Orders tried by the adaptive order choice (docs/math/chain.md §8.2).
pub const ADAPTIVE_ORDERS: [usize; 8] = [4, 6, 8, 12, 16, 24, 32, 40];

/// When to run the refinement of docs/math/chain.md §8.3.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "lowercase")]
pub enum RefineMode {
    /// Only when the patent route misses the tolerance (default).
    #[default]
    Auto,
    /// Always.
    On,
    /// Never.
    Off,
}

/// Where the intermediate axis D may sit: on the carrier line OA, as in the patent, or turned
/// off it by the idler offset ε ([`crate::geometry::mechanism`], docs/math/chain.md §6.5).
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "lowercase")]
pub enum IdlerOffset {
    /// [`IdlerOffset::AUTO_RULE`] (default). Without a module there is no tooth count and the
    /// train stays on the line; a design that then misses the target names the off-line figure
    /// among its alternatives ([`DesignOptions::alternatives`]). Designing for a module, ε is
    /// free in the fit of the free design the module stage starts from, and in the module fits
    /// where the centre distance exceeds half the arm, so that `l1 = 2a·cos ε` stays where the
    /// target needs it. Freeing ε in the free design as well takes the toothed trains of the
    /// bundled targets closer on the whole than starting from the collinear free design, though
    /// not on every target (docs/performance.md, "The idler offset").
    #[default]
    Auto,
    /// Always on the line (ε = 0): the patent's train, `l1 = 2a`.
    Collinear,
    /// Free in every fit, also without a module (a housing with the intermediate shaft off the
    /// carrier line: the train then traces targets the collinear one cannot).
    Free,
}

impl IdlerOffset {
    /// The one rule of [`IdlerOffset::Auto`], as the CLI, the trade-off table and the designer
    /// page state it.
    pub const AUTO_RULE: &'static str = "the intermediate axis stays on the carrier line \
        (the patent's layout) unless a whole number of teeth would move the arm: designing for \
        a module, it leaves the line by the idler offset that keeps the arm (l1 = 2a·cos ε); \
        without a module it stays on the line, and a design that misses the target names the \
        off-line figure (--idler-offset free)";
}

/// Gap the sun's and the planet's pitch curves keep across the carrier at a module, in modules:
/// two addenda (1·m each) and a root clearance (0.25·m), so that their tips never touch (C13).
pub const SUN_PLANET_GAP_MODULES: f64 = 2.25;

/// Every knob of the chain; [`DesignOptions::default`] is what `ncgear design` runs with.
/// (De)serialisable (lengths mm, angles rad as the field names say; a missing field takes its
/// default, an unknown one is an error) and built with `with_*`:
///
/// ```
/// use ncgear::design::DesignOptions;
/// let o = DesignOptions::default().with_tol_mm(0.1).with_module_mm(Some(2.0));
/// let json = serde_json::to_string(&o).unwrap();
/// assert_eq!(serde_json::from_str::<DesignOptions>(&json).unwrap(), o);
/// let partial: DesignOptions = serde_json::from_str(r#"{"tol_mm": 0.1, "module_mm": 2.0}"#).unwrap();
/// assert_eq!(partial, o);
/// // A renamed field still reads under its old name (`tol_tip_mm`, one layout version).
/// let old: DesignOptions = serde_json::from_str(r#"{"tol_tip_mm": 0.1, "module_mm": 2.0}"#).unwrap();
/// assert_eq!(old, o);
/// let old: DesignOptions = serde_json::from_str(r#"{"gear_limits": false, "fit_to_points": false}"#).unwrap();
/// assert_eq!(old, DesignOptions::default().with_limits(false).with_fit(false));
/// assert!(serde_json::from_str::<DesignOptions>(r#"{"tolerance_mm": 0.1}"#).is_err());
/// ```
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
#[non_exhaustive]
pub struct DesignOptions {
    /// Carrier axis O in the trajectory's frame, mm. Default [0, 0].
    pub center_mm: Point,
    /// Step-1 accuracy knobs. Default [`InverseOptions::default`].
    pub inverse: InverseOptions,
    /// Smooth a measured/noisy trajectory to this many Fourier harmonics before step 1
    /// (deviations are still measured against the points as read). Default `None`: measured
    /// points are detected from their estimated noise and smoothed for the start only.
    #[serde(alias = "smoothing")]
    pub smooth: Option<usize>,
    /// Patent-route knobs. Default [`SegmentedOptions::default`].
    pub segmented: SegmentedOptions,
    /// Fixed Fourier order K; `None` (default) = adaptive to `tol_mm`.
    pub order: Option<usize>,
    /// Target max synchronous tip deviation, mm. Default 0.05: the round-trip acceptance bound
    /// for exactly traceable targets (docs/math/chain.md §8.2 suggests 0.1).
    #[serde(alias = "tol_tip_mm")]
    pub tol_mm: f64,
    /// Refinement policy. Default [`RefineMode::Auto`].
    pub refine: RefineMode,
    /// Fit every parameter to the points as the last stage ([`crate::design::fit`]), when the chain's
    /// result is not within 0.2·`tol_mm` of them, leaves the ratio bounds, or came from smoothed
    /// points (default true). Off: the chain's result (patent route, or docs/math/chain.md §8.3 with `refine: On`).
    /// Read under its old name `fit_to_points` too (one layout version).
    #[serde(alias = "fit_to_points")]
    pub fit: bool,
    /// Refinement knobs (ratio bounds are shared with check C6 and the fit). Default
    /// [`RefineOptions::default`].
    pub refine_options: RefineOptions,
    /// Fourier order used by the refinement when no fixed order is given. Default 12.
    pub refine_order: usize,
    /// Samples per pitch curve in the outputs (≥ 720). Default 3600.
    #[serde(alias = "curve_samples")]
    pub samples: usize,
    /// Carrier angles used to measure deviations. Default 2048.
    pub check_samples: usize,
    /// Rack pressure angle α used by the pressure-angle check C10, rad. Default 20°.
    pub pressure_angle_rad: f64,
    /// Limit on the effective pressure angle α + max|atan(r_θ/r)| of the three pitch curves,
    /// rad (C10). Default 45°.
    #[serde(alias = "pressure_angle_limit_rad")]
    pub max_pressure_angle_rad: f64,
    /// Design within the gear limits (default true): the effective pressure angle within
    /// `max_pressure_angle_rad`, every concave arc no tighter than the concave-radius limit,
    /// the sun ratio within its bounds — constraints of every stage that chooses the curves
    /// ([`crate::geometry::limits`]). False: the ratio bounds alone (research use; C9 and C10
    /// are still checked). Read under its old name `gear_limits` too (one layout version).
    #[serde(alias = "gear_limits")]
    pub limits: bool,
    /// Smallest admissible concave radius of curvature of a pitch curve, mm (C9). Default
    /// `None`: 12.5·m at module `m` ([`Self::module_mm`], [`SMALLEST_CUTTER_RADIUS_MODULES`]),
    /// 10 mm without one ([`DEFAULT_MIN_CONCAVE_RADIUS_MM`]).
    pub min_concave_radius_mm: Option<f64>,
    /// Smallest admissible convex radius of curvature of a pitch curve, mm (C8). Default
    /// `None`: 7·m at module `m` ([`Self::module_mm`], [`UNDERCUT_RADIUS_MODULES`]), no limit
    /// without one.
    pub min_convex_radius_mm: Option<f64>,
    /// Module the gears are designed for, mm (default `None`): the smallest concave and convex
    /// radii follow from it (see `min_concave_radius_mm`, `min_convex_radius_mm`).
    pub module_mm: Option<f64>,
    /// Where the intermediate axis may sit. Default [`IdlerOffset::Auto`]: on the carrier line
    /// unless a whole number of teeth would move the arm.
    pub idler_offset: IdlerOffset,
    /// Knobs of the fit to the points ([`crate::design::fit`]): orders, iterations, points,
    /// smoothness. Default [`FitOptions::default`]. Its order, tolerance, noise level, limits and
    /// perimeter are the chain's: set from `order`, `tol_mm`, the points, the gear limits
    /// and the module.
    pub fit_options: FitOptions,
    /// When the design fails its verification, design its nearest alternative too (the other
    /// idler layout, else a looser pressure-angle limit, else the next smaller module: one more
    /// design) and name it in the report ([`crate::design::chain::alternatives`]). Default false (a
    /// design inside a search, a sweep or a drag does not need it, and it costs one more design):
    /// unasked, a failed design names the alternatives that apply without designing them. The
    /// CLI's `--alternatives`, Python's `alternatives=True`.
    pub alternatives: bool,
}

crate::builder::with_fields!(DesignOptions {
    with_center_mm => center_mm: Point,
    with_inverse => inverse: InverseOptions,
    with_smooth => smooth: Option<usize>,
    with_segmented => segmented: SegmentedOptions,
    with_order => order: Option<usize>,
    with_tol_mm => tol_mm: f64,
    with_refine => refine: RefineMode,
    with_fit => fit: bool,
    with_refine_options => refine_options: RefineOptions,
    with_refine_order => refine_order: usize,
    with_samples => samples: usize,
    with_check_samples => check_samples: usize,
    with_pressure_angle_rad => pressure_angle_rad: f64,
    with_max_pressure_angle_rad => max_pressure_angle_rad: f64,
    with_limits => limits: bool,
    with_min_concave_radius_mm => min_concave_radius_mm: Option<f64>,
    with_min_convex_radius_mm => min_convex_radius_mm: Option<f64>,
    with_module_mm => module_mm: Option<f64>,
    with_idler_offset => idler_offset: IdlerOffset,
    with_fit_options => fit_options: FitOptions,
    with_alternatives => alternatives: bool,
});

/// Smallest concave radius of a design made for a module, in modules: the pitch radius of a
/// 25-tooth shaper cutter. The smallest standard cutter, 20 teeth (10·m), fails on hollows
/// within about a quarter of its radius of its own (its tips below its base circle, or its
/// other teeth cutting into the gear: secondary cutting), so a hollow a cutter must fit has a
/// 25 % margin over it.
pub const SMALLEST_CUTTER_RADIUS_MODULES: f64 = 12.5;

/// Smallest convex radius of a design made for a module, in modules: the pitch radius of a
/// 14-tooth gear. A 20° rack of addendum 1·m cuts an arc of radius ρ without undercut when
/// `ρ ≥ m/sin²α` (8.55·m, 17 teeth); below about 14 teeth the undercut takes away so much of
/// the involute that the contact ratio falls under 1 and the mesh loses its transmission
/// (measured: designs with 5–8·m arcs at m = 1.5 mesh with transmission errors of 5e-3°;
/// within 7·m, below 1e-5°).
pub const UNDERCUT_RADIUS_MODULES: f64 = 7.0;

/// Smallest concave radius without a module, mm: a 20-tooth cutter at m = 1.
pub const DEFAULT_MIN_CONCAVE_RADIUS_MM: f64 = 10.0;

impl DesignOptions {
    /// Checks every option against its range, as [`crate::design::design`] does first.
    pub fn validate(&self) -> Result<(), DesignError> {
        validate(self)
    }

    /// The concave-radius limit in force, mm: `min_concave_radius_mm`, or 12.5·m at
    /// `module_mm`, or 10 mm.
    #[must_use]
    pub fn min_concave_radius_in_force_mm(&self) -> f64 {
        self.min_concave_radius_mm.unwrap_or(
            self.module_mm.map_or(DEFAULT_MIN_CONCAVE_RADIUS_MM, |m| {
                SMALLEST_CUTTER_RADIUS_MODULES * m
            }),
        )
    }

    /// The convex-radius limit in force, mm: `min_convex_radius_mm`, or 7·m at `module_mm`;
    /// `None` without either.
    #[must_use]
    pub fn min_convex_radius_in_force_mm(&self) -> Option<f64> {
        self.min_convex_radius_mm
            .or(self.module_mm.map(|m| UNDERCUT_RADIUS_MODULES * m))
    }

    /// The least gap (mm) the sun's and the planet's pitch curves keep across the carrier
    /// (check C13): [`SUN_PLANET_GAP_MODULES`]·m at `module_mm`, 0 without a module.
    #[must_use]
    pub fn sun_planet_gap_mm(&self) -> f64 {
        self.module_mm.map_or(0.0, |m| SUN_PLANET_GAP_MODULES * m)
    }

    /// The gear limits in force: all of them with [`Self::limits`], the ratio bounds alone
    /// without. The options must be valid (as [`crate::design::design`] checks first).
    #[must_use]
    pub fn limits_in_force(&self) -> GearLimits {
        let bounds = self.refine_options.ratio_bounds;
        let limits = if self.limits {
            GearLimits::new(
                bounds,
                self.pressure_angle_rad,
                self.max_pressure_angle_rad,
                self.min_concave_radius_in_force_mm(),
            )
            .and_then(|l| match self.min_convex_radius_in_force_mm() {
                Some(r) => l.with_min_convex_radius(r),
                None => Ok(l),
            })
        } else {
            GearLimits::ratio_only(bounds)
        };
        limits.expect("validated options")
    }
}

impl Default for DesignOptions {
    fn default() -> Self {
        Self {
            center_mm: Point::new(0.0, 0.0),
            inverse: InverseOptions::default(),
            smooth: None,
            segmented: SegmentedOptions::default(),
            order: None,
            tol_mm: 0.05,
            refine: RefineMode::Auto,
            fit: true,
            refine_options: RefineOptions::default(),
            refine_order: 12,
            samples: 3600,
            check_samples: 2048,
            pressure_angle_rad: 20f64.to_radians(),
            max_pressure_angle_rad: 45f64.to_radians(),
            limits: true,
            min_concave_radius_mm: None,
            min_convex_radius_mm: None,
            module_mm: None,
            idler_offset: IdlerOffset::Auto,
            fit_options: FitOptions::default(),
            alternatives: false,
        }
    }
}

/// Most samples per output pitch curve ([`DesignOptions::samples`]).
pub const MAX_CURVE_SAMPLES: usize = 1 << 18;

/// Most dense samples of the trajectory interpolant (`inverse.dense_samples`).
pub const MAX_DENSE_SAMPLES: usize = 1 << 22;

pub(super) fn validate(opts: &DesignOptions) -> Result<(), DesignError> {
    let rules = (input_rules(opts).into_iter())
        .chain(stage_rules(opts))
        .chain(fit_rules(opts));
    match rules.into_iter().find(|r| !r.0) {
        Some((_, option, value, expected)) => Err(DesignError::BadOption {
            option,
            value,
            expected,
        }),
        None => Ok(()),
    }
}

/// A rule of an option: (valid, option, given value, what is expected).
type Rule = (bool, &'static str, String, &'static str);

/// Whether a value is finite and > 0.
fn positive(v: f64) -> bool {
    v.is_finite() && v > 0.0
}

/// An optional value as written in an error.
fn show<T: ToString>(v: Option<T>) -> String {
    v.map_or_else(|| "none".into(), |k| k.to_string())
}

/// The rules of the order, the tolerance, the centre and the inversion, checked first, in order.
fn input_rules(opts: &DesignOptions) -> [Rule; 11] {
    let (inv, refine) = (&opts.inverse, &opts.refine_options);
    let [lo, hi] = refine.ratio_bounds;
    let Point { x: cx, y: cy } = opts.center_mm;
    [
        (
            opts.order.is_none_or(|k| (1..=64).contains(&k)),
            "order",
            show(opts.order),
            "an integer in 1..=64 (40 is the recommended cap, docs/math/chain.md §8.2)",
        ),
        (
            opts.smooth.is_none_or(|h| (4..=512).contains(&h)),
            "smooth",
            show(opts.smooth),
            "a number of harmonics in 4..=512 (about 1/10 of the points for noisy data)",
        ),
        (
            positive(opts.tol_mm),
            "tol_mm",
            opts.tol_mm.to_string(),
            "a positive length in mm",
        ),
        (
            inv.sense.is_none_or(|d| d == 1 || d == -1),
            "inverse.sense",
            format!("{:?}", inv.sense),
            "+1 (CCW), -1 (CW) or unset (either, the better one kept)",
        ),
        (
            (64..=1 << 16).contains(&inv.grid),
            "inverse.grid",
            inv.grid.to_string(),
            "a grid size in 64..=65536",
        ),
        (
            (720..=MAX_CURVE_SAMPLES).contains(&opts.samples),
            "samples",
            opts.samples.to_string(),
            "720..=262144 samples per pitch curve (time and files grow linearly: 1e7 took 27 s)",
        ),
        (
            lo > 0.0 && lo < 1.0 && hi > 1.0 && hi.is_finite(),
            "refine_options.ratio_bounds",
            format!("{lo},{hi}"),
            "0 < min < 1 < max (the ratio's mean is 1)",
        ),
        (
            cx.is_finite() && cy.is_finite(),
            "center_mm",
            format!("{cx},{cy}"),
            "two finite coordinates in mm",
        ),
        (
            positive(inv.tol_relative) && inv.tol_relative < 1e-2,
            "inverse.tol_relative",
            inv.tol_relative.to_string(),
            "a relative tolerance in (0, 0.01)",
        ),
        (
            (64..=MAX_DENSE_SAMPLES).contains(&inv.dense_samples),
            "inverse.dense_samples",
            inv.dense_samples.to_string(),
            "64..=4194304 dense samples (1e7 take 2.5 s, 1e9 run out of time and memory)",
        ),
        (
            inv.law_harmonics != Some(0),
            "inverse.law_harmonics",
            show(inv.law_harmonics),
            "at least one harmonic (or none to keep the law as computed)",
        ),
    ]
}

/// The rules of the patent route, the refinement, the checks and the gear limits, in order.
fn stage_rules(opts: &DesignOptions) -> [Rule; 12] {
    let angle = |v: f64| positive(v) && v < std::f64::consts::FRAC_PI_2;
    let (seg, refine) = (&opts.segmented, &opts.refine_options);
    [
        (
            positive(seg.tol_j),
            "segmented.tol_j",
            seg.tol_j.to_string(),
            "a positive junction tolerance",
        ),
        (
            seg.k_max <= 200,
            "segmented.k_max",
            seg.k_max.to_string(),
            "at most 200 patent iterations (it converges in a few or not at all; 20 is the default)",
        ),
        (
            seg.w1 > 0.0 && seg.w1 <= 1.0,
            "segmented.w1",
            seg.w1.to_string(),
            "a mirror weight in (0, 1]",
        ),
        (
            refine.smoothness.is_finite() && refine.smoothness >= 0.0,
            "refine_options.smoothness",
            refine.smoothness.to_string(),
            "a finite weight ≥ 0",
        ),
        (
            refine.samples >= 16,
            "refine_options.samples",
            refine.samples.to_string(),
            "at least 16 residual samples",
        ),
        (
            (1..=64).contains(&opts.refine_order),
            "refine_order",
            opts.refine_order.to_string(),
            "an integer in 1..=64",
        ),
        (
            opts.check_samples >= 16,
            "check_samples",
            opts.check_samples.to_string(),
            "at least 16 carrier angles",
        ),
        (
            angle(opts.pressure_angle_rad),
            "pressure_angle_rad",
            format!("{} rad", opts.pressure_angle_rad),
            "an angle in (0°, 90°)",
        ),
        (
            angle(opts.max_pressure_angle_rad)
                && opts.max_pressure_angle_rad > opts.pressure_angle_rad,
            "max_pressure_angle_rad",
            format!("{}°", opts.max_pressure_angle_rad.to_degrees()),
            "an angle above the rack's pressure angle (20°) and below 90°",
        ),
        (
            opts.min_concave_radius_mm
                .is_none_or(|r| r > 0.0 && !r.is_nan()),
            "min_concave_radius_mm",
            show(opts.min_concave_radius_mm),
            "a radius > 0 mm (infinite: convex pitch curves only)",
        ),
        (
            opts.min_convex_radius_mm
                .is_none_or(|r| r > 0.0 && r.is_finite()),
            "min_convex_radius_mm",
            show(opts.min_convex_radius_mm),
            "a finite radius > 0 mm",
        ),
        (
            opts.module_mm.is_none_or(|m| (0.05..=50.0).contains(&m)),
            "module_mm",
            show(opts.module_mm),
            "a module in [0.05, 50] mm",
        ),
    ]
}

/// The rules of the fit's own knobs ([`FitOptions`]), checked last, in order.
fn fit_rules(opts: &DesignOptions) -> [Rule; 4] {
    [
        (
            (1..=64).contains(&opts.fit_options.max_order),
            "fit_options.max_order",
            opts.fit_options.max_order.to_string(),
            "an integer in 1..=64",
        ),
        (
            (1..=10_000).contains(&opts.fit_options.max_iterations),
            "fit_options.max_iterations",
            opts.fit_options.max_iterations.to_string(),
            "1..=10000 iterations per order",
        ),
        (
            (16..=100_000).contains(&opts.fit_options.max_points),
            "fit_options.max_points",
            opts.fit_options.max_points.to_string(),
            "16..=100000 points driving the iterations",
        ),
        (
            opts.fit_options.smoothness.is_finite() && opts.fit_options.smoothness >= 0.0,
            "fit_options.smoothness",
            opts.fit_options.smoothness.to_string(),
            "a finite weight ≥ 0",
        ),
    ]
}
