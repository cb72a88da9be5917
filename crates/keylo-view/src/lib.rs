//! A keylo run watched live and recorded: [`Viewer`] sends each frame's results to the Foxglove
//! SDK, whose WebSocket server Foxglove and Lichtblick connect to (`--view`) and whose MCAP
//! writer records the same streams (`--record FILE`).
//!
//! Streams (topics in [`topics`]): the input scan as `sensor_msgs/msg/PointCloud2` (CDR, so the
//! recording is also a data set `keylo run --data` reads), the registered cloud, the local map,
//! the pose, the sensor's transform, the trajectory and the reference (Foxglove schemas), the
//! LiDAR images with their keypoints, and the frame's figures as JSON. Nothing is encoded for a
//! live stream no client subscribed to, the large live messages go at most
//! [`ViewOptions::max_hz`] times a second, and a slow or vanished client never holds the run
//! up: its queue drops its oldest messages. The recording takes every frame, written on a
//! thread of its own.
//!
//! ```no_run
//! use keylo_view::{RunInfo, ViewOptions, Viewer};
//! let options = ViewOptions {
//!     serve: Some("127.0.0.1:8765".into()),
//!     ..ViewOptions::default()
//! };
//! let viewer = Viewer::start(&options, &RunInfo::default()).unwrap();
//! println!("open Foxglove or Lichtblick at {}", viewer.url().unwrap_or_default());
//! ```

mod channels;
mod convert;
mod error;
mod frame_view;
mod images;
mod live;
mod options;
mod record;
mod recorder;
mod reference;
mod scan_cdr;
mod stats;
mod streams;
pub mod topics;
mod viewer;

pub use error::ViewError;
pub use frame_view::{FrameView, RecordSummary};
pub use options::{RunInfo, ViewOptions};
pub use scan_cdr::POINTCLOUD2_SCHEMA;
pub use viewer::Viewer;
