//! `[source] kind = "kitti"`: the parameters of a KITTI-style scan folder.

use serde::{Deserialize, Serialize};

use crate::cloud::ProjectionConfig;
use crate::select::FrameSelection;

/// A KITTI odometry sequence folder (`kind = "kitti"`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct KittiSourceConfig {
    /// The sequence folder (`velodyne/*.bin` plus optional `times.txt`, `calib.txt` and
    /// poses), a folder of `.bin` scans, or one `.bin` file; relative to the config file.
    pub path: String,
    /// Index of the first scan to read.
    pub start: usize,
    /// Read every `stride`-th scan from `start` (1 = every scan).
    pub stride: usize,
    /// Scans to read at most; 0 = all.
    pub max_frames: usize,
    /// Scans per second; frame times are `index / frame_rate_hz` when there is no
    /// `times.txt`.
    pub frame_rate_hz: f64,
    /// Ground-truth pose file (KITTI 3×4 per line, cam0 frame, one pose per scan), relative
    /// to the sequence folder; converted to the LiDAR frame with `calib.txt`'s `Tr`. Empty:
    /// `poses.txt` when the folder has one.
    pub poses: String,
    /// Rotate every point up by this angle (degrees) about the horizontal axis perpendicular
    /// to it, as KISS-ICP's `--dataloader kitti` does (0.205; also IMLS-SLAM, CT-ICP) to
    /// undo a bias of KITTI's calibration. 0: the points as the files hold them (KISS-ICP's
    /// generic loader for a folder of `.bin` files).
    pub vertical_angle_correction_deg: f64,
    /// `[source.projection]`: how scans become images. `sensor = "auto"` is KITTI's HDL-64E
    /// (64 × 2048 over +3°..−25°).
    pub projection: ProjectionConfig,
}

impl Default for KittiSourceConfig {
    fn default() -> Self {
        Self {
            path: String::new(),
            start: 0,
            stride: 1,
            max_frames: 0,
            frame_rate_hz: 10.0,
            poses: String::new(),
            vertical_angle_correction_deg: 0.0,
            projection: ProjectionConfig::default(),
        }
    }
}

impl KittiSourceConfig {
    /// The frame selection; the error names the key.
    pub fn selection(&self) -> Result<FrameSelection, crate::select::SelectionError> {
        FrameSelection::new(self.start, self.stride, self.max_frames)
    }
}
