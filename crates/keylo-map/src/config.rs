//! `[map]`: how a run's global map is built (read from a config's `[map]` table).

use serde::{Deserialize, Serialize};

use crate::MapError;

/// The settings of a saved map (`[map]` in a config, `--set map.KEY=VALUE`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct MapConfig {
    /// Edge of the global cloud's voxels (m): each voxel keeps the centroid and the mean
    /// intensity of every point that fell into it.
    pub voxel_size: f64,
    /// Points nearer than this to the sensor stay out of the map (m): the robot itself.
    pub min_range: f64,
    /// Points farther than this from the sensor stay out of the map (m). Also how far from
    /// the sensor the map's tiles stay in memory.
    pub max_range: f64,
    /// Edge of the square tiles (x, y; m) the map is built in. Tiles out of the sensor's
    /// reach go to disk; all are merged at the end.
    pub tile_size: f64,
    /// Memory for the voxels being built, MB (about 72 bytes a voxel): past it every tile in
    /// memory goes to disk, so a long run, or one that passes the same place many times,
    /// stays within it. The saved map is the same (means equal to f32 rounding).
    pub memory_mb: f64,
    /// A new keyframe when the sensor has moved this far from the last keyframe (m).
    pub keyframe_distance: f64,
    /// … or turned this much (degrees).
    pub keyframe_angle_deg: f64,
    /// Voxel edge of each keyframe's own cloud (m; the first point of each voxel is kept,
    /// with its intensity); 0 keeps every point.
    pub keyframe_voxel_size: f64,
    /// Write each keyframe's keypoints, their 3-D points and descriptors when the pipeline
    /// makes them.
    pub keyframe_features: bool,
    /// Move every point to the scan's end with the frame's own motion (from the previous
    /// pose to this one) before it enters the map; needs per-point times.
    pub deskew: bool,
}

impl Default for MapConfig {
    fn default() -> Self {
        Self {
            voxel_size: 0.2,
            min_range: 0.0,
            max_range: 100.0,
            tile_size: 50.0,
            memory_mb: 256.0,
            keyframe_distance: 1.0,
            keyframe_angle_deg: 10.0,
            keyframe_voxel_size: 0.1,
            keyframe_features: true,
            deskew: true,
        }
    }
}

/// Bytes a voxel takes in memory while a map is built (key, mean, intensity, count, and the
/// hash table's share), for `memory_mb`.
pub(crate) const BYTES_PER_VOXEL: f64 = 72.0;

impl MapConfig {
    /// Voxels that fit in `memory_mb`.
    pub(crate) fn voxel_budget(&self) -> usize {
        (self.memory_mb * 1e6 / BYTES_PER_VOXEL) as usize
    }

    /// The settings of a config's `[map]` table (`origin` names the config in errors); the
    /// error names the key and what was expected.
    pub fn from_table(table: &toml::Table, origin: &str) -> Result<Self, MapError> {
        parse_table(table, "map", origin, Self::check)
    }

    /// Checks every value; the message names the key, its value and what is expected.
    pub fn check(&self) -> Result<(), String> {
        let positive = [
            ("voxel_size", self.voxel_size),
            ("max_range", self.max_range),
            ("tile_size", self.tile_size),
            ("memory_mb", self.memory_mb),
        ];
        for (key, v) in positive {
            if !(v.is_finite() && v > 0.0) {
                return Err(format!("map.{key} = {v}: expected a finite value above 0"));
            }
        }
        let non_negative = [
            ("min_range", self.min_range),
            ("keyframe_distance", self.keyframe_distance),
            ("keyframe_angle_deg", self.keyframe_angle_deg),
            ("keyframe_voxel_size", self.keyframe_voxel_size),
        ];
        for (key, v) in non_negative {
            if !(v.is_finite() && v >= 0.0) {
                return Err(format!(
                    "map.{key} = {v}: expected a finite value of 0 or more"
                ));
            }
        }
        if self.min_range >= self.max_range {
            return Err(format!(
                "map.min_range = {} is not below map.max_range = {}",
                self.min_range, self.max_range
            ));
        }
        // Voxel keys are i32: a voxel this small would overflow them within the tile grid.
        if self.max_range / self.voxel_size > 1e7 {
            return Err(format!(
                "map.voxel_size = {}: expected at least max_range / 1e7 = {} m",
                self.voxel_size,
                self.max_range / 1e7
            ));
        }
        Ok(())
    }
}

/// A config's `[section]` table as `T`, checked by `check`; the error names `section.key`
/// and what is wrong.
pub(crate) fn parse_table<T: serde::de::DeserializeOwned>(
    table: &toml::Table,
    section: &str,
    origin: &str,
    check: impl FnOnce(&T) -> Result<(), String>,
) -> Result<T, MapError> {
    let value = toml::Value::Table(table.clone());
    let config: T = serde_path_to_error::deserialize(value).map_err(|e| {
        let path = e.path().to_string();
        let inner = e.into_inner();
        MapError::Config {
            origin: origin.into(),
            message: if path == "." {
                format!("[{section}] {}", inner.message())
            } else {
                format!("{section}.{path}: {}", inner.message())
            },
        }
    })?;
    check(&config).map_err(|message| MapError::Config {
        origin: origin.into(),
        message,
    })?;
    Ok(config)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_and_bad_values_are_named() {
        let ok = MapConfig::from_table(&toml::Table::new(), "t.toml").unwrap();
        assert_eq!(ok, MapConfig::default());
        let cases = [
            ("voxel_size = 0.0", "map.voxel_size = 0"),
            ("max_range = -1.0", "map.max_range = -1"),
            ("min_range = 200.0", "map.min_range = 200 is not below"),
            ("keyframe_angle_deg = nan", "map.keyframe_angle_deg = NaN"),
            ("voxels = 1.0", "unknown field `voxels`"),
            ("voxel_size = \"big\"", "map.voxel_size: invalid type"),
        ];
        for (text, want) in cases {
            let table: toml::Table = toml::from_str(text).unwrap();
            let e = MapConfig::from_table(&table, "t.toml")
                .unwrap_err()
                .to_string();
            assert!(e.starts_with("t.toml: ") && e.contains(want), "{text}: {e}");
        }
    }
}
