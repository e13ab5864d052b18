//! Scene → model: the DOF set the named effects need (docs/math/companion.md §B.10 pruning: 16 / 6 / 4 / 2 / 1), the
//! diagonal mass, the shared mesh kernel and the force-term list, in the run log's order (mesh,
//! load, friction, shafts, bearings, eccentricity, gravity).

use super::layout::Layout;
use super::terms::{self, BearingLaw};
use super::{Derived, DofSet, Effects, Scene, SceneError, invalid, mesh};
use crate::analysis::dynamics::model::{
    DOF_NAMES, ForceTerm, MeshCore, MeshTerm, Model, StiffnessLaw,
};
use std::f64::consts::PI;
use std::sync::Arc;

/// Which DOF families the effects need.
struct Needs {
    /// Motor and load inertias θp, θq (shafts named).
    shafts: bool,
    /// Bearings with a stiffness (not rigid).
    soft_bearings: bool,
    /// y (line of action) of the gear centres.
    lateral: bool,
    /// x (perpendicular) of the gear centres as well.
    with_x: bool,
    /// The SDOF relative coordinate `u` suffices.
    sdof: bool,
}

/// Decides the DOF families: lateral DOFs exist with shaft bending or soft bearings; x is kept
/// when something forces it (friction, eccentricity, horizontal gravity, Hertz bearings) or with
/// `dofs = "full"`; without shafts, lateral DOFs or friction the model is the SDOF `u`.
fn needs(file: &str, e: &Effects, law: BearingLaw, full: bool) -> Result<Needs, SceneError> {
    let shafts = e.shafts.as_ref();
    let soft_bearings = law != BearingLaw::Rigid;
    if shafts.is_some_and(|s| s.ks.is_none()) && soft_bearings {
        return Err(invalid(
            file,
            "effects.shafts.ks",
            "missing".into(),
            "bending stiffnesses [ks1, ks2] in N/m (required with non-rigid bearings)",
        ));
    }
    let lateral = shafts.is_some_and(|s| s.ks.is_some()) || soft_bearings;
    let x_forced = e.friction.is_some()
        || e.eccentricity.is_some()
        || e.gravity.as_ref().is_some_and(|g| g.g[0] != 0.0)
        || matches!(law, BearingLaw::Hertz { .. });
    if !lateral {
        for (key, set) in [
            ("effects.eccentricity", e.eccentricity.is_some()),
            ("effects.gravity", e.gravity.is_some()),
        ] {
            if set {
                return Err(invalid(
                    file,
                    key,
                    "set".into(),
                    "lateral DOFs: add effects.bearings (non-rigid) or effects.shafts",
                ));
            }
        }
    }
    Ok(Needs {
        shafts: shafts.is_some(),
        soft_bearings,
        lateral,
        with_x: lateral && (x_forced || full),
        sdof: !lateral && shafts.is_none() && e.friction.is_none(),
    })
}

/// The kept DOFs (indices into [`DOF_NAMES`], in its order).
fn select_dofs(n: &Needs) -> Vec<usize> {
    if n.sdof {
        return vec![16];
    }
    let bearing_masses = n.shafts && n.soft_bearings;
    (0..16)
        .filter(|&i| match DOF_NAMES[i] {
            "theta_p" | "theta_q" => n.shafts,
            "theta1" | "theta2" => true,
            "x1" | "x2" => n.with_x,
            "y1" | "y2" => n.lateral,
            name if name.starts_with("xb") => bearing_masses && n.with_x,
            name if name.starts_with("yb") => bearing_masses,
            _ => false,
        })
        .collect()
}

/// Diagonal mass of each kept DOF: inertias (kg·m²) for rotations, masses (kg) for translations,
/// m_e for `u`.
fn masses(scene: &Scene, lay: &Layout, d: &Derived) -> Vec<f64> {
    let shafts = scene.effects.shafts.as_ref();
    let [m1, m2] = d.mass_kg;
    let [j1, j2] = d.inertia_kgm2;
    lay.names()
        .map(|name| match name {
            "theta_p" => shafts.map_or(0.0, |s| s.j_kgm2[0]),
            "theta_q" => shafts.map_or(0.0, |s| s.j_kgm2[1]),
            "x1" | "y1" => m1,
            "x2" | "y2" => m2,
            "theta1" => j1,
            "theta2" => j2,
            "u" => d.m_e_kg,
            n => {
                let b: usize = n[2..].parse().unwrap_or(1);
                shafts.map_or(1.0, |s| s.mb_kg[b - 1])
            }
        })
        .collect()
}

/// The shared mesh kernel: deflection `(y1−y2) + rb1θ1 − rb2θ2` (or `u`), stiffness law, STE,
/// backlash and tip relief.
fn mesh_core(scene: &Scene, file: &str, lay: &Layout, d: &Derived) -> Result<MeshCore, SceneError> {
    let e = &scene.effects;
    let geom = d.geometry;
    let [rb1, rb2] = geom.rb_m;
    let coeffs: Vec<(usize, f64)> = if lay.sdof {
        vec![(0, 1.0)]
    } else {
        [("y1", 1.0), ("y2", -1.0), ("theta1", rb1), ("theta2", -rb2)]
            .iter()
            .filter_map(|&(n, c)| lay.idx(n).map(|i| (i, c)))
            .collect()
    };
    let ste = e
        .static_te
        .as_ref()
        .map(|s| mesh::static_te(file, s))
        .transpose()?;
    let backlash = e
        .backlash
        .as_ref()
        .map(|b| mesh::backlash(file, b))
        .transpose()?;
    let relief = e
        .tip_relief
        .as_ref()
        .map(|r| mesh::tip_relief(file, r, &geom))
        .transpose()?;
    let law = mesh::stiffness_law(file, scene.mesh_spec(file)?, geom.contact_ratio)?;
    Ok(MeshCore {
        coeffs,
        law,
        c_m: d.c_m_n_s_per_m,
        t0: d.t_mesh_s,
        eps: geom.contact_ratio,
        omega_e: d.omega_e_rad_s,
        ste,
        backlash,
        relief,
        contact_length: geom.contact_ratio * geom.base_pitch_m,
        per_pair: relief.is_some() || e.friction.is_some() || matches!(law, StiffnessLaw::Pairs(_)),
    })
}

fn gcd(a: u32, b: u32) -> u32 {
    if b == 0 { a } else { gcd(b, a % b) }
}

fn lcm(a: u32, b: u32) -> u32 {
    a / gcd(a, b) * b
}

impl Scene {
    /// Builds the model: DOF pruning (16 / 6 / 4 / 2 / 1), term list, derived parameters.
    ///
    /// # Errors
    /// [`SceneError::Invalid`] naming the key of the first bad value.
    pub fn build(&self, file: &str) -> Result<(Model, Derived), SceneError> {
        let d = self.derived(file)?;
        let e = &self.effects;
        let (law, cb) = terms::bearing_law(file, e.bearings.as_ref())?;
        if let Some(s) = &e.shafts {
            terms::check_shafts(file, s)?;
        }
        let needs = needs(file, e, law, self.scene.dofs == DofSet::Full)?;
        let lay = Layout {
            dofs: select_dofs(&needs),
            sdof: needs.sdof,
            omega: [
                d.omega_e_rad_s / f64::from(self.gears.z1),
                d.omega_e_rad_s / f64::from(self.gears.z2),
            ],
        };
        let mass = masses(self, &lay, &d);
        let core = Arc::new(mesh_core(self, file, &lay, &d)?);
        let mut list: Vec<Box<dyn ForceTerm>> = vec![Box::new(MeshTerm { core: core.clone() })];
        list.push(terms::load(
            &lay,
            &d,
            self.operating.input_torque_Nm,
            needs.shafts,
        ));
        if let Some(f) = &e.friction {
            list.push(terms::friction(file, f, &lay, &core, &d)?);
        }
        if let Some(s) = &e.shafts {
            terms::shafts(s, &lay, &mut list);
        }
        terms::bearings(law, cb, needs.shafts, &lay, &mut list);
        if let Some(ecc) = &e.eccentricity {
            terms::eccentricity(file, ecc, &lay, &d, &mut list)?;
        }
        if let Some(g) = &e.gravity {
            list.push(terms::gravity(file, g, &lay, &mass)?);
        }
        // with eccentricity the motion repeats after the hunting period lcm(z1, z2) mesh periods
        let hunting = if e.eccentricity.is_some() {
            f64::from(lcm(self.gears.z1, self.gears.z2))
        } else {
            1.0
        };
        // Hertz bearings: 20 steps per ball-passing period 2π/(Nb ω1 ratio)
        let max_step = match law {
            BearingLaw::Hertz { nb, ratio, .. } => {
                2.0 * PI / (f64::from(nb) * lay.omega[0] * ratio) / 20.0
            }
            _ => f64::INFINITY,
        };
        let model = Model {
            dofs: lay.dofs,
            mass,
            terms: list,
            mesh: core,
            omega: lay.omega,
            poincare_period: d.t_mesh_s * hunting,
            max_step,
        };
        Ok((model, d))
    }
}
