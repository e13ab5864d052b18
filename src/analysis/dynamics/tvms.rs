//! Time-varying mesh stiffness (docs/math/companion.md §B.2) and spur-pair contact geometry (docs/math/companion.md §B.4, §B.8).

use std::f64::consts::PI;

/// Involute spur-pair geometry at standard centre distance (α' = α), SI units (m, rad).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, schemars::JsonSchema)]
pub struct PairGeometry {
    /// Base radii rb1, rb2, m.
    pub rb_m: [f64; 2],
    /// Pitch radii r1, r2, m.
    pub r_m: [f64; 2],
    /// Tip radii ra1, ra2, m.
    pub ra_m: [f64; 2],
    /// Working pressure angle α', rad.
    pub alpha_rad: f64,
    /// Base pitch pb = 2π rb1 / z1, m.
    pub base_pitch_m: f64,
    /// Contact ratio ε = (N1E − N1A)/pb.
    pub contact_ratio: f64,
    /// N1N2 = (rb1+rb2) tan α', m.
    pub n1n2_m: f64,
    /// N1A: start of contact from the pinion tangency point N1, m.
    pub n1a_m: f64,
    /// N1P = rb1 tan α': pitch point, m.
    pub n1p_m: f64,
    /// N1E: end of contact, m.
    pub n1e_m: f64,
}

impl PairGeometry {
    /// Standard geometry from tooth numbers, module (mm), pressure angle (deg), addendum
    /// coefficient h_a*. Returns `None` when the inputs are not positive or ε ≤ 1.
    #[must_use]
    pub fn new(z1: u32, z2: u32, module_mm: f64, alpha_deg: f64, ha: f64) -> Option<Self> {
        if z1 < 5
            || z2 < 5
            || !(module_mm > 0.0)
            || !(alpha_deg > 0.0 && alpha_deg < 45.0)
            || !(ha > 0.0)
        {
            return None;
        }
        let m = module_mm * 1e-3;
        let a = alpha_deg.to_radians();
        let r = [m * z1 as f64 / 2.0, m * z2 as f64 / 2.0];
        let rb = [r[0] * a.cos(), r[1] * a.cos()];
        let ra = [r[0] + ha * m, r[1] + ha * m];
        let pb = 2.0 * PI * rb[0] / z1 as f64;
        let n1n2 = (rb[0] + rb[1]) * a.tan();
        let n1a = n1n2 - (ra[1] * ra[1] - rb[1] * rb[1]).sqrt();
        let n1p = rb[0] * a.tan();
        let n1e = (ra[0] * ra[0] - rb[0] * rb[0]).sqrt();
        let eps = (n1e - n1a) / pb;
        if !(eps > 1.0 && eps < 2.0) || n1a < 0.0 {
            return None;
        }
        Some(Self {
            rb_m: rb,
            r_m: r,
            ra_m: ra,
            alpha_rad: a,
            base_pitch_m: pb,
            contact_ratio: eps,
            n1n2_m: n1n2,
            n1a_m: n1a,
            n1p_m: n1p,
            n1e_m: n1e,
        })
    }
}

/// Rectangular-wave mesh stiffness (docs/math/companion.md §B.2 eq. B-1) with double contact during the first (ε−1)t0 of each
/// mesh period, N/m.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RectangularTvms {
    /// Double-contact stiffness, N/m.
    pub kmax: f64,
    /// Single-contact stiffness, N/m.
    pub kmin: f64,
    /// Contact ratio ε ∈ (1, 2).
    pub eps: f64,
}

impl RectangularTvms {
    /// Mean stiffness `kmax(ε−1) + kmin(2−ε)`, N/m (docs/math/companion.md §B.2: the correct mean).
    #[must_use]
    pub fn mean(&self) -> f64 {
        self.kmax * (self.eps - 1.0) + self.kmin * (2.0 - self.eps)
    }

    /// The patent's `kd = k0 + A0/2` with `A0 = 2Δ(2ε−3)`, which double-counts A0/2 (docs/math/companion.md §B.2).
    /// Kept only to flag the inconsistency; never used by the simulator.
    #[must_use]
    pub fn patent_kd(&self) -> f64 {
        let delta = (self.kmax - self.kmin) / 2.0;
        self.mean() + delta * (2.0 * self.eps - 3.0)
    }

    /// Fourier cosine amplitude `kn = 4Δ sin(nπ(ε−1))/(nπ)`, N/m, of `k(t) = k0 + Σ kn cos(n ωe (t − tc))`.
    #[must_use]
    pub fn harmonic(&self, n: u32) -> f64 {
        let delta = (self.kmax - self.kmin) / 2.0;
        let x = n as f64 * PI;
        4.0 * delta * (x * (self.eps - 1.0)).sin() / x
    }

    /// Stiffness at mesh phase `s = mod(t, t0)/t0 ∈ [0, 1)`, N/m.
    #[must_use]
    pub fn at_phase(&self, s: f64) -> f64 {
        if s < self.eps - 1.0 {
            self.kmax
        } else {
            self.kmin
        }
    }

    /// Single-pair stiffness (docs/math/companion.md §B.2 eq. B-2) at local pair time `s` in mesh periods since the pair entered
    /// (`s ∈ [0, ε)`; 0 outside), N/m.
    #[must_use]
    pub fn pair(&self, s: f64) -> f64 {
        if s < 0.0 || s >= self.eps {
            0.0
        } else if s < self.eps - 1.0 || s >= 1.0 {
            self.kmax / 2.0
        } else {
            self.kmin
        }
    }

    /// Truncated Fourier series with `n` harmonics at mesh phase `s` (fraction of t0), N/m.
    #[must_use]
    pub fn fourier(&self, s: f64, n: u32) -> f64 {
        let tc = (self.eps - 1.0) / 2.0;
        self.mean()
            + (1..=n)
                .map(|j| self.harmonic(j) * (2.0 * PI * j as f64 * (s - tc)).cos())
                .sum::<f64>()
    }

    /// Time derivative factor of [`Self::fourier`]: d k/d s (per mesh period), N/m.
    #[must_use]
    pub fn fourier_ds(&self, s: f64, n: u32) -> f64 {
        let tc = (self.eps - 1.0) / 2.0;
        (1..=n)
            .map(|j| {
                let w = 2.0 * PI * j as f64;
                -self.harmonic(j) * w * (w * (s - tc)).sin()
            })
            .sum()
    }
}
