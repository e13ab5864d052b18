//! The whole design chain and its report (docs/math/chain.md §3–§10).
//!
//! `trajectory → inverse → compat → segmented → fourier → refine → mechanism → assembly`:
//!
//! 1. [`crate::design::inverse`]: l1, l3, ψ3, i31 (step 1–2);
//! 2. [`crate::design::compat`]: half-closure origin τ and compatibility residual E_c (docs/math/chain.md §6.4);
//! 3. [`crate::design::segmented`]: Fourier hypothesis, mirror/weight iteration (docs/math/chain.md §7);
//! 4. [`crate::geometry::fourier`]: least-squares fit with exact closure, order fixed or adaptive (docs/math/chain.md §8.1–§8.2);
//! 5. [`crate::design::refine`]: direct fit of the tip motion when the patent route misses the tolerance (docs/math/chain.md §8.3);
//! 6. pitch curves, assembly angles, checks C1–C13 and the round trip from the output tables (docs/math/chain.md §9–§10).
//!
//! ```no_run
//! use ncgear::design::{design, DesignOptions, trajectory::Trajectory};
//! let traj = Trajectory::from_path(std::path::Path::new("assets/trajectories/g1_ellipse.csv")).unwrap();
//! let d = design(&traj, &DesignOptions::default()).unwrap();
//! assert!(d.report.roundtrip.max_deviation_mm < 0.1);
//! ```

pub mod alternatives;
mod chain;
mod checks;
pub mod compat;
mod ellipse;
mod error;
pub mod fit;
mod fit_stage;
pub mod inverse;
mod module;
pub mod needle_law;
pub mod noise;
mod offset_start;
mod options;
mod redesign;
pub mod refine;
mod report;
mod roundtrip;
mod routes;
pub mod segmented;
pub mod sizing;
mod start;
pub mod tradeoff;
pub mod train;
mod trains;
pub mod trajectory;
pub mod warm;

pub use chain::design;
pub use error::DesignError;
pub use module::{MIN_TEETH, ModuleSummary};
pub use options::{
    ADAPTIVE_ORDERS, DEFAULT_MIN_CONCAVE_RADIUS_MM, DesignOptions, IdlerOffset, RefineMode,
    SMALLEST_CUTTER_RADIUS_MODULES, SUN_PLANET_GAP_MODULES, UNDERCUT_RADIUS_MODULES,
};
pub use redesign::redesign;
pub use report::{
    Carrier, Check, CompatSummary, Design, DesignReport, FitSummary, FourierSummary, Gear, Gears,
    LimitsSummary, RoundTrip, RouteSummary, SCHEMA_VERSION, Timings, TrajectorySummary, Units,
};
