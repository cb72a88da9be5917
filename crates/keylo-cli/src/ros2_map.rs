//! `keylo ros2 --map-out DIR`: the node's frames saved as a global map. A reset
//! (`keylo/reset`) starts a new trajectory at the identity, so the map so far is finished and
//! the next goes to `DIR-1`, `DIR-2`, …; a map that cannot be written is logged and dropped,
//! and the node goes on.

use std::path::{Path, PathBuf};

use keylo::map::{MapBuilder, MapConfig, MapManifest};
use keylo_ros2::Published;

/// The maps a node saves.
pub struct NodeMap {
    base: PathBuf,
    settings: MapConfig,
    current: Option<MapBuilder>,
    /// The reset count the current map belongs to.
    resets: u64,
    /// Maps finished so far, with their folders.
    pub finished: Vec<(PathBuf, MapManifest)>,
}

impl NodeMap {
    /// Starts the first map in `dir`; the error names a folder that cannot be made.
    pub fn start(dir: &Path, settings: MapConfig) -> Result<Self, keylo::map::MapError> {
        let current = MapBuilder::create(dir, settings.clone(), SOURCE)?;
        Ok(Self {
            base: dir.to_path_buf(),
            settings,
            current: Some(current),
            resets: 0,
            finished: Vec::new(),
        })
    }

    /// Whether the maps keep the frames' keypoints and descriptors.
    pub fn wants_features(&self) -> bool {
        self.settings.keyframe_features
    }

    /// Adds a published frame, after a reset to a new map.
    pub fn add(&mut self, p: &Published) {
        if p.resets != self.resets {
            self.finish_current();
            self.resets = p.resets;
            let dir = PathBuf::from(format!("{}-{}", self.base.display(), p.resets));
            match MapBuilder::create(&dir, self.settings.clone(), SOURCE) {
                Ok(m) => self.current = Some(m),
                Err(e) => tracing::error!(
                    "map after reset {}: {e}; no map until the next reset",
                    p.resets
                ),
            }
        }
        if let Some(map) = self.current.as_mut() {
            if let Err(e) = map.add(p.frame, p.result, p.features) {
                tracing::error!(
                    "map: frame {}: {e}; the map stops here, the node goes on",
                    p.result.index
                );
                self.finish_current();
            }
        }
    }

    fn finish_current(&mut self) {
        let dir = match self.resets {
            0 => self.base.clone(),
            n => PathBuf::from(format!("{}-{n}", self.base.display())),
        };
        if let Some(map) = self.current.take() {
            match map.finish() {
                Ok(m) => self.finished.push((dir, m)),
                Err(e) => tracing::error!("map {}: {e}", dir.display()),
            }
        }
    }

    /// Finishes the map being saved; returns every map saved.
    pub fn finish(mut self) -> Vec<(PathBuf, MapManifest)> {
        self.finish_current();
        self.finished
    }
}

const SOURCE: &str = "ROS 2 topic (keylo ros2)";
