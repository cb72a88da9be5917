//! KITTI's vertical-angle correction, as KISS-ICP's `--dataloader kitti` applies it (after
//! IMLS-SLAM and CT-ICP): every point is rotated up by a fixed angle about the horizontal
//! axis perpendicular to it, `p × ẑ`, which undoes a bias in KITTI's HDL-64E calibration.

/// The angle KISS-ICP's KITTI loader uses, degrees.
pub const KISS_ICP_KITTI_DEG: f64 = 0.205;

/// A rotation of every point by `angle` about `normalize(p × ẑ)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VerticalAngleCorrection {
    angle_rad: f64,
}

impl VerticalAngleCorrection {
    /// The correction by `angle_deg` degrees; `None` for 0 (no correction).
    pub fn new(angle_deg: f64) -> Option<Self> {
        (angle_deg != 0.0).then(|| Self {
            angle_rad: angle_deg * std::f64::consts::PI / 180.0,
        })
    }

    /// The corrected point. The arithmetic follows Eigen's `AngleAxisd(angle, axis) * p`
    /// (the rotation matrix first, then the product) so that the result equals KISS-ICP's
    /// to the last bit. A point on the z axis has no such axis: the result is NaN, as
    /// upstream's, and the reader drops it.
    pub fn apply(&self, p: [f64; 3]) -> [f64; 3] {
        // p × (0, 0, 1), with Eigen's operation order.
        let axis = [
            p[1] * 1.0 - p[2] * 0.0,
            p[2] * 0.0 - p[0] * 1.0,
            p[0] * 0.0 - p[1] * 0.0,
        ];
        let norm = (axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]).sqrt();
        let a = [axis[0] / norm, axis[1] / norm, axis[2] / norm];
        let m = rotation_matrix(self.angle_rad, a);
        let mut out = [0.0; 3];
        for (i, o) in out.iter_mut().enumerate() {
            *o = m[i][0] * p[0] + m[i][1] * p[1] + m[i][2] * p[2];
        }
        out
    }
}

/// Eigen's `AngleAxis::toRotationMatrix`.
fn rotation_matrix(angle: f64, a: [f64; 3]) -> [[f64; 3]; 3] {
    let (s, c) = (angle.sin(), angle.cos());
    let sin_axis = [s * a[0], s * a[1], s * a[2]];
    let cos1_axis = [(1.0 - c) * a[0], (1.0 - c) * a[1], (1.0 - c) * a[2]];
    let mut m = [[0.0; 3]; 3];
    let xy = cos1_axis[0] * a[1];
    m[0][1] = xy - sin_axis[2];
    m[1][0] = xy + sin_axis[2];
    let xz = cos1_axis[0] * a[2];
    m[0][2] = xz + sin_axis[1];
    m[2][0] = xz - sin_axis[1];
    let yz = cos1_axis[1] * a[2];
    m[1][2] = yz - sin_axis[0];
    m[2][1] = yz + sin_axis[0];
    for i in 0..3 {
        m[i][i] = cos1_axis[i] * a[i] + c;
    }
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn points_are_lifted_by_the_angle_and_keep_their_range() {
        let c = VerticalAngleCorrection::new(KISS_ICP_KITTI_DEG).unwrap();
        for p in [[10.0, 0.0, 0.0], [-3.0, 4.0, -1.0], [0.5, -20.0, 2.0]] {
            let q = c.apply(p);
            let r = |v: [f64; 3]| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
            assert!((r(q) - r(p)).abs() < 1e-12);
            let elevation = |v: [f64; 3]| (v[2] / r(v)).asin().to_degrees();
            assert!((elevation(q) - elevation(p) - KISS_ICP_KITTI_DEG).abs() < 1e-9);
            // The azimuth does not change.
            assert!((q[1].atan2(q[0]) - p[1].atan2(p[0])).abs() < 1e-12);
        }
        assert!(c.apply([0.0, 0.0, 5.0])[0].is_nan());
        assert!(VerticalAngleCorrection::new(0.0).is_none());
    }
}
