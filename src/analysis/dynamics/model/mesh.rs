//! The mesh kernel: stiffness law, static transmission error, backlash and tip relief per tooth
//! pair (docs/math/companion.md §B.3 eq. B-3..B-5), and the mesh force term acting along the line of action.

use super::{ForceTerm, StateEvent};
use crate::analysis::dynamics::tvms::RectangularTvms;
use nalgebra::DMatrix;
use std::sync::Arc;

/// How the mesh stiffness varies (docs/math/companion.md §B.2).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum StiffnessLaw {
    /// Constant k, N/m.
    Constant(f64),
    /// Truncated Fourier series of the rectangular wave with `n` harmonics.
    Fourier(RectangularTvms, u32),
    /// Exact rectangular wave (one mesh).
    Rectangular(RectangularTvms),
    /// Exact per-pair split (docs/math/companion.md §B.2 eq. B-2).
    Pairs(RectangularTvms),
}

/// Static transmission error `e(t) = e0 + er sin(ωe t + φ)`, m.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ste {
    /// Mean, m.
    pub e0: f64,
    /// Amplitude, m.
    pub er: f64,
    /// Phase, rad.
    pub phase: f64,
}

/// Backlash dead zone (docs/math/companion.md §B.3 eq. B-5).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Backlash {
    /// Half gap b, m.
    pub b: f64,
    /// Damping also acts inside the gap (Kahraman–Singh convention).
    pub damping_in_gap: bool,
    /// Clamp pulling mesh forces to zero.
    pub no_tension: bool,
}

/// Linear tip relief (docs/math/companion.md §B.3 eq. B-4).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Relief {
    /// Δmax, m.
    pub delta_max: f64,
    /// Relief length along the line of action, m.
    pub length: f64,
}

/// Shared mesh kernel: per-pair deflections and forces (docs/math/companion.md §B.3 eq. B-3..B-5).
pub struct MeshCore {
    /// Geometric deflection coefficients (DOF index, coefficient) of `(y1−y2) + rb1θ1 − rb2θ2`.
    pub coeffs: Vec<(usize, f64)>,
    /// Stiffness law.
    pub law: StiffnessLaw,
    /// Mesh damping c_m, N·s/m.
    pub c_m: f64,
    /// Mesh period t0, s.
    pub t0: f64,
    /// Contact ratio ε.
    pub eps: f64,
    /// Mesh frequency ωe, rad/s.
    pub omega_e: f64,
    /// Static TE.
    pub ste: Option<Ste>,
    /// Backlash.
    pub backlash: Option<Backlash>,
    /// Tip relief.
    pub relief: Option<Relief>,
    /// Contact length ε·pb, m.
    pub contact_length: f64,
    /// Split the mesh into the two tooth pairs (relief, friction, `pairs`).
    pub per_pair: bool,
}

/// State of one tooth pair at an instant.
#[derive(Debug, Clone, Copy, Default)]
pub struct PairState {
    /// In contact zone.
    pub active: bool,
    /// Local time since the pair entered, in mesh periods.
    pub s: f64,
    /// Stiffness k_j, N/m.
    pub k: f64,
    /// Deflection δ_j, m.
    pub delta: f64,
    /// Rate δ̇_j, m/s.
    pub delta_dot: f64,
    /// Mesh force F_mj, N.
    pub force: f64,
}

fn dead_zone(d: f64, b: f64) -> f64 {
    if d > b {
        d - b
    } else if d < -b {
        d + b
    } else {
        0.0
    }
}

impl MeshCore {
    /// Geometric deflection `(y1−y2) + rb1θ1 − rb2θ2` (or `u`), m.
    #[must_use]
    pub fn geometric(&self, q: &[f64]) -> f64 {
        self.coeffs.iter().map(|&(i, c)| c * q[i]).sum()
    }

    fn ste(&self, t: f64) -> (f64, f64) {
        match self.ste {
            Some(s) => {
                let a = self.omega_e * t + s.phase;
                (s.e0 + s.er * a.sin(), s.er * self.omega_e * a.cos())
            }
            None => (0.0, 0.0),
        }
    }

    /// Dynamic transmission error `δ = geometric − e(t)`, m (without relief).
    #[must_use]
    pub fn dte(&self, t: f64, q: &[f64]) -> f64 {
        self.geometric(q) - self.ste(t).0
    }

    fn phase(&self, t: f64) -> f64 {
        let s = (t / self.t0).rem_euclid(1.0);
        if s >= 1.0 { 0.0 } else { s }
    }

    fn rect(&self) -> Option<RectangularTvms> {
        match self.law {
            StiffnessLaw::Constant(_) => None,
            StiffnessLaw::Fourier(r, _) | StiffnessLaw::Rectangular(r) | StiffnessLaw::Pairs(r) => {
                Some(r)
            }
        }
    }

    fn total_k(&self, s: f64) -> (f64, f64) {
        match self.law {
            StiffnessLaw::Constant(k) => (k, 0.0),
            StiffnessLaw::Fourier(r, n) => (r.fourier(s, n), r.fourier_ds(s, n) / self.t0),
            StiffnessLaw::Rectangular(r) | StiffnessLaw::Pairs(r) => (r.at_phase(s), 0.0),
        }
    }

    /// Mean mesh stiffness, N/m.
    #[must_use]
    pub fn mean_k(&self) -> f64 {
        match self.law {
            StiffnessLaw::Constant(k) => k,
            StiffnessLaw::Fourier(r, _) | StiffnessLaw::Rectangular(r) | StiffnessLaw::Pairs(r) => {
                r.mean()
            }
        }
    }

    fn relief_at(&self, s_len: f64, v: f64) -> (f64, f64) {
        match self.relief {
            Some(r) if s_len < r.length => (
                r.delta_max * (r.length - s_len) / r.length,
                -r.delta_max * v / r.length,
            ),
            Some(r) if s_len > self.contact_length - r.length => (
                r.delta_max * (s_len - (self.contact_length - r.length)) / r.length,
                r.delta_max * v / r.length,
            ),
            _ => (0.0, 0.0),
        }
    }

    /// The (one or two) pair states and the time derivative of the stiffness part (for the
    /// energy audit: Σ k̇_j Φ(δ_j)).
    pub fn pairs(&self, t: f64, q: &[f64], v: &[f64], out: &mut [PairState; 2]) -> (usize, f64) {
        let g = self.geometric(q);
        let gd = self.geometric(v);
        let (e, ed) = self.ste(t);
        let s1 = self.phase(t);
        let (ktot, kdot) = self.total_k(s1);
        let b = self.backlash.map_or(0.0, |b| b.b);
        let mut kdot_phi = 0.0;
        let np = if self.per_pair { 2 } else { 1 };
        let vel = self.contact_length / (self.eps * self.t0);
        for (j, p) in out.iter_mut().enumerate().take(np) {
            let s = s1 + j as f64;
            let (k, kd, c) = if self.per_pair {
                let r = self.rect().unwrap_or(RectangularTvms {
                    kmax: 2.0 * ktot,
                    kmin: ktot,
                    eps: self.eps,
                });
                let share = r.pair(s) / r.at_phase(s1);
                (ktot * share, kdot * share, self.c_m * share)
            } else {
                (ktot, kdot, self.c_m)
            };
            let (rel, reld) = if self.per_pair {
                self.relief_at(s * self.t0 * vel, vel)
            } else {
                (0.0, 0.0)
            };
            let delta = g - e - rel;
            let dd = gd - ed - reld;
            let fd = dead_zone(delta, b);
            let in_contact = delta.abs() > b;
            let damp = match self.backlash {
                Some(bl) if !bl.damping_in_gap && !in_contact => 0.0,
                _ => c * dd,
            };
            let mut force = k * fd + damp;
            if self.backlash.is_some_and(|bl| bl.no_tension)
                && force * delta.signum() < 0.0
                && in_contact
            {
                force = 0.0;
            }
            if self.backlash.is_some_and(|bl| bl.no_tension) && !in_contact {
                force = 0.0;
            }
            kdot_phi += kd * 0.5 * fd * fd;
            *p = PairState {
                active: k > 0.0,
                s,
                k,
                delta,
                delta_dot: dd,
                force,
            };
        }
        (np, kdot_phi)
    }
}

/// Mesh force term (TVMS + STE + backlash + tip relief) acting along the line of action.
pub struct MeshTerm {
    /// Kernel shared with the friction term.
    pub core: Arc<MeshCore>,
}

impl ForceTerm for MeshTerm {
    fn name(&self) -> String {
        let c = &self.core;
        let mut s = match c.law {
            StiffnessLaw::Constant(k) => format!("mesh(constant k = {k:.4e} N/m"),
            StiffnessLaw::Fourier(r, n) => {
                format!("mesh(fourier n = {n}, mean {:.4e} N/m", r.mean())
            }
            StiffnessLaw::Rectangular(r) => format!("mesh(rectangular, mean {:.4e} N/m", r.mean()),
            StiffnessLaw::Pairs(r) => format!("mesh(pairs, mean {:.4e} N/m", r.mean()),
        };
        s += &format!(", c_m = {:.4} N·s/m", c.c_m);
        if c.per_pair {
            s += ", per tooth pair";
        }
        s += ")";
        if let Some(b) = c.backlash {
            s += &format!(" + backlash(b = {:.3} µm)", b.b * 1e6);
        }
        if let Some(e) = c.ste {
            s += &format!(" + static_te(er = {:.3} µm)", e.er * 1e6);
        }
        if let Some(r) = c.relief {
            s += &format!(
                " + tip_relief({:.3} µm over {:.3} mm)",
                r.delta_max * 1e6,
                r.length * 1e3
            );
        }
        s
    }
    fn add_forces(&self, t: f64, q: &[f64], v: &[f64], f: &mut [f64]) {
        let mut ps = [PairState::default(); 2];
        let (np, _) = self.core.pairs(t, q, v, &mut ps);
        let fm: f64 = ps[..np].iter().map(|p| p.force).sum();
        for &(i, c) in &self.core.coeffs {
            f[i] -= fm * c;
        }
    }
    fn breakpoints(&self, t0: f64, t1: f64, out: &mut Vec<f64>) {
        let c = &self.core;
        let mut offs = Vec::new();
        if matches!(c.law, StiffnessLaw::Rectangular(_) | StiffnessLaw::Pairs(_)) || c.per_pair {
            offs.extend([0.0, c.eps - 1.0]);
        }
        if let (Some(r), true) = (c.relief, c.per_pair) {
            let len = c.contact_length / c.eps; // = pb: distance per mesh period
            offs.push(r.length / len);
            offs.push((c.contact_length - r.length) / len - 1.0);
        }
        push_periodic(&offs, c.t0, t0, t1, out);
    }
    fn events(&self) -> Vec<StateEvent<'_>> {
        let Some(bl) = self.core.backlash else {
            return Vec::new();
        };
        let mut ev: Vec<StateEvent<'_>> = Vec::new();
        let np = if self.core.per_pair { 2 } else { 1 };
        for j in 0..np {
            for sign in [1.0, -1.0] {
                let core = &self.core;
                ev.push(Box::new(move |t: f64, q: &[f64]| {
                    let mut ps = [PairState::default(); 2];
                    let zeros = vec![0.0; q.len()];
                    core.pairs(t, q, &zeros, &mut ps);
                    ps[j].delta - sign * bl.b
                }));
            }
        }
        ev
    }
    fn potential(&self, t: f64, q: &[f64]) -> Option<f64> {
        let mut ps = [PairState::default(); 2];
        let zeros = vec![0.0; q.len()];
        let (np, _) = self.core.pairs(t, q, &zeros, &mut ps);
        let b = self.core.backlash.map_or(0.0, |b| b.b);
        Some(
            ps[..np]
                .iter()
                .map(|p| 0.5 * p.k * dead_zone(p.delta, b).powi(2))
                .sum(),
        )
    }
    fn source_rate(&self, t: f64, q: &[f64], v: &[f64]) -> f64 {
        // P + dV/dt = −F·ġ + Σ k f(δ) δ̇ + Σ k̇ Φ(δ)
        let mut ps = [PairState::default(); 2];
        let (np, kdot_phi) = self.core.pairs(t, q, v, &mut ps);
        let gd = self.core.geometric(v);
        let b = self.core.backlash.map_or(0.0, |b| b.b);
        ps[..np]
            .iter()
            .map(|p| -p.force * gd + p.k * dead_zone(p.delta, b) * p.delta_dot)
            .sum::<f64>()
            + kdot_phi
    }
    fn linear_matrices(&self, k: &mut DMatrix<f64>, c: &mut DMatrix<f64>) -> bool {
        let (km, cm) = (self.core.mean_k(), self.core.c_m);
        for &(i, a) in &self.core.coeffs {
            for &(j, b) in &self.core.coeffs {
                k[(i, j)] += km * a * b;
                c[(i, j)] += cm * a * b;
            }
        }
        true
    }
    fn is_nonlinear(&self) -> bool {
        let c = &self.core;
        c.backlash.is_some() || c.relief.is_some() || !matches!(c.law, StiffnessLaw::Constant(_))
    }
}

pub(super) fn push_periodic(offsets: &[f64], period: f64, t0: f64, t1: f64, out: &mut Vec<f64>) {
    if offsets.is_empty() {
        return;
    }
    let j0 = (t0 / period).floor() as i64 - 1;
    let j1 = (t1 / period).ceil() as i64 + 1;
    for j in j0..=j1 {
        for &o in offsets {
            let t = (j as f64 + o) * period;
            if t > t0 && t < t1 {
                out.push(t);
            }
        }
    }
}
