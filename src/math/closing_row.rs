//! The closing row of a periodic table: a table over one turn is often written with both ends,
//! its last row at the first row's abscissa plus one period. That row is the first row again
//! (the same point of the period), so a reader drops it; a last row there that is *not* the
//! first row is a contradiction, which a reader refuses naming both rows.
//!
//! Rows are `[x, v_1, …, v_m]`: the abscissa `x` (an angle, in the table's unit) and values. A
//! value may advance by a fixed amount per period (the driven angle ψ of a gear law gains one
//! turn, `ψ(φ + 360°) = ψ(φ) + 360°`); a force table's values advance by 0.

/// Relative tolerance of "equal" between two numbers of a table, `|a − b| ≤ 1e-9·max(1, |a|, |b|)`:
/// the numbers as written, up to the last digits of a decimal rounding.
pub const EQUAL_RELATIVE: f64 = 1e-9;

/// What the last row of a periodic table is (module docs).
#[derive(Debug, Clone, PartialEq)]
pub enum ClosingRow {
    /// Its abscissa is not the first's plus one period: a row of its own.
    Inside,
    /// At the first's abscissa plus one period and equal to the first row (values advanced):
    /// the same point, to drop.
    Repeat,
    /// At the first's abscissa plus one period but not equal to the first row: `expected` is
    /// the row it would have to be (the first row advanced by one period).
    Differs {
        /// The first row shifted by one period, `[x_0 + period, v_0,1 + advance_1, …]`.
        expected: Vec<f64>,
    },
}

/// `|a − b| ≤` [`EQUAL_RELATIVE`]·max(1, |a|, |b|)`.
fn equal(a: f64, b: f64) -> bool {
    (a - b).abs() <= EQUAL_RELATIVE * 1f64.max(a.abs()).max(b.abs())
}

/// The kind of the last row `last` of a table whose first row is `first` (module docs), the
/// period in the abscissa's unit, `advance[i]` what value `i` gains over one period.
#[must_use]
pub fn closing_row(first: &[f64], last: &[f64], period: f64, advance: &[f64]) -> ClosingRow {
    if first.is_empty() || first.len() != last.len() || !equal(last[0], first[0] + period) {
        return ClosingRow::Inside;
    }
    let expected: Vec<f64> = std::iter::once(first[0] + period)
        .chain(
            first[1..]
                .iter()
                .enumerate()
                .map(|(i, v)| v + advance.get(i).copied().unwrap_or(0.0)),
        )
        .collect();
    if expected[1..]
        .iter()
        .zip(&last[1..])
        .all(|(e, l)| equal(*e, *l))
    {
        ClosingRow::Repeat
    } else {
        ClosingRow::Differs { expected }
    }
}

/// A row as the file would write it: `[0, 4.5, -2]` (9 significant digits).
#[must_use]
pub fn show_row(row: &[f64]) -> String {
    let cells: Vec<String> = row
        .iter()
        .map(|v| format!("{}", (v * 1e9).round() / 1e9))
        .collect();
    format!("[{}]", cells.join(", "))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_closing_row_is_the_first_again_or_a_contradiction() {
        // A force table [deg, Fx, Fy]: 360° equal to 0° is the same point.
        let first = [0.0, 4.5, -2.0];
        assert_eq!(
            closing_row(&first, &[360.0, 4.5, -2.0], 360.0, &[]),
            ClosingRow::Repeat
        );
        assert_eq!(
            closing_row(&first, &[350.0, 4.5, -2.0], 360.0, &[]),
            ClosingRow::Inside
        );
        assert_eq!(
            closing_row(&first, &[360.0, 4.5, -2.5], 360.0, &[]),
            ClosingRow::Differs {
                expected: vec![360.0, 4.5, -2.0]
            }
        );
        // A gear law [φ, ψ]: ψ gains one turn; written to 12 digits it is still the same row.
        assert_eq!(
            closing_row(&[10.0, 5.0], &[370.0, 365.000000000001], 360.0, &[360.0]),
            ClosingRow::Repeat
        );
        assert_eq!(
            closing_row(&[10.0, 5.0], &[370.0, 5.0], 360.0, &[360.0]),
            ClosingRow::Differs {
                expected: vec![370.0, 365.0]
            }
        );
        assert_eq!(show_row(&[360.00000000000006, -2.0, 0.1]), "[360, -2, 0.1]");
    }
}
