//! `ncgear tradeoff TRAJ --out DIR`: what accuracy costs, one design per limit and module.
use super::design::design_failure;
use super::design_args::{DrawingArgs, parse_point};
use super::{CliResult, print_json, progress_bar, runtime_error};
use ncgear::design::DesignOptions;
use ncgear::design::tradeoff::{ROWS, trade_off};
use ncgear::math::Point;
use std::path::PathBuf;

/// Arguments of `ncgear tradeoff`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Trajectory file (as for `ncgear design`).
    pub trajectory: PathBuf,
    /// How to read a DXF or SVG drawing (as for `ncgear design`).
    #[command(flatten)]
    pub drawing: DrawingArgs,
    /// Output directory (tradeoff.json, tradeoff.md, tradeoff.svg).
    #[arg(long, default_value = "out")]
    pub out: PathBuf,
    /// Carrier axis O as `X,Y` in mm.
    #[arg(long, value_parser = parse_point, default_value = "0,0", allow_hyphen_values = true)]
    pub center: Point,
    /// Print the table (tradeoff.json) to stdout instead of the console table.
    #[arg(long)]
    pub json: bool,
    /// A loads scene (as for `ncgear design --module auto --loads`): the table gets the module
    /// sized by strength — each standard module rated, up to the first that carries the loads.
    #[arg(long)]
    pub loads: Option<PathBuf>,
}

/// Runs `ncgear tradeoff`.
pub fn run(args: Args) -> CliResult {
    let scene = match &args.loads {
        Some(p) => Some(super::loads::sizing_scene(p)?),
        None => None,
    };
    let traj = args.drawing.read(&args.trajectory)?;
    let opts = DesignOptions::default().with_center_mm(args.center);
    let file = args.trajectory.display().to_string();
    let pb = progress_bar(ROWS as u64, "designs");
    let start = std::time::Instant::now();
    let t = trade_off(&traj, &opts, &super::bar_sink(&pb));
    pb.finish_and_clear();
    let mut t = t.map_err(|e| design_failure(&file, &e))?;
    if let Some((case, scene_file, dynamics)) = &scene {
        let pb = super::spinner("sizing the module");
        let sized = ncgear::loads::size_module(
            &traj,
            &opts,
            case,
            &ncgear::loads::SizingOptions::default(),
            &ncgear::loads::rating_teeth,
            dynamics.as_deref(),
            scene_file,
        );
        pb.finish_and_clear();
        t.sizing = Some(sized.map_err(super::loads::loads_failure)?.sizing);
    }
    let written = ncgear::output::write_tradeoff(&t, &args.out)
        .map_err(|e| runtime_error(miette::miette!("{e}")))?;
    if args.json {
        return print_json(&t);
    }
    println!("{file}: {} points, {ROWS} designs", t.points);
    print!("{}", t.markdown(true));
    println!(
        "{:.1} ms; wrote {}",
        1e3 * start.elapsed().as_secs_f64(),
        written
            .iter()
            .map(|p| p.display().to_string())
            .collect::<Vec<_>>()
            .join(", ")
    );
    Ok(())
}
