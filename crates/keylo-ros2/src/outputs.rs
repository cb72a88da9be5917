//! The messages of one registered frame: odometry, TF, path and the optional debug topics.

use std::collections::VecDeque;

use keylo_core::{FrameFeatures, FrameResult, LidarFrame};
use nalgebra::Isometry3;

use crate::frames::{self, BaseFrame};
use crate::msgs::{self, Header, Time};

/// What the odometry message needs besides the frame's result.
pub struct OdometryParts<'a> {
    pub odom_frame: &'a str,
    pub base_frame: &'a str,
    pub stamp: Time,
    /// The base's pose and stamp (s) of the previous frame, for the twist.
    pub previous: Option<(Isometry3<f64>, f64)>,
    pub base: &'a BaseFrame,
    /// The set-pose correction: published pose = anchor · base pose.
    pub anchor: &'a Isometry3<f64>,
    /// The pose published: `anchor · base.base_pose(r.pose)`.
    pub base_pose: Isometry3<f64>,
    /// The frame's covariance (world frame, keylo's twist order), when it has an estimate.
    pub covariance: Option<[[f64; 6]; 6]>,
    /// Fallback `(position, orientation)` variances.
    pub fallback: (f64, f64),
}

/// `nav_msgs/Odometry` of a frame; the second value says whether the covariance is keylo's
/// own estimate (false: the fixed fallback diagonal).
pub fn odometry(r: &FrameResult, p: &OdometryParts) -> (msgs::Odometry, bool) {
    let base_pose = p.base_pose;
    let estimated = p
        .covariance
        .filter(|c| c.iter().flatten().all(|v| v.is_finite()))
        .map(|c| frames::rotate_covariance(&p.base.pose_covariance(&r.pose, &c), p.anchor));
    let pose_cov =
        estimated.unwrap_or_else(|| frames::diagonal_covariance(p.fallback.0, p.fallback.1));
    let (twist, twist_cov) = match p.previous {
        Some((before, t0)) => {
            let dt = r.stamp - t0;
            (
                frames::twist(&before, &base_pose, dt),
                twist_covariance(&pose_cov, &base_pose, dt),
            )
        }
        None => (msgs::Twist::default(), [0.0; 36]),
    };
    let msg = msgs::Odometry {
        header: Header {
            stamp: p.stamp,
            frame_id: p.odom_frame.to_string(),
        },
        child_frame_id: p.base_frame.to_string(),
        pose: msgs::PoseWithCovariance {
            pose: frames::pose_msg(&base_pose),
            covariance: pose_cov,
        },
        twist: msgs::TwistWithCovariance {
            twist,
            covariance: twist_cov,
        },
    };
    (msg, estimated.is_some())
}

/// The frame's pose covariance (odometry frame) as a rate in the base frame: the
/// registration's uncertainty is that of the motion since the map, spread over `dt`.
fn twist_covariance(pose_cov: &[f64; 36], base_pose: &Isometry3<f64>, dt: f64) -> [f64; 36] {
    if !(dt > 0.0 && dt.is_finite()) {
        return [0.0; 36];
    }
    let mut out = frames::rotate_covariance(pose_cov, &base_pose.inverse());
    out.iter_mut().for_each(|v| *v /= dt * dt);
    out
}

/// The `/tf` message: `odom → base`, or `base → odom` when `invert`.
pub fn tf(odom: &msgs::Odometry, base_pose: &Isometry3<f64>, invert: bool) -> msgs::TfMessage {
    let (parent, child, t) = if invert {
        (
            odom.child_frame_id.clone(),
            odom.header.frame_id.clone(),
            base_pose.inverse(),
        )
    } else {
        (
            odom.header.frame_id.clone(),
            odom.child_frame_id.clone(),
            *base_pose,
        )
    };
    msgs::TfMessage {
        transforms: vec![msgs::TransformStamped {
            header: Header {
                stamp: odom.header.stamp,
                frame_id: parent,
            },
            child_frame_id: child,
            transform: frames::transform_msg(&t),
        }],
    }
}

/// The path so far, keeping at most `max` poses (0: all).
pub struct PathKeeper {
    poses: VecDeque<msgs::PoseStamped>,
    max: usize,
}

impl PathKeeper {
    pub fn new(max: usize) -> Self {
        Self {
            poses: VecDeque::new(),
            max,
        }
    }

    /// Adds the odometry's pose and returns the path message.
    pub fn push(&mut self, odom: &msgs::Odometry) -> msgs::Path {
        self.poses.push_back(msgs::PoseStamped {
            header: odom.header.clone(),
            pose: odom.pose.pose,
        });
        while self.max > 0 && self.poses.len() > self.max {
            self.poses.pop_front();
        }
        msgs::Path {
            header: odom.header.clone(),
            poses: self.poses.iter().cloned().collect(),
        }
    }

    pub fn clear(&mut self) {
        self.poses.clear();
    }
}

/// A cloud of points (f64) as an `x y z` PointCloud2 in `frame`.
pub fn cloud(
    points: impl Iterator<Item = nalgebra::Point3<f64>>,
    stamp: Time,
    frame: &str,
) -> msgs::PointCloud2 {
    let pts: Vec<[f32; 3]> = points
        .map(|p| [p.x as f32, p.y as f32, p.z as f32])
        .collect();
    msgs::PointCloud2::xyz(
        Header {
            stamp,
            frame_id: frame.to_string(),
        },
        &pts,
        &[],
    )
}

/// The 3-D points of every keypoint found (sensor frame).
pub fn keypoint_points(frame: &LidarFrame, features: &FrameFeatures) -> Vec<nalgebra::Point3<f64>> {
    features
        .per_image
        .iter()
        .flat_map(|c| keylo_core::keypoint_points(frame, c))
        .flatten()
        .collect()
}

/// The first LiDAR image (its first plane, grey) with its keypoints marked red, as `rgb8`.
pub fn keypoint_image(features: &FrameFeatures, stamp: Time, frame: &str) -> Option<msgs::Image> {
    let c = features.per_image.first()?;
    let img = &c.image;
    let (w, h) = (img.width, img.height);
    let mut data = vec![0u8; w * h * 3];
    for y in 0..h {
        for x in 0..w {
            let v = img
                .data
                .get(y * img.stride + x * img.channels.max(1))
                .copied()
                .unwrap_or(0);
            data[(y * w + x) * 3..][..3].copy_from_slice(&[v, v, v]);
        }
    }
    for kp in &c.keypoints {
        let (cx, cy) = (kp.x.round() as i64, kp.y.round() as i64);
        for (dx, dy) in [(0, 0), (-1, 0), (1, 0), (0, -1), (0, 1)] {
            let (x, y) = (cx + dx, cy + dy);
            if x >= 0 && y >= 0 && (x as usize) < w && (y as usize) < h {
                let i = (y as usize * w + x as usize) * 3;
                data[i..i + 3].copy_from_slice(&[255, 0, 0]);
            }
        }
    }
    Some(msgs::Image {
        header: Header {
            stamp,
            frame_id: frame.to_string(),
        },
        height: h as u32,
        width: w as u32,
        encoding: "rgb8".into(),
        is_bigendian: 0,
        step: (w * 3) as u32,
        data,
    })
}
