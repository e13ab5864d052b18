//! The module sized by strength as `design.json` and `tradeoff.json` hold it (`sizing`): one row
//! per standard module designed and rated, and the module kept. The sizing itself (designing,
//! toothing and rating each module) is [`crate::loads::sizing`]; this is its report.

use serde::{Deserialize, Serialize};

/// `sizing`: the modules tried, smallest first, and the one kept.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[non_exhaustive]
pub struct ModuleSizing {
    /// Target of the smallest pitting safety factor.
    #[serde(rename = "S_H_min")]
    pub s_h_min: f64,
    /// Target of the smallest bending safety factor.
    #[serde(rename = "S_F_min")]
    pub s_f_min: f64,
    /// The face width rule: `"auto"` (the smallest within `[6, 15]·m` that meets the targets)
    /// or the scene's, mm.
    pub face_width: String,
    /// One row per module tried, smallest first.
    pub rows: Vec<SizingRow>,
    /// The module kept, mm: the smallest that meets both targets (absent when none does).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub chosen_module_mm: Option<f64>,
}

/// One module designed and rated.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[non_exhaustive]
pub struct SizingRow {
    /// Module, mm.
    pub module_mm: f64,
    /// Tooth count of each gear (absent when the design failed).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub teeth: Option<u32>,
    /// Face width rated, mm.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub face_width_mm: Option<f64>,
    /// Largest distance of the toothed train's tip from the target, mm.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_deviation_mm: Option<f64>,
    /// Smallest pitting safety factor over the turn.
    #[serde(default, rename = "S_H", skip_serializing_if = "Option::is_none")]
    pub s_h: Option<f64>,
    /// Smallest bending safety factor over the turn.
    #[serde(default, rename = "S_F", skip_serializing_if = "Option::is_none")]
    pub s_f: Option<f64>,
    /// Mass of the gears: the sun and every arm's intermediate and planet gears, kg.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gears_mass_kg: Option<f64>,
    /// Peak carrier torque, N·m.
    #[serde(
        default,
        rename = "carrier_torque_peak_Nm",
        skip_serializing_if = "Option::is_none"
    )]
    pub carrier_torque_peak_nm: Option<f64>,
    /// Shortest life by Miner's sum, h.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub life_h: Option<f64>,
    /// Meets both targets.
    pub passed: bool,
    /// Which limit fails, and by how much (absent when the row passes).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fails: Option<String>,
}

impl ModuleSizing {
    /// The failure of the sizing, when no module met the targets.
    #[must_use]
    pub fn failure(&self) -> Option<String> {
        if self.chosen_module_mm.is_some() {
            return None;
        }
        let tried: Vec<String> = self
            .rows
            .iter()
            .map(|r| format!("{}", r.module_mm))
            .collect();
        Some(format!(
            "sizing: no module of {} mm meets S_H ≥ {} and S_F ≥ {} (the rows of `sizing` say \
             which limit fails)",
            tried.join(", "),
            self.s_h_min,
            self.s_f_min
        ))
    }

    /// The table in Markdown: module, teeth, face width, deviation, S_H, S_F, mass, life, what
    /// fails; the kept module in bold.
    #[must_use]
    pub fn markdown(&self) -> String {
        let opt = |v: Option<f64>, d: usize| v.map_or("–".to_string(), |x| format!("{x:.d$}"));
        let mut s = String::from(
            "| module (mm) | teeth | face width (mm) | max deviation (mm) | S_H | S_F | gears mass (kg) | life (h) | fails |\n|---:|---:|---:|---:|---:|---:|---:|---:|---|\n",
        );
        for r in &self.rows {
            let module = if Some(r.module_mm) == self.chosen_module_mm {
                format!("**{}**", r.module_mm)
            } else {
                format!("{}", r.module_mm)
            };
            let life = r.life_h.map_or("–".to_string(), |h| {
                if h.is_finite() && h < 1e9 {
                    format!("{h:.3e}")
                } else {
                    "> 1e9".to_string()
                }
            });
            s.push_str(&format!(
                "| {module} | {} | {} | {} | {} | {} | {} | {life} | {} |\n",
                r.teeth.map_or("–".to_string(), |z| z.to_string()),
                opt(r.face_width_mm, 1),
                opt(r.max_deviation_mm, 4),
                opt(r.s_h, 3),
                opt(r.s_f, 3),
                opt(r.gears_mass_kg, 3),
                r.fails.as_deref().unwrap_or("–"),
            ));
        }
        s
    }
}
