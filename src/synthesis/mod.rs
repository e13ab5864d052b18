//! Synthesis from key poses or target bands: the needle's prescribed positions and directions, or
//! the agronomic indices' bands → the mechanism.
//!
//! The engineers of planting arms start from a few **key poses** of the needle (where, and at
//! what angle, it takes the seedling, pushes it into the soil, returns) rather than from a whole
//! trajectory. This folder sits above [`mod@crate::design`]: it finds the arms that can reach the
//! poses, then hands the chain a mechanism to make gears for.
//!
//! Stage A, the dyad ([`dyad`]): the carrier axis O, the carrier arm `l1 = |OA|` and the needle
//! `l3 = |AB|` of every arm that puts the tip on each pose with the needle in its direction.
//!
//! Stage B, the timing ([`timing`]): the carrier sense and the carrier angle of each pose, then
//! the smoothest sun ratio (with its phase and the needle angle) whose train turns the needle
//! into each pose's direction — a train, so the design chain can make its gears.
//!
//! [`synthesize`] runs both for a [`Spec`] (`ncgear synthesize SPEC.toml`), hands each candidate
//! train's path to the design chain, measures the poses on the resulting gears and reports the
//! target bands ([`run`]). A spec of target bands without poses is synthesised from the bands
//! alone ([`targets`]): the train whose indices lie in them, within the gear limits.
//!
//! Frame and units as everywhere: world frame, y up, mm; a pose's needle direction is the world
//! direction of the line planet axis A → needle tip B, rad (degrees in files).

pub mod dyad;
pub mod report;
pub mod run;
pub mod spec;
pub mod targets;
pub mod timing;

pub use dyad::{
    Dyad, DyadError, DyadOptions, DyadSolutions, Pose, solve_dyads, solve_dyads_weighted,
};
pub use report::{Synthesis, SynthesisError, SynthesisReport};
pub use run::synthesize;
pub use spec::Spec;
pub use timing::{
    POSE_TOL_RAD, Timing, TimingError, carrier_angles, check_planet_turns, fit_timing,
};
