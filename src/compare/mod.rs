//! A filmed needle-tip track registered to the static path of the design it was built from, and
//! compared with it (`ncgear compare`, docs/compare.md).
//!
//! The chain: [`track`] reads the frames (plain CSV, Tracker, Kinovea; s, ms or frames; mm, cm,
//! m or px) → the scale (given by the units, `px_per_mm`, a two-point calibration, or fitted)
//! and the axes (image y down flipped, an optional mirror) → [`initial`] finds the period and a
//! starting transform and phase → [`register`] fits the similarity and the timing robustly
//! (outlier frames flagged, standard errors) → [`figures`] gives the smooth deviation `d(φ)` by
//! carrier angle and the agronomic figures of [`crate::simulate`] on the track beside the
//! design's, each whole turn and their spread → [`report::CompareReport`]; [`crate::output::compare_plot`] draws it.

pub mod args;
pub mod design_path;
pub mod dynamic;
mod error;
pub mod figures;
pub mod initial;
pub mod period;
pub mod register;
pub mod report;
pub mod smooth;
pub mod track;

pub use error::CompareError;
pub use report::CompareReport;
pub use track::{LengthUnit, ReadOptions, Track, parse_track};

use crate::geometry::assembly::Rebuilt;
use crate::math::Point;
use crate::simulate::FeatureOptions;
use design_path::DesignPath;
use figures::SmoothPath;
use register::FitOptions;
use report::{Estimate, RegistrationReport, TrackSummary, TurnReport};
use std::f64::consts::TAU;

/// How the track's lengths become mm.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Scale {
    /// The file's unit (mm, cm, m; pixels are refused).
    Units,
    /// Pixels per mm.
    PxPerMm(f64),
    /// Two points of the image (track units and axes as in the file) `distance_mm` apart.
    Calibration {
        /// First point.
        p1: Point,
        /// Second point.
        p2: Point,
        /// Their distance, mm.
        distance_mm: f64,
    },
    /// Fitted to the design (absorbs any size error of the built mechanism).
    Fit,
}

/// Options of a comparison.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CompareOptions {
    /// The scale.
    pub scale: Scale,
    /// Mirror the track (`x → −x`): filmed from the other side of the arm.
    pub mirror: bool,
    /// The carrier speed, rpm (default: found from the frames' period).
    pub rpm: Option<f64>,
    /// The carrier axis as filmed (track units and axes): pins the translation.
    pub carrier_axis: Option<Point>,
    /// The rotation from the track's axes (flipped and mirrored) to the design's, rad, when known
    /// (the image levelled, or a level line in it): pins the rotation.
    pub rotation_rad: Option<f64>,
    /// Highest power D of the timing drift (1: constant speed; ≤ 6). Default 3.
    pub drift_order: usize,
    /// Order K of the smooth deviation (2..=40); default `None`: chosen from the frames by
    /// [`smooth::bic_order`] within `2..=`[`MAX_CHOSEN_ORDER`] (the registration's own smooth
    /// model of the deviation then has order [`MAX_CHOSEN_ORDER`]).
    pub smooth_order: Option<usize>,
    /// Outlier threshold, in σ of the frames' noise. Default 4.5.
    pub outlier_sigma: f64,
    /// Forward speed and depth for the agronomic figures (their `rpm` is the record's).
    pub features: FeatureOptions,
    /// Plant spacing, mm: sets the forward speed at the record's carrier speed (two plants per
    /// turn), overriding `features.forward_mm_s`.
    pub spacing_mm: Option<f64>,
}

impl Default for CompareOptions {
    fn default() -> Self {
        Self {
            scale: Scale::Units,
            mirror: false,
            rpm: None,
            carrier_axis: None,
            rotation_rad: None,
            drift_order: 3,
            smooth_order: None,
            outlier_sigma: 4.5,
            features: FeatureOptions::default(),
            spacing_mm: None,
        }
    }
}

/// The highest order of the smooth deviation chosen from the frames, and the order of the
/// registration's smooth model of it when none is given.
pub const MAX_CHOSEN_ORDER: usize = 8;

/// One frame as registered.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frame {
    /// Line of the track file.
    pub line: usize,
    /// Time, s.
    pub time_s: f64,
    /// Carrier angle, rad (unwrapped).
    pub phi_rad: f64,
    /// Registered tip, mm (design frame).
    pub q_mm: Point,
    /// `q − B(φ)`, mm.
    pub residual_mm: Point,
    /// The smooth deviation `d(φ)` at its carrier angle, mm.
    pub smooth_mm: Point,
    /// Flagged as an outlier.
    pub outlier: bool,
}

/// A comparison: the report and the frames.
#[derive(Debug, Clone)]
pub struct Comparison {
    /// The report.
    pub report: CompareReport,
    /// Every frame.
    pub frames: Vec<Frame>,
    /// The design path at [`figures::TURN_SAMPLES`] carrier angles, mm.
    pub design_mm: Vec<Point>,
}

fn bad(option: &'static str, message: String) -> CompareError {
    CompareError::BadOption { option, message }
}

/// Checks the options and gives the scale in mm per track unit (`None`: fitted).
fn scale_of(track: &Track, opts: &CompareOptions) -> Result<Option<f64>, CompareError> {
    if !(1..=6).contains(&opts.drift_order) {
        return Err(bad(
            "drift-order",
            format!("{}: expected 1..=6", opts.drift_order),
        ));
    }
    if let Some(k) = opts.smooth_order
        && !(2..=40).contains(&k)
    {
        return Err(bad("smooth-order", format!("{k}: expected 2..=40")));
    }
    if !(opts.outlier_sigma.is_finite() && opts.outlier_sigma >= 2.0) {
        return Err(bad(
            "outlier-sigma",
            format!("{}: expected ≥ 2", opts.outlier_sigma),
        ));
    }
    if let Some(r) = opts.rpm
        && !(r.is_finite() && r > 0.0)
    {
        return Err(bad(
            "rpm",
            format!("{r}: expected a positive carrier speed"),
        ));
    }
    match opts.scale {
        Scale::Units => track
            .unit
            .mm()
            .map(Some)
            .ok_or_else(|| CompareError::PixelsWithoutScale {
                file: track.file.clone(),
            }),
        Scale::PxPerMm(s) if s.is_finite() && s > 0.0 => Ok(Some(1.0 / s)),
        Scale::PxPerMm(s) => Err(bad("px-per-mm", format!("{s}: expected a positive scale"))),
        Scale::Calibration {
            p1,
            p2,
            distance_mm,
        } => {
            let d = p1.distance(p2);
            if !(distance_mm.is_finite() && distance_mm > 0.0 && d.is_finite() && d > 0.0) {
                return Err(bad(
                    "calibration",
                    "expected x1,y1,x2,y2,dist_mm: two distinct image points and their distance in mm > 0".into(),
                ));
            }
            Ok(Some(distance_mm / d))
        }
        Scale::Fit => Ok(None),
    }
}

/// Registers `track` to the design path of `rebuilt` and compares them.
///
/// # Errors
/// [`CompareError`]: a bad option, pixels without a scale, less than a turn of frames, a track
/// that runs the other way round or is far off the design's size; [`CompareError::NoFit`] when
/// the fit fails.
pub fn compare(
    track: &Track,
    rebuilt: &Rebuilt,
    opts: &CompareOptions,
) -> Result<Comparison, CompareError> {
    compare_to_path(track, &DesignPath::new(rebuilt), opts)
}

/// [`compare`] against the reference path `path` (the design's static path, or the dynamic
/// path of [`dynamic::against_dynamics`]).
///
/// # Errors
/// As [`compare`].
pub fn compare_to_path(
    track: &Track,
    path: &DesignPath,
    opts: &CompareOptions,
) -> Result<Comparison, CompareError> {
    let n = track.tip.len();
    let scale = scale_of(track, opts)?;
    if n < 32 {
        return Err(CompareError::TooShort {
            file: track.file.clone(),
            message: format!("{n} frames"),
        });
    }
    let axes = Point::new(
        if opts.mirror { -1.0 } else { 1.0 },
        if track.y_down { -1.0 } else { 1.0 },
    );
    let flip = |p: Point| Point::new(p.x * axes.x, p.y * axes.y);
    let pts: Vec<Point> = track.tip.iter().map(|p| flip(*p)).collect();
    let reference = match opts.carrier_axis {
        Some(a) => flip(a),
        None => pts.iter().fold(Point::default(), |a, p| a + *p) / n as f64,
    };
    let u: Vec<Point> = pts.iter().map(|p| *p - reference).collect();
    let (t0, t1) = (track.time_s[0], track.time_s[n - 1]);
    let (mid, half) = (0.5 * (t0 + t1), 0.5 * (t1 - t0));
    let dt: Vec<f64> = track.time_s.iter().map(|t| t - mid).collect();
    let sense = f64::from(path.direction);
    // The carrier angle of each frame from the mid frame's: measured (encoder), or ω·(t − t_m).
    let encoder: Option<Vec<f64>> = track.encoder_deg.as_ref().map(|e| {
        let m = dt
            .iter()
            .map(|t| t.abs())
            .enumerate()
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .map_or(0, |(k, _)| k);
        e.iter().map(|a| sense * (a - e[m]).to_radians()).collect()
    });
    let (offsets, omega0) = match &encoder {
        Some(e) => {
            let turns = (e[n - 1] - e[0]).abs() / TAU;
            if turns < 1.0 {
                return Err(CompareError::TooShort {
                    file: track.file.clone(),
                    message: format!("the encoder turns {:.1}° over the record", turns * 360.0),
                });
            }
            (e.clone(), (e[n - 1] - e[0]) / (t1 - t0))
        }
        None => {
            let period = initial::period(&track.file, &track.time_s, &u, opts.rpm)?;
            let w = sense * TAU / period;
            (dt.iter().map(|t| w * t).collect(), w)
        }
    };
    let datum = opts.carrier_axis.is_some();
    if let Some(r) = opts.rotation_rad
        && !r.is_finite()
    {
        return Err(bad("rotation", format!("{r}: expected a finite angle")));
    }
    let start = initial::start(
        &track.file,
        path,
        &u,
        &offsets,
        omega0,
        initial::Known {
            scale,
            datum,
            rotation: opts.rotation_rad,
        },
    )?;
    let fo = FitOptions {
        fit_scale: scale.is_none(),
        datum,
        fixed_rotation: opts.rotation_rad.is_some(),
        drift_order: opts.drift_order,
        smooth_order: opts.smooth_order.unwrap_or(MAX_CHOSEN_ORDER),
        huber_k: 2.0,
        outlier_k: opts.outlier_sigma,
    };
    let fit = register::fit(path, &u, &dt, half, &start, fo, encoder.as_deref());
    if !fit.values.iter().all(|v| v.is_finite()) {
        return Err(CompareError::NoFit {
            message: "the parameters left the finite numbers".into(),
        });
    }
    let get = |name: &str| {
        fit.names.iter().position(|n| *n == name).map(|k| Estimate {
            value: fit.values[k],
            se: fit.standard_errors[k],
        })
    };
    let theta = get("rotation_rad").unwrap_or(Estimate {
        value: start.rotation_rad,
        se: 0.0,
    });
    let t = match (get("translation_x_mm"), get("translation_y_mm")) {
        (Some(x), Some(y)) => [x, y],
        _ => [
            Estimate {
                value: path.center_mm.x,
                se: 0.0,
            },
            Estimate {
                value: path.center_mm.y,
                se: 0.0,
            },
        ],
    };
    let s = match get("ln_scale") {
        Some(l) => Estimate {
            value: start.scale * l.value.exp(),
            se: start.scale * l.value.exp() * l.se,
        },
        None => Estimate {
            value: start.scale,
            se: 0.0,
        },
    };
    let land = |p: Point| {
        (p - reference).rotate(theta.value) * s.value + Point::new(t[0].value, t[1].value)
    };
    let t_full = land(Point::default());
    let (phase, omega) = (
        get("phase_rad").expect("fitted"),
        get("omega_rad_s").unwrap_or(Estimate {
            value: omega0,
            se: 0.0,
        }),
    );
    let rpm_of = |w: f64| w.abs() * 60.0 / TAU;
    let inlier: Vec<bool> = fit.outlier.iter().map(|o| !o).collect();
    let needle: Option<Vec<f64>> = track.marker.as_ref().map(|m| {
        m.iter()
            .zip(&fit.q_mm)
            .map(|(m, q)| (*q - land(flip(*m))).atan2())
            .collect()
    });
    let order = opts.smooth_order.unwrap_or_else(|| {
        let w: Vec<f64> = inlier.iter().map(|u| f64::from(u8::from(*u))).collect();
        let comps = [
            fit.residual_mm.iter().map(|p| p.x).collect(),
            fit.residual_mm.iter().map(|p| p.y).collect::<Vec<_>>(),
        ];
        smooth::bic_order(&fit.phi_rad, &comps, &w, 2, MAX_CHOSEN_ORDER)
    });
    let smooth = SmoothPath::fit(
        path,
        &fit.phi_rad,
        &fit.residual_mm,
        needle.as_deref(),
        &inlier,
        order,
    )
    .ok_or_else(|| CompareError::NoFit {
        message: "the frames do not determine the deviation by carrier angle".into(),
    })?;
    let mean_rpm = rpm_of((fit.phi_rad[n - 1] - fit.phi_rad[0]) / (t1 - t0));
    let mut fopts = opts.features.with_rpm(mean_rpm);
    if let Some(sp) = opts.spacing_mm {
        fopts = fopts.with_forward_mm_s(FeatureOptions::forward_for_spacing(sp, mean_rpm));
    }
    let fe = |e: crate::simulate::SimulateError| bad("features", e.to_string());
    let design_features = SmoothPath::design(path).features(&fopts).map_err(fe)?;
    let track_features = smooth.features(&fopts).map_err(fe)?;
    let deviation = figures::deviation_report(
        &smooth,
        &fit.phi_rad,
        &fit.residual_mm,
        &inlier,
        fit.sigma_mm,
        order,
    );
    let design_fig = figures::figures_of(&design_features, 0.0);
    let track_fig = figures::figures_of(&track_features, deviation.rms_mm);
    let turns = turns(path, track, &fit, &inlier, needle.as_deref(), order, &fopts)?;
    let per_turn: Vec<_> = turns.iter().map(|t| t.figures).collect();
    let mut dts: Vec<f64> = track.time_s.windows(2).map(|w| w[1] - w[0]).collect();
    dts.sort_by(f64::total_cmp);
    let outlier_lines: Vec<usize> = fit
        .outlier
        .iter()
        .zip(&track.line)
        .filter(|(o, _)| **o)
        .map(|(_, l)| *l)
        .collect();
    let deg = |e: Estimate| Estimate {
        value: e.value.to_degrees(),
        se: e.se.to_degrees(),
    };
    let report = CompareReport {
        schema_version: 1,
        track: TrackSummary {
            file: track.file.clone(),
            format: track.format.into(),
            frames: n,
            skipped_rows: track.skipped,
            unit: format!("{:?}", track.unit).to_ascii_lowercase(),
            y_down: track.y_down,
            marker: track.marker.is_some(),
            encoder: track.encoder_deg.is_some(),
            duration_s: t1 - t0,
            fps: 1.0 / dts[dts.len() / 2],
        },
        registration: RegistrationReport {
            rotation_deg: deg(theta),
            rotation_given: opts.rotation_rad.is_some(),
            translation_mm: [
                Estimate {
                    value: t_full.x,
                    se: t[0].se,
                },
                Estimate {
                    value: t_full.y,
                    se: t[1].se,
                },
            ],
            scale_mm_per_unit: s,
            scale_fitted: scale.is_none(),
            mirrored: opts.mirror,
            carrier_axis: opts.carrier_axis.map(|a| [a.x, a.y]),
            mid_time_s: mid,
            phase_deg: Estimate {
                value: phase.value.to_degrees().rem_euclid(360.0),
                se: phase.se.to_degrees(),
            },
            rpm: Estimate {
                value: rpm_of(omega.value),
                se: rpm_of(omega.se),
            },
            mean_rpm,
            drift_deg: fit
                .names
                .iter()
                .zip(fit.values.iter().zip(&fit.standard_errors))
                .filter(|(n, _)| n.starts_with("drift"))
                .map(|(_, (v, e))| deg(Estimate { value: *v, se: *e }))
                .collect(),
            noise_mm: fit.sigma_mm,
            outliers: outlier_lines.len(),
            outlier_lines,
            iterations: fit.iterations,
            converged: fit.converged,
        },
        deviation,
        features: report::FeaturesComparison {
            needle_from: if track.marker.is_some() {
                "marker"
            } else {
                "design"
            }
            .into(),
            difference: figures::difference(&track_fig, &design_fig),
            design: design_features,
            track: track_features,
        },
        spread: figures::spread(&per_turn),
        turns,
        dynamics: None,
        files: Vec::new(),
    };
    let frames = (0..n)
        .map(|i| Frame {
            line: track.line[i],
            time_s: track.time_s[i],
            phi_rad: fit.phi_rad[i],
            q_mm: fit.q_mm[i],
            residual_mm: fit.residual_mm[i],
            smooth_mm: smooth.deviation(fit.phi_rad[i]),
            outlier: fit.outlier[i],
        })
        .collect();
    Ok(Comparison {
        report,
        frames,
        design_mm: path.turn(figures::TURN_SAMPLES),
    })
}

/// The whole turns of the record, each fitted on its own frames.
fn turns(
    path: &DesignPath,
    track: &Track,
    fit: &register::Fit,
    inlier: &[bool],
    needle: Option<&[f64]>,
    order: usize,
    fopts: &FeatureOptions,
) -> Result<Vec<TurnReport>, CompareError> {
    let sense = f64::from(path.direction);
    let phi0 = fit.phi_rad[0];
    let index: Vec<f64> = fit
        .phi_rad
        .iter()
        .map(|p| (sense * (p - phi0) / TAU).floor())
        .collect();
    let whole = (sense * (fit.phi_rad[fit.phi_rad.len() - 1] - phi0) / TAU)
        .floor()
        .max(0.0) as usize;
    let mut out = Vec::new();
    for j in 0..whole {
        let mine: Vec<bool> = index
            .iter()
            .zip(inlier)
            .map(|(k, u)| *k == j as f64 && *u)
            .collect();
        let all: Vec<usize> = (0..index.len()).filter(|&i| index[i] == j as f64).collect();
        let (Some(&a), Some(&b)) = (all.first(), all.last()) else {
            continue;
        };
        let Some(smooth) =
            SmoothPath::fit(path, &fit.phi_rad, &fit.residual_mm, needle, &mine, order)
        else {
            continue;
        };
        let used: Vec<f64> = (0..index.len())
            .filter(|&i| mine[i])
            .map(|i| fit.residual_mm[i].norm_squared())
            .collect();
        let figures = smooth
            .figures(fopts)
            .map_err(|e| bad("features", e.to_string()))?;
        out.push(TurnReport {
            index: j,
            frames: used.len(),
            start_s: track.time_s[a],
            rpm: (fit.phi_rad[b] - fit.phi_rad[a]).abs() / (track.time_s[b] - track.time_s[a])
                * 60.0
                / TAU,
            frame_rms_mm: (used.iter().sum::<f64>() / used.len().max(1) as f64).sqrt(),
            figures,
        });
    }
    Ok(out)
}

/// The whole job of `ncgear compare` (and `ncgear.compare`): the track file at `path` read and
/// compared with `rebuilt` as `args` say, and with a rotor scene `dynamics` of the same train,
/// against its dynamic path too ([`dynamic::against_dynamics`], its summary in the report's
/// `dynamics`); `progress` hears the rotor's turns.
///
/// # Errors
/// As [`CompareArgs::resolve`](args::CompareArgs::resolve), [`read_track`], [`compare`] and
/// [`dynamic::against_dynamics`].
pub fn compare_track(
    path: &std::path::Path,
    rebuilt: &Rebuilt,
    args: &args::CompareArgs,
    dynamics: Option<&crate::analysis::dynamics::rotor::Prepared>,
    progress: &crate::progress::Progress,
) -> Result<Comparison, CompareError> {
    let (read, opts) = args.resolve()?;
    let track = read_track(path, &read)?;
    let mut c = compare(&track, rebuilt, &opts)?;
    if let Some(p) = dynamics {
        let (_, d) = dynamic::against_dynamics(&track, rebuilt, &c, p, &opts, progress)?;
        c.report.dynamics = Some(d);
    }
    Ok(c)
}

/// Reads a track file (see [`track`]).
///
/// # Errors
/// [`CompareError::Unreadable`], or as [`parse_track`].
pub fn read_track(path: &std::path::Path, opts: &ReadOptions) -> Result<Track, CompareError> {
    let file = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| CompareError::Unreadable {
        file: file.clone(),
        message: e.to_string(),
    })?;
    parse_track(&text, &file, opts)
}
