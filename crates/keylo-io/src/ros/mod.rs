//! ROS recordings: ROS1 bags (source kind `ros1-bag`) and MCAP files or ROS2 bag folders
//! (source kind `mcap`).
//!
//! `sensor_msgs/PointCloud2` messages become frames (organised clouds pixel for pixel,
//! unorganised ones through [`crate::cloud::Projector`]); `sensor_msgs/Image` topics may fill
//! the frame's channels. Messages are read lazily in log-time order: only the index (or
//! summary) is read up front, then one chunk at a time. Layout rules: `docs/formats.md`.

mod bag;
mod file;
mod image;
mod mcap_file;
mod merge;
mod msgs;
mod pointcloud2;
mod wire;

pub use file::BagFormat;
pub use msgs::{Header, Image, PointCloud2, PointField};
pub use pointcloud2::to_raw_cloud;
pub use wire::Encoding;
