//! What the node publishes for one registered frame: odometry, TF, path and the debug
//! topics (registered cloud, keypoint cloud, local map, keypoint image).

use keylo_core::{FrameFeatures, FrameResult, LidarFrame, Odometry};

use crate::msgs::Time;
use crate::outputs::{self, OdometryParts};
use crate::runner::Ros2Node;

impl Ros2Node {
    /// Publishes frame `r`'s odometry, TF, path and debug topics (nothing, with a warning,
    /// for a localiser's frame that is not tracking), stamped `stamp_ns`.
    pub(crate) fn publish(
        &mut self,
        odometry: &Odometry,
        r: &FrameResult,
        frame: &LidarFrame,
        features: Option<&FrameFeatures>,
        cloud_frame: &str,
        stamp_ns: i64,
    ) {
        self.last_registered = Some(r.stamp);
        if let Some(fit) = r.fit.filter(|f| !f.tracking) {
            self.stats.frames_not_tracking += 1;
            tracing::warn!(
                "ros2: frame {}: not tracking in the map (fitness {:.2}); nothing published",
                r.index,
                fit.fitness
            );
            return;
        }
        let stamp = Time::from_ns(stamp_ns);
        let base_frame = if self.config.base_frame.is_empty() {
            cloud_frame
        } else {
            self.config.base_frame.as_str()
        };
        let raw_base = self.base.base_pose(&r.pose);
        let base_pose = self.anchor * raw_base;
        let (odom, estimated) = outputs::odometry(
            r,
            &OdometryParts {
                odom_frame: &self.config.lidar_odom_frame,
                base_frame,
                stamp,
                previous: self.previous,
                base: &self.base,
                anchor: &self.anchor,
                base_pose,
                covariance: self.frame_covariance(r),
                fallback: (
                    self.config.position_covariance,
                    self.config.orientation_covariance,
                ),
            },
        );
        if !estimated {
            self.stats.fallback_covariances += 1;
        }
        self.last_raw_base = Some(raw_base);
        self.last_lidar = Some(r.pose);
        self.previous = Some((base_pose, r.stamp));
        let w = &self.dds.writers;
        let topic = &self.config.odometry_topic;
        if let Some(tf) = &w.tf {
            report(
                tf.publish(outputs::tf(&odom, &base_pose, self.config.invert_odom_tf)),
                "/tf",
            );
        }
        if let Some(p) = &w.path {
            report(p.publish(self.path.push(&odom)), &self.config.path_topic);
        }
        if let Some(p) = &w.registered_cloud {
            if let Some(c) = odometry.last_cloud() {
                let m = outputs::cloud(c.points.iter().copied(), stamp, cloud_frame);
                report(p.publish(m), &self.config.registered_cloud_topic);
            }
        }
        if let (Some(p), Some(f)) = (&w.keypoint_cloud, features) {
            let pts = outputs::keypoint_points(frame, f);
            let m = outputs::cloud(pts.into_iter(), stamp, cloud_frame);
            report(p.publish(m), &self.config.keypoint_cloud_topic);
        }
        if let Some(p) = &w.local_map {
            // The map is in the first scan's LiDAR frame; the odometry frame is the base's.
            let to_odom = self.anchor * self.base.extrinsic();
            let pts = odometry.local_map().into_iter().map(|q| to_odom * q);
            let m = outputs::cloud(pts, stamp, &self.config.lidar_odom_frame);
            report(p.publish(m), &self.config.local_map_topic);
        }
        if let (Some(p), Some(f)) = (&w.keypoint_image, features) {
            if let Some(m) = outputs::keypoint_image(f, stamp, cloud_frame) {
                report(p.publish(m), &self.config.keypoint_image_topic);
            }
        }
        report(w.odometry.publish(odom), topic);
    }
}

fn report<E: std::fmt::Debug>(r: Result<(), E>, topic: &str) {
    if let Err(e) = r {
        tracing::warn!("{topic}: publishing failed: {e:?}");
    }
}
