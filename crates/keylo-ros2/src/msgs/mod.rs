//! The ROS 2 messages keylo sends and receives, as serde structs with the field order and
//! types of their `.msg` files (Humble and Jazzy have the same layouts). RustDDS serialises
//! them as CDR (XCDR1, little endian), as every ROS 2 middleware does.

mod geometry;
mod nav;
mod sensor;
mod std_msgs;

pub use geometry::{
    Point, Pose, PoseStamped, PoseWithCovariance, PoseWithCovarianceStamped, Quaternion, Transform,
    TransformStamped, Twist, TwistWithCovariance, Vector3,
};
pub use nav::{Odometry, Path, TfMessage};
pub use sensor::{Image, PointCloud2, PointField};
pub use std_msgs::{Empty, Header, Time};

/// A message type and its ROS 2 name (`package`, `Type`): DDS matches readers and writers by
/// `package::msg::dds_::Type_`, which ros2-client makes from these.
pub trait RosMessage {
    /// The package, e.g. `nav_msgs`.
    const PACKAGE: &'static str;
    /// The type, e.g. `Odometry`.
    const NAME: &'static str;
}

macro_rules! ros_message {
    ($($t:ty => $pkg:literal / $name:literal),* $(,)?) => {
        $(impl RosMessage for $t {
            const PACKAGE: &'static str = $pkg;
            const NAME: &'static str = $name;
        })*
    };
}

ros_message! {
    PointCloud2 => "sensor_msgs" / "PointCloud2",
    Image => "sensor_msgs" / "Image",
    Odometry => "nav_msgs" / "Odometry",
    Path => "nav_msgs" / "Path",
    TfMessage => "tf2_msgs" / "TFMessage",
    PoseWithCovarianceStamped => "geometry_msgs" / "PoseWithCovarianceStamped",
    Empty => "std_msgs" / "Empty",
}
