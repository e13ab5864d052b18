//! Numerical helpers shared by every layer: periodic functions on a turn, closed polylines,
//! roots on a bracket.

pub mod periodic;
pub mod polyline;
pub mod roots;

/// Euclidean length `√(x² + y²)` of a vector in mm (or any unit of mm scale).
///
/// The plain root: mm-scale values are far from overflow and underflow, where it is as accurate
/// as `hypot` (within an ulp) and several times cheaper — the design chain takes it at every
/// dense sample.
///
/// ```
/// assert_eq!(ncgear::math::norm([3.0, 4.0]), 5.0);
/// ```
#[must_use]
#[inline]
pub fn norm(v: [f64; 2]) -> f64 {
    (v[0] * v[0] + v[1] * v[1]).sqrt()
}
