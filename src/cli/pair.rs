//! `ncgear pair`: a single non-circular gear pair from a motion law, a centrode or a CSV law,
//! with rack-generated teeth, mesh verification and CAD exports. Thin shell over
//! [`ncgear::pair`] and [`ncgear::cad`].
use super::{CliResult, Failure, print_json, progress_bar};

fn input_error(e: impl std::fmt::Display) -> Failure {
    super::input_error(miette::miette!("{e}"))
}

fn runtime_error(e: impl std::fmt::Display) -> Failure {
    super::runtime_error(miette::miette!("{e}"))
}
use super::teeth_args::RackArgs;
use ncgear::cad::dxf::{DxfVersion, write_dxf};
use ncgear::cad::points::write_points;
use ncgear::cad::svg::write_svg;
use ncgear::pair::{
    Expr, Law, PairDesign, PairError, PairOptions, PairTimings, design_pair_staged,
};
use ncgear::teeth::ToothingOptions;
use std::path::PathBuf;

/// Arguments of `ncgear pair`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Motion law ψ(φ) in radians, e.g. "phi - 0.08*sin(2*phi)" (operators + - * / ^, phi, pi,
    /// sin cos tan exp sqrt abs). Omit when using --centrode or --csv. A law may begin with a
    /// minus sign ("-phi + …"); write `--` before it if it could be read as a flag.
    #[arg(allow_hyphen_values = true)]
    pub law: Option<String>,
    /// Drive pitch radius at the contact r(φ), e.g. "1 + 0.08*cos(2*phi)"; the centre distance is
    /// solved for closure and the shape scaled to the teeth.
    #[arg(long, conflicts_with_all = ["law", "csv"])]
    pub centrode: Option<String>,
    /// Driven rotation per driver turn that the centrode's centre distance is solved for, degrees
    /// (360: equal gears; 180: the driven gear turns once per two driver turns, twice the teeth).
    /// Motion laws bring their own advance ψ(2π) − ψ(0).
    #[arg(long, default_value_t = 360.0, requires = "centrode")]
    pub cycle_advance: f64,
    /// An open (incomplete) pair: teeth only over the driver interval --drive-start..--drive-end,
    /// with --teeth on that interval (motion laws only).
    #[arg(long, requires_all = ["drive_start", "drive_end"])]
    pub open: bool,
    /// Start of the open sector's driver interval, degrees.
    #[arg(long, requires = "open")]
    pub drive_start: Option<f64>,
    /// End of the open sector's driver interval, degrees.
    #[arg(long, requires = "open")]
    pub drive_end: Option<f64>,
    /// CSV law file with header `phi_deg,psi_deg` (one driver turn, degrees).
    #[arg(long, conflicts_with = "law")]
    pub csv: Option<PathBuf>,
    /// Driver tooth count (required for a motion or CSV law); the driven gear gets z·360°/Δ with Δ
    /// the law's advance per driver turn (equal counts for a 1:1 law).
    #[arg(long)]
    pub teeth: Option<u32>,
    /// Module, mm.
    #[arg(long, default_value_t = 1.0)]
    pub module: f64,
    /// Rack, backlash and CAD-export options.
    #[command(flatten)]
    pub rack: RackArgs,
    /// Driver positions checked by the mesh verification over one turn (0 = skip).
    #[arg(long, default_value_t = 90)]
    pub verify_steps: usize,
    /// Output directory (created if missing; files are overwritten).
    #[arg(long, short = 'o', default_value = "out")]
    pub out: PathBuf,
    /// Print the JSON report to stdout.
    #[arg(long)]
    pub json: bool,
    /// Exit 0 even when the mesh verification fails (interference, a backlash that is not finite
    /// or negative; pair.json still says so, in `verdict`); without it such a run writes its
    /// files and exits with code 3.
    #[arg(long)]
    pub accept_failed: bool,
}

/// Runs `ncgear pair`.
pub fn run(args: Args) -> CliResult {
    // The printed time is the whole command's.
    let started = std::time::Instant::now();
    args.rack.check_exports()?;
    let law = law_of(&args)?;
    let opts = pair_options(&args)?;
    let to_failure = pair_failure;
    let (mut design, pending) = design_pair_staged(&law, &opts).map_err(to_failure)?;
    let t_design = super::ms_since(started);
    std::fs::create_dir_all(&args.out)
        .map_err(|e| runtime_error(format!("cannot create {}: {e}", args.out.display())))?;
    // The report is written last; an earlier run's goes first (ncgear::files).
    let json_path = args.out.join("pair.json");
    super::remove_stale_report(&json_path)?;
    let sheet = design.assembly_sheet();
    let version = DxfVersion::from(args.rack.dxf_version);
    let dxf = args.out.join("pair.dxf");
    let svg = args.out.join("pair.svg");
    let step = args.out.join("pair.step");
    let pb = progress_bar(opts.toothing.verify_steps as u64, "mesh check");
    // The mesh check and the four exports are independent: run side by side (the exports need
    // only the outlines; the STEP model is the longest of them).
    let t_files = std::time::Instant::now();
    let ((mesh, t_mesh), ((r_dxf, r_svg), (r_points, r_step))) = rayon::join(
        || {
            let t0 = std::time::Instant::now();
            let mesh = pending.map(|p| p.run(&super::bar_sink(&pb))).transpose();
            (mesh, super::ms_since(t0))
        },
        || {
            rayon::join(
                || {
                    rayon::join(
                        || write_dxf(&sheet, &dxf, version, opts.toothing.chord_tol_mm),
                        || write_svg(&sheet, &svg, 2.0 * args.module),
                    )
                },
                || {
                    rayon::join(
                        || write_points(&sheet, &args.out, "pair_points"),
                        || {
                            let model = ncgear::output::pair_step(
                                &design,
                                opts.toothing.chord_tol_mm,
                                &args.rack.solids(),
                            );
                            ncgear::cad::step::write_step(&model, &step)
                        },
                    )
                },
            )
        },
    );
    pb.finish_and_clear();
    let t_files = super::ms_since(t_files);
    design.mesh = mesh.map_err(to_failure)?;
    r_dxf.map_err(runtime_error)?;
    r_svg.map_err(runtime_error)?;
    let mut files = r_points.map_err(runtime_error)?;
    r_step.map_err(|e| super::teeth_args::step_failure(&e))?;
    files.push(step);
    files.push(dxf);
    files.push(svg);
    let mut report = design.report(&opts);
    report.files = files.iter().map(|p| p.display().to_string()).collect();
    report.timings_ms = PairTimings {
        design: t_design,
        verification: t_mesh,
        verification_and_files: t_files,
        command: super::ms_since(started),
    };
    let verdict = report.verdict.clone();
    ncgear::output::write_pair_report(&report, &args.out).map_err(runtime_error)?;
    if args.json {
        // Every object's keys in sorted order, as in pair.json.
        print_json(&serde_json::to_value(&report).unwrap_or_default())?;
    } else {
        print_summary(&design, &args.out, [t_design, t_mesh, t_files], started);
    }
    super::verdict_outcome(&verdict, args.accept_failed, &[])
}

/// The law the pair is made for: a motion law, a centrode, or a CSV table (exactly one).
fn law_of(args: &Args) -> Result<Law, super::Failure> {
    Ok(match (&args.law, &args.centrode, &args.csv) {
        (Some(e), None, None) => Law::Motion(Expr::parse(e).map_err(input_error)?),
        (None, Some(e), None) => Law::Centrode(Expr::parse(e).map_err(input_error)?),
        (None, None, Some(p)) => Law::from_csv(p).map_err(input_error)?,
        _ => {
            return Err(input_error(miette::miette!(
                "give exactly one of: a motion law, --centrode, --csv"
            )));
        }
    })
}

/// The pair's options from the flags (rack, backlash and export options checked).
fn pair_options(args: &Args) -> Result<PairOptions, super::Failure> {
    let sector = match (args.open, args.drive_start, args.drive_end) {
        (true, Some(a), Some(b)) => Some([a.to_radians(), b.to_radians()]),
        _ => None,
    };
    let mut toothing = ToothingOptions::new(args.module).with_verify_steps(args.verify_steps);
    args.rack
        .apply_to(&mut toothing)
        .map_err(super::teeth_args::option_failure)?;
    Ok(PairOptions::new(args.teeth, args.module)
        .with_centrode_advance_rad(args.cycle_advance.to_radians())
        .with_open_sector_rad(sector)
        .with_toothing(toothing))
}

/// The CLI failure for a pair error: the flag behind a bad option, a runtime error for the
/// teeth and the mesh, an input error otherwise.
fn pair_failure(e: PairError) -> super::Failure {
    match &e {
        PairError::Teeth(ncgear::teeth::TeethError::Bounds(b)) | PairError::Bounds(b) => {
            super::option_error(Some(&b.quantity), &e)
        }
        PairError::Teeth(ncgear::teeth::TeethError::InvalidParameter { name, .. })
        | PairError::InvalidParameter { name, .. } => super::option_error(Some(name), &e),
        PairError::Teeth(_) | PairError::Mesh(_) => runtime_error(e),
        _ => input_error(e),
    }
}

/// The console summary: tooth counts, processes, undercut, mesh, and the times (ms) of the
/// design, the verification and the files.
fn print_summary(
    design: &PairDesign,
    out: &std::path::Path,
    [t_design, t_mesh, t_files]: [f64; 3],
    started: std::time::Instant,
) {
    println!(
        "z = {}:{}, m = {} mm, a = {:.6} mm; outputs in {}",
        design.z,
        design.z_driven,
        design.module_mm,
        design.center_distance_mm,
        out.display()
    );
    println!(
        "driver: {}",
        super::teeth_args::process_line(&design.driver_process)
    );
    println!(
        "driven: {}",
        super::teeth_args::process_line(&design.driven_process)
    );
    for (name, u, p) in [
        ("driver", &design.driver_undercut, &design.driver_process),
        ("driven", &design.driven_undercut, &design.driven_process),
    ] {
        if let Some(w) = super::teeth_args::undercut_line(name, u, Some(p)) {
            println!("{w}");
        }
    }
    if let Some(m) = &design.mesh {
        println!("mesh: {}", m.summary());
    }
    println!(
        "{:.1} ms (teeth {t_design:.1}, verification {t_mesh:.1} beside the files, all \
         {t_files:.1})",
        super::ms_since(started)
    );
}
