//! `voxel-budget`: a voxel grid whose size is searched per frame to meet a point budget.

use keylo_core::voxel::downsample_indices;
use keylo_core::{CoreError, Downsampler, FrameFeatures, LidarFrame, PixelPoints, PointCloud};
use serde::{Deserialize, Serialize};

use super::Budget;
use crate::neighbourhood::{Mapping, Windows};

/// `[downsampler] kind = "voxel-budget"`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct VoxelBudgetConfig {
    /// Points kept per frame (at most); 0: as many as the keypoint windows (`windows`,
    /// `mapping`) select in the same frame (needs [image] and [detector]).
    pub points: usize,
    /// With `points = 0`: the keypoint-neighbourhood windows whose count is matched.
    pub windows: Windows,
    /// With `points = 0`: the keypoint-neighbourhood mapping whose count is matched.
    pub mapping: Mapping,
    /// Bisection steps of the voxel size search (each one voxelises the frame once).
    pub search_steps: usize,
    /// Voxelise `all` points of an unorganised scan, or one point per pixel (`nearest`, as
    /// the images show them); also how the keypoint budget is counted.
    pub pixel_points: PixelPoints,
}

impl Default for VoxelBudgetConfig {
    fn default() -> Self {
        Self {
            points: 0,
            windows: Windows::default(),
            mapping: Mapping::Exact,
            search_steps: 16,
            pixel_points: PixelPoints::All,
        }
    }
}

/// One point (the first in scan order) per voxel, with the smallest voxel size found whose
/// count fits the budget.
pub struct VoxelBudgetDownsampler {
    budget: Budget,
    steps: usize,
}

impl VoxelBudgetDownsampler {
    /// Checks the config.
    pub fn new(config: VoxelBudgetConfig) -> Result<Self, CoreError> {
        Ok(Self {
            budget: Budget::new(
                (config.points, config.pixel_points),
                &config.windows,
                config.mapping,
            )?,
            steps: config.search_steps.clamp(1, 64),
        })
    }
}

/// Smallest and largest voxel edge searched (m).
const SIZE_RANGE: (f64, f64) = (0.005, 200.0);

impl Downsampler for VoxelBudgetDownsampler {
    fn downsample(
        &mut self,
        frame: &LidarFrame,
        features: &FrameFeatures,
    ) -> Result<PointCloud, CoreError> {
        let n = self.budget.for_frame(frame, features)?.max(1);
        let full = self.budget.candidates(frame);
        if n >= full.len() {
            return Ok(full);
        }
        // Log-space bisection on the voxel edge: count(size) falls as size grows; keep the
        // smallest size whose count fits.
        let (mut lo, mut hi) = (SIZE_RANGE.0.ln(), SIZE_RANGE.1.ln());
        let mut best = downsample_indices(&full.points, SIZE_RANGE.1);
        for _ in 0..self.steps {
            let mid = 0.5 * (lo + hi);
            let idx = downsample_indices(&full.points, mid.exp());
            if idx.len() <= n {
                hi = mid;
                best = idx;
            } else {
                lo = mid;
            }
        }
        Ok(full.subset(&best))
    }
}
