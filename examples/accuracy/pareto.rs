//! Pareto plots of the accuracy-vs-time tables under `assets/accuracy/*.csv` (columns
//! `knob,value,measure,error,time_ms`): log10 error against log10 time, one series per knob,
//! points joined in sweep order. Writes `assets/accuracy/pareto.{png,svg}` (every knob) and
//! `assets/accuracy/pareto_<area>.{png,svg}` (one per CSV, readable legends).
use ncgear::output::plot::{ChartLabels, Series, line_chart};
use std::path::Path;

/// One knob's line: (knob, [(log10 ms, log10 error)]).
type KnobSeries = (String, Vec<(f64, f64)>);

/// Series of one CSV, in file order.
fn read_series(path: &Path) -> std::io::Result<Vec<KnobSeries>> {
    let text = std::fs::read_to_string(path)?;
    let mut out: Vec<KnobSeries> = Vec::new();
    for line in text.lines().skip(1) {
        let f: Vec<&str> = line.split(',').collect();
        if f.len() < 5 {
            continue;
        }
        let (Ok(err), Ok(ms)) = (f[f.len() - 2].parse::<f64>(), f[f.len() - 1].parse::<f64>())
        else {
            continue;
        };
        if !(err > 0.0 && ms > 0.0) {
            continue;
        }
        let p = (ms.log10(), err.log10());
        match out.iter_mut().find(|(k, _)| k == f[0]) {
            Some((_, v)) => v.push(p),
            None => out.push((f[0].to_string(), vec![p])),
        }
    }
    Ok(out)
}

fn draw(
    dir: &Path,
    stem: &str,
    title: &str,
    series: &[KnobSeries],
    size: (u32, u32),
) -> Result<(), Box<dyn std::error::Error>> {
    let all: Vec<Series> = series
        .iter()
        .map(|(k, v)| {
            if v.len() == 1 {
                Series::markers(k.clone(), v.clone())
            } else {
                Series::line(k.clone(), v.clone())
            }
        })
        .collect();
    let labels = ChartLabels {
        title: title.into(),
        x: "log10 time (ms)".into(),
        y: "log10 error (unit per knob, see the tables)".into(),
        equal_aspect: false,
    };
    for ext in ["png", "svg"] {
        line_chart(&dir.join(format!("{stem}.{ext}")), &labels, &all, size)?;
    }
    Ok(())
}

/// Redraws the plots from the CSVs.
pub fn plot() -> Result<(), Box<dyn std::error::Error>> {
    let dir = Path::new("assets/accuracy");
    let mut files: Vec<_> = std::fs::read_dir(dir)?
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e == "csv"))
        .collect();
    files.sort();
    let mut every = Vec::new();
    for path in files {
        let area = path
            .file_stem()
            .and_then(|s| s.to_str())
            .unwrap_or("area")
            .to_string();
        let series = read_series(&path)?;
        draw(
            dir,
            &format!("pareto_{area}"),
            &format!("What accuracy costs in time: {area}"),
            &series,
            (1000, 600),
        )?;
        every.extend(series);
    }
    draw(
        dir,
        "pareto",
        "What accuracy costs in time (each line: one knob, swept)",
        &every,
        (1400, 900),
    )
}
