use crate::{CoreError, FrameFeatures, LidarFrame, PointCloud};

/// Chooses the points of a frame that go to the registrar.
///
/// Owns: its selection rule (all valid points, a voxel grid, keypoint neighbourhoods, …).
/// `features` is empty when the pipeline has no detector.
pub trait Downsampler: Send {
    /// The cloud to register, in the sensor frame, keeping per-point times where it can.
    fn downsample(
        &mut self,
        frame: &LidarFrame,
        features: &FrameFeatures,
    ) -> Result<PointCloud, CoreError>;
}
