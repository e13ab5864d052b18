//! The load factors of ISO 6336-1 and the other factors of the rating: which are used, their
//! documented choices (`factors = "iso"`), and the bare stresses (`factors = "nominal"`: every
//! load factor, Z_ε, Z_B, Z_D = 1).
//!
//! | factor | `iso` choice | source |
//! |---|---|---|
//! | K_A | 1.50 | ISO 6336-6:2019 Table 4: a multi-cylinder engine (the tractor's, "moderate shocks") driving a machine with light shocks (rice planting in puddled soil); set it from a measured load spectrum when there is one |
//! | K_v | `1 + (K1/(K_A·F_t/b) + K2)·(z1·v/100)·√(u²/(1 + u²))`, `K_A·F_t/b ≥ 100 N/mm`, K2 = 0.0193, K1 by accuracy grade (grade 8: 39.1) | ISO 6336-1:2006 method C (DIN 3990-1, 3.3.1), on the local equivalent pair: z1 = 2ρ_pinion/m, u = ρ_wheel/ρ_pinion, v the pitch-line speed relative to the carrier |
//! | K_Hβ | 1.15 | the order of ISO 6336-1 method C for a stiff carrier, b/d ≤ 1, grade 8; the mounting's misalignment sets it (settable) |
//! | K_Fβ | `K_Hβ^N_F`, `N_F = (b/h)²/(1 + b/h + (b/h)²)`, h = (2h_a* + c*)·m, b/h ≥ 3 | ISO 6336-1 |
//! | K_Hα, K_Fα | ISO 6336-1:2006 Table 9 by grade (spur; surface-hardened or not); `max(1/Z_ε², 1.2)` (K_Fα: `1/Y_ε²`, `Y_ε = 0.25 + 0.75/ε_α`) where `K_A·F_t/b < 100 N/mm` or the grade is coarse | ISO 6336-1 |
//! | Z_ε, Z_B, Z_D | the local equivalent pair's ([`super::equivalent`]) | ISO 6336-2 |
//! | Y_F, Y_S | the tooth's own root ([`super::tooth_form`]), load at the outer point of single contact | ISO 6336-3 method B |
//! | Y_β, Y_DT | 1 (spur; grade coarser than 4) | ISO 6336-3 |
//! | Y_B | 1 for a rim `s_R ≥ 1.2·h`, else `1.6·ln(2.242·h/s_R)` (s_R from the root to the bore) | ISO 6336-3 |
//! | Y_ST | 2 (root endurance `σ_FE = 2·σ_Flim`) | ISO 6336-3, -5 |
//! | Y_M | 0.7 for a tooth loaded on both flanks in a turn (an idler, or a reversal while it meshes) | ISO 6336-3 (alternating bending) |
//! | Z_NT, Y_NT, Z_L, Z_v, Z_R, Z_W, Z_X, Y_δrelT, Y_RrelT, Y_X | 1: the safety factors are against the long-life strength; the life is read off the S–N lines ([`super::material`]) | ISO 6336-2, -3 |

use serde::{Deserialize, Serialize};

/// `factors = "iso"` or `"nominal"`.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "lowercase")]
pub enum FactorMode {
    /// The documented ISO choices (module docs).
    #[default]
    Iso,
    /// Every load factor and Z_ε, Z_B, Z_D = 1: the bare Hertz contact stress at the pitch point
    /// and the nominal root stress `F_t/(b·m)·Y_F·Y_S`.
    Nominal,
}

/// The factors of a rating, as chosen or set.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Factors {
    /// Which set.
    pub mode: FactorMode,
    /// Application factor K_A.
    #[serde(rename = "K_A")]
    pub k_a: f64,
    /// ISO 1328-1 accuracy grade (5..=12), for K_v and K_Hα.
    pub accuracy_grade: u8,
    /// K_v set by the scene, instead of the formula.
    #[serde(rename = "K_v", default, skip_serializing_if = "Option::is_none")]
    pub k_v: Option<f64>,
    /// Face load factor K_Hβ.
    #[serde(rename = "K_Hbeta")]
    pub k_h_beta: f64,
    /// K_Fβ set by the scene, instead of `K_Hβ^N_F`.
    #[serde(rename = "K_Fbeta", default, skip_serializing_if = "Option::is_none")]
    pub k_f_beta: Option<f64>,
    /// K_Hα set by the scene, instead of the table.
    #[serde(rename = "K_Halpha", default, skip_serializing_if = "Option::is_none")]
    pub k_h_alpha: Option<f64>,
    /// K_Fα set by the scene, instead of the table.
    #[serde(rename = "K_Falpha", default, skip_serializing_if = "Option::is_none")]
    pub k_f_alpha: Option<f64>,
    /// Stress correction factor of the reference test gear Y_ST.
    #[serde(rename = "Y_ST")]
    pub y_st: f64,
    /// Alternating-bending factor Y_M of a tooth loaded on both flanks.
    #[serde(rename = "Y_M")]
    pub y_m: f64,
}

/// K1 of the simplified K_v formula for spur gears, ISO grades 5..=12 (ISO 6336-1:2006 method C,
/// DIN 3990-1 Table 3.1).
const K1_SPUR: [f64; 8] = [7.5, 14.9, 26.8, 39.1, 52.8, 76.6, 102.6, 146.3];
/// K2 of the simplified K_v formula, spur gears.
const K2_SPUR: f64 = 0.0193;
/// Smallest specific load the factors of ISO 6336-1 take, N/mm.
const MIN_SPECIFIC_LOAD_N_MM: f64 = 100.0;

impl Factors {
    /// The documented choices of `mode` (module docs).
    #[must_use]
    pub fn new(mode: FactorMode) -> Self {
        let iso = mode == FactorMode::Iso;
        Self {
            mode,
            k_a: if iso { 1.5 } else { 1.0 },
            accuracy_grade: 8,
            k_v: None,
            k_h_beta: if iso { 1.15 } else { 1.0 },
            k_f_beta: None,
            k_h_alpha: None,
            k_f_alpha: None,
            y_st: 2.0,
            y_m: 0.7,
        }
    }

    /// Whether the load factors and Z_ε, Z_B, Z_D apply (`iso`).
    #[must_use]
    pub fn iso(&self) -> bool {
        self.mode == FactorMode::Iso
    }

    /// The dynamic factor K_v at tangential force `f_t_n` (N), face width `b_mm`, pinion
    /// equivalent tooth count `z1`, ratio `u ≥ 1` and pitch-line speed `v_m_s` (m/s).
    #[must_use]
    pub fn k_v(&self, f_t_n: f64, b_mm: f64, z1: f64, u: f64, v_m_s: f64) -> f64 {
        if !self.iso() {
            return 1.0;
        }
        if let Some(k) = self.k_v {
            return k;
        }
        let grade = usize::from(self.accuracy_grade.clamp(5, 12)) - 5;
        let w = (self.k_a * f_t_n / b_mm).max(MIN_SPECIFIC_LOAD_N_MM);
        1.0 + (K1_SPUR[grade] / w + K2_SPUR) * (z1 * v_m_s / 100.0) * (u * u / (1.0 + u * u)).sqrt()
    }

    /// K_Fβ = K_Hβ^N_F for face width `b_mm` and tooth depth `h_mm` (or the value set).
    #[must_use]
    pub fn k_f_beta(&self, b_mm: f64, h_mm: f64) -> f64 {
        if let Some(k) = self.k_f_beta {
            return k;
        }
        let bh = (b_mm / h_mm).max(3.0);
        let n_f = bh * bh / (1.0 + bh + bh * bh);
        self.k_h_beta.powf(n_f)
    }

    /// `[K_Hα, K_Fα]` at tangential force `f_t_n` (N), face width `b_mm` and contact ratio
    /// `eps_alpha`, for a surface-hardened gear or not (ISO 6336-1 Table 9, spur), or the values
    /// set.
    #[must_use]
    pub fn k_alpha(&self, f_t_n: f64, b_mm: f64, eps_alpha: f64, hardened: bool) -> [f64; 2] {
        if !self.iso() {
            return [1.0, 1.0];
        }
        let z_eps2 = ((4.0 - eps_alpha) / 3.0).max(1e-6);
        let y_eps = 0.25 + 0.75 / eps_alpha.max(1e-6);
        let coarse = [(1.0 / z_eps2).max(1.2), (1.0 / (y_eps * y_eps)).max(1.2)];
        let table = if self.k_a * f_t_n / b_mm < MIN_SPECIFIC_LOAD_N_MM {
            None
        } else {
            match (hardened, self.accuracy_grade) {
                (true, ..=6) | (false, ..=7) => Some(1.0),
                (true, 7) | (false, 8) => Some(1.1),
                (true, 8) | (false, 9) => Some(1.2),
                _ => None,
            }
        };
        let [h, f] = table.map_or(coarse, |k| [k, k]);
        [self.k_h_alpha.unwrap_or(h), self.k_f_alpha.unwrap_or(f)]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The K_v formula against a hand evaluation (grade 6, K1 = 14.9: z1 = 20, u = 2, v = 2π
    /// m/s, K_A·F_t/b = 156.25 N/mm → 1.12887), and K_Fβ = 1.15^N_F at b/h = 40/9 (N_F = 0.78393
    /// → 1.11579).
    #[test]
    fn the_factors_follow_their_formulas() {
        let mut f = Factors::new(FactorMode::Iso);
        f.k_a = 1.25;
        f.accuracy_grade = 6;
        // v = π·d1·n1 = π·0.08 m·25 /s = 2π m/s.
        let v = std::f64::consts::TAU;
        assert!((f.k_v(5000.0, 40.0, 20.0, 2.0, v) - 1.12887).abs() < 1e-5);
        assert!((f.k_f_beta(40.0, 9.0) - 1.11579).abs() < 1e-5);
        // Below 100 N/mm the transverse factor is 1/Z_ε² at least 1.2.
        let [h, _] = f.k_alpha(100.0, 40.0, 1.6, false);
        assert!((h - (3.0 / 2.4f64).max(1.2)).abs() < 1e-12);
        let nominal = Factors::new(FactorMode::Nominal);
        assert_eq!(nominal.k_v(5000.0, 40.0, 20.0, 2.0, 6.0), 1.0);
        assert_eq!(nominal.k_alpha(5000.0, 40.0, 1.6, false), [1.0, 1.0]);
    }
}
