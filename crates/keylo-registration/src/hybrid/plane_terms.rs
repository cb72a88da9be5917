//! Point-to-plane cloud residuals against the local map: `r = nᵀ(p − q)` with `q` the nearest
//! map point and `n` the direction in which the map points within one voxel of `q` spread
//! least (PCL's normal estimate, planar or not: across a wall-floor edge or a scan line it has
//! no component along it). A point whose neighbour has fewer than 5 map points around it gives
//! no residual: there the map is sparse, mostly at its frontier, where a point-to-point pull
//! would point back into the map. Unlike point-to-point terms, these say nothing along a plane
//! or an edge, so in a corridor the cloud leaves the axis to the keypoints instead of pulling
//! towards the nearest samples.
//!
//! Normals are computed once per map point and frame ([`NormalCache`]), since the nearest
//! neighbours barely change between Gauss–Newton iterations.

use std::collections::HashMap;

use nalgebra::{Point3, RowVector6, Vector3};
use rayon::prelude::*;

use crate::degeneracy::least_spread_normal;
use crate::kiss_icp::icp::{IcpSettings, System};
use crate::kiss_icp::voxel_map::VoxelHashMap;

/// Points per parallel work item; sums are reduced in chunk order (thread-count independent).
const CHUNK: usize = 512;

/// Map points' normals ([`normal_at`]; `None`: too few points around) for one frame, keyed by
/// the point's bits.
#[derive(Debug, Default)]
pub struct NormalCache {
    normals: HashMap<[u64; 3], Option<Vector3<f64>>>,
}

fn key(q: &Point3<f64>) -> [u64; 3] {
    [q.x.to_bits(), q.y.to_bits(), q.z.to_bits()]
}

impl NormalCache {
    /// Forgets every normal (the map changed).
    pub fn clear(&mut self) {
        self.normals.clear();
    }
}

/// The normal of the map around its point `q`: the direction of least spread of the map
/// points within one voxel of it; `near` is scratch.
pub(crate) fn normal_at(
    map: &VoxelHashMap,
    q: &Point3<f64>,
    near: &mut Vec<Point3<f64>>,
) -> Option<Vector3<f64>> {
    near.clear();
    map.points_within(q, map.voxel_size(), near);
    least_spread_normal(near)
}

/// The normal equations (twist about the world origin, as [`crate::kiss_icp::icp`]) of
/// `source` (world frame) against `map`, of the points whose nearest neighbour has a normal,
/// Geman–McClure weights `κ² / (κ + r²)²` as
/// upstream KISS-ICP's.
pub(crate) fn plane_system(
    source: &[Point3<f64>],
    map: &VoxelHashMap,
    s: &IcpSettings,
    cache: &mut NormalCache,
) -> System {
    let pairs: Vec<Option<Point3<f64>>> = source
        .par_iter()
        .with_min_len(CHUNK)
        .map(|p| {
            map.closest_neighbour_within(p, s.max_distance)
                .map(|(q, _)| q)
        })
        .collect();
    // Normals of neighbours not seen yet this frame, in parallel, then cached: afterwards the
    // cache holds every neighbour's.
    let mut fresh: Vec<Point3<f64>> = pairs
        .iter()
        .flatten()
        .filter(|q| !cache.normals.contains_key(&key(q)))
        .copied()
        .collect();
    fresh.sort_unstable_by_key(key);
    fresh.dedup();
    let computed: Vec<Option<Vector3<f64>>> = fresh
        .par_iter()
        .with_min_len(64)
        .map_init(Vec::new, |near, q| normal_at(map, q, near))
        .collect();
    for (q, n) in fresh.iter().zip(computed) {
        cache.normals.insert(key(q), n);
    }
    let normals: Vec<Option<Vector3<f64>>> = pairs
        .iter()
        .map(|q| q.and_then(|q| cache.normals.get(&key(&q)).copied().flatten()))
        .collect();
    let partials: Vec<System> = source
        .par_chunks(CHUNK)
        .zip(pairs.par_chunks(CHUNK))
        .zip(normals.par_chunks(CHUNK))
        .map(|((ps, qs), ns)| chunk_system(ps, qs, ns, s.kernel))
        .collect();
    partials.iter().fold(System::zero(), |a, b| a.add(b))
}

fn chunk_system(
    ps: &[Point3<f64>],
    qs: &[Option<Point3<f64>>],
    ns: &[Option<Vector3<f64>>],
    kernel: f64,
) -> System {
    let mut sys = System::zero();
    let kappa2 = kernel * kernel;
    for ((p, q), n) in ps.iter().zip(qs).zip(ns) {
        let Some(q) = q else { continue };
        let d = p - q;
        // A point whose neighbour has no normal gives no residual: there the map is sparse,
        // mostly at its frontier, where a point-to-point pull would point back into the map
        // and hold the pose against the motion.
        let Some(n) = n else { continue };
        let r = n.dot(&d);
        let w = kappa2 / (kernel + r * r).powi(2);
        let c = p.coords.cross(n);
        let j = RowVector6::new(n.x, n.y, n.z, c.x, c.y, c.z);
        sys.jtj += j.transpose() * j * w;
        sys.jtr += j.transpose() * (r * w);
        sys.count += 1;
    }
    sys
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Isometry3;

    /// Two walls at y = ±2 and a floor, along x, 20 m.
    fn corridor(seed: u64) -> Vec<Point3<f64>> {
        crate::test_scenes::corridor(seed, 6000, 20.0)
    }

    fn settings() -> IcpSettings {
        IcpSettings {
            max_iterations: 1,
            convergence: 1e-4,
            max_distance: 1.0,
            kernel: 1.0,
        }
    }

    #[test]
    fn planes_leave_the_corridor_axis_free_and_pull_across_it() {
        let mut map = VoxelHashMap::new(0.5, 100.0, 20);
        map.update(&corridor(1), &Isometry3::identity());
        let shifted: Vec<_> = corridor(2)
            .iter()
            .map(|p| p + Vector3::new(0.3, 0.1, 0.0))
            .collect();
        let mut cache = NormalCache::default();
        let sys = plane_system(&shifted, &map, &settings(), &mut cache);
        assert!(sys.count > 5000);
        // Along x (the axis) the information is far below that across the walls (y); the
        // point-to-point terms of upstream have as much along x as along y.
        assert!(sys.jtj[(0, 0)] < 1e-2 * sys.jtj[(1, 1)], "{}", sys.jtj);
        let p2p = crate::kiss_icp::icp::build_system(&shifted, &map, &settings());
        assert!(p2p.jtj[(0, 0)] > 0.5 * p2p.jtj[(1, 1)], "{}", p2p.jtj);
        // The step pulls back across the corridor and not along it.
        let h = sys.jtj.fixed_view::<3, 3>(1, 1).into_owned();
        let g = sys.jtr.fixed_rows::<3>(1).into_owned();
        let dy = -(h.cholesky().map(|c| c.solve(&g)).unwrap_or_default())[0];
        assert!((dy + 0.1).abs() < 0.02, "step across: {dy}");
        // The cache answers the second iteration without new normals.
        let cached = cache.normals.len();
        let again = plane_system(&shifted, &map, &settings(), &mut cache);
        assert_eq!(cache.normals.len(), cached);
        assert_eq!(again.jtj, sys.jtj);
    }
}
