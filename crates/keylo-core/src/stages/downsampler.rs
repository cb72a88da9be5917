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

    /// Whether it reads the frame's image grid (pixels, windows, one point per pixel). By
    /// default true; a downsampler of the whole scan's points (`passthrough`, `voxel`) says
    /// false, so that an unorganised source need not project its points.
    fn needs_grid(&self) -> bool {
        true
    }

    /// Row-major frame-grid pixels whose points the last [`Downsampler::downsample`] kept,
    /// for pictures of what was selected (`keylo run --images`); `None` when the
    /// downsampler does not select by pixel (voxel grids, random budgets, plugins).
    fn selected_pixels(&self) -> Option<&[usize]> {
        None
    }
}
