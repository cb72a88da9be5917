//! `[ros2]`: the node's topics, frames, QoS and covariance settings. Names follow official
//! KISS-ICP's ROS 2 node where they mean the same (`base_frame`, `lidar_odom_frame`,
//! `publish_odom_tf`, `invert_odom_tf`, `position_covariance`, `orientation_covariance`).

use serde::{Deserialize, Serialize};

use crate::Ros2Error;

/// How the input topic is read.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum Reliability {
    /// ROS 2's sensor-data profile: best effort, keep last 5 (what LiDAR drivers publish).
    BestEffort,
    /// Reliable, keep last 100: for replays (`ros2 bag play`) where no cloud may be lost.
    Reliable,
}

/// `[ros2]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct Ros2Config {
    /// The node's name (`ros2 node list` shows `/NAMESPACE/NAME`).
    pub node_name: String,
    /// The node's namespace; relative topics below are resolved in it.
    pub namespace: String,
    /// sensor_msgs/PointCloud2 input (organised Ouster clouds or unorganised ones).
    pub points_topic: String,
    /// Reliability of the input: `best-effort` (sensor data) or `reliable` (replays).
    pub input_reliability: Reliability,
    /// nav_msgs/Odometry output (reliable, keep last 100).
    pub odometry_topic: String,
    /// nav_msgs/Path output (empty: none).
    pub path_topic: String,
    /// Poses kept in the path message (the oldest go first; memory stays bounded).
    pub path_max_poses: usize,
    /// The robot frame the odometry is of (`child_frame_id`); empty: the cloud's frame.
    pub base_frame: String,
    /// The LiDAR's frame when frames come from the config's `[source]` (a live `ouster-udp`
    /// sensor) instead of the points topic (ouster-ros names it `os_sensor`).
    pub sensor_frame: String,
    /// The odometry frame (`header.frame_id` of the odometry, parent of `base_frame` in TF).
    pub lidar_odom_frame: String,
    /// Publish `lidar_odom_frame → base_frame` on `/tf`.
    pub publish_odom_tf: bool,
    /// Publish the inverse, `base_frame → lidar_odom_frame` (when `base_frame` already has a
    /// parent, e.g. wheel odometry's `odom`).
    pub invert_odom_tf: bool,
    /// Pose of the LiDAR in `base_frame`: `[x, y, z, qx, qy, qz, qw]` (m, unit quaternion).
    /// The odometry frame coincides with the base at the first scan, as in KISS-ICP's node.
    pub base_to_lidar: Vec<f64>,
    /// DDS domain; absent: `ROS_DOMAIN_ID`, else 0.
    pub domain_id: Option<u16>,
    /// Clouds waiting for registration at most: when registration falls behind, the oldest
    /// waiting cloud is dropped (and counted).
    pub max_pending_clouds: usize,
    /// The pose covariance: 0 uses the noise model fitted for the registrar against simulated
    /// ground truth (`s·H⁻¹` plus terms growing with the frame's motion, the pose graph's;
    /// docs/results/maps.md); a value σ (m) uses plain `σ² H⁻¹`.
    pub residual_sigma_m: f64,
    /// Position variance (m²) used when the registrar gives no covariance for a frame
    /// (KISS-ICP's node uses this constant for every frame).
    pub position_covariance: f64,
    /// Orientation variance (rad²) used in the same case.
    pub orientation_covariance: f64,
    /// std_msgs/Empty: start over (map and motion forgotten, pose back to identity).
    pub reset_topic: String,
    /// geometry_msgs/PoseWithCovarianceStamped: the pose of `base_frame` in
    /// `lidar_odom_frame` from now on (map and motion kept), like rviz's `/initialpose`.
    pub set_pose_topic: String,
    /// nav_msgs/Odometry of another odometry (wheels, IMU): the motion between its two messages
    /// around each scan becomes the next registration's initial guess. Empty: off.
    pub motion_prior_topic: String,
    /// sensor_msgs/PointCloud2 of the points registered (sensor frame); empty: off.
    pub registered_cloud_topic: String,
    /// sensor_msgs/PointCloud2 of the keypoints' 3-D points (sensor frame); empty: off.
    pub keypoint_cloud_topic: String,
    /// sensor_msgs/PointCloud2 of the registrar's local map (odometry frame); empty: off.
    pub local_map_topic: String,
    /// sensor_msgs/Image (mono8) of the first LiDAR image with its keypoints; empty: off.
    pub keypoint_image_topic: String,
}

impl Default for Ros2Config {
    fn default() -> Self {
        Self {
            node_name: "keylo".into(),
            namespace: "/".into(),
            points_topic: "/points".into(),
            input_reliability: Reliability::BestEffort,
            odometry_topic: "keylo/odometry".into(),
            path_topic: "keylo/path".into(),
            path_max_poses: 10_000,
            base_frame: String::new(),
            sensor_frame: "os_sensor".into(),
            lidar_odom_frame: "odom_lidar".into(),
            publish_odom_tf: true,
            invert_odom_tf: false,
            base_to_lidar: vec![0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0],
            domain_id: None,
            max_pending_clouds: 2,
            residual_sigma_m: 0.0,
            position_covariance: 0.1,
            orientation_covariance: 0.1,
            reset_topic: "keylo/reset".into(),
            set_pose_topic: "keylo/set_pose".into(),
            motion_prior_topic: String::new(),
            registered_cloud_topic: String::new(),
            keypoint_cloud_topic: String::new(),
            local_map_topic: String::new(),
            keypoint_image_topic: String::new(),
        }
    }
}

impl Ros2Config {
    /// Reads and checks the `[ros2]` table of a config (`origin` names the file).
    pub fn from_table(table: &toml::Table, origin: &str) -> Result<Self, Ros2Error> {
        let value = toml::Value::Table(table.clone());
        let config: Self = serde_path_to_error::deserialize(value).map_err(|e| {
            let path = e.path().to_string();
            let inner = e.into_inner();
            Ros2Error::Config {
                origin: origin.into(),
                message: if path == "." {
                    format!("[ros2] {}", inner.message())
                } else {
                    format!("ros2.{path}: {}", inner.message())
                },
            }
        })?;
        config.check().map_err(|message| Ros2Error::Config {
            origin: origin.into(),
            message,
        })?;
        Ok(config)
    }

    fn check(&self) -> Result<(), String> {
        if self.points_topic.is_empty() || self.odometry_topic.is_empty() {
            return Err("ros2.points_topic and ros2.odometry_topic must not be empty".into());
        }
        if self.lidar_odom_frame.is_empty() {
            return Err("ros2.lidar_odom_frame must not be empty".into());
        }
        if self.max_pending_clouds == 0 {
            return Err("ros2.max_pending_clouds is 0; expected at least 1".into());
        }
        let sigma = self.residual_sigma_m;
        if !(sigma.is_finite() && sigma >= 0.0) {
            return Err(format!(
                "ros2.residual_sigma_m is {sigma}; expected 0 (the fitted noise model) or a \
                 positive number of metres"
            ));
        }
        for (key, v) in [
            ("position_covariance", self.position_covariance),
            ("orientation_covariance", self.orientation_covariance),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(format!("ros2.{key} is {v}; expected a positive number"));
            }
        }
        self.check_names()?;
        crate::frames::extrinsic(&self.base_to_lidar).map(|_| ())
    }

    /// Topic and node names as ROS 2 accepts them (checked before joining DDS).
    fn check_names(&self) -> Result<(), String> {
        let ns = self.namespace_path();
        ros2_client::NodeName::new(&ns, &self.node_name).map_err(|e| {
            format!(
                "ros2.node_name `{}` in ros2.namespace `{}` is not a valid ROS 2 node name ({e:?})",
                self.node_name, self.namespace
            )
        })?;
        for (key, topic) in [
            ("points_topic", &self.points_topic),
            ("odometry_topic", &self.odometry_topic),
            ("path_topic", &self.path_topic),
            ("reset_topic", &self.reset_topic),
            ("set_pose_topic", &self.set_pose_topic),
            ("motion_prior_topic", &self.motion_prior_topic),
            ("registered_cloud_topic", &self.registered_cloud_topic),
            ("keypoint_cloud_topic", &self.keypoint_cloud_topic),
            ("local_map_topic", &self.local_map_topic),
            ("keypoint_image_topic", &self.keypoint_image_topic),
        ] {
            if topic.is_empty() {
                continue;
            }
            let full = crate::dds::resolve(&ns, topic);
            ros2_client::Name::parse(&full).map_err(|e| {
                format!("ros2.{key} `{topic}` is not a valid ROS 2 topic name ({e:?})")
            })?;
        }
        Ok(())
    }

    /// The namespace as an absolute path (`robot` → `/robot`).
    pub(crate) fn namespace_path(&self) -> String {
        if self.namespace.starts_with('/') {
            self.namespace.clone()
        } else {
            format!("/{}", self.namespace)
        }
    }

    /// A topic of these settings, resolved in the namespace.
    pub(crate) fn topic(&self, topic: &str) -> String {
        crate::dds::resolve(&self.namespace_path(), topic)
    }

    /// The DDS domain: `domain_id`, else `ROS_DOMAIN_ID`, else 0.
    pub fn domain(&self) -> Result<u16, Ros2Error> {
        if let Some(d) = self.domain_id {
            return Ok(d);
        }
        match std::env::var("ROS_DOMAIN_ID") {
            Ok(v) if !v.trim().is_empty() => v.trim().parse().map_err(|_| Ros2Error::Config {
                origin: "environment".into(),
                message: format!("ROS_DOMAIN_ID is `{v}`; expected 0..=232"),
            }),
            _ => Ok(0),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<Ros2Config, Ros2Error> {
        Ros2Config::from_table(&text.parse::<toml::Table>().unwrap(), "t.toml")
    }

    #[test]
    fn defaults_are_kiss_icps_where_they_mean_the_same() {
        let c = parse("").unwrap();
        assert_eq!(c.points_topic, "/points");
        assert_eq!(c.odometry_topic, "keylo/odometry");
        assert_eq!(c.lidar_odom_frame, "odom_lidar");
        assert!(c.publish_odom_tf && !c.invert_odom_tf);
        assert_eq!(c.input_reliability, Reliability::BestEffort);
        let c = parse("input_reliability = \"reliable\"\ndomain_id = 7").unwrap();
        assert_eq!(c.domain().unwrap(), 7);
        assert_eq!(c.input_reliability, Reliability::Reliable);
    }

    #[test]
    fn bad_values_name_the_key() {
        let e = parse("points_topc = \"/x\"").unwrap_err().to_string();
        assert!(e.contains("points_topc") && e.contains("t.toml"), "{e}");
        let e = parse("base_to_lidar = [0, 0, 0, 0, 0, 0, 2]")
            .unwrap_err()
            .to_string();
        assert!(e.contains("base_to_lidar"), "{e}");
        let e = parse("points_topic = \"/a//b\"").unwrap_err().to_string();
        assert!(e.contains("ros2.points_topic"), "{e}");
        let e = parse("node_name = \"9lives\"").unwrap_err().to_string();
        assert!(e.contains("ros2.node_name"), "{e}");
        let e = parse("max_pending_clouds = 0").unwrap_err().to_string();
        assert!(e.contains("max_pending_clouds"), "{e}");
        let e = parse("residual_sigma_m = -1.0").unwrap_err().to_string();
        assert!(e.contains("residual_sigma_m"), "{e}");
    }
}
