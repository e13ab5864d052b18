//! The effects besides the mesh turned into force terms, one function per effect: drive and load
//! torques, sliding friction (docs/math/companion.md §B.4), shafts (torsion and bending), bearings (linear or Hertz, docs/math/companion.md §B.5),
//! mass unbalance and gravity. Each validates its table (key path in the error) first.

use super::layout::Layout;
use super::{
    BearingSpec, EccKind, EccentricitySpec, FrictionSpec, GravitySpec, SceneError, ShaftSpec,
};
use super::{Derived, ERROR_UM, MAX_MAGNITUDE, PHASE_DEG, invalid, nonneg, pos, ranged};
use crate::analysis::dynamics::model::{
    ConstantForce, ForceTerm, FrictionDirection, FrictionTerm, HertzBearing, LinearSpring,
    MeshCore, UnbalanceTerm,
};
use crate::bounds::Span;
use std::sync::Arc;

/// A validated bearing law (SI units).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum BearingLaw {
    /// No bearing DOFs.
    Rigid,
    /// Linear stiffness kb, N/m.
    Linear(f64),
    /// Hertz contact: constant Kc (N/m^p), Nb elements, clearance γ0 (m), exponent p, cage
    /// ratio r′/(r′ + R′).
    Hertz {
        kc: f64,
        nb: u32,
        gamma0: f64,
        p: f64,
        ratio: f64,
    },
}

/// `effects.bearings` (absent: rigid): the law and the damping cb (N·s/m).
pub(super) fn bearing_law(
    file: &str,
    spec: Option<&BearingSpec>,
) -> Result<(BearingLaw, f64), SceneError> {
    let Some(b) = spec else {
        return Ok((BearingLaw::Rigid, 0.0));
    };
    nonneg(file, "effects.bearings.cb", b.cb())?;
    let law = match *b {
        BearingSpec::Rigid { .. } => BearingLaw::Rigid,
        BearingSpec::Linear { kb, .. } => {
            pos(file, "effects.bearings.kb", kb)?;
            BearingLaw::Linear(kb)
        }
        BearingSpec::Hertz {
            Kc,
            Nb,
            clearance_um,
            exponent,
            r_in_mm,
            R_out_mm,
            ..
        } => hertz_law(file, Kc, Nb, clearance_um, exponent, r_in_mm, R_out_mm)?,
    };
    Ok((law, b.cb()))
}

/// The `hertz` bearing law; clearance µm → m.
fn hertz_law(
    file: &str,
    kc: f64,
    nb: u32,
    clearance_um: f64,
    p: f64,
    ri: f64,
    ro: f64,
) -> Result<BearingLaw, SceneError> {
    let req = |k: &str, v: f64, what: &str| -> Result<f64, SceneError> {
        let span = if k == "clearance_um" {
            Span::closed(0.0, ERROR_UM.hi)
        } else {
            Span::closed(0.0, MAX_MAGNITUDE)
        };
        ranged(file, &format!("effects.bearings.{k}"), v, span, what)
    };
    let kc = req("Kc", kc, "a positive contact constant in N/m^p")?;
    pos(file, "effects.bearings.Kc", kc)?;
    if nb < 3 {
        return Err(invalid(
            file,
            "effects.bearings.Nb",
            nb.to_string(),
            "the number of rolling elements (≥ 3)",
        ));
    }
    let gamma0 = req("clearance_um", clearance_um, "a radial clearance ≥ 0 in µm")? * 1e-6;
    let p = req("exponent", p, "1.5 (ball) or 1.111 (roller)")?;
    if !(1.0..=2.0).contains(&p) {
        return Err(invalid(
            file,
            "effects.bearings.exponent",
            p.to_string(),
            "1 ≤ p ≤ 2 (1.5 ball, 10/9 roller)",
        ));
    }
    let ri = req("r_in_mm", ri, "the inner-race radius in mm (> 0)")?;
    let ro = req("R_out_mm", ro, "the outer-race radius in mm (> r_in_mm)")?;
    if !(ri > 0.0 && ro > ri) {
        return Err(invalid(
            file,
            "effects.bearings.R_out_mm",
            ro.to_string(),
            "the outer-race radius in mm, greater than r_in_mm > 0",
        ));
    }
    Ok(BearingLaw::Hertz {
        kc,
        nb,
        gamma0,
        p,
        ratio: ri / (ri + ro),
    })
}

/// Validates `effects.shafts`: stiffnesses and inertias > 0, dampings ≥ 0, η in [0, 1] with
/// η1 + η2 = 1 and η3 + η4 = 1.
pub(super) fn check_shafts(file: &str, s: &ShaftSpec) -> Result<(), SceneError> {
    for i in 0..2 {
        pos(file, &format!("effects.shafts.kt[{i}]"), s.kt[i])?;
        if let Some(ks) = s.ks {
            pos(file, &format!("effects.shafts.ks[{i}]"), ks[i])?;
        }
        pos(file, &format!("effects.shafts.j_kgm2[{i}]"), s.j_kgm2[i])?;
        nonneg(file, &format!("effects.shafts.ct[{i}]"), s.ct[i])?;
        nonneg(file, &format!("effects.shafts.cs[{i}]"), s.cs[i])?;
    }
    for i in 0..4 {
        pos(file, &format!("effects.shafts.mb_kg[{i}]"), s.mb_kg[i])?;
        if !(0.0..=1.0).contains(&s.eta[i]) {
            return Err(invalid(
                file,
                &format!("effects.shafts.eta[{i}]"),
                s.eta[i].to_string(),
                "a position coefficient in [0, 1]",
            ));
        }
    }
    for (a, b) in [(0, 1), (2, 3)] {
        if (s.eta[a] + s.eta[b] - 1.0).abs() > 1e-9 {
            return Err(invalid(
                file,
                &format!("effects.shafts.eta[{a}]"),
                format!("{} + {}", s.eta[a], s.eta[b]),
                "η1 + η2 = 1 and η3 + η4 = 1 (η_i = l_bi / l)",
            ));
        }
    }
    Ok(())
}

/// Drive and load torques in static balance `Mq = Mp rb2/rb1` (on the motor and load inertias
/// with shafts, else on the gears), or the load `F0 = T1/rb1` on `u` for the SDOF model.
pub(super) fn load(lay: &Layout, d: &Derived, mp: f64, shafts: bool) -> Box<dyn ForceTerm> {
    if lay.sdof {
        return Box::new(ConstantForce {
            label: format!("load(F0 = {:.4} N on u)", d.f0_n),
            forces: vec![(0, d.f0_n)],
        });
    }
    let [rb1, rb2] = d.geometry.rb_m;
    let mq = mp * rb2 / rb1;
    let (a, b) = if shafts {
        ("theta_p", "theta_q")
    } else {
        ("theta1", "theta2")
    };
    let forces = vec![
        (lay.idx(a).unwrap_or(0), mp),
        (lay.idx(b).unwrap_or(0), -mq),
    ];
    Box::new(ConstantForce {
        label: format!("torques(Mp = {mp} N·m on {a}, Mq = {mq:.4} N·m on {b})"),
        forces,
    })
}

/// `effects.friction`: 0 ≤ μ < 1; `tanh` needs v0 > 0 (m/s).
pub(super) fn friction(
    file: &str,
    f: &FrictionSpec,
    lay: &Layout,
    core: &Arc<MeshCore>,
    d: &Derived,
) -> Result<Box<dyn ForceTerm>, SceneError> {
    let mu = f.mu();
    if !(mu.is_finite() && (0.0..1.0).contains(&mu)) {
        return Err(invalid(
            file,
            "effects.friction.mu",
            mu.to_string(),
            "a friction coefficient 0 ≤ μ < 1",
        ));
    }
    let direction = match *f {
        FrictionSpec::PitchSwitch { .. } => FrictionDirection::PitchSwitch,
        FrictionSpec::Tanh { v0, .. } if Span::positive(100.0).contains(v0) => {
            FrictionDirection::Tanh(v0)
        }
        FrictionSpec::Tanh { v0, .. } => {
            return Err(invalid(
                file,
                "effects.friction.v0",
                v0.to_string(),
                "a positive velocity scale in m/s, at most 100 (required by direction = \"tanh\")",
            ));
        }
    };
    Ok(Box::new(FrictionTerm {
        core: core.clone(),
        mu,
        direction,
        geom: d.geometry,
        omega: lay.omega,
        idx: [
            lay.idx("x1"),
            lay.idx("x2"),
            lay.idx("theta1"),
            lay.idx("theta2"),
        ],
    }))
}

/// `effects.shafts`: torsion springs motor–pinion and gear–load (kt, ct), and bending springs
/// from each gear centre to its two bearings (ks, cs):
/// δx1 = x1 − η2 xb1 − η1 xb2 ; δx2 = x2 − η4 xb3 − η3 xb4 (same in y).
pub(super) fn shafts(s: &ShaftSpec, lay: &Layout, out: &mut Vec<Box<dyn ForceTerm>>) {
    let idx = |n: &str| lay.idx(n).unwrap_or(0);
    out.push(Box::new(LinearSpring {
        label: format!("shaft1 torsion(kt = {} N·m/rad)", s.kt[0]),
        coeffs: vec![(idx("theta_p"), 1.0), (idx("theta1"), -1.0)],
        k: s.kt[0],
        c: s.ct[0],
    }));
    out.push(Box::new(LinearSpring {
        label: format!("shaft2 torsion(kt = {} N·m/rad)", s.kt[1]),
        coeffs: vec![(idx("theta2"), 1.0), (idx("theta_q"), -1.0)],
        k: s.kt[1],
        c: s.ct[1],
    }));
    let ks = s.ks.unwrap_or([0.0; 2]);
    for (gear, shaft, bs, etas) in [
        (1, 0usize, [1, 2], [s.eta[1], s.eta[0]]),
        (2, 1, [3, 4], [s.eta[3], s.eta[2]]),
    ] {
        for ax in ["x", "y"] {
            let Some(gi) = lay.idx(&format!("{ax}{gear}")) else {
                continue;
            };
            let mut coeffs = vec![(gi, 1.0)];
            for (b, eta) in bs.iter().zip(etas) {
                if let Some(bi) = lay.idx(&format!("{ax}b{b}")) {
                    coeffs.push((bi, -eta));
                }
            }
            out.push(Box::new(LinearSpring {
                label: format!("shaft{} bending {ax}(ks = {} N/m)", shaft + 1, ks[shaft]),
                coeffs,
                k: ks[shaft],
                c: s.cs[shaft],
            }));
        }
    }
}

/// Bearings: on the four bearing masses (with shafts) or directly on the gear centres; linear
/// springs per axis, or a Hertz bearing (+ a damper when cb > 0). Rigid: no term.
pub(super) fn bearings(
    law: BearingLaw,
    cb: f64,
    with_shafts: bool,
    lay: &Layout,
    out: &mut Vec<Box<dyn ForceTerm>>,
) {
    let [omega1, omega2] = lay.omega;
    let sites: Vec<(String, Option<usize>, Option<usize>, f64)> = if with_shafts {
        (1..=4)
            .map(|b| {
                (
                    format!("bearing{b}"),
                    lay.idx(&format!("xb{b}")),
                    lay.idx(&format!("yb{b}")),
                    if b <= 2 { omega1 } else { omega2 },
                )
            })
            .collect()
    } else {
        vec![
            (
                "bearing(pinion)".into(),
                lay.idx("x1"),
                lay.idx("y1"),
                omega1,
            ),
            ("bearing(gear)".into(), lay.idx("x2"), lay.idx("y2"), omega2),
        ]
    };
    for (label, ix, iy, om) in sites {
        let sites = [("x", ix), ("y", iy)];
        match law {
            BearingLaw::Rigid => {}
            BearingLaw::Linear(kb) => {
                axis_springs(
                    out,
                    &label,
                    sites,
                    &format!("linear(kb = {kb} N/m)"),
                    kb,
                    cb,
                );
            }
            BearingLaw::Hertz {
                kc,
                nb,
                gamma0,
                p,
                ratio,
            } => {
                out.push(Box::new(HertzBearing {
                    label: format!(
                        "{label} hertz(Kc = {kc:e}, Nb = {nb}, γ0 = {:.2} µm, p = {p})",
                        gamma0 * 1e6
                    ),
                    idx: [ix, iy],
                    kc,
                    nb,
                    gamma0,
                    p,
                    omega_cage: om * ratio,
                }));
                if cb > 0.0 {
                    axis_springs(out, &label, sites, &format!("damper(cb = {cb})"), 0.0, cb);
                }
            }
        }
    }
}

/// One spring–damper `what` (stiffness k, damping c) per present axis of a bearing site.
fn axis_springs(
    out: &mut Vec<Box<dyn ForceTerm>>,
    label: &str,
    sites: [(&str, Option<usize>); 2],
    what: &str,
    k: f64,
    c: f64,
) {
    for (ax, i) in sites {
        if let Some(i) = i {
            out.push(Box::new(LinearSpring {
                label: format!("{label} {ax} {what}"),
                coeffs: vec![(i, 1.0)],
                k,
                c,
            }));
        }
    }
}

/// `effects.eccentricity`: the unbalance force `m ρ ω²` of each named gear (ρ µm → m); a gear
/// without lateral DOFs gets no term.
pub(super) fn eccentricity(
    file: &str,
    ecc: &EccentricitySpec,
    lay: &Layout,
    d: &Derived,
    out: &mut Vec<Box<dyn ForceTerm>>,
) -> Result<(), SceneError> {
    let [m1, m2] = d.mass_kg;
    let [omega1, omega2] = lay.omega;
    for (which, spec, m, om, g) in [
        ("pinion", &ecc.pinion, m1, omega1, 1),
        ("gear", &ecc.gear, m2, omega2, 2),
    ] {
        let Some(s) = spec else { continue };
        match s.kind {
            EccKind::Unbalance => {}
        }
        ranged(
            file,
            &format!("effects.eccentricity.{which}.rho_um"),
            s.rho_um,
            Span::closed(0.0, ERROR_UM.hi),
            "an eccentricity in µm (10 mm at most)",
        )?;
        ranged(
            file,
            &format!("effects.eccentricity.{which}.phase_deg"),
            s.phase_deg,
            PHASE_DEG,
            "a phase in degrees",
        )?;
        let (Some(ix), Some(iy)) = (lay.idx(&format!("x{g}")), lay.idx(&format!("y{g}"))) else {
            continue;
        };
        out.push(Box::new(UnbalanceTerm {
            label: format!("unbalance {which}(ρ = {} µm)", s.rho_um),
            idx: [ix, iy],
            m_rho: m * s.rho_um * 1e-6,
            omega: om,
            phase: s.phase_deg.to_radians(),
        }));
    }
    Ok(())
}

/// `effects.gravity`: the weight `m g` on every lateral DOF (x: g[0], y: g[1]), m/s².
pub(super) fn gravity(
    file: &str,
    gr: &GravitySpec,
    lay: &Layout,
    mass: &[f64],
) -> Result<Box<dyn ForceTerm>, SceneError> {
    for (k, g) in gr.g.iter().enumerate() {
        ranged(
            file,
            &format!("effects.gravity.g[{k}]"),
            *g,
            Span::symmetric(100.0),
            "an acceleration in m/s² (10 g at most)",
        )?;
    }
    let forces: Vec<(usize, f64)> = lay
        .names()
        .enumerate()
        .filter_map(|(i, n)| {
            if n.starts_with('x') {
                Some((i, mass[i] * gr.g[0]))
            } else if n.starts_with('y') {
                Some((i, mass[i] * gr.g[1]))
            } else {
                None
            }
        })
        .collect();
    Ok(Box::new(ConstantForce {
        label: format!("gravity(g = [{}, {}] m/s²)", gr.g[0], gr.g[1]),
        forces,
    }))
}
