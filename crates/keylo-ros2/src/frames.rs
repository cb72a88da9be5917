//! From keylo's LiDAR poses to ROS's frames: the base pose in the odometry frame, its
//! covariance in ROS order and the twist of the last motion.
//!
//! keylo's pose `T_l` is the LiDAR's in the frame of the first scan. With the LiDAR at
//! `A = base_to_lidar` on the base, the base's pose in the odometry frame is
//! `A · T_l · A⁻¹`: the odometry frame is the base's at the first scan (KISS-ICP's node does
//! the same).

use nalgebra::{Isometry3, Matrix3, Matrix6, Quaternion, Translation3, UnitQuaternion, Vector3};

use crate::msgs;

/// The extrinsic `[x, y, z, qx, qy, qz, qw]` as an isometry; the quaternion must be unit
/// length within 1e-6 (so a typo is not silently normalised away).
pub fn extrinsic(v: &[f64]) -> Result<Isometry3<f64>, String> {
    let [x, y, z, qx, qy, qz, qw] = <[f64; 7]>::try_from(v).map_err(|_| {
        format!(
            "ros2.base_to_lidar has {} numbers; expected 7: x y z qx qy qz qw",
            v.len()
        )
    })?;
    if v.iter().any(|a| !a.is_finite()) {
        return Err("ros2.base_to_lidar holds a number that is not finite".into());
    }
    let q = Quaternion::new(qw, qx, qy, qz);
    if (q.norm() - 1.0).abs() > 1e-6 {
        return Err(format!(
            "ros2.base_to_lidar's quaternion has norm {}; expected a unit quaternion",
            q.norm()
        ));
    }
    Ok(Isometry3::from_parts(
        Translation3::new(x, y, z),
        UnitQuaternion::new_normalize(q),
    ))
}

/// A pose as a ROS message.
pub fn pose_msg(p: &Isometry3<f64>) -> msgs::Pose {
    let t = p.translation.vector;
    let q = p.rotation.quaternion();
    msgs::Pose {
        position: msgs::Point {
            x: t.x,
            y: t.y,
            z: t.z,
        },
        orientation: msgs::Quaternion {
            x: q.i,
            y: q.j,
            z: q.k,
            w: q.w,
        },
    }
}

/// A ROS pose as an isometry; `None` when it is not finite or its quaternion is not unit
/// length within 1e-3 (not a rigid transform).
pub fn pose_from_msg(p: &msgs::Pose) -> Option<Isometry3<f64>> {
    let o = p.orientation;
    let q = Quaternion::new(o.w, o.x, o.y, o.z);
    let t = Vector3::new(p.position.x, p.position.y, p.position.z);
    let finite = t.iter().chain(q.coords.iter()).all(|v| v.is_finite());
    if !finite || (q.norm() - 1.0).abs() > 1e-3 {
        return None;
    }
    Some(Isometry3::from_parts(
        Translation3::from(t),
        UnitQuaternion::new_normalize(q),
    ))
}

/// The transform as a ROS message.
pub fn transform_msg(p: &Isometry3<f64>) -> msgs::Transform {
    let pose = pose_msg(p);
    msgs::Transform {
        translation: msgs::Vector3 {
            x: pose.position.x,
            y: pose.position.y,
            z: pose.position.z,
        },
        rotation: pose.orientation,
    }
}

/// Converts between the LiDAR's poses (keylo) and the base's (ROS).
#[derive(Debug, Clone, Copy)]
pub struct BaseFrame {
    /// `base_to_lidar`.
    a: Isometry3<f64>,
}

impl BaseFrame {
    pub fn new(base_to_lidar: Isometry3<f64>) -> Self {
        Self { a: base_to_lidar }
    }

    /// `base_to_lidar`.
    pub fn extrinsic(&self) -> Isometry3<f64> {
        self.a
    }

    /// The base's pose in the odometry frame of the LiDAR pose `lidar`.
    pub fn base_pose(&self, lidar: &Isometry3<f64>) -> Isometry3<f64> {
        self.a * lidar * self.a.inverse()
    }

    /// The LiDAR pose of a base pose (inverse of [`Self::base_pose`]).
    pub fn lidar_pose(&self, base: &Isometry3<f64>) -> Isometry3<f64> {
        self.a.inverse() * base * self.a
    }

    /// keylo's covariance of the LiDAR pose `lidar` (twist `[ρ, φ]`: world-axis translation
    /// of the LiDAR and world-axis rotation about it, as [`keylo_core::Degeneracy`] defines
    /// it) as the covariance of the base pose in ROS order (x, y, z, rotation about the
    /// odometry frame's X, Y, Z), row-major.
    pub fn pose_covariance(&self, lidar: &Isometry3<f64>, c: &[[f64; 6]; 6]) -> [f64; 36] {
        // The base origin moves by ρ + φ × (q − c): q the base origin, c the LiDAR, both in
        // the first scan's frame; then both blocks turn into the odometry frame by A's rotation.
        let lever = lidar.rotation * self.a.inverse().translation.vector;
        let mut j = Matrix6::<f64>::identity();
        j.fixed_view_mut::<3, 3>(0, 3).copy_from(&(-skew(&lever)));
        let j = rotation6(&self.a) * j;
        let cov = Matrix6::from_fn(|i, k| c[i][k]);
        let out = j * cov * j.transpose();
        row_major(&out)
    }
}

/// A pose covariance (ROS order, row-major) of a pose `P` as the covariance of `C · P`: both
/// blocks turn with `C`'s rotation (its translation moves nothing uncertain).
pub fn rotate_covariance(cov: &[f64; 36], c: &Isometry3<f64>) -> [f64; 36] {
    let j = rotation6(c);
    row_major(&(j * Matrix6::from_row_slice(cov) * j.transpose()))
}

/// `blockdiag(R, R)` of `c`'s rotation: turns both blocks of a (position, rotation) vector.
fn rotation6(c: &Isometry3<f64>) -> Matrix6<f64> {
    let r = c.rotation.to_rotation_matrix().into_inner();
    let mut j = Matrix6::<f64>::zeros();
    j.fixed_view_mut::<3, 3>(0, 0).copy_from(&r);
    j.fixed_view_mut::<3, 3>(3, 3).copy_from(&r);
    j
}

/// The fixed diagonal of KISS-ICP's node: position variance on x y z, orientation on the rest.
pub fn diagonal_covariance(position: f64, orientation: f64) -> [f64; 36] {
    let mut out = [0.0; 36];
    for i in 0..6 {
        out[i * 7] = if i < 3 { position } else { orientation };
    }
    out
}

/// The twist (in the base frame, as `nav_msgs/Odometry` wants it) of the motion from pose
/// `before` to pose `after` over `dt` seconds; zero when `dt` is not positive.
pub fn twist(before: &Isometry3<f64>, after: &Isometry3<f64>, dt: f64) -> msgs::Twist {
    if !(dt > 0.0 && dt.is_finite()) {
        return msgs::Twist::default();
    }
    let delta = before.inverse() * after;
    let v = delta.translation.vector / dt;
    let w = delta.rotation.scaled_axis() / dt;
    msgs::Twist {
        linear: msgs::Vector3 {
            x: v.x,
            y: v.y,
            z: v.z,
        },
        angular: msgs::Vector3 {
            x: w.x,
            y: w.y,
            z: w.z,
        },
    }
}

fn skew(v: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -v.z, v.y, v.z, 0.0, -v.x, -v.y, v.x, 0.0)
}

fn row_major(m: &Matrix6<f64>) -> [f64; 36] {
    let mut out = [0.0; 36];
    for i in 0..6 {
        for k in 0..6 {
            out[i * 6 + k] = m[(i, k)];
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Point3;

    fn iso(t: [f64; 3], axis_angle: [f64; 3]) -> Isometry3<f64> {
        Isometry3::new(Vector3::from(t), Vector3::from(axis_angle))
    }

    #[test]
    fn base_pose_starts_at_identity_and_follows_the_lidar() {
        let a = iso([0.5, 0.0, 1.2], [0.0, 0.0, 0.3]);
        let f = BaseFrame::new(a);
        let id = f.base_pose(&Isometry3::identity());
        assert!(
            (id.to_homogeneous() - Isometry3::<f64>::identity().to_homogeneous()).norm() < 1e-12
        );
        let l = iso([1.0, 2.0, 0.1], [0.01, -0.02, 0.5]);
        let back = f.lidar_pose(&f.base_pose(&l));
        assert!((back.to_homogeneous() - l.to_homogeneous()).norm() < 1e-12);
        // The base moved as the LiDAR moved, seen through the mounting.
        let b = f.base_pose(&l);
        let lidar_in_odom = b * a * Point3::origin();
        let expected = a * (l * Point3::origin());
        assert!((lidar_in_odom - expected).norm() < 1e-12);
    }

    /// The covariance mapping agrees with pushing sampled perturbations through the frames.
    #[test]
    fn covariance_matches_perturbed_poses() {
        let a = iso([0.3, -0.2, 0.9], [0.1, 0.0, 0.7]);
        let f = BaseFrame::new(a);
        let l = iso([4.0, -3.0, 0.5], [0.0, 0.05, 1.2]);
        // One perturbation direction at a time: J's columns from finite differences.
        let eps = 1e-6;
        let base = f.base_pose(&l);
        for k in 0..6 {
            let mut xi = [0.0; 6];
            xi[k] = eps;
            // keylo's convention: world-axis rotation about the LiDAR, then translation.
            let rot = UnitQuaternion::from_scaled_axis(Vector3::new(xi[3], xi[4], xi[5]));
            let c = l.translation.vector;
            let moved = Isometry3::from_parts(
                Translation3::from(c + Vector3::new(xi[0], xi[1], xi[2])),
                rot * l.rotation,
            );
            let b2 = f.base_pose(&moved);
            let dp = (b2.translation.vector - base.translation.vector) / eps;
            let dr = (b2.rotation * base.rotation.inverse()).scaled_axis() / eps;
            let mut c6 = [[0.0; 6]; 6];
            c6[k][k] = 1.0;
            let cov = f.pose_covariance(&l, &c6);
            // cov = J e_k e_kᵀ Jᵀ: its diagonal is the squared column of J.
            let col = [dp.x, dp.y, dp.z, dr.x, dr.y, dr.z];
            for i in 0..6 {
                assert!(
                    (cov[i * 7] - col[i] * col[i]).abs() < 1e-6,
                    "k {k} i {i}: {} vs {}",
                    cov[i * 7],
                    col[i] * col[i]
                );
            }
        }
    }

    #[test]
    fn twist_is_in_the_body_frame() {
        let before = iso([1.0, 0.0, 0.0], [0.0, 0.0, std::f64::consts::FRAC_PI_2]);
        // One metre forward along the body x axis (world y) and 0.1 rad of yaw in 0.1 s.
        let after = before * iso([1.0, 0.0, 0.0], [0.0, 0.0, 0.1]);
        let t = twist(&before, &after, 0.1);
        assert!((t.linear.x - 10.0).abs() < 1e-9 && t.linear.y.abs() < 1e-9);
        assert!((t.angular.z - 1.0).abs() < 1e-9);
        assert_eq!(twist(&before, &after, 0.0), msgs::Twist::default());
    }

    #[test]
    fn extrinsics_are_checked() {
        assert!(extrinsic(&[0.0; 6]).is_err());
        assert!(extrinsic(&[0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.5]).is_err());
        let a = extrinsic(&[1.0, 2.0, 3.0, 0.0, 0.0, 0.0, 1.0]).unwrap();
        assert_eq!(a.translation.vector, Vector3::new(1.0, 2.0, 3.0));
        assert!(pose_from_msg(&pose_msg(&a)).is_some());
        let mut bad = pose_msg(&a);
        bad.orientation.w = 0.0;
        assert!(pose_from_msg(&bad).is_none());
    }
}
