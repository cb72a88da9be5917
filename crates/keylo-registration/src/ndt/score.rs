//! The NDT score of a source cloud against the target distributions and its gradient and
//! Hessian in the pose vector (Magnusson 2009, eq. 6.9–6.13), summed in parallel in a fixed
//! chunk order so a result is bit-for-bit repeatable.

use nalgebra::{Matrix3, Matrix3x6, Matrix6, Point3, Vector3, Vector6};
use rayon::prelude::*;

use super::euler::{pose_of, RotationDerivatives};
use super::neighbours::NdtTarget;
use super::voxel_grid::Cell;

/// Points per parallel chunk; chunk sums are added in chunk order.
const CHUNK: usize = 256;

/// The Gaussian-plus-uniform fit constants `d1`, `d2` (eq. 6.8).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gauss {
    /// Scale `d1` (negative).
    pub d1: f64,
    /// Exponent scale `d2`.
    pub d2: f64,
}

impl Gauss {
    /// The constants for an outlier ratio and a voxel resolution.
    pub fn new(outlier_ratio: f64, resolution: f64) -> Self {
        let c1 = 10.0 * (1.0 - outlier_ratio);
        let c2 = outlier_ratio / resolution.powi(3);
        let d3 = -c2.ln();
        let d1 = -(c1 + c2).ln() - d3;
        let d2 = -2.0 * ((-(c1 * (-0.5f64).exp() + c2).ln() - d3) / d1).ln();
        Self { d1, d2 }
    }
}

/// Score (to maximise), gradient and Hessian in `[x, y, z, roll, pitch, yaw]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Derivatives {
    /// Σ −d1·exp(−d2/2 · qᵀΣ⁻¹q) over point–voxel pairs.
    pub score: f64,
    /// ∂score/∂p.
    pub gradient: Vector6<f64>,
    /// ∂²score/∂p² (zero when not asked for).
    pub hessian: Matrix6<f64>,
}

impl Derivatives {
    fn zero() -> Self {
        Self {
            score: 0.0,
            gradient: Vector6::zeros(),
            hessian: Matrix6::zeros(),
        }
    }

    fn add(mut self, o: &Self) -> Self {
        self.score += o.score;
        self.gradient += o.gradient;
        self.hessian += o.hessian;
        self
    }
}

/// Score, gradient and (when `hessian`) Hessian of `source` at pose vector `p`.
pub fn derivatives(
    target: &NdtTarget,
    source: &[Point3<f64>],
    p: &Vector6<f64>,
    gauss: Gauss,
    hessian: bool,
) -> Derivatives {
    let pose = pose_of(p);
    let rot = RotationDerivatives::at(p);
    let partial: Vec<Derivatives> = source
        .par_chunks(CHUNK)
        .map(|chunk| {
            let mut acc = Derivatives::zero();
            for x in chunk {
                let moved = pose * x;
                let columns = rot.jacobian_columns(&x.coords);
                target.for_each_neighbour(&moved, |cell| {
                    accumulate(
                        &mut acc, &moved, &x.coords, cell, &columns, &rot, gauss, hessian,
                    );
                });
            }
            acc
        })
        .collect();
    partial.iter().fold(Derivatives::zero(), Derivatives::add)
}

/// Adds one point–voxel pair (eq. 6.10, 6.12, 6.13). Pairs whose weight is not in [0, 1]
/// (numerically broken) are skipped, as PCL skips them.
#[allow(clippy::too_many_arguments)]
#[inline]
fn accumulate(
    acc: &mut Derivatives,
    moved: &Point3<f64>,
    x: &Vector3<f64>,
    cell: &Cell,
    columns: &[Vector3<f64>; 3],
    rot: &RotationDerivatives,
    gauss: Gauss,
    hessian: bool,
) {
    let q = moved.coords - cell.mean;
    let c: &Matrix3<f64> = &cell.inverse_covariance;
    let cq = c * q;
    let e = (-gauss.d2 * q.dot(&cq) / 2.0).exp();
    let weight = gauss.d2 * e;
    if !(0.0..=1.0).contains(&weight) {
        return;
    }
    acc.score += -gauss.d1 * e;
    let w = weight * gauss.d1;
    // Point Jacobian J = [I | ∂R/∂θ · x] (3×6).
    let mut j = Matrix3x6::zeros();
    j.fixed_view_mut::<3, 3>(0, 0).fill_with_identity();
    for (k, col) in columns.iter().enumerate() {
        j.set_column(3 + k, col);
    }
    let qcj = j.transpose() * cq; // qᵀ Σ⁻¹ Jᵢ
    acc.gradient += qcj * w;
    if !hessian {
        return;
    }
    let cj = c * j;
    let mut h = j.transpose() * cj - qcj * qcj.transpose() * gauss.d2;
    for a in 0..3 {
        for b in 0..3 {
            h[(3 + a, 3 + b)] += cq.dot(&(rot.second[a][b] * x));
        }
    }
    acc.hessian += h * w;
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ndt::neighbours::NeighbourSearch;
    use crate::ndt::voxel_grid::GridSettings;

    /// A wavy surface sampled densely, and a sparser source taken from it.
    fn scene() -> (NdtTarget, Vec<Point3<f64>>) {
        let mut target = Vec::new();
        for i in 0..60 {
            for j in 0..60 {
                let (x, y) = (f64::from(i) * 0.1, f64::from(j) * 0.1);
                target.push(Point3::new(
                    x,
                    y,
                    0.3 * (x * 1.3).sin() + 0.2 * (y * 0.9).cos(),
                ));
                target.push(Point3::new(x, 0.2 * (x * 2.1).sin(), 0.1 * f64::from(j)));
            }
        }
        let source = target.iter().step_by(7).copied().collect();
        let grid =
            NdtTarget::new(&target, &GridSettings::default(), NeighbourSearch::Radius).unwrap();
        (grid, source)
    }

    #[test]
    fn gauss_constants_match_pcl_defaults() {
        // outlier 0.55, resolution 1: c1 = 4.5, c2 = 0.55.
        let g = Gauss::new(0.55, 1.0);
        let d3 = -(0.55f64).ln();
        assert!((g.d1 - (-(5.05f64).ln() - d3)).abs() < 1e-12);
        assert!(g.d1 < 0.0 && g.d2 > 0.0);
    }

    #[test]
    fn gradient_and_hessian_match_finite_differences() {
        let (target, source) = scene();
        let gauss = Gauss::new(0.55, 1.0);
        // Angles away from the |θ| < 1e-4 simplification.
        let p = Vector6::new(0.05, -0.04, 0.03, 0.02, -0.03, 0.04);
        let d = derivatives(&target, &source, &p, gauss, true);
        assert!(d.score > 0.0);
        let h = 1e-6;
        for i in 0..6 {
            let (mut a, mut b) = (p, p);
            a[i] += h;
            b[i] -= h;
            let da = derivatives(&target, &source, &a, gauss, true);
            let db = derivatives(&target, &source, &b, gauss, true);
            let g = (da.score - db.score) / (2.0 * h);
            let scale = d.gradient.norm().max(1.0);
            assert!(
                (g - d.gradient[i]).abs() < 1e-4 * scale,
                "g{i}: {g} vs {}",
                d.gradient[i]
            );
            let col = (da.gradient - db.gradient) / (2.0 * h);
            let hs = d.hessian.norm().max(1.0);
            assert!((col - d.hessian.column(i)).norm() < 1e-4 * hs, "H col {i}");
        }
    }

    #[test]
    fn the_sum_is_repeatable() {
        let (target, source) = scene();
        let p = Vector6::new(0.1, 0.0, 0.0, 0.01, 0.0, 0.0);
        let a = derivatives(&target, &source, &p, Gauss::new(0.55, 1.0), true);
        let b = derivatives(&target, &source, &p, Gauss::new(0.55, 1.0), true);
        assert_eq!(a, b);
    }
}
