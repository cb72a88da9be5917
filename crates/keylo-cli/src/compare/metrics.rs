//! One table row per run: accuracy against ground truth, resources, points, rate and the
//! divergence verdict, read from what `keylo run` wrote (summary.json, trajectory.tum,
//! frames.csv, config.toml).

use std::path::Path;

use keylo::eval::ape::ApeResult;
use keylo::eval::associate::Associated;
use keylo::eval::divergence::{aligned_ape, judge, verdict_ape, VerdictApe};
use keylo::Trajectory;
use serde_json::Value;

use super::association;
use super::row::{Criterion, Row};
use super::schedule::{Outcome, Planned};
use crate::trajectories;

/// Per-frame series of a run, for the plots.
#[derive(Debug, Clone, Default)]
pub struct Series {
    /// Aligned estimate positions (x, y) and the matched ground truth (x, y).
    pub est_xy: Vec<(f64, f64)>,
    pub gt_xy: Vec<(f64, f64)>,
    /// (time since the first frame s, APE m).
    pub ape: Vec<(f64, f64)>,
    /// (frame, points to registrar), (frame, Hz), (frame, RSS MB).
    pub points: Vec<(f64, f64)>,
    pub rate: Vec<(f64, f64)>,
    pub rss: Vec<(f64, f64)>,
}

/// Builds the row and series of one run.
pub fn collect(plan: &Planned, outcome: &Outcome, crit: &Criterion) -> (Row, Series) {
    let mut row = Row {
        data: plan.data_label.clone(),
        variant: plan.variant.clone(),
        config: plan
            .config
            .as_ref()
            .map_or("built-in default".into(), |p| p.display().to_string()),
        resumed: outcome.resumed,
        reference: plan.gt_label.clone(),
        ..Row::default()
    };
    let mut series = Series::default();
    read_kinds(&plan.dir, &mut row);
    let summary = read_json(&plan.dir.join("summary.json"));
    if let Some(s) = &summary {
        fill_from_summary(s, &mut row);
    }
    read_frames(&plan.dir.join("frames.csv"), &mut series);
    let mut est = trajectories::Labelled::read(&plan.dir.join("trajectory.tum")).ok();
    let time = plan.gt_time.unwrap_or_default();
    let mut gt = plan
        .gt
        .as_ref()
        .and_then(|p| crate::reference_args::read(p, time).ok());
    let mut ape = None;
    if let (Some(e), Some(g)) = (est.as_mut(), gt.as_mut()) {
        // A KITTI ground truth has no stamps: pair it one for one, as `keylo run` does.
        if trajectories::reconcile(e, g).is_ok() {
            let (e, g) = (&e.trajectory, &g.trajectory);
            association::measure(plan, e, g, crit, &mut row);
            let aligned = aligned_ape(e, g, crit.t_max_diff_s).ok();
            if let Some((pairs, result)) = &aligned {
                fill_ape(pairs, result, &mut row, &mut series);
            }
            ape = verdict_ape(aligned.as_ref().map(|(_, r)| r), e, g, crit.t_max_diff_s);
        }
    }
    let est = est.map(|l| l.trajectory);
    let stopped = summary
        .as_ref()
        .and_then(|s| s.get("failed"))
        .filter(|f| !f.is_null())
        .map(|f| {
            format!(
                "stopped at frame {}: {}",
                f["frame"],
                f["error"].as_str().unwrap_or("?")
            )
        });
    let (verdict, reason) = if outcome.timed_out {
        let done = row.frames.map_or("no".into(), |n| n.to_string());
        let how = match outcome.exit_code {
            Some(_) => "stopped",
            None => "killed",
        };
        (
            "failed",
            format!(
                "timed out after {:.1} s ({how}; {done} frames done and kept)",
                outcome.seconds
            ),
        )
    } else if let Some(why) = stopped {
        ("failed", why)
    } else if let Some(why) = all_degenerate(summary.as_ref()) {
        ("failed", why)
    } else if summary.is_none() {
        let why = outcome
            .error
            .clone()
            .unwrap_or_else(|| "no summary.json".into());
        ("failed", why)
    } else {
        divergence(est.as_ref(), ape, crit, gt.is_some())
    };
    row.reason = association::explain(&row, verdict, reason);
    row.verdict = verdict.into();
    (row, series)
}

fn divergence(
    est: Option<&Trajectory>,
    ape: Option<VerdictApe>,
    crit: &Criterion,
    has_gt: bool,
) -> (&'static str, String) {
    let Some(est) = est else {
        return ("failed", "no trajectory.tum".into());
    };
    let (verdict, reason) = judge(est, ape, has_gt, crit);
    (verdict.as_str(), reason)
}

/// Why a run counts as failed when summary.json says no frame after the first constrained
/// its pose (`keylo run` exited 4).
fn all_degenerate(summary: Option<&Value>) -> Option<String> {
    let s = summary?;
    if s.get("all_degenerate").and_then(Value::as_bool) != Some(true) {
        return None;
    }
    let first = s.get("degenerate").and_then(|d| d.get(0));
    let reason = first
        .and_then(|f| f.get("reason"))
        .and_then(Value::as_str)
        .unwrap_or("?");
    Some(format!(
        "every frame after the first degenerate ({reason}): the trajectory is the motion \
         model's prediction, not odometry"
    ))
}

fn read_json(path: &Path) -> Option<Value> {
    serde_json::from_str(&std::fs::read_to_string(path).ok()?).ok()
}

fn read_kinds(dir: &Path, row: &mut Row) {
    let Some(table) = std::fs::read_to_string(dir.join("config.toml"))
        .ok()
        .and_then(|t| t.parse::<toml::Table>().ok())
    else {
        return;
    };
    let kind = |s: &str| {
        table
            .get(s)
            .and_then(|v| v.get("kind"))
            .and_then(toml::Value::as_str)
            .unwrap_or("")
            .to_string()
    };
    row.registrar = kind("registrar");
    row.downsampler = kind("downsampler");
}

fn fill_from_summary(s: &Value, row: &mut Row) {
    let f = |k: &str| s.get(k).and_then(Value::as_f64);
    row.frames = s.get("frames").and_then(Value::as_u64).map(|n| n as usize);
    row.degenerate_frames = s
        .get("frames_degenerate")
        .and_then(Value::as_u64)
        .map(|n| n as usize);
    row.cpu_percent = f("cpu_percent");
    row.peak_rss_mb = f("peak_rss_mb");
    row.playback_speed = f("playback_speed");
    row.frames_late = s
        .get("frames_late")
        .and_then(Value::as_u64)
        .map(|n| n as usize);
    row.mean_points = f("mean_cloud_points");
    row.mean_registered_points = f("mean_registered_points");
    row.odometry_hz = f("odometry_hz");
    let acc = s.get("accuracy");
    let a = |k: &str| acc.and_then(|a| a.get(k)).and_then(Value::as_f64);
    row.rpe_trans_m = a("rpe_trans_rmse_m");
    row.rpe_rot_deg = a("rpe_rot_rmse_deg");
}

fn fill_ape(pairs: &Associated, result: &ApeResult, row: &mut Row, series: &mut Series) {
    row.associated_poses = Some(pairs.len());
    row.trans_mean_m = Some(result.translation.mean);
    row.trans_rmse_m = Some(result.translation.rmse);
    row.trans_max_m = Some(result.translation.max);
    row.rot_mean_deg = Some(result.rotation_deg.mean);
    row.rot_rmse_deg = Some(result.rotation_deg.rmse);
    let aligned = result.alignment.apply_trajectory(&pairs.estimate);
    series.est_xy = xy(&aligned);
    series.gt_xy = xy(&pairs.reference);
    let t0 = pairs.reference.stamps.first().copied().unwrap_or(0.0);
    series.ape = pairs
        .reference
        .stamps
        .iter()
        .zip(&result.translation_errors)
        .map(|(t, e)| (t - t0, *e))
        .collect();
}

fn xy(t: &Trajectory) -> Vec<(f64, f64)> {
    t.poses
        .iter()
        .map(|p| (p.translation.vector.x, p.translation.vector.y))
        .collect()
}

fn read_frames(path: &Path, series: &mut Series) {
    let Ok((header, records)) = keylo::io::csv_table::read(path) else {
        return;
    };
    // Columns by name, so files of older layouts (without `map_points`) still read.
    let col = |name: &str| header.iter().position(|h| h == name);
    let (points, ms, rss) = (col("cloud_points"), col("odometry_ms"), col("rss_mb"));
    for cols in &records {
        let num = |i: Option<usize>| i.and_then(|i| cols.get(i)?.parse::<f64>().ok());
        let Some(frame) = num(Some(0)) else { continue };
        if let Some(p) = num(points) {
            series.points.push((frame, p));
        }
        if let Some(ms) = num(ms).filter(|ms| *ms > 0.0) {
            series.rate.push((frame, 1e3 / ms));
        }
        if let Some(r) = num(rss) {
            series.rss.push((frame, r));
        }
    }
}

/// Fills `rate_vs_raw`: each run's odometry rate over that of the `passthrough` run with the
/// same data and registrar kind.
pub fn add_rate_ratios(rows: &mut [Row]) {
    let raw: Vec<(String, String, f64)> = rows
        .iter()
        .filter(|r| r.downsampler == "passthrough")
        .filter_map(|r| Some((r.data.clone(), r.registrar.clone(), r.odometry_hz?)))
        .collect();
    for r in rows.iter_mut() {
        let base = raw
            .iter()
            .find(|(d, k, _)| *d == r.data && *k == r.registrar)
            .map(|(_, _, hz)| *hz);
        r.rate_vs_raw = r.odometry_hz.zip(base).map(|(a, b)| a / b.max(1e-12));
    }
}
