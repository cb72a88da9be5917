//! `brisk`: OpenCV's BRISK detector and descriptor.

use opencv::core::Ptr;
use opencv::features2d::{Feature2D, BRISK};
use serde::{Deserialize, Serialize};

use super::feature::CvParams;
use crate::{check, FeaturesError};

/// `[detector]`/`[descriptor] kind = "brisk"` (OpenCV's defaults; the paper's BRISK
/// descriptor used threshold 30, 3 octaves, pattern scale 1).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct BriskParams {
    /// AGAST detection threshold score.
    pub thresh: i32,
    /// Detection octaves (0: single scale).
    pub octaves: i32,
    /// Scale applied to the sampling pattern around a keypoint.
    pub pattern_scale: f32,
    /// As a detector: also compute descriptors in the same pass (kept when no
    /// `[descriptor]` is configured).
    pub describe: bool,
}

impl Default for BriskParams {
    fn default() -> Self {
        Self {
            thresh: 30,
            octaves: 3,
            pattern_scale: 1.0,
            describe: false,
        }
    }
}

impl CvParams for BriskParams {
    const KIND: &'static str = "brisk";
    const DESCRIBES: bool = true;
    fn create(&self) -> Result<Ptr<Feature2D>, FeaturesError> {
        check(self.thresh >= 0, "thresh", self.thresh, "expected >= 0")?;
        check(
            (0..=8).contains(&self.octaves),
            "octaves",
            self.octaves,
            "expected 0..=8",
        )?;
        check(
            self.pattern_scale.is_finite() && self.pattern_scale > 0.0,
            "pattern_scale",
            self.pattern_scale,
            "expected > 0",
        )?;
        let b = BRISK::create(self.thresh, self.octaves, self.pattern_scale)
            .map_err(|e| FeaturesError::opencv("BRISK::create", e))?;
        Ok(b.into())
    }
    fn describe_in_detector(&self) -> bool {
        self.describe
    }
}
