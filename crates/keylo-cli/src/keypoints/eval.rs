//! `keylo keypoints eval`: per-image results, per-combination summaries (CSV, JSON,
//! Markdown) and a box plot per metric.

use std::process::ExitCode;

use anyhow::Result;
use indicatif::{ProgressBar, ProgressStyle};
use keylo::kpeval::sweep::parse_interpolation;
use keylo::kpeval::{evaluate, EvalOptions};
use keylo::BuildContext;

use super::eval_report::{write_report, EvalReport};
use super::report::PaperFigures;
use super::{input, EvalArgs};

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
    let prepared = input::prepare(&args.input, &spec, threads)?;
    let ctx = BuildContext {
        base_dir: args
            .input
            .config
            .as_ref()
            .and_then(|p| p.parent().map(std::path::Path::to_path_buf))
            .unwrap_or_default(),
        trust: args.input.trust.trust(),
    };
    if let Some(shard) = args.input.shard {
        return super::shards::eval_shard(&args, shard, &spec, &prepared, &ctx, quiet);
    }
    let input::Prepared {
        registry,
        set,
        combos,
        planes,
        jobs,
    } = prepared;
    let out = args.input.out();
    let bar = progress(quiet, "evaluating");
    let tick = |done: usize, total: usize| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
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
    if let Some(every) = args.images {
        let pictured = keylo::kpeval::pictures::detect_for_pictures(
            &planes,
            &combos,
            &spec,
            &registry,
            &ctx,
            every,
            set.skips_unavailable(),
        )?;
        let n = super::pictures::write(out, &pictured)?;
        if !quiet {
            println!("pictures: {n} in {}", out.join("images").display());
        }
    }
    let labels: Vec<String> = planes.iter().map(|p| p.label.clone()).collect();
    write_report(
        out,
        &EvalReport {
            rows: &result.rows,
            skipped: &result.skipped,
            failed: &result.failed,
            spec: &spec,
            images: &labels,
            jobs,
            seconds: result.seconds,
            paper: paper.as_ref(),
            reference: reference.as_ref(),
        },
        args.input.no_plots,
        quiet,
    )
}
