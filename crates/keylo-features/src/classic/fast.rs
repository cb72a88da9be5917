//! `fast`: OpenCV's `FastFeatureDetector`.

use opencv::core::Ptr;
use opencv::features2d::{FastFeatureDetector, FastFeatureDetector_DetectorType, Feature2D};
use serde::{Deserialize, Serialize};

use super::feature::CvParams;
use crate::{check, FeaturesError};

/// The FAST circle: pixels tested / contiguous pixels needed.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, schemars::JsonSchema,
)]
pub enum FastType {
    /// 8-pixel circle, 5 contiguous.
    #[serde(rename = "5_8")]
    Type5_8,
    /// 12-pixel circle, 7 contiguous.
    #[serde(rename = "7_12")]
    Type7_12,
    /// 16-pixel circle, 9 contiguous (OpenCV's default).
    #[default]
    #[serde(rename = "9_16")]
    Type9_16,
}

/// `[detector] kind = "fast"` (defaults are OpenCV's; the paper used threshold 30).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct FastParams {
    /// Intensity difference between the centre and the circle pixels.
    pub threshold: i32,
    /// Non-maximum suppression of adjacent corners.
    pub nonmax_suppression: bool,
    /// Circle: `5_8`, `7_12` or `9_16`.
    pub detector_type: FastType,
}

impl Default for FastParams {
    fn default() -> Self {
        Self {
            threshold: 10,
            nonmax_suppression: true,
            detector_type: FastType::Type9_16,
        }
    }
}

impl CvParams for FastParams {
    const KIND: &'static str = "fast";
    const DESCRIBES: bool = false;
    fn create(&self) -> Result<Ptr<Feature2D>, FeaturesError> {
        check(
            (0..=255).contains(&self.threshold),
            "threshold",
            self.threshold,
            "expected 0..=255",
        )?;
        let t = match self.detector_type {
            FastType::Type5_8 => FastFeatureDetector_DetectorType::TYPE_5_8,
            FastType::Type7_12 => FastFeatureDetector_DetectorType::TYPE_7_12,
            FastType::Type9_16 => FastFeatureDetector_DetectorType::TYPE_9_16,
        };
        let d = FastFeatureDetector::create(self.threshold, self.nonmax_suppression, t)
            .map_err(|e| FeaturesError::opencv("FastFeatureDetector::create", e))?;
        Ok(d.into())
    }
}
