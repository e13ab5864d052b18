//! Pareto plot of every accuracy-vs-time table under `assets/accuracy/*.csv` (columns
//! `knob,value,measure,error,time_ms`): log10 error against log10 time, one series per knob.
//! Writes `assets/accuracy/pareto.png` and `.svg`.
use ncgear::plot::{ChartLabels, Series, line_chart};
use std::collections::BTreeMap;
use std::path::Path;

/// Redraws the plot from the CSVs.
pub fn plot() -> Result<(), Box<dyn std::error::Error>> {
    let dir = Path::new("assets/accuracy");
    let mut series: BTreeMap<String, Vec<(f64, f64)>> = BTreeMap::new();
    let mut files: Vec<_> = std::fs::read_dir(dir)?
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e == "csv"))
        .collect();
    files.sort();
    for path in files {
        let text = std::fs::read_to_string(&path)?;
        for line in text.lines().skip(1) {
            let f: Vec<&str> = line.split(',').collect();
            if f.len() < 5 {
                continue;
            }
            let (Ok(err), Ok(ms)) = (f[f.len() - 2].parse::<f64>(), f[f.len() - 1].parse::<f64>())
            else {
                continue;
            };
            if err > 0.0 && ms > 0.0 {
                series
                    .entry(f[0].to_string())
                    .or_default()
                    .push((ms.log10(), err.log10()));
            }
        }
    }
    let all: Vec<Series> = series
        .into_iter()
        .map(|(k, mut v)| {
            v.sort_by(|a, b| a.0.total_cmp(&b.0));
            Series::line(k, v)
        })
        .collect();
    let labels = ChartLabels {
        title: "What accuracy costs in time (each line: one knob, swept)".into(),
        x: "log10 time (ms)".into(),
        y: "log10 error (unit per knob, see the tables)".into(),
        equal_aspect: false,
    };
    for ext in ["png", "svg"] {
        line_chart(
            &dir.join(format!("pareto.{ext}")),
            &labels,
            &all,
            (1100, 700),
        )?;
    }
    Ok(())
}
