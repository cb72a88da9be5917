//! `keylo info --image N --config C`: one frame pictured through a config's stages.

use std::path::Path;

use anyhow::{Context, Result};
use keylo::{LidarFrame, Odometry};

use super::FrameOverlay;
use crate::arg_groups::DataArgs;

/// The per-frame stages of a config, for picturing one frame.
pub struct Single {
    odometry: Odometry,
}

impl Single {
    /// Builds the stages of `config` (with the data's `--set`s), before any frame is read, so
    /// that a bad config is reported first.
    pub fn build(config: &Path, data: &DataArgs, trust: keylo::config::Trust) -> Result<Self> {
        let mut registry = keylo::registry();
        let resolved = crate::configs::load(
            &mut registry,
            Some(config),
            Some(&data.data),
            data.meta.as_deref(),
            &data.sets,
            trust,
        )?;
        let odometry = Odometry::build(&resolved, &registry)
            .with_context(|| format!("config {}", config.display()))?;
        Ok(Self { odometry })
    }

    /// Runs the stages on `frame` and writes its pictures and clouds into `out`; returns the
    /// paths written.
    pub fn write(&mut self, out: &Path, frame: &LidarFrame) -> Result<Vec<String>> {
        let (_, features) = self
            .odometry
            .process_with_features(frame)
            .with_context(|| format!("frame {}", frame.index))?;
        let raw = frame.to_cloud();
        let overlay = FrameOverlay {
            frame,
            features: &features,
            selected_pixels: self.odometry.downsampler.selected_pixels(),
            cloud: self.odometry.last_cloud(),
            raw: &raw,
        };
        let pictured = super::write(out, &overlay)?;
        let clouds = super::write_clouds(out, &overlay)?;
        let names = pictured
            .images
            .iter()
            .map(|i| i.file.clone())
            .chain([pictured.top.file.clone()])
            .chain(clouds);
        Ok(names.map(|n| out.join(n).display().to_string()).collect())
    }
}
