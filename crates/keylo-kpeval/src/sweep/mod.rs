//! The paper's Algorithm 1: every (interpolation, width, height) cell evaluated with every
//! combination; per-cell means kept in a CSV that is appended as cells finish, so a stopped
//! sweep resumes where it was; optima per metric and overall.

mod grid;
mod store;

use std::collections::BTreeSet;
use std::io::Write;
use std::path::PathBuf;
use std::time::Instant;

use keylo_core::{BuildContext, Registry};
use rayon::prelude::*;

pub use crate::spec::{interpolation_name, parse_interpolation};
pub use grid::{parse_sizes, Cell, SweepGrid, INTERPOLATIONS};
pub use store::{csv_header, read_store, sort_results, CellResult};

use crate::runner::run_group;
use crate::stages::{build_groups, Skipped};
use crate::{summarise, Combo, EvalSpec, KpEvalError, Plane};
use store::open_store;

/// How a sweep runs.
pub struct SweepOptions<'a> {
    /// Cells × detector groups evaluated at a time.
    pub jobs: usize,
    /// Skip combinations this build cannot construct instead of failing.
    pub skip_unavailable: bool,
    /// The CSV appended as cells finish (and read to resume).
    pub store: PathBuf,
    /// Called with (tasks done, tasks in all, tasks resumed from the store).
    pub progress: Option<&'a (dyn Fn(usize, usize, usize) + Sync)>,
    /// Only the tasks of these [`task_id`]s (a shard's); `None`: every task.
    pub only: Option<&'a BTreeSet<String>>,
    /// Called with a task's id and its wall-clock seconds as it finishes.
    pub timed: Option<&'a TaskTimer<'a>>,
}

/// Called with a finished task's id and its seconds.
pub type TaskTimer<'a> = dyn Fn(&str, f64) + Sync + 'a;

/// The name of the task of `detector`'s group in `cell`: `linear 1024x64 akaze`.
pub fn task_id(cell: &Cell, detector: &str) -> String {
    task_name(
        &interpolation_name(cell.interpolation),
        (cell.width, cell.height),
        detector,
    )
}

/// [`task_id`] from an interpolation's name (as [`CellResult`] holds it).
pub fn task_name(interpolation: &str, (width, height): (usize, usize), detector: &str) -> String {
    format!("{interpolation} {width}x{height} {detector}")
}

/// The combinations of each detector group (groups in first-seen order) and the
/// combinations skipped, found once on the first cell's size.
fn group_combos(
    combos: &[Combo],
    spec: &EvalSpec,
    grid: &SweepGrid,
    (registry, ctx): (&Registry, &BuildContext),
    skip_unavailable: bool,
) -> Result<(Vec<Vec<Combo>>, Skipped), KpEvalError> {
    let probe = grid
        .cells()
        .first()
        .map_or((1024, 64), |c| (c.width, c.height));
    let (groups, skipped) = build_groups(combos, spec, registry, ctx, probe, skip_unavailable)?;
    let out = groups
        .iter()
        .map(|g| g.combos.iter().map(|(c, _)| c.clone()).collect())
        .collect();
    Ok((out, skipped))
}

/// Every task of a sweep in order with its expected cost (pixels × the group's cost per
/// image, [`crate::items::group_cost`]), for splitting it into shards.
pub fn sweep_tasks(
    combos: &[Combo],
    spec: &EvalSpec,
    grid: &SweepGrid,
    (registry, ctx): (&Registry, &BuildContext),
    skip_unavailable: bool,
) -> Result<SweepTasks, KpEvalError> {
    let (groups, skipped) = group_combos(combos, spec, grid, (registry, ctx), skip_unavailable)?;
    let mut out = Vec::new();
    for cell in grid.cells() {
        for gc in &groups {
            let detector = gc.first().map_or("", |c| c.detector.as_str());
            let pixels = (cell.width * cell.height) as f64 / (1024.0 * 64.0);
            let cost = pixels * crate::items::group_cost(detector, gc.len());
            out.push((task_id(&cell, detector), cost));
        }
    }
    Ok((out, skipped))
}

/// `(task id, expected cost)` of every task in order, and the combinations skipped.
pub type SweepTasks = (Vec<(String, f64)>, Skipped);

/// What a sweep found.
#[derive(Debug, Default)]
pub struct SweepResult {
    /// Every (cell, combination) result, resumed ones included, in cell order.
    pub results: Vec<CellResult>,
    /// Combinations not built: (name, reason).
    pub skipped: Vec<(String, String)>,
    /// Tasks that failed: (cell and detector, error).
    pub failed: Vec<(String, String)>,
    /// (cell, detector group) tasks run now, and found done in the store.
    pub tasks_run: usize,
    pub tasks_resumed: usize,
    /// Images evaluated now (per combination) and the wall-clock seconds it took.
    pub images_evaluated: usize,
    pub seconds: f64,
}

/// Runs the sweep of `combos` over `grid` on `planes`.
pub fn run_sweep(
    planes: &[Plane],
    combos: &[Combo],
    spec: &EvalSpec,
    grid: &SweepGrid,
    registry: &Registry,
    ctx: &BuildContext,
    opts: &SweepOptions,
) -> Result<SweepResult, KpEvalError> {
    crate::runner::check_planes(planes)?;
    let start = Instant::now();
    let earlier = read_store(&opts.store)?;
    let done: DoneSet = earlier
        .iter()
        .map(|r| {
            (
                (r.interpolation.clone(), r.width, r.height),
                r.combo.clone(),
            )
        })
        .collect();
    // The groups (one per detector) and the skipped combinations, found once.
    let cells = grid.cells();
    let (group_combos, skipped) =
        group_combos(combos, spec, grid, (registry, ctx), opts.skip_unavailable)?;
    let (tasks, resumed) = plan_tasks(&cells, &group_combos, &done, opts.only);
    let store = open_store(&opts.store, earlier.is_empty())?;
    let total = tasks.len() + resumed;
    let finished = std::sync::atomic::AtomicUsize::new(resumed);
    let images = std::sync::atomic::AtomicUsize::new(0);
    let run_task = |(cell, gc): &(Cell, Vec<Combo>)| -> Result<Vec<CellResult>, (String, String)> {
        let started = Instant::now();
        let what = |e: &dyn std::fmt::Display| {
            (
                task_id(cell, gc.first().map_or("", |c| c.detector.as_str())),
                e.to_string(),
            )
        };
        let out = evaluate_cell(cell, gc, (spec, registry, ctx), planes, &images)
            .map_err(|e| what(&e))?;
        if let Ok(mut f) = store.lock() {
            let text: String = out
                .iter()
                .map(|r| keylo_io::csv_table::line(r.record()))
                .collect();
            // A failed write only loses resumability of this cell.
            let _ = f.write_all(text.as_bytes()).and_then(|()| f.flush());
        }
        if let Some(t) = opts.timed {
            let detector = gc.first().map_or("", |c| c.detector.as_str());
            t(&task_id(cell, detector), started.elapsed().as_secs_f64());
        }
        let n = finished.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
        if let Some(p) = opts.progress {
            p(n, total, resumed);
        }
        Ok(out)
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(opts.jobs.max(1))
        .build()
        .map_err(|e| KpEvalError::Input(format!("thread pool: {e}")))?;
    let _single = (opts.jobs > 1).then(crate::runner::OpenCvThreads::single);
    let outcomes: Vec<_> = pool.install(|| tasks.par_iter().map(run_task).collect());
    let mut result = SweepResult {
        skipped,
        tasks_run: tasks.len(),
        tasks_resumed: resumed,
        ..SweepResult::default()
    };
    let mut all = earlier;
    for o in outcomes {
        match o {
            Ok(r) => all.extend(r),
            Err(f) => result.failed.push(f),
        }
    }
    sort_results(&mut all);
    result.results = all;
    result.images_evaluated = images.into_inner();
    result.seconds = start.elapsed().as_secs_f64();
    Ok(result)
}

/// The tasks to run now, (cell, detector group) in cell order, and how many are resumed (every
/// combination of theirs found `done` in the store); with `only`, the tasks it names alone.
fn plan_tasks(
    cells: &[Cell],
    group_combos: &[Vec<Combo>],
    done: &DoneSet,
    only: Option<&BTreeSet<String>>,
) -> (Vec<(Cell, Vec<Combo>)>, usize) {
    let mut tasks = Vec::new();
    let mut resumed = 0;
    for cell in cells {
        for gc in group_combos {
            let detector = gc.first().map_or("", |c| c.detector.as_str());
            if only.is_some_and(|only| !only.contains(&task_id(cell, detector))) {
                continue;
            }
            if gc
                .iter()
                .all(|c| done.contains(&(cell.key(), c.name.clone())))
            {
                resumed += 1;
            } else {
                tasks.push((*cell, gc.clone()));
            }
        }
    }
    (tasks, resumed)
}

/// The (cell, combination) pairs a store already holds.
type DoneSet = BTreeSet<((String, usize, usize), String)>;

/// Every combination of one detector group `gc` evaluated on `planes` preprocessed as `cell`
/// says: the mean of each metric, counting the images evaluated into `images`; `Err`: what
/// failed.
fn evaluate_cell(
    cell: &Cell,
    gc: &[Combo],
    (spec, registry, ctx): (&EvalSpec, &Registry, &BuildContext),
    planes: &[Plane],
    images: &std::sync::atomic::AtomicUsize,
) -> Result<Vec<CellResult>, String> {
    let mut cell_spec = spec.clone();
    cell_spec.image.width = cell.width;
    cell_spec.image.height = cell.height;
    cell_spec.image.interpolation = cell.interpolation;
    let (groups, _) = build_groups(
        gc,
        &cell_spec,
        registry,
        ctx,
        (cell.width, cell.height),
        false,
    )
    .map_err(|e| e.to_string())?;
    let mut out = Vec::new();
    for g in groups {
        let (rows, failure) = run_group(g, planes, &cell_spec, &|| {}, 0);
        if let Some((_, e)) = failure {
            return Err(e);
        }
        images.fetch_add(rows.len(), std::sync::atomic::Ordering::Relaxed);
        for s in summarise(&rows) {
            out.push(CellResult {
                interpolation: interpolation_name(cell.interpolation),
                width: cell.width,
                height: cell.height,
                combo: s.combo.clone(),
                images: s.images,
                means: s.metrics.iter().map(|(k, q)| (k.clone(), q.mean)).collect(),
            });
        }
    }
    Ok(out)
}
