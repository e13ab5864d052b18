//! `ncgear simulate DESIGN.json --out DIR`.
use super::{CliResult, input_error, print_json, runtime_error};
use ncgear::design::train::{TrainPolicy, TrainSource, TrainTeethOptions, tooth_train};
use ncgear::geometry::assembly::Assembly;
use ncgear::math::Point;
use ncgear::output::animate::AnimationOptions;
use ncgear::output::{SimulationReport, write_simulation};
use ncgear::simulate::{DesignFile, FeatureOptions, SimulateError, Simulation};
use ncgear::teeth::ToothPolicy;
use std::path::PathBuf;

/// Arguments of `ncgear simulate`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Design file written by `ncgear design` (design.json).
    pub design: PathBuf,
    /// Output directory.
    #[arg(long, default_value = "out/simulate")]
    pub out: PathBuf,
    /// Target trajectory to compare with (default: the points stored in the design file).
    #[arg(long)]
    pub target: Option<PathBuf>,
    /// How to read a DXF or SVG `--target` drawing (as for `ncgear design`).
    #[command(flatten)]
    pub drawing: super::design_args::DrawingArgs,
    /// Carrier speed, rpm.
    #[arg(long, default_value_t = 300.0)]
    pub rpm: f64,
    /// Forward speed of the machine, m/s.
    #[arg(long, conflicts_with = "spacing")]
    pub speed: Option<f64>,
    /// Plant spacing, mm (sets the forward speed: two plants per carrier turn).
    #[arg(long)]
    pub spacing: Option<f64>,
    /// Planting depth, mm (soil surface at the lowest point + depth).
    #[arg(long, default_value_t = 30.0)]
    pub depth: f64,
    /// Seedling-taking level y, mm (default: the highest point).
    #[arg(long, allow_hyphen_values = true)]
    pub take_level: Option<f64>,
    /// Planting level y, mm (default: the lowest point).
    #[arg(long, allow_hyphen_values = true)]
    pub plant_level: Option<f64>,
    /// Key frames of the animation per turn (8..=3600).
    #[arg(long, default_value_t = 360, value_parser = super::count_in(8, 3600))]
    pub frames: usize,
    /// Seconds per carrier turn in the animation.
    #[arg(long, default_value_t = 6.0)]
    pub duration: f64,
    /// Print the report as JSON on stdout.
    #[arg(long)]
    pub json: bool,
    /// Draw toothed gears at this module (mm; the centre distance is scaled up to an integer
    /// tooth count, as `ncgear design --module`). Default: the design file's `teeth` block, if any.
    #[arg(long)]
    pub module: Option<f64>,
}

fn input(e: SimulateError) -> super::Failure {
    input_error(miette::miette!("{e}"))
}

/// Runs `ncgear simulate`.
pub fn run(args: Args) -> CliResult {
    let (file, asm) = DesignFile::from_path(&args.design).map_err(input)?;
    let target = match &args.target {
        Some(p) => args.drawing.read(p)?.points().to_vec(),
        None => file.target_points.clone(),
    };
    let (opts, anim) = options(&args)?;
    let sim = simulation(&args, &file, asm, &target)?;
    // The report is written last, by the library; an earlier run's goes first (ncgear::files).
    let report = write_simulation(&sim, &target, &opts, &anim, &args.out).map_err(|e| match e {
        SimulateError::BadOption { option: "out", .. } => runtime_error(miette::miette!("{e}")),
        _ => input(e),
    })?;
    if args.json {
        return print_json(&report);
    }
    print_summary(&args, &report);
    Ok(())
}

/// The feature options (carrier speed, forward speed from `--speed` m/s or `--spacing` mm,
/// depth, levels) and the animation options of the arguments.
fn options(args: &Args) -> Result<(FeatureOptions, AnimationOptions), super::Failure> {
    let forward_mm_s = match (args.speed, args.spacing) {
        (Some(v), _) => v * 1000.0,
        (None, Some(s)) if s > 0.0 => FeatureOptions::forward_for_spacing(s, args.rpm),
        (None, Some(s)) => {
            return Err(input_error(miette::miette!(
                "--spacing {s}: must be a positive plant spacing in mm"
            )));
        }
        (None, None) => FeatureOptions::default().forward_mm_s,
    };
    if !(args.duration > 0.0 && args.frames >= 8) {
        return Err(input_error(miette::miette!(
            "--duration must be > 0 s and --frames ≥ 8"
        )));
    }
    let opts = FeatureOptions::default()
        .with_rpm(args.rpm)
        .with_forward_mm_s(forward_mm_s)
        .with_planting_depth_mm(args.depth)
        .with_take_level_mm(args.take_level)
        .with_plant_level_mm(args.plant_level);
    let anim = AnimationOptions::default()
        .with_frames(args.frames)
        .with_seconds(args.duration);
    Ok((opts, anim))
}

/// The simulated train: toothed at `--module`, or at the z and module of the design file's
/// `teeth` block; else the pitch curves.
fn simulation(
    args: &Args,
    file: &DesignFile,
    asm: Assembly,
    target: &[Point],
) -> Result<Simulation, super::Failure> {
    let policy = match (args.module, &file.teeth) {
        (Some(m), _) => Some((m, TrainPolicy::ScaleCenterDistance(ToothPolicy::ScaleUp))),
        (None, Some(t)) => Some((
            t.module_mm,
            TrainPolicy::ScaleCenterDistance(ToothPolicy::Exact(t.z)),
        )),
        (None, None) => None,
    };
    Ok(match policy {
        Some((m, policy)) => {
            let mut opts = TrainTeethOptions::new(m).with_policy(policy);
            opts.toothing.verify_steps = 0;
            let on = TrainSource::Assembly {
                assembly: &asm,
                target_mm: target,
            };
            let train = tooth_train(on, &opts)
                .map_err(|e| input_error(miette::miette!("--module {m}: {e}")))?;
            Simulation::toothed(&train)
        }
        None => Simulation::new(asm),
    })
}

/// The summary on stdout: distance from the target, the agronomic features, the files.
fn print_summary(args: &Args, report: &SimulationReport) {
    let f = &report.features;
    println!(
        "{}: simulated both arms over one turn",
        args.design.display()
    );
    if let (Some(mx), Some(mean)) = (report.deviation_max_mm, report.deviation_mean_mm) {
        println!("  distance from the target: max {mx:.4} mm, mean {mean:.4} mm");
    }
    println!(
        "  arm 2 vs arm 1 static path: {:.2e} mm",
        report.arm2_vs_arm1_mm
    );
    println!(
        "  height {:.2} mm, ρ ∈ [{:.3}, {:.3}] mm",
        f.height_mm, f.rho_range_mm[1], f.rho_range_mm[0]
    );
    println!(
        "  needle angle: taking {:.2}°, planting {:.2}° (to the horizontal: {:.2}°, {:.2}°)",
        f.needle_angle_take_deg, f.needle_angle_plant_deg, f.take_angle_deg, f.push_angle_deg
    );
    println!(
        "  hole width at {} mm depth: {:.2} mm (static loop width {:.2} mm)",
        args.depth, f.hole_width_mm, f.static_width_at_depth_mm
    );
    println!(
        "  tip speed: max {:.0} mm/s, at planting {:.0} mm/s; plant spacing {:.1} mm",
        f.max_tip_speed_mm_s, f.tip_speed_at_plant_mm_s, f.plant_spacing_mm
    );
    println!(
        "  min clearance between the needles: {:.2} mm",
        f.min_arm_clearance_mm
    );
    println!(
        "  wrote {} files into {}",
        report.files.len() + 1,
        args.out.display()
    );
}
