//! PCL's NDT pose vector `p = [x, y, z, roll, pitch, yaw]` with `R = Rx(roll)·Ry(pitch)·Rz(yaw)`,
//! and the first and second derivatives of `R` that the score's Jacobian and Hessian need
//! (Magnusson 2009, eq. 6.17–6.21).

use nalgebra::{Isometry3, Matrix3, Rotation3, Translation3, UnitQuaternion, Vector3, Vector6};

/// The pose of a parameter vector.
pub fn pose_of(p: &Vector6<f64>) -> Isometry3<f64> {
    let r = rot_x(p[3]) * rot_y(p[4]) * rot_z(p[5]);
    Isometry3::from_parts(
        Translation3::new(p[0], p[1], p[2]),
        UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(r)),
    )
}

/// The parameter vector of a pose, with Eigen's `eulerAngles(0, 1, 2)` ranges as PCL takes
/// its initial guess (roll in [0, π]: a guess with a small negative roll starts from
/// roll ≈ π, pitch ≈ π, yaw ≈ π, the same rotation).
pub fn params_of(pose: &Isometry3<f64>) -> Vector6<f64> {
    let m = pose.rotation.to_rotation_matrix().into_inner();
    let t = pose.translation.vector;
    let mut a0 = m[(1, 2)].atan2(m[(2, 2)]);
    let c2 = m[(0, 0)].hypot(m[(0, 1)]);
    let a1 = if a0 > 0.0 {
        a0 -= std::f64::consts::PI;
        (-m[(0, 2)]).atan2(-c2)
    } else {
        (-m[(0, 2)]).atan2(c2)
    };
    let (s1, c1) = a0.sin_cos();
    let a2 = (s1 * m[(2, 0)] - c1 * m[(1, 0)]).atan2(c1 * m[(1, 1)] - s1 * m[(2, 1)]);
    Vector6::new(t.x, t.y, t.z, -a0, -a1, -a2)
}

fn rot_x(a: f64) -> Matrix3<f64> {
    let (s, c) = a.sin_cos();
    Matrix3::new(1.0, 0.0, 0.0, 0.0, c, -s, 0.0, s, c)
}

fn rot_y(a: f64) -> Matrix3<f64> {
    let (s, c) = a.sin_cos();
    Matrix3::new(c, 0.0, s, 0.0, 1.0, 0.0, -s, 0.0, c)
}

fn rot_z(a: f64) -> Matrix3<f64> {
    let (s, c) = a.sin_cos();
    Matrix3::new(c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0)
}

/// `[R, R', R'']` of one axis rotation from its cosine and sine.
fn axis_terms(axis: usize, c: f64, s: f64) -> [Matrix3<f64>; 3] {
    // In the plane of the two other axes the rotation is [[c, -s], [s, c]]; its derivatives
    // are [[-s, -c], [c, -s]] and [[-c, s], [-s, -c]]. The fixed axis has 1, 0, 0.
    let (u, v) = match axis {
        0 => (1, 2),
        1 => (2, 0),
        _ => (0, 1),
    };
    let plane = |a: f64, b: f64, fixed: f64| {
        let mut m = Matrix3::zeros();
        m[(axis, axis)] = fixed;
        m[(u, u)] = a;
        m[(u, v)] = -b;
        m[(v, u)] = b;
        m[(v, v)] = a;
        m
    };
    [plane(c, s, 1.0), plane(-s, c, 0.0), plane(-c, -s, 0.0)]
}

/// `dR/dθᵢ` and `d²R/dθᵢdθⱼ` at one parameter vector (θ = roll, pitch, yaw).
pub struct RotationDerivatives {
    /// First derivatives.
    pub first: [Matrix3<f64>; 3],
    /// Second derivatives, symmetric in (i, j).
    pub second: [[Matrix3<f64>; 3]; 3],
}

impl RotationDerivatives {
    /// The derivatives at `p`. As PCL does, an angle with |θ| < 1e-4 is taken as exactly 0
    /// (cos 1, sin 0) here; the pose itself always uses the exact angle.
    pub fn at(p: &Vector6<f64>) -> Self {
        let terms: [[Matrix3<f64>; 3]; 3] = std::array::from_fn(|axis| {
            let a = p[3 + axis];
            let (s, c) = if a.abs() < 1e-4 {
                (0.0, 1.0)
            } else {
                a.sin_cos()
            };
            axis_terms(axis, c, s)
        });
        // Order of derivatives of each factor for ∂/∂θᵢ (and ∂²/∂θᵢ∂θⱼ) of Rx·Ry·Rz.
        let product =
            |orders: [usize; 3]| terms[0][orders[0]] * terms[1][orders[1]] * terms[2][orders[2]];
        let first = std::array::from_fn(|i| {
            let mut o = [0; 3];
            o[i] = 1;
            product(o)
        });
        let second = std::array::from_fn(|i| {
            std::array::from_fn(|j| {
                let mut o = [0; 3];
                o[i] += 1;
                o[j] += 1;
                product(o)
            })
        });
        Self { first, second }
    }

    /// The rotation part of the point Jacobian `∂(R x)/∂θᵢ` for source point `x`.
    #[inline]
    pub fn jacobian_columns(&self, x: &Vector3<f64>) -> [Vector3<f64>; 3] {
        [self.first[0] * x, self.first[1] * x, self.first[2] * x]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn params_round_trip_and_roll_is_in_zero_pi() {
        for p in [
            Vector6::new(1.0, -2.0, 0.5, 0.1, -0.2, 0.3),
            Vector6::new(0.0, 0.0, 0.0, -0.01, 0.02, -0.03),
            Vector6::new(0.3, 0.2, 0.1, 2.0, 0.4, -1.0),
        ] {
            let pose = pose_of(&p);
            let q = params_of(&pose);
            assert!((0.0..=std::f64::consts::PI).contains(&q[3]), "{q}");
            let back = pose_of(&q);
            assert!((back.to_homogeneous() - pose.to_homogeneous()).norm() < 1e-12);
        }
        // Eigen's convention: a small negative roll becomes roll ≈ π.
        let q = params_of(&pose_of(&Vector6::new(0.0, 0.0, 0.0, -0.01, 0.0, 0.0)));
        assert!((q[3] - (std::f64::consts::PI - 0.01)).abs() < 1e-12, "{q}");
    }

    #[test]
    fn derivatives_match_finite_differences() {
        let p = Vector6::new(0.0, 0.0, 0.0, 0.3, -0.4, 0.7);
        let d = RotationDerivatives::at(&p);
        let r = |q: &Vector6<f64>| pose_of(q).rotation.to_rotation_matrix().into_inner();
        let h = 1e-5;
        for i in 0..3 {
            let mut a = p;
            let mut b = p;
            a[3 + i] += h;
            b[3 + i] -= h;
            let fd = (r(&a) - r(&b)) / (2.0 * h);
            assert!((fd - d.first[i]).norm() < 1e-8, "first {i}");
            for j in 0..3 {
                let f = |q: &Vector6<f64>| RotationDerivatives::at(q).first[j];
                let fd2 = (f(&a) - f(&b)) / (2.0 * h);
                assert!((fd2 - d.second[i][j]).norm() < 1e-8, "second {i} {j}");
            }
        }
    }
}
