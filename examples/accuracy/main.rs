//! What accuracy costs in time, for every knob of the tool that trades the two: one
//! module per area, each measuring its error against a reference (a closed form or a converged
//! run) and the median wall time of a few runs. Writes `assets/accuracy/<area>.csv` (columns
//! `knob,value,measure,error,time_ms`, no commas inside fields), prints one Markdown table per
//! area, and redraws the Pareto plot `assets/accuracy/pareto.{png,svg}` from every CSV there.
//!
//! Run everything (≈ 2–4 min on 2 cores):
//! `cargo run --release --example accuracy`
//! or some areas only (the plot is always redrawn from all CSVs):
//! `cargo run --release --example accuracy -- orbit teeth`
mod design;
mod dynamics;
mod orbit;
mod pareto;
mod teeth;
mod tolerance;

use std::fmt::Write as _;
use std::time::Instant;

/// One measured setting of one knob.
pub struct Row {
    /// Knob name (one series of the Pareto plot).
    pub knob: String,
    /// Setting.
    pub value: String,
    /// What the error measures, with its unit.
    pub measure: String,
    /// Error against the reference.
    pub error: f64,
    /// Median wall time, ms.
    pub time_ms: f64,
}

impl Row {
    /// A row.
    pub fn new(
        knob: impl Into<String>,
        value: impl ToString,
        measure: impl Into<String>,
        error: f64,
        time_ms: f64,
    ) -> Self {
        Self {
            knob: knob.into(),
            value: value.to_string(),
            measure: measure.into(),
            error,
            time_ms,
        }
    }
}

/// Median wall time (ms) of `reps` runs, and the last result.
pub fn timed<T>(reps: usize, mut f: impl FnMut() -> T) -> (f64, T) {
    let mut times = Vec::new();
    let mut last = None;
    for _ in 0..reps.max(1) {
        let t = Instant::now();
        last = Some(f());
        times.push(t.elapsed().as_secs_f64() * 1e3);
    }
    times.sort_by(f64::total_cmp);
    (times[times.len() / 2], last.expect("reps ≥ 1"))
}

fn write(area: &str, rows: &[Row]) -> std::io::Result<()> {
    let field = |s: &str| s.replace(',', ";");
    let mut md = format!(
        "\n### {area}\n\n| knob | value | error measure | error | time (ms) |\n|---|---|---|---|---|\n"
    );
    let mut csv = String::from("knob,value,measure,error,time_ms\n");
    let cell = |s: &str| s.replace('|', "\\|");
    for r in rows {
        let _ = writeln!(
            md,
            "| {} | {} | {} | {:.2e} | {:.3} |",
            cell(&r.knob),
            cell(&r.value),
            cell(&r.measure),
            r.error,
            r.time_ms
        );
        let _ = writeln!(
            csv,
            "{},{},{},{:e},{:.4}",
            field(&r.knob),
            field(&r.value),
            field(&r.measure),
            r.error,
            r.time_ms
        );
    }
    print!("{md}");
    std::fs::create_dir_all("assets/accuracy")?;
    std::fs::write(format!("assets/accuracy/{area}.csv"), csv)
}

type Area = (&'static str, fn() -> Vec<Row>);

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let areas: [Area; 5] = [
        ("design", design::rows),
        ("tolerance", tolerance::rows),
        ("orbit", orbit::rows),
        ("teeth", teeth::rows),
        ("dynamics", dynamics::rows),
    ];
    let wanted: Vec<String> = std::env::args().skip(1).collect();
    for name in &wanted {
        if !areas.iter().any(|(a, _)| a == name) {
            return Err(format!(
                "unknown area `{name}` (expected design, tolerance, orbit, teeth, dynamics)"
            )
            .into());
        }
    }
    let t_all = Instant::now();
    for (name, rows) in areas {
        if wanted.is_empty() || wanted.iter().any(|w| w == name) {
            let t = Instant::now();
            write(name, &rows())?;
            eprintln!("{name}: {:.1} s", t.elapsed().as_secs_f64());
        }
    }
    pareto::plot()?;
    eprintln!("total: {:.1} s", t_all.elapsed().as_secs_f64());
    Ok(())
}
