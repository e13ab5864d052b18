//! The law of a pair as given: a motion law, a drive centrode or a CSV table of `(φ, ψ)`.
use super::{Expr, PairError};
use crate::math::closing_row::{ClosingRow, closing_row, show_row};

/// The law of the pair.
#[derive(Debug, Clone)]
#[non_exhaustive]
pub enum Law {
    /// Motion law ψ(φ), rad → rad.
    Motion(Expr),
    /// Drive pitch radius at the contact `r(φ)` (any length unit; the shape is scaled to the teeth).
    Centrode(Expr),
    /// Table of (φ, ψ) in radians, φ strictly increasing over one turn `[φ0, φ0 + 2π)`.
    Table(Vec<[f64; 2]>),
}

impl Law {
    /// Reads a CSV law file with header `phi_deg,psi_deg` (degrees; one driver turn, φ strictly
    /// increasing and spanning less than 360°; ψ strictly increasing). A last row at the first
    /// row's φ + 360° with ψ + 360° is the first row again and is dropped; with another ψ it is
    /// refused, naming both lines.
    pub fn from_csv(path: &std::path::Path) -> Result<Self, PairError> {
        let p = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|e| PairError::Csv {
            path: p.clone(),
            line: 0,
            message: e.to_string(),
        })?;
        Self::parse_csv(&text, &p)
    }

    /// Parses CSV law text (format of [`Law::from_csv`]); `file` names the source in errors.
    ///
    /// # Errors
    /// [`PairError::Csv`] naming the file, the 1-based line and what was expected.
    pub fn parse_csv(text: &str, file: &str) -> Result<Self, PairError> {
        let p = file.to_string();
        let (mut rows, mut lines) = (Vec::new(), Vec::new());
        for (k, line) in text.lines().enumerate() {
            let line = line.trim();
            if k == 0 {
                if line.replace(' ', "") != "phi_deg,psi_deg" {
                    return Err(PairError::Csv {
                        path: p,
                        line: 1,
                        message: "expected header `phi_deg,psi_deg`".into(),
                    });
                }
                continue;
            }
            if line.is_empty() {
                continue;
            }
            let parts: Vec<&str> = line.split(',').map(str::trim).collect();
            let vals: Option<Vec<f64>> = parts
                .iter()
                .map(|s| s.parse::<f64>().ok().filter(|v| v.is_finite()))
                .collect();
            match vals {
                Some(v) if v.len() == 2 => {
                    rows.push([v[0], v[1]]);
                    lines.push(k + 1);
                }
                _ => {
                    return Err(PairError::Csv {
                        path: p,
                        line: k + 1,
                        message: format!(
                            "expected two finite numbers `phi_deg,psi_deg`, got `{line}`"
                        ),
                    });
                }
            }
        }
        if rows.len() < 8 {
            return Err(PairError::Csv {
                path: p,
                line: rows.len() + 1,
                message: "need at least 8 rows".into(),
            });
        }
        for k in 1..rows.len() {
            if rows[k][0] <= rows[k - 1][0] || rows[k][1] <= rows[k - 1][1] {
                return Err(PairError::Csv {
                    path: p,
                    line: lines[k],
                    message: "phi and psi must be strictly increasing".into(),
                });
            }
        }
        // ψ(φ + 360°) = ψ(φ) + 360°: a last row one turn on from the first is the first again.
        let last = rows.len() - 1;
        match closing_row(&rows[0], &rows[last], 360.0, &[360.0]) {
            ClosingRow::Inside => {}
            ClosingRow::Repeat => {
                rows.pop();
            }
            ClosingRow::Differs { expected } => {
                return Err(PairError::Csv {
                    path: p,
                    line: lines[last],
                    message: format!(
                        "{} is one turn on from line {}'s {}, the same point of the law, but psi does not gain 360°: make it {} or drop it",
                        show_row(&rows[last]),
                        lines[0],
                        show_row(&rows[0]),
                        show_row(&expected)
                    ),
                });
            }
        }
        if rows[rows.len() - 1][0] - rows[0][0] >= 360.0 {
            return Err(PairError::Csv {
                path: p,
                line: lines[rows.len() - 1],
                message: "phi must span less than 360° (one turn; a last row at the first's phi + 360° must repeat the first, psi + 360°)".into(),
            });
        }
        Ok(Law::Table(
            rows.iter()
                .map(|r| [r[0].to_radians(), r[1].to_radians()])
                .collect(),
        ))
    }
}
