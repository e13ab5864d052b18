//! `Point`: a point or a displacement in the plane, mm.

use std::ops::{Add, AddAssign, Div, Mul, MulAssign, Neg, Sub, SubAssign};

use serde::{Deserialize, Serialize};

/// A point of the plane, or a vector between two points, in mm (or a unit vector, unitless).
///
/// One type for both, as in most geometry kernels that work on one plane: `b - a` is the
/// displacement from `a` to `b`, `a + t·d` the point reached along it. Files and JSON carry it as
/// the pair `[x, y]` (serde goes through `[f64; 2]`), so reports read as they always have.
///
/// Every method evaluates its formula in the order written in its doc comment, with no fused
/// multiply-add: a result is the same to the bit as the same formula written out by hand.
///
/// ```
/// use ncgear::math::Point;
/// let (a, b) = (Point::new(1.0, 2.0), Point::new(4.0, 6.0));
/// assert_eq!((b - a).norm(), 5.0);
/// assert_eq!(a.lerp(b, 0.5), Point::new(2.5, 4.0));
/// assert_eq!(Point::new(1.0, 0.0).cross(Point::new(0.0, 1.0)), 1.0);
/// let json = serde_json::to_string(&a).unwrap();
/// assert_eq!(json, "[1.0,2.0]");
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(from = "[f64; 2]", into = "[f64; 2]")]
#[repr(C)]
pub struct Point {
    /// Abscissa, mm.
    pub x: f64,
    /// Ordinate, mm.
    pub y: f64,
}

impl Point {
    /// The origin (or the zero vector).
    pub const ZERO: Self = Self { x: 0.0, y: 0.0 };

    /// The point `(x, y)`, mm.
    #[must_use]
    #[inline]
    pub const fn new(x: f64, y: f64) -> Self {
        Self { x, y }
    }

    /// `(r·cos θ, r·sin θ)`: the point at radius `r` (mm) and polar angle `theta` (rad).
    #[must_use]
    #[inline]
    pub fn from_polar(r: f64, theta: f64) -> Self {
        let (s, c) = theta.sin_cos();
        Self::new(r * c, r * s)
    }

    /// The unit vector `(cos θ, sin θ)` at angle `theta` (rad).
    #[must_use]
    #[inline]
    pub fn unit(theta: f64) -> Self {
        let (s, c) = theta.sin_cos();
        Self::new(c, s)
    }

    /// `[x, y]`.
    #[must_use]
    #[inline]
    pub const fn to_array(self) -> [f64; 2] {
        [self.x, self.y]
    }

    /// Euclidean length `√(x² + y²)`.
    ///
    /// The plain root: mm-scale values are far from overflow and underflow, where it is as
    /// accurate as [`hypot`](Self::hypot) (within an ulp) and several times cheaper — the design
    /// chain takes it at every dense sample.
    #[must_use]
    #[inline]
    pub fn norm(self) -> f64 {
        (self.x * self.x + self.y * self.y).sqrt()
    }

    /// Euclidean length by `f64::hypot` (no overflow or underflow at any scale).
    #[must_use]
    #[inline]
    pub fn hypot(self) -> f64 {
        self.x.hypot(self.y)
    }

    /// Squared length `x² + y²`.
    #[must_use]
    #[inline]
    pub fn norm_squared(self) -> f64 {
        self.x * self.x + self.y * self.y
    }

    /// Distance `|other − self|` by [`hypot`](Self::hypot).
    #[must_use]
    #[inline]
    pub fn distance(self, other: Self) -> f64 {
        (other.x - self.x).hypot(other.y - self.y)
    }

    /// Dot product `x·x' + y·y'`.
    #[must_use]
    #[inline]
    pub fn dot(self, other: Self) -> f64 {
        self.x * other.x + self.y * other.y
    }

    /// Cross product (the z of the 3-D one) `x·y' − y·x'`: positive when `other` is
    /// counter-clockwise of `self`.
    #[must_use]
    #[inline]
    pub fn cross(self, other: Self) -> f64 {
        self.x * other.y - self.y * other.x
    }

    /// Polar angle `atan2(y, x)`, rad in (−π, π].
    #[must_use]
    #[inline]
    pub fn atan2(self) -> f64 {
        self.y.atan2(self.x)
    }

    /// The vector turned a quarter turn counter-clockwise: `(−y, x)`.
    #[must_use]
    #[inline]
    pub fn perp(self) -> Self {
        Self::new(-self.y, self.x)
    }

    /// Turned counter-clockwise about the origin by the angle whose sine and cosine are `s`, `c`:
    /// `(c·x − s·y, s·x + c·y)`.
    #[must_use]
    #[inline]
    pub fn rotate_sc(self, s: f64, c: f64) -> Self {
        Self::new(c * self.x - s * self.y, s * self.x + c * self.y)
    }

    /// Turned counter-clockwise about the origin by `theta` (rad); see [`rotate_sc`](Self::rotate_sc).
    #[must_use]
    #[inline]
    pub fn rotate(self, theta: f64) -> Self {
        let (s, c) = theta.sin_cos();
        self.rotate_sc(s, c)
    }

    /// `self + (other − self)·t`: the point a fraction `t` of the way to `other`.
    #[must_use]
    #[inline]
    pub fn lerp(self, other: Self, t: f64) -> Self {
        Self::new(
            self.x + (other.x - self.x) * t,
            self.y + (other.y - self.y) * t,
        )
    }

    /// `(self + other)·0.5`.
    #[must_use]
    #[inline]
    pub fn midpoint(self, other: Self) -> Self {
        Self::new((self.x + other.x) * 0.5, (self.y + other.y) * 0.5)
    }

    /// Both coordinates finite.
    #[must_use]
    #[inline]
    pub fn is_finite(self) -> bool {
        self.x.is_finite() && self.y.is_finite()
    }
}

impl From<[f64; 2]> for Point {
    #[inline]
    fn from([x, y]: [f64; 2]) -> Self {
        Self { x, y }
    }
}

impl From<Point> for [f64; 2] {
    #[inline]
    fn from(p: Point) -> Self {
        [p.x, p.y]
    }
}

/// nalgebra interop: the vector of the point's coordinates.
impl From<Point> for nalgebra::Vector2<f64> {
    #[inline]
    fn from(p: Point) -> Self {
        Self::new(p.x, p.y)
    }
}

impl From<nalgebra::Vector2<f64>> for Point {
    #[inline]
    fn from(v: nalgebra::Vector2<f64>) -> Self {
        Self::new(v.x, v.y)
    }
}

impl From<(f64, f64)> for Point {
    #[inline]
    fn from((x, y): (f64, f64)) -> Self {
        Self { x, y }
    }
}

impl Add for Point {
    type Output = Self;
    #[inline]
    fn add(self, o: Self) -> Self {
        Self::new(self.x + o.x, self.y + o.y)
    }
}

impl Sub for Point {
    type Output = Self;
    #[inline]
    fn sub(self, o: Self) -> Self {
        Self::new(self.x - o.x, self.y - o.y)
    }
}

impl Neg for Point {
    type Output = Self;
    #[inline]
    fn neg(self) -> Self {
        Self::new(-self.x, -self.y)
    }
}

impl Mul<f64> for Point {
    type Output = Self;
    #[inline]
    fn mul(self, k: f64) -> Self {
        Self::new(self.x * k, self.y * k)
    }
}

impl Mul<Point> for f64 {
    type Output = Point;
    #[inline]
    fn mul(self, p: Point) -> Point {
        Point::new(self * p.x, self * p.y)
    }
}

impl Div<f64> for Point {
    type Output = Self;
    #[inline]
    fn div(self, k: f64) -> Self {
        Self::new(self.x / k, self.y / k)
    }
}

impl AddAssign for Point {
    #[inline]
    fn add_assign(&mut self, o: Self) {
        *self = *self + o;
    }
}

impl SubAssign for Point {
    #[inline]
    fn sub_assign(&mut self, o: Self) {
        *self = *self - o;
    }
}

impl MulAssign<f64> for Point {
    #[inline]
    fn mul_assign(&mut self, k: f64) {
        *self = *self * k;
    }
}

#[cfg(test)]
mod tests {
    use super::Point;

    #[test]
    fn rotation_by_a_quarter_turn_is_the_perpendicular() {
        let p = Point::new(3.0, -2.0);
        let q = p.rotate(std::f64::consts::FRAC_PI_2);
        assert!((q - p.perp()).norm() < 1e-15);
        assert_eq!(p.dot(p.perp()), 0.0);
        assert_eq!(p.cross(p.perp()), p.norm_squared());
    }

    #[test]
    fn reads_and_writes_the_json_pair() {
        let p: Point = serde_json::from_str("[0.1, -2.5]").unwrap();
        assert_eq!(p, Point::new(0.1, -2.5));
        assert_eq!(serde_json::to_string(&p).unwrap(), "[0.1,-2.5]");
        assert!(serde_json::from_str::<Point>("{\"x\": 1}").is_err());
    }
}
