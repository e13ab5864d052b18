//! Numerical helpers shared by every layer: the plane's `Point` (points and vectors, mm),
//! periodic functions on a turn, closed polylines, roots on a bracket, small least squares
//! (Levenberg–Marquardt), a seeded parallel Monte Carlo and a multistart Nelder–Mead.

pub mod closing_row;
pub mod least_squares;
pub mod monte_carlo;
pub mod optimize;
pub mod periodic;
pub mod point;
pub mod polyline;
pub mod roots;

pub use point::Point;
