//! `[downsampler] kind = "keypoint-neighbourhood"`: window sizes per image and mapping rules.

use std::collections::BTreeMap;

use keylo_core::PixelPoints;
use serde::{Deserialize, Serialize};

use crate::FeaturesError;

/// Window sizes: the paper's `"<K_signal>_<K_range>"` notation, or one size per image name.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(untagged)]
pub enum Windows {
    /// `"4_7"`: K_sig = 4 for the `signal` image, K_rng = 7 for the `range` image (the
    /// paper's outdoor preset; `"5_5"` is its indoor one).
    Preset(String),
    /// `{ signal = 4, range = 7, "signal+range" = 5 }`: K per image name.
    PerImage(BTreeMap<String, usize>),
}

impl Default for Windows {
    fn default() -> Self {
        Windows::Preset("4_7".into())
    }
}

impl Windows {
    /// The sizes per image name, checked (every K ≥ 1).
    pub fn sizes(&self) -> Result<BTreeMap<String, usize>, FeaturesError> {
        let sizes = match self {
            Windows::Preset(text) => {
                let parsed = text
                    .split_once('_')
                    .and_then(|(s, r)| Some((s.trim().parse().ok()?, r.trim().parse().ok()?)));
                let Some((sig, rng)) = parsed else {
                    return Err(FeaturesError::bad_parameter(
                        "windows",
                        text,
                        "expected \"<K_signal>_<K_range>\" such as \"4_7\" or \"5_5\", \
                         or a table { signal = 4, range = 7 }",
                    ));
                };
                BTreeMap::from([("signal".to_string(), sig), ("range".to_string(), rng)])
            }
            Windows::PerImage(map) => map.clone(),
        };
        if let Some((name, k)) = sizes.iter().find(|(_, k)| **k == 0 || **k > 64) {
            return Err(FeaturesError::bad_parameter(
                format!("windows.{name}"),
                k,
                "expected a window size of 1 to 64 pixels",
            ));
        }
        Ok(sizes)
    }
}

/// How window pixels of the resized image become points of the frame.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "kebab-case")]
pub enum Mapping {
    /// Every frame pixel the window covers through the resize (the paper's method as
    /// described): a K×K window of a halved image selects 2K×2K points.
    #[default]
    Exact,
    /// One frame pixel per window pixel, the first it covers (`(2x, 2y)` for a halved
    /// image) — what the paper's published code does; a sparse stride-2 pattern.
    UpstreamStride,
}

/// What happens when a frame yields fewer than `min_points` points.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "kebab-case")]
pub enum TooFew {
    /// The frame fails with a "too few points" error (`[output] on_bad_frame` decides
    /// whether the run goes on).
    #[default]
    Error,
    /// The frame's whole valid cloud is registered instead.
    AllPoints,
}

/// Which keypoints select points.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "kebab-case")]
pub enum KeypointUse {
    /// Every keypoint.
    #[default]
    All,
    /// Only keypoints whose descriptor matches one of the previous frame's (same image; brute
    /// force, best `matched_fraction` by distance; all keypoints on the first frame) — the
    /// paper's published AKAZE path, which with `windows = "1_1"` also drops the window.
    /// Needs descriptors (`describe = true` on the detector, or a `[descriptor]`).
    Matched,
}

/// `[downsampler] kind = "keypoint-neighbourhood"`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct NeighbourhoodConfig {
    /// Window size per image: `"4_7"` (signal 4, range 7; outdoor), `"5_5"` (indoor), or a
    /// table `{ signal = 4, range = 7 }` keyed by image name.
    pub windows: Windows,
    /// `exact` (every point the window covers) or `upstream-stride` (the published code's
    /// one point per window pixel).
    pub mapping: Mapping,
    /// `all` keypoints, or only those `matched` to the previous frame.
    pub keypoints: KeypointUse,
    /// With `keypoints = "matched"`: the fraction of matches kept, best first (the
    /// published code: 0.9).
    pub matched_fraction: f64,
    /// Fewest points a frame may give.
    pub min_points: usize,
    /// Below `min_points`: `error`, or register `all-points` of the frame.
    pub on_too_few: TooFew,
    /// Unorganised scans (KITTI, PLY/PCD, unorganised PointCloud2) can put several points
    /// into one pixel: `all` keeps every point of a selected pixel, `nearest` only the one
    /// the images show (one point per pixel, as the paper's organised Ouster cloud gives).
    /// Organised frames have one point per pixel: both are the same.
    pub pixel_points: PixelPoints,
}

impl Default for NeighbourhoodConfig {
    fn default() -> Self {
        Self {
            windows: Windows::default(),
            mapping: Mapping::Exact,
            keypoints: KeypointUse::All,
            matched_fraction: 0.9,
            min_points: 100,
            on_too_few: TooFew::Error,
            pixel_points: PixelPoints::All,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn presets_parse() {
        let s = Windows::Preset("5_5".into()).sizes().unwrap();
        assert_eq!((s["signal"], s["range"]), (5, 5));
        let s = Windows::default().sizes().unwrap();
        assert_eq!((s["signal"], s["range"]), (4, 7));
    }

    #[test]
    fn bad_windows_are_named() {
        for w in [
            Windows::Preset("4x7".into()),
            Windows::Preset("0_3".into()),
            Windows::PerImage(BTreeMap::from([("range".into(), 100)])),
        ] {
            let e = w.sizes().unwrap_err().to_string();
            assert!(e.contains("windows"), "{e}");
        }
    }
}
