//! One mesh rated at every sample of the turn: the local equivalent pair, the contact stress,
//! the root stress of both gears with their tooth and loaded flank, and the remarks on the
//! standard's validity (formulas in the parent module's docs).

use super::equivalent::EquivalentPair;
use super::tooth_form::Flank;
use super::{RatedGear, RatingOptions, loaded_flank};
use crate::geometry::pitch::PitchCurve;
use crate::loads::kinetostatics::MeshForce;
use crate::loads::motion::PitchPoint;

/// A gear of a mesh: its CCW-frame pitch curve, its teeth and `θ → s` map (world body frame),
/// its rim factor Y_B.
pub(super) struct MeshGear<'a> {
    pub curve_ccw: &'a PitchCurve,
    pub rated: &'a RatedGear,
    pub y_b: f64,
}

/// One sample of a mesh, CCW frame: the pitch point and force, the orientations and centres of
/// driver and driven, and the pitch-line speed relative to the carrier (m/s).
pub(super) struct MeshSample<'a> {
    pub pitch: &'a PitchPoint,
    pub force: &'a MeshForce,
    pub orientation_rad: [f64; 2],
    pub speed_m_s: f64,
}

/// What the rating of a mesh gives, per sample (driver, driven).
#[derive(Default)]
pub(super) struct MeshRating {
    pub flank_radius_mm: Vec<[f64; 2]>,
    pub contact_ratio: Vec<f64>,
    pub contact_mpa: Vec<f64>,
    pub root_mpa: [Vec<f64>; 2],
    pub tooth: [Vec<usize>; 2],
    pub flank: [Vec<usize>; 2],
    pub y_fs: [Vec<f64>; 2],
    /// Smallest and largest notch parameter q_s met.
    pub q_s: [f64; 2],
    /// Samples with a concave (internal-contact) flank.
    pub concave: usize,
    /// Smallest contact ratio met and its sample.
    pub min_contact_ratio: (f64, usize),
}

/// Rates one mesh over the turn: `gears` `[driver, driven]`, face width `b_mm`, module `m_mm`,
/// rack pressure angle `alpha` and addendum `addendum_mm`, tooth depth `depth_mm`, the world's
/// `sign`.
#[allow(clippy::too_many_arguments)]
pub(super) fn rate_mesh(
    samples: &[MeshSample<'_>],
    gears: [&MeshGear<'_>; 2],
    opts: &RatingOptions,
    b_mm: f64,
    m_mm: f64,
    alpha: f64,
    addendum_mm: f64,
    depth_mm: f64,
    sign: f64,
) -> MeshRating {
    let f = &opts.factors;
    let z_e = opts.material.elasticity_factor();
    let hardened = opts.material.surface_hardened;
    let k_f_beta = f.k_f_beta(b_mm, depth_mm);
    let mut out = MeshRating {
        q_s: [f64::INFINITY, 0.0],
        min_contact_ratio: (f64::INFINITY, 0),
        ..MeshRating::default()
    };
    for (k, s) in samples.iter().enumerate() {
        let angles = [s.pitch.driver_angle_rad, s.pitch.driven_angle_rad];
        let rho = [0, 1].map(|i| {
            gears[i]
                .curve_ccw
                .geometry(angles[i])
                .radius_of_curvature_mm()
        });
        let pair = EquivalentPair {
            rho_mm: rho,
            alpha_rad: alpha,
            module_mm: m_mm,
            addendum_mm,
        };
        let flank_r = pair.flank_radii_mm();
        let eps = pair.contact_ratio();
        out.flank_radius_mm.push(flank_r);
        out.contact_ratio.push(eps);
        if eps < out.min_contact_ratio.0 {
            out.min_contact_ratio = (eps, k);
        }
        if rho[0] < 0.0 || rho[1] < 0.0 {
            out.concave += 1;
        }
        let f_n = s.force.normal_force_n;
        let f_t = f_n * alpha.cos();
        let k_v = pair.k_v(f, f_t, b_mm, s.speed_m_s);
        let [k_h_alpha, k_f_alpha] = f.k_alpha(f_t, b_mm, eps, hardened);
        let curvature = 1.0 / flank_r[0] + 1.0 / flank_r[1];
        let hertz = z_e * (f_n / b_mm * curvature).max(0.0).sqrt();
        let contact = if f.iso() {
            let [z_b, z_d] = pair.single_pair_factors();
            z_b.max(z_d) * pair.z_epsilon() * (f.k_a * k_v * f.k_h_beta * k_h_alpha).sqrt() * hertz
        } else {
            hertz
        };
        out.contact_mpa.push(contact);
        let k_f = if f.iso() {
            f.k_a * k_v * k_f_beta * k_f_alpha
        } else {
            1.0
        };
        for i in 0..2 {
            let g = gears[i];
            let on_gear = if i == 0 {
                -s.force.force_n
            } else {
                s.force.force_n
            };
            let flank = loaded_flank(g.curve_ccw, angles[i], s.orientation_rad[i], on_gear, sign);
            let tooth = g.rated.teeth.tooth_at(g.rated.arc_at(sign * angles[i]));
            let ff = g
                .rated
                .teeth
                .form_factors(tooth, flank, pair.load_height_mm(i));
            let root = if f_n > 0.0 {
                f_t / (b_mm * m_mm) * ff.y_f * ff.y_s * g.y_b * k_f
            } else {
                0.0
            };
            out.root_mpa[i].push(root);
            out.tooth[i].push(tooth);
            out.flank[i].push(usize::from(flank == Flank::Right));
            out.y_fs[i].push(ff.y_f * ff.y_s);
            if f_n > 0.0 {
                out.q_s = [out.q_s[0].min(ff.q_s), out.q_s[1].max(ff.q_s)];
            }
        }
    }
    out
}

/// The rim factor Y_B of a gear (ISO 6336-3): rim thickness `s_R` from the root to the bore
/// against the tooth depth `h`: 1 for `s_R ≥ 1.2·h`, else `1.6·ln(2.242·h/s_R)`.
pub(super) fn rim_factor(rim_mm: f64, depth_mm: f64) -> f64 {
    if rim_mm >= 1.2 * depth_mm {
        1.0
    } else {
        1.6 * (2.242 * depth_mm / rim_mm.max(1e-9)).ln()
    }
}
