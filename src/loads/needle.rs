//! The force of the soil and the seedling on the needle tip, by the arm's own angle of travel: a
//! periodic table (linear between rows), or the `planting` profile built on the design's own
//! tip path from published planting-force measurements.
//!
//! **The `planting` profile** (an example of the shape and size of the load, not a standard):
//! Kumar & Thomas (CIGR Journal 17(1), 2015) measured on a rice transplanter's picking claw a mean
//! tangential seedling-separation force of 3.10–5.32 N and a peak resultant of 28.3 N (15 mm mat)
//! to 29.7 N (20 mm mat) lasting about a millisecond. The profile puts
//! - the **separation** at the tip's highest point (against gravity; +y without gravity):
//!   5.32 N against the tip's velocity there, over ±10° of travel;
//! - the **planting** at the tip's lowest point: 29.7 N against the tip's velocity there, over
//!   ±5° of travel (at 300 r/min, 5° is 2.8 ms).
//!
//! Each pulse is the raised cosine `F(θ) = F·cos²(π(θ − c)/(2h))` on `|θ − c| < h` (c the
//! centre, h the half-width, F the peak, N), zero outside: its impulse `∫F dθ = F·h` is the
//! triangle's of the same peak and window, and its slope is zero at the peak and at both ends.
//! A measured force pulse has no corners; a triangle's corners (slope jumps of 2F/h at the peak,
//! F/h at the ends) ring a stiff train. The table holds each pulse in rows a tenth of the tip
//! path's sample spacing apart (0.05° at the loads' 720 samples a turn) inside its window, and a
//! zero row just outside, linear between rows like any table; the loads report gives those rows
//! (`needle_table_N`) beside the force at its samples. On 0.05° rows the slope jumps by at most
//! `F·(π/h)²/2·Δθ` (17 N/rad on the 29.7 N pulse, against the triangle's 681 N/rad at its peak),
//! and the rows' trapezoidal impulse is `F·h` exactly (h a whole number of rows). Rows at the
//! samples alone (0.5°) were not enough: their kinks, 0.28 ms apart at 300 r/min, rang the
//! clockwise test design's train at 100× ISO stiffness (≈ 7 kHz, two periods a row) to 1.56 % of
//! its rigid peak, more than the triangle's corners (1.25 %).
//!
//! The velocity is the static path's (the machine's forward travel is not added).

use super::LoadsError;
use crate::math::Point;
use crate::math::closing_row::{ClosingRow, closing_row, show_row};
use serde::{Deserialize, Serialize};
use std::f64::consts::TAU;

/// Peak of the planting profile's separation force, N (Kumar & Thomas 2015, mean tangential
/// separation force, upper value).
pub const SEPARATION_FORCE_N: f64 = 5.32;
/// Peak of the planting profile's planting force, N (Kumar & Thomas 2015, peak resultant,
/// 20 mm mat).
pub const PLANTING_FORCE_N: f64 = 29.7;
/// Half-width of the separation window, rad of travel (10°).
const SEPARATION_HALF_WIDTH_RAD: f64 = 10.0 * std::f64::consts::PI / 180.0;
/// Half-width of the planting window, rad of travel (5°).
const PLANTING_HALF_WIDTH_RAD: f64 = 5.0 * std::f64::consts::PI / 180.0;

/// Most rows a needle table may have.
pub const MAX_ROWS: usize = 100_000;

/// `[needle]` as written: a table or a named profile.
#[derive(Debug, Clone, Default, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct NeedleSpec {
    /// Rows `[travel_deg, Fx_N, Fy_N]`: the arm's own angle of travel, degrees, strictly
    /// increasing over less than a turn (a last row at the first's travel + 360° repeating the
    /// first is dropped); the force on the tip, N, world frame.
    #[serde(default, rename = "force_N", skip_serializing_if = "Option::is_none")]
    pub force_n: Option<Vec<[f64; 3]>>,
    /// `"planting"`: the documented profile (module docs).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub profile: Option<String>,
}

/// A validated needle load.
#[derive(Debug, Clone, PartialEq)]
pub enum NeedleLoad {
    /// A periodic table.
    Table(NeedleTable),
    /// The planting profile, built on the design's tip path ([`NeedleLoad::table`]).
    Planting,
}

/// A periodic table of the needle force: rows `(travel_rad, force_N)`, linear between rows and
/// from the last row round to the first.
#[derive(Debug, Clone, PartialEq)]
pub struct NeedleTable {
    rows: Vec<(f64, Point)>,
}

impl NeedleSpec {
    /// Checks the table's numbers and order, or the profile's name.
    ///
    /// # Errors
    /// [`LoadsError::Field`] naming the row.
    pub fn validate(&self, file: &str) -> Result<NeedleLoad, LoadsError> {
        let field = |key: String, message: String| LoadsError::Field {
            file: file.into(),
            key,
            message,
        };
        match (&self.force_n, self.profile.as_deref()) {
            (Some(_), Some(_)) => Err(field(
                "needle".into(),
                "gives both force_N and profile: keep one".into(),
            )),
            (None, None) => Err(field(
                "needle".into(),
                "needs force_N = [[travel_deg, Fx, Fy], …] or profile = \"planting\"".into(),
            )),
            (None, Some("planting")) => Ok(NeedleLoad::Planting),
            (None, Some(other)) => Err(field(
                "needle.profile".into(),
                format!("`{other}` is not a profile; the one profile is \"planting\""),
            )),
            (Some(rows), None) => {
                if rows.is_empty() || rows.len() > MAX_ROWS {
                    return Err(field(
                        "needle.force_N".into(),
                        format!(
                            "{} rows: give 1..={MAX_ROWS} rows [travel_deg, Fx_N, Fy_N]",
                            rows.len()
                        ),
                    ));
                }
                let mut out = Vec::with_capacity(rows.len());
                for (k, r) in rows.iter().enumerate() {
                    let key = format!("needle.force_N[{k}]");
                    if !r.iter().all(|v| v.is_finite()) {
                        return Err(field(key, "every value must be a finite number".into()));
                    }
                    if r[1].hypot(r[2]) > 1e6 {
                        return Err(field(
                            key,
                            format!("[{}, {}] N: a needle force of at most 1 MN", r[1], r[2]),
                        ));
                    }
                    if r[0].abs() > 3600.0 {
                        return Err(field(
                            key,
                            format!("travel_deg = {} must be within ±3600°", r[0]),
                        ));
                    }
                    out.push((r[0].to_radians(), Point::new(r[1], r[2])));
                }
                NeedleTable::new(out)
                    .map_err(|(k, message)| field(format!("needle.force_N[{k}]"), message))
                    .map(NeedleLoad::Table)
            }
        }
    }
}

impl NeedleTable {
    /// A table of rows `(travel_rad, force_N)`, strictly increasing in travel over less than a
    /// turn; a last row at the first's travel + 2π with the first's force is the first row
    /// again and is dropped ([`crate::math::closing_row`]). On error, the row that breaks the
    /// order and why (a last row at + 2π with another force names row 0 too).
    pub fn new(rows: Vec<(f64, Point)>) -> Result<Self, (usize, String)> {
        let mut rows = rows;
        for k in 1..rows.len() {
            if !(rows[k].0 > rows[k - 1].0) {
                return Err((
                    k,
                    format!(
                        "travel_deg {} does not follow {}: the rows must be in increasing travel",
                        rows[k].0.to_degrees(),
                        rows[k - 1].0.to_degrees()
                    ),
                ));
            }
        }
        let degrees = |r: &(f64, Point)| [r.0.to_degrees(), r.1.x, r.1.y];
        let last = rows.len() - 1;
        match closing_row(&degrees(&rows[0]), &degrees(&rows[last]), 360.0, &[]) {
            ClosingRow::Inside => {}
            ClosingRow::Repeat => {
                rows.pop();
            }
            ClosingRow::Differs { expected } => {
                return Err((
                    last,
                    format!(
                        "{} is at row 0's travel + 360°, the same point of the turn as row 0 (needle.force_N[0] = {}), but its force differs: make it {} or drop it",
                        show_row(&degrees(&rows[last])),
                        show_row(&degrees(&rows[0])),
                        show_row(&expected)
                    ),
                ));
            }
        }
        let span = rows[rows.len() - 1].0 - rows[0].0;
        if span >= TAU {
            return Err((
                rows.len() - 1,
                format!(
                    "the rows span {:.3}°: a periodic table covers one turn (360°), its last row before the first's travel + 360° or at it repeating the first row",
                    span.to_degrees()
                ),
            ));
        }
        Ok(Self { rows })
    }

    /// The rows `(travel_rad, force_N)`, increasing in travel over less than a turn.
    #[must_use]
    pub fn rows(&self) -> &[(f64, Point)] {
        &self.rows
    }

    /// The travel angles of the table's rows, rad (where its linear pieces meet).
    #[must_use]
    pub fn knots_rad(&self) -> Vec<f64> {
        self.rows.iter().map(|r| r.0).collect()
    }

    /// The force at travel angle `travel_rad` (any real angle), N.
    #[must_use]
    pub fn at(&self, travel_rad: f64) -> Point {
        let r = &self.rows;
        if r.len() == 1 {
            return r[0].1;
        }
        let x0 = r[0].0;
        let x = x0 + (travel_rad - x0).rem_euclid(TAU);
        let k = r.partition_point(|row| row.0 <= x);
        // Between row k − 1 and row k, or from the last row round to the first.
        let (a, b) = if k < r.len() {
            (r[k - 1], r[k])
        } else {
            (r[r.len() - 1], (r[0].0 + TAU, r[0].1))
        };
        let t = (x - a.0) / (b.0 - a.0);
        a.1.lerp(b.1, t)
    }
}

impl NeedleLoad {
    /// The table of this load on a tip path: the table itself, or the planting profile built on
    /// `tips_mm` (uniform in travel over one turn, world frame) and `gravity` (its direction
    /// gives "down"; zero: −y).
    #[must_use]
    pub fn table(&self, tips_mm: &[Point], gravity: Point) -> NeedleTable {
        match self {
            Self::Table(t) => t.clone(),
            Self::Planting => planting_table(tips_mm, gravity),
        }
    }
}

/// Rows of the planting profile per sample of the tip path: 10, 0.05° apart at 720 samples a
/// turn (module docs: rows at the samples alone, 0.5° apart, rang the stiff train at 100× ISO).
const ROWS_PER_SAMPLE: f64 = 10.0;

/// The planting profile on a tip path (module docs): each pulse `F·cos²(π(θ − c)/(2h))` in rows
/// [`ROWS_PER_SAMPLE`] to a sample of the path inside its window `|θ − c| < h` (c a sample), with
/// a zero row just outside it on either side; overlapping pulses add.
fn planting_table(tips_mm: &[Point], gravity: Point) -> NeedleTable {
    let n = tips_mm.len();
    let zero = Point::new(0.0, 0.0);
    let empty = || NeedleTable {
        rows: vec![(0.0, zero)],
    };
    if n == 0 {
        return empty();
    }
    let down = if gravity.norm() > 0.0 {
        gravity / gravity.norm()
    } else {
        Point::new(0.0, -1.0)
    };
    let height = |k: usize| -tips_mm[k].dot(down);
    let by_height = |a: &usize, b: &usize| height(*a).total_cmp(&height(*b));
    let highest = (0..n).max_by(by_height).unwrap_or(0);
    let lowest = (0..n).min_by(by_height).unwrap_or(0);
    let against_velocity = |k: usize, magnitude: f64| {
        let v = tips_mm[(k + 1) % n] - tips_mm[(k + n - 1) % n];
        let len = v.norm();
        if len > 0.0 {
            v * (-magnitude / len)
        } else {
            zero
        }
    };
    let at = |k: usize| TAU * k as f64 / n as f64;
    let pulses = [
        (
            at(highest),
            against_velocity(highest, SEPARATION_FORCE_N),
            SEPARATION_HALF_WIDTH_RAD,
        ),
        (
            at(lowest),
            against_velocity(lowest, PLANTING_FORCE_N),
            PLANTING_HALF_WIDTH_RAD,
        ),
    ];
    let step = TAU / n as f64 / ROWS_PER_SAMPLE;
    let mut angles = Vec::new();
    for &(c, _, half) in &pulses {
        // c + i·step for |i·step| < h, and the first row outside on either side (zero there)
        let m = ((half / step * (1.0 - 1e-12)).ceil() as i64 - 1).max(0);
        angles.extend((-(m + 1)..=(m + 1)).map(|i| c + i as f64 * step));
    }
    let x0 = angles.iter().copied().fold(f64::INFINITY, f64::min);
    for x in &mut angles {
        *x = x0 + (*x - x0).rem_euclid(TAU);
    }
    angles.sort_by(f64::total_cmp);
    angles.dedup_by(|b, a| *b - *a < 1e-12);
    let force = |x: f64| {
        pulses.iter().fold(zero, |sum, &(c, peak, half)| {
            // the distance from the centre, wrapped into (−π, π]
            let u = (x - c + std::f64::consts::PI).rem_euclid(TAU) - std::f64::consts::PI;
            sum + peak * raised_cosine(u, half)
        })
    };
    let rows = angles.into_iter().map(|x| (x, force(x))).collect();
    NeedleTable::new(rows).unwrap_or_else(|_| empty())
}

/// The pulse's shape at `u` rad from its centre, half-width `half` rad: `cos²(πu/(2h))` inside
/// `|u| < h`, 0 outside (the raised cosine, 1 at the centre, zero value and slope at `±h`; its
/// integral `h` is the triangle's of the same peak and window).
fn raised_cosine(u: f64, half: f64) -> f64 {
    if u.abs() < half {
        (std::f64::consts::FRAC_PI_2 * u / half).cos().powi(2)
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_table_is_linear_between_rows_and_periodic() {
        let d = f64::to_radians;
        let t = NeedleTable::new(vec![
            (d(0.0), Point::new(0.0, 0.0)),
            (d(165.0), Point::new(4.0, 25.0)),
            (d(185.0), Point::new(0.0, 0.0)),
        ])
        .unwrap();
        let f = t.at(d(175.0));
        assert!((f.x - 2.0).abs() < 1e-12 && (f.y - 12.5).abs() < 1e-12);
        assert!(t.at(d(270.0)).norm() < 1e-12);
        let g = t.at(d(165.0 + 720.0));
        assert!((g.y - 25.0).abs() < 1e-9);
        // Between the last row and the first, round the turn.
        let u = NeedleTable::new(vec![
            (d(10.0), Point::new(10.0, 0.0)),
            (d(350.0), Point::new(0.0, 0.0)),
        ])
        .unwrap();
        assert!((u.at(d(0.0)).x - 5.0).abs() < 1e-9);
    }

    #[test]
    fn rows_out_of_order_or_over_a_turn_are_refused() {
        let d = f64::to_radians;
        let z = Point::new(0.0, 0.0);
        assert_eq!(
            NeedleTable::new(vec![(d(10.0), z), (d(10.0), z)])
                .unwrap_err()
                .0,
            1
        );
        assert!(NeedleTable::new(vec![(d(0.0), z), (d(370.0), z)]).is_err());
        // A 360° row equal to the 0° row is the same point; another force is refused at it.
        let t = NeedleTable::new(vec![
            (d(0.0), z),
            (d(90.0), Point::new(1.0, 0.0)),
            (d(360.0), z),
        ]);
        assert_eq!(t.unwrap().rows.len(), 2);
        let (k, m) =
            NeedleTable::new(vec![(d(0.0), z), (d(360.0), Point::new(0.0, 1.0))]).unwrap_err();
        assert_eq!(k, 1);
        assert!(m.contains("[360, 0, 1]") && m.contains("[0, 0, 0]"), "{m}");
    }

    /// The planting profile on a circular tip path of 720 samples (radius 100 mm, CCW, gravity
    /// −y): the pulses peak at 29.7 N (lowest point, 270°) and 5.32 N (highest, 90°) against the
    /// velocity, follow the raised cosine between (1.5° from the planting centre: cos²(0.15π) of
    /// the peak, 0.794, not the triangle's 0.7), vanish at ±h, and keep the triangle's impulse F·h.
    #[test]
    fn the_planting_pulses_are_raised_cosines_with_the_triangles_impulse() {
        let n = 720;
        let tips: Vec<Point> = (0..n)
            .map(|k| Point::unit(TAU * k as f64 / n as f64) * 100.0)
            .collect();
        let t = NeedleLoad::Planting.table(&tips, Point::new(0.0, -9.81));
        let d = f64::to_radians;
        // at 270° the CCW velocity is +x: the force is −x
        let low = t.at(d(270.0));
        assert!(
            (low.x + PLANTING_FORCE_N).abs() < 1e-9 && low.y.abs() < 1e-9,
            "{low:?}"
        );
        let high = t.at(d(90.0));
        assert!((high.x - SEPARATION_FORCE_N).abs() < 1e-9, "{high:?}");
        let shape = (0.15 * std::f64::consts::PI).cos().powi(2);
        assert!((t.at(d(271.5)).norm() - shape * PLANTING_FORCE_N).abs() < 1e-9);
        assert!(t.at(d(275.0)).norm() < 1e-12 && t.at(d(100.0)).norm() < 1e-12);
        assert!(t.at(d(180.0)).norm() < 1e-12);
        // the impulse: the rows' trapezoidal integral (the table is linear between them)
        let m = 100 * n;
        let area = |c: f64| -> f64 {
            (0..m)
                .map(|k| {
                    let x = c - d(20.0) + d(40.0) * k as f64 / m as f64;
                    t.at(x).norm()
                })
                .sum::<f64>()
                * d(40.0)
                / m as f64
        };
        let (ap, asep) = (area(d(270.0)), area(d(90.0)));
        assert!((ap - PLANTING_FORCE_N * d(5.0)).abs() < 1e-9, "{ap}");
        assert!((asep - SEPARATION_FORCE_N * d(10.0)).abs() < 1e-9, "{asep}");
        // rows 0.05° apart inside the windows, and a zero row just outside each
        assert_eq!(t.knots_rad().len(), (2 * 200 + 1) + (2 * 100 + 1));
    }
}
