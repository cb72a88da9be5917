//! The tables and heat maps of `keylo keypoints sweep` (one process's or merged shards').

use std::fmt::Write as _;
use std::path::Path;
use std::process::ExitCode;

use anyhow::{Context, Result};
use keylo::kpeval::sweep::{interpolation_name, CellResult, SweepGrid, SweepResult};
use keylo::kpeval::{EvalSpec, Metric, METRICS};

use super::eval_report::skip_notes;
use super::plots;
use super::plots::HeatMap;
use crate::EXIT_FRAME_FAILED;

/// The mean over combinations of one metric, for the results matching `keep`.
fn mean_of(results: &[&CellResult], key: &str) -> Option<f64> {
    let v: Vec<f64> = results.iter().filter_map(|r| r.mean(key)).collect();
    (!v.is_empty()).then(|| v.iter().sum::<f64>() / v.len() as f64)
}

/// `(label, results)` groups of `results` by `key`, in first-seen order.
fn group_by<K: PartialEq + Clone>(
    results: &[CellResult],
    key: impl Fn(&CellResult) -> K,
) -> Vec<(K, Vec<&CellResult>)> {
    let mut out: Vec<(K, Vec<&CellResult>)> = Vec::new();
    for r in results {
        let k = key(r);
        match out.iter_mut().find(|(g, _)| *g == k) {
            Some((_, v)) => v.push(r),
            None => out.push((k, vec![r])),
        }
    }
    out
}

/// The overall criterion of the paper: distinctiveness and match score first.
fn overall(results: &[&CellResult]) -> Option<f64> {
    Some((mean_of(results, "distinctiveness")? + mean_of(results, "match_score")?) / 2.0)
}

fn better(m: &Metric, a: f64, b: f64) -> bool {
    if m.higher_is_better {
        a > b
    } else {
        a < b
    }
}

fn table<K: std::fmt::Display>(title: &str, groups: &[(K, Vec<&CellResult>)]) -> String {
    let mut out = format!("\n### {title}\n\n| |");
    for m in METRICS {
        let _ = write!(out, " {} |", m.key);
    }
    out.push_str(" overall |\n|---|");
    for _ in 0..=METRICS.len() {
        out.push_str("---:|");
    }
    out.push('\n');
    for (k, rs) in groups {
        let _ = write!(out, "| {k} |");
        for m in METRICS {
            let v = mean_of(rs, m.key).map_or("–".into(), |v| format!("{v:.3}"));
            let _ = write!(out, " {v} |");
        }
        let v = overall(rs).map_or("–".into(), |v| format!("{v:.3}"));
        let _ = writeln!(out, " {v} |");
    }
    out
}

/// The optimum cell per metric and overall (the paper's criterion), as a Markdown table and
/// as JSON (`metric → {cell, value}`).
fn optima(
    by_cell: &[(String, Vec<&CellResult>)],
) -> (String, serde_json::Map<String, serde_json::Value>) {
    let mut md = String::from("### Optimum per metric (mean over the combinations)\n\n| metric | best cell | value |\n|---|---|---:|\n");
    let mut optima = serde_json::Map::new();
    for m in METRICS {
        let best = by_cell
            .iter()
            .filter_map(|(c, rs)| mean_of(rs, m.key).map(|v| (c, v)))
            .fold(None, |acc: Option<(&String, f64)>, (c, v)| match acc {
                Some((_, b)) if !better(m, v, b) => acc,
                _ => Some((c, v)),
            });
        if let Some((c, v)) = best {
            let _ = writeln!(md, "| {} | {c} | {v:.4} |", m.key);
            optima.insert(m.key.into(), serde_json::json!({"cell": c, "value": v}));
        }
    }
    let best_overall = by_cell
        .iter()
        .filter_map(|(c, rs)| overall(rs).map(|v| (c, v)))
        .fold(None, |acc: Option<(&String, f64)>, (c, v)| match acc {
            Some((_, b)) if v <= b => acc,
            _ => Some((c, v)),
        });
    if let Some((c, v)) = best_overall {
        let _ = writeln!(
            md,
            "| **overall** (mean of distinctiveness and match score, the paper's criterion) | **{c}** | {v:.4} |"
        );
        optima.insert("overall".into(), serde_json::json!({"cell": c, "value": v}));
    }
    (md, optima)
}

/// What a sweep's tables and plots are made of (one process's, or merged shards').
pub(crate) struct SweepReport<'a> {
    pub grid: &'a SweepGrid,
    pub spec: &'a EvalSpec,
    /// Images per cell.
    pub images: usize,
    pub jobs: usize,
    pub result: &'a SweepResult,
}

/// sweep.md, sweep.json and the heat maps, into `out`; exit status 3 when a task failed.
pub(crate) fn write_report(
    out: &Path,
    r: &SweepReport,
    no_plots: bool,
    quiet: bool,
) -> Result<ExitCode> {
    let (grid, result) = (r.grid, r.result);
    let cell_label = |r: &CellResult| format!("{} {}x{}", r.interpolation, r.width, r.height);
    let by_cell = group_by(&result.results, cell_label);
    let mut md = String::from("## Keypoint sweep\n\n");
    let _ = writeln!(
        md,
        "{} images per cell, {} cells × {} detector groups ({} run now, {} resumed), {} jobs; \
         {} image evaluations in {:.1} s ({:.1} per second).\n",
        r.images,
        grid.cells().len(),
        (result.tasks_run + result.tasks_resumed) / grid.cells().len().max(1),
        result.tasks_run,
        result.tasks_resumed,
        r.jobs,
        result.images_evaluated,
        result.seconds,
        result.images_evaluated as f64 / result.seconds.max(1e-9)
    );
    let (optimum_table, optima) = optima(&by_cell);
    md.push_str(&optimum_table);
    md.push_str(&table(
        "By interpolation (mean over sizes and combinations)",
        &group_by(&result.results, |r| r.interpolation.clone()),
    ));
    md.push_str(&table(
        "By resolution (mean over interpolations and combinations)",
        &group_by(&result.results, |r| format!("{}x{}", r.width, r.height)),
    ));
    for note in skip_notes(&result.skipped) {
        let _ = writeln!(md, "\n{note}");
    }
    for (c, why) in &result.failed {
        let _ = writeln!(md, "\nFAILED {c}: {why}");
    }
    let write = |name: &str, text: &str| {
        let p = out.join(name);
        crate::atomic::write(&p, text).with_context(|| format!("writing {}", p.display()))
    };
    write("sweep.md", &md)?;
    let json = serde_json::json!({
        "settings": r.spec,
        "images": r.images,
        "jobs": r.jobs,
        "seconds": result.seconds,
        "images_evaluated": result.images_evaluated,
        "tasks_run": result.tasks_run,
        "tasks_resumed": result.tasks_resumed,
        "optima": optima,
        "results": result.results,
        "skipped": result.skipped,
        "failed": result.failed,
    });
    write("sweep.json", &serde_json::to_string_pretty(&json)?)?;
    if !no_plots {
        for &interp in &grid.interpolations {
            let name = interpolation_name(interp);
            for m in METRICS {
                let values: Vec<Vec<Option<f64>>> = grid
                    .heights
                    .iter()
                    .map(|&h| {
                        grid.widths
                            .iter()
                            .map(|&w| {
                                let rs: Vec<&CellResult> = result
                                    .results
                                    .iter()
                                    .filter(|r| {
                                        r.interpolation == name && r.width == w && r.height == h
                                    })
                                    .collect();
                                mean_of(&rs, m.key)
                            })
                            .collect()
                    })
                    .collect();
                let fig = HeatMap {
                    title: format!("{} — {name}", m.label),
                    widths: grid.widths.clone(),
                    heights: grid.heights.clone(),
                    values,
                };
                plots::write(
                    &out.join("plots"),
                    &format!("{name}-{}", m.key),
                    (960, 560),
                    &fig,
                )?;
            }
        }
    }
    if !quiet {
        print!("{md}");
        println!("\nresults in {}", out.display());
    }
    if !result.failed.is_empty() {
        return Ok(ExitCode::from(EXIT_FRAME_FAILED));
    }
    Ok(ExitCode::SUCCESS)
}
