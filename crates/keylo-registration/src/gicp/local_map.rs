//! GICP's local map: KISS-ICP's voxel hash (at most `max_points_per_voxel` points a voxel,
//! spaced by `voxel_size / √max_points`, voxels beyond `max_range` from the sensor dropped),
//! each point with its covariance in the world frame — computed once, from the frame that
//! brought it, and rotated with that frame's pose (small_gicp's incremental map does the
//! same), so no frame recomputes the map's covariances; and computed only for the points the
//! map admits (most of a frame's points land in full voxels).

use nalgebra::{Isometry3, Matrix3, Point3, Vector3};

use super::align::{Neighbour, Target};
use super::covariances::Patch;
use crate::kiss_icp::voxel_map::{faces, gap2, NEIGHBOURS};
use crate::voxel::{voxel_of, VoxelMap};

/// A voxel's points and their patches (world frame), apart: the nearest-point search reads
/// only the points.
#[derive(Default)]
struct Block {
    points: Vec<Point3<f64>>,
    patches: Vec<Patch>,
}

/// The local map of points with covariances.
pub struct CovarianceMap {
    voxel_size: f64,
    max_distance: f64,
    max_points_per_voxel: usize,
    map: VoxelMap<Block>,
    len: usize,
}

impl CovarianceMap {
    pub fn new(voxel_size: f64, max_distance: f64, max_points_per_voxel: usize) -> Self {
        Self {
            voxel_size,
            max_distance,
            max_points_per_voxel,
            map: VoxelMap::default(),
            len: 0,
        }
    }

    pub fn len(&self) -> usize {
        self.len
    }

    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Every point, world frame (voxels in key order, so the order does not depend on the
    /// hash).
    pub fn points(&self) -> Vec<Point3<f64>> {
        let mut keys: Vec<_> = self.map.keys().copied().collect();
        keys.sort_unstable();
        keys.iter()
            .flat_map(|k| self.map[k].points.iter().copied())
            .collect()
    }

    /// Adds the `points` (sensor frame) seen from `pose` that the map admits (KISS-ICP's
    /// rule: a voxel not full, no point of it closer than `voxel_size / √max_points`), each
    /// with the patch `patches_of` gives for it (called once with the admitted points'
    /// indices into `points`, sensor frame); then drops the voxels beyond the range from the
    /// sensor.
    pub fn update(
        &mut self,
        points: &[Point3<f64>],
        pose: &Isometry3<f64>,
        patches_of: impl FnOnce(&[usize]) -> Vec<Patch>,
    ) {
        let resolution2 = self.voxel_size * self.voxel_size / self.max_points_per_voxel as f64;
        let placeholder = Patch {
            covariance: Matrix3::zeros(),
            normal: Vector3::zeros(),
        };
        let (mut admitted, mut slots) = (Vec::new(), Vec::new());
        for (i, p) in points.iter().enumerate() {
            let w = pose * p;
            let key = voxel_of(&w, self.voxel_size);
            let block = self.map.entry(key).or_default();
            if block.points.len() >= self.max_points_per_voxel
                || block
                    .points
                    .iter()
                    .any(|q| (q - w).norm_squared() < resolution2)
            {
                continue;
            }
            slots.push((key, block.points.len()));
            block.points.push(w);
            block.patches.push(placeholder);
            admitted.push(i);
        }
        let r = pose.rotation.to_rotation_matrix().into_inner();
        for ((key, slot), patch) in slots.iter().zip(patches_of(&admitted)) {
            if let Some(entry) = self.map.get_mut(key).and_then(|b| b.patches.get_mut(*slot)) {
                *entry = patch.rotated(&r);
            }
        }
        self.len += admitted.len();
        let (origin, max2) = (pose.translation.vector, self.max_distance.powi(2));
        let mut removed = 0;
        self.map.retain(|_, b| {
            let keep = b
                .points
                .first()
                .is_some_and(|p| (p.coords - origin).norm_squared() < max2);
            if !keep {
                removed += b.points.len();
            }
            keep
        });
        self.len -= removed;
    }
}

impl Target for CovarianceMap {
    /// The nearest map point among the 27 voxels around `q` (a pair farther than one voxel
    /// may be missed, as in KISS-ICP), the query's own voxel first and the voxels that cannot
    /// hold a nearer point than the best so far skipped, as KISS-ICP's map searches.
    fn nearest(&self, q: &Point3<f64>, max_d2: f64) -> Option<Neighbour> {
        let (v, faces) = faces(q, self.voxel_size);
        let mut best: Option<(&Block, usize)> = None;
        let mut best_d2 = max_d2;
        for d in NEIGHBOURS {
            if gap2(&d, &faces) >= best_d2 {
                continue;
            }
            let Some(block) = self.map.get(&[v[0] + d[0], v[1] + d[1], v[2] + d[2]]) else {
                continue;
            };
            for (i, p) in block.points.iter().enumerate() {
                let d2 = (p - q).norm_squared();
                if d2 < best_d2 {
                    best = Some((block, i));
                    best_d2 = d2;
                }
            }
        }
        best.map(|(block, i)| Neighbour {
            point: block.points[i],
            patch: block.patches[i],
        })
    }

    /// The map points closer than `radius` to `q` among the 27 voxels around it, as
    /// KISS-ICP's map gives them to its degeneracy analysis.
    fn points_within(&self, q: &Point3<f64>, radius: f64, out: &mut Vec<Point3<f64>>) {
        let (v, faces) = faces(q, self.voxel_size);
        let r2 = radius * radius;
        for d in NEIGHBOURS {
            if gap2(&d, &faces) >= r2 {
                continue;
            }
            if let Some(block) = self.map.get(&[v[0] + d[0], v[1] + d[1], v[2] + d[2]]) {
                out.extend(block.points.iter().filter(|p| (*p - q).norm_squared() < r2));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kiss_icp::voxel_map::VoxelHashMap;
    use crate::test_scenes::room;

    /// The same points and nearest neighbours as KISS-ICP's voxel map.
    #[test]
    fn holds_and_finds_what_kiss_icps_map_does() {
        let pts = room();
        let pose = Isometry3::translation(0.3, -0.2, 0.1);
        let mut ours = CovarianceMap::new(0.3, 100.0, 20);
        let patch = Patch {
            covariance: Matrix3::identity(),
            normal: Vector3::z(),
        };
        ours.update(&pts, &pose, |admitted| vec![patch; admitted.len()]);
        let mut kiss = VoxelHashMap::new(0.3, 100.0, 20);
        kiss.update(&pts, &pose);
        assert_eq!(ours.len(), kiss.len());
        let mut s = 9u64;
        for _ in 0..500 {
            let q = Point3::new(
                crate::test_scenes::rnd(&mut s) * 10.0 - 5.0,
                crate::test_scenes::rnd(&mut s) * 8.0 - 4.0,
                crate::test_scenes::rnd(&mut s) * 3.0 - 1.0,
            );
            let a = ours.nearest(&q, 0.25).map(|n| n.point);
            let b = kiss
                .closest_neighbour_within(&q, 0.5)
                .filter(|(_, d)| d * d < 0.25)
                .map(|(p, _)| p);
            assert_eq!(a, b, "{q}");
        }
    }
}
