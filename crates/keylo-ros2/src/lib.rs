//! keylo as a ROS 2 node, in pure Rust over DDS (`ros2-client` on RustDDS): no ROS install.
//!
//! In: `sensor_msgs/PointCloud2` (organised Ouster clouds become LiDAR images from their own
//! fields; unorganised clouds are projected), made into frames by the same code as `keylo
//! run`'s bag sources, so deskew and images are the same. Out: `nav_msgs/Odometry` stamped
//! with the scan's end on the cloud's own clock, with keylo's per-frame covariance; `/tf`;
//! `nav_msgs/Path`; optional debug clouds and the keypoint picture. Control: reset, set-pose
//! and an external motion prior. Topics, QoS and frames: `docs/ros2.md`.

mod config;
mod control;
mod dds;
mod error;
pub mod frames;
mod inbox;
pub mod msgs;
mod outputs;
mod prior;
mod publish;
mod runner;
mod source_input;

pub use config::{Reliability, Ros2Config};
pub use error::Ros2Error;
pub use inbox::Inbox;
pub use runner::{NodeStats, Published, Ros2Node};
