//! NDT's degeneracy analysis: the point-to-plane information of the aligned source against the
//! target's planar Gaussians (each voxel's normal is its covariance's smallest-spread
//! direction), the same matrix KISS-ICP and hybrid analyse against their voxel maps.
//!
//! NDT's own score Hessian is not used: measured on the simulated long hall, corridor, lab and
//! road (docs/results/hybrid.md, "Degeneracy of NDT"), its negation is indefinite at 5–17 % of
//! the final poses and names the hall's axis as the weakest direction in only 60 % of frames,
//! and its Gauss–Newton part never does (PCL's eigenvalue floor gives each wall voxel 1 % of its
//! across-wall information along the wall, which outweighs roll's).

use nalgebra::{Isometry3, Point3, Vector3};

use super::neighbours::NdtTarget;
use super::voxel_grid::Cell;
use crate::degeneracy::{information_with_normals, planar_normal_of, PlaneInformation};

/// A point belongs to a cell's plane when its Mahalanobis distance is at most this (3σ).
const MAX_MAHALANOBIS2: f64 = 9.0;

/// The information of (a stride of at most `max_points` of) `source` at `pose` against
/// `target`: each point takes the neighbour cell it fits best, when that cell is planar and
/// the point lies within 3σ of it.
pub fn plane_information(
    target: &NdtTarget,
    source: &[Point3<f64>],
    pose: &Isometry3<f64>,
    max_points: usize,
) -> PlaneInformation {
    information_with_normals(source, pose, max_points, |world| {
        let mut best: Option<(f64, Cell)> = None;
        target.for_each_neighbour(world, |cell| {
            let q = world.coords - cell.mean;
            let m = q.dot(&(cell.inverse_covariance * q));
            if m <= MAX_MAHALANOBIS2 && best.is_none_or(|(b, _)| m < b) {
                best = Some((m, *cell));
            }
        });
        best.and_then(|(_, cell)| planar_normal(&cell))
    })
}

/// The unit normal of a planar cell: the planarity rule of the KISS-style analysis applied to
/// the cell's (regularised) covariance.
fn planar_normal(cell: &Cell) -> Option<Vector3<f64>> {
    planar_normal_of(&cell.inverse_covariance.try_inverse()?)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::degeneracy::{analyse, DegeneracyConfig};
    use crate::ndt::{GridSettings, NeighbourSearch};
    use crate::test_scenes::{corridor, room};

    fn degeneracy_of(cloud: &[Point3<f64>]) -> keylo_core::Degeneracy {
        let target =
            NdtTarget::new(cloud, &GridSettings::default(), NeighbourSearch::Radius).unwrap();
        let info = plane_information(&target, cloud, &Isometry3::identity(), 3000);
        assert!(info.residuals > 1000, "{}", info.residuals);
        let ratio = DegeneracyConfig::default().weak_ratio;
        analyse(&info.matrix, info.residuals, info.rms_range, ratio)
    }

    #[test]
    fn a_corridor_is_weak_along_its_axis_only() {
        let d = degeneracy_of(&corridor(3, 20_000, 40.0));
        assert_eq!(d.weak, 1, "{d:?}");
        assert!(d.weak_directions()[0][0].abs() > 0.99, "{d:?}");
    }

    #[test]
    fn a_closed_room_is_not_degenerate() {
        let d = degeneracy_of(&room());
        assert_eq!(d.weak, 0, "{d:?}");
    }
}
