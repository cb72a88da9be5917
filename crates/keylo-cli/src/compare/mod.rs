//! `keylo compare`: run several configs (and a grid of overrides) on the same data, each as
//! its own `keylo run` child process, and tabulate and plot the results the way the paper's
//! tables do.
//!
//! * [`grid`]: `--grid KEY=V1,V2,…` parsing and expansion; [`plan`]: the runs it makes.
//! * [`schedule`]: child processes, `--jobs`, resume.
//! * [`metrics`]: one row per run, the divergence verdict.
//! * [`tables`]: Markdown, CSV, JSON.
//! * [`figures`]: which figures a comparison draws; [`plots`]: PNG + SVG drawing.

mod args;
mod association;
mod budget;
mod child;
mod error;
mod figures;
mod grid;
mod metrics;
mod plan;
pub(crate) mod plots;
mod row;
mod schedule;
mod sharded;
mod tables;

use std::path::Path;
use std::process::ExitCode;

use anyhow::{bail, Context, Result};

pub use args::{CompareArgs, CompareCommand};
use error::CompareError;
use metrics::Series;
use row::{Criterion, Row};
use schedule::Planned;

pub fn run(args: CompareArgs, threads: Option<usize>, quiet: bool) -> Result<ExitCode> {
    if let Some(CompareCommand::Merge(m)) = &args.command {
        return sharded::merge(m, quiet);
    }
    if args.gt.is_some() && args.data.len() > 1 {
        bail!("--gt names one ground truth, but {} --data were given: put a gt.tum beside each data instead", args.data.len());
    }
    if let Some(t) = args.timeout {
        if !(t.is_finite() && t > 0.0) {
            bail!("--timeout {t}: expected a positive number of seconds");
        }
    }
    if args.jobs == 0 {
        bail!("--jobs 0: expected at least 1");
    }
    if let Some(speed) = args.realtime {
        if !(speed.is_finite() && speed > 0.0) {
            bail!("--realtime {speed}: expected a positive playback speed (1: the sensor's rate)");
        }
    }
    let axes = args
        .grids
        .iter()
        .map(|g| grid::parse_axis(g))
        .collect::<Result<Vec<_>, _>>()?;
    grid::expand(&axes)?; // two axes on one key
    let plans = plan::plan(&args, &axes, quiet)?;
    let crit = Criterion {
        max_ape_m: args.diverge_ape,
        max_step_m: args.diverge_step,
        t_max_diff_s: args.t_max_diff,
    };
    let (plans, manifest) = match args.shard {
        Some(shard) => {
            let (mine, manifest) = sharded::start(plans, &crit, shard);
            (mine, Some(manifest))
        }
        None => (plans, None),
    };
    if args.dry_run {
        for p in &plans {
            println!("{}\t{}", p.id, p.sets.join(" "));
        }
        return Ok(ExitCode::SUCCESS);
    }
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("creating {}", args.out.display()))?;
    let manifest = manifest.map(|m| m.resume_in(&args.out)).transpose()?;
    if let Some(m) = &manifest {
        m.write(&args.out)?;
    }
    if !quiet {
        eprintln!(
            "keylo compare: {} runs{}, {} at a time, into {}",
            plans.len(),
            args.shard
                .map_or(String::new(), |s| format!(" (shard {s})")),
            args.jobs,
            args.out.display()
        );
    }
    let started = std::time::Instant::now();
    let outcomes = schedule::run_all(
        &plans,
        &schedule::Options {
            jobs: args.jobs,
            threads,
            trust_plugins: args.trust.trust_plugins,
            rerun: args.rerun,
            timeout: args.timeout.map(std::time::Duration::from_secs_f64),
            quiet,
        },
    )?;
    if let Some(m) = manifest {
        sharded::finish(m, &plans, &outcomes, started.elapsed(), &args.out)?;
    }
    report(&args.out, &plans, &outcomes, &crit, args.no_plots, quiet)
}

/// The tables (Markdown, CSV, JSON) and plots of finished runs, written into `out`.
fn report(
    out: &Path,
    plans: &[Planned],
    outcomes: &[schedule::Outcome],
    crit: &Criterion,
    no_plots: bool,
    quiet: bool,
) -> Result<ExitCode> {
    let (mut rows, series): (Vec<Row>, Vec<Series>) = plans
        .iter()
        .zip(outcomes)
        .map(|(p, o)| metrics::collect(p, o, crit))
        .unzip();
    metrics::add_rate_ratios(&mut rows);
    // Shown even with -q (as `keylo run` does): the accuracy columns would mislead.
    for (data, text) in association::warnings(&rows) {
        eprintln!("warning: {data}: {text}");
    }
    let md = tables::markdown(&rows, crit);
    write(&out.join("compare.md"), &md)?;
    write(&out.join("compare.csv"), &tables::csv(&rows))?;
    write(&out.join("compare.json"), &tables::json(&rows, crit))?;
    if !no_plots {
        figures::write_plots(out, plans, &rows, &series)?;
    }
    if !quiet {
        println!("{md}");
        println!(
            "written: {} (compare.md, compare.csv, compare.json{})",
            out.display(),
            if no_plots { "" } else { ", plots/" }
        );
    }
    Ok(ExitCode::SUCCESS)
}

/// Writes `text` to `path` whole or not at all.
fn write(path: &Path, text: &str) -> Result<(), CompareError> {
    crate::atomic::write(path, text).map_err(|e| CompareError::io(path, e))
}

/// A folder name: letters, digits, `.`, `-`, `_`, `=`; anything else becomes `_`.
pub(crate) fn slug(text: &str) -> String {
    text.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || ".-_=".contains(c) {
                c
            } else {
                '_'
            }
        })
        .collect()
}
