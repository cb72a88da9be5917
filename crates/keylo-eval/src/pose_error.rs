//! Pose-error building blocks shared by APE, RPE and drift.

use keylo_core::Pose;
use nalgebra::UnitQuaternion;

/// Which scalar is taken from an error pose (evo's `--pose_relation`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
pub enum PoseRelation {
    /// Norm of the translation part, metres (evo `trans_part`).
    #[default]
    Translation,
    /// Rotation angle of the rotation part, degrees (evo `angle_deg`).
    AngleDeg,
}

impl PoseRelation {
    /// The scalar error of `error_pose` under this relation.
    pub fn of(self, error_pose: &Pose) -> f64 {
        match self {
            Self::Translation => error_pose.translation.vector.norm(),
            Self::AngleDeg => angle_deg(&error_pose.rotation),
        }
    }
}

/// `a⁻¹ · b` (evo `lie.relative_se3`).
pub fn relative(a: &Pose, b: &Pose) -> Pose {
    a.inv_mul(b)
}

/// Rotation angle in degrees, in `[0, 180]`, computed stably as `2·atan2(|v|, |w|)`.
pub fn angle_deg(rotation: &UnitQuaternion<f64>) -> f64 {
    rotation.angle().to_degrees()
}

/// Relative pose error of a pair: `(Qᵢ⁻¹ Qⱼ)⁻¹ (Pᵢ⁻¹ Pⱼ)` with reference `Q` and estimate `P`
/// (evo `RPE.rpe_base`).
pub fn relative_error(q_i: &Pose, q_j: &Pose, p_i: &Pose, p_j: &Pose) -> Pose {
    relative(&relative(q_i, q_j), &relative(p_i, p_j))
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Translation3, Vector3};

    #[test]
    fn identical_motions_have_zero_error() {
        let a = Pose::from_parts(
            Translation3::new(1.0, 2.0, 3.0),
            UnitQuaternion::from_euler_angles(0.1, 0.2, 0.3),
        );
        let b = Pose::from_parts(
            Translation3::new(-1.0, 0.0, 3.0),
            UnitQuaternion::from_euler_angles(0.3, 0.2, 0.1),
        );
        let offset = Pose::from_parts(
            Translation3::new(5.0, 5.0, 5.0),
            UnitQuaternion::from_euler_angles(1.0, 0.0, 0.0),
        );
        let e = relative_error(&a, &b, &(offset * a), &(offset * b));
        assert!(PoseRelation::Translation.of(&e) < 1e-12);
        assert!(PoseRelation::AngleDeg.of(&e) < 1e-9);
    }

    #[test]
    fn angle_of_half_turn() {
        let q = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), std::f64::consts::PI);
        assert!((angle_deg(&q) - 180.0).abs() < 1e-12);
    }
}
