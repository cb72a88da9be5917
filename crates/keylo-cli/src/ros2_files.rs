//! The files `keylo ros2 --out` writes per frame: what `keylo run` writes (trajectory,
//! frames.csv) and ros2_frames.csv (each odometry message's stamp and how long the node held
//! its cloud). A failed write is logged once and the node goes on; the run then ends in error.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::Path;

use anyhow::{Context, Result};

use crate::journal::Journal;
use crate::{report, resources};

/// The per-frame files of a node run with `--out` (none without it).
#[derive(Default)]
pub struct NodeFiles {
    journal: Option<Journal>,
    latency: Option<BufWriter<File>>,
    /// The first write that failed: no more is written after it.
    error: Option<anyhow::Error>,
}

impl NodeFiles {
    /// Creates `dir` with the resolved config and the per-frame files; `None`: no files.
    pub fn create(
        dir: Option<&Path>,
        resolved: &str,
        output: &keylo::config::OutputConfig,
    ) -> Result<Self> {
        let Some(dir) = dir else {
            return Ok(Self::default());
        };
        std::fs::create_dir_all(dir)
            .with_context(|| format!("creating output directory {}", dir.display()))?;
        std::fs::write(dir.join("config.toml"), resolved)
            .with_context(|| format!("writing {}", dir.join("config.toml").display()))?;
        let journal = Journal::create(dir, output)?;
        let path = dir.join("ros2_frames.csv");
        let mut latency = BufWriter::new(
            File::create(&path).with_context(|| format!("creating {}", path.display()))?,
        );
        writeln!(
            latency,
            "frame,stamp_ns,odometry_ms,in_node_ms,waited_ms,prepare_ms,publish_ms"
        )?;
        Ok(Self {
            journal: Some(journal),
            latency: Some(latency),
            error: None,
        })
    }

    /// Writes one published frame's lines (nothing after a failed write).
    pub fn record(&mut self, p: &keylo_ros2::Published) {
        if self.error.is_some() {
            return;
        }
        if let Some(f) = self.latency.as_mut() {
            let line = writeln!(
                f,
                "{},{},{:.3},{:.3},{:.3},{:.3},{:.3}",
                p.result.index,
                p.stamp_ns,
                1e3 * p.seconds,
                1e3 * p.in_node_seconds,
                1e3 * p.waited_seconds,
                1e3 * p.prepare_seconds,
                1e3 * p.publish_seconds
            )
            .and_then(|()| f.flush());
            if let Err(e) = line {
                tracing::error!("writing ros2_frames.csv failed: {e}; the node goes on");
                self.error = Some(e.into());
                return;
            }
        }
        if let Some(j) = self.journal.as_mut() {
            let row = report::FrameRow {
                frame: p.result.index,
                stamp: p.result.stamp,
                keypoints: p.result.keypoints,
                cloud_points: p.result.cloud_points,
                registered_points: p.result.registered_points,
                map_points: p.result.map_points,
                odometry_ms: 1e3 * p.seconds,
                rss_mb: resources::rss_mb(),
                degenerate: p.result.degenerate.map(|d| d.label()),
            };
            if let Err(e) = j.record(p.result.stamp, &p.result.pose, &row) {
                tracing::error!("writing the run's files failed: {e:#}; the node goes on");
                self.error = Some(e);
            }
        }
    }

    /// Closes the files; the first write that failed, if one did.
    pub fn finish(self) -> Option<anyhow::Error> {
        self.error
    }
}
