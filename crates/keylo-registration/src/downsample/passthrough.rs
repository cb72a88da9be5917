use keylo_core::{CoreError, Downsampler, FrameFeatures, LidarFrame, PointCloud};
use serde::{Deserialize, Serialize};

/// `[downsampler] kind = "passthrough"`: no parameters.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct PassthroughConfig {}

/// Passes every valid, finite point of the frame with its time and signal.
pub struct Passthrough;

impl Passthrough {
    /// The pass-through downsampler.
    pub fn new(_config: PassthroughConfig) -> Self {
        Self
    }
}

impl Downsampler for Passthrough {
    fn downsample(
        &mut self,
        frame: &LidarFrame,
        _f: &FrameFeatures,
    ) -> Result<PointCloud, CoreError> {
        Ok(frame.to_cloud())
    }
}
