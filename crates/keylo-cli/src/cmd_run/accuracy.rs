//! `keylo run`'s accuracy: which reference it reads, the figures against it, the warning
//! when few poses pair with it, and the aligned reference for pictures.

use std::path::PathBuf;

use anyhow::{Context, Result};
use keylo::config::PipelineConfig;
use keylo::Trajectory;

use super::args::RunArgs;
use crate::report::Summary;
use crate::trajectories;

/// The reference file of the run, read (its clock mapped by `--gt-time-scale` /
/// `--gt-time-offset`, named by `--gt-label`), or `None` when there is none; the time options
/// without a reference file are said to do nothing.
pub fn reference_file(
    args: &RunArgs,
    config: &PipelineConfig,
) -> Result<Option<trajectories::Labelled>> {
    let Some(path) = ground_truth_file(args, config) else {
        if !args.reference.stamp_map().is_identity() {
            tracing::warn!(
                "--gt-time-scale/--gt-time-offset apply to a reference file (--gt, [output] gt \
                 or a gt.tum beside the data) and there is none: ignored (a source's own ground \
                 truth keeps its times)"
            );
        }
        return Ok(None);
    };
    let mut gt = args
        .reference
        .read(&path)
        .with_context(|| format!("ground truth {}", path.display()))?;
    if let Some(label) = &args.reference.gt_label {
        gt.label.clone_from(label);
    }
    Ok(Some(gt))
}

/// Ground-truth file: `--gt`, else `[output] gt`, else a `gt.tum` beside the data (`--data` or
/// the source's `path`). A source with ground truth of its own (the simulator) needs none.
fn ground_truth_file(args: &RunArgs, config: &PipelineConfig) -> Option<PathBuf> {
    if let Some(gt) = &args.gt {
        return Some(gt.clone());
    }
    if !config.output.gt.is_empty() {
        return Some(config.base_dir.join(&config.output.gt));
    }
    let data = args.data.clone().or_else(|| {
        let path = config.source.params.get("path")?.as_str()?;
        (!path.is_empty()).then(|| config.base_dir.join(path))
    })?;
    Some(data.join("gt.tum")).filter(|p| p.is_file())
}

/// Accuracy against `gt` into the summary, and the aligned reference into `out`.
pub fn add_accuracy(
    summary: &mut Summary,
    est: &Trajectory,
    gt: Option<trajectories::Labelled>,
    out: &std::path::Path,
    map: keylo::eval::stamp_map::StampMap,
) {
    let Some(mut gt) = gt else { return };
    let mut ours = trajectories::Labelled::stamped(est.clone(), "the estimated trajectory");
    let result = trajectories::reconcile(&mut ours, &mut gt).and_then(|()| {
        warn_poor_association(summary, &ours.trajectory, &gt, map);
        let opts = keylo::eval::EvalOptions {
            reference_label: gt.label.clone(),
            estimate_label: ours.label.clone(),
            ..keylo::eval::EvalOptions::default()
        };
        Ok(keylo::eval::evaluate(
            &ours.trajectory,
            &gt.trajectory,
            &opts,
        )?)
    });
    summary.ground_truth = Some(gt.label.clone());
    match result {
        Ok(a) => {
            summary.accuracy = Some(a);
            if let Err(e) = crate::reference_out::write(out, &ours.trajectory, &gt.trajectory) {
                tracing::warn!("no {} for pictures: {e:#}", crate::reference_out::FILE);
            }
        }
        Err(e) => {
            // Shown even with -q: the user asked for accuracy and does not get it.
            tracing::error!("no accuracy figures: {e:#}");
            summary.accuracy_error = Some(format!("{e:#}"));
        }
    }
}

/// Says so (stderr and `summary.json`) when fewer than 90 % of the estimated poses pair
/// with the reference, with the likely cause and the options that undo it.
fn warn_poor_association(
    summary: &mut Summary,
    est: &Trajectory,
    gt: &trajectories::Labelled,
    map: keylo::eval::stamp_map::StampMap,
) {
    let opts = keylo::eval::associate::AssociateOptions::default();
    let coverage = keylo::eval::coverage::of_pairing(est, &gt.trajectory, &opts);
    if coverage.is_low() {
        let text = crate::reference_args::warning(&coverage, &gt.label, map);
        // Shown even with -q, as a missing accuracy is: the figures would mislead.
        eprintln!("warning: {text}");
        summary.association_warning = Some(text);
    }
}
