//! `keylo compare --shard I/N` and `keylo compare merge`: the runs split across processes or
//! machines, each shard's runs under its own `--out` with a manifest, joined into the tables
//! and plots of one process (the same rows; only the timing columns differ).

use std::path::Path;
use std::process::ExitCode;
use std::time::Duration;

use anyhow::{Context, Result};
use keylo::config::PipelineConfig;
use serde_json::{json, Value};

use super::row::Criterion;
use super::schedule::{is_done, Outcome, Planned};
use crate::arg_groups::MergeArgs;
use crate::shard::manifest::Manifest;
use crate::shard::{self, merge, Shard, ShardError};

const COMMAND: &str = "compare";

/// The expected cost of running `config` on `data`: the data's bytes, times 4 with SuperPoint
/// (its network dominates a frame) and times 2 with the hybrid registrar (two alignments).
pub fn expected_cost(config: &PipelineConfig, data: &Path) -> f64 {
    let mut factor = 1.0;
    if config.detector.kind == "superpoint" || config.descriptor.kind == "superpoint" {
        factor *= 4.0;
    }
    if config.registrar.kind == "hybrid" {
        factor *= 2.0;
    }
    factor * (shard::data_size(data).max(1) as f64)
}

/// What makes the study: every plan and the divergence criterion (not `--out`, `--jobs`,
/// `--timeout`, which may differ between shards).
fn detail(plans: &[Planned], crit: &Criterion) -> Value {
    json!({
        "plans": plans,
        "criterion": {
            "max_ape_m": crit.max_ape_m,
            "max_step_m": crit.max_step_m,
            "t_max_diff_s": crit.t_max_diff_s,
        },
    })
}

/// This shard's plans and its fresh manifest.
pub fn start(plans: Vec<Planned>, crit: &Criterion, shard: Shard) -> (Vec<Planned>, Manifest) {
    let costs: Vec<f64> = plans.iter().map(|p| p.cost).collect();
    let assigned = shard::partition(&costs, shard.count);
    let ids = plans.iter().map(|p| p.id.clone()).collect();
    let manifest = Manifest::new(COMMAND, shard, detail(&plans, crit), ids, &assigned);
    let mine = plans
        .into_iter()
        .zip(&assigned)
        .filter(|(_, s)| **s == shard.index)
        .map(|(p, _)| p)
        .collect();
    (mine, manifest)
}

/// Records the shard's outcomes (a run resumed keeps the outcome recorded when it ran) and
/// whether all of them finished; an interrupted run leaves the shard incomplete.
pub fn finish(
    mut manifest: Manifest,
    plans: &[Planned],
    outcomes: &[Outcome],
    took: Duration,
    out: &Path,
) -> Result<(), ShardError> {
    let mut complete = true;
    for (p, o) in plans.iter().zip(outcomes) {
        let interrupted = !o.resumed && !o.timed_out && matches!(o.exit_code, None | Some(130));
        if interrupted || (o.resumed && !is_done(&p.dir)) {
            complete = false;
            manifest.results.remove(&p.id);
            continue;
        }
        let recorded = match manifest.results.get(&p.id) {
            Some(earlier) if o.resumed => {
                let mut e: Outcome = serde_json::from_value(earlier.clone()).unwrap_or_default();
                e.resumed = true;
                e
            }
            _ => o.clone(),
        };
        manifest.results.insert(
            p.id.clone(),
            serde_json::to_value(recorded).unwrap_or(Value::Null),
        );
    }
    manifest.complete = complete;
    manifest.seconds = took.as_secs_f64();
    manifest.write(out)
}

/// `keylo compare merge OUT DIR...`.
pub fn merge(args: &MergeArgs, quiet: bool) -> Result<ExitCode> {
    let joined = merge::join(COMMAND, &args.dirs)?;
    let bad = |why: &str| ShardError::Mismatch(format!("study {}: {why}", joined.study));
    let all: Vec<Planned> = serde_json::from_value(joined.detail["plans"].clone())
        .map_err(|e| bad(&format!("its plans cannot be read: {e}")))?;
    let c = &joined.detail["criterion"];
    let number = |k: &str| {
        c[k].as_f64()
            .ok_or_else(|| bad(&format!("criterion `{k}` missing")))
    };
    let crit = Criterion {
        max_ape_m: number("max_ape_m")?,
        max_step_m: number("max_step_m")?,
        t_max_diff_s: number("t_max_diff_s")?,
    };
    let mut plans = Vec::new();
    let mut outcomes = Vec::new();
    for (id, dir, result) in &joined.items {
        let mut p = all
            .iter()
            .find(|p| &p.id == id)
            .cloned()
            .ok_or_else(|| bad(&format!("item `{id}` has no plan")))?;
        p.dir = dir.join("runs").join(id);
        if !is_done(&p.dir) {
            return Err(ShardError::Mismatch(format!(
                "{}: the run of `{id}` has no finished summary.json, though its shard's manifest \
                 lists it: run that shard again",
                p.dir.display()
            ))
            .into());
        }
        outcomes.push(serde_json::from_value::<Outcome>(result.clone()).unwrap_or_default());
        plans.push(p);
    }
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("creating {}", args.out.display()))?;
    joined.write_note(&args.out)?;
    if !quiet {
        eprintln!(
            "keylo compare merge: {} runs of study {} from {} shards",
            plans.len(),
            joined.study,
            joined.shards.len()
        );
    }
    super::report(&args.out, &plans, &outcomes, &crit, args.no_plots, quiet)
}
