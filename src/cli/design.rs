//! `ncgear design TRAJ --out DIR`.
pub use super::design_args::Args;
use super::design_args::{DEFAULT_VERIFY_STEPS, ModuleArg, ToothPolicyArg};
use super::{CliResult, input_error, print_json, progress_bar, runtime_error};
use ncgear::design::inverse::InverseError;
use ncgear::design::train::{
    PendingTrainMesh, ToothedTrain, TrainError, TrainPolicy, TrainTeethOptions, TrainTeethReport,
    tooth_train_staged,
};
use ncgear::design::{DesignError, design};
use ncgear::teeth::ToothPolicy;
use std::path::PathBuf;

/// Runs `ncgear design`: options checked, design, teeth and their checks beside the CAD files
/// (with `--module`), the report written last, the console summary.
pub fn run(args: Args) -> CliResult {
    // The printed time is the whole command's: design, teeth, checks and files.
    let started = std::time::Instant::now();
    // Every option is checked before any work: the tooth and export options and the loads
    // scene too.
    let scene = super::loads::design_scene(&args)?;
    let teeth_opts = match args.module {
        Some(ModuleArg::Mm(m)) => Some(teeth_options(&args, m)?),
        Some(ModuleArg::Auto) => Some(teeth_options(&args, 1.0)?),
        None => {
            refuse_tooth_flags(&args)?;
            None
        }
    };
    let traj = args.drawing.read(&args.trajectory)?;
    let opts = args.options();
    let file = args.trajectory.display().to_string();
    // `--module auto` cuts and rates the teeth of each module it tries: the kept module's come
    // back cut, their mesh check still to run, and rated.
    let (mut d, module, sized) = match (&scene, args.module) {
        (Some(sc), Some(ModuleArg::Auto)) => {
            let teeth = |m: f64| toothing_at(&args, m);
            let k = super::loads::sized_design(&traj, &opts, sc, &teeth, &file)?;
            let m = k.train.report.module_mm;
            (k.design, Some(m), Some((k.train, k.pending_mesh, k.loads)))
        }
        _ => {
            let pb = super::spinner("designing the gears");
            let d = design(&traj, &opts).map_err(|e| design_failure(&file, &e));
            pb.finish_and_clear();
            (d?, args.module.and_then(ModuleArg::mm), None)
        }
    };
    // The report is written last; an earlier run's goes before any file (ncgear::files).
    super::remove_stale_report(&args.out.join("design.json"))?;
    let mut files = ncgear::output::DesignFiles::default();
    files.png = args.png;
    let (train, teeth_files, sized_loads) = match (module, &teeth_opts, sized) {
        (_, _, Some((t, pending, loads))) => {
            let (t, written) = checked_and_exported(&args, &mut d, t, pending, files)?;
            (Some(t), written, Some(loads))
        }
        (Some(m), Some(checked), None) => {
            let (t, written) = teeth_and_cad_files(&args, &mut d, m, checked, files)?;
            (Some(t), written, None)
        }
        _ => (None, Vec::new(), None),
    };
    let loads = match (&scene, &train, sized_loads) {
        (_, _, Some(l)) => Some(l),
        (Some((case, scene_file, dynamics)), Some(t), None) => Some(
            ncgear::loads::analyse_with(
                &ncgear::loads::Rotor::toothed(t),
                case,
                scene_file,
                dynamics.as_deref(),
            )
            .map_err(super::loads::loads_failure)?,
        ),
        _ => None,
    };
    d.report.timings_ms.command = super::ms_since(started);
    let mut written = ncgear::output::write_design_with(&d, &args.out, files)
        .map_err(|e| runtime_error(miette::miette!("{e}")))?;
    written.extend(teeth_files);
    if let Some(l) = &loads {
        written.extend(
            ncgear::output::write_loads(l, &args.out.join("loads"), args.png)
                .map_err(|e| runtime_error(miette::miette!("{e}")))?,
        );
    }
    let notes: Vec<String> = ncgear::design::chain::alternatives::failure_note(&opts, &d.report)
        .into_iter()
        .collect();
    if args.json {
        print_json(&d.report)?;
        return super::verdict_outcome(&d.report.verdict, args.accept_failed, &notes);
    }
    print_summary(
        &file,
        &d.report,
        train.as_ref(),
        &written,
        &args.out,
        started,
    );
    if let Some(l) = &loads {
        super::loads::print_sizing(&d.report, l);
    }
    super::verdict_outcome(&d.report.verdict, args.accept_failed, &notes)
}

/// Teeth on the designed gears, then their mesh check beside the CAD exports (they do not read
/// it); the design files are written when the teeth or the check fail. Returns the toothed train
/// (recorded in `d`'s report) and the CAD files written.
fn teeth_and_cad_files(
    args: &Args,
    d: &mut ncgear::design::Design,
    m: f64,
    teeth_opts: &TrainTeethOptions,
    files: ncgear::output::DesignFiles,
) -> Result<(ToothedTrain, Vec<PathBuf>), super::Failure> {
    // The design files are written even when the teeth are refused.
    let write_design = |d: &ncgear::design::Design| {
        ncgear::output::write_design_with(d, &args.out, files)
            .map_err(|e| runtime_error(miette::miette!("{e}")))
    };
    let t0 = std::time::Instant::now();
    let pb = super::spinner("cutting the teeth");
    let cut = toothed(args, d, m, teeth_opts);
    pb.finish_and_clear();
    let (t, pending) = match cut {
        Ok(t) => t,
        Err(e) => {
            write_design(d)?;
            return Err(e);
        }
    };
    d.report.timings_ms.teeth = super::ms_since(t0);
    checked_and_exported(args, d, t, pending, files)
}

/// The mesh check of teeth cut (`pending`; none when `--verify-steps 0`) beside the CAD exports
/// (they do not read it); the design files are written when the check fails. Returns the train
/// (recorded in `d`'s report) and the CAD files written.
fn checked_and_exported(
    args: &Args,
    d: &mut ncgear::design::Design,
    mut t: ToothedTrain,
    pending: Option<PendingTrainMesh>,
    files: ncgear::output::DesignFiles,
) -> Result<(ToothedTrain, Vec<PathBuf>), super::Failure> {
    let write_design = |d: &ncgear::design::Design| {
        ncgear::output::write_design_with(d, &args.out, files)
            .map_err(|e| runtime_error(miette::miette!("{e}")))
    };
    // The mesh check runs beside the CAD exports (they do not read it).
    let pb = progress_bar(2 * args.verify_steps as u64, "mesh check");
    let ((mesh, t_mesh), (exports, t_files)) = rayon::join(
        || {
            let t0 = std::time::Instant::now();
            (
                pending.map(|p| p.run(&super::bar_sink(&pb))).transpose(),
                super::ms_since(t0),
            )
        },
        || {
            let t0 = std::time::Instant::now();
            let r = (|| -> Result<Vec<PathBuf>, super::Failure> {
                let mut files =
                    ncgear::output::write_teeth(&mut t, &args.out, args.rack.dxf_version.into())
                        .map_err(|e| runtime_error(miette::miette!("{e}")))?;
                let step = ncgear::output::write_teeth_step(&t, &args.out, &args.rack.solids())
                    .map_err(|e| match &e {
                        ncgear::output::OutputError::Export(x) => {
                            super::teeth_args::step_failure(x)
                        }
                        _ => runtime_error(miette::miette!("{e}")),
                    })?;
                t.report
                    .files
                    .extend(step.iter().map(|p| p.display().to_string()));
                files.extend(step);
                Ok(files)
            })();
            (r, super::ms_since(t0))
        },
    );
    pb.finish_and_clear();
    d.report.timings_ms.verification = t_mesh;
    d.report.timings_ms.cad_files = t_files;
    match mesh {
        Ok(mesh) => t.report.mesh = mesh,
        Err(e) => {
            write_design(d)?;
            return Err(runtime_error(miette::miette!("{e}")));
        }
    }
    let written = exports?;
    // The report now lists the CAD files.
    t.record(d);
    Ok((t, written))
}

/// The console summary of design report `r` of trajectory `file`: arms, compatibility, routes,
/// round trip, gear limits, checks, warnings, the teeth when cut, the time and the files.
fn print_summary(
    file: &str,
    r: &ncgear::design::DesignReport,
    train: Option<&ToothedTrain>,
    written: &[PathBuf],
    out: &std::path::Path,
    started: std::time::Instant,
) {
    println!(
        "{file}: {} points, carrier {}",
        r.trajectory.points,
        if r.carrier.direction > 0 { "CCW" } else { "CW" }
    );
    println!(
        "  l1 = {:.6} mm, l3 = {:.6} mm, a = {:.6} mm, needle angle {:.4}°{}",
        r.l1_mm,
        r.l3_mm,
        r.center_distance_mm,
        r.needle_angle_deg,
        if r.idler_offset_deg == 0.0 {
            String::new()
        } else {
            format!(
                ", intermediate axis {:.4}° off the carrier line (l1 = 2a·cos ε)",
                r.idler_offset_deg
            )
        }
    );
    println!(
        "  compatibility: E_c·l3 = {:.4} mm at τ = {:.3}°",
        r.compatibility.tip_equivalent_mm, r.compatibility.tau_deg
    );
    println!(
        "  patent route: K = {}, max deviation {:.4} mm",
        r.patent_route.order, r.patent_route.max_deviation_mm
    );
    if let Some(f) = &r.refinement {
        println!(
            "  refinement:   K = {}, max deviation {:.4} mm ({})",
            f.order, f.max_deviation_mm, f.note
        );
    }
    println!(
        "  round trip from the output curves ({}): max deviation {:.4} mm, Hausdorff {:.4} mm",
        r.chosen, r.roundtrip.max_deviation_mm, r.roundtrip.hausdorff_mm
    );
    println!("{}", limits_line(&r.limits));
    let failed: Vec<&str> = r
        .checks
        .iter()
        .filter(|c| !c.pass)
        .map(|c| c.id.as_str())
        .collect();
    println!(
        "  checks C1–C13: {}",
        if failed.is_empty() {
            "all pass".to_string()
        } else {
            format!("FAILED {}", failed.join(", "))
        }
    );
    for w in &r.warnings {
        println!("  warning: {w}");
    }
    if let Some(t) = train {
        print_teeth(&t.report);
    }
    let teeth_dir = out.join("teeth");
    let (teeth, rest): (Vec<_>, Vec<_>) = written.iter().partition(|p| p.starts_with(&teeth_dir));
    let tm = &r.timings_ms;
    println!(
        "  {:.1} ms (design {:.1}, teeth {:.1}, verification {:.1} beside CAD files {:.1}, design \
         files {:.1}); wrote {}{}",
        super::ms_since(started),
        tm.total,
        tm.teeth,
        tm.verification,
        tm.cad_files,
        super::ms_since(started) - tm.command,
        rest.iter()
            .map(|p| p.display().to_string())
            .collect::<Vec<_>>()
            .join(", "),
        if teeth.is_empty() {
            String::new()
        } else {
            format!(" and {} CAD files in {}", teeth.len(), teeth_dir.display())
        }
    );
}

/// The console line of the design's gear limits: where it stands and what binds.
fn limits_line(l: &ncgear::design::LimitsSummary) -> String {
    format!(
        "  gear limits{}: pressure angle {:.2}° (≤ {}°), tightest concave radius {} (≥ {} mm), tightest convex radius {:.2} mm{}, i21 in [{:.3}, {:.3}]{}",
        if l.enabled {
            ""
        } else {
            " (off: not constraints)"
        },
        l.pressure_angle_deg,
        l.max_pressure_angle_deg,
        l.tightest_concave_radius_mm
            .map_or_else(|| "none (convex)".into(), |v| format!("{v:.2} mm")),
        l.min_concave_radius_mm,
        l.tightest_convex_radius_mm,
        l.min_convex_radius_mm
            .map_or_else(String::new, |v| format!(" (≥ {v} mm)")),
        l.ratio_range[0],
        l.ratio_range[1],
        if l.binding.is_empty() {
            String::new()
        } else {
            format!("; binding: {}", l.binding.join(", "))
        }
    )
}

/// The console lines of the toothed train: tooth count and deviation, processes, undercut, meshes.
fn print_teeth(t: &TrainTeethReport) {
    println!(
        "  teeth: z = {}, m = {:.4} mm, a = {:.6} mm (scale {:.6}, ratio amplitude {:.6}); \
         the toothed train traces {:.4} mm from the target, Hausdorff {:.4} mm (the designed \
         gears: {:.4} mm, Hausdorff {:.4} mm)",
        t.z,
        t.module_mm,
        t.center_distance_mm,
        t.scale,
        t.ratio_amplitude,
        t.roundtrip.max_deviation_mm,
        t.roundtrip.hausdorff_mm,
        t.roundtrip.before_max_deviation_mm,
        t.roundtrip.before_hausdorff_mm
    );
    if let Some(g) = t.needle_angle_deg {
        println!(
            "  needle angle γ re-fitted for the rescaled ratio: {g:.4}° (replaces the design's)"
        );
    }
    for w in &t.warnings {
        println!("  warning: {w}");
    }
    if let Some(p) = &t.process {
        for (name, g) in [
            ("sun", &p.sun),
            ("intermediate", &p.intermediate),
            ("planet", &p.planet),
        ] {
            println!("  {name}: {}", super::teeth_args::process_line(g));
        }
    }
    let p = t.process.as_ref();
    for (name, u, g) in [
        ("sun", &t.undercut.sun, p.map(|p| &p.sun)),
        (
            "intermediate",
            &t.undercut.intermediate,
            p.map(|p| &p.intermediate),
        ),
        ("planet", &t.undercut.planet, p.map(|p| &p.planet)),
    ] {
        if let Some(w) = super::teeth_args::undercut_line(name, u, g) {
            println!("  {w}");
        }
    }
    if let Some(mesh) = &t.mesh {
        for (name, m) in [
            ("sun-intermediate", &mesh.sun_intermediate),
            ("intermediate-planet", &mesh.intermediate_planet),
        ] {
            println!("  mesh {name}: {}", m.summary());
        }
    }
}

/// The CLI failure for a design error on trajectory `file`: the flag behind a bad option, the
/// `--center` hint when the axis does not fit the trajectory.
pub(super) fn design_failure(file: &str, e: &DesignError) -> super::Failure {
    match e {
        DesignError::Internal(_) => runtime_error(miette::miette!("{file}: {e}")),
        DesignError::BadOption { option, .. } => super::option_error(Some(option), e),
        DesignError::Bounds(b) => super::option_error(Some(&b.quantity), e),
        DesignError::ConvexLimitUnreachable { module_mm, .. } => super::option_error(
            Some(match module_mm {
                Some(_) => "module_mm",
                None => "min_convex_radius_mm",
            }),
            format!("{file}: {e}"),
        ),
        DesignError::Inverse(
            InverseError::AxisInsideLoop { .. }
            | InverseError::TooCloseToAxis { .. }
            | InverseError::AxisTooFar { .. },
        ) => input_error(miette::miette!(
            help = "the carrier axis is set by --center X,Y (mm)",
            "{file}: {e}"
        )),
        _ => input_error(miette::miette!("{file}: {e}")),
    }
}

/// The tooth options of `--module` (rack, backlash, exports, policy), checked before any work.
fn teeth_options(args: &Args, module_mm: f64) -> Result<TrainTeethOptions, super::Failure> {
    if let Some(z) = args.teeth {
        ncgear::bounds::check_teeth("teeth", z)
            .map_err(|e| super::option_error(Some("teeth"), e))?;
    }
    args.rack.check_exports()?;
    toothing_at(args, module_mm).map_err(super::teeth_args::option_failure)
}

/// The tooth options the flags give at module `module_mm` (what `--module auto` cuts each
/// module it tries with).
fn toothing_at(
    args: &Args,
    module_mm: f64,
) -> Result<TrainTeethOptions, ncgear::teeth::TeethError> {
    let mut opts = TrainTeethOptions::new(module_mm);
    opts.toothing.verify_steps = args.verify_steps;
    opts.wire_edm = args.wire_edm;
    args.rack.apply_to(&mut opts.toothing)?;
    opts.toothing.validate()?;
    opts.policy = match (args.teeth, args.tooth_policy) {
        (Some(z), _) => TrainPolicy::ScaleCenterDistance(ToothPolicy::Exact(z)),
        (None, ToothPolicyArg::ScaleUp) => TrainPolicy::ScaleCenterDistance(ToothPolicy::ScaleUp),
        (None, ToothPolicyArg::Nearest) => TrainPolicy::ScaleCenterDistance(ToothPolicy::Nearest),
        (None, ToothPolicyArg::ScaleDown) => {
            TrainPolicy::ScaleCenterDistance(ToothPolicy::ScaleDown)
        }
        (None, ToothPolicyArg::RatioAmplitude) => TrainPolicy::RatioAmplitude,
        (None, ToothPolicyArg::AdjustModule) => TrainPolicy::AdjustModule,
        (None, ToothPolicyArg::Design) => TrainPolicy::Designed,
    };
    Ok(opts)
}

/// Without `--module` no teeth are made: a tooth or export option given would do nothing.
fn refuse_tooth_flags(args: &Args) -> Result<(), super::Failure> {
    let flag = args.rack.first_given().or_else(|| {
        [
            (args.verify_steps != DEFAULT_VERIFY_STEPS, "--verify-steps"),
            (
                !matches!(args.tooth_policy, ToothPolicyArg::Design),
                "--tooth-policy",
            ),
        ]
        .into_iter()
        .find_map(|(given, flag)| given.then_some(flag))
    });
    match flag {
        Some(flag) => Err(input_error(miette::miette!(
            help = "give --module M to put teeth on the gears, or leave the flag out",
            "{flag} sets the teeth, and no teeth are made without --module"
        ))),
        None => Ok(()),
    }
}

/// Teeth on the designed gears (`--module`), their mesh check still to run.
fn toothed(
    args: &Args,
    d: &ncgear::design::Design,
    module_mm: f64,
    opts: &TrainTeethOptions,
) -> Result<(ToothedTrain, Option<PendingTrainMesh>), super::Failure> {
    tooth_train_staged(d, opts).map_err(|e| match e {
        TrainError::Teeth {
            source: ncgear::teeth::TeethError::NoCutter { .. },
            ..
        } if !args.wire_edm => input_error(miette::miette!(
            help = "design within the gear limits (--limits on, the default; --min-concave-radius sets the hollow a cutter must fit), a smaller module, or --wire-edm to sweep the gear with its cut neighbours",
            "--module {module_mm}: {e}"
        )),
        TrainError::Teeth { .. }
        | TrainError::InvalidOption { .. }
        | TrainError::NotDesignedForModule { .. } => {
            input_error(miette::miette!("--module {module_mm}: {e}"))
        }
        _ => runtime_error(miette::miette!("{e}")),
    })
}
