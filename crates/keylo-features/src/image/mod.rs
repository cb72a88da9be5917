//! The `lidar` image builder: frame channels → 8-bit images (normalise, then resize), with
//! `scale_x/scale_y` set so keypoints map back to the frame grid.

mod config;
mod normalise;
mod ouster_ros;
mod resize;

pub use config::{Interpolation, LidarImageConfig};
pub use normalise::{Normalise, NormaliseMethod};
pub use resize::{interleave, resize_plane};

use keylo_core::config::StageParams;
use keylo_core::{Channel, CoreError, Image, ImageBuilder, LidarFrame};

/// Makes the configured images of every frame.
pub struct LidarImageBuilder {
    config: LidarImageConfig,
    planes: Vec<Vec<Channel>>,
}

impl LidarImageBuilder {
    /// Checks the config.
    pub fn new(config: LidarImageConfig) -> Result<Self, CoreError> {
        config.validate().map_err(|e| e.in_stage("image"))?;
        let planes = config.image_planes().map_err(|e| e.in_stage("image"))?;
        Ok(Self { config, planes })
    }

    /// The 8-bit, resized plane of one channel.
    fn plane(&self, frame: &LidarFrame, channel: Channel) -> Result<Vec<u8>, CoreError> {
        let (width, height) = self.size(frame);
        let full = self
            .config
            .normalise_for(channel)
            .to_u8(frame.channel(channel), &frame.valid);
        resize_plane(
            &full,
            frame.rows,
            frame.cols,
            width,
            height,
            self.config.interpolation,
        )
        .map_err(|e| e.in_stage("image"))
    }

    /// Output size for `frame` (0 in the config: the frame's own).
    fn size(&self, frame: &LidarFrame) -> (usize, usize) {
        let pick = |v: usize, own: usize| if v == 0 { own } else { v };
        (
            pick(self.config.width, frame.cols),
            pick(self.config.height, frame.rows),
        )
    }
}

impl ImageBuilder for LidarImageBuilder {
    fn image_names(&self) -> Vec<String> {
        self.planes
            .iter()
            .map(|p| p.iter().map(|c| c.name()).collect::<Vec<_>>().join("+"))
            .collect()
    }

    fn build(&mut self, frame: &LidarFrame) -> Result<Vec<Image>, CoreError> {
        let (width, height) = self.size(frame);
        let mut images = Vec::with_capacity(self.planes.len());
        for sources in &self.planes {
            let planes = sources
                .iter()
                .map(|&c| self.plane(frame, c))
                .collect::<Result<Vec<_>, _>>()?;
            let mut image = interleave(planes, sources.clone(), width, height);
            image.scale_x = frame.cols as f64 / width as f64;
            image.scale_y = frame.rows as f64 / height as f64;
            images.push(image);
        }
        Ok(images)
    }
}

keylo_core::stage_params!(LidarImageConfig => "lidar" as ImageParams);

/// Registers image builder `lidar`.
pub fn register(registry: &mut keylo_core::Registry) {
    registry.images.add::<LidarImageConfig>(
        LidarImageConfig::KIND,
        "8-bit images of frame channels: normalise (fixed, percentile, equalise, ouster-ros), then resize",
        |config, _ctx| Ok(Box::new(LidarImageBuilder::new(config)?)),
    );
}
