//! Global maps saved from a keylo run (`keylo run … --map-out DIR`, docs/maps.md).
//!
//! A map folder holds the whole run's cloud in the world frame, voxelised (each voxel keeps
//! the centroid and mean intensity of its points) as `map.ply` and `map.pcd`, and keyframes
//! (pose, stamp, the keyframe's cloud, its keypoints and descriptors when the pipeline made
//! them), described by a versioned `map.json`. While a map is built only what was added to
//! the tiles within the sensor's reach (since it last came by) stays in memory, within a
//! budget (`memory_mb`); the rest is on disk and merged at the end, so memory stays bounded
//! however long the run.
//!
//! - [`MapBuilder`]: feed it each registered frame, then `finish`.
//! - [`Map`]: an existing map folder, checked ([`Map::open`]), its cloud read or cropped.

mod accumulate;
mod builder;
mod config;
pub mod covariance;
mod error;
mod features_json;
mod keyframes;
pub mod localise;
mod manifest;
mod open;
mod pose_graph;
mod tiles;

pub use builder::MapBuilder;
pub use config::MapConfig;
pub use error::MapError;
pub use keyframes::KeyframeRow;
pub use manifest::{Bounds, MapManifest, FORMAT, VERSION};
pub use open::Map;
pub use pose_graph::{PoseGraph, FALLBACK_VARIANCE};
