//! The topics a run streams and records, and the frames they are in (docs/report.md,
//! "Watching a run live").

/// The frame the poses, the trajectory, the reference and the map are in.
pub const WORLD_FRAME: &str = "odom";
/// The sensor's frame: the scan, the registered cloud.
pub const SENSOR_FRAME: &str = "lidar";

/// The input scan, `sensor_msgs/msg/PointCloud2` (CDR), sensor frame: the organised grid
/// (`height` rows) or, for unorganised sources, every point.
pub const SCAN: &str = "/keylo/scan";
/// The points the registrar was given (`foxglove.PointCloud`, sensor frame).
pub const REGISTERED: &str = "/keylo/registered";
/// The registrar's local map (`foxglove.PointCloud`, world frame), every `map_every` frames.
pub const MAP: &str = "/keylo/map";
/// The frame's pose (`foxglove.PoseInFrame`, world frame).
pub const POSE: &str = "/keylo/pose";
/// World → sensor (`foxglove.FrameTransform`), so the 3-D panel places the sensor-frame clouds.
pub const TF: &str = "/tf";
/// The trajectory so far (`foxglove.PosesInFrame`), with the map.
pub const TRAJECTORY: &str = "/keylo/trajectory";
/// The reference trajectory (ground truth), aligned to the estimate's first pose
/// (`foxglove.PosesInFrame`), with the map.
pub const REFERENCE: &str = "/keylo/reference";
/// The frame's figures (JSON: keypoints, points, iterations, milliseconds, degenerate).
pub const STATS: &str = "/keylo/stats";

/// A LiDAR image (`foxglove.RawImage`, mono8 or rgb8).
pub fn image(name: &str) -> String {
    format!("/keylo/image/{name}")
}

/// The keypoints found in an image (`foxglove.ImageAnnotations`).
pub fn keypoints(name: &str) -> String {
    format!("/keylo/image/{name}/keypoints")
}
