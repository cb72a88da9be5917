//! The metrics' parameters; defaults are the authors' (`../shared/paper/upstream-code-notes.md`).

use serde::{Deserialize, Serialize};

use crate::KpEvalError;

/// Which homography the scaling robustness maps keypoints with.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum ScalingHomography {
    /// The authors': scale `s` plus a translation of `(s−1)·cols/2, (s−1)·rows/2`, which is not
    /// what `resize` does (it depresses every detector's figure; the paper's numbers).
    Paper,
    /// What `resize` does to pixel centres: `x' = s·x + (s−1)/2`.
    Corrected,
    /// `diag(s, s, 1)`: the authors' SuperPoint script (no offset at all).
    Plain,
}

/// Whose definitions of the metrics a combination follows when evaluated "as the authors
/// compute it" (the `paper` preset).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Definitions {
    /// The authors' C++ program (`perfermance_comparison.cpp`): every OpenCV combination.
    Program,
    /// Their Python script for SuperPoint (`superpoint_evaluation.py`): the rotated canvas
    /// truncated to whole pixels, the scaling homography `diag(s, s, 1)`, matches kept below
    /// descriptor distance 0.7, and distinctiveness over the current image's descriptors
    /// (the kNN queries run from the current image into the previous one).
    SuperPointScript,
}

/// Descriptor distance below which the authors' SuperPoint script keeps a match.
pub const SUPERPOINT_MATCH_DISTANCE: f64 = 0.7;

/// `[metrics]` of a keypoint evaluation.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct MetricParams {
    /// A keypoint is repeated when the transformed image has a keypoint this close (pixels)
    /// to its mapped position.
    pub repeat_px: f64,
    /// Rotation of the rotation-robustness test, degrees (counter-clockwise, about the image
    /// centre, on a canvas enlarged to the rotated bounding box).
    pub rotation_deg: f64,
    /// Scale factor of the scaling-robustness test (`resize`, linear interpolation).
    pub scale: f64,
    /// Gaussian blur kernel of the blur-robustness test, pixels (odd).
    pub blur_kernel: usize,
    /// Gaussian blur sigma (0: from the kernel size, as OpenCV does).
    pub blur_sigma: f64,
    /// RANSAC reprojection threshold of the match score, pixels.
    pub ransac_px: f64,
    /// Lowe's ratio of the distinctiveness metric.
    pub ratio: f64,
    /// Cross-check the brute-force matches of the match ratio and match score.
    pub cross_check: bool,
    /// Drop matches with a descriptor distance above this (0: keep all). The authors' SuperPoint
    /// evaluation used 0.7 on its unit-length descriptors.
    pub max_match_distance: f64,
}

impl Default for MetricParams {
    fn default() -> Self {
        Self {
            repeat_px: 4.0,
            rotation_deg: 45.0,
            scale: 2.0,
            blur_kernel: 5,
            blur_sigma: 0.0,
            ransac_px: 3.0,
            ratio: 0.8,
            cross_check: true,
            max_match_distance: 0.0,
        }
    }
}

impl MetricParams {
    /// Checks every parameter; `origin` names the file (or `defaults`).
    pub fn validate(&self, origin: &str) -> Result<(), KpEvalError> {
        let bad = |key: &str, msg: String| Err(KpEvalError::setting(origin, key, msg));
        if !(self.repeat_px.is_finite() && self.repeat_px > 0.0) {
            return bad(
                "metrics.repeat_px",
                format!("{}: expected pixels > 0", self.repeat_px),
            );
        }
        if !self.rotation_deg.is_finite() {
            return bad(
                "metrics.rotation_deg",
                format!("{}: expected degrees", self.rotation_deg),
            );
        }
        if !(self.scale.is_finite() && self.scale > 0.0 && self.scale <= 8.0) {
            return bad(
                "metrics.scale",
                format!("{}: expected a factor in (0, 8]", self.scale),
            );
        }
        if self.blur_kernel.is_multiple_of(2) || self.blur_kernel > 99 {
            return bad(
                "metrics.blur_kernel",
                format!("{}: expected an odd size up to 99", self.blur_kernel),
            );
        }
        if !(self.blur_sigma.is_finite() && self.blur_sigma >= 0.0) {
            return bad(
                "metrics.blur_sigma",
                format!("{}: expected >= 0", self.blur_sigma),
            );
        }
        if !(self.ransac_px.is_finite() && self.ransac_px > 0.0) {
            return bad(
                "metrics.ransac_px",
                format!("{}: expected pixels > 0", self.ransac_px),
            );
        }
        if !(self.ratio.is_finite() && self.ratio > 0.0 && self.ratio <= 1.0) {
            return bad(
                "metrics.ratio",
                format!("{}: expected a ratio in (0, 1]", self.ratio),
            );
        }
        if !(self.max_match_distance.is_finite() && self.max_match_distance >= 0.0) {
            return bad(
                "metrics.max_match_distance",
                format!("{}: expected >= 0", self.max_match_distance),
            );
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_the_authors_and_bad_values_are_named() {
        let p = MetricParams::default();
        assert_eq!((p.repeat_px, p.rotation_deg, p.scale), (4.0, 45.0, 2.0));
        assert_eq!((p.blur_kernel, p.ransac_px, p.ratio), (5, 3.0, 0.8));
        p.validate("defaults").unwrap();
        let e = MetricParams {
            blur_kernel: 4,
            ..p.clone()
        }
        .validate("eval.toml")
        .unwrap_err()
        .to_string();
        assert!(
            e.contains("eval.toml") && e.contains("metrics.blur_kernel"),
            "{e}"
        );
        let e = MetricParams { ratio: 1.5, ..p }
            .validate("x")
            .unwrap_err()
            .to_string();
        assert!(e.contains("metrics.ratio"), "{e}");
    }
}
