//! What the page draws, computed from a design: the traced path and each target point's
//! distance from it, the gears in their body frames (pitch curves, or the toothed outlines), both
//! arms over a turn, and the sun ratio. World frame, mm and degrees, as in the files.

use ncgear::design::Design;
use ncgear::design::train::ToothedTrain;
use ncgear::geometry::assembly::Pose;
use ncgear::geometry::pitch::PitchCurve;
use ncgear::math::Point;
use ncgear::math::polyline::distances_to_polyline;
use ncgear::simulate::{FeatureOptions, Features, Simulation, features};
use serde::Serialize;
use std::f64::consts::TAU;

/// Carrier positions of the posture table (every 2°).
const POSES: usize = 180;

/// Samples of a pitch curve and of the ratio plot.
const CURVE_SAMPLES: usize = 360;

/// The drawing data of one design (`view` in the answer of `POST /api/design`).
#[derive(Debug, Serialize, schemars::JsonSchema)]
pub struct View {
    /// Carrier axis O, mm.
    pub center_mm: Point,
    /// +1 CCW, −1 CW.
    pub direction: i8,
    /// Traced tip path (round trip), mm.
    pub traced_mm: Vec<Point>,
    /// Each target point's distance from the traced path, mm.
    pub deviation_mm: Vec<f64>,
    /// Gear outlines in their body frames, mm: `[sun, intermediate, planet]`.
    pub gears_mm: [Vec<Point>; 3],
    /// The outlines are toothed (a module was set).
    pub toothed: bool,
    /// Needle length l3, mm, and its angle γ in the planet's body frame, degrees.
    pub needle: [f64; 2],
    /// Both arms every 2° of carrier angle over a turn, in time order.
    pub poses: Vec<[ArmPose; 2]>,
    /// Sun ratio `[polar angle deg, i21]` over a turn.
    pub ratio: Vec<[f64; 2]>,
    /// The agronomic figures `ncgear simulate` reports, at the requested plant spacing (`None`
    /// when they cannot be computed for this path; the reason is in `features_error`).
    pub features: Option<Features>,
    /// Why `features` is missing.
    pub features_error: Option<String>,
}

/// One arm at one carrier angle.
#[derive(Debug, Clone, Copy, Serialize, schemars::JsonSchema)]
pub struct ArmPose {
    /// Carrier angle φH, degrees.
    pub phi_deg: f64,
    /// Intermediate centre, mm.
    pub intermediate_mm: Point,
    /// Planet centre A, mm.
    pub planet_mm: Point,
    /// Needle tip B, mm.
    pub tip_mm: Point,
    /// Intermediate orientation, degrees.
    pub intermediate_deg: f64,
    /// Planet orientation, degrees.
    pub planet_deg: f64,
}

impl From<Pose> for ArmPose {
    fn from(p: Pose) -> Self {
        Self {
            phi_deg: p.phi_h_rad.to_degrees(),
            intermediate_mm: p.intermediate_center_mm,
            planet_mm: p.planet_center_mm,
            tip_mm: p.tip_mm,
            intermediate_deg: p.intermediate_angle_rad.to_degrees(),
            planet_deg: p.planet_angle_rad.to_degrees(),
        }
    }
}

/// Carrier positions per turn of the agronomic figures (`ncgear simulate` takes 3600; the page
/// shows them to 0.1° and 0.1 mm).
const FEATURE_SAMPLES: usize = 1440;

/// The view of `design`, with `train`'s outlines when it has teeth; the agronomic figures at
/// `spacing_mm` (plant spacing, mm, two plants per carrier turn at `ncgear simulate`'s default
/// 300 r/min; `None`: its default forward speed).
pub fn view(design: &Design, train: Option<&ToothedTrain>, spacing_mm: Option<f64>) -> View {
    let sim = match train {
        Some(t) => Simulation::toothed(t),
        None => Simulation::new(design.assembly.clone()),
    };
    let asm = &sim.assembly;
    let body = |c: &PitchCurve| -> Vec<Point> {
        (0..CURVE_SAMPLES)
            .map(|k| c.point_mm(TAU * k as f64 / CURVE_SAMPLES as f64))
            .collect()
    };
    let gears_mm = sim
        .outlines
        .clone()
        .unwrap_or_else(|| [body(&asm.sun), body(&asm.intermediate), body(&asm.planet)]);
    let poses = (0..POSES)
        .map(|k| {
            let t = sim.pose(sim.angle_at(k as f64 / POSES as f64));
            [t.arm1.into(), t.arm2.into()]
        })
        .collect();
    let ratio = design.mechanism.ratio.clone();
    let defaults = FeatureOptions::default();
    let forward_mm_s = spacing_mm.map_or(defaults.forward_mm_s, |s| {
        FeatureOptions::forward_for_spacing(s, defaults.rpm)
    });
    let fopts = defaults
        .with_samples(FEATURE_SAMPLES)
        .with_forward_mm_s(forward_mm_s);
    let (features, features_error) = match features(&sim, &fopts) {
        Ok(f) => (Some(f), None),
        Err(e) => (None, Some(e.to_string())),
    };
    let traced = &design.traced_mm;
    View {
        center_mm: asm.center_mm,
        direction: asm.direction,
        traced_mm: traced.clone(),
        deviation_mm: distances_to_polyline(&design.report.target_points, traced),
        gears_mm,
        toothed: train.is_some(),
        needle: [asm.l3_mm, asm.needle_angle_rad.to_degrees()],
        poses,
        ratio: (0..CURVE_SAMPLES)
            .map(|k| {
                let t = TAU * k as f64 / CURVE_SAMPLES as f64;
                [t.to_degrees(), ratio.value(t)]
            })
            .collect(),
        features,
        features_error,
    }
}
