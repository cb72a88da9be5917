//! KITTI odometry folders as a source (`kind = "kitti"`): `velodyne/*.bin` scans (float32
//! x y z reflectance), optional `times.txt`, `calib.txt` (`Tr:` Velodyne → cam0) and a pose
//! file (cam0 frame) that becomes LiDAR ground truth. Layout and rules: `docs/formats.md`.

mod config;
mod ground_truth;
mod side_files;
mod source;

pub use config::KittiSourceConfig;
pub use ground_truth::{cam_to_lidar, lidar_ground_truth};
pub use side_files::{read_calib_tr, read_times};
pub use source::{is_kitti_data, KittiSource};
