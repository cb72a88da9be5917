//! `random`: a uniform sample of the frame's valid points.

use keylo_core::{CoreError, Downsampler, FrameFeatures, LidarFrame, PixelPoints, PointCloud};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

use super::Budget;
use crate::neighbourhood::{Mapping, Windows};

/// `[downsampler] kind = "random"`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct RandomConfig {
    /// Points kept per frame; 0: as many as the keypoint windows (`windows`, `mapping`)
    /// select in the same frame (needs [image] and [detector]).
    pub points: usize,
    /// With `points = 0`: the keypoint-neighbourhood windows whose count is matched.
    pub windows: Windows,
    /// With `points = 0`: the keypoint-neighbourhood mapping whose count is matched.
    pub mapping: Mapping,
    /// Seed of the sample (combined with the frame index: runs are repeatable).
    pub seed: u64,
    /// Sample from `all` points of an unorganised scan, or from one point per pixel
    /// (`nearest`, as the images show them); also how the keypoint budget is counted.
    pub pixel_points: PixelPoints,
}

impl Default for RandomConfig {
    fn default() -> Self {
        Self {
            points: 0,
            windows: Windows::default(),
            mapping: Mapping::Exact,
            seed: 0,
            pixel_points: PixelPoints::All,
        }
    }
}

/// Keeps a uniform random subset of the frame's points (not at the origin), in scan order,
/// with their times.
pub struct RandomDownsampler {
    budget: Budget,
    seed: u64,
}

impl RandomDownsampler {
    /// Checks the config.
    pub fn new(config: RandomConfig) -> Result<Self, CoreError> {
        Ok(Self {
            budget: Budget::new(
                (config.points, config.pixel_points),
                &config.windows,
                config.mapping,
            )?,
            seed: config.seed,
        })
    }
}

impl Downsampler for RandomDownsampler {
    fn downsample(
        &mut self,
        frame: &LidarFrame,
        features: &FrameFeatures,
    ) -> Result<PointCloud, CoreError> {
        let n = self.budget.for_frame(frame, features)?;
        let all = self.budget.candidates(frame);
        let valid: Vec<usize> = (0..all.len())
            .filter(|&i| all.points[i].coords.norm_squared() > 0.0)
            .collect();
        let mut rng = ChaCha8Rng::seed_from_u64(self.seed ^ frame.index.rotate_left(32));
        let picked: Vec<usize> = if n >= valid.len() {
            valid
        } else {
            let mut p: Vec<usize> = rand::seq::index::sample(&mut rng, valid.len(), n)
                .into_iter()
                .map(|k| valid[k])
                .collect();
            p.sort_unstable();
            p
        };
        Ok(all.subset(&picked))
    }
}
