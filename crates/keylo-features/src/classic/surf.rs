//! `surf`'s settings. The detector and descriptor are keylo's own
//! (`native::surf`, cargo feature `nonfree`); without the feature the kind says how to get it.

use serde::{Deserialize, Serialize};

#[cfg(not(feature = "nonfree"))]
use crate::FeaturesError;

/// `[detector]`/`[descriptor] kind = "surf"` (OpenCV's defaults). Without the cargo feature
/// `nonfree` it is accepted by the config so that it can say why SURF is unavailable.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct SurfParams {
    /// Hessian threshold for the keypoint detector.
    pub hessian_threshold: f64,
    /// Pyramid octaves.
    pub n_octaves: i32,
    /// Layers per octave.
    pub n_octave_layers: i32,
    /// 128-element descriptor instead of 64.
    pub extended: bool,
    /// No orientation.
    pub upright: bool,
    /// As a detector: also compute descriptors in the same pass.
    pub describe: bool,
}

impl Default for SurfParams {
    fn default() -> Self {
        Self {
            hessian_threshold: 100.0,
            n_octaves: 4,
            n_octave_layers: 3,
            extended: false,
            upright: false,
            describe: false,
        }
    }
}

/// The error every SURF construction returns in a build without the feature `nonfree`.
#[cfg(not(feature = "nonfree"))]
pub fn unavailable() -> FeaturesError {
    FeaturesError::Unavailable(
        "SURF is not in this build: it is behind the cargo feature `nonfree` (SURF was \
         patented; OpenCV too ships it only in its non-free build). Build keylo with \
         `cargo build --release --features nonfree` (docs/keypoints.md, \"SURF\"), or choose \
         another detector (sift, akaze, orb, brisk, fast, shi-tomasi, harris, superpoint)"
            .into(),
    )
}
