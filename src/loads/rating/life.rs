//! Service life under the turn's stress spectrum (ISO 6336-6 style): every engagement of a tooth
//! is one load cycle at the largest stress it sees while it meshes; Miner's linear sum of
//! `1/N(σ)` over a turn's cycles, N read off the material's S–N line ([`super::material`]),
//! gives the damage per turn of every tooth (and, for pitting, every flank), and the worst of
//! them the life: `turns = 1/D`, hours `= turns/(60·n)` at `n` r/min.

use super::material::SnLine;

/// One engagement: the tooth, the flank it was loaded on, its largest stress (MPa).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Engagement {
    /// Tooth index.
    pub tooth: usize,
    /// 0 left, 1 right.
    pub flank: usize,
    /// Largest stress during the engagement, MPa.
    pub stress_mpa: f64,
}

/// The engagements of one gear in one mesh over a turn, from its per-sample tooth, flank and
/// stress (samples uniform over the turn): consecutive samples on the same tooth are one
/// engagement (round the turn too); unloaded samples (`stress ≤ 0`) belong to none.
#[must_use]
pub fn engagements(tooth: &[usize], flank: &[usize], stress_mpa: &[f64]) -> Vec<Engagement> {
    let n = tooth.len();
    let mut out: Vec<Engagement> = Vec::new();
    let mut last: Option<usize> = None;
    for k in 0..n {
        if !(stress_mpa[k] > 0.0) {
            continue;
        }
        match out.last_mut() {
            Some(e) if last == Some(k.wrapping_sub(1)) && e.tooth == tooth[k] => {
                if stress_mpa[k] > e.stress_mpa {
                    e.stress_mpa = stress_mpa[k];
                    e.flank = flank[k];
                }
            }
            _ => out.push(Engagement {
                tooth: tooth[k],
                flank: flank[k],
                stress_mpa: stress_mpa[k],
            }),
        }
        last = Some(k);
    }
    // The turn closes: an engagement over sample 0 continues the last one.
    if out.len() > 1 && last == Some(n - 1) && stress_mpa[0] > 0.0 && tooth[0] == tooth[n - 1] {
        let tail = out.pop().expect("two engagements");
        let head = &mut out[0];
        if tail.stress_mpa > head.stress_mpa {
            head.stress_mpa = tail.stress_mpa;
            head.flank = tail.flank;
        }
    }
    out
}

/// Miner's damage per turn of the worst tooth (or flank, when `per_flank`): each engagement
/// counts `repeats` cycles (the sun meshes with every arm) at `stress/limit(tooth)` on `line`.
#[must_use]
pub fn worst_damage(
    engagements: &[Engagement],
    limit_mpa: impl Fn(usize) -> f64,
    line: &SnLine,
    repeats: f64,
    per_flank: bool,
) -> f64 {
    let mut damage: std::collections::HashMap<(usize, usize), f64> = Default::default();
    for e in engagements {
        let key = (e.tooth, if per_flank { e.flank } else { 0 });
        *damage.entry(key).or_default() +=
            repeats / line.cycles_at(e.stress_mpa / limit_mpa(e.tooth));
    }
    damage.values().copied().fold(0.0, f64::max)
}

/// Hours of life at `rpm` for a damage `per_turn` per carrier turn; [`f64::MAX`] (1.8e308, a
/// number JSON can hold) for no damage at all: unlimited.
#[must_use]
pub fn hours(per_turn: f64, rpm: f64) -> f64 {
    if per_turn > 0.0 {
        (1.0 / (per_turn * rpm * 60.0)).min(f64::MAX)
    } else {
        f64::MAX
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::loads::rating::material::BENDING_V;

    #[test]
    fn engagements_group_samples_and_close_the_turn() {
        let tooth = [3, 3, 0, 0, 1, 1, 2, 3];
        let flank = [1, 1, 1, 0, 0, 0, 0, 1];
        let s = [5.0, 7.0, 1.0, 2.0, 0.0, 4.0, 3.0, 6.0];
        let e = engagements(&tooth, &flank, &s);
        assert_eq!(e.len(), 4);
        assert_eq!((e[0].tooth, e[0].stress_mpa), (3, 7.0));
        assert_eq!((e[1].tooth, e[1].stress_mpa, e[1].flank), (0, 2.0, 0));
        assert_eq!((e[2].tooth, e[2].stress_mpa), (1, 4.0));
        // At the S–N knee a cycle costs 1/(3·10⁶) of the life.
        let d = worst_damage(&e, |_| 7.0, &BENDING_V, 2.0, false);
        assert!((d - 2.0 / 3e6).abs() < 1e-9 / 3e6);
        assert!((hours(1.0 / 3e6, 300.0) - 3e6 / 18_000.0).abs() < 1e-6);
    }
}
