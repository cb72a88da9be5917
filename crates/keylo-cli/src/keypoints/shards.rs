//! `keylo keypoints eval|sweep --shard I/N` and `… merge OUT DIR...`: the keypoint study split
//! into items (eval: detector group × block of images; sweep: cell × detector group), each
//! shard doing its part into its own folder, the merge writing the tables of one process
//! (identical except the timing columns and notes).

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;
use std::process::ExitCode;
use std::sync::Mutex;
use std::time::Instant;

use anyhow::{Context, Result};
use keylo::kpeval::items::{eval_items, evaluate_items, BLOCK};
use keylo::kpeval::sweep::{
    run_sweep, sweep_tasks, task_name, CellResult, SweepGrid, SweepOptions, SweepResult,
};
use keylo::kpeval::{EvalOptions, EvalSpec, Plane, Row};
use keylo::BuildContext;
use serde_json::{json, Value};
use sha2::{Digest, Sha256};

use super::eval_report::{write_report, EvalReport};
use super::input::Prepared;
use super::report::PaperFigures;
use crate::arg_groups::MergeArgs;
use crate::shard::manifest::Manifest;
use crate::shard::{merge, partition, Shard, ShardError};
use crate::EXIT_FRAME_FAILED;

const EVAL: &str = "keypoints eval";
const SWEEP: &str = "keypoints sweep";

/// A digest of the images' pixels: shards of one study must have read the same images.
fn digest(planes: &[Plane]) -> String {
    let mut h = Sha256::new();
    for p in planes {
        h.update((p.rows as u64).to_le_bytes());
        h.update((p.cols as u64).to_le_bytes());
        h.update(&p.data);
    }
    h.finalize()
        .iter()
        .take(8)
        .map(|b| format!("{b:02x}"))
        .collect()
}

fn combo_names(p: &Prepared) -> Vec<String> {
    p.combos.iter().map(|c| c.name.clone()).collect()
}

fn labels(planes: &[Plane]) -> Vec<String> {
    planes.iter().map(|p| p.label.clone()).collect()
}

/// This shard's fresh (or resumed) manifest in `out`, already written.
fn open(
    command: &str,
    shard: Shard,
    detail: Value,
    items: &[(String, f64)],
    out: &Path,
) -> Result<Manifest, ShardError> {
    let costs: Vec<f64> = items.iter().map(|(_, c)| *c).collect();
    let ids = items.iter().map(|(id, _)| id.clone()).collect();
    let m = Manifest::new(command, shard, detail, ids, &partition(&costs, shard.count))
        .resume_in(out)?;
    m.write(out)?;
    Ok(m)
}

fn say_done(command: &str, m: &Manifest, ran: usize, quiet: bool) {
    if !quiet {
        eprintln!(
            "keylo {command}: shard {}/{} of study {}: {} items ({ran} run now, {} resumed) in \
             {:.1} s; join the shards with `keylo {command} merge OUT DIR...`",
            m.shard,
            m.shards,
            m.study,
            m.items.len(),
            m.items.len() - ran,
            m.seconds
        );
    }
}

/// The optional path of `detail[key]`.
fn path_of(detail: &Value, key: &str) -> Option<std::path::PathBuf> {
    detail[key].as_str().map(std::path::PathBuf::from)
}

/// `keylo keypoints eval --shard I/N`.
pub fn eval_shard(
    args: &super::EvalArgs,
    shard: Shard,
    spec: &EvalSpec,
    p: &Prepared,
    ctx: &BuildContext,
    quiet: bool,
) -> Result<ExitCode> {
    let started = Instant::now();
    let out = args.input.out();
    let (items, skipped) = eval_items(
        p.planes.len(),
        &p.combos,
        spec,
        &p.registry,
        ctx,
        (&p.planes, p.set.skips_unavailable()),
    )?;
    let detail = json!({
        "settings": spec,
        "images": labels(&p.planes),
        "pixels": digest(&p.planes),
        "combos": combo_names(p),
        "block": BLOCK,
        "skipped": skipped,
        "paper": args.paper.as_ref().map(|p| p.display().to_string()),
        "reference": args.reference.as_ref().map(|p| p.display().to_string()),
    });
    let ids: Vec<(String, f64)> = items.iter().map(|i| (i.id(), i.cost)).collect();
    let manifest = open(EVAL, shard, detail, &ids, out)?;
    let todo: Vec<_> = items
        .iter()
        .filter(|i| {
            let id = i.id();
            manifest.items.contains(&id) && !manifest.results.contains_key(&id)
        })
        .cloned()
        .collect();
    let manifest = Mutex::new(manifest);
    let write_error: Mutex<Option<ShardError>> = Mutex::new(None);
    let done = |i: usize, (rows, failure): &(Vec<Row>, Option<(String, String)>), secs: f64| {
        let result = json!({ "rows": rows, "failed": failure, "seconds": secs });
        if let (Ok(mut m), Some(item)) = (manifest.lock(), todo.get(i)) {
            m.results.insert(item.id(), result);
            if let Err(e) = m.write(out) {
                if let Ok(mut w) = write_error.lock() {
                    w.get_or_insert(e);
                }
            }
        }
    };
    let opts = EvalOptions {
        jobs: p.jobs,
        skip_unavailable: p.set.skips_unavailable(),
        progress: None,
    };
    evaluate_items(
        &p.planes,
        &p.combos,
        spec,
        (&p.registry, ctx),
        &opts,
        &todo,
        &done,
    )?;
    if let Some(e) = write_error.into_inner().ok().flatten() {
        return Err(e.into());
    }
    let mut m = manifest
        .into_inner()
        .map_err(|_| anyhow::anyhow!("a shard worker panicked"))?;
    m.complete = m.items.iter().all(|id| m.results.contains_key(id));
    m.seconds = started.elapsed().as_secs_f64();
    m.write(out)?;
    say_done(EVAL, &m, todo.len(), quiet);
    let failed = m.results.values().any(|r| !r["failed"].is_null());
    Ok(if failed {
        ExitCode::from(EXIT_FRAME_FAILED)
    } else {
        ExitCode::SUCCESS
    })
}

fn bad(study: &str, why: String) -> anyhow::Error {
    ShardError::Mismatch(format!("study {study}: {why}")).into()
}

/// `keylo keypoints eval merge OUT DIR...`.
pub fn eval_merge(args: &MergeArgs, quiet: bool) -> Result<ExitCode> {
    let joined = merge::join(EVAL, &args.dirs)?;
    let d = &joined.detail;
    let read = |v: &Value, what: &str| -> Result<Value> {
        if v.is_null() {
            return Err(bad(&joined.study, format!("its {what} are missing")));
        }
        Ok(v.clone())
    };
    let spec: EvalSpec = serde_json::from_value(read(&d["settings"], "settings")?)?;
    let images: Vec<String> = serde_json::from_value(read(&d["images"], "images")?)?;
    let skipped: Vec<(String, String)> = serde_json::from_value(read(&d["skipped"], "skips")?)?;
    let mut rows: Vec<Row> = Vec::new();
    let mut failed: Vec<(String, String)> = Vec::new();
    for (id, _, result) in &joined.items {
        let r: Vec<Row> = serde_json::from_value(result["rows"].clone())
            .map_err(|e| bad(&joined.study, format!("item `{id}`: its rows: {e}")))?;
        rows.extend(r);
        if let Ok(f) = serde_json::from_value::<(String, String)>(result["failed"].clone()) {
            failed.push(f);
        }
    }
    let paper = path_of(d, "paper")
        .map(|p| PaperFigures::read(&p))
        .transpose()?;
    let reference = path_of(d, "reference")
        .map(|p| keylo::kpeval::reference::Reference::read_dir(&p))
        .transpose()?;
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("creating {}", args.out.display()))?;
    let seconds: f64 = joined.shards.iter().map(|(_, s)| s).sum();
    joined.write_note(&args.out)?;
    write_report(
        &args.out,
        &EvalReport {
            rows: &rows,
            skipped: &skipped,
            failed: &failed,
            spec: &spec,
            images: &images,
            jobs: joined.shards.len(),
            seconds,
            paper: paper.as_ref(),
            reference: reference.as_ref(),
        },
        args.no_plots,
        quiet,
    )
}

/// `keylo keypoints sweep --shard I/N`.
pub fn sweep_shard(
    args: &super::SweepArgs,
    shard: Shard,
    (spec, grid): (&EvalSpec, &SweepGrid),
    p: &Prepared,
    quiet: bool,
    progress: &(dyn Fn(usize, usize, usize) + Sync),
) -> Result<ExitCode> {
    let started = Instant::now();
    let out = args.input.out();
    let ctx = BuildContext {
        trust: args.input.trust.trust(),
        ..BuildContext::default()
    };
    let (tasks, skipped) = sweep_tasks(
        &p.combos,
        spec,
        grid,
        (&p.registry, &ctx),
        p.set.skips_unavailable(),
    )?;
    let interpolations: Vec<String> = grid
        .interpolations
        .iter()
        .map(|i| keylo::kpeval::sweep::interpolation_name(*i))
        .collect();
    let detail = json!({
        "settings": spec,
        "images": labels(&p.planes),
        "pixels": digest(&p.planes),
        "combos": combo_names(p),
        "grid": {"interpolations": interpolations, "widths": grid.widths, "heights": grid.heights},
        "skipped": skipped,
    });
    let mut m = open(SWEEP, shard, detail, &tasks, out)?;
    let only: BTreeSet<String> = m.items.iter().cloned().collect();
    let seconds: Mutex<BTreeMap<String, f64>> = Mutex::new(BTreeMap::new());
    let timed = |id: &str, s: f64| {
        if let Ok(mut t) = seconds.lock() {
            t.insert(id.to_string(), s);
        }
    };
    let result = run_sweep(
        &p.planes,
        &p.combos,
        spec,
        grid,
        &p.registry,
        &ctx,
        &SweepOptions {
            jobs: p.jobs,
            skip_unavailable: p.set.skips_unavailable(),
            store: out.join("sweep.csv"),
            progress: Some(progress),
            only: Some(&only),
            timed: Some(&timed),
        },
    )?;
    let detector: BTreeMap<&str, &str> = p
        .combos
        .iter()
        .map(|c| (c.name.as_str(), c.detector.as_str()))
        .collect();
    let task_of = |r: &CellResult| {
        let group = detector.get(r.combo.as_str()).copied().unwrap_or("");
        task_name(&r.interpolation, (r.width, r.height), group)
    };
    let mut cells: BTreeMap<String, Vec<&CellResult>> = BTreeMap::new();
    for r in &result.results {
        cells.entry(task_of(r)).or_default().push(r);
    }
    let times = seconds.into_inner().unwrap_or_default();
    for id in &m.items {
        let failure = result.failed.iter().find(|(what, _)| what == id);
        let found = cells.get(id).filter(|c| !c.is_empty());
        if found.is_none() && failure.is_none() {
            continue;
        }
        // A task resumed from sweep.csv keeps the seconds recorded when it ran.
        let secs = times
            .get(id)
            .copied()
            .or_else(|| m.results.get(id).and_then(|r| r["seconds"].as_f64()));
        let entry = json!({ "cells": found.cloned().unwrap_or_default(), "failed": failure,
                            "seconds": secs });
        m.results.insert(id.clone(), entry);
    }
    m.complete = m.items.iter().all(|id| m.results.contains_key(id));
    m.seconds = started.elapsed().as_secs_f64();
    m.write(out)?;
    say_done(SWEEP, &m, result.tasks_run, quiet);
    Ok(if result.failed.is_empty() {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(EXIT_FRAME_FAILED)
    })
}

/// `keylo keypoints sweep merge OUT DIR...`.
pub fn sweep_merge(args: &MergeArgs, quiet: bool) -> Result<ExitCode> {
    let joined = merge::join(SWEEP, &args.dirs)?;
    let d = &joined.detail;
    let study = joined.study.clone();
    let spec: EvalSpec = serde_json::from_value(d["settings"].clone())
        .map_err(|e| bad(&study, format!("its settings: {e}")))?;
    let g = &d["grid"];
    let grid = SweepGrid {
        interpolations: serde_json::from_value::<Vec<String>>(g["interpolations"].clone())
            .map_err(|e| bad(&study, format!("its grid: {e}")))?
            .iter()
            .map(|n| keylo::kpeval::sweep::parse_interpolation(n))
            .collect::<Result<_, _>>()?,
        widths: serde_json::from_value(g["widths"].clone())
            .map_err(|e| bad(&study, format!("its grid: {e}")))?,
        heights: serde_json::from_value(g["heights"].clone())
            .map_err(|e| bad(&study, format!("its grid: {e}")))?,
    };
    let images = d["images"].as_array().map_or(0, Vec::len);
    let mut result = SweepResult {
        skipped: serde_json::from_value(d["skipped"].clone()).unwrap_or_default(),
        tasks_run: joined.items.len(),
        seconds: joined.shards.iter().map(|(_, s)| s).sum(),
        ..SweepResult::default()
    };
    for (id, _, r) in &joined.items {
        let cells: Vec<CellResult> = serde_json::from_value(r["cells"].clone())
            .map_err(|e| bad(&study, format!("item `{id}`: its cells: {e}")))?;
        result.images_evaluated += cells.iter().map(|c| c.images).sum::<usize>();
        result.results.extend(cells);
        if let Ok(f) = serde_json::from_value::<(String, String)>(r["failed"].clone()) {
            result.failed.push(f);
        }
    }
    keylo::kpeval::sweep::sort_results(&mut result.results);
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("creating {}", args.out.display()))?;
    joined.write_note(&args.out)?;
    super::sweep_report::write_report(
        &args.out,
        &super::sweep_report::SweepReport {
            grid: &grid,
            spec: &spec,
            images,
            jobs: joined.shards.len(),
            result: &result,
        },
        args.no_plots,
        quiet,
    )
}
