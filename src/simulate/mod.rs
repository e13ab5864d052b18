//! Forward kinematics of a designed transplanting mechanism from its design file, both arms, the
//! dynamic trajectory and the agronomic features (docs/math/chain.md §2).
//!
//! The design file is read through the documented `design.json` conventions only (see
//! [`crate::geometry::assembly`]), so files written by other tools work too: `l3_mm`, `center_distance_mm`
//! (`l3`, `center_distance` in version 1 files), `needle_angle_deg`, `carrier`, `gears.{sun,intermediate,planet}.pitch` and the two
//! `angle_at_zero_deg`. Unknown fields are ignored (design.json carries many report fields).
//!
//! Arm 2 (gears 4, 5; needle 8) is arm 1 half a turn later: at carrier angle φH its pose is arm 1's
//! pose at `φH + π` (docs/math/chain.md §2), so both needles trace the same static path.
//!
//! ## Agronomic features (definitions)
//!
//! With `y` up and the static trajectory of one arm sampled over one carrier turn:
//! - **trajectory height** `H = max y − min y` of the static trajectory, mm;
//! - **planting level** `y_p` (default: the lowest point) and **taking level** `y_t` (default: the
//!   highest point). The *planting instant* is the carrier angle of the lowest point, or, with a
//!   level, the first crossing of `y_p` downwards after the highest point; the *taking instant* is
//!   that of the highest point, or the first crossing of `y_t` downwards after the lowest point;
//! - **needle angle** at an instant: the direction of the needle from A to the tip, measured from the
//!   +x axis (travel direction of the tip at the bottom of a CCW loop is −x), degrees in (−180, 180];
//! - **taking and pushing angles** `α_T`, `α_P`: the needle's angle to the horizontal at the taking
//!   and planting instants, `α = atan2(−u_y, |u_x|)` with `u` the needle direction, degrees in
//!   (−90, 90], > 0 when the tip points below the horizontal (the literature's 取秧角 and 推秧角;
//!   [`angle_to_horizontal`]); the **angle difference** is `α_P − α_T`;
//! - **hole width at planting depth d**: the horizontal extent (max x − min x) of the part of one
//!   arm's dynamic trajectory (one planting stroke) that lies below `min y + d`, mm;
//! - **static loop width at depth d**: the same on the static trajectory, mm;
//! - **tip speed**: `|dB/dt|` along the static path at the given carrier speed, mm/s (max and at the
//!   planting instant), and along the dynamic path (forward travel added);
//! - **minimum clearance between the two arms**: the smallest distance over one turn between the
//!   needle segments `A1B1` and `A2B2`, mm.

mod error;
mod features;
mod file;
mod kinematics;

pub use error::SimulateError;
pub use features::{
    FeatureOptions, Features, angle_to_horizontal, deviation_along, features, features_of_turn,
};
pub use file::{CarrierFile, DesignFile, GearFile, GearsFile, TeethFile};
pub use kinematics::{Simulation, TwoArms};
