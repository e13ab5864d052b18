//! Transplanter tolerance analysis (docs/math/companion.md §C.6): exact perturbed kinematics, closed forms,
//! the circular-gear phasor limit, linear vs exact, Monte Carlo stability, file errors.
//! Shared fixtures here; [`kinematics`] tests the models, [`analysis`] the report, files and CLI.
use ncgear::analysis::tolerance::{ToleranceError, phasor_sum};
use ncgear::analysis::transplanter::*;
use ncgear::config::Format;
use ncgear::geometry::assembly::Assembly;
use ncgear::geometry::golden::{ellipse_ratio, g1_mechanism};
use ncgear::math::Point;
use ncgear::math::monte_carlo::McOptions;
use ncgear::simulate::{FeatureOptions, Simulation, features};
use rand::SeedableRng;
use rand::rngs::ChaCha8Rng;
use std::f64::consts::{FRAC_PI_2, PI};

mod analysis;
mod kinematics;

const ERRORS: &str = include_str!("../../../assets/transplanter/g1_errors.toml");

fn g1(direction: i8) -> Assembly {
    Assembly::from_mechanism(&g1_mechanism(), Point::new(10.0, -5.0), direction, 720).unwrap()
}

/// All three gears circles of radius r = a/2 = 22.5 mm (ratio 1: the needle translates).
fn circular() -> Assembly {
    let mut m = g1_mechanism();
    m.ratio = ellipse_ratio(0.0);
    Assembly::from_mechanism(&m, Point::new(0.0, 0.0), 1, 720).unwrap()
}

fn inventory() -> Inventory {
    ErrorInventory::parse(ERRORS, "g1_errors.toml", Format::Toml).unwrap()
}

fn e(a: f64) -> Point {
    Point::new(a.cos(), a.sin())
}
fn dot(a: Point, b: Point) -> f64 {
    a.x * b.x + a.y * b.y
}
fn dist(a: Point, b: Point) -> f64 {
    a.distance(b)
}

const ZERO: ErrorVector = [0.0; N_COORDS];
