//! `ncgear compare TRACK.csv --design design.json`: a filmed needle-tip track registered to the
//! design's static path and compared with it.
use super::{CliResult, input_error, print_json, runtime_error};
use ncgear::analysis::dynamics::rotor::Prepared;
use ncgear::compare::dynamic::against_dynamics;
use ncgear::compare::{
    CompareError, CompareOptions, LengthUnit, ReadOptions, Scale, compare, read_track,
};
use ncgear::math::Point;
use ncgear::simulate::{DesignFile, FeatureOptions};
use std::path::PathBuf;

/// Arguments of `ncgear compare`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The track: CSV of time (s, ms, or frame numbers with --fps), x, y (mm, cm, m or px);
    /// plain, Tracker's or Kinovea's export.
    pub track: PathBuf,
    /// The design file the mechanism was built from (design.json).
    #[arg(long)]
    pub design: PathBuf,
    /// Output directory.
    #[arg(long, default_value = "out/compare")]
    pub out: PathBuf,
    /// Carrier speed, rpm (default: found from the record's period).
    #[arg(long)]
    pub rpm: Option<f64>,
    /// Frames per second: for a frame-number time column (or none).
    #[arg(long)]
    pub fps: Option<f64>,
    /// Columns time,x,y or time,x,y,x2,y2 (x2, y2: a second marker on the needle's axis), names or
    /// 1-based positions; time `-` for none.
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    pub columns: Vec<String>,
    /// The encoder column (name or 1-based position): each frame's carrier angle, deg, in the
    /// direction of travel (default: a column named `encoder` or `carrier_deg`).
    #[arg(long)]
    pub encoder: Option<String>,
    /// The track's length unit (mm, cm, m, px), overriding the header's.
    #[arg(long)]
    pub units: Option<String>,
    /// Pixels per mm.
    #[arg(long, conflicts_with_all = ["calibration", "fit_scale"])]
    pub px_per_mm: Option<f64>,
    /// Two-point calibration x1,y1,x2,y2,dist_mm: two image points (track units) and their distance.
    #[arg(
        long,
        value_delimiter = ',',
        allow_hyphen_values = true,
        conflicts_with = "fit_scale"
    )]
    pub calibration: Vec<f64>,
    /// Fit the scale to the design (it then absorbs any size error of the built mechanism).
    #[arg(long)]
    pub fit_scale: bool,
    /// The carrier axis as filmed, x,y (track units): pins the translation.
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    pub carrier_axis: Vec<f64>,
    /// The rotation from the track's axes (y flipped, mirrored) to the design's, deg, when known
    /// (a levelled camera: 0): pins the rotation.
    #[arg(long, allow_hyphen_values = true)]
    pub rotation: Option<f64>,
    /// Mirror the track (filmed from the other side).
    #[arg(long)]
    pub mirror: bool,
    /// y points down (image coordinates; the default for pixels).
    #[arg(long, conflicts_with = "y_up")]
    pub y_down: bool,
    /// y points up (the default for mm, cm, m).
    #[arg(long)]
    pub y_up: bool,
    /// Highest power of the timing drift (1: constant speed).
    #[arg(long, default_value_t = 3)]
    pub drift_order: usize,
    /// Order of the smooth deviation by carrier angle (Fourier harmonics, 2..=40; default:
    /// chosen from the frames, at most 8, by the Bayesian information criterion).
    #[arg(long)]
    pub smooth_order: Option<usize>,
    /// Planting depth, mm (for the hole width).
    #[arg(long, default_value_t = 30.0)]
    pub depth: f64,
    /// Plant spacing, mm (sets the forward speed for the hole width; default 1 m/s).
    #[arg(long)]
    pub spacing: Option<f64>,
    /// A rotor dynamics scene (`[scene] model = "rotor"`) of the same design: its settled turn
    /// at the track's mean speed becomes a second reference path (backlash, elastic teeth).
    #[arg(long)]
    pub dynamics: Option<PathBuf>,
    /// Also write compare.png.
    #[arg(long)]
    pub png: bool,
    /// Print the report as JSON on stdout.
    #[arg(long)]
    pub json: bool,
}

fn input(e: impl std::fmt::Display) -> super::Failure {
    input_error(miette::miette!("{e}"))
}

fn options(args: &Args) -> Result<(ReadOptions, CompareOptions), super::Failure> {
    let units = match &args.units {
        Some(u) => Some(
            LengthUnit::parse(u)
                .ok_or_else(|| input(format!("--units {u}: expected mm, cm, m or px")))?,
        ),
        None => None,
    };
    let y_down = if args.y_down {
        Some(true)
    } else if args.y_up {
        Some(false)
    } else {
        None
    };
    let read = ReadOptions {
        columns: args.columns.clone(),
        fps: args.fps,
        units,
        y_down,
        encoder: args.encoder.clone(),
    };
    let scale = match (args.px_per_mm, args.calibration.as_slice(), args.fit_scale) {
        (Some(s), _, _) => Scale::PxPerMm(s),
        (None, [x1, y1, x2, y2, d], _) => Scale::Calibration {
            p1: Point::new(*x1, *y1),
            p2: Point::new(*x2, *y2),
            distance_mm: *d,
        },
        (None, [], true) => Scale::Fit,
        (None, [], false) => Scale::Units,
        (None, c, _) => {
            return Err(input(format!(
                "--calibration: {} numbers given; expected x1,y1,x2,y2,dist_mm",
                c.len()
            )));
        }
    };
    let carrier_axis = match args.carrier_axis.as_slice() {
        [] => None,
        [x, y] => Some(Point::new(*x, *y)),
        c => {
            return Err(input(format!(
                "--carrier-axis: {} numbers given; expected x,y",
                c.len()
            )));
        }
    };
    let features = FeatureOptions::default().with_planting_depth_mm(args.depth);
    if let Some(s) = args.spacing
        && !(s.is_finite() && s > 0.0)
    {
        return Err(input(format!(
            "--spacing {s}: expected a positive plant spacing in mm"
        )));
    }
    let opts = CompareOptions {
        scale,
        mirror: args.mirror,
        rpm: args.rpm,
        carrier_axis,
        rotation_rad: args.rotation.map(f64::to_radians),
        drift_order: args.drift_order,
        smooth_order: args.smooth_order,
        features,
        spacing_mm: args.spacing,
        ..CompareOptions::default()
    };
    Ok((read, opts))
}

/// Runs `ncgear compare`.
pub fn run(args: Args) -> CliResult {
    let (read, opts) = options(&args)?;
    let (_, asm) = DesignFile::from_path(&args.design).map_err(input)?;
    let track = read_track(&args.track, &read).map_err(input)?;
    let scene = args
        .dynamics
        .as_deref()
        .map(|p| Prepared::from_path(p).map_err(input))
        .transpose()?;
    let failed = |e: CompareError| match e {
        CompareError::NoFit { .. } => runtime_error(miette::miette!("{e}")),
        _ => input(e),
    };
    let rebuilt = asm.rebuild();
    let mut c = compare(&track, &rebuilt, &opts).map_err(failed)?;
    if let Some(p) = &scene {
        let pb = super::progress_bar(u64::from(p.case.settings.max_turns), "turns");
        let (_, d) = against_dynamics(&track, &rebuilt, &c, p, &opts, &super::bar_sink(&pb))
            .map_err(failed)?;
        pb.finish_and_clear();
        c.report.dynamics = Some(d);
    }
    let report = ncgear::output::write_compare(&c, &args.out, args.png)
        .map_err(|e| runtime_error(miette::miette!("{e}")))?;
    if args.json {
        return print_json(&report);
    }
    let r = &report.registration;
    let d = &report.deviation;
    let f = &report.features;
    println!(
        "{}: {} frames ({} outliers) registered to {}",
        args.track.display(),
        report.track.frames,
        r.outliers,
        args.design.display()
    );
    println!(
        "  rotation {:.4}° ± {:.4}°, translation ({:.3}, {:.3}) mm, scale {:.6} mm/unit{}",
        r.rotation_deg.value,
        r.rotation_deg.se,
        r.translation_mm[0].value,
        r.translation_mm[1].value,
        r.scale_mm_per_unit.value,
        if r.scale_fitted { " (fitted)" } else { "" }
    );
    println!(
        "  carrier {:.2} rpm (mean {:.2}), frame noise σ {:.3} mm",
        r.rpm.value, r.mean_rpm, r.noise_mm
    );
    println!(
        "  deviation by carrier angle: RMS {:.3} mm, max {:.3} mm at {:.0}°, Hausdorff {:.3} mm (noise floor {:.3} mm)",
        d.rms_mm, d.max_mm, d.max_at_carrier_deg, d.hausdorff_mm, d.noise_floor_mm
    );
    println!(
        "  taking angle {:.2}° (design {:.2}°), pushing angle {:.2}° (design {:.2}°), hole width {:.2} mm (design {:.2} mm)",
        f.track.take_angle_deg,
        f.design.take_angle_deg,
        f.track.push_angle_deg,
        f.design.push_angle_deg,
        f.track.hole_width_mm,
        f.design.hole_width_mm
    );
    if let Some(d) = &report.dynamics {
        println!(
            "  against the dynamics of `{}` at {:.2} r/min ({} turns{}): deviation RMS {:.3} mm, max {:.3} mm at {:.0}° (static RMS {:.3} mm; the dynamic tip leaves the static path by up to {:.3} mm): the dynamics explain {:.0} % of the mean square",
            d.scene,
            d.carrier_rpm,
            d.turns,
            if d.settled { "" } else { ", not settled" },
            d.rms_mm,
            d.max_mm,
            d.max_at_carrier_deg,
            d.static_rms_mm,
            d.max_tip_departure_mm,
            100.0 * d.explained
        );
    }
    if let Some(s) = &report.spread {
        println!(
            "  {} turns: spread of the pushing angle {:.3}°, of the hole width {:.3} mm",
            report.turns.len(),
            s.push_angle_deg,
            s.hole_width_mm
        );
    }
    println!(
        "  wrote {} files into {}",
        report.files.len() + 1,
        args.out.display()
    );
    Ok(())
}
