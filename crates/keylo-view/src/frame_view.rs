//! What the viewer is given per frame, and what the recording reports.

use std::path::PathBuf;

use keylo_core::{FrameFeatures, FrameResult, LidarFrame, PointCloud};
use nalgebra::Point3;

/// One frame's results, as the viewer takes them.
pub struct FrameView<'a> {
    pub frame: &'a LidarFrame,
    pub result: &'a FrameResult,
    /// The images, keypoints and descriptors (`None` when the features were not kept).
    pub features: Option<&'a FrameFeatures>,
    /// The points the registrar was given (sensor frame).
    pub cloud: Option<&'a PointCloud>,
    /// The local map (world frame): give it when [`Viewer::wants_map`] said so.
    pub map: Option<&'a [Point3<f64>]>,
    /// Seconds every stage of the frame took.
    pub seconds: f64,
}

/// The recording written.
#[derive(Debug, Clone)]
pub struct RecordSummary {
    pub path: PathBuf,
    pub bytes: u64,
    pub frames: u64,
}
