//! Turning file numbers into rotations: quaternion normalisation and robust
//! re-orthonormalisation of 3x3 matrices.

use nalgebra::{Matrix3, Quaternion, Rotation3, UnitQuaternion};

/// Quaternions with a norm below this cannot be normalised.
const MIN_QUATERNION_NORM: f64 = 1e-9;

/// Largest accepted ‖MᵀM − I‖_F for a matrix read as a rotation.
const MAX_ORTHOGONALITY_DEFECT: f64 = 1e-2;

/// Normalised quaternion from TUM order `qx qy qz qw`; `Err(norm)` when the norm is ~0.
pub(crate) fn quaternion_xyzw(q: [f64; 4]) -> Result<UnitQuaternion<f64>, f64> {
    let raw = Quaternion::new(q[3], q[0], q[1], q[2]);
    let norm = raw.norm();
    if norm.is_finite() && norm > MIN_QUATERNION_NORM {
        Ok(UnitQuaternion::new_normalize(raw))
    } else {
        Err(norm)
    }
}

/// The rotation nearest to `m` (polar decomposition by SVD, `R = U Vᵀ`).
///
/// Fails with a reason when `m` has a non-positive determinant or is far from orthogonal
/// (‖MᵀM − I‖_F above 1e-2), e.g. because the columns of a file were shuffled.
pub(crate) fn nearest_rotation(m: &Matrix3<f64>) -> Result<UnitQuaternion<f64>, String> {
    let det = m.determinant();
    if det <= 0.0 {
        return Err(format!("determinant {det:.6} is not positive"));
    }
    let defect = (m.transpose() * m - Matrix3::identity()).norm();
    if defect > MAX_ORTHOGONALITY_DEFECT {
        return Err(format!(
            "|R^T R - I| = {defect:.3e} exceeds {MAX_ORTHOGONALITY_DEFECT:e}"
        ));
    }
    let svd = m.svd(true, true);
    let (Some(u), Some(v_t)) = (svd.u, svd.v_t) else {
        return Err("SVD did not converge".to_string());
    };
    let r = Rotation3::from_matrix_unchecked(u * v_t);
    Ok(UnitQuaternion::from_rotation_matrix(&r))
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn normalises_scaled_quaternion() {
        let q = quaternion_xyzw([0.0, 0.0, 2.0, 2.0]).unwrap();
        assert_relative_eq!(q.angle(), std::f64::consts::FRAC_PI_2, epsilon = 1e-12);
    }

    #[test]
    fn rejects_zero_quaternion() {
        assert_eq!(quaternion_xyzw([0.0; 4]), Err(0.0));
    }

    #[test]
    fn cleans_slightly_perturbed_rotation() {
        let truth = UnitQuaternion::from_euler_angles(0.3, -0.2, 2.9);
        let mut m = *truth.to_rotation_matrix().matrix();
        m[(0, 1)] += 1e-6;
        m[(2, 2)] -= 2e-6;
        let r = nearest_rotation(&m).unwrap();
        assert!(r.angle_to(&truth) < 1e-5);
        let rm = r.to_rotation_matrix();
        let defect = (rm.matrix().transpose() * rm.matrix() - Matrix3::identity()).norm();
        assert!(defect < 1e-12);
    }

    #[test]
    fn rejects_reflection_and_scaled_matrix() {
        let reflection = Matrix3::from_diagonal(&nalgebra::Vector3::new(1.0, 1.0, -1.0));
        assert!(nearest_rotation(&reflection)
            .unwrap_err()
            .contains("determinant"));
        assert!(nearest_rotation(&(Matrix3::identity() * 2.0)).is_err());
    }
}
