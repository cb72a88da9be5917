//! Per-point covariances of a cloud from its `k` nearest neighbours, regularised as PCL's
//! `GeneralizedIterativeClosestPoint::computeCovariances` (Segal et al. 2009): the sample
//! covariance's eigenvectors kept, its eigenvalues set to (1, 1, ε), so every point is a small
//! plane patch whatever the neighbours' spread.

use nalgebra::{Matrix3, Point3, SymmetricEigen, Vector3};
use rayon::prelude::*;

use super::knn::KnnTree;
use crate::RegistrationError;

/// A cloud with the k-d tree of its points (for correspondences and neighbours).
pub struct Indexed {
    pub points: Vec<Point3<f64>>,
    pub tree: KnnTree,
}

impl Indexed {
    /// Builds the tree; an error for an empty cloud.
    pub fn new(points: Vec<Point3<f64>>) -> Result<Self, RegistrationError> {
        if points.is_empty() {
            return Err(RegistrationError::BadCloud(
                "GICP: an empty cloud has no neighbours".into(),
            ));
        }
        let tree = KnnTree::new(&points);
        Ok(Self { points, tree })
    }

    /// The nearest point to `q`: (index, squared distance).
    #[inline]
    pub fn nearest(&self, q: &Point3<f64>) -> (usize, f64) {
        let (i, d2) = self.tree.nearest(q).unwrap_or((0, f64::INFINITY));
        (i as usize, d2)
    }
}

/// A point's regularised covariance and its normal (the covariance's thinnest direction).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Patch {
    pub covariance: Matrix3<f64>,
    pub normal: Vector3<f64>,
}

impl Patch {
    /// The patch in a frame rotated by `r` (a rotation matrix).
    pub fn rotated(&self, r: &Matrix3<f64>) -> Self {
        Self {
            covariance: r * self.covariance * r.transpose(),
            normal: r * self.normal,
        }
    }
}

/// The patch of every point of `cloud` from its `k` nearest neighbours (itself included, as
/// PCL's `nearestKSearch`), eigenvalues set to (1, 1, `epsilon`). With fewer than `k` points
/// in the cloud, all of them are the neighbours.
pub fn patches(cloud: &Indexed, k: usize, epsilon: f64) -> Vec<Patch> {
    patches_at(cloud, &cloud.points, k, epsilon)
}

/// [`patches`] at `queries`, each from its `k` nearest points of `cloud` (a sparse cloud's
/// points get their patches from a denser one).
pub fn patches_at(cloud: &Indexed, queries: &[Point3<f64>], k: usize, epsilon: f64) -> Vec<Patch> {
    let k = k.min(cloud.points.len()).max(1);
    queries
        .par_iter()
        .with_min_len(256)
        .map_init(Vec::new, |hits, p| {
            cloud.tree.nearest_k(p, k, hits);
            let mut mean = Vector3::zeros();
            let mut outer = Matrix3::zeros();
            for &(i, _) in hits.iter() {
                let q = cloud.points[i as usize].coords;
                mean += q;
                outer += q * q.transpose();
            }
            let m = hits.len().max(1) as f64;
            mean /= m;
            let cov = outer / m - mean * mean.transpose();
            regularise(&cov, epsilon)
        })
        .collect()
}

/// The covariance with its eigenvectors and eigenvalues (1, 1, `epsilon`), the smallest
/// eigenvalue's direction (the patch's normal) getting `epsilon`: `I − (1 − ε) n nᵀ`.
pub fn regularise(cov: &Matrix3<f64>, epsilon: f64) -> Patch {
    let eig = SymmetricEigen::new(*cov);
    let normal = eig.eigenvectors.column(eig.eigenvalues.imin()).into_owned();
    Patch {
        covariance: Matrix3::identity() - (1.0 - epsilon) * normal * normal.transpose(),
        normal,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn points_on_a_plane_get_its_normal_with_epsilon() {
        let pts: Vec<Point3<f64>> = (0..400)
            .map(|i| {
                let (a, b) = (f64::from(i % 20) * 0.1, f64::from(i / 20) * 0.1);
                // The plane z = 0.5 x, tilted.
                Point3::new(a, b, 0.5 * a)
            })
            .collect();
        let cloud = Indexed::new(pts).unwrap();
        let patches = patches(&cloud, 20, 1e-3);
        let normal = Vector3::new(-0.5, 0.0, 1.0).normalize();
        for p in patches.iter().step_by(37) {
            let c = &p.covariance;
            assert!((p.normal.dot(&normal).abs() - 1.0).abs() < 1e-9);
            assert!(((normal.transpose() * c * normal)[0] - 1e-3).abs() < 1e-9);
            let along = Vector3::new(1.0, 0.0, 0.5).normalize();
            assert!(((along.transpose() * c * along)[0] - 1.0).abs() < 1e-9);
        }
    }
}
