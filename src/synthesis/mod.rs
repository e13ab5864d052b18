//! Synthesis from key poses: the needle's prescribed positions and directions → the mechanism.
//!
//! The engineers of planting arms start from a few **key poses** of the needle (where, and at
//! what angle, it takes the seedling, pushes it into the soil, returns) rather than from a whole
//! trajectory. This folder sits above [`mod@crate::design`]: it finds the arms that can reach the
//! poses, then hands the chain a mechanism to make gears for.
//!
//! Stage A, the dyad ([`dyad`]): the carrier axis O, the carrier arm `l1 = |OA|` and the needle
//! `l3 = |AB|` of every arm that puts the tip on each pose with the needle in its direction.
//!
//! Frame and units as everywhere: world frame, y up, mm; a pose's needle direction is the world
//! direction of the line planet axis A → needle tip B, rad (degrees in files).

pub mod dyad;

pub use dyad::{Dyad, DyadError, DyadOptions, DyadSolutions, Pose, solve_dyads};
