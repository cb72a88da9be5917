//! `keylo run --images N`: the pictures of every N-th frame, and the clouds of the first.

use std::path::PathBuf;

use anyhow::{Context, Result};
use keylo::{FrameFeatures, LidarFrame, Odometry};

use super::{FrameOverlay, Pictured};

/// The list of pictured frames in the pictures' folder.
pub const INDEX: &str = "pictures.json";

/// Which frames are pictured, and where.
pub struct Pictures {
    every: u64,
    dir: PathBuf,
    clouds_written: bool,
    /// Everything pictured so far, rewritten to `pictures.json` after each frame.
    index: Vec<Pictured>,
}

impl Pictures {
    /// Frames 0, `every`, 2 × `every`, … into `dir`.
    pub fn new(every: u64, dir: PathBuf) -> Self {
        Self {
            every: every.max(1),
            dir,
            clouds_written: false,
            index: Vec::new(),
        }
    }

    /// Whether frame `index` is pictured (its features must then be kept).
    pub fn wants(&self, index: u64) -> bool {
        index.is_multiple_of(self.every)
    }

    /// Writes frame's pictures from what `odometry` made of it; the first pictured frame
    /// with a registered cloud also gets its raw and registered points as PLY.
    pub fn record(
        &mut self,
        odometry: &Odometry,
        frame: &LidarFrame,
        features: &FrameFeatures,
    ) -> Result<()> {
        let raw = frame.to_cloud();
        let overlay = FrameOverlay {
            frame,
            features,
            selected_pixels: odometry.downsampler.selected_pixels(),
            cloud: odometry.last_cloud(),
            raw: &raw,
        };
        let mut pictured = super::write(&self.dir, &overlay)?;
        if !self.clouds_written && overlay.cloud.is_some_and(|c| !c.is_empty()) {
            pictured.clouds = Some(super::write_clouds(&self.dir, &overlay)?);
            self.clouds_written = true;
        }
        self.index.push(pictured);
        let path = self.dir.join(INDEX);
        crate::atomic::write(&path, serde_json::to_vec_pretty(&self.index)?)
            .with_context(|| format!("writing {}", path.display()))
    }
}
