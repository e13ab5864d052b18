//! Gear materials: elasticity, the endurance limits of ISO 6336-5, and the S–N lines of
//! ISO 6336-2 (`Z_NT`) and ISO 6336-3 (`Y_NT`) that the life by Miner's sum reads.
//!
//! **Presets** (the strength numbers are ISO 6336-5:2016 Table 1, quality MQ, `σ_lim = A·x + B`
//! at the hardness named; E and ν as ISO 6336-2 takes them):
//!
//! | preset | material | E, MPa | ν | σ_Hlim, MPa | σ_Flim, MPa |
//! |---|---|---|---|---|---|
//! | `steel` | through-hardened alloy steel (42CrMo4 QT), 300 HV | 206 000 | 0.3 | 1.313·300 + 373 = 767 | 0.425·300 + 187 = 315 |
//! | `case_hardened_steel` | case-hardened steel (16MnCr5, 18CrNiMo7-6), core ≥ 25 HRC | 206 000 | 0.3 | 1500 | 425 |
//! | `cast_iron` | nodular cast iron EN-GJS (pearlitic), 220 HBW | 173 000 | 0.3 | 1.434·220 + 211 = 526 | 0.350·220 + 119 = 196 |
//! | `grey_iron` | grey cast iron EN-GJL, 200 HBW | 118 000 | 0.3 | 1.033·200 + 132 = 339 | 0.256·200 + 8 = 59 |
//! | `pom` | polyacetal, 60 °C, 10⁸ cycles (VDI 2736-2 fits as the open GEARpie package implements them; unverified against VDI 2736) | 3 200 | 0.35 | 50.7 | 27.1 |
//!
//! ISO 6336 is a standard for metal gears: a plastic gear rated by its structure is a first
//! estimate.
//!
//! **S–N lines** (straight in log–log, the life factor `f(N) = (N_knee/N)^k` from the static
//! value to the knee and on with the long-life slope to 0.85 at 10¹⁰ cycles, as the load-spectrum
//! example of ISO 6336-6:2019 Annex C uses them): contact, ISO 6336-2 line 2 (St, V, GGG, Eh: 1.6
//! at 10⁵, 1 at 5·10⁷) or line 3 (GG: 1.3 at 10⁵, 1 at 2·10⁶); bending, ISO 6336-3 (V, GGG:
//! 2.5 at 10⁴; Eh: 2.5 at 10³; GG: 1.6 at 10³; 1 at 3·10⁶ for all).

use serde::{Deserialize, Serialize};

/// One S–N line: `σ_limit·f(N)` is the stress a flank or root survives for N cycles, with
/// `f(N) = (N_knee/N)^k` for N up to the knee (`f(N_static) = static_factor`) and
/// `(N_knee/N)^k_long` beyond it (`f(10¹⁰) = 0.85`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct SnLine {
    /// Cycles at the static limit.
    pub static_cycles: f64,
    /// Life factor at the static limit (Z_NT or Y_NT).
    pub static_factor: f64,
    /// Cycles at the knee (life factor 1).
    pub knee_cycles: f64,
}

/// Cycles where the long-life branch reaches [`LONG_LIFE_FACTOR`].
const LONG_LIFE_CYCLES: f64 = 1e10;
/// Life factor at 10¹⁰ cycles (ISO 6336-2/-3, normal conditions).
const LONG_LIFE_FACTOR: f64 = 0.85;

impl SnLine {
    /// Exponent of the finite-life branch, `k = ln f_static / ln(N_knee/N_static)`.
    #[must_use]
    pub fn finite_exponent(&self) -> f64 {
        self.static_factor.ln() / (self.knee_cycles / self.static_cycles).ln()
    }

    /// Exponent of the long-life branch, `ln(1/0.85) / ln(10¹⁰/N_knee)`.
    #[must_use]
    pub fn long_exponent(&self) -> f64 {
        (1.0 / LONG_LIFE_FACTOR).ln() / (LONG_LIFE_CYCLES / self.knee_cycles).ln()
    }

    /// Cycles to failure at the stress ratio `x = σ/σ_limit` (> 0): the inverse of the line,
    /// `N = N_knee·x^(−1/k)` on the branch `x` falls on.
    #[must_use]
    pub fn cycles_at(&self, x: f64) -> f64 {
        if !(x > 0.0) {
            return f64::INFINITY;
        }
        let k = if x >= 1.0 {
            self.finite_exponent()
        } else {
            self.long_exponent()
        };
        self.knee_cycles * x.powf(-1.0 / k)
    }
}

/// Contact, ISO 6336-2 line 2 (St, V, GGG perl., GTS, Eh, IF; no pitting allowed).
pub const CONTACT_LINE_2: SnLine = SnLine {
    static_cycles: 1e5,
    static_factor: 1.6,
    knee_cycles: 5e7,
};
/// Contact, ISO 6336-2 line 3 (GG, GGG ferr., nitrided).
pub const CONTACT_LINE_3: SnLine = SnLine {
    static_cycles: 1e5,
    static_factor: 1.3,
    knee_cycles: 2e6,
};
/// Bending, ISO 6336-3, V, GGG (perl.), GTS, St.
pub const BENDING_V: SnLine = SnLine {
    static_cycles: 1e4,
    static_factor: 2.5,
    knee_cycles: 3e6,
};
/// Bending, ISO 6336-3, Eh, IF.
pub const BENDING_EH: SnLine = SnLine {
    static_cycles: 1e3,
    static_factor: 2.5,
    knee_cycles: 3e6,
};
/// Bending, ISO 6336-3, GG, GGG (ferr.), NT, NV.
pub const BENDING_GG: SnLine = SnLine {
    static_cycles: 1e3,
    static_factor: 1.6,
    knee_cycles: 3e6,
};

/// A validated material (MPa).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Material {
    /// The preset it came from, or `custom`.
    pub name: String,
    /// Young's modulus, MPa.
    #[serde(rename = "E_MPa")]
    pub e_mpa: f64,
    /// Poisson's ratio.
    pub poisson: f64,
    /// Endurance limit for contact stress σ_Hlim, MPa.
    #[serde(rename = "sigma_Hlim_MPa")]
    pub sigma_hlim_mpa: f64,
    /// Nominal stress number for bending σ_Flim, MPa (the root endurance is `Y_ST·σ_Flim`).
    #[serde(rename = "sigma_Flim_MPa")]
    pub sigma_flim_mpa: f64,
    /// The contact S–N line.
    pub contact_sn: SnLine,
    /// The bending S–N line.
    pub bending_sn: SnLine,
    /// Surface-hardened (the transverse load factor's table row).
    pub surface_hardened: bool,
}

/// The preset names, in the docs' order.
pub const PRESETS: [&str; 5] = [
    "steel",
    "case_hardened_steel",
    "cast_iron",
    "grey_iron",
    "pom",
];

impl Material {
    /// The preset `name` (module docs), or `None`.
    #[must_use]
    pub fn preset(name: &str) -> Option<Self> {
        let m = |e, nu, h, f, c, b, hard| Self {
            name: name.into(),
            e_mpa: e,
            poisson: nu,
            sigma_hlim_mpa: h,
            sigma_flim_mpa: f,
            contact_sn: c,
            bending_sn: b,
            surface_hardened: hard,
        };
        Some(match name {
            "steel" => m(
                206_000.0,
                0.3,
                1.313 * 300.0 + 373.0,
                0.425 * 300.0 + 187.0,
                CONTACT_LINE_2,
                BENDING_V,
                false,
            ),
            "case_hardened_steel" => m(
                206_000.0,
                0.3,
                1500.0,
                425.0,
                CONTACT_LINE_2,
                BENDING_EH,
                true,
            ),
            "cast_iron" => m(
                173_000.0,
                0.3,
                1.434 * 220.0 + 211.0,
                0.350 * 220.0 + 119.0,
                CONTACT_LINE_2,
                BENDING_V,
                false,
            ),
            "grey_iron" => m(
                118_000.0,
                0.3,
                1.033 * 200.0 + 132.0,
                0.256 * 200.0 + 8.0,
                CONTACT_LINE_3,
                BENDING_GG,
                false,
            ),
            "pom" => m(3200.0, 0.35, 50.7, 27.1, CONTACT_LINE_2, BENDING_V, false),
            _ => return None,
        })
    }

    /// The elasticity factor `Z_E = √(1/(π·2(1 − ν²)/E))` of two gears of this material,
    /// √MPa (189.8 for steel on steel).
    #[must_use]
    pub fn elasticity_factor(&self) -> f64 {
        (self.e_mpa / (2.0 * std::f64::consts::PI * (1.0 - self.poisson * self.poisson))).sqrt()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The S–N lines pass through their defining points (ISO 6336-2 line 2 checked against the
    /// Z_NT of ISO/TR 6336-30 Example 1: 0.91 at 1.08·10⁹ and 0.962 at 1.783·10⁸ cycles).
    #[test]
    fn the_sn_lines_pass_through_their_points() {
        let l = CONTACT_LINE_2;
        assert!((l.cycles_at(1.6) - 1e5).abs() < 1e-6 * 1e5);
        assert!((l.cycles_at(1.0) - 5e7).abs() < 1e-6 * 5e7);
        assert!((l.cycles_at(0.85) - 1e10).abs() < 1e-6 * 1e10);
        let z = |n: f64| (5e7 / n).powf(l.long_exponent());
        assert!((z(1.08e9) - 0.91).abs() < 0.005);
        assert!((z(1.783e8) - 0.962).abs() < 0.005);
        assert!((BENDING_V.cycles_at(2.5) - 1e4).abs() < 1e-6 * 1e4);
        assert!((BENDING_V.finite_exponent() - 0.16).abs() < 0.001);
        assert!((BENDING_EH.finite_exponent() - 0.115).abs() < 0.001);
    }

    #[test]
    fn steel_on_steel_has_the_standard_elasticity_factor() {
        let s = Material::preset("steel").unwrap();
        assert!((s.elasticity_factor() - 189.81).abs() < 0.01);
        assert!((s.sigma_hlim_mpa - 766.9).abs() < 1e-9);
        let c = Material::preset("cast_iron").unwrap();
        // ISO 6336-2: Z_E of nodular iron on nodular iron, E = 173 000 MPa.
        assert!((c.elasticity_factor() - 173.96).abs() < 0.05);
    }
}
