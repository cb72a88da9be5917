//! Rigid transforms at the edges: checking that a [`Pose`] handed in is rigid, and the
//! row-major 4x4 matrices of the C API and the plugin ABI.

use crate::{CoreError, Pose};

/// Whether every value of `t` (translation and rotation quaternion) is finite.
pub fn is_finite(t: &Pose) -> bool {
    t.translation
        .vector
        .iter()
        .chain(t.rotation.coords.iter())
        .all(|v| v.is_finite())
}

/// Refuses a transform with a non-finite value or a rotation quaternion off unit length (it
/// would not be rigid); the error names `what`.
pub fn check_rigid(t: &Pose, what: &str) -> Result<(), CoreError> {
    let norm = t.rotation.coords.norm();
    if !is_finite(t) || (norm - 1.0).abs() > 1e-6 {
        return Err(CoreError::stage(
            "registrar",
            format!(
                "{what}: not a rigid transform (translation {:?}, quaternion norm {norm}); \
                 expected finite values and a unit quaternion",
                t.translation.vector.as_slice()
            ),
        ));
    }
    Ok(())
}

/// Why a row-major 4x4 matrix is not a rigid transform.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum RigidError {
    #[error("a non-finite entry")]
    NonFinite,
    #[error("the last row is not 0 0 0 1")]
    LastRow,
    #[error("the 3x3 part is not a rotation")]
    NotRotation,
}

/// A row-major 4x4 rigid transform as a pose; the error says why `m` is not one
/// (a non-finite entry, a last row other than `0 0 0 1`, or a 3x3 part that is not a rotation
/// within 1e-6).
///
/// ```
/// use keylo_core::rigid::{pose_from_matrix, pose_to_matrix};
/// let pose = keylo_core::Pose::translation(1.0, 2.0, 3.0);
/// assert_eq!(pose_from_matrix(&pose_to_matrix(&pose)).unwrap(), pose);
/// let mut scaled = pose_to_matrix(&pose);
/// scaled[0] = 2.0;
/// assert_eq!(pose_from_matrix(&scaled), Err(keylo_core::rigid::RigidError::NotRotation));
/// ```
pub fn pose_from_matrix(m: &[f64; 16]) -> Result<Pose, RigidError> {
    if !m.iter().all(|v| v.is_finite()) {
        return Err(RigidError::NonFinite);
    }
    if m[12..] != [0.0, 0.0, 0.0, 1.0] {
        return Err(RigidError::LastRow);
    }
    let r = nalgebra::Matrix3::new(m[0], m[1], m[2], m[4], m[5], m[6], m[8], m[9], m[10]);
    let off = (r.transpose() * r - nalgebra::Matrix3::identity())
        .abs()
        .max();
    if off > 1e-6 || r.determinant() < 0.0 {
        return Err(RigidError::NotRotation);
    }
    let rotation = nalgebra::UnitQuaternion::from_matrix(&r);
    let translation = nalgebra::Translation3::new(m[3], m[7], m[11]);
    Ok(Pose::from_parts(translation, rotation))
}

/// `pose` as a row-major 4x4 matrix.
pub fn pose_to_matrix(pose: &Pose) -> [f64; 16] {
    let h = pose.to_homogeneous();
    std::array::from_fn(|i| h[(i / 4, i % 4)])
}
