//! `keylo keypoints eval`: per-image results, per-combination summaries (CSV, JSON,
//! Markdown) and a box plot per metric.

use std::process::ExitCode;

use anyhow::{Context, Result};
use indicatif::{ProgressBar, ProgressStyle};
use keylo::kpeval::sweep::parse_interpolation;
use keylo::kpeval::{evaluate, summarise, EvalOptions, METRICS};
use keylo::BuildContext;

use super::plots::{BoxPlot, BoxRow};
use super::report::{self, PaperFigures};
use super::{input, plots, EvalArgs};
use crate::EXIT_FRAME_FAILED;

/// A progress bar with an ETA (hidden when quiet).
pub fn progress(quiet: bool, what: &str) -> ProgressBar {
    if quiet {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::new(0);
    let style = ProgressStyle::with_template(&format!(
        "{what} [{{bar:30}}] {{pos}}/{{len}} {{msg}} elapsed {{elapsed}} ETA {{eta}}"
    ))
    .unwrap_or_else(|_| ProgressStyle::default_bar());
    bar.set_style(style);
    bar
}

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

pub fn run(args: EvalArgs, threads: Option<usize>, quiet: bool) -> Result<ExitCode> {
    let mut spec = input::spec(&args.input)?;
    if let Some(w) = args.width {
        spec.image.width = w;
    }
    if let Some(h) = args.height {
        spec.image.height = h;
    }
    if let Some(i) = &args.interpolation {
        spec.image.interpolation = parse_interpolation(i)?;
    }
    let paper = args.paper.as_deref().map(PaperFigures::read).transpose()?;
    // Read before the (long) evaluation, so a wrong folder fails at once.
    let reference = args
        .reference
        .as_deref()
        .map(keylo::kpeval::reference::Reference::read_dir)
        .transpose()?;
    let input::Prepared {
        registry,
        set,
        combos,
        planes,
        jobs,
    } = input::prepare(&args.input, &spec, threads)?;
    let out = &args.input.out;
    let bar = progress(quiet, "evaluating");
    let tick = |done: usize, total: usize| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
    };
    let ctx = BuildContext {
        base_dir: args
            .input
            .config
            .as_ref()
            .and_then(|p| p.parent().map(std::path::Path::to_path_buf))
            .unwrap_or_default(),
    };
    let result = evaluate(
        &planes,
        &combos,
        &spec,
        &registry,
        &ctx,
        &EvalOptions {
            jobs,
            skip_unavailable: set.skips_unavailable(),
            progress: Some(&tick),
        },
    )?;
    bar.finish_and_clear();
    let summaries = summarise(&result.rows);
    let mut notes = vec![format!(
        "{} images ({}×{}, {}), {} combinations, {} jobs, {:.1} s.",
        planes.len(),
        result.rows.first().map_or(0, |r| r.width),
        result.rows.first().map_or(0, |r| r.height),
        keylo::kpeval::sweep::interpolation_name(spec.image.interpolation),
        summaries.len(),
        jobs,
        result.seconds
    )];
    notes.extend(skip_notes(&result.skipped));
    notes.extend(
        result
            .failed
            .iter()
            .map(|(c, why)| format!("FAILED {c}: {why}")),
    );
    let write = |name: &str, text: &str| {
        let p = out.join(name);
        std::fs::write(&p, text).with_context(|| format!("writing {}", p.display()))
    };
    write("per_image.csv", &report::per_image_csv(&result.rows))?;
    write(
        "summary.csv",
        &report::summary_csv(&summaries, paper.as_ref()),
    )?;
    let mut md = report::markdown(&summaries, paper.as_ref(), &notes);
    write("summary.md", &md)?;
    if let Some(reference) = &reference {
        let agreements = keylo::kpeval::reference::agreement(&result.rows, reference);
        let table = super::reference::markdown(&agreements);
        write("reference.csv", &super::reference::csv(&agreements))?;
        write("reference.md", &table)?;
        md.push_str("\n## Against the authors' per-image results\n\n");
        md.push_str(&table);
    }
    let json = serde_json::json!({
        "settings": spec,
        "images": planes.iter().map(|p| &p.label).collect::<Vec<_>>(),
        "jobs": jobs,
        "seconds": result.seconds,
        "combos": summaries,
        "skipped": result.skipped,
        "failed": result.failed,
    });
    write("summary.json", &serde_json::to_string_pretty(&json)?)?;
    if !args.input.no_plots {
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
                title: format!("{} ({} images)", m.label, planes.len()),
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
    if !result.failed.is_empty() {
        eprintln!(
            "error: {} combination group(s) failed; their results up to the failure are kept",
            result.failed.len()
        );
        return Ok(ExitCode::from(EXIT_FRAME_FAILED));
    }
    Ok(ExitCode::SUCCESS)
}
