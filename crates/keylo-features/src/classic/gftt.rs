//! `shi-tomasi` and `harris`: OpenCV's `GFTTDetector` (good features to track).

use opencv::core::Ptr;
use opencv::features2d::{Feature2D, GFTTDetector};
use serde::{Deserialize, Serialize};

use super::feature::CvParams;
use crate::{check, FeaturesError};

/// `[detector] kind = "shi-tomasi"` or `"harris"` (OpenCV `GFTTDetector`; defaults are
/// OpenCV's — the paper used block_size 4, min_distance 4, max_corners rows·cols/4).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct GfttParams {
    /// Most corners returned (the strongest); 0: no limit.
    pub max_corners: i32,
    /// Corners weaker than this fraction of the strongest corner's score are dropped.
    pub quality_level: f64,
    /// Smallest distance between returned corners, pixels.
    pub min_distance: f64,
    /// Neighbourhood over which the derivative covariation is summed, pixels.
    pub block_size: i32,
    /// Sobel aperture for the derivatives (odd, 1–7).
    pub gradient_size: i32,
    /// Harris free parameter k (used by `harris` only).
    pub k: f64,
}

impl Default for GfttParams {
    fn default() -> Self {
        Self {
            max_corners: 1000,
            quality_level: 0.01,
            min_distance: 1.0,
            block_size: 3,
            gradient_size: 3,
            k: 0.04,
        }
    }
}

impl GfttParams {
    fn make(&self, harris: bool) -> Result<Ptr<Feature2D>, FeaturesError> {
        check(
            self.max_corners >= 0,
            "max_corners",
            self.max_corners,
            "expected >= 0",
        )?;
        check(
            self.quality_level > 0.0 && self.quality_level < 1.0,
            "quality_level",
            self.quality_level,
            "expected a value in (0, 1)",
        )?;
        check(
            self.min_distance >= 0.0,
            "min_distance",
            self.min_distance,
            "expected >= 0",
        )?;
        check(
            self.block_size >= 1,
            "block_size",
            self.block_size,
            "expected >= 1",
        )?;
        check(
            [1, 3, 5, 7].contains(&self.gradient_size),
            "gradient_size",
            self.gradient_size,
            "expected 1, 3, 5 or 7",
        )?;
        let detector = GFTTDetector::create_with_gradient(
            self.max_corners,
            self.quality_level,
            self.min_distance,
            self.block_size,
            self.gradient_size,
            harris,
            self.k,
        )
        .map_err(|e| FeaturesError::opencv("GFTTDetector::create", e))?;
        Ok(detector.into())
    }
}

/// Shi–Tomasi corners (`GFTTDetector`, minimum eigenvalue score).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(transparent)]
pub struct ShiTomasiParams(pub GfttParams);

/// Harris corners (`GFTTDetector` with `useHarrisDetector`).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(transparent)]
pub struct HarrisParams(pub GfttParams);

impl CvParams for ShiTomasiParams {
    const KIND: &'static str = "shi-tomasi";
    const DESCRIBES: bool = false;
    fn create(&self) -> Result<Ptr<Feature2D>, FeaturesError> {
        self.0.make(false)
    }
}

impl CvParams for HarrisParams {
    const KIND: &'static str = "harris";
    const DESCRIBES: bool = false;
    fn create(&self) -> Result<Ptr<Feature2D>, FeaturesError> {
        self.0.make(true)
    }
}
