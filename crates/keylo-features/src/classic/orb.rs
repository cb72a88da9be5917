//! `orb`: OpenCV's ORB detector and descriptor.

use opencv::core::Ptr;
use opencv::features2d::{Feature2D, ORB_ScoreType, ORB};
use serde::{Deserialize, Serialize};

use super::feature::CvParams;
use crate::{check, FeaturesError};

/// How ORB ranks keypoints.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "kebab-case")]
pub enum OrbScore {
    /// Harris corner measure (OpenCV's default).
    #[default]
    Harris,
    /// FAST score (faster, slightly less stable).
    Fast,
}

/// `[detector]`/`[descriptor] kind = "orb"` (OpenCV's defaults).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct OrbParams {
    /// Most features kept.
    pub nfeatures: i32,
    /// Pyramid decimation ratio (> 1).
    pub scale_factor: f32,
    /// Pyramid levels.
    pub nlevels: i32,
    /// Border where features are not detected, pixels (about `patch_size`).
    pub edge_threshold: i32,
    /// Pyramid level the source image is placed on.
    pub first_level: i32,
    /// Points compared per descriptor element: 2, 3 or 4.
    pub wta_k: i32,
    /// `harris` or `fast`.
    pub score_type: OrbScore,
    /// Patch size of the oriented BRIEF descriptor, pixels.
    pub patch_size: i32,
    /// FAST threshold of the detector.
    pub fast_threshold: i32,
    /// As a detector: also compute descriptors in the same pass.
    pub describe: bool,
}

impl Default for OrbParams {
    fn default() -> Self {
        Self {
            nfeatures: 500,
            scale_factor: 1.2,
            nlevels: 8,
            edge_threshold: 31,
            first_level: 0,
            wta_k: 2,
            score_type: OrbScore::Harris,
            patch_size: 31,
            fast_threshold: 20,
            describe: false,
        }
    }
}

impl CvParams for OrbParams {
    const KIND: &'static str = "orb";
    const DESCRIBES: bool = true;
    fn max_octave(&self) -> Option<i32> {
        Some(self.nlevels - 1)
    }
    fn create(&self) -> Result<Ptr<Feature2D>, FeaturesError> {
        check(
            self.nfeatures >= 1,
            "nfeatures",
            self.nfeatures,
            "expected >= 1",
        )?;
        check(
            self.scale_factor > 1.0,
            "scale_factor",
            self.scale_factor,
            "expected > 1",
        )?;
        check(self.nlevels >= 1, "nlevels", self.nlevels, "expected >= 1")?;
        check(
            (2..=4).contains(&self.wta_k),
            "wta_k",
            self.wta_k,
            "expected 2, 3 or 4",
        )?;
        check(
            self.patch_size >= 2,
            "patch_size",
            self.patch_size,
            "expected >= 2",
        )?;
        check(
            self.first_level >= 0 && self.first_level < self.nlevels,
            "first_level",
            self.first_level,
            "expected 0 <= first_level < nlevels",
        )?;
        let score = match self.score_type {
            OrbScore::Harris => ORB_ScoreType::HARRIS_SCORE,
            OrbScore::Fast => ORB_ScoreType::FAST_SCORE,
        };
        let o = ORB::create(
            self.nfeatures,
            self.scale_factor,
            self.nlevels,
            self.edge_threshold,
            self.first_level,
            self.wta_k,
            score,
            self.patch_size,
            self.fast_threshold,
        )
        .map_err(|e| FeaturesError::opencv("ORB::create", e))?;
        Ok(o.into())
    }
    fn describe_in_detector(&self) -> bool {
        self.describe
    }
}
