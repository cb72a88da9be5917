use std::path::PathBuf;

use serde::{Deserialize, Serialize};

/// What to do with a frame a stage rejects (empty, all-NaN, …). A frame the source cannot
/// read (a truncated or corrupt file) always stops the run: later frames may be unreadable too.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "kebab-case")]
pub enum OnBadFrame {
    /// Stop the run with an error naming the frame; the trajectory so far is written.
    #[default]
    Stop,
    /// Skip the frame, log a warning and count it in the summary.
    Skip,
}

/// `output.on_degenerate`: what a degenerate frame does to a run (too few registered points,
/// or a pose direction without information; see `keylo_core::Degenerate`).
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "kebab-case")]
pub enum OnDegenerate {
    /// A warning naming the frame; the frame is flagged in frames.csv and summary.json and
    /// the run goes on.
    #[default]
    Warn,
    /// Stop the run at the frame with an error; the frames before it are written.
    Error,
}

/// `[output]`: where and what a run writes.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct OutputConfig {
    /// Output directory; empty means `runs/<timestamp>/`. `--out` overrides it.
    pub dir: String,
    /// Write `trajectory.tum` (t tx ty tz qx qy qz qw).
    pub tum: bool,
    /// Write `trajectory.kitti` (3x4 row-major pose matrices).
    pub kitti: bool,
    /// Ground-truth trajectory (TUM or KITTI) for accuracy figures; empty: use the source's own.
    pub gt: String,
    /// What to do with a frame a stage rejects (empty, all-NaN): `stop` or `skip`. A frame the
    /// source cannot read always stops the run.
    pub on_bad_frame: OnBadFrame,
    /// What a degenerate frame does: `warn` (flag it, go on) or `error` (stop there, keeping
    /// the frames before). A frame is degenerate when the registrar used fewer points than
    /// its minimum (KISS-ICP and hybrid 3, the others 6) or its degeneracy analysis finds a
    /// pose direction with no information. Under `warn`, a run in which every frame after the
    /// first is degenerate exits with status 4; under `error` the run stops at the first
    /// degenerate frame with status 3.
    pub on_degenerate: OnDegenerate,
    /// Write the trajectory files' numbers in their shortest exact form (`1.2345678901234567e0`)
    /// instead of 9 decimals (TUM) or 13 digits (KITTI): read back, bit for bit the poses.
    pub exact: bool,
    /// Write `pose_graph.g2o`: a `VERTEX_SE3:QUAT` per keyframe (every `[map]`
    /// `keyframe_distance` m or `keyframe_angle_deg`°) and an `EDGE_SE3:QUAT` between
    /// consecutive keyframes whose information is keylo's own covariance estimate
    /// (docs/maps.md).
    pub pose_graph: bool,
    /// The pose graph's covariances: 0 uses the noise model fitted for the registrar against
    /// simulated ground truth (`s·H⁻¹` plus terms growing with each frame's motion;
    /// docs/results/maps.md); a value σ (m) uses plain `σ² H⁻¹` instead.
    pub covariance_sigma_m: f64,
}

impl Default for OutputConfig {
    fn default() -> Self {
        Self {
            dir: String::new(),
            tum: true,
            kitti: true,
            gt: String::new(),
            on_bad_frame: OnBadFrame::Stop,
            on_degenerate: OnDegenerate::Warn,
            exact: false,
            pose_graph: false,
            covariance_sigma_m: 0.0,
        }
    }
}

impl OutputConfig {
    /// The output directory, if one is set.
    pub fn dir_path(&self) -> Option<PathBuf> {
        (!self.dir.is_empty()).then(|| PathBuf::from(&self.dir))
    }
}
