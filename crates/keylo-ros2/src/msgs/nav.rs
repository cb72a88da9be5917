//! `nav_msgs/Odometry`, `nav_msgs/Path` and `tf2_msgs/TFMessage`.

use serde::{Deserialize, Serialize};

use super::{Header, PoseStamped, PoseWithCovariance, TransformStamped, TwistWithCovariance};

/// `nav_msgs/Odometry`: the pose in `header.frame_id`, the twist in `child_frame_id`.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct Odometry {
    pub header: Header,
    pub child_frame_id: String,
    pub pose: PoseWithCovariance,
    pub twist: TwistWithCovariance,
}

/// `nav_msgs/Path`.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct Path {
    pub header: Header,
    pub poses: Vec<PoseStamped>,
}

/// `tf2_msgs/TFMessage` (topics `/tf` and `/tf_static`).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct TfMessage {
    pub transforms: Vec<TransformStamped>,
}
