//! `random`: a uniform sample of the frame's valid points.

use keylo_core::{CoreError, Downsampler, FrameFeatures, LidarFrame, PointCloud};
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
}

impl Default for RandomConfig {
    fn default() -> Self {
        Self {
            points: 0,
            windows: Windows::default(),
            mapping: Mapping::Exact,
            seed: 0,
        }
    }
}

/// Keeps a uniform random subset of the valid points, in scan order, with their times.
pub struct RandomDownsampler {
    budget: Budget,
    seed: u64,
}

impl RandomDownsampler {
    /// Checks the config.
    pub fn new(config: RandomConfig) -> Result<Self, CoreError> {
        Ok(Self {
            budget: Budget::new(config.points, &config.windows, config.mapping)?,
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
        let valid: Vec<usize> = (0..frame.rows * frame.cols)
            .filter(|&i| frame.valid[i] && frame.range[i] > 0.0)
            .collect();
        if n >= valid.len() {
            return Ok(frame.cloud_of_pixels(valid.into_iter()));
        }
        let mut rng = ChaCha8Rng::seed_from_u64(self.seed ^ frame.index.rotate_left(32));
        let mut picked: Vec<usize> = rand::seq::index::sample(&mut rng, valid.len(), n)
            .into_iter()
            .map(|k| valid[k])
            .collect();
        picked.sort_unstable();
        Ok(frame.cloud_of_pixels(picked.into_iter()))
    }
}
