//! An evaluation split into items that separate processes can do (`keylo keypoints eval
//! --shard`): a detector group over a block of consecutive images. A block starts one image
//! early, so its first image has its pair; that earlier image's rows are dropped. The rows of
//! all items, in item order, are those of one [`crate::evaluate`] (detectors keep no state
//! between images besides the previous image's features).

use std::ops::Range;

use keylo_core::{BuildContext, Registry};
use rayon::prelude::*;

use crate::runner::{check_planes, output_size, run_group, GroupOutcome, OpenCvThreads};
use crate::stages::{build_groups, Skipped};
use crate::{Combo, EvalOptions, EvalSpec, KpEvalError, Plane};

/// Images per item.
pub const BLOCK: usize = 25;

/// Expected cost of one image with a detector group of `combos` combinations (about the ms of
/// detect + describe per 1024×64 image measured in docs/results/keypoints.md, four detections
/// per image for the robustness tests, plus one describe-and-match per combination).
pub fn group_cost(detector_kind: &str, combos: usize) -> f64 {
    let kind = detector_kind.to_ascii_lowercase();
    let detect = [
        ("superpoint", 40.0),
        ("kaze", 30.0),
        ("sift", 8.0),
        ("brisk", 8.0),
        ("akaze", 2.0),
    ]
    .iter()
    .find(|(k, _)| kind == *k || (kind.contains(k) && *k != "kaze"))
    .map_or(1.0, |(_, ms)| *ms);
    4.0 * detect + combos as f64
}

/// One detector group over one block of images.
#[derive(Debug, Clone, PartialEq)]
pub struct EvalItem {
    /// Registry kind of the group's detector.
    pub detector: String,
    /// Indices of the images whose rows the item gives.
    pub images: Range<usize>,
    /// Expected cost ([`group_cost`] × images).
    pub cost: f64,
}

impl EvalItem {
    /// A name unique within the evaluation: `akaze@0-24`.
    pub fn id(&self) -> String {
        format!(
            "{}@{}-{}",
            self.detector,
            self.images.start,
            self.images.end.saturating_sub(1)
        )
    }
}

/// Every item of evaluating `combos` on `images` images (group-major, blocks in order) and
/// the combinations this build cannot construct (skipped when `skip_unavailable`).
pub fn eval_items(
    images: usize,
    combos: &[Combo],
    spec: &EvalSpec,
    registry: &Registry,
    ctx: &BuildContext,
    (planes, skip_unavailable): (&[Plane], bool),
) -> Result<(Vec<EvalItem>, Skipped), KpEvalError> {
    let size = output_size(planes, spec);
    let (groups, skipped) = build_groups(combos, spec, registry, ctx, size, skip_unavailable)?;
    let mut items = Vec::new();
    for g in &groups {
        let per_image = group_cost(&g.detector_kind, g.combos.len());
        for start in (0..images).step_by(BLOCK) {
            let end = (start + BLOCK).min(images);
            items.push(EvalItem {
                detector: g.detector_kind.clone(),
                images: start..end,
                cost: per_image * (end - start) as f64,
            });
        }
    }
    Ok((items, skipped))
}

/// Evaluates `items` (at most `opts.jobs` at a time); `done(i, outcome, seconds)` is called
/// as item `i` finishes. Returns the outcomes in item order.
pub fn evaluate_items(
    planes: &[Plane],
    combos: &[Combo],
    spec: &EvalSpec,
    (registry, ctx): (&Registry, &BuildContext),
    opts: &EvalOptions,
    items: &[EvalItem],
    done: &(dyn Fn(usize, &GroupOutcome, f64) + Sync),
) -> Result<Vec<GroupOutcome>, KpEvalError> {
    check_planes(planes)?;
    let size = output_size(planes, spec);
    let run = |(i, item): (usize, &EvalItem)| -> Result<GroupOutcome, KpEvalError> {
        let start = std::time::Instant::now();
        let own: Vec<Combo> = combos
            .iter()
            .filter(|c| c.detector == item.detector)
            .cloned()
            .collect();
        let (groups, _) = build_groups(&own, spec, registry, ctx, size, true)?;
        let Some(group) = groups.into_iter().next() else {
            return Err(KpEvalError::Input(format!(
                "item {}: detector `{}` cannot be built here",
                item.id(),
                item.detector
            )));
        };
        let from = item.images.start.saturating_sub(1);
        let end = item.images.end.min(planes.len());
        let (mut rows, failure) = run_group(group, &planes[from..end], spec, &|| {}, from);
        rows.retain(|r| r.index >= item.images.start);
        let outcome = (rows, failure);
        done(i, &outcome, start.elapsed().as_secs_f64());
        Ok(outcome)
    };
    if opts.jobs > 1 {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(opts.jobs)
            .build()
            .map_err(|e| KpEvalError::Input(format!("thread pool: {e}")))?;
        let _single = OpenCvThreads::single();
        pool.install(|| items.par_iter().enumerate().map(run).collect())
    } else {
        items.iter().enumerate().map(run).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn heavier_detectors_cost_more_and_ids_name_the_block() {
        assert!(group_cost("superpoint", 1) > group_cost("kaze", 1));
        assert!(group_cost("kaze", 1) > group_cost("akaze", 1));
        assert!(group_cost("akaze", 1) > group_cost("fast", 1));
        assert!(group_cost("fast", 3) > group_cost("fast", 1));
        let item = EvalItem {
            detector: "akaze".into(),
            images: 25..50,
            cost: 1.0,
        };
        assert_eq!(item.id(), "akaze@25-49");
    }
}
