//! What one frame gives: its pose, counts and stage timings.

use crate::Pose;

/// Seconds spent in each stage for one frame.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct StageTimings {
    pub image: f64,
    pub detect: f64,
    pub describe: f64,
    pub downsample: f64,
    pub register: f64,
}

impl StageTimings {
    /// Sum over stages.
    pub fn total(&self) -> f64 {
        self.image + self.detect + self.describe + self.downsample + self.register
    }
}

/// The result of one frame.
#[derive(Debug, Clone, PartialEq)]
pub struct FrameResult {
    pub index: u64,
    /// Time the pose refers to, seconds: the frame's end ([`LidarFrame::end_stamp`]), the same
    /// whichever points the downsampler kept.
    pub stamp: f64,
    pub pose: Pose,
    /// Keypoints found over all images.
    pub keypoints: usize,
    /// Points the downsampler passed to the registrar.
    pub cloud_points: usize,
    /// Points the registrar used after its own preprocessing.
    pub registered_points: usize,
    /// Points in the registrar's local map after this frame.
    pub map_points: usize,
    pub iterations: usize,
    pub converged: bool,
    /// The registrar's degeneracy analysis of this frame, when it makes one.
    pub degeneracy: Option<crate::Degeneracy>,
    /// Why the registration could not constrain the pose, when it could not (too few points,
    /// a direction without information): the pose is then (partly) the prediction.
    pub degenerate: Option<crate::Degenerate>,
    /// How well the frame fits the prior map, when the registrar localises in one.
    pub fit: Option<crate::MapFit>,
    pub timings: StageTimings,
}

impl FrameResult {
    /// The result of a frame whose pose came from elsewhere (ground truth, another odometry):
    /// for a [`FrameResult`]-taking consumer such as a map builder; counts zero, no
    /// degeneracy analysis.
    pub fn with_pose(index: u64, stamp: f64, pose: Pose) -> Self {
        Self {
            index,
            stamp,
            pose,
            keypoints: 0,
            cloud_points: 0,
            registered_points: 0,
            map_points: 0,
            iterations: 0,
            converged: true,
            degeneracy: None,
            degenerate: None,
            fit: None,
            timings: StageTimings::default(),
        }
    }
}
