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
    let rotation = nalgebra::UnitQuaternion::from_rotation_matrix(&nearest_rotation(r));
    let translation = nalgebra::Translation3::new(m[3], m[7], m[11]);
    Ok(Pose::from_parts(translation, rotation))
}

/// The rotation nearest to `r` (the orthogonal factor of its polar decomposition), for an `r`
/// already within 1e-6 of one: Newton's iteration `(R + R^-T) / 2`, which converges
/// quadratically, to machine precision in two or three steps. (nalgebra's `from_matrix` iterates
/// from the identity, dozens of steps for a large rotation, and ends within about 1e-8 rad.)
fn nearest_rotation(r: nalgebra::Matrix3<f64>) -> nalgebra::Rotation3<f64> {
    let mut x = r;
    for _ in 0..8 {
        let Some(inverse) = x.try_inverse() else {
            break;
        };
        let next = (x + inverse.transpose()) * 0.5;
        let step = (next - x).abs().max();
        x = next;
        if step < 1e-15 {
            break;
        }
    }
    nalgebra::Rotation3::from_matrix_unchecked(x)
}

/// `pose` as a row-major 4x4 matrix.
pub fn pose_to_matrix(pose: &Pose) -> [f64; 16] {
    let h = pose.to_homogeneous();
    std::array::from_fn(|i| h[(i / 4, i % 4)])
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        /// The rotation is the nearest one, as an SVD gives it (`U V^T`), to 1e-12 rad for any
        /// rotation (at pi included) off by up to the accepted 1e-6, and the exact one to
        /// 1e-15 rad for an exact rotation.
        #[test]
        fn the_rotation_is_the_nearest_one(
            axis in (-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0),
            angle in prop_oneof![-std::f64::consts::PI..std::f64::consts::PI,
                                 Just(std::f64::consts::PI)],
            noise in proptest::array::uniform9(-3e-7f64..3e-7),
            exact in any::<bool>(),
        ) {
            let axis = nalgebra::Vector3::new(axis.0, axis.1, axis.2);
            prop_assume!(axis.norm() > 1e-3);
            let q = nalgebra::UnitQuaternion::from_axis_angle(
                &nalgebra::Unit::new_normalize(axis), angle);
            let mut r = *q.to_rotation_matrix().matrix();
            if !exact {
                for (v, e) in r.iter_mut().zip(noise) {
                    *v += e;
                }
            }
            let m = [r[(0, 0)], r[(0, 1)], r[(0, 2)], 0.5,
                     r[(1, 0)], r[(1, 1)], r[(1, 2)], -1.5,
                     r[(2, 0)], r[(2, 1)], r[(2, 2)], 2.5,
                     0.0, 0.0, 0.0, 1.0];
            let ours = pose_from_matrix(&m).unwrap();
            prop_assert_eq!(ours.translation.vector, nalgebra::Vector3::new(0.5, -1.5, 2.5));
            if exact {
                prop_assert!(ours.rotation.angle_to(&q) < 1e-15);
            } else {
                let svd = r.svd(true, true);
                let (u, v_t) = (svd.u.unwrap(), svd.v_t.unwrap());
                let nearest = nalgebra::UnitQuaternion::from_rotation_matrix(
                    &nalgebra::Rotation3::from_matrix_unchecked(u * v_t));
                prop_assert!(ours.rotation.angle_to(&nearest) < 1e-12,
                             "{} rad from the SVD's", ours.rotation.angle_to(&nearest));
            }
        }
    }
}
