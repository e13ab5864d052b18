//! Numerical helpers shared by every layer: periodic functions on a turn, closed polylines.

pub mod periodic;
pub mod polyline;
