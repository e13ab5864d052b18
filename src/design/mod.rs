//! The whole design chain and its report (docs/math/chain.md §3–§10).
//!
//! `trajectory → inverse → compat → segmented → fourier → refine → mechanism → assembly`:
//!
//! 1. [`crate::design::inverse`]: l1, l3, ψ3, i31 (step 1–2);
//! 2. [`crate::design::inverse::compat`]: half-closure origin τ and compatibility residual E_c (docs/math/chain.md §6.4);
//! 3. [`crate::design::hypothesis::segmented`]: Fourier hypothesis, mirror/weight iteration (docs/math/chain.md §7);
//! 4. [`crate::geometry::fourier`]: least-squares fit with exact closure, order fixed or adaptive (docs/math/chain.md §8.1–§8.2);
//! 5. [`crate::design::hypothesis::refine`]: direct fit of the tip motion when the patent route misses the tolerance (docs/math/chain.md §8.3);
//! 6. pitch curves, assembly angles, checks C1–C13 and the round trip from the output tables (docs/math/chain.md §9–§10).
//!
//! ```no_run
//! use ncgear::design::{design, DesignOptions, trajectory::Trajectory};
//! let traj = Trajectory::from_path(std::path::Path::new("assets/trajectories/g1_ellipse.csv")).unwrap();
//! let d = design(&traj, &DesignOptions::default()).unwrap();
//! assert!(d.report.roundtrip.max_deviation_mm < 0.1);
//! ```

// The rooms in data-flow order (each imports only rooms above it; `scripts/check_cycles.py`
// holds this order and fails on an import against it): the target, step 1, the patent
// route's ratio, the fit to the points, the errors and knobs of those stages, the strategies
// that choose the train (free, for a module, warm, off the line), the toothed train, the report
// and its checks; `chain` runs them, `tradeoff` runs the chain over a ladder of limits.
pub mod trajectory;

pub mod inverse;

pub mod hypothesis;

pub mod fit;

mod error;

mod options;

pub mod strategy;

pub mod train;

pub mod report;

pub mod chain;

pub mod tradeoff;

pub use chain::design;
pub use chain::redesign::redesign;
pub use error::DesignError;
pub use options::{
    ADAPTIVE_ORDERS, DEFAULT_MIN_CONCAVE_RADIUS_MM, DesignOptions, IdlerOffset, RefineMode,
    SMALLEST_CUTTER_RADIUS_MODULES, SUN_PLANET_GAP_MODULES, UNDERCUT_RADIUS_MODULES,
};
pub use report::{
    Carrier, Check, CompatSummary, Design, DesignReport, FitSummary, FourierSummary, Gear, Gears,
    LimitsSummary, RoundTrip, RouteSummary, SCHEMA_VERSION, Timings, TrajectorySummary, Units,
};
pub use strategy::module::{MIN_TEETH, ModuleSummary};
