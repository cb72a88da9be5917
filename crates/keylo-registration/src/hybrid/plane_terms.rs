//! Point-to-plane cloud residuals against the local map: `r = nᵀ(p − q)` with `q` the nearest
//! map point and `n` the direction in which the map points within one voxel of `q` spread
//! least (PCL's normal estimate, planar or not: across a wall-floor edge or a scan line it has
//! no component along it). A point whose neighbour has fewer than 5 map points around it gives
//! no residual: there the map is sparse, mostly at its frontier, where a point-to-point pull
//! would point back into the map. Unlike point-to-point terms, these say nothing along a plane
//! or an edge, so in a corridor the cloud leaves the axis to the keypoints instead of pulling
//! towards the nearest samples.
//!
//! Normals are computed once per map point and kept across frames until the map changes
//! around the point ([`NormalCache`]).

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hash, Hasher};

use keylo_core::voxel::{voxel_of, Voxel, VoxelHasher, VoxelMap};
use nalgebra::{Isometry3, Point3, RowVector6, Vector3};
use rayon::prelude::*;

use crate::degeneracy::{normals_of, plane_information_with, PlaneInformation};
use crate::kiss_icp::icp::{IcpSettings, System};
use crate::kiss_icp::neighbours::NeighbourCache;
use crate::kiss_icp::voxel_map::{VoxelHashMap, NEIGHBOURS};

/// Points per parallel work item; sums are reduced in chunk order (thread-count independent).
const CHUNK: usize = 512;

/// The two normals of a map point's neighbourhood (the map points within one voxel of it):
/// the direction of least spread ([`normal_at`]; `None`: fewer than 5 points) and the normal
/// when the neighbourhood is planar (the degeneracy analysis's).
#[derive(Debug, Clone, Copy, Default)]
pub struct Normals {
    pub least: Option<Vector3<f64>>,
    pub planar: Option<Vector3<f64>>,
}

/// Map points' [`Normals`], keyed by the point's bits. They depend only on the map points in
/// the 27 voxels around the point's voxel (which hold every point within one voxel of it), so
/// after a map update only those around the voxels it changed are dropped; the others are
/// exactly what would be computed again. Shared by the point-to-plane terms and the degeneracy
/// analyses of a frame.
#[derive(Debug, Default)]
pub struct NormalCache {
    normals: HashMap<Key, Normals, BuildHasherDefault<VoxelHasher>>,
    /// The cached points of each voxel, to drop them when the map changes around it.
    by_voxel: VoxelMap<Vec<Key>>,
    /// The map's [`VoxelHashMap::updates`] the normals are of (`None`: none yet).
    synced: Option<u64>,
}

/// The voxel at offset `d` from `v`.
fn offset(v: &Voxel, d: &Voxel) -> Voxel {
    [v[0] + d[0], v[1] + d[1], v[2] + d[2]]
}

/// Removes `keys` from `normals`.
fn forget(keys: Vec<Key>, normals: &mut HashMap<Key, Normals, BuildHasherDefault<VoxelHasher>>) {
    for k in keys {
        normals.remove(&k);
    }
}

/// A map point's bits, hashed as three words.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
struct Key([u64; 3]);

impl Hash for Key {
    fn hash<H: Hasher>(&self, state: &mut H) {
        for w in self.0 {
            state.write_u64(w);
        }
    }
}

fn key(q: &Point3<f64>) -> Key {
    Key([q.x.to_bits(), q.y.to_bits(), q.z.to_bits()])
}

impl NormalCache {
    /// Forgets every normal.
    pub fn clear(&mut self) {
        self.normals.clear();
        self.by_voxel.clear();
        self.synced = None;
    }

    /// Keeps the normals still valid for `map`: all when it is the map they were computed on,
    /// those away from the voxels its last update changed when it is one update later, none
    /// otherwise.
    fn sync(&mut self, map: &VoxelHashMap) {
        let now = map.updates();
        match self.synced {
            Some(v) if v == now => {}
            Some(v) if v + 1 == now => self.drop_around(map.changed_in_last_update()),
            _ => {
                self.normals.clear();
                self.by_voxel.clear();
            }
        }
        self.synced = Some(now);
    }

    /// Drops the normals of the points in the 27 voxels around each of `changed` (which may
    /// repeat). Walks whichever is smaller: the changed voxels' neighbourhoods, or the cached
    /// voxels (asking whether a changed voxel is among their 27); both drop the same normals.
    fn drop_around(&mut self, changed: &[Voxel]) {
        let changed: VoxelMap<()> = changed.iter().map(|c| (*c, ())).collect();
        if changed.len() <= self.by_voxel.len() {
            self.drop_around_changed(&changed);
        } else {
            self.drop_near_changed(&changed);
        }
    }

    /// [`NormalCache::drop_around`] walking the changed voxels.
    fn drop_around_changed(&mut self, changed: &VoxelMap<()>) {
        for c in changed.keys() {
            for d in NEIGHBOURS {
                if let Some(keys) = self.by_voxel.remove(&offset(c, &d)) {
                    forget(keys, &mut self.normals);
                }
            }
        }
    }

    /// [`NormalCache::drop_around`] walking the cached voxels.
    fn drop_near_changed(&mut self, changed: &VoxelMap<()>) {
        let normals = &mut self.normals;
        self.by_voxel.retain(|v, keys| {
            let near = NEIGHBOURS
                .iter()
                .any(|d| changed.contains_key(&offset(v, d)));
            if near {
                forget(std::mem::take(keys), normals);
            }
            !near
        });
    }

    /// Computes (in parallel) and caches the normals of the map points `qs` not cached yet.
    pub fn fill<'a>(&mut self, map: &VoxelHashMap, qs: impl Iterator<Item = &'a Point3<f64>>) {
        self.sync(map);
        let size = map.voxel_size();
        let mut fresh: Vec<Point3<f64>> = qs
            .filter(|q| !self.normals.contains_key(&key(q)))
            .copied()
            .collect();
        fresh.sort_unstable_by_key(key);
        fresh.dedup();
        let computed: Vec<Normals> = fresh
            .par_iter()
            .with_min_len(64)
            .map_init(Vec::new, |near, q| normals_at(map, q, near))
            .collect();
        for (q, n) in fresh.iter().zip(computed) {
            self.normals.insert(key(q), n);
            self.by_voxel
                .entry(voxel_of(q, size))
                .or_default()
                .push(key(q));
        }
    }

    /// The normals of `qs` (each filled before; a missing one counts as none), in order.
    pub fn normals_of(&self, qs: &[Option<Point3<f64>>]) -> Vec<Normals> {
        qs.par_iter()
            .with_min_len(CHUNK)
            .map(|q| {
                q.and_then(|q| self.normals.get(&key(&q)).copied())
                    .unwrap_or_default()
            })
            .collect()
    }

    /// Normals held (for tests).
    #[cfg(test)]
    fn len(&self) -> usize {
        self.normals.len()
    }
}

/// Both normals of the map around its point `q`; `near` is scratch.
fn normals_at(map: &VoxelHashMap, q: &Point3<f64>, near: &mut Vec<Point3<f64>>) -> Normals {
    near.clear();
    map.points_within(q, map.voxel_size(), near);
    let (least, planar) = normals_of(near);
    Normals { least, planar }
}

/// The normal of the map around its point `q`: the direction of least spread of the map
/// points within one voxel of it; `near` is scratch.
pub(crate) fn normal_at(
    map: &VoxelHashMap,
    q: &Point3<f64>,
    near: &mut Vec<Point3<f64>>,
) -> Option<Vector3<f64>> {
    normals_at(map, q, near).least
}

/// The degeneracy information ([`crate::degeneracy::plane_information`], the same result) of
/// `source` at `pose`, its normals taken from (and added to) `cache`.
pub(crate) fn plane_information_cached(
    source: &[Point3<f64>],
    map: &VoxelHashMap,
    pose: &Isometry3<f64>,
    (max_distance, max_points): (f64, usize),
    cache: &mut NormalCache,
) -> PlaneInformation {
    plane_information_with(source, map, pose, max_distance, max_points, |qs| {
        cache.fill(map, qs.iter().flatten());
        cache.normals_of(qs).iter().map(|n| n.planar).collect()
    })
}

/// Each source point's nearest map point and its normal in the last call of one alignment
/// (the map does not change within it): a point whose neighbour is the same as last time
/// takes the normal from here instead of from the [`NormalCache`]. Late in an alignment
/// nearly every point keeps its neighbour.
#[derive(Debug, Default)]
pub(crate) struct LastNormals {
    last: Vec<Option<(Key, Option<Vector3<f64>>)>>,
}

/// The normal equations (twist about the world origin, as [`crate::kiss_icp::icp`]) of
/// `source` (world frame) against `map`, of the points whose nearest neighbour has a normal,
/// Geman–McClure weights `κ² / (κ + r²)²` as upstream KISS-ICP's. `around` and `last` keep
/// each point's map blocks and last neighbour's normal between calls of one alignment.
pub(crate) fn plane_system<'m>(
    source: &[Point3<f64>],
    map: &'m VoxelHashMap,
    s: &IcpSettings,
    cache: &mut NormalCache,
    (around, last): (&mut NeighbourCache<'m>, &mut LastNormals),
) -> System {
    let mut pairs: Vec<Option<Point3<f64>>> = vec![None; source.len()];
    pairs
        .par_chunks_mut(CHUNK)
        .zip(source.par_chunks(CHUNK))
        .zip(around.chunks(source.len(), CHUNK).par_iter_mut())
        .for_each(|((qs, ps), around)| {
            for (i, (q, p)) in qs.iter_mut().zip(ps).enumerate() {
                *q = around.closest(i, map, p, s.max_distance).map(|(q, _)| q);
            }
        });
    let normals = last.normals(&pairs, map, cache);
    let partials: Vec<System> = source
        .par_chunks(CHUNK)
        .zip(pairs.par_chunks(CHUNK))
        .zip(normals.par_chunks(CHUNK))
        .map(|((ps, qs), ns)| chunk_system(ps, qs, ns, s.kernel))
        .collect();
    partials.iter().fold(System::zero(), |a, b| a.add(b))
}

impl LastNormals {
    /// The normal (of least spread) of each neighbour in `pairs`: kept from the last call where
    /// the neighbour is the same, else from `cache` (filled first).
    fn normals(
        &mut self,
        pairs: &[Option<Point3<f64>>],
        map: &VoxelHashMap,
        cache: &mut NormalCache,
    ) -> Vec<Option<Vector3<f64>>> {
        if self.last.len() != pairs.len() {
            self.last = vec![None; pairs.len()];
        }
        let mut normals = vec![None; pairs.len()];
        let mut changed: Vec<(usize, Point3<f64>)> = Vec::new();
        for (i, q) in pairs.iter().enumerate() {
            let Some(q) = q else { continue };
            match self.last[i] {
                Some((k, n)) if k == key(q) => normals[i] = n,
                _ => changed.push((i, *q)),
            }
        }
        cache.fill(map, changed.iter().map(|(_, q)| q));
        for (i, q) in changed {
            let n = cache.normals.get(&key(&q)).and_then(|n| n.least);
            normals[i] = n;
            self.last[i] = Some((key(&q), n));
        }
        normals
    }
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
        let sys = plane_system(
            &shifted,
            &map,
            &settings(),
            &mut cache,
            (&mut NeighbourCache::default(), &mut LastNormals::default()),
        );
        assert!(sys.count > 5000);
        // Along x (the axis) the information is far below that across the walls (y); the
        // point-to-point terms of upstream have as much along x as along y.
        assert!(sys.jtj[(0, 0)] < 1e-2 * sys.jtj[(1, 1)], "{}", sys.jtj);
        let p2p = crate::kiss_icp::icp::build_system(
            &shifted,
            &map,
            &settings(),
            &mut NeighbourCache::default(),
        );
        assert!(p2p.jtj[(0, 0)] > 0.5 * p2p.jtj[(1, 1)], "{}", p2p.jtj);
        // The step pulls back across the corridor and not along it.
        let h = sys.jtj.fixed_view::<3, 3>(1, 1).into_owned();
        let g = sys.jtr.fixed_rows::<3>(1).into_owned();
        let dy = -(h.cholesky().map(|c| c.solve(&g)).unwrap_or_default())[0];
        assert!((dy + 0.1).abs() < 0.02, "step across: {dy}");
        // The cache answers the second iteration without new normals.
        let cached = cache.len();
        let again = plane_system(
            &shifted,
            &map,
            &settings(),
            &mut cache,
            (&mut NeighbourCache::default(), &mut LastNormals::default()),
        );
        assert_eq!(cache.len(), cached);
        assert_eq!(again.jtj, sys.jtj);
    }

    /// Both ways of dropping the normals around changed voxels drop the same ones.
    #[test]
    fn both_ways_of_dropping_normals_agree() {
        let mut map = VoxelHashMap::new(0.5, 100.0, 20);
        map.update(&corridor(1), &Isometry3::identity());
        let queries: Vec<Point3<f64>> = map.points().into_iter().step_by(2).collect();
        let mut a = NormalCache::default();
        a.fill(&map, queries.iter());
        let mut b = NormalCache::default();
        b.fill(&map, queries.iter());
        let changed: VoxelMap<()> = [[0, 0, 0], [3, 4, 0], [10, -4, 1], [-2, 3, 0], [3, 4, 0]]
            .into_iter()
            .map(|v| (v, ()))
            .collect();
        a.drop_around_changed(&changed);
        b.drop_near_changed(&changed);
        let kept = |c: &NormalCache| {
            let mut k: Vec<Key> = c.normals.keys().copied().collect();
            k.sort();
            k
        };
        assert_eq!(kept(&a), kept(&b));
        assert!(a.len() < queries.len() && a.len() > queries.len() / 2);
    }

    #[test]
    fn cached_normals_stay_those_of_the_map_after_updates() {
        let mut map = VoxelHashMap::new(0.5, 100.0, 20);
        map.update(&corridor(1), &Isometry3::identity());
        let mut cache = NormalCache::default();
        let queries: Vec<Point3<f64>> = map.points().into_iter().step_by(3).collect();
        for step in 0..4 {
            let qs: Vec<Option<Point3<f64>>> = queries.iter().copied().map(Some).collect();
            cache.fill(&map, queries.iter());
            let cached = cache.normals_of(&qs);
            let mut near = Vec::new();
            for (q, c) in queries.iter().zip(&cached) {
                let fresh = normals_at(&map, q, &mut near);
                assert_eq!(
                    (c.least, c.planar),
                    (fresh.least, fresh.planar),
                    "step {step}"
                );
            }
            // The next frame adds points to part of the corridor only.
            let more: Vec<Point3<f64>> = corridor(10 + step)
                .into_iter()
                .filter(|p| p.x < 5.0 + 3.0 * step as f64)
                .collect();
            map.update(&more, &Isometry3::identity());
        }
        assert!(cache.len() > 100);
    }
}
