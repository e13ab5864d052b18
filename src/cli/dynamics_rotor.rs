//! `ncgear dynamics ROTOR.toml`: thin shell over `ncgear::analysis::dynamics::rotor`.
use super::{CliResult, Failure, input_error, print_json, progress_bar, runtime_error};
use ncgear::analysis::dynamics::rotor::{self, Prepared, RotorError, sweep::MAX_SWEEP_SPEEDS};
use ncgear::loads::scene::MAX_CARRIER_RPM;

fn rotor_err(e: RotorError) -> Failure {
    if e.is_input() {
        input_error(miette::miette!("{e}"))
    } else {
        runtime_error(miette::miette!("{e}"))
    }
}

/// Parses `--sweep-rpm A:B:STEP` (r/min, within (0, 3000], at most [`MAX_SWEEP_SPEEDS`]).
fn parse_sweep_rpm(s: &str) -> Result<Vec<f64>, Failure> {
    let bad = |why: String| {
        input_error(miette::miette!(
            "--sweep-rpm `{s}`: {why}; expected START:END:STEP in r/min, e.g. 100:400:10"
        ))
    };
    let p: Vec<f64> = s
        .split(':')
        .map(|x| x.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| bad("three numbers separated by `:`".into()))?;
    let [a, b, h] = p[..] else {
        return Err(bad("three numbers separated by `:`".into()));
    };
    if !(a > 0.0 && b >= a && b <= MAX_CARRIER_RPM && h > 0.0 && h.is_finite()) {
        return Err(bad(format!(
            "the speeds must lie in (0, {MAX_CARRIER_RPM}] r/min with START ≤ END and STEP > 0"
        )));
    }
    let count = ((b - a) / h + 1e-9).floor() as usize + 1;
    if count > MAX_SWEEP_SPEEDS {
        return Err(bad(format!(
            "{count} speeds, more than a sweep may run ({MAX_SWEEP_SPEEDS}, each a steady \
             state): take a larger STEP"
        )));
    }
    Ok((0..count).map(|i| a + h * i as f64).collect())
}

/// Runs a rotor scene: the run log, the steady state (exit 3 when it does not settle),
/// `dynamics.json` and its charts, and with `sweep_rpm` the sweep's table (`sweep.csv`, its
/// chart), all written by `ncgear::output`.
pub fn run(args: &super::dynamics::Args) -> CliResult {
    let prepared = Prepared::from_path(&args.scene).map_err(rotor_err)?;
    let sweep = args.sweep_rpm.as_deref().map(parse_sweep_rpm).transpose()?;
    if args.sweep.is_some() {
        return Err(input_error(miette::miette!(
            "--sweep is the spur model's frequency-ratio sweep: a rotor scene sweeps the \
             carrier speed with --sweep-rpm START:END:STEP"
        )));
    }
    if args.format.is_some() {
        return Err(input_error(miette::miette!(
            "--format picks the plot format of a spur scene: a rotor scene's charts are SVG, \
             and also PNG with --png"
        )));
    }
    std::fs::create_dir_all(&args.out)
        .map_err(|e| runtime_error(miette::miette!("cannot create {}: {e}", args.out.display())))?;
    let c = &prepared.case;
    eprintln!("scene `{}` ({}), rotor model", c.name, args.scene.display());
    if prepared.built.model.has_drive() {
        eprintln!(
            "DOFs: per train the intermediate's Δθ2 and the planet's Δθ3, and the carrier on its \
             shaft (every arm integrated)"
        );
    } else {
        eprintln!(
            "DOFs per train: intermediate Δθ2, planet Δθ3 (the carrier at exactly the scene's \
             speed)"
        );
    }
    for line in &prepared.built.effects_log {
        eprintln!("effect: {line}");
    }
    let f = prepared.built.model.natural_frequencies_hz();
    eprintln!(
        "natural frequencies (linearised, mean stiffness) [Hz]: {:.1}, {:.1}",
        f[0], f[1]
    );
    if let Some(rpm) = sweep {
        let pb = progress_bar(rpm.len() as u64, "speeds");
        let rows = rotor::sweep_rpm(&prepared, &rpm, &super::bar_sink(&pb)).map_err(rotor_err)?;
        pb.finish_and_clear();
        eprint!("{}", ncgear::output::rotor_sweep_table(&rows));
        ncgear::output::write_rotor_sweep(&rows, &args.out, args.png)
            .map_err(|e| runtime_error(miette::miette!("{e}")))?;
        eprintln!("sweep written to {}", args.out.join("sweep.csv").display());
        if args.json {
            print_json(&rows)?;
        }
        return Ok(());
    }
    let pb = progress_bar(u64::from(c.settings.max_turns), "turns");
    let run = prepared.run(&super::bar_sink(&pb)).map_err(rotor_err)?;
    pb.finish_and_clear();
    let r = &run.report;
    ncgear::output::write_rotor(r, &args.out, args.png)
        .map_err(|e| runtime_error(miette::miette!("{e}")))?;
    eprintln!(
        "steady state: {} turns, periodic residual {:.2e} (tolerance {:.0e}); {} RHS evaluations, {} events",
        r.steady.turns, r.steady.residual, r.steady.poincare_tol, r.stats.rhs_evals, r.stats.events
    );
    for (name, m) in [
        ("sun–intermediate", &r.summary.meshes.sun_intermediate),
        ("intermediate–planet", &r.summary.meshes.intermediate_planet),
    ] {
        eprintln!(
            "{name}: dynamic factor {:.4} (ISO K_v {}), {} impacts a turn{}",
            m.dynamic_factor,
            m.iso_k_v.map_or("—".to_string(), |k| format!("{k:.4}")),
            m.impacts_per_turn,
            m.impacts
                .iter()
                .map(|i| format!(
                    "; at {:.1}°: {:.4} m/s, peak {:.1} N",
                    i.travel_deg, i.speed_m_s, i.peak_force_n
                ))
                .collect::<String>()
        );
    }
    eprintln!(
        "largest tip deviation {:.4} mm at {:.1}°",
        r.summary.max_tip_deviation_mm, r.summary.max_tip_deviation_at_deg
    );
    eprintln!("charts written to {}", args.out.display());
    eprintln!(
        "report written to {}",
        args.out.join("dynamics.json").display()
    );
    if args.json {
        print_json(r)?;
    }
    if !r.steady.settled {
        return Err(Failure::Verification(miette::miette!(
            "the rotor did not settle in {} turns: periodic residual {:.3e} above the tolerance \
             {:.1e}; raise [steady] max_turns or the damping",
            r.steady.turns,
            r.steady.residual,
            r.steady.poincare_tol
        )));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::parse_sweep_rpm;

    #[test]
    fn a_speed_sweep_is_bounded() {
        assert_eq!(parse_sweep_rpm("100:400:10").unwrap().len(), 31);
        assert!(parse_sweep_rpm("0:100:10").is_err());
        assert!(parse_sweep_rpm("100:3100:10").is_err());
        assert!(parse_sweep_rpm("1:3000:1").is_err());
        assert_eq!(parse_sweep_rpm("300:300:1").unwrap(), vec![300.0]);
    }
}
