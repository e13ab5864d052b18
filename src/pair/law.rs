//! The law of a pair as given: a motion law, a drive centrode or a CSV table of `(φ, ψ)`.
use super::{Expr, PairError};
use std::f64::consts::TAU;

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
    /// increasing and spanning less than 360°; ψ strictly increasing).
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
        let mut rows = Vec::new();
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
                Some(v) if v.len() == 2 => rows.push([v[0].to_radians(), v[1].to_radians()]),
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
                    line: k + 2,
                    message: "phi and psi must be strictly increasing".into(),
                });
            }
        }
        if rows[rows.len() - 1][0] - rows[0][0] >= TAU {
            return Err(PairError::Csv {
                path: p,
                line: rows.len() + 1,
                message: "phi must span less than 360° (one turn, no repeated end row)".into(),
            });
        }
        Ok(Law::Table(rows))
    }
}
