use keylo_core::{CoreError, Downsampler, FrameFeatures, LidarFrame, PointCloud};
use serde::{Deserialize, Serialize};

use crate::voxel::{downsample_indices, voxel_of, VoxelMap};

/// Which point represents a voxel.
#[derive(
    Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "kebab-case")]
pub enum VoxelKeep {
    /// The first point in scan order (keeps its time; what KISS-ICP does).
    #[default]
    First,
    /// The mean of the voxel's points (and of their times).
    Centroid,
}

/// `[downsampler] kind = "voxel"`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct VoxelDownsamplerConfig {
    /// Voxel edge (m).
    pub voxel_size: f64,
    /// Which point represents a voxel.
    pub keep: VoxelKeep,
}

impl Default for VoxelDownsamplerConfig {
    fn default() -> Self {
        Self {
            voxel_size: 0.5,
            keep: VoxelKeep::First,
        }
    }
}

/// One point per voxel of the frame's valid points.
pub struct VoxelDownsampler {
    config: VoxelDownsamplerConfig,
}

impl VoxelDownsampler {
    /// Checks `voxel_size` > 0.
    pub fn new(config: VoxelDownsamplerConfig) -> Result<Self, CoreError> {
        if !(config.voxel_size.is_finite() && config.voxel_size > 0.0) {
            return Err(CoreError::stage(
                "downsampler",
                format!(
                    "`voxel_size` = {}: expected a finite value > 0",
                    config.voxel_size
                ),
            ));
        }
        Ok(Self { config })
    }
}

impl Downsampler for VoxelDownsampler {
    fn downsample(
        &mut self,
        frame: &LidarFrame,
        _f: &FrameFeatures,
    ) -> Result<PointCloud, CoreError> {
        let full = frame.to_cloud();
        Ok(match self.config.keep {
            VoxelKeep::First => {
                full.subset(&downsample_indices(&full.points, self.config.voxel_size))
            }
            VoxelKeep::Centroid => centroids(&full, self.config.voxel_size),
        })
    }

    fn needs_grid(&self) -> bool {
        false
    }
}

fn centroids(cloud: &PointCloud, size: f64) -> PointCloud {
    // slot per voxel, in first-seen order: (sum xyz, sum t, sum intensity, n)
    let mut slot: VoxelMap<usize> = VoxelMap::default();
    let mut sums: Vec<([f64; 3], f64, f64, f64)> = Vec::new();
    for (i, p) in cloud.points.iter().enumerate() {
        let k = *slot.entry(voxel_of(p, size)).or_insert_with(|| {
            sums.push(([0.0; 3], 0.0, 0.0, 0.0));
            sums.len() - 1
        });
        let s = &mut sums[k];
        s.0[0] += p.x;
        s.0[1] += p.y;
        s.0[2] += p.z;
        s.1 += cloud.times.as_ref().map_or(0.0, |t| t[i]);
        s.2 += cloud.intensities.as_ref().map_or(0.0, |v| f64::from(v[i]));
        s.3 += 1.0;
    }
    PointCloud {
        timestamp: cloud.timestamp,
        points: sums
            .iter()
            .map(|s| nalgebra::Point3::new(s.0[0] / s.3, s.0[1] / s.3, s.0[2] / s.3))
            .collect(),
        times: cloud
            .times
            .as_ref()
            .map(|_| sums.iter().map(|s| s.1 / s.3).collect()),
        intensities: cloud
            .intensities
            .as_ref()
            .map(|_| sums.iter().map(|s| (s.2 / s.3) as f32).collect()),
    }
}
