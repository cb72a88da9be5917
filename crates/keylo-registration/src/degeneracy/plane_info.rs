//! The point-to-plane information `Σ J_nᵀ J_n`, `J_n = nᵀ[I | −hat(p − c)]`, of points
//! against a voxel map, with normals from the map points around each point's nearest
//! neighbour. It is what point-to-plane ICP would minimise and what the geometry constrains.

use nalgebra::{Isometry3, Matrix3, Matrix6, Point3, Vector3, Vector6};
use rayon::prelude::*;

use crate::kiss_icp::voxel_map::VoxelHashMap;

/// Map points within this many voxel edges of the neighbour fit its plane.
const PLANE_RADIUS_VOXELS: f64 = 1.0;
/// Fewest map points for a plane.
const MIN_PLANE_POINTS: usize = 5;
/// A neighbourhood is planar when its smallest covariance eigenvalue is below this fraction of
/// the middle one.
const PLANARITY: f64 = 0.1;

/// Point-to-plane information of a cloud, in twist coordinates `[ρ, φ]` about the sensor.
#[derive(Debug, Clone, Copy)]
pub struct PlaneInformation {
    pub matrix: Matrix6<f64>,
    /// Points that found a planar neighbourhood.
    pub residuals: usize,
    /// RMS distance of those points from the sensor (m).
    pub rms_range: f64,
}

/// Points per parallel work item of [`plane_information`]; partial sums are added in chunk
/// order, so the result does not depend on the number of threads.
const CHUNK: usize = 128;

/// Information of (an even stride of at most `max_points` of) `source` (sensor frame) placed
/// at `pose` against `map`, for points whose nearest map point is closer than
/// `max_distance`. Rotations are about the sensor position, so the matrix does not depend on
/// how far the sensor is from the world origin. Runs in parallel (rayon).
pub fn plane_information(
    source: &[Point3<f64>],
    map: &VoxelHashMap,
    pose: &Isometry3<f64>,
    max_distance: f64,
    max_points: usize,
) -> PlaneInformation {
    let radius = PLANE_RADIUS_VOXELS * map.voxel_size();
    plane_information_with(source, map, pose, max_distance, max_points, |neighbours| {
        neighbours
            .par_iter()
            .with_min_len(CHUNK)
            .map_init(Vec::new, |near, q| {
                let q = (*q)?;
                near.clear();
                map.points_within(&q, radius, near);
                plane_normal(near)
            })
            .collect()
    })
}

/// [`plane_information`] with the planar normals of the picked points' nearest map points
/// given by `planar(neighbours)` (one per neighbour, in order; `None`: no neighbour, or not
/// planar): [`plane_information`] computes them, the hybrid registrar takes them from its
/// cache; the sums are the same, in the same order.
pub(crate) fn plane_information_with(
    source: &[Point3<f64>],
    map: &VoxelHashMap,
    pose: &Isometry3<f64>,
    max_distance: f64,
    max_points: usize,
    mut planar: impl FnMut(&[Option<Point3<f64>>]) -> Vec<Option<Vector3<f64>>>,
) -> PlaneInformation {
    let picked: Vec<Point3<f64>> = source
        .iter()
        .step_by(stride(source, max_points))
        .copied()
        .collect();
    let neighbours: Vec<Option<Point3<f64>>> = picked
        .par_iter()
        .with_min_len(CHUNK)
        .map(|p| {
            map.closest_neighbour_within(&(pose * p), max_distance)
                .map(|(q, _)| q)
        })
        .collect();
    let normals = planar(&neighbours);
    let partials: Vec<Sums> = picked
        .par_chunks(CHUNK)
        .zip(normals.par_chunks(CHUNK))
        .map(|(chunk, ns)| {
            let mut given = ns.iter();
            sums(chunk.iter(), pose, |_| given.next().copied().flatten())
        })
        .collect();
    partials.iter().fold(Sums::default(), Sums::add).finish()
}

/// The information of (an even stride of at most `max_points` of) `source` placed at `pose`,
/// with `normal_at(world point)` giving the unit normal of the surface the point lies on
/// (`None`: no planar surface there; the point gives nothing).
pub fn information_with_normals(
    source: &[Point3<f64>],
    pose: &Isometry3<f64>,
    max_points: usize,
    normal_at: impl FnMut(&Point3<f64>) -> Option<Vector3<f64>>,
) -> PlaneInformation {
    sums(
        source.iter().step_by(stride(source, max_points)),
        pose,
        normal_at,
    )
    .finish()
}

fn stride(source: &[Point3<f64>], max_points: usize) -> usize {
    source.len().div_ceil(max_points.max(1)).max(1)
}

/// Running sums of the information.
#[derive(Default, Clone, Copy)]
struct Sums {
    matrix: Matrix6<f64>,
    residuals: usize,
    range2: f64,
}

impl Sums {
    fn add(mut self, other: &Sums) -> Sums {
        self.matrix += other.matrix;
        self.residuals += other.residuals;
        self.range2 += other.range2;
        self
    }

    fn finish(self) -> PlaneInformation {
        PlaneInformation {
            matrix: self.matrix,
            residuals: self.residuals,
            rms_range: (self.range2 / self.residuals.max(1) as f64).sqrt(),
        }
    }
}

fn sums<'a>(
    points: impl Iterator<Item = &'a Point3<f64>>,
    pose: &Isometry3<f64>,
    mut normal_at: impl FnMut(&Point3<f64>) -> Option<Vector3<f64>>,
) -> Sums {
    let centre = pose.translation.vector;
    let mut s = Sums::default();
    for p in points {
        let world = pose * p;
        let Some(n) = normal_at(&world) else {
            continue;
        };
        let arm = world.coords - centre;
        let j = Vector6::new(n.x, n.y, n.z, 0.0, 0.0, 0.0) + {
            let c = arm.cross(&n);
            Vector6::new(0.0, 0.0, 0.0, c.x, c.y, c.z)
        };
        s.matrix += j * j.transpose();
        s.residuals += 1;
        s.range2 += arm.norm_squared();
    }
    s
}

/// Unit normal of a planar neighbourhood, `None` when too few points or not planar.
pub(crate) fn plane_normal(points: &[Point3<f64>]) -> Option<Vector3<f64>> {
    planar_normal_of(&covariance(points)?)
}

/// The unit normal of a distribution with covariance `cov` when it is planar (its smallest
/// eigenvalue below `PLANARITY` times the middle one), else `None`.
pub(crate) fn planar_normal_of(cov: &Matrix3<f64>) -> Option<Vector3<f64>> {
    let (n, l0, l1) = least_spread_of(cov)?;
    (l1 > 0.0 && l0 < PLANARITY * l1).then_some(n)
}

/// Both normals of `points` from one eigen-decomposition: the direction in which they spread
/// least (PCL's normal: the covariance's smallest eigenvector, planar or not; across a line or
/// an edge it has no component along it; `None` with fewer than 5 points), and
/// [`plane_normal`].
pub(crate) fn normals_of(points: &[Point3<f64>]) -> (Option<Vector3<f64>>, Option<Vector3<f64>>) {
    let Some((n, l0, l1)) = covariance(points).and_then(|c| least_spread_of(&c)) else {
        return (None, None);
    };
    (Some(n), (l1 > 0.0 && l0 < PLANARITY * l1).then_some(n))
}

/// The sample covariance of `points`, `None` with fewer than 5.
fn covariance(points: &[Point3<f64>]) -> Option<Matrix3<f64>> {
    if points.len() < MIN_PLANE_POINTS {
        return None;
    }
    let n = points.len() as f64;
    let mean = points.iter().map(|p| p.coords).sum::<Vector3<f64>>() / n;
    let cov = points
        .iter()
        .map(|p| {
            let d = p.coords - mean;
            d * d.transpose()
        })
        .sum::<Matrix3<f64>>()
        / n;
    Some(cov)
}

/// A covariance's smallest eigenvector and its two smallest eigenvalues.
fn least_spread_of(cov: &Matrix3<f64>) -> Option<(Vector3<f64>, f64, f64)> {
    let e = cov.symmetric_eigen();
    let mut order = [0usize, 1, 2];
    order.sort_by(|&a, &b| e.eigenvalues[a].total_cmp(&e.eigenvalues[b]));
    let normal = e.eigenvectors.column(order[0]).into_owned();
    normal.iter().all(|v| v.is_finite()).then_some(())?;
    Some((normal, e.eigenvalues[order[0]], e.eigenvalues[order[1]]))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::degeneracy::analyse;

    use crate::test_scenes::room;

    /// A corridor along x: two walls at y = ±2 and a floor, 40 m long.
    fn corridor() -> Vec<Point3<f64>> {
        crate::test_scenes::corridor(3, 9000, 40.0)
    }

    fn degeneracy_of(cloud: &[Point3<f64>]) -> keylo_core::Degeneracy {
        let mut map = VoxelHashMap::new(0.5, 100.0, 20);
        map.update(cloud, &Isometry3::identity());
        let info = plane_information(cloud, &map, &Isometry3::identity(), 1.0, 3000);
        assert!(info.residuals > 1000, "{}", info.residuals);
        let ratio = crate::degeneracy::DegeneracyConfig::default().weak_ratio;
        analyse(&info.matrix, info.residuals, info.rms_range, ratio)
    }

    #[test]
    fn a_corridor_is_weak_along_its_axis() {
        let d = degeneracy_of(&corridor());
        assert_eq!(d.weak, 1, "{d:?}");
        let v = d.weak_directions()[0];
        assert!(v[0].abs() > 0.99, "weak direction {v:?}");
        assert!(d.condition > 1e3, "{}", d.condition);
    }

    #[test]
    fn a_closed_room_is_not_degenerate() {
        let d = degeneracy_of(&room());
        assert_eq!(d.weak, 0, "{d:?}");
        assert!(d.condition < 50.0, "{}", d.condition);
    }
}
