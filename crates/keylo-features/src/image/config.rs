//! `[image] kind = "lidar"`: which images to make from a frame and how.

use std::collections::BTreeMap;

use keylo_core::Channel;
use serde::{Deserialize, Serialize};

use super::Normalise;
use crate::{check, FeaturesError};

/// OpenCV's resize interpolations (the five the paper compares).
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "kebab-case")]
pub enum Interpolation {
    /// `INTER_NEAREST`.
    Nearest,
    /// `INTER_LINEAR` (the paper's optimum).
    #[default]
    Linear,
    /// `INTER_CUBIC`.
    Cubic,
    /// `INTER_AREA`.
    Area,
    /// `INTER_LANCZOS4`.
    Lanczos4,
}

impl Interpolation {
    /// The OpenCV flag.
    pub fn cv_flag(self) -> i32 {
        use opencv::imgproc;
        match self {
            Interpolation::Nearest => imgproc::INTER_NEAREST,
            Interpolation::Linear => imgproc::INTER_LINEAR,
            Interpolation::Cubic => imgproc::INTER_CUBIC,
            Interpolation::Area => imgproc::INTER_AREA,
            Interpolation::Lanczos4 => imgproc::INTER_LANCZOS4,
        }
    }
}

/// `[image] kind = "lidar"`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct LidarImageConfig {
    /// The images to make, in order. Each is a channel (`signal`, `range`, `reflectivity`,
    /// `near-ir`), or two joined by `+` (`signal+range`) for one two-plane image (the
    /// shipped two-channel SuperPoint). The name also selects `[detector.by_image.<name>]`
    /// and the downsampler's window for the image.
    pub images: Vec<String>,
    /// Width the images are resized to, pixels (0: the frame's column count).
    pub width: usize,
    /// Height the images are resized to, pixels (0: the frame's row count).
    pub height: usize,
    /// Resize interpolation: `nearest`, `linear`, `cubic`, `area`, `lanczos4`.
    pub interpolation: Interpolation,
    /// How every channel becomes 8-bit, unless `normalise_by_channel` says otherwise.
    pub normalise: Normalise,
    /// Per-channel normalisation (keys: channel names), replacing `normalise` for it.
    pub normalise_by_channel: BTreeMap<String, Normalise>,
}

impl Default for LidarImageConfig {
    fn default() -> Self {
        Self {
            images: vec!["signal".into()],
            width: 1024,
            height: 64,
            interpolation: Interpolation::Linear,
            normalise: Normalise::default(),
            normalise_by_channel: BTreeMap::new(),
        }
    }
}

impl LidarImageConfig {
    /// The channels of every image, checked.
    pub fn image_planes(&self) -> Result<Vec<Vec<Channel>>, FeaturesError> {
        check(
            !self.images.is_empty(),
            "images",
            &self.images,
            "expected at least one image, e.g. [\"signal\"]",
        )?;
        let mut out = Vec::with_capacity(self.images.len());
        for spec in &self.images {
            let planes = spec
                .split('+')
                .map(|name| {
                    name.trim()
                        .parse::<Channel>()
                        .map_err(|message| FeaturesError::bad_parameter("images", spec, message))
                })
                .collect::<Result<Vec<_>, _>>()?;
            check(
                planes.len() <= 2,
                "images",
                spec,
                "expected one channel or two joined by `+`",
            )?;
            out.push(planes);
        }
        Ok(out)
    }

    /// The normalisation of `channel`.
    pub fn normalise_for(&self, channel: Channel) -> &Normalise {
        self.normalise_by_channel
            .get(channel.name())
            .unwrap_or(&self.normalise)
    }

    /// Checks every parameter.
    pub fn validate(&self) -> Result<(), FeaturesError> {
        self.image_planes()?;
        self.normalise.validate("normalise")?;
        for (name, n) in &self.normalise_by_channel {
            name.parse::<Channel>()
                .map_err(|m| FeaturesError::bad_parameter("normalise_by_channel", name, m))?;
            n.validate(&format!("normalise_by_channel.{name}"))?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_image_specs() {
        let c = LidarImageConfig {
            images: vec!["signal".into(), "signal+range".into()],
            ..LidarImageConfig::default()
        };
        assert_eq!(
            c.image_planes().unwrap(),
            vec![vec![Channel::Signal], vec![Channel::Signal, Channel::Range]]
        );
    }

    #[test]
    fn rejects_unknown_channels_and_triples() {
        for bad in ["intensity", "signal+range+near-ir", ""] {
            let c = LidarImageConfig {
                images: vec![bad.into()],
                ..LidarImageConfig::default()
            };
            let e = c.validate().unwrap_err().to_string();
            assert!(e.contains("images"), "{e}");
        }
    }
}
