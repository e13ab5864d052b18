//! Sensitivity ranking: each error's contribution to `max_φ |ΔB|` at its 3σ value.

use super::common::UM;
use super::report::Contribution;
use super::{ARM, BACKLASH, GEARS, Inventory, LinearModel, PIN_A, PIN_D, clock_index, ecc_index};
use crate::math::Point;

/// The error items of the ranking: an eccentricity (gear k) or a scalar coordinate.
#[derive(Debug, Clone, Copy)]
enum Item {
    Ecc(usize),
    Scalar(usize, &'static str),
}

fn items() -> Vec<(Item, String)> {
    let mut v: Vec<(Item, String)> = (0..3)
        .map(|k| (Item::Ecc(k), format!("{} eccentricity", GEARS[k])))
        .collect();
    for (k, gear) in GEARS.iter().enumerate() {
        v.push((
            Item::Scalar(clock_index(k), "deg"),
            format!("{gear} clocking"),
        ));
    }
    for (i, n) in [
        (PIN_D[0], "pin D radial"),
        (PIN_D[1], "pin D tangential"),
        (PIN_A[0], "pin A radial"),
        (PIN_A[1], "pin A tangential"),
        (BACKLASH[0], "backlash sun-intermediate"),
        (BACKLASH[1], "backlash intermediate-planet"),
    ] {
        v.push((Item::Scalar(i, "µm"), n.to_string()));
    }
    v.push((Item::Scalar(ARM, "deg"), "arm mounting angle".into()));
    v
}

/// Largest singular value of the 2×2 matrix with columns `a`, `b`.
fn sigma_max(a: Point, b: Point) -> f64 {
    let (p, q, r) = (
        a.x * a.x + a.y * a.y,
        a.x * b.x + a.y * b.y,
        b.x * b.x + b.y * b.y,
    );
    (0.5 * (p + r) + (0.25 * (p - r) * (p - r) + q * q).sqrt())
        .max(0.0)
        .sqrt()
}

/// The contributions `3σ · max_φ |S(φ)|` (µm) of every error, largest first, with their shares.
pub(super) fn ranking(lin: &LinearModel, inv: &Inventory) -> Vec<Contribution> {
    let mut out: Vec<Contribution> = items()
        .into_iter()
        .map(|(item, name)| {
            let (tol, sens, unit) = match item {
                Item::Ecc(k) => {
                    let s = lin
                        .jacobian
                        .iter()
                        .map(|c| sigma_max(c[ecc_index(k)], c[ecc_index(k) + 1]))
                        .fold(0.0, f64::max);
                    (inv.three_sigma_eccentricity(k) * UM, s, "µm")
                }
                Item::Scalar(j, unit) => {
                    let s = lin
                        .jacobian
                        .iter()
                        .map(|c| c[j].hypot())
                        .fold(0.0, f64::max);
                    let t = inv.nominal[j].abs() + inv.spread[j].three_sigma();
                    if unit == "deg" {
                        (t.to_degrees(), s * UM / 1f64.to_degrees(), unit)
                    } else {
                        (t * UM, s, unit)
                    }
                }
            };
            Contribution {
                error: name,
                unit: unit.into(),
                three_sigma: tol,
                sensitivity_um_per_unit: sens,
                max_deviation_um: tol * sens,
                share_percent: 0.0,
            }
        })
        .collect();
    let total: f64 = out.iter().map(|c| c.max_deviation_um).sum();
    for c in &mut out {
        c.share_percent = if total > 0.0 {
            100.0 * c.max_deviation_um / total
        } else {
            0.0
        };
    }
    out.sort_by(|a, b| b.max_deviation_um.total_cmp(&a.max_deviation_um));
    out
}
