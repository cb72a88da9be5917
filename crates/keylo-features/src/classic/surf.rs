//! `surf`: needs OpenCV's non-free xfeatures2d module, which Debian's OpenCV lacks.

use serde::{Deserialize, Serialize};

use crate::FeaturesError;

/// `[detector]`/`[descriptor] kind = "surf"` (OpenCV's defaults). Accepted by the config
/// so that it can say why SURF is unavailable in this build.
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
}

impl Default for SurfParams {
    fn default() -> Self {
        Self {
            hessian_threshold: 100.0,
            n_octaves: 4,
            n_octave_layers: 3,
            extended: false,
            upright: false,
        }
    }
}

/// The error every SURF construction returns in this build.
pub fn unavailable() -> FeaturesError {
    let version = opencv::core::get_version_string().unwrap_or_else(|_| "unknown".into());
    FeaturesError::Unavailable(format!(
        "SURF is not available: it lives in OpenCV's non-free `xfeatures2d` contrib module, \
         which this keylo is not built with (OpenCV {version}; Debian's libopencv-dev has no \
         xfeatures2d). To use SURF, build OpenCV with opencv_contrib \
         (-DOPENCV_EXTRA_MODULES_PATH=<opencv_contrib>/modules -DOPENCV_ENABLE_NONFREE=ON) \
         and add a SURF binding to keylo-features; or choose another detector \
         (sift, akaze, orb, brisk, fast, shi-tomasi, harris, superpoint)"
    ))
}
