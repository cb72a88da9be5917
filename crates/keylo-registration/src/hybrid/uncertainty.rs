//! How well a keypoint's 3-D point is known. The keypoint's pixel fixes the ray only to about
//! a pixel (angular errors `σ_az` across, `σ_el` up the ray); the point is where that ray hits
//! the surface, so an angular error `d` (perpendicular to the ray `u`, scaled by the range)
//! moves it along the surface by `(I − u nᵀ / (n·u)) d` (`n` the surface normal): little on a
//! wall seen face on, metres along a wall seen at a grazing angle. The range adds `σ_r` along
//! the ray. A pair of points is weighted by the inverse of the sum of both covariances, so
//! such grazing pairs stop dragging the pose along the wall.

use nalgebra::{Matrix3, Point3, Vector3};

use super::plane_terms::normal_at;
use crate::kiss_icp::voxel_map::VoxelHashMap;

/// A pair whose summed covariance is `σ₀² I` has information `I` (as one cloud residual).
pub const REFERENCE_SIGMA: f64 = 0.05;
/// `|n·u|` at most this small: a ray nearly along the surface.
const MIN_INCIDENCE_COS: f64 = 0.05;

/// The angular and range noise of keypoint points.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointNoise {
    /// Across the ray, horizontally (rad).
    pub azimuth: f64,
    /// Across the ray, vertically (rad).
    pub elevation: f64,
    /// Along the ray (m).
    pub range: f64,
}

/// Covariance of the point `p` seen from `origin` on a surface of normal `normal` (all in one
/// frame whose z is up); without a normal, the angular error stays perpendicular to the ray.
pub fn point_covariance(
    p: &Point3<f64>,
    origin: &Vector3<f64>,
    normal: Option<Vector3<f64>>,
    noise: &PointNoise,
) -> Matrix3<f64> {
    let ray = p.coords - origin;
    let r = ray.norm();
    if r.is_nan() || r <= 1e-6 {
        return Matrix3::identity() * noise.range * noise.range;
    }
    let u = ray / r;
    let across = Vector3::z().cross(&u);
    let across = if across.norm() > 1e-6 {
        across.normalize()
    } else {
        Vector3::x()
    };
    let up = u.cross(&across);
    let (sa, se) = (r * noise.azimuth, r * noise.elevation);
    let perpendicular = across * across.transpose() * (sa * sa) + up * up.transpose() * (se * se);
    let onto_surface = match normal {
        Some(n) => {
            let c = n.dot(&u);
            let c = if c.abs() < MIN_INCIDENCE_COS {
                MIN_INCIDENCE_COS.copysign(c)
            } else {
                c
            };
            Matrix3::identity() - u * n.transpose() / c
        }
        None => Matrix3::identity(),
    };
    onto_surface * perpendicular * onto_surface.transpose()
        + u * u.transpose() * (noise.range * noise.range)
}

/// Normal of the map's surface at world point `p`: of the map points within one voxel of its
/// nearest map point (closer than one voxel).
pub fn map_normal(
    map: &VoxelHashMap,
    p: &Point3<f64>,
    near: &mut Vec<Point3<f64>>,
) -> Option<Vector3<f64>> {
    let (q, _) = map.closest_neighbour_within(p, map.voxel_size())?;
    normal_at(map, &q, near)
}

/// The information `σ₀² (Σ_a + Σ_b)⁻¹` of a pair; `None` when not invertible.
pub fn pair_information(a: &Matrix3<f64>, b: &Matrix3<f64>) -> Option<Matrix3<f64>> {
    let sum = (a + b) / (REFERENCE_SIGMA * REFERENCE_SIGMA);
    let inv = sum.try_inverse()?;
    inv.iter()
        .all(|v| v.is_finite())
        .then_some(0.5 * (inv + inv.transpose()))
}

#[cfg(test)]
mod tests {
    use super::*;

    const NOISE: PointNoise = PointNoise {
        azimuth: 0.005,
        elevation: 0.01,
        range: 0.01,
    };

    #[test]
    fn a_grazing_wall_point_is_uncertain_along_the_wall_only() {
        // A wall at y = 1.2 along x, its point 6 m ahead: the ray meets it at ~11°.
        let n = Vector3::new(0.0, -1.0, 0.0);
        let p = Point3::new(6.0, 1.2, 0.0);
        let c = point_covariance(&p, &Vector3::zeros(), Some(n), &NOISE);
        let along = c[(0, 0)].sqrt();
        let off = (n.transpose() * c * n)[(0, 0)].sqrt();
        // Across the ray the angular error is 6.1 m × 5 mrad ≈ 3 cm; on the wall it is
        // stretched by 1 / sin(11°) ≈ 5 along x.
        assert!(along > 0.12 && along < 0.2, "{along}");
        assert!(off < 0.005, "{off}");
        // Face on, the point is known to the angular error.
        let face = point_covariance(
            &Point3::new(0.0, 1.2, 0.0),
            &Vector3::zeros(),
            Some(n),
            &NOISE,
        );
        assert!((face[(0, 0)].sqrt() - 1.2 * 0.005).abs() < 1e-6);
        let info = pair_information(&c, &face).unwrap();
        assert!(info[(0, 0)] < 0.2 && info[(1, 1)] > 10.0, "{info}");
    }
}
