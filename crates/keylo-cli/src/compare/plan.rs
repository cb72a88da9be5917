//! What a comparison runs: every (data, config, grid point, same-budget flavour), each
//! config checked against the grid first.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};

use super::args::CompareArgs;
use super::error::CompareError;
use super::schedule::Planned;
use super::{budget, grid, sharded, slug};
use crate::configs;

/// Every (data, config, grid point), checked. Each grid key is first tried alone on every
/// config: a key no config accepts is an error that names it; a key only some configs accept
/// (window sizes and a raw-cloud config) is left out for the others, which run once.
pub(super) fn plan(args: &CompareArgs, axes: &[grid::Axis], quiet: bool) -> Result<Vec<Planned>> {
    let mut registry = keylo::registry();
    let configs: Vec<Option<PathBuf>> = if args.configs.is_empty() {
        vec![None]
    } else {
        args.configs.iter().cloned().map(Some).collect()
    };
    let Some(first_data) = args.data.first() else {
        bail!("--data: at least one is needed");
    };
    let per_config = configs_and_axes(&mut registry, args, axes, (&configs, first_data))?;
    refuse_axes_no_config_takes(axes, &per_config)?;
    let data_labels = labels(&args.data);
    let mut plans = Vec::new();
    for ConfigAxes {
        config,
        windows,
        rejected,
        flavours,
    } in &per_config
    {
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

/// One config of a comparison: its windows (for `k_*` grid keys), the grid axes it does not
/// accept (index, why) and its same-budget flavours.
struct ConfigAxes<'a> {
    config: &'a Option<PathBuf>,
    windows: BTreeMap<String, usize>,
    rejected: Vec<(usize, String)>,
    flavours: Vec<budget::Flavour>,
}

/// Each config loaded on the first data, with the grid axes it rejects.
fn configs_and_axes<'a>(
    registry: &mut keylo::Registry,
    args: &CompareArgs,
    axes: &[grid::Axis],
    (configs, first_data): (&'a [Option<PathBuf>], &Path),
) -> Result<Vec<ConfigAxes<'a>>> {
    let mut out = Vec::new();
    for config in configs {
        let base = configs::load(
            registry,
            config.as_deref(),
            Some(first_data),
            None,
            &args.sets,
            args.trust.trust(),
        )?;
        let windows = grid::windows_of(base.downsampler.params.get("windows"));
        let rejected = rejected_axes(
            registry,
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
        out.push(ConfigAxes {
            config,
            windows,
            rejected,
            flavours,
        });
    }
    Ok(out)
}

/// A grid axis that every config rejects is an error naming it, with each config's reason.
fn refuse_axes_no_config_takes(axes: &[grid::Axis], per_config: &[ConfigAxes]) -> Result<()> {
    for (i, a) in axes.iter().enumerate() {
        let rejected_by = |c: &ConfigAxes| {
            c.rejected
                .iter()
                .find(|(j, _)| *j == i)
                .map(|(_, m)| m.clone())
        };
        if per_config.iter().all(|c| rejected_by(c).is_some()) {
            let why = per_config
                .iter()
                .filter_map(rejected_by)
                .collect::<Vec<_>>()
                .join("; ");
            return Err(CompareError::BadGrid {
                key: a.name.clone(),
                message: why,
            }
            .into());
        }
    }
    Ok(())
}
