//! `akaze` and `kaze`: OpenCV's nonlinear-scale-space detectors and descriptors.

use opencv::core::Ptr;
use opencv::features2d::{AKAZE_DescriptorType, Feature2D, KAZE_DiffusivityType, AKAZE, KAZE};
use serde::{Deserialize, Serialize};

use super::feature::CvParams;
use crate::{check, FeaturesError};

/// The conductance function of the nonlinear diffusion.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "kebab-case")]
pub enum Diffusivity {
    /// Perona–Malik g1.
    PmG1,
    /// Perona–Malik g2 (OpenCV's default).
    #[default]
    PmG2,
    /// Weickert.
    Weickert,
    /// Charbonnier.
    Charbonnier,
}

impl Diffusivity {
    fn cv(self) -> KAZE_DiffusivityType {
        match self {
            Diffusivity::PmG1 => KAZE_DiffusivityType::DIFF_PM_G1,
            Diffusivity::PmG2 => KAZE_DiffusivityType::DIFF_PM_G2,
            Diffusivity::Weickert => KAZE_DiffusivityType::DIFF_WEICKERT,
            Diffusivity::Charbonnier => KAZE_DiffusivityType::DIFF_CHARBONNIER,
        }
    }
}

/// AKAZE's descriptor.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "kebab-case")]
pub enum AkazeDescriptor {
    /// KAZE's float descriptor, no orientation.
    KazeUpright,
    /// KAZE's float descriptor.
    Kaze,
    /// Binary modified-local-difference descriptor, no orientation.
    MldbUpright,
    /// Binary modified-local-difference descriptor (OpenCV's default).
    #[default]
    Mldb,
}

/// `[detector]`/`[descriptor] kind = "akaze"` (OpenCV's defaults, as the paper used).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct AkazeParams {
    /// `kaze-upright`, `kaze`, `mldb-upright` or `mldb`.
    pub descriptor_type: AkazeDescriptor,
    /// MLDB descriptor size in bits (0: full size).
    pub descriptor_size: i32,
    /// MLDB channels: 1, 2 or 3.
    pub descriptor_channels: i32,
    /// Detector response threshold to accept a point.
    pub threshold: f32,
    /// Maximum octave evolution of the image.
    pub n_octaves: i32,
    /// Sublevels per scale level.
    pub n_octave_layers: i32,
    /// `pm-g1`, `pm-g2`, `weickert` or `charbonnier`.
    pub diffusivity: Diffusivity,
    /// As a detector: also compute descriptors in the same pass.
    pub describe: bool,
}

impl Default for AkazeParams {
    fn default() -> Self {
        Self {
            descriptor_type: AkazeDescriptor::Mldb,
            descriptor_size: 0,
            descriptor_channels: 3,
            threshold: 0.001,
            n_octaves: 4,
            n_octave_layers: 4,
            diffusivity: Diffusivity::PmG2,
            describe: false,
        }
    }
}

fn check_scales(threshold: f32, octaves: i32, layers: i32) -> Result<(), FeaturesError> {
    check(threshold > 0.0, "threshold", threshold, "expected > 0")?;
    check(octaves >= 1, "n_octaves", octaves, "expected >= 1")?;
    check(layers >= 1, "n_octave_layers", layers, "expected >= 1")
}

impl CvParams for AkazeParams {
    const KIND: &'static str = "akaze";
    const DESCRIBES: bool = true;
    fn create(&self) -> Result<Ptr<Feature2D>, FeaturesError> {
        check_scales(self.threshold, self.n_octaves, self.n_octave_layers)?;
        check(
            (1..=3).contains(&self.descriptor_channels),
            "descriptor_channels",
            self.descriptor_channels,
            "expected 1, 2 or 3",
        )?;
        check(
            self.descriptor_size >= 0,
            "descriptor_size",
            self.descriptor_size,
            "expected >= 0",
        )?;
        let d = match self.descriptor_type {
            AkazeDescriptor::KazeUpright => AKAZE_DescriptorType::DESCRIPTOR_KAZE_UPRIGHT,
            AkazeDescriptor::Kaze => AKAZE_DescriptorType::DESCRIPTOR_KAZE,
            AkazeDescriptor::MldbUpright => AKAZE_DescriptorType::DESCRIPTOR_MLDB_UPRIGHT,
            AkazeDescriptor::Mldb => AKAZE_DescriptorType::DESCRIPTOR_MLDB,
        };
        let a = AKAZE::create(
            d,
            self.descriptor_size,
            self.descriptor_channels,
            self.threshold,
            self.n_octaves,
            self.n_octave_layers,
            self.diffusivity.cv(),
        )
        .map_err(|e| FeaturesError::opencv("AKAZE::create", e))?;
        Ok(a.into())
    }
    fn describe_in_detector(&self) -> bool {
        self.describe
    }
}

/// `[detector]`/`[descriptor] kind = "kaze"` (OpenCV's defaults).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct KazeParams {
    /// 128-element descriptor instead of 64.
    pub extended: bool,
    /// No orientation (faster, not rotation invariant).
    pub upright: bool,
    /// Detector response threshold to accept a point.
    pub threshold: f32,
    /// Maximum octave evolution of the image.
    pub n_octaves: i32,
    /// Sublevels per scale level.
    pub n_octave_layers: i32,
    /// `pm-g1`, `pm-g2`, `weickert` or `charbonnier`.
    pub diffusivity: Diffusivity,
    /// As a detector: also compute descriptors in the same pass.
    pub describe: bool,
}

impl Default for KazeParams {
    fn default() -> Self {
        Self {
            extended: false,
            upright: false,
            threshold: 0.001,
            n_octaves: 4,
            n_octave_layers: 4,
            diffusivity: Diffusivity::PmG2,
            describe: false,
        }
    }
}

impl CvParams for KazeParams {
    const KIND: &'static str = "kaze";
    const DESCRIBES: bool = true;
    fn create(&self) -> Result<Ptr<Feature2D>, FeaturesError> {
        check_scales(self.threshold, self.n_octaves, self.n_octave_layers)?;
        let k = KAZE::create(
            self.extended,
            self.upright,
            self.threshold,
            self.n_octaves,
            self.n_octave_layers,
            self.diffusivity.cv(),
        )
        .map_err(|e| FeaturesError::opencv("KAZE::create", e))?;
        Ok(k.into())
    }
    fn describe_in_detector(&self) -> bool {
        self.describe
    }
}
