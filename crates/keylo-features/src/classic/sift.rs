//! `sift`: OpenCV's SIFT detector and descriptor.

use opencv::core::Ptr;
use opencv::features2d::{Feature2D, SIFT};
use serde::{Deserialize, Serialize};

use super::feature::CvParams;
use crate::{check, FeaturesError};

/// `[detector]`/`[descriptor] kind = "sift"` (OpenCV's defaults).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct SiftParams {
    /// Best features kept, ranked by contrast (0: all).
    pub nfeatures: i32,
    /// Layers per octave of the difference-of-Gaussians pyramid.
    pub n_octave_layers: i32,
    /// Weak-feature filter on low-contrast regions (divided by `n_octave_layers`).
    pub contrast_threshold: f64,
    /// Edge-like feature filter (larger keeps more).
    pub edge_threshold: f64,
    /// Gaussian sigma of the input at octave 0.
    pub sigma: f64,
    /// As a detector: also compute descriptors in the same pass.
    pub describe: bool,
}

impl Default for SiftParams {
    fn default() -> Self {
        Self {
            nfeatures: 0,
            n_octave_layers: 3,
            contrast_threshold: 0.04,
            edge_threshold: 10.0,
            sigma: 1.6,
            describe: false,
        }
    }
}

impl CvParams for SiftParams {
    const KIND: &'static str = "sift";
    const DESCRIBES: bool = true;
    fn create(&self) -> Result<Ptr<Feature2D>, FeaturesError> {
        check(
            self.nfeatures >= 0,
            "nfeatures",
            self.nfeatures,
            "expected >= 0",
        )?;
        check(
            self.n_octave_layers >= 1,
            "n_octave_layers",
            self.n_octave_layers,
            "expected >= 1",
        )?;
        check(self.sigma > 0.0, "sigma", self.sigma, "expected > 0")?;
        let s = SIFT::create(
            self.nfeatures,
            self.n_octave_layers,
            self.contrast_threshold,
            self.edge_threshold,
            self.sigma,
        )
        .map_err(|e| FeaturesError::opencv("SIFT::create", e))?;
        Ok(s.into())
    }
    fn describe_in_detector(&self) -> bool {
        self.describe
    }
}
