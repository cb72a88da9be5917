//! The NDT target: one Gaussian (mean, regularised inverse covariance) per voxel of the target
//! cloud, as PCL's `VoxelGridCovariance`.

use nalgebra::{Matrix3, Point3, Vector3};

use crate::voxel::{voxel_of, Voxel, VoxelMap};
use crate::RegistrationError;

/// How target voxels become Gaussians.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GridSettings {
    /// Voxel edge (m).
    pub resolution: f64,
    /// Voxels with fewer points are left out (PCL: 6).
    pub min_points_per_voxel: usize,
    /// Eigenvalues below this fraction of the largest are raised to it (PCL: 0.01).
    pub min_eigenvalue_ratio: f64,
}

impl Default for GridSettings {
    fn default() -> Self {
        Self {
            resolution: 1.0,
            min_points_per_voxel: 6,
            min_eigenvalue_ratio: 0.01,
        }
    }
}

/// One target voxel's normal distribution.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cell {
    /// Mean of the voxel's points.
    pub mean: Vector3<f64>,
    /// Inverse of the regularised sample covariance.
    pub inverse_covariance: Matrix3<f64>,
    /// Points the voxel holds.
    pub points: usize,
}

/// Running sums of one voxel while the grid is built.
#[derive(Clone, Copy)]
struct Sums {
    sum: Vector3<f64>,
    outer: Matrix3<f64>,
    n: usize,
}

/// The usable voxels of a target cloud, in first-seen order, and their index by voxel key.
pub struct Distributions {
    pub(crate) cells: Vec<Cell>,
    pub(crate) keys: Vec<Voxel>,
    pub(crate) index: VoxelMap<u32>,
}

impl Distributions {
    /// Builds the distributions of `points` (every coordinate finite).
    pub fn build(points: &[Point3<f64>], settings: &GridSettings) -> Self {
        let mut slot: VoxelMap<usize> = VoxelMap::default();
        let mut sums: Vec<(Voxel, Sums)> = Vec::new();
        for p in points {
            let key = voxel_of(p, settings.resolution);
            let i = *slot.entry(key).or_insert_with(|| {
                sums.push((
                    key,
                    Sums {
                        sum: Vector3::zeros(),
                        outer: Matrix3::zeros(),
                        n: 0,
                    },
                ));
                sums.len() - 1
            });
            let s = &mut sums[i].1;
            s.sum += p.coords;
            s.outer += p.coords * p.coords.transpose();
            s.n += 1;
        }
        let mut out = Self {
            cells: Vec::new(),
            keys: Vec::new(),
            index: VoxelMap::default(),
        };
        for (key, s) in sums {
            if s.n < settings.min_points_per_voxel.max(2) {
                continue;
            }
            if let Some(cell) = cell_of(&s, settings.min_eigenvalue_ratio) {
                out.index.insert(key, out.cells.len() as u32);
                out.cells.push(cell);
                out.keys.push(key);
            }
        }
        out
    }

    /// The usable voxels.
    pub fn cells(&self) -> &[Cell] {
        &self.cells
    }
}

/// The voxel's Gaussian, or `None` when its covariance is degenerate (PCL drops those too).
fn cell_of(s: &Sums, min_ratio: f64) -> Option<Cell> {
    let n = s.n as f64;
    let mean = s.sum / n;
    let covariance = (s.outer - s.sum * mean.transpose()) / (n - 1.0);
    let covariance = regularise(&covariance, min_ratio)?;
    let inverse_covariance = covariance.try_inverse()?;
    inverse_covariance
        .iter()
        .all(|v| v.is_finite())
        .then_some(Cell {
            mean,
            inverse_covariance,
            points: s.n,
        })
}

/// PCL's regularisation of a near-singular covariance: with eigenvalues λ₀ ≤ λ₁ ≤ λ₂, when
/// λ₀ < r·λ₂ both λ₀ and (if also below) λ₁ are raised to r·λ₂ and the matrix is rebuilt.
/// `None` for a covariance with a negative eigenvalue or λ₂ ≤ 0 (no shape at all).
pub fn regularise(covariance: &Matrix3<f64>, min_ratio: f64) -> Option<Matrix3<f64>> {
    let eigen = covariance.symmetric_eigen();
    let mut order = [0usize, 1, 2];
    order.sort_by(|&a, &b| eigen.eigenvalues[a].total_cmp(&eigen.eigenvalues[b]));
    let mut values = [
        eigen.eigenvalues[order[0]],
        eigen.eigenvalues[order[1]],
        eigen.eigenvalues[order[2]],
    ];
    let tiny = 1e-12; // Eigen's dummy_precision for double
    if !values.iter().all(|v| v.is_finite()) || values[0] < -tiny || values[1] < -tiny {
        return None;
    }
    if values[2] <= 0.0 {
        return None;
    }
    let floor = min_ratio * values[2];
    if values[0] >= floor {
        return Some(*covariance);
    }
    values[0] = floor;
    values[1] = values[1].max(floor);
    let mut rebuilt = Matrix3::zeros();
    for (k, &i) in order.iter().enumerate() {
        let v = eigen.eigenvectors.column(i);
        rebuilt += v * v.transpose() * values[k];
    }
    Some(rebuilt)
}

/// Fails when `points` would give no usable voxel.
pub(crate) fn require_cells(
    d: &Distributions,
    points: usize,
    settings: &GridSettings,
) -> Result<(), RegistrationError> {
    if d.cells.is_empty() {
        return Err(RegistrationError::BadCloud(format!(
            "NDT target of {points} points has no voxel of {} m with at least {} points and a \
             non-degenerate covariance",
            settings.resolution, settings.min_points_per_voxel
        )));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_flat_covariance_is_inflated_to_one_percent() {
        let c = Matrix3::from_diagonal(&Vector3::new(1.0, 0.5, 1e-6));
        let r = regularise(&c, 0.01).unwrap();
        let e = r.symmetric_eigen().eigenvalues;
        let mut v: Vec<f64> = e.iter().copied().collect();
        v.sort_by(f64::total_cmp);
        assert!((v[0] - 0.01).abs() < 1e-12, "{v:?}");
        assert!((v[1] - 0.5).abs() < 1e-12 && (v[2] - 1.0).abs() < 1e-12);
    }

    #[test]
    fn a_line_raises_both_small_eigenvalues_and_keeps_the_axis() {
        let axis = Vector3::new(1.0, 1.0, 0.0).normalize();
        let c = axis * axis.transpose() * 4.0;
        let r = regularise(&c, 0.01).unwrap();
        assert!((r * axis - axis * 4.0).norm() < 1e-9);
        let normal = Vector3::new(0.0, 0.0, 1.0);
        assert!((r * normal - normal * 0.04).norm() < 1e-9);
    }

    #[test]
    fn well_conditioned_covariances_are_untouched_and_degenerate_ones_dropped() {
        let c = Matrix3::new(2.0, 0.1, 0.0, 0.1, 1.0, 0.0, 0.0, 0.0, 0.5);
        assert_eq!(regularise(&c, 0.01), Some(c));
        assert_eq!(regularise(&Matrix3::zeros(), 0.01), None);
        assert_eq!(regularise(&(-Matrix3::identity()), 0.01), None);
    }

    #[test]
    fn voxels_with_few_points_are_skipped() {
        let mut pts: Vec<Point3<f64>> = (0..10)
            .map(|i| {
                Point3::new(
                    0.1 * f64::from(i % 3),
                    0.1 * f64::from(i % 5),
                    0.05 * f64::from(i),
                )
            })
            .collect();
        pts.extend(
            (0..5).map(|i| Point3::new(5.0 + 0.1 * f64::from(i), 0.2, 0.3 * f64::from(i % 2))),
        );
        let d = Distributions::build(&pts, &GridSettings::default());
        assert_eq!(d.cells().len(), 1);
        assert_eq!(d.cells()[0].points, 10);
        let mean = pts[..10].iter().map(|p| p.coords).sum::<Vector3<f64>>() / 10.0;
        assert!((d.cells()[0].mean - mean).norm() < 1e-12);
    }

    #[test]
    fn identical_points_give_no_cell() {
        let pts = vec![Point3::new(0.5, 0.5, 0.5); 50];
        let d = Distributions::build(&pts, &GridSettings::default());
        assert!(d.cells().is_empty());
        assert!(require_cells(&d, 50, &GridSettings::default()).is_err());
    }
}
