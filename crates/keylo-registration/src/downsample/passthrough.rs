use keylo_core::{CoreError, Downsampler, FrameFeatures, LidarFrame, PixelPoints, PointCloud};
use serde::{Deserialize, Serialize};

/// `[downsampler] kind = "passthrough"`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct PassthroughConfig {
    /// `all`: every finite point of the frame (of an unorganised scan: every point of the
    /// file, in file order); `nearest`: one point per image pixel, the one the images show.
    /// Organised frames have one point per pixel: both are the same.
    pub pixel_points: PixelPoints,
}

/// Passes every point of the frame with its time and intensity.
pub struct Passthrough {
    mode: PixelPoints,
}

impl Passthrough {
    /// The pass-through downsampler.
    pub fn new(config: PassthroughConfig) -> Self {
        Self {
            mode: config.pixel_points,
        }
    }
}

impl Downsampler for Passthrough {
    fn downsample(
        &mut self,
        frame: &LidarFrame,
        _f: &FrameFeatures,
    ) -> Result<PointCloud, CoreError> {
        Ok(frame.cloud(self.mode))
    }

    fn needs_grid(&self) -> bool {
        self.mode == PixelPoints::Nearest
    }
}
