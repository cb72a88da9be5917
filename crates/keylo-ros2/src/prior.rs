//! The external motion prior: poses of another odometry (wheels, IMU) on a topic, interpolated
//! at two scans' end times to give the motion between them.

use std::collections::VecDeque;

use nalgebra::Isometry3;

use crate::frames::pose_from_msg;
use crate::msgs;

/// Poses kept (at 100 Hz, 5 s).
const KEEP: usize = 500;
/// How far outside the kept poses a time may lie and still be answered (s).
const REACH_S: f64 = 0.05;

/// The last poses of another odometry, by stamp.
#[derive(Default)]
pub struct PriorTrack {
    poses: VecDeque<(f64, Isometry3<f64>)>,
}

impl PriorTrack {
    /// Adds a message; `Err` says why it was not taken.
    pub fn push(&mut self, m: &msgs::Odometry) -> Result<(), String> {
        let t = m.header.stamp.to_ns() as f64 * 1e-9;
        let pose = pose_from_msg(&m.pose.pose)
            .ok_or("its pose is not finite or its quaternion is not unit length")?;
        if let Some(&(last, _)) = self.poses.back() {
            if t <= last {
                return Err(format!(
                    "stamp {t:.6} s is not after the previous one ({last:.6} s)"
                ));
            }
        }
        self.poses.push_back((t, pose));
        if self.poses.len() > KEEP {
            self.poses.pop_front();
        }
        Ok(())
    }

    /// The pose at `t`, interpolated (linear translation, slerp rotation).
    pub fn at(&self, t: f64) -> Option<Isometry3<f64>> {
        let first = self.poses.front()?;
        let last = self.poses.back()?;
        if t < first.0 - REACH_S || t > last.0 + REACH_S {
            return None;
        }
        let after = self.poses.partition_point(|(s, _)| *s < t);
        match (
            after.checked_sub(1).map(|i| self.poses[i]),
            self.poses.get(after),
        ) {
            (Some((t0, p0)), Some(&(t1, p1))) => Some(p0.lerp_slerp(&p1, (t - t0) / (t1 - t0))),
            (Some((_, p)), None) | (None, Some(&(_, p))) => Some(p),
            (None, None) => None,
        }
    }

    /// The motion `P(t0)⁻¹ · P(t1)` (in the frame the other odometry's poses are of).
    pub fn motion(&self, t0: f64, t1: f64) -> Option<Isometry3<f64>> {
        Some(self.at(t0)?.inverse() * self.at(t1)?)
    }

    pub fn clear(&mut self) {
        self.poses.clear();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frames::pose_msg;
    use crate::msgs::{Header, Time};
    use nalgebra::Vector3;

    fn msg(t_ns: i64, x: f64) -> msgs::Odometry {
        let mut m = msgs::Odometry {
            header: Header {
                stamp: Time::from_ns(t_ns),
                frame_id: "odom".into(),
            },
            ..Default::default()
        };
        m.pose.pose = pose_msg(&Isometry3::translation(x, 0.0, 0.0));
        m
    }

    #[test]
    fn interpolates_between_messages_and_refuses_far_times() {
        let mut p = PriorTrack::default();
        p.push(&msg(1_000_000_000, 0.0)).unwrap();
        p.push(&msg(1_100_000_000, 1.0)).unwrap();
        let d = p.motion(1.025, 1.075).unwrap();
        assert!((d.translation.vector - Vector3::new(0.5, 0.0, 0.0)).norm() < 1e-9);
        assert!(p.at(2.0).is_none());
        assert!(p.push(&msg(1_050_000_000, 0.0)).is_err());
        let mut bad = msg(1_200_000_000, 0.0);
        bad.pose.pose.orientation.w = 3.0;
        assert!(p.push(&bad).is_err());
    }
}
