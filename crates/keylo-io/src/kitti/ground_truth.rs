//! KITTI poses (cam0 frame) as ground truth of the LiDAR: `T_velo = inv(Tr) · T_cam · Tr`.

use std::path::Path;

use keylo_core::{Pose, Trajectory};

use super::side_files::trajectory_error;
use crate::IoError;

/// Reads the KITTI pose file `path` (3×4 per line, cam0 frame, one pose per scan) and
/// returns the LiDAR poses stamped with `stamps`; the error names the line or the counts.
pub fn lidar_ground_truth(path: &Path, tr: &Pose, stamps: &[f64]) -> Result<Trajectory, IoError> {
    let text = std::fs::read_to_string(path).map_err(|e| IoError::io(path, e))?;
    let label = path.display().to_string();
    let cam = crate::trajectory::parse_kitti(&text, &label)
        .map_err(|e| trajectory_error(path, &label, &e))?;
    if cam.len() != stamps.len() {
        return Err(IoError::format(
            path,
            format!(
                "{} poses for {} scans; expected one pose per scan",
                cam.len(),
                stamps.len()
            ),
        ));
    }
    let mut out = Trajectory::default();
    for (pose, &t) in cam.poses.iter().zip(stamps) {
        out.push(t, cam_to_lidar(pose, tr));
    }
    Ok(out)
}

/// `inv(Tr) · T_cam · Tr`: a cam0 pose as the pose of the LiDAR (`Tr`: Velodyne → cam0).
pub fn cam_to_lidar(cam: &Pose, tr: &Pose) -> Pose {
    tr.inverse() * cam * tr
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Translation3, UnitQuaternion, Vector3};

    #[test]
    fn conjugation_moves_the_motion_into_the_lidar_frame() {
        // Velodyne x forward = cam0 z forward: Tr maps (x, y, z)_velo to (-y, -z, x)_cam.
        let r = UnitQuaternion::from_basis_unchecked(&[
            Vector3::new(0.0, 0.0, 1.0),
            Vector3::new(-1.0, 0.0, 0.0),
            Vector3::new(0.0, -1.0, 0.0),
        ]);
        let tr = Pose::from_parts(Translation3::new(0.0, -0.1, -0.3), r);
        let cam = Pose::from_parts(Translation3::new(0.0, 0.0, 2.0), UnitQuaternion::identity());
        let velo = cam_to_lidar(&cam, &tr);
        assert!((velo.translation.vector - Vector3::new(2.0, 0.0, 0.0)).norm() < 1e-12);
        assert!(velo.rotation.angle() < 1e-12);
    }
}
