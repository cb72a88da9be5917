//! What a run writes and prints: trajectories, `summary.json`, the result table.

use std::path::Path;

use anyhow::{Context, Result};
use keylo::eval::Accuracy;
use keylo::{FrameResult, StageTimings};
use serde::Serialize;

/// Mean milliseconds per frame spent in each stage.
#[derive(Debug, Default, Serialize)]
pub struct StageMs {
    pub image: f64,
    pub detect: f64,
    pub describe: f64,
    pub downsample: f64,
    pub register: f64,
}

/// The frame that stopped a run.
#[derive(Debug, Serialize)]
pub struct Failure {
    /// Frame index in the source (or the count of frames read, if the source itself failed).
    pub frame: u64,
    pub error: String,
}

impl Failure {
    /// Says on stderr that the run stopped here and that its `frames` frames done before it
    /// are written to `out`.
    pub fn say(&self, frames: usize, out: &Path) {
        eprintln!(
            "error: stopped at frame {}: {}\n       the {frames} frames done before it are \
             written to {}",
            self.frame,
            self.error,
            out.display()
        );
    }
}

/// `summary.json`.
#[derive(Debug, Default, Serialize)]
pub struct Summary {
    pub keylo_version: &'static str,
    pub config: String,
    pub source: String,
    pub frames: usize,
    pub frames_skipped: usize,
    /// Frames with no point to register (an empty scan, nothing within the range limits)
    /// whose pose is the registrar's constant-velocity prediction (`empty_frame = "predict"`).
    pub frames_predicted: usize,
    pub failed: Option<Failure>,
    /// Frames whose registration could not constrain the pose (too few registered points, or
    /// a direction without information): the count, and each frame with its reason.
    pub frames_degenerate: usize,
    pub degenerate: Vec<crate::degenerate_out::DegenerateFrame>,
    /// No frame after the first constrained its pose (the run exits with status 4).
    pub all_degenerate: bool,
    /// Frames per second of the odometry stages alone (source reading excluded).
    pub odometry_hz: f64,
    /// Frames per second end to end, source included.
    pub wall_hz: f64,
    pub mean_keypoints: f64,
    /// Mean points the downsampler handed to the registrar.
    pub mean_cloud_points: f64,
    /// Mean points the registrar aligned after its own voxel downsampling.
    pub mean_registered_points: f64,
    pub mean_iterations: f64,
    pub frames_not_converged: usize,
    /// Localisation in a prior map (`[registrar] kind = "localise"`): frames whose fitness
    /// stayed below the threshold (each logged as a warning); absent for odometry.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub frames_not_tracking: Option<usize>,
    pub stage_ms: StageMs,
    pub peak_rss_mb: Option<f64>,
    pub cpu_percent: Option<f64>,
    /// `--realtime`: the playback speed (1: the sensor's rate); absent when frames were read
    /// as fast as they were processed.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub playback_speed: Option<f64>,
    /// `--realtime`: frames released after their time (odometry did not keep up).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub frames_late: Option<u64>,
    pub path_length_m: f64,
    pub ground_truth: Option<String>,
    pub accuracy: Option<Accuracy>,
    /// Why accuracy is missing although ground truth was given.
    pub accuracy_error: Option<String>,
    /// Fewer than 90 % of the estimated poses paired with the reference: the figures, the
    /// likely cause and the options that undo it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub association_warning: Option<String>,
    /// The registrar's degeneracy analysis over the run (per frame in `degeneracy.csv`).
    pub degeneracy: Option<crate::degeneracy_out::DegeneracySummary>,
    /// What the source counted while reading (a live sensor: `packets_lost`, datagrams of
    /// other sizes or sensors, IMU packets).
    #[serde(skip_serializing_if = "std::collections::BTreeMap::is_empty")]
    pub source_counters: std::collections::BTreeMap<String, u64>,
    /// `keylo ros2`: clouds received, dropped, refused and registered by the node.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ros2: Option<serde_json::Value>,
    /// The global map saved with `--map-out`: its folder, points and keyframes.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub map: Option<serde_json::Value>,
}

/// Running sums over frames.
#[derive(Debug, Default)]
pub struct Totals {
    pub frames: usize,
    pub keypoints: usize,
    pub cloud_points: usize,
    pub registered_points: usize,
    pub iterations: usize,
    pub not_converged: usize,
    /// Frames registered without a point (pose predicted).
    pub predicted: usize,
    /// Frames that reported a fit to a prior map, and those of them not tracking.
    pub localised: usize,
    pub not_tracking: usize,
    pub timings: StageTimings,
    pub odometry_seconds: f64,
}

impl Totals {
    pub fn add(&mut self, r: &FrameResult) {
        self.frames += 1;
        self.keypoints += r.keypoints;
        self.cloud_points += r.cloud_points;
        self.registered_points += r.registered_points;
        self.iterations += r.iterations;
        self.not_converged += usize::from(!r.converged);
        self.predicted += usize::from(r.registered_points == 0);
        if let Some(fit) = &r.fit {
            self.localised += 1;
            self.not_tracking += usize::from(!fit.tracking);
        }
        let t = &mut self.timings;
        t.image += r.timings.image;
        t.detect += r.timings.detect;
        t.describe += r.timings.describe;
        t.downsample += r.timings.downsample;
        t.register += r.timings.register;
    }

    pub fn fill(&self, s: &mut Summary) {
        let n = self.frames.max(1) as f64;
        s.frames = self.frames;
        s.mean_keypoints = self.keypoints as f64 / n;
        s.mean_cloud_points = self.cloud_points as f64 / n;
        s.mean_registered_points = self.registered_points as f64 / n;
        s.mean_iterations = self.iterations as f64 / n;
        s.frames_not_converged = self.not_converged;
        s.frames_predicted = self.predicted;
        s.frames_not_tracking = (self.localised > 0).then_some(self.not_tracking);
        s.odometry_hz = if self.odometry_seconds > 0.0 {
            self.frames as f64 / self.odometry_seconds
        } else {
            0.0
        };
        let ms = |v: f64| 1e3 * v / n;
        let t = &self.timings;
        s.stage_ms = StageMs {
            image: ms(t.image),
            detect: ms(t.detect),
            describe: ms(t.describe),
            downsample: ms(t.downsample),
            register: ms(t.register),
        };
    }
}

impl Summary {
    /// `frames_degenerate` and `degenerate` from a run's log (`keylo run`, `keylo ros2 --out`).
    pub fn set_degenerate(&mut self, log: &crate::degenerate_out::DegenerateLog) {
        self.frames_degenerate = log.count;
        self.degenerate = log.frames.clone();
    }
}

/// Writes `summary.json` (the per-frame files are written as the run goes: `journal`).
pub fn write_summary(dir: &Path, summary: &Summary) -> Result<()> {
    let p = dir.join("summary.json");
    let text = serde_json::to_string_pretty(summary)?;
    std::fs::write(&p, text).with_context(|| format!("writing {}", p.display()))?;
    Ok(())
}

/// One registered frame in `frames.csv`: what `keylo compare` plots over time.
#[derive(Debug, Clone, Copy)]
pub struct FrameRow {
    pub frame: u64,
    pub stamp: f64,
    pub keypoints: usize,
    pub cloud_points: usize,
    pub registered_points: usize,
    /// Points in the registrar's local map after the frame.
    pub map_points: usize,
    /// Milliseconds of the odometry stages for this frame (source reading excluded).
    pub odometry_ms: f64,
    /// Resident set size after the frame, MB (`None` off Linux).
    pub rss_mb: Option<f64>,
    /// Why the frame is degenerate (`too-few-points`, `no-information`); `None`: it is not.
    pub degenerate: Option<&'static str>,
}

/// Header of `frames.csv`.
pub const FRAMES_CSV_HEADER: &str =
    "frame,stamp,keypoints,cloud_points,registered_points,map_points,odometry_ms,rss_mb,degenerate";

impl FrameRow {
    /// This frame's line of `frames.csv` (with its newline).
    pub fn csv_line(&self) -> String {
        keylo::io::csv_table::line([
            self.frame.to_string(),
            format!("{:.6}", self.stamp),
            self.keypoints.to_string(),
            self.cloud_points.to_string(),
            self.registered_points.to_string(),
            self.map_points.to_string(),
            format!("{:.3}", self.odometry_ms),
            self.rss_mb.map_or(String::new(), |v| format!("{v:.1}")),
            self.degenerate.unwrap_or_default().to_string(),
        ])
    }
}

/// The human-readable result table.
pub fn table(s: &Summary) -> String {
    let opt =
        |v: Option<f64>, digits: usize| v.map_or("-".to_string(), |v| format!("{v:.digits$}"));
    let acc = s.accuracy.as_ref();
    let rows = [
        ("frames", s.frames.to_string()),
        ("odometry rate (Hz)", format!("{:.1}", s.odometry_hz)),
        ("end-to-end rate (Hz)", format!("{:.1}", s.wall_hz)),
        (
            "points to registrar (mean)",
            format!("{:.0}", s.mean_cloud_points),
        ),
        (
            "points registered (mean)",
            format!("{:.0}", s.mean_registered_points),
        ),
        ("ATE RMSE (m)", opt(acc.map(|a| a.ate_rmse_m), 4)),
        (
            "RPE trans (m/frame)",
            opt(acc.map(|a| a.rpe_trans_rmse_m), 4),
        ),
        (
            "RPE rot (deg/frame)",
            opt(acc.map(|a| a.rpe_rot_rmse_deg), 4),
        ),
        ("drift (%)", opt(acc.and_then(|a| a.drift_pct), 3)),
        ("peak RSS (MB)", opt(s.peak_rss_mb, 1)),
        ("CPU (%)", opt(s.cpu_percent, 0)),
    ];
    let mut out = String::new();
    for (k, v) in rows {
        out.push_str(&format!("  {k:<28} {v:>12}\n"));
    }
    if s.frames_degenerate > 0 {
        let k = "degenerate frames";
        out.push_str(&format!("  {k:<28} {:>12}\n", s.frames_degenerate));
    }
    if let (Some(speed), Some(late)) = (s.playback_speed, s.frames_late) {
        let k = format!("frames late at {speed}x rate");
        out.push_str(&format!("  {k:<28} {late:>12}\n"));
    }
    out
}

/// Logs a source's loss counters: lost packets and skipped datagrams as a warning.
pub fn log_counters(counters: &std::collections::BTreeMap<String, u64>) {
    let lost = counters.get("packets_lost").copied().unwrap_or(0);
    let garbage = counters.get("datagrams_other_size").copied().unwrap_or(0)
        + counters.get("datagrams_other_sensor").copied().unwrap_or(0);
    if lost > 0 {
        tracing::warn!("{lost} packets lost (their columns are invalid in their frames)");
    }
    if garbage > 0 {
        tracing::info!("{garbage} datagrams skipped (not lidar packets of this sensor)");
    }
}
