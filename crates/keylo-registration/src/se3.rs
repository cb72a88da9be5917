//! The SE(3) exponential and logarithm (twist order `[ρ, φ]`: translation then rotation, as
//! Sophus uses), which ICP updates and deskewing need.

use nalgebra::{Isometry3, Matrix3, Translation3, UnitQuaternion, Vector3, Vector6};

/// Skew-symmetric matrix of `v`: `hat(v) * w == v.cross(&w)`.
pub fn hat(v: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -v.z, v.y, v.z, 0.0, -v.x, -v.y, v.x, 0.0)
}

/// `exp` of a twist `[ρ, φ]`.
///
/// ```
/// use keylo_registration::se3::{exp, log};
/// use nalgebra::Vector6;
/// let xi = Vector6::new(0.1, -0.2, 0.3, 0.01, 0.02, -0.03);
/// assert!((log(&exp(&xi)) - xi).norm() < 1e-12);
/// ```
pub fn exp(xi: &Vector6<f64>) -> Isometry3<f64> {
    let rho = Vector3::new(xi[0], xi[1], xi[2]);
    let phi = Vector3::new(xi[3], xi[4], xi[5]);
    let rotation = UnitQuaternion::from_scaled_axis(phi);
    let t = left_jacobian(&phi) * rho;
    Isometry3::from_parts(Translation3::from(t), rotation)
}

/// `log` of a pose, as a twist `[ρ, φ]`.
pub fn log(pose: &Isometry3<f64>) -> Vector6<f64> {
    let phi = pose.rotation.scaled_axis();
    let rho = inverse_left_jacobian(&phi) * pose.translation.vector;
    Vector6::new(rho.x, rho.y, rho.z, phi.x, phi.y, phi.z)
}

/// The SO(3) left Jacobian `V(φ)`, with `t = V ρ`.
fn left_jacobian(phi: &Vector3<f64>) -> Matrix3<f64> {
    let theta2 = phi.norm_squared();
    let w = hat(phi);
    let (a, b) = if theta2 < 1e-10 {
        (0.5 - theta2 / 24.0, 1.0 / 6.0 - theta2 / 120.0)
    } else {
        let theta = theta2.sqrt();
        (
            (1.0 - theta.cos()) / theta2,
            (theta - theta.sin()) / (theta2 * theta),
        )
    };
    Matrix3::identity() + w * a + w * w * b
}

fn inverse_left_jacobian(phi: &Vector3<f64>) -> Matrix3<f64> {
    let theta2 = phi.norm_squared();
    let w = hat(phi);
    let c = if theta2 < 1e-10 {
        1.0 / 12.0 + theta2 / 720.0
    } else {
        let theta = theta2.sqrt();
        (1.0 - theta * theta.sin() / (2.0 * (1.0 - theta.cos()))) / theta2
    };
    Matrix3::identity() - w * 0.5 + w * w * c
}

/// Rotation angle of a pose, radians in `[0, π]`.
pub fn angle(pose: &Isometry3<f64>) -> f64 {
    pose.rotation.angle()
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn twist() -> impl Strategy<Value = Vector6<f64>> {
        (
            -5.0..5.0f64,
            -5.0..5.0f64,
            -5.0..5.0f64,
            -3.0..3.0f64,
            -3.0..3.0f64,
            -3.0..3.0f64,
        )
            .prop_map(|(a, b, c, d, e, f)| Vector6::new(a, b, c, d, e, f))
    }

    proptest! {
        #[test]
        fn log_inverts_exp(xi in twist()) {
            prop_assume!(Vector3::new(xi[3], xi[4], xi[5]).norm() < 3.1);
            prop_assert!((log(&exp(&xi)) - xi).norm() < 1e-9);
        }

        #[test]
        fn exp_of_scaled_twist_is_a_one_parameter_group(xi in twist(), s in 0.0..1.0f64) {
            let a = exp(&(xi * s));
            let b = exp(&(xi * (1.0 - s)));
            let whole = exp(&xi);
            prop_assert!(((a * b).to_homogeneous() - whole.to_homogeneous()).norm() < 1e-9);
        }

        #[test]
        fn hat_is_the_cross_product(a in twist(), b in twist()) {
            let (u, v) = (Vector3::new(a[0], a[1], a[2]), Vector3::new(b[0], b[1], b[2]));
            prop_assert!((hat(&u) * v - u.cross(&v)).norm() < 1e-12);
        }
    }

    #[test]
    fn small_angles_are_stable() {
        let xi = Vector6::new(1.0, 2.0, 3.0, 1e-9, 0.0, 0.0);
        let pose = exp(&xi);
        assert!((pose.translation.vector - Vector3::new(1.0, 2.0, 3.0)).norm() < 1e-8);
        assert!((log(&pose) - xi).norm() < 1e-12);
    }
}
