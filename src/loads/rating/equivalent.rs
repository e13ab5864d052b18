//! The local equivalent spur pair of a non-circular mesh at one instant: two circular gears
//! whose pitch radii are the pitch curves' signed radii of curvature at the contact (a concave
//! arc is an internal gear), with the rack's pressure angle α and addendum `h_a`, and what ISO
//! 6336 reads of such a pair: the transverse contact ratio ε_α, the contact-ratio factor Z_ε,
//! the single-pair contact factors Z_B, Z_D and the load point of method B (the outer point of
//! single pair contact) on each gear.
//!
//! Along the line of action, measured from gear 1's base-circle tangent point T1, the contact
//! runs over `g_α = A1 + A2`, with `A_i` gear i's share beyond the pitch point:
//!
//! ```text
//! external (ρ > 0):  A = √(r_a² − r_b²) − ρ·sin α,   r_a = ρ + h_a,   r_b = ρ·cos α
//! internal (ρ < 0):  A = |ρ|·sin α − √(r_a² − r_b²), r_a = |ρ| − h_a
//! ε_α = (A1 + A2)/p_b,   p_b = π·m·cos α,   Z_ε = √((4 − ε_α)/3)           (ISO 6336-2, spur)
//! ```
//!
//! (written as `(2|ρ|h_a ± h_a²)/(√(r_a² − r_b²) + |ρ| sin α)`, which stays exact as ρ → ∞, the
//! rack). Each share is at most the mate's flank radius at the pitch point (the contact ends at
//! the interference point). At a contact `u` from the pitch point the flank radii are `ρ1 sin α + u`
//! and `ρ2 sin α − u` (both grow together for an internal pair); the single-pair factors are the
//! ratio of the flank radii products at the pitch point and at the inner point of single contact:
//! `Z_B = √(ρ1P·ρ2P/(ρ1B·ρ2B))` at gear 1's inner point of single contact `u = A1 − p_b` (ISO
//! 6336-2 M1), `Z_D` at gear 2's, `u = p_b − A2` (M2; 1 for an internal gear), each at least 1. The load point of method B on gear i lies `(ε_α − 1)·p_b`
//! from its tip contact towards the pitch point, at the radius `r_en` of ISO 6336-3:
//! `r_en = √((√(r_a² − r_b²) ∓ (ε_α − 1)·p_b)² + r_b²)` (− external, + internal).

use super::factors::Factors;

/// One gear of the pair.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EquivalentGear {
    /// Signed pitch radius (radius of curvature of the pitch curve at the contact), mm.
    pub rho_mm: f64,
}

/// The equivalent pair at one instant.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EquivalentPair {
    /// Signed pitch radii `[ρ1, ρ2]`, mm.
    pub rho_mm: [f64; 2],
    /// Pressure angle α, rad.
    pub alpha_rad: f64,
    /// Module, mm.
    pub module_mm: f64,
    /// Addendum `h_a`, mm.
    pub addendum_mm: f64,
}

impl EquivalentPair {
    /// Base pitch `p_b = π·m·cos α`, mm.
    #[must_use]
    pub fn base_pitch_mm(&self) -> f64 {
        std::f64::consts::PI * self.module_mm * self.alpha_rad.cos()
    }

    /// Roll length of gear `i`'s tip, `√(r_a² − r_b²)`, mm.
    fn tip_roll_mm(&self, i: usize) -> f64 {
        let (rho, h) = (self.rho_mm[i].abs(), self.addendum_mm);
        let ra = if self.rho_mm[i] > 0.0 {
            rho + h
        } else {
            rho - h
        };
        let rb = rho * self.alpha_rad.cos();
        (ra * ra - rb * rb).max(0.0).sqrt()
    }

    /// Gear `i`'s share of the path of contact beyond the pitch point, mm (module docs).
    #[must_use]
    pub fn share_mm(&self, i: usize) -> f64 {
        let (rho, h) = (self.rho_mm[i].abs(), self.addendum_mm);
        let sa = self.alpha_rad.sin();
        let num = if self.rho_mm[i] > 0.0 {
            2.0 * rho * h + h * h
        } else {
            2.0 * rho * h - h * h
        };
        let own = num / (self.tip_roll_mm(i) + rho * sa);
        // The contact ends where the line of action touches the mate's base circle.
        let mate = self.rho_mm[1 - i];
        if mate > 0.0 { own.min(mate * sa) } else { own }
    }

    /// Transverse contact ratio ε_α.
    #[must_use]
    pub fn contact_ratio(&self) -> f64 {
        (self.share_mm(0) + self.share_mm(1)) / self.base_pitch_mm()
    }

    /// Contact-ratio factor `Z_ε = √((4 − ε_α)/3)` (ISO 6336-2, spur gears).
    #[must_use]
    pub fn z_epsilon(&self) -> f64 {
        ((4.0 - self.contact_ratio()).max(0.0) / 3.0).sqrt()
    }

    /// Flank radii at the pitch point `ρ_i·sin α` (signed), mm.
    #[must_use]
    pub fn flank_radii_mm(&self) -> [f64; 2] {
        let sa = self.alpha_rad.sin();
        [self.rho_mm[0] * sa, self.rho_mm[1] * sa]
    }

    /// The single-pair contact factors `[Z_B, Z_D]` of gear 1 and gear 2 (module docs).
    #[must_use]
    pub fn single_pair_factors(&self) -> [f64; 2] {
        let [f1, f2] = self.flank_radii_mm().map(f64::abs);
        let internal = self.rho_mm[0] * self.rho_mm[1] < 0.0;
        let pb = self.base_pitch_mm();
        let (a1, a2) = (self.share_mm(0), self.share_mm(1));
        // Gear 1's flank radius at the contact u from the pitch point (towards gear 1's tip: u > 0),
        // and gear 2's: shorter for an external pair, longer for an internal one.
        let product = |u: f64| {
            let r1 = f1 + u;
            let r2 = if internal { f2 + u } else { f2 - u };
            r1 * r2
        };
        let at = |u: f64| {
            let p = product(u);
            if p > 0.0 {
                ((f1 * f2) / p).sqrt().max(1.0)
            } else {
                1.0
            }
        };
        if self.contact_ratio() <= 1.0 {
            return [1.0, 1.0];
        }
        // Single contact runs from u = A1 − p_b (gear 1's inner point) to u = p_b − A2 (gear
        // 2's); an internal gear's is 1 (ISO 6336-2).
        [at(a1 - pb), if internal { 1.0 } else { at(pb - a2) }]
    }

    /// The pinion's and the wheel's pitch radii `(ρ_p, ρ_w)`, mm: the pinion is the smaller
    /// convex gear (a concave arc is the wheel, by its magnitude).
    #[must_use]
    pub fn pinion_wheel_mm(&self) -> (f64, f64) {
        let rho = self.rho_mm;
        match (rho[0] > 0.0, rho[1] > 0.0) {
            (true, true) => (rho[0].min(rho[1]), rho[0].max(rho[1])),
            (true, false) => (rho[0], rho[1].abs()),
            _ => (rho[1], rho[0].abs()),
        }
    }

    /// ISO 6336-1's K_v ([`Factors::k_v`]) of this pair at tangential force `f_t_n` (N), face
    /// width `b_mm` and pitch-line speed `v_m_s`: `z1 = 2ρ_p/m`, `u = ρ_w/ρ_p`.
    #[must_use]
    pub fn k_v(&self, f: &Factors, f_t_n: f64, b_mm: f64, v_m_s: f64) -> f64 {
        let (rp, rw) = self.pinion_wheel_mm();
        f.k_v(f_t_n, b_mm, 2.0 * rp / self.module_mm, rw / rp, v_m_s)
    }

    /// Method B's load point on gear `i`: its height above the pitch circle towards the tooth
    /// tip, mm (module docs).
    #[must_use]
    pub fn load_height_mm(&self, i: usize) -> f64 {
        let rho = self.rho_mm[i].abs();
        let rb = rho * self.alpha_rad.cos();
        let shift = (self.contact_ratio() - 1.0).max(0.0) * self.base_pitch_mm();
        let roll = if self.rho_mm[i] > 0.0 {
            self.tip_roll_mm(i) - shift
        } else {
            self.tip_roll_mm(i) + shift
        };
        let r_en2 = roll * roll + rb * rb;
        // r_en − ρ (external) or ρ − r_en (internal), from r_en² − ρ² without cancellation.
        let diff = (r_en2 - rho * rho) / (r_en2.sqrt() + rho);
        if self.rho_mm[i] > 0.0 { diff } else { -diff }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The spur pair z = 20/40, m = 4, α = 20°, x = 0 (ISO 6336-2 formulas): ε_α = 1.63519,
    /// Z_ε = 0.88785, Z_B = M1 = 1.06234, Z_D = 1 (M2 = 0.97397), and the load point of method B
    /// on the pinion at d_en = 81.21920 mm.
    #[test]
    fn a_circular_pair_has_its_iso_factors() {
        let p = EquivalentPair {
            rho_mm: [40.0, 80.0],
            alpha_rad: 20f64.to_radians(),
            module_mm: 4.0,
            addendum_mm: 4.0,
        };
        assert!((p.contact_ratio() - 1.63519).abs() < 1e-5);
        assert!((p.z_epsilon() - 0.88785).abs() < 1e-5);
        let [zb, zd] = p.single_pair_factors();
        assert!((zb - 1.06234).abs() < 1e-5, "{zb}");
        assert!((zd - 1.0).abs() < 1e-12);
        assert!((p.load_height_mm(0) - (81.21920 / 2.0 - 40.0)).abs() < 1e-4);
        assert!((p.load_height_mm(1) - (161.86454 / 2.0 - 80.0)).abs() < 1e-4);
    }

    /// Near a rack the shares tend to `h_a/sin α` and nothing cancels.
    #[test]
    fn the_rack_limit_is_exact() {
        let p = EquivalentPair {
            rho_mm: [1e12, 1e12],
            alpha_rad: 20f64.to_radians(),
            module_mm: 2.0,
            addendum_mm: 2.0,
        };
        let a = 2.0 / 20f64.to_radians().sin();
        assert!((p.share_mm(0) - a).abs() < 1e-9);
    }
}
