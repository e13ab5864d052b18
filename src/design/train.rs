//! The toothed planetary train: teeth on the designed sun, intermediate and planet pitch curves
//! (`ncgear design --module M`), with the tooth count made an integer, the mating phases, the mesh
//! verification of both meshes and the round trip of the final, scaled mechanism.
//!
//! Spec: design-chain §12 (12.1 tooth count, 12.3 mating phase, 12.4 undercut) on the conventions
//! of §2/§9 (the `design.json` conventions). Lengths in mm, angles in radians unless named `_deg`.
//!
//! # The two meshes as fixed-axis pairs
//! In the frame that turns with the carrier (x′ along O→D), at carrier angle φH:
//! - **sun → intermediate**: the sun (centre O, world orientation 0) turns by `φ = −φH`; the
//!   intermediate (centre D at `(a, 0)`) has orientation `θ2 − φH = −ψ`, so
//!   `ψ₁(φ) = φH − θ2(φH)` with `φH = −φ`;
//! - **intermediate → planet**: the intermediate (centre D) turns by `φ = θ2 − φH`; the planet
//!   (centre A at `(a, 0)` from D) has orientation `θ3 − φH`, so `ψ₂ = φH − θ3(φH)`.
//!
//! Both are the convention of [`crate::teeth::mesh::verify_mesh`] (driver CCW by φ, contact at
//! driver body angle −φ; driven CW by ψ, contact at driven body angle π + ψ).
//!
//! # Tooth count (§12.1)
//! The three pitch curves have the same perimeter L (equal tooth counts: one relative turn each per
//! carrier turn). `z` comes from `L/(πm)` with a [`ToothPolicy`]; the curves and the centre distance
//! are scaled by `s = zπm/L`. Uniform scaling keeps every ratio `r/(a − r)`, hence θ2(φH) and
//! θ3(φH); with `l3` and γ unchanged, every tip point moves radially by exactly `(s − 1)·l1`
//! (`l1 = 2a`) — the consequence reported as `radial_shift_mm`, and measured by the round trip.
//!
//! # Mating phase (§12.3)
//! Sun tooth 0 is centred on the contact with the intermediate at φH = 0 (sun body angle 0). For a
//! driver whose contact lies `δ` (arc, mm) ahead of a tooth centre, the driven tooth 0 is centred
//! at `s_n + δ + p/2` (`s_n` its contact arc position): a space faces the driver tooth. Every gear's
//! coast (smaller-s) flank is thinned by half the backlash, so the working flanks of both meshes
//! stay exactly conjugate.
use crate::design::Design;
use crate::export::{Contour, Marker, Sheet};
use crate::geometry::assembly::Assembly;
use crate::geometry::fourier::SunRatio;
use crate::geometry::mechanism::Mechanism;
use crate::geometry::pitch::{PitchCurve, PitchError};
use crate::math::periodic::{bisect_root, uniform_angles};
use crate::math::polyline::{distances_to_polyline, hausdorff_mm};
use crate::teeth::mesh::{MeshCheck, MeshError, MeshReport, verify_mesh};
use crate::teeth::{
    ArcFrame, Outline, OutlineOptions, RackParams, TeethError, ToothPolicy, UndercutReport,
    outline::generate_on, scale_curve, tooth_count,
};
use serde::Serialize;
use std::f64::consts::{PI, TAU};

/// Errors of [`tooth_train`].
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum TrainError {
    /// Teeth cannot be generated on one gear (undercut with the largest module that works,
    /// concave pitch arc, bad rack parameter).
    #[error("{gear}: {source}")]
    Teeth {
        /// `sun`, `intermediate` or `planet`.
        gear: &'static str,
        /// Cause.
        source: TeethError,
    },
    /// The mesh verification could not run.
    #[error("mesh {pair}: {source}")]
    Mesh {
        /// `sun-intermediate` or `intermediate-planet`.
        pair: &'static str,
        /// Cause.
        source: MeshError,
    },
    /// A scaled pitch curve is invalid.
    #[error(transparent)]
    Pitch(#[from] PitchError),
    /// An option is out of range.
    #[error("invalid option `{name}` = {value}: {expected}")]
    InvalidOption {
        /// Name.
        name: &'static str,
        /// Value.
        value: f64,
        /// Expectation.
        expected: &'static str,
    },
}

/// How the tooth count is made an integer (spec §12.1).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[non_exhaustive]
pub enum TrainPolicy {
    /// Option 1: scale the centre distance (and `l1`) by `zπm/L`, z by the rounding rule; every tip
    /// point moves radially by `(s − 1)·l1`.
    ScaleCenterDistance(ToothPolicy),
    /// Option 2: keep `a`, rescale the ratio amplitude `i_λ = 1 + λ(i21 − 1)` so that `L(λ) = zπm`
    /// (z the achievable count nearest to `L/(πm)`); needs the designed mechanism
    /// ([`tooth_design`]). The trajectory change is measured by the round trip.
    RatioAmplitude,
    /// Option 3: keep the gears, z = round(L/(πm)) and the module adjusted to `L/(zπ)` (a
    /// non-standard module; the trajectory is unchanged).
    AdjustModule,
}

/// Options of [`tooth_train`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct TrainTeethOptions {
    /// Module, mm.
    pub module_mm: f64,
    /// How z is made an integer.
    pub policy: TrainPolicy,
    /// Basic rack (α, ha*, c*, ρf*).
    pub rack: RackParams,
    /// Circumferential backlash of each mesh on the pitch curve, mm.
    pub backlash_mm: f64,
    /// Chord tolerance of the exported outlines, mm.
    pub chord_tol_mm: f64,
    /// Chord tolerance of the outlines used by the mesh verification, mm.
    pub verify_chord_tol_mm: f64,
    /// Carrier positions of the mesh verification per mesh (0 = skip).
    pub verify_steps: usize,
    /// Carrier positions of the round trip of the scaled mechanism.
    pub roundtrip_samples: usize,
}

impl TrainTeethOptions {
    /// Defaults at `module_mm`: 20° rack (ha* 1, c* 0.25, ρf* 0.38), scale the centre distance
    /// up, backlash 0.04·m, chord 1e-3·m (exports) and 1e-6·m (verification), 72 verified
    /// positions (every 5°), 3600 round-trip samples.
    #[must_use]
    pub fn new(module_mm: f64) -> Self {
        Self {
            module_mm,
            policy: TrainPolicy::ScaleCenterDistance(ToothPolicy::ScaleUp),
            rack: RackParams::default(),
            backlash_mm: 0.04 * module_mm,
            chord_tol_mm: 1e-3 * module_mm,
            verify_chord_tol_mm: 1e-6 * module_mm,
            verify_steps: 72,
            roundtrip_samples: 3600,
        }
    }
}

/// Undercut reports of the three gears.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TrainUndercut {
    /// Sun.
    pub sun: UndercutReport,
    /// Intermediate.
    pub intermediate: UndercutReport,
    /// Planet.
    pub planet: UndercutReport,
}

/// Mesh verification of both meshes over one carrier turn.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TrainMesh {
    /// Sun → intermediate.
    pub sun_intermediate: MeshReport,
    /// Intermediate → planet.
    pub intermediate_planet: MeshReport,
}

/// Round trip of the final (scaled) mechanism against the target trajectory.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct TrainRoundTrip {
    /// Max distance of the traced tip from the target polyline, mm (designed gears, before the
    /// tooth-count policy).
    pub before_max_deviation_mm: f64,
    /// Max distance of the traced tip from the target polyline, mm (final gears).
    pub max_deviation_mm: f64,
    /// Hausdorff distance traced ↔ target, mm (final gears).
    pub hausdorff_mm: f64,
    /// Max synchronous displacement of the tip by the tooth-count policy, mm (closed form
    /// `|s − 1|·l1` when scaling the centre distance).
    pub max_tip_shift_mm: f64,
}

/// The `teeth` block of `design.json`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TrainTeethReport {
    /// Options used.
    pub options: TrainTeethOptions,
    /// Tooth count of each gear (sun, intermediate, planet).
    pub z: u32,
    /// Module of the teeth, mm (the requested one, or the adjusted one with
    /// [`TrainPolicy::AdjustModule`]).
    pub module_mm: f64,
    /// Ratio amplitude factor λ of [`TrainPolicy::RatioAmplitude`] (1 otherwise).
    pub ratio_amplitude: f64,
    /// `L/(πm)` before scaling.
    pub z_raw: f64,
    /// Scale factor `s = zπm/L` applied to the curves and the centre distance.
    pub scale: f64,
    /// Pitch-curve perimeter after scaling (= zπm), mm.
    pub perimeter_mm: f64,
    /// Centre distance after scaling, mm.
    pub center_distance_mm: f64,
    /// `l1 = 2a` after scaling, mm.
    pub l1_mm: f64,
    /// Radial displacement of every tip point by the scaling, `(s − 1)·l1`, mm.
    pub radial_shift_mm: f64,
    /// Round trip of the final gears.
    pub roundtrip: TrainRoundTrip,
    /// Arc-length position of tooth 0's centre on each gear (sun, intermediate, planet), mm.
    pub phase_mm: [f64; 3],
    /// Undercut and concavity per gear.
    pub undercut: TrainUndercut,
    /// Mesh verification (absent when `verify_steps` = 0).
    pub mesh: Option<TrainMesh>,
    /// Files written (filled by the writer).
    pub files: Vec<String>,
}

/// The toothed train.
#[derive(Debug, Clone)]
pub struct ToothedTrain {
    /// Report (`design.json` → `teeth`).
    pub report: TrainTeethReport,
    /// The scaled assembly (final gears), world frame.
    pub assembly: Assembly,
    /// Sun outline, body frame (about O), export chord tolerance.
    pub sun: Outline,
    /// Intermediate outline, body frame (about its centre).
    pub intermediate: Outline,
    /// Planet outline, body frame (about its centre).
    pub planet: Outline,
}

fn scaled(asm: &Assembly, s: f64) -> Result<Assembly, PitchError> {
    Ok(Assembly {
        a_mm: asm.a_mm * s,
        sun: scale_curve(&asm.sun, s)?,
        intermediate: scale_curve(&asm.intermediate, s)?,
        planet: scale_curve(&asm.planet, s)?,
        ..asm.clone()
    })
}

/// Arc length (mm) from body angle 0 to `theta` (CCW, wrapped to `[0, 2π)`).
fn arc_at(curve: &PitchCurve, theta: f64, accuracy_mm: f64) -> f64 {
    curve.arc_length_between_mm(0.0, theta.rem_euclid(TAU), accuracy_mm)
}

fn max_tip_distance(traced: &[[f64; 2]], target: &[[f64; 2]]) -> f64 {
    distances_to_polyline(traced, target)
        .into_iter()
        .fold(0.0, f64::max)
}

/// Puts teeth on an assembled train (world frame, as read from `design.json`): integer tooth
/// count by scaling, rack-generated outlines with mating phases, undercut reports, the mesh
/// verification of both meshes (`progress(1)` per verified position, `2·verify_steps` in all) and
/// the round trip of the scaled mechanism against `target_mm` (the trajectory, world frame).
///
/// Errors: [`TrainError::Teeth`] naming the gear (undercut with the largest module that works,
/// concave arc), [`TrainError::InvalidOption`].
pub fn tooth_train(
    asm: &Assembly,
    target_mm: &[[f64; 2]],
    opts: &TrainTeethOptions,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<ToothedTrain, TrainError> {
    train_from(asm, None, target_mm, opts, progress)
}

/// [`tooth_train`] on a fresh design, with every policy of §12.1 including
/// [`TrainPolicy::RatioAmplitude`] (which rebuilds the mechanism with `i_λ = 1 + λ(i21 − 1)`, the
/// same `a`, `l3` and γ, and `accuracy_mm` on the perimeter equation `L(λ) = zπm`).
pub fn tooth_design(
    design: &Design,
    opts: &TrainTeethOptions,
    accuracy_mm: f64,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<ToothedTrain, TrainError> {
    let target = &design.report.target_points;
    if opts.policy != TrainPolicy::RatioAmplitude {
        return tooth_train(&design.assembly, target, opts, progress);
    }
    let n = design.assembly.sun.len();
    let fit = rescale_ratio_amplitude(&design.mechanism, opts.module_mm, n, accuracy_mm)?;
    let asm = Assembly::from_mechanism(
        &fit.mechanism,
        design.assembly.center_mm,
        design.assembly.direction,
        n,
    )?;
    let exact = TrainTeethOptions {
        policy: TrainPolicy::ScaleCenterDistance(ToothPolicy::Exact(fit.z)),
        ..*opts
    };
    let mut train = train_from(&asm, Some(&design.assembly), target, &exact, progress)?;
    train.report.options.policy = TrainPolicy::RatioAmplitude;
    train.report.ratio_amplitude = fit.lambda;
    Ok(train)
}

/// Result of [`rescale_ratio_amplitude`].
#[derive(Debug, Clone, PartialEq)]
pub struct AmplitudeFit {
    /// The mechanism with the rescaled ratio (same `a`, `l3`, γ, sun phase).
    pub mechanism: Mechanism,
    /// Tooth count.
    pub z: u32,
    /// Amplitude factor λ.
    pub lambda: f64,
    /// Sun perimeter `L(λ)` (= zπm to `accuracy_mm`), mm.
    pub perimeter_mm: f64,
}

fn with_amplitude(mech: &Mechanism, lambda: f64) -> Mechanism {
    let k = |v: &[f64]| v.iter().map(|x| x * lambda).collect::<Vec<_>>();
    Mechanism {
        ratio: SunRatio::new_unchecked(
            k(mech.ratio.cos_coefficients()),
            k(mech.ratio.sin_coefficients()),
        ),
        ..mech.clone()
    }
}

/// Spec §12.1 option 2: the amplitude λ of `i_λ = 1 + λ(i21 − 1)` with `a` held fixed such that
/// the sun perimeter `L(λ) = zπm`, z the achievable integer nearest to `L(1)/(πm)`.
///
/// `L(λ)` is sampled on `λ ∈ [0, λmax]` (`λmax` keeps `i_λ ≥ 0.05` and ≤ 4); the bracket
/// nearest to λ = 1 is refined by bisection to `accuracy_mm` in L. `L(0) = πa` (circle).
/// Errors: no integer z is achievable in that range (module too large for the curve).
pub fn rescale_ratio_amplitude(
    mech: &Mechanism,
    module_mm: f64,
    samples: usize,
    accuracy_mm: f64,
) -> Result<AmplitudeFit, TrainError> {
    let perimeter = |lambda: f64| -> Result<f64, TrainError> {
        Ok(with_amplitude(mech, lambda)
            .sun_curve(samples)?
            .perimeter_mm(0.1 * accuracy_mm))
    };
    let grid = 64;
    let (i_min, _) = mech
        .ratio
        .sampled_extreme(64 * mech.ratio.order() + 256, false);
    let lambda_max = if i_min < 1.0 {
        (0.95 / (1.0 - i_min)).min(4.0)
    } else {
        4.0
    };
    let lambdas: Vec<f64> = (0..=grid)
        .map(|k| lambda_max * k as f64 / f64::from(grid))
        .collect();
    let ls: Vec<f64> = lambdas
        .iter()
        .map(|&l| perimeter(l))
        .collect::<Result<_, _>>()?;
    let pm = PI * module_mm;
    let z_raw = perimeter(1.0)? / pm;
    // Candidate z values, nearest first; take the first with a bracket, nearest to λ = 1.
    let mut candidates: Vec<f64> = (0..40)
        .flat_map(|k| {
            [
                z_raw.round() + f64::from(k),
                z_raw.round() - f64::from(k + 1),
            ]
        })
        .filter(|z| *z >= 3.0)
        .collect();
    candidates.sort_by(|x, y| (x - z_raw).abs().total_cmp(&(y - z_raw).abs()));
    for z in candidates {
        let target = z * pm;
        let best = lambdas
            .windows(2)
            .zip(ls.windows(2))
            .filter(|(_, l)| (l[0] - target) * (l[1] - target) <= 0.0)
            .min_by(|(x, _), (y, _)| {
                (0.5 * (x[0] + x[1]) - 1.0)
                    .abs()
                    .total_cmp(&(0.5 * (y[0] + y[1]) - 1.0).abs())
            });
        if let Some((lam, _)) = best {
            // A failing sample (cannot happen for i_λ ≥ 0.05) reads as NaN and is caught below.
            let lambda = bisect_root(
                |l| perimeter(l).map_or(f64::NAN, |v| v - target),
                lam[0],
                lam[1],
                1e-14,
            );
            let mechanism = with_amplitude(mech, lambda);
            let perimeter_mm = mechanism
                .sun_curve(samples)?
                .perimeter_mm(0.1 * accuracy_mm);
            return Ok(AmplitudeFit {
                mechanism,
                z: z as u32,
                lambda,
                perimeter_mm,
            });
        }
    }
    Err(TrainError::InvalidOption {
        name: "module_mm",
        value: module_mm,
        expected: "a module for which some integer tooth count is reachable by rescaling the \
                   ratio amplitude (L(λ) ranges between the circle πa and the largest amplitude)",
    })
}

fn train_from(
    asm: &Assembly,
    designed: Option<&Assembly>,
    target_mm: &[[f64; 2]],
    opts: &TrainTeethOptions,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<ToothedTrain, TrainError> {
    let m = opts.module_mm;
    for (name, v) in [
        ("module_mm", m),
        ("backlash_mm", opts.backlash_mm),
        ("chord_tol_mm", opts.chord_tol_mm),
        ("verify_chord_tol_mm", opts.verify_chord_tol_mm),
    ] {
        if !(v.is_finite() && v > 0.0) {
            return Err(TrainError::InvalidOption {
                name,
                value: v,
                expected: "finite and > 0",
            });
        }
    }
    if opts.roundtrip_samples < 16 {
        return Err(TrainError::InvalidOption {
            name: "roundtrip_samples",
            value: opts.roundtrip_samples as f64,
            expected: "≥ 16",
        });
    }
    let teeth_err = |gear: &'static str| move |source| TrainError::Teeth { gear, source };
    let (rounding, adjust) = match opts.policy {
        TrainPolicy::ScaleCenterDistance(p) => (p, false),
        TrainPolicy::AdjustModule => (ToothPolicy::Nearest, true),
        TrainPolicy::RatioAmplitude => {
            return Err(TrainError::InvalidOption {
                name: "policy",
                value: f64::NAN,
                expected: "scale-centre-distance or adjust-module here; the ratio-amplitude \
                           policy needs the designed mechanism (tooth_design)",
            });
        }
    };
    let count = tooth_count(&asm.sun, m, rounding, 1e-10 * asm.a_mm).map_err(teeth_err("sun"))?;
    let (s, m) = if adjust {
        (1.0, count.perimeter_mm / (f64::from(count.z) * PI))
    } else {
        (count.scale, m)
    };
    let fin = scaled(asm, s)?;
    let a = fin.a_mm;
    let acc = 1e-12 * a;
    let rebuilt = fin.rebuild();
    let pose0 = rebuilt.pose(0.0);
    let (th2_0, th3_0) = (pose0.intermediate_angle_rad, pose0.planet_angle_rad);

    let frames = [
        ArcFrame::new(&fin.sun),
        ArcFrame::new(&fin.intermediate),
        ArcFrame::new(&fin.planet),
    ];
    let p = frames[0].length_mm() / f64::from(count.z);
    // Mating phases at φH = 0 (module doc).
    let phase_sun = 0.0;
    let s_mid_sun = arc_at(&fin.intermediate, PI - th2_0, acc);
    let phase_mid = s_mid_sun + 0.5 * p;
    let s_mid_planet = arc_at(&fin.intermediate, -th2_0, acc);
    let delta = (s_mid_planet - phase_mid).rem_euclid(p);
    let s_planet = arc_at(&fin.planet, PI - th3_0, acc);
    let phase_planet = s_planet + delta + 0.5 * p;
    let phases = [phase_sun, phase_mid, phase_planet];
    let names = ["sun", "intermediate", "planet"];

    let generate = |k: usize, tol: f64| {
        generate_on(
            &frames[k],
            &opts.rack,
            count.z,
            m,
            &OutlineOptions {
                phase_mm: phases[k],
                thin_left_mm: 0.5 * opts.backlash_mm,
                thin_right_mm: 0.0,
                chord_tol_mm: tol,
            },
        )
        .map_err(teeth_err(names[k]))
    };
    let sun = generate(0, opts.chord_tol_mm)?;
    let intermediate = generate(1, opts.chord_tol_mm)?;
    let planet = generate(2, opts.chord_tol_mm)?;

    let mesh = if opts.verify_steps > 0 {
        let fine: Vec<Outline> = (0..3)
            .map(|k| generate(k, opts.verify_chord_tol_mm))
            .collect::<Result<_, _>>()?;
        let check = MeshCheck {
            centre_distance_mm: a,
            steps: opts.verify_steps,
            backlash_mm: opts.backlash_mm,
            module_mm: m,
            angle_tol_rad: 1e-13,
        };
        let theta2 = |phi_h: f64| rebuilt.pose(phi_h).intermediate_angle_rad;
        // Sun → intermediate: φ = −φH.
        let psi1 = |phi: f64| -phi - theta2(-phi);
        let sun_intermediate = verify_mesh(
            &fine[0].points_mm,
            &fine[1].points_mm,
            &psi1,
            &check,
            progress,
        )
        .map_err(|source| TrainError::Mesh {
            pair: "sun-intermediate",
            source,
        })?;
        // Intermediate → planet: φ = θ2(φH) − φH, increasing in φH; invert by bisection.
        let phi2 = |phi_h: f64| theta2(phi_h) - phi_h;
        let phi2_0 = phi2(0.0);
        let psi2 = |phi: f64| {
            let guess = phi - phi2_0;
            let phi_h = bisect_root(|x| phi2(x) - phi, guess - 16.0, guess + 16.0, 1e-15);
            let pose = rebuilt.pose(phi_h);
            phi_h - pose.planet_angle_rad
        };
        let intermediate_planet = verify_mesh(
            &fine[1].points_mm,
            &fine[2].points_mm,
            &psi2,
            &check,
            progress,
        )
        .map_err(|source| TrainError::Mesh {
            pair: "intermediate-planet",
            source,
        })?;
        Some(TrainMesh {
            sun_intermediate,
            intermediate_planet,
        })
    } else {
        None
    };

    // Round trip of the final gears (and of the unscaled ones, for the comparison).
    let n = opts.roundtrip_samples;
    let before = designed.unwrap_or(asm).rebuild().traced(n);
    let after = rebuilt.traced(n);
    let shift = before
        .iter()
        .zip(&after)
        .map(|(p, q)| (p[0] - q[0]).hypot(p[1] - q[1]))
        .fold(0.0, f64::max);
    let roundtrip = TrainRoundTrip {
        before_max_deviation_mm: max_tip_distance(&before, target_mm),
        max_deviation_mm: max_tip_distance(&after, target_mm),
        hausdorff_mm: hausdorff_mm(&after, target_mm),
        max_tip_shift_mm: shift,
    };
    let report = TrainTeethReport {
        options: *opts,
        z: count.z,
        module_mm: m,
        ratio_amplitude: 1.0,
        z_raw: count.z_raw,
        scale: s,
        perimeter_mm: frames[0].length_mm(),
        center_distance_mm: a,
        l1_mm: 2.0 * a,
        radial_shift_mm: (s - 1.0) * 2.0 * asm.a_mm,
        roundtrip,
        phase_mm: phases,
        undercut: TrainUndercut {
            sun: sun.undercut.clone(),
            intermediate: intermediate.undercut.clone(),
            planet: planet.undercut.clone(),
        },
        mesh,
        files: Vec::new(),
    };
    Ok(ToothedTrain {
        report,
        assembly: fin,
        sun,
        intermediate,
        planet,
    })
}

/// Places body-frame points at `centre` rotated by `angle` (rad).
fn place(points: &[[f64; 2]], centre: [f64; 2], angle: f64) -> Vec<[f64; 2]> {
    let (s, c) = angle.sin_cos();
    points
        .iter()
        .map(|p| {
            [
                centre[0] + c * p[0] - s * p[1],
                centre[1] + s * p[0] + c * p[1],
            ]
        })
        .collect()
}

fn pitch_polyline(curve: &PitchCurve) -> Vec<[f64; 2]> {
    uniform_angles(1440)
        .iter()
        .map(|&t| curve.point_mm(t))
        .collect()
}

fn contour(name: &str, layer: &str, points_mm: Vec<[f64; 2]>) -> Contour {
    Contour {
        name: name.into(),
        layer: layer.into(),
        points_mm,
        closed: true,
    }
}

/// Which gear of the train.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum Gear {
    /// The fixed sun (centre O).
    Sun,
    /// The intermediate gear (centre D).
    Intermediate,
    /// The planet gear (centre A, carries the needle).
    Planet,
}

impl Gear {
    /// The three gears in train order.
    pub const ALL: [Gear; 3] = [Gear::Sun, Gear::Intermediate, Gear::Planet];

    /// Lower-case name (`sun`, `intermediate`, `planet`).
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Gear::Sun => "sun",
            Gear::Intermediate => "intermediate",
            Gear::Planet => "planet",
        }
    }
}

impl ToothedTrain {
    fn parts(&self, gear: Gear) -> (&Outline, &PitchCurve) {
        match gear {
            Gear::Sun => (&self.sun, &self.assembly.sun),
            Gear::Intermediate => (&self.intermediate, &self.assembly.intermediate),
            Gear::Planet => (&self.planet, &self.assembly.planet),
        }
    }

    /// One gear in its body frame (rotation centre at the origin), for manufacturing: layers
    /// `<GEAR>_OUTLINE`, `<GEAR>_PITCH`, `CENTRES`.
    #[must_use]
    pub fn gear_sheet(&self, gear: Gear) -> Sheet {
        let (o, c) = self.parts(gear);
        let up = gear.name().to_uppercase();
        Sheet {
            contours: vec![
                contour(
                    &format!("{}_outline", gear.name()),
                    &format!("{up}_OUTLINE"),
                    o.points_mm.clone(),
                ),
                contour(
                    &format!("{}_pitch", gear.name()),
                    &format!("{up}_PITCH"),
                    pitch_polyline(c),
                ),
            ],
            markers: vec![Marker {
                name: format!("{}_centre", gear.name()),
                layer: "CENTRES".into(),
                at_mm: [0.0, 0.0],
            }],
        }
    }

    /// The whole train at carrier angle `phi_h_rad`, world frame (mm): every gear's outline and
    /// pitch curve placed at its centre and orientation, the centres O, D, A and the needle tip.
    #[must_use]
    pub fn sheet(&self, phi_h_rad: f64) -> Sheet {
        let pose = self.assembly.rebuild().pose(phi_h_rad);
        let o = self.assembly.center_mm;
        let at = [
            (o, 0.0),
            (pose.intermediate_center_mm, pose.intermediate_angle_rad),
            (pose.planet_center_mm, pose.planet_angle_rad),
        ];
        let mut sheet = Sheet::default();
        for (gear, (centre, angle)) in Gear::ALL.into_iter().zip(at) {
            let body = self.gear_sheet(gear);
            for c in body.contours {
                sheet.contours.push(Contour {
                    points_mm: place(&c.points_mm, centre, angle),
                    ..c
                });
            }
            sheet.markers.push(Marker {
                name: format!("{}_centre", gear.name()),
                layer: "CENTRES".into(),
                at_mm: centre,
            });
        }
        sheet.markers.push(Marker {
            name: "needle_tip".into(),
            layer: "CENTRES".into(),
            at_mm: pose.tip_mm,
        });
        sheet
    }
}
