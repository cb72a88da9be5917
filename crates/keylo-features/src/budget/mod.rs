//! Same-budget baselines for the keypoint-neighbourhood downsampler: `random` and
//! `voxel-budget` keep as many points as a fixed count or as the keypoint windows of the
//! same frame select, so a comparison isolates *which* points are chosen from *how many*.

mod random;
mod voxel;

pub use random::{RandomConfig, RandomDownsampler};
pub use voxel::{VoxelBudgetConfig, VoxelBudgetDownsampler};

use std::collections::BTreeMap;

use keylo_core::config::StageParams;
use keylo_core::{CoreError, FrameFeatures, LidarFrame, PixelPoints, PointCloud};

use crate::neighbourhood::{select_pixels, Mapping, Windows};

/// How many points a baseline keeps in one frame.
pub(crate) struct Budget {
    points: usize,
    sizes: BTreeMap<String, usize>,
    mapping: Mapping,
    pixel_points: PixelPoints,
}

impl Budget {
    pub(crate) fn new(
        (points, pixel_points): (usize, PixelPoints),
        windows: &Windows,
        mapping: Mapping,
    ) -> Result<Self, CoreError> {
        let sizes = windows.sizes().map_err(|e| e.in_stage("downsampler"))?;
        Ok(Self {
            points,
            sizes,
            mapping,
            pixel_points,
        })
    }

    /// The frame's points the baseline samples from: every point of the scan, or one per
    /// pixel (`pixel_points`).
    pub(crate) fn candidates(&self, frame: &LidarFrame) -> PointCloud {
        frame.cloud(self.pixel_points)
    }

    /// The point count for `frame`: the fixed count, or what the keypoint windows select.
    pub(crate) fn for_frame(
        &self,
        frame: &LidarFrame,
        features: &FrameFeatures,
    ) -> Result<usize, CoreError> {
        if self.points > 0 {
            return Ok(self.points);
        }
        if features.per_image.is_empty() {
            return Err(CoreError::stage(
                "downsampler",
                "`points = 0` matches the keypoint-neighbourhood budget and needs keypoints: \
                 configure [image] and [detector], or set `points` to a fixed count",
            ));
        }
        select_pixels(frame, features, &self.sizes, self.mapping)
            .map(|p| frame.count_selected(&p, self.pixel_points))
            .map_err(|e| e.in_stage("downsampler"))
    }
}

keylo_core::stage_params!(RandomConfig => "random" as DownsamplerParams);
keylo_core::stage_params!(VoxelBudgetConfig => "voxel-budget" as DownsamplerParams);

/// Registers downsamplers `random` and `voxel-budget`.
pub fn register(registry: &mut keylo_core::Registry) {
    registry.downsamplers.add::<RandomConfig>(
        RandomConfig::KIND,
        "uniformly random valid points, as many as a fixed count or the keypoint windows select",
        |config, _ctx| Ok(Box::new(RandomDownsampler::new(config)?)),
    );
    registry.downsamplers.add::<VoxelBudgetConfig>(
        VoxelBudgetConfig::KIND,
        "a voxel grid sized per frame to keep a fixed count or as many points as the keypoint windows select",
        |config, _ctx| Ok(Box::new(VoxelBudgetDownsampler::new(config)?)),
    );
}
