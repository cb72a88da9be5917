//! `map.json`: what a map folder holds, versioned.

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::{MapConfig, MapError};

/// `format` of every keylo map's `map.json`.
pub const FORMAT: &str = "keylo-map";
/// The folder layout this keylo writes and reads.
pub const VERSION: u32 = 1;

/// The file names inside a map folder.
pub(crate) mod files {
    pub const MANIFEST: &str = "map.json";
    pub const CLOUD_PLY: &str = "map.ply";
    pub const CLOUD_PCD: &str = "map.pcd";
    pub const KEYFRAMES: &str = "keyframes.csv";
    pub const KEYFRAME_DIR: &str = "keyframes";
}

/// An axis-aligned box, world frame (m).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Bounds {
    pub min: [f64; 3],
    pub max: [f64; 3],
}

impl Bounds {
    /// The box holding nothing (grows with [`Bounds::grow`]).
    pub fn empty() -> Self {
        Self {
            min: [f64::INFINITY; 3],
            max: [f64::NEG_INFINITY; 3],
        }
    }

    /// Grows the box to hold `p`.
    pub fn grow(&mut self, p: [f64; 3]) {
        for ((lo, hi), v) in self.min.iter_mut().zip(&mut self.max).zip(p) {
            *lo = lo.min(v);
            *hi = hi.max(v);
        }
    }

    /// Whether `p` lies in the box (edges included).
    pub fn contains(&self, p: [f64; 3]) -> bool {
        (0..3).all(|k| p[k] >= self.min[k] && p[k] <= self.max[k])
    }
}

/// The contents of `map.json`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MapManifest {
    /// Always [`FORMAT`].
    pub format: String,
    /// The folder layout's version ([`VERSION`]).
    pub version: u32,
    /// The keylo that wrote it.
    pub keylo_version: String,
    /// The frame the cloud and poses are in: the odometry's world frame (the first pose).
    pub frame: String,
    /// How the map was built.
    pub settings: MapConfig,
    /// Frames that went into the map.
    pub frames: usize,
    /// Points (voxels) of the global cloud.
    pub points: usize,
    /// The box around the global cloud (`null` for an empty map).
    pub bounds: Option<Bounds>,
    /// Keyframes (rows of `keyframes.csv`).
    pub keyframes: usize,
    /// Whether keyframes carry keypoints and descriptors (`keyframes/NNNNNN.features.json`).
    pub keyframe_features: bool,
    /// The source the run read, as keylo described it.
    pub source: String,
    /// Where this map was cut from (`keylo map crop`), if it was.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cropped_from: Option<String>,
}

impl MapManifest {
    /// Reads and checks `dir/map.json`: a keylo map of this version, else an error naming
    /// the file and what it holds.
    pub fn read(dir: &Path) -> Result<Self, MapError> {
        let path = dir.join(files::MANIFEST);
        if !dir.is_dir() {
            return Err(MapError::format(dir, "no such map folder"));
        }
        let text = std::fs::read_to_string(&path).map_err(|e| match e.kind() {
            std::io::ErrorKind::NotFound => MapError::format(
                &path,
                "missing: this folder is not a keylo map (make one with `keylo run … --map-out DIR`)",
            ),
            _ => MapError::io(&path, e),
        })?;
        let value: serde_json::Value = serde_json::from_str(&text)
            .map_err(|e| MapError::format(&path, format!("not JSON: {e}")))?;
        let format = value.get("format").and_then(|v| v.as_str());
        if format != Some(FORMAT) {
            return Err(MapError::format(
                &path,
                format!(
                    "format is {:?}; expected \"{FORMAT}\" (not a keylo map)",
                    format.unwrap_or("missing")
                ),
            ));
        }
        let version = value.get("version").and_then(|v| v.as_u64());
        if version != Some(u64::from(VERSION)) {
            return Err(MapError::format(
                &path,
                format!(
                    "map version {}; this keylo reads version {VERSION} (rebuild the map with this keylo)",
                    version.map_or("missing".to_string(), |v| v.to_string())
                ),
            ));
        }
        let manifest: Self =
            serde_json::from_value(value).map_err(|e| MapError::format(&path, e))?;
        manifest
            .settings
            .check()
            .map_err(|m| MapError::format(&path, format!("settings: {m}")))?;
        Ok(manifest)
    }

    /// Writes `dir/map.json`.
    pub fn write(&self, dir: &Path) -> Result<(), MapError> {
        let path = dir.join(files::MANIFEST);
        let text = serde_json::to_string_pretty(self).map_err(|e| MapError::format(&path, e))?;
        std::fs::write(&path, text + "\n").map_err(|e| MapError::io(&path, e))
    }
}
