//! Integration tests: the options structs of the analyses (orbit, dynamics, tolerance,
//! transplanter, simulate, synthesis) and of the outputs (STEP solids, animation) are built with
//! `with_*` and (de)serialised whole or in part — a missing field takes its default, an unknown
//! one is refused naming it.
use ncgear::analysis::dynamics::{AnalysisOptions, Method as Integrator, RunOptions};
use ncgear::analysis::orbit::evaluate::{MeasureOptions, SensorFrame};
use ncgear::analysis::orbit::measure::{ExtractOptions, Frame, Method};
use ncgear::analysis::orbit::model::{Line, LineKind};
use ncgear::analysis::peak::PeakOptions;
use ncgear::analysis::tolerance::ToleranceOptions;
use ncgear::analysis::transplanter::TransplanterOptions;
use ncgear::math::Point;
use ncgear::math::monte_carlo::McOptions;
use ncgear::simulate::FeatureOptions;
use ncgear::synthesis::DyadOptions;
use serde::Serialize;
use serde::de::DeserializeOwned;
use std::fmt::Debug;

/// `built` round-trips through JSON, `partial` (some of its fields) reads as `built`, and a
/// field `bogus` is refused with an error that names it.
fn round_trips<T: Serialize + DeserializeOwned + PartialEq + Debug>(built: &T, partial: &str) {
    let json = serde_json::to_string(built).unwrap();
    assert_eq!(&serde_json::from_str::<T>(&json).unwrap(), built, "{json}");
    assert_eq!(
        &serde_json::from_str::<T>(partial).unwrap(),
        built,
        "{partial}"
    );
    let err = serde_json::from_str::<T>(r#"{"bogus": 1}"#).unwrap_err();
    assert!(err.to_string().contains("unknown field `bogus`"), "{err}");
}

#[test]
fn orbit_options_round_trip() {
    let measure = MeasureOptions::default()
        .with_frame(SensorFrame::Housing)
        .with_carrier_speed_rpm(Some(300.0))
        .with_method(Method::HannDtft)
        .with_line_hz(vec![50.0]);
    round_trips(
        &measure,
        r#"{"frame": "housing", "carrier_speed_rpm": 300.0, "method": "hann_dtft",
            "line_hz": [50.0]}"#,
    );
    let extract = ExtractOptions::default()
        .with_frame(Frame::HousingFullSpectrum {
            carrier_rad_s: 31.5,
        })
        .with_nuisance(vec![Line::new("mesh", 100.0, LineKind::Nuisance)])
        .with_drift(false);
    round_trips(
        &extract,
        r#"{"frame": {"housing_full_spectrum": {"carrier_rad_s": 31.5}}, "drift": false,
            "nuisance": [{"label": "mesh", "omega_rad_s": 100.0, "kind": "nuisance"}]}"#,
    );
}

#[test]
fn dynamics_options_round_trip() {
    let run = RunOptions::default()
        .with_method(Integrator::Rk4 {
            steps_per_mesh: 64,
            aligned: true,
        })
        .with_max_periods(10);
    round_trips(
        &run,
        r#"{"method": {"rk4": {"steps_per_mesh": 64, "aligned": true}}, "max_periods": 10}"#,
    );
    let analysis = AnalysisOptions::default().with_sweep(Some(vec![0.8, 1.0]));
    round_trips(&analysis, r#"{"sweep": [0.8, 1.0]}"#);
}

#[test]
fn tolerance_options_round_trip() {
    let mc = McOptions::default().with_samples(1000).with_seed(7);
    round_trips(&mc, r#"{"samples": 1000, "seed": 7}"#);
    let peak = PeakOptions::default()
        .with_samples_per_min_period(16)
        .with_tol_relative(1e-10);
    round_trips(
        &peak,
        r#"{"samples_per_min_period": 16, "tol_relative": 1e-10}"#,
    );
    let tolerance = ToleranceOptions::default()
        .with_monte_carlo(None)
        .with_joint_starts(8)
        .with_peak(PeakOptions::default().with_refine_top(2));
    round_trips(
        &tolerance,
        r#"{"monte_carlo": null, "joint_starts": 8, "peak": {"refine_top": 2}}"#,
    );
}

#[test]
fn transplanter_options_round_trip() {
    let transplanter = TransplanterOptions::default()
        .with_mc(McOptions::default().with_samples(500))
        .with_starts(4)
        .with_features(FeatureOptions::default().with_rpm(250.0));
    round_trips(
        &transplanter,
        r#"{"mc": {"samples": 500}, "starts": 4, "features": {"rpm": 250.0}}"#,
    );
    // The finite-difference steps: by field, a missing one at its default, an unknown refused.
    let steps: TransplanterOptions =
        serde_json::from_str(r#"{"fd_steps": {"angle_rad": 2e-5}}"#).unwrap();
    let default = TransplanterOptions::default().fd_steps;
    assert_eq!(steps.fd_steps.angle_rad, 2e-5);
    assert_eq!(steps.fd_steps.length_mm, default.length_mm);
    let err =
        serde_json::from_str::<TransplanterOptions>(r#"{"fd_steps": {"length": 1}}"#).unwrap_err();
    assert!(err.to_string().contains("unknown field `length`"), "{err}");
}

#[test]
fn simulate_and_synthesis_options_round_trip() {
    let features = FeatureOptions::default()
        .with_rpm(250.0)
        .with_take_level_mm(Some(5.0));
    round_trips(&features, r#"{"rpm": 250.0, "take_level_mm": 5.0}"#);
    let dyads = DyadOptions::default()
        .with_center_mm(Some(Point::new(1.0, 2.0)))
        .with_samples(500);
    round_trips(&dyads, r#"{"center_mm": [1.0, 2.0], "samples": 500}"#);
}

/// The output options (STEP solids, the animation) like the analyses'.
#[test]
fn solid_and_animation_options_round_trip() {
    use ncgear::output::SolidOptions;
    use ncgear::output::animate::AnimationOptions;
    let solids = SolidOptions::default()
        .with_face_width_mm(Some(12.0))
        .with_bore_mm(8.0);
    round_trips(&solids, r#"{"face_width_mm": 12.0, "bore_mm": 8.0}"#);
    assert_eq!(solids.face_width_at(2.0), 12.0);
    let anim = AnimationOptions::default().with_seconds(3.0);
    round_trips(&anim, r#"{"seconds": 3.0}"#);
    assert_eq!((anim.frames, anim.outline_points), (360, 720));
}
