//! Evaluating combinations over a sequence of images: detector groups in parallel, the images
//! of a group in order (each is matched against the previous one).

use std::time::Instant;

use keylo_core::{BuildContext, Registry};
use rayon::prelude::*;

use crate::frame_eval::{evaluate_image, GroupState};
use crate::stages::{build_groups, Group};
use crate::{Combo, EvalSpec, KpEvalError, Plane, Row};

/// How an evaluation runs.
pub struct EvalOptions<'a> {
    /// Detector groups evaluated at a time (each on one thread; OpenCV's own threading is
    /// turned off when more than one, so the threads do not compete).
    pub jobs: usize,
    /// Skip combinations this build cannot construct (SURF without the feature `nonfree`) instead of
    /// failing.
    pub skip_unavailable: bool,
    /// Called with (images done, images in all) as groups advance.
    pub progress: Option<&'a (dyn Fn(usize, usize) + Sync)>,
}

/// What an evaluation found.
#[derive(Debug, Default)]
pub struct EvalResult {
    /// One row per image per combination, grouped by detector, in image order.
    pub rows: Vec<Row>,
    /// Combinations not built: (name, reason).
    pub skipped: Vec<(String, String)>,
    /// Combinations that failed on an image: (detector group, error). Their rows up to the
    /// failure are kept.
    pub failed: Vec<(String, String)>,
    /// Wall-clock seconds of the evaluation.
    pub seconds: f64,
}

/// A group's rows and, when it stopped early, (what, error).
pub type GroupOutcome = (Vec<Row>, Option<(String, String)>);

/// Evaluates `combos` on `planes` with the image, metric and backend settings of `spec`.
pub fn evaluate(
    planes: &[Plane],
    combos: &[Combo],
    spec: &EvalSpec,
    registry: &Registry,
    ctx: &BuildContext,
    opts: &EvalOptions,
) -> Result<EvalResult, KpEvalError> {
    check_planes(planes)?;
    let start = Instant::now();
    let size = output_size(planes, spec);
    let (groups, skipped) = build_groups(combos, spec, registry, ctx, size, opts.skip_unavailable)?;
    let total = groups.len() * planes.len();
    let done = std::sync::atomic::AtomicUsize::new(0);
    let tick = || {
        let n = done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
        if let Some(p) = opts.progress {
            p(n, total);
        }
    };
    let outcomes: Vec<GroupOutcome> = if opts.jobs > 1 {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(opts.jobs)
            .build()
            .map_err(|e| KpEvalError::Input(format!("thread pool: {e}")))?;
        let _single = OpenCvThreads::single();
        pool.install(|| {
            groups
                .into_par_iter()
                .map(|g| run_group(g, planes, spec, &tick, 0))
                .collect()
        })
    } else {
        groups
            .into_iter()
            .map(|g| run_group(g, planes, spec, &tick, 0))
            .collect()
    };
    let mut result = EvalResult {
        skipped,
        ..EvalResult::default()
    };
    for (rows, failure) in outcomes {
        result.rows.extend(rows);
        result.failed.extend(failure);
    }
    result.seconds = start.elapsed().as_secs_f64();
    Ok(result)
}

/// The match metrics need a previous image: at least two.
pub(crate) fn check_planes(planes: &[Plane]) -> Result<(), KpEvalError> {
    if planes.len() < 2 {
        return Err(KpEvalError::Input(format!(
            "{} image(s): the match metrics need at least 2 consecutive images",
            planes.len()
        )));
    }
    Ok(())
}

/// The evaluated image size: `[image]`'s, 0 standing for the first image's own.
pub(crate) fn output_size(planes: &[Plane], spec: &EvalSpec) -> (usize, usize) {
    let first = planes.first().map_or((0, 0), |p| (p.cols, p.rows));
    let pick = |v: usize, own: usize| if v == 0 { own } else { v };
    (
        pick(spec.image.width, first.0),
        pick(spec.image.height, first.1),
    )
}

/// One detector group over every image of `planes` (the first being image `first_index` of
/// the sequence); a failure ends the group and is returned with its rows.
pub(crate) fn run_group(
    mut group: Group,
    planes: &[Plane],
    spec: &EvalSpec,
    tick: &(dyn Fn() + Sync),
    first_index: usize,
) -> GroupOutcome {
    let mut state = GroupState::new(&group);
    let mut rows = Vec::new();
    let interpolation = crate::spec::interpolation_name(spec.image.interpolation);
    let channel = spec.image.channel().unwrap_or(keylo_core::Channel::Signal);
    for (local, plane) in planes.iter().enumerate() {
        let index = first_index + local;
        let outcome = plane
            .image(
                spec.image.width,
                spec.image.height,
                spec.image.interpolation,
                channel,
            )
            .and_then(|image| {
                evaluate_image(
                    &mut group,
                    &mut state,
                    &image,
                    (index, &plane.label),
                    &interpolation,
                    &spec.metrics,
                )
            });
        tick();
        match outcome {
            Ok(r) => rows.extend(r),
            Err(e) => {
                let what = format!("{} (image {index}, {})", group.detector_name, plane.label);
                return (rows, Some((what, e.to_string())));
            }
        }
    }
    (rows, None)
}

/// Turns OpenCV's internal threads off while alive, restoring the previous count after.
pub(crate) struct OpenCvThreads {
    previous: Option<i32>,
}

impl OpenCvThreads {
    pub(crate) fn single() -> Self {
        let previous = opencv::core::get_num_threads().ok();
        let _ = opencv::core::set_num_threads(1);
        Self { previous }
    }
}

impl Drop for OpenCvThreads {
    fn drop(&mut self) {
        if let Some(n) = self.previous {
            let _ = opencv::core::set_num_threads(n);
        }
    }
}
