//! Tables of a keypoint evaluation: per-image CSV, per-combination summary CSV/JSON and a
//! Markdown table of medians, with the paper's medians beside ours when given.

use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::Path;

use anyhow::{Context, Result};
use keylo::io::csv_table::table;
use keylo::kpeval::{csv_columns, ComboSummary, Quartiles, Row, METRICS};

/// The paper's quartiles per (figure, combination), from `paper-figure-medians.tsv`.
#[derive(Debug, Default)]
pub struct PaperFigures {
    map: HashMap<(String, String), (f64, f64, f64)>,
}

impl PaperFigures {
    /// Reads the TSV (`figure  combination  q1  median  q3` with a header line).
    pub fn read(path: &Path) -> Result<Self> {
        let text = std::fs::read_to_string(path)
            .with_context(|| format!("--paper {}: cannot read", path.display()))?;
        let mut map = HashMap::new();
        for (n, line) in text.lines().enumerate().skip(1) {
            let f: Vec<&str> = line.split('\t').collect();
            let num = |s: &str| s.trim().parse::<f64>().ok();
            match f.as_slice() {
                [fig, combo, q1, med, q3] => {
                    let (Some(q1), Some(med), Some(q3)) = (num(q1), num(med), num(q3)) else {
                        anyhow::bail!(
                            "--paper {} line {}: expected numbers in columns 3–5",
                            path.display(),
                            n + 1
                        );
                    };
                    map.insert(
                        (fig.to_string(), combo.to_ascii_uppercase()),
                        (q1, med, q3),
                    );
                }
                [] | [""] => {}
                _ => anyhow::bail!(
                    "--paper {} line {}: expected 5 tab-separated columns (figure, combination, q1, median, q3)",
                    path.display(),
                    n + 1
                ),
            }
        }
        Ok(Self { map })
    }

    /// The paper's (q1, median, q3) of `metric` for `summary`'s combination: per-detector
    /// figures are listed under the detector, the others under DETECTOR_DESCRIPTOR, and the
    /// paper's SuperPoint under `Superpoint`.
    pub fn get(&self, metric: &str, s: &ComboSummary) -> Option<(f64, f64, f64)> {
        let m = keylo::kpeval::Metric::by_key(metric)?;
        if m.paper_figure.is_empty() {
            return None;
        }
        let det = s
            .combo
            .split('_')
            .next()
            .unwrap_or_default()
            .to_ascii_uppercase();
        let key = if det == "SUPERPOINT" || m.per_detector {
            det
        } else {
            s.combo.to_ascii_uppercase()
        };
        self.map.get(&(m.paper_figure.to_string(), key)).copied()
    }
}

/// `per_image.csv`.
pub fn per_image_csv(rows: &[Row]) -> String {
    let header: Vec<&str> = csv_columns().collect();
    table(&header, rows.iter().map(Row::record))
}

fn num(v: f64) -> String {
    if v.abs() >= 100.0 {
        format!("{v:.0}")
    } else if v.abs() >= 10.0 {
        format!("{v:.1}")
    } else {
        format!("{v:.3}")
    }
}

/// `summary.csv`: one line per combination and metric.
pub fn summary_csv(summaries: &[ComboSummary], paper: Option<&PaperFigures>) -> String {
    const HEADER: [&str; 14] = [
        "combo",
        "detector",
        "descriptor",
        "metric",
        "n",
        "min",
        "q1",
        "median",
        "q3",
        "max",
        "mean",
        "paper_q1",
        "paper_median",
        "paper_q3",
    ];
    let mut records = Vec::new();
    for s in summaries {
        for (key, q) in &s.metrics {
            let p = paper.and_then(|p| p.get(key, s));
            let pf = |v: Option<f64>| v.map_or_else(String::new, |v| v.to_string());
            records.push([
                s.combo.clone(),
                s.detector.clone(),
                s.descriptor.clone(),
                key.to_string(),
                q.n.to_string(),
                q.min.to_string(),
                q.q1.to_string(),
                q.median.to_string(),
                q.q3.to_string(),
                q.max.to_string(),
                q.mean.to_string(),
                pf(p.map(|x| x.0)),
                pf(p.map(|x| x.1)),
                pf(p.map(|x| x.2)),
            ]);
        }
    }
    table(&HEADER, records)
}

/// `summary.md`: medians per combination (paper medians in parentheses when known).
pub fn markdown(
    summaries: &[ComboSummary],
    paper: Option<&PaperFigures>,
    notes: &[String],
) -> String {
    let mut out = String::new();
    out.push_str("| combination |");
    for m in METRICS {
        let _ = write!(out, " {} |", m.key);
    }
    out.push('\n');
    out.push_str("|---|");
    for _ in METRICS {
        out.push_str("---:|");
    }
    out.push('\n');
    for s in summaries {
        let _ = write!(out, "| {} |", s.combo);
        for m in METRICS {
            let ours = s.get(m.key).map(|q: &Quartiles| num(q.median));
            let theirs = paper.and_then(|p| p.get(m.key, s)).map(|x| num(x.1));
            let cell = match (ours, theirs) {
                (Some(o), Some(t)) => format!("{o} ({t})"),
                (Some(o), None) => o,
                (None, Some(t)) => format!("– ({t})"),
                (None, None) => "–".into(),
            };
            let _ = write!(out, " {cell} |");
        }
        out.push('\n');
    }
    out.push_str("\nMedians over the evaluated images");
    if paper.is_some() {
        out.push_str("; the paper's medians in parentheses");
    }
    out.push_str(".\n");
    for n in notes {
        let _ = writeln!(out, "\n{n}");
    }
    out
}
