//! `keylo compare`: run several configs (and a grid of overrides) on the same data, each as
//! its own `keylo run` child process, and tabulate and plot the results the way the paper's
//! tables do.
//!
//! * [`grid`]: `--grid KEY=V1,V2,…` parsing and expansion.
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
pub(crate) mod plots;
mod row;
mod schedule;
mod sharded;
mod tables;

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{bail, Context, Result};

use crate::configs;
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
    let plans = plan(&args, &axes, quiet)?;
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

/// Every (data, config, grid point), checked. Each grid key is first tried alone on every
/// config: a key no config accepts is an error that names it; a key only some configs accept
/// (window sizes and a raw-cloud config) is left out for the others, which run once.
fn plan(args: &CompareArgs, axes: &[grid::Axis], quiet: bool) -> Result<Vec<Planned>> {
    let mut registry = keylo::registry();
    let configs: Vec<Option<PathBuf>> = if args.configs.is_empty() {
        vec![None]
    } else {
        args.configs.iter().cloned().map(Some).collect()
    };
    let Some(first_data) = args.data.first() else {
        bail!("--data: at least one is needed");
    };
    let mut per_config = Vec::new();
    for config in &configs {
        let base = configs::load(
            &mut registry,
            config.as_deref(),
            Some(first_data),
            None,
            &args.sets,
            args.trust.trust(),
        )?;
        let windows = grid::windows_of(base.downsampler.params.get("windows"));
        let rejected = rejected_axes(
            &mut registry,
            config.as_deref(),
            first_data,
            &args.sets,
            axes,
            &windows,
            args.trust.trust(),
        );
        let flavours = if args.same_budget {
            budget::flavours(&base.downsampler)
        } else {
            vec![budget::Flavour::default()]
        };
        per_config.push((config, windows, rejected, flavours));
    }
    for (i, a) in axes.iter().enumerate() {
        if per_config
            .iter()
            .all(|(_, _, r, _)| r.iter().any(|(j, _)| *j == i))
        {
            let why = per_config
                .iter()
                .filter_map(|(_, _, r, _)| r.iter().find(|(j, _)| *j == i).map(|(_, m)| m.clone()))
                .collect::<Vec<_>>()
                .join("; ");
            return Err(CompareError::BadGrid {
                key: a.name.clone(),
                message: why,
            }
            .into());
        }
    }
    let data_labels = labels(&args.data);
    let mut plans = Vec::new();
    for (config, windows, rejected, flavours) in &per_config {
        let kept: Vec<grid::Axis> = axes
            .iter()
            .enumerate()
            .filter(|(i, _)| !rejected.iter().any(|(j, _)| j == i))
            .map(|(_, a)| a.clone())
            .collect();
        if !quiet {
            for (_, why) in rejected {
                eprintln!("note: grid axis left out (this config runs once without it): {why}");
            }
        }
        let many = configs.len() > 1 || flavours.len() > 1;
        let points = grid::expand(&kept)?;
        for (flavour, point) in flavours
            .iter()
            .flat_map(|f| points.iter().map(move |p| (f, p)))
        {
            let stem = format!("{}{}", config_stem(config.as_deref()), flavour.suffix);
            let mut sets = args.sets.clone();
            sets.extend(flavour.sets.iter().cloned());
            sets.extend(grid::set_strings(point, windows));
            let variant = variant_label(&stem, &grid::label(point, windows), many);
            for (data, data_label) in args.data.iter().zip(&data_labels) {
                let loaded = configs::load(
                    &mut registry,
                    config.as_deref(),
                    Some(data),
                    None,
                    &sets,
                    args.trust.trust(),
                )
                .with_context(|| format!("configuration {variant} on {data_label}"))?;
                let id = format!("{data_label}/{}", slug(&variant));
                let gt = args
                    .gt
                    .clone()
                    .or_else(|| Some(data.join("gt.tum")).filter(|p| p.is_file()));
                let time = args.reference.stamp_map();
                plans.push(Planned {
                    dir: args.out.join("runs").join(&id),
                    id,
                    data_label: data_label.clone(),
                    variant: variant.clone(),
                    config: (*config).clone(),
                    data: data.clone(),
                    gt_time: (gt.is_some() && !time.is_identity()).then_some(time),
                    gt_label: gt.as_deref().map(|p| args.reference.label(p)),
                    gt,
                    sets: sets.clone(),
                    realtime: args.realtime,
                    images: args.images,
                    cost: sharded::expected_cost(&loaded, data),
                });
            }
        }
    }
    Ok(plans)
}

/// The axes (index, why) that `config` rejects when each of their values is set alone.
fn rejected_axes(
    registry: &mut keylo::Registry,
    config: Option<&Path>,
    data: &Path,
    sets: &[String],
    axes: &[grid::Axis],
    windows: &std::collections::BTreeMap<String, usize>,
    trust: keylo::config::Trust,
) -> Vec<(usize, String)> {
    let mut out = Vec::new();
    for (i, a) in axes.iter().enumerate() {
        for v in &a.values {
            let mut all = sets.to_vec();
            all.extend(grid::set_strings(
                &vec![(a.name.clone(), a.key.clone(), v.clone())],
                windows,
            ));
            if let Err(e) = configs::load(registry, config, Some(data), None, &all, trust) {
                let config =
                    config.map_or("the built-in config".into(), |p| p.display().to_string());
                out.push((
                    i,
                    format!(
                        "{} = {v} is not valid for {config}: {}",
                        a.key,
                        crate::error_chain(&e)
                    ),
                ));
                break;
            }
        }
    }
    out
}

fn config_stem(config: Option<&Path>) -> String {
    config
        .and_then(Path::file_stem)
        .map_or("default".into(), |s| s.to_string_lossy().into_owned())
}

fn variant_label(stem: &str, grid: &str, many_configs: bool) -> String {
    match (grid.is_empty(), many_configs) {
        (true, _) => stem.to_string(),
        (false, false) => grid.to_string(),
        (false, true) => format!("{stem} {grid}"),
    }
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

/// Unique labels of the data paths (their file stems, numbered when two agree).
fn labels(data: &[PathBuf]) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for d in data {
        let abs = std::path::absolute(d).unwrap_or_else(|_| d.clone());
        let base = slug(
            &abs.file_stem()
                .map_or("data".into(), |s| s.to_string_lossy().into_owned()),
        );
        let mut label = base.clone();
        let mut n = 2;
        while out.contains(&label) {
            label = format!("{base}-{n}");
            n += 1;
        }
        out.push(label);
    }
    out
}
