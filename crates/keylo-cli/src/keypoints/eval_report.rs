//! The tables and plots of `keylo keypoints eval` (one process's or merged shards').

use std::path::Path;
use std::process::ExitCode;

use anyhow::{Context, Result};
use keylo::kpeval::reference::Reference;
use keylo::kpeval::{summarise, EvalSpec, Row, METRICS};

use super::plots;
use super::plots::{BoxPlot, BoxRow};
use super::report::{self, PaperFigures};
use crate::EXIT_FRAME_FAILED;

/// One line per distinct reason: "Skipped A, B: reason".
pub fn skip_notes(skipped: &[(String, String)]) -> Vec<String> {
    let mut by_reason: Vec<(&str, Vec<&str>)> = Vec::new();
    for (combo, why) in skipped {
        match by_reason.iter_mut().find(|(w, _)| *w == why) {
            Some((_, v)) => v.push(combo),
            None => by_reason.push((why, vec![combo])),
        }
    }
    by_reason
        .into_iter()
        .map(|(why, combos)| format!("Skipped {}: {why}", combos.join(", ")))
        .collect()
}

/// What an evaluation's tables and plots are made of (one process's, or merged shards').
pub(crate) struct EvalReport<'a> {
    pub rows: &'a [Row],
    pub skipped: &'a [(String, String)],
    pub failed: &'a [(String, String)],
    pub spec: &'a EvalSpec,
    /// The images' labels, in order.
    pub images: &'a [String],
    pub jobs: usize,
    pub seconds: f64,
    pub paper: Option<&'a PaperFigures>,
    pub reference: Option<&'a Reference>,
}

/// per_image.csv, summary.csv/.md/.json, reference.csv/.md and the box plots, into `out`;
/// exit status 3 when a combination group failed.
pub(crate) fn write_report(
    out: &Path,
    r: &EvalReport,
    no_plots: bool,
    quiet: bool,
) -> Result<ExitCode> {
    let summaries = summarise(r.rows);
    let mut notes = vec![format!(
        "{} images ({}×{}, {}), {} combinations, {} jobs, {:.1} s.",
        r.images.len(),
        r.rows.first().map_or(0, |r| r.width),
        r.rows.first().map_or(0, |r| r.height),
        keylo::kpeval::sweep::interpolation_name(r.spec.image.interpolation),
        summaries.len(),
        r.jobs,
        r.seconds
    )];
    notes.extend(skip_notes(r.skipped));
    notes.extend(r.failed.iter().map(|(c, why)| format!("FAILED {c}: {why}")));
    let write = |name: &str, text: &str| {
        let p = out.join(name);
        crate::atomic::write(&p, text).with_context(|| format!("writing {}", p.display()))
    };
    write("per_image.csv", &report::per_image_csv(r.rows))?;
    write("summary.csv", &report::summary_csv(&summaries, r.paper))?;
    let mut md = report::markdown(&summaries, r.paper, &notes);
    write("summary.md", &md)?;
    if let Some(reference) = r.reference {
        let agreements = keylo::kpeval::reference::agreement(r.rows, reference);
        let table = super::reference::markdown(&agreements);
        write("reference.csv", &super::reference::csv(&agreements))?;
        write("reference.md", &table)?;
        md.push_str("\n## Against the authors' per-image results\n\n");
        md.push_str(&table);
    }
    let json = serde_json::json!({
        "settings": r.spec,
        "images": r.images,
        "jobs": r.jobs,
        "seconds": r.seconds,
        "combos": summaries,
        "skipped": r.skipped,
        "failed": r.failed,
    });
    write("summary.json", &serde_json::to_string_pretty(&json)?)?;
    if !no_plots {
        for m in METRICS {
            let rows: Vec<BoxRow> = summaries
                .iter()
                .filter_map(|s| {
                    s.get(m.key).map(|q| BoxRow {
                        name: s.combo.clone(),
                        min: q.min,
                        q1: q.q1,
                        median: q.median,
                        q3: q.q3,
                        max: q.max,
                    })
                })
                .collect();
            if rows.is_empty() {
                continue;
            }
            let height = (120 + 26 * rows.len()).clamp(300, 2000) as u32;
            let fig = BoxPlot {
                title: format!("{} ({} images)", m.label, r.images.len()),
                x_label: m.label.to_string(),
                rows,
            };
            plots::write(&out.join("plots"), m.key, (960, height), &fig)?;
        }
    }
    if !quiet {
        print!("{md}");
        println!("\nresults in {}", out.display());
    }
    if !r.failed.is_empty() {
        eprintln!(
            "error: {} combination group(s) failed; their results up to the failure are kept",
            r.failed.len()
        );
        return Ok(ExitCode::from(EXIT_FRAME_FAILED));
    }
    Ok(ExitCode::SUCCESS)
}
