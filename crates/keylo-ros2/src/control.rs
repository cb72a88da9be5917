//! The node's control inputs: reset, set-pose (a re-anchoring of the published odometry) and
//! the external motion prior handed to the registrar before each scan.

use keylo_core::{LidarFrame, Odometry};
use nalgebra::Isometry3;

use crate::dds::Command;
use crate::frames;
use crate::runner::Ros2Node;

impl Ros2Node {
    pub(crate) fn command(&mut self, odometry: &mut Odometry, c: Command) {
        match c {
            Command::Reset => match odometry.reset() {
                Ok(()) => {
                    self.previous = None;
                    self.last_registered = None;
                    self.last_raw_base = None;
                    self.last_lidar = None;
                    self.anchor = Isometry3::identity();
                    self.cloud_frame = None;
                    self.path.clear();
                    self.prior.clear();
                    self.stats.resets += 1;
                    tracing::info!("ros2: reset: map and motion forgotten");
                }
                Err(e) => tracing::warn!("ros2: reset refused: {e}"),
            },
            Command::SetPose(m) => {
                let Some(base) = frames::pose_from_msg(&m.pose.pose) else {
                    tracing::warn!(
                        "{}: pose is not finite or its quaternion is not unit length; ignored",
                        self.config.set_pose_topic
                    );
                    return;
                };
                if !m.header.frame_id.is_empty()
                    && m.header.frame_id != self.config.lidar_odom_frame
                {
                    tracing::warn!(
                        "{}: the pose is in `{}`, expected `{}`; ignored",
                        self.config.set_pose_topic,
                        m.header.frame_id,
                        self.config.lidar_odom_frame
                    );
                    return;
                }
                if self.localising {
                    self.relocalise(odometry, base);
                    return;
                }
                // The published odometry is re-anchored: the base is at `base` now and moves on
                // from there. keylo's own map and poses are left as they are, so registration
                // goes on against a consistent map.
                let raw = self.last_raw_base.unwrap_or_else(Isometry3::identity);
                self.anchor = base * raw.inverse();
                // The next twist would otherwise jump by the set-pose step.
                self.previous = self.previous.map(|(_, t)| (base, t));
                self.stats.poses_set += 1;
                tracing::info!("ros2: pose set");
            }
            Command::MotionPrior(m) => {
                if let Err(e) = self.prior.push(&m) {
                    tracing::warn!("{}: {e}; ignored", self.config.motion_prior_topic);
                } else {
                    self.pending_prior = true;
                }
            }
        }
    }

    /// Set-pose for a localiser: the map is fixed, so the localiser itself starts again from
    /// `base` (its LiDAR pose) rather than the output being re-anchored.
    fn relocalise(&mut self, odometry: &mut Odometry, base: Isometry3<f64>) {
        match odometry.set_pose(&self.base.lidar_pose(&base)) {
            Ok(()) => {
                self.anchor = Isometry3::identity();
                self.last_raw_base = Some(base);
                // The pose set is the pose now: a motion since the last scan is not added.
                self.pending_prior = false;
                self.previous = self.previous.map(|(_, t)| (base, t));
                self.stats.poses_set += 1;
                tracing::info!("ros2: pose set: the localiser starts again from it");
            }
            Err(e) => tracing::warn!("ros2: set-pose refused: {e}"),
        }
    }

    /// Gives the registrar the other odometry's motion between the last scan and this one.
    pub(crate) fn apply_prior(&mut self, odometry: &mut Odometry, frame: &LidarFrame) {
        if !self.pending_prior {
            return;
        }
        let Some(t0) = self.last_registered else {
            return;
        };
        let Some(base_motion) = self.prior.motion(t0, frame.end_stamp()) else {
            tracing::debug!("ros2: no motion prior covers this scan; the motion model is used");
            return;
        };
        // The other odometry tracks the base; keylo's motion is the LiDAR's.
        let a = self.base.extrinsic();
        let lidar_motion = a.inverse() * base_motion * a;
        match odometry.set_motion_prior(&lidar_motion) {
            Ok(()) => self.stats.motion_priors_used += 1,
            Err(e) => {
                tracing::warn!("ros2: motion prior refused: {e}");
                self.pending_prior = false;
            }
        }
    }
}
