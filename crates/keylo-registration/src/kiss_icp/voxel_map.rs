//! The local map: a voxel hash holding up to `max_points_per_voxel` points per voxel.
//!
//! Upstream KISS-ICP bounds the map only by distance (voxels farther than `max_range` from the
//! sensor are dropped). In a closed space that bound never bites, and a slowly drifting
//! estimate smears the same walls into ever new voxels, so the map can grow without end. Two
//! optional bounds, both by recency (each voxel remembers the last frame that put a point in
//! it, whether or not the point was kept), close that gap: voxels unseen for more than
//! `max_voxel_age` frames are dropped, and when the map holds more than `max_map_points`
//! points the least recently seen voxels are dropped until it holds at most 95 % of that.

use nalgebra::{Isometry3, Point3, Vector3};

use crate::voxel::{voxel_of, Voxel, VoxelMap};

/// Offsets of the 27 voxels around (and including) a query voxel, in upstream's order
/// (centre first), so that ties between equally near points resolve as upstream resolves them.
pub(crate) const NEIGHBOURS: [Voxel; 27] = [
    [0, 0, 0],
    [1, 0, 0],
    [-1, 0, 0],
    [0, 1, 0],
    [0, -1, 0],
    [0, 0, 1],
    [0, 0, -1],
    [1, 1, 0],
    [1, -1, 0],
    [-1, 1, 0],
    [-1, -1, 0],
    [1, 0, 1],
    [1, 0, -1],
    [-1, 0, 1],
    [-1, 0, -1],
    [0, 1, 1],
    [0, 1, -1],
    [0, -1, 1],
    [0, -1, -1],
    [1, 1, 1],
    [1, 1, -1],
    [1, -1, 1],
    [1, -1, -1],
    [-1, 1, 1],
    [-1, 1, -1],
    [-1, -1, 1],
    [-1, -1, -1],
];

/// Distances from a point to the low and high faces of its voxel, per axis.
pub(crate) struct Faces {
    below: [f64; 3],
    above: [f64; 3],
}

/// The voxel (edge `voxel_size`) of `query` and its distances to the voxel's low and high
/// faces, per axis.
#[inline]
pub(crate) fn faces(query: &Point3<f64>, voxel_size: f64) -> (Voxel, Faces) {
    let v = voxel_of(query, voxel_size);
    let mut below = [0.0; 3];
    let mut above = [0.0; 3];
    for k in 0..3 {
        let low = f64::from(v[k]) * voxel_size;
        below[k] = query[k] - low;
        above[k] = low + voxel_size - query[k];
    }
    (v, Faces { below, above })
}

/// The squared distance from the point of `f` to the voxel at offset `d` from its own (a
/// voxel that far cannot hold a point nearer than that).
#[inline]
pub(crate) fn gap2(d: &Voxel, f: &Faces) -> f64 {
    let mut g = 0.0;
    for (k, step) in d.iter().enumerate() {
        g += match step {
            1 => f.above[k] * f.above[k],
            -1 => f.below[k] * f.below[k],
            _ => 0.0,
        };
    }
    g
}

/// The nearest point found so far, closer than a bound.
struct Nearest {
    best: Option<Point3<f64>>,
    d2: f64,
}

impl Nearest {
    #[inline]
    fn within(max_distance: f64) -> Self {
        Self {
            best: None,
            d2: max_distance * max_distance,
        }
    }

    /// Keeps the first of `points` strictly nearer `query` than the best so far.
    #[inline]
    fn scan(&mut self, points: &[Point3<f64>], query: &Point3<f64>) {
        for p in points {
            let d2 = (p - query).norm_squared();
            if d2 < self.d2 {
                self.best = Some(*p);
                self.d2 = d2;
            }
        }
    }

    #[inline]
    fn found(&self) -> Option<(Point3<f64>, f64)> {
        self.best.map(|p| (p, self.d2.sqrt()))
    }
}

#[derive(Debug, Clone)]
struct Block {
    points: Vec<Point3<f64>>,
    seen: u64,
}

/// Recency bounds of the map (0 = off, upstream's behaviour).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct MapLimits {
    /// Points the map may hold at most.
    pub max_points: usize,
    /// Updates a voxel may go without a new point before it is dropped.
    pub max_age: u64,
}

/// A voxel-hash point map, as upstream's `VoxelHashMap`, with optional recency bounds.
#[derive(Debug, Clone)]
pub struct VoxelHashMap {
    voxel_size: f64,
    max_distance: f64,
    max_points_per_voxel: usize,
    limits: MapLimits,
    updates: u64,
    len: usize,
    map: VoxelMap<Block>,
    /// Voxels whose points the last [`VoxelHashMap::update`] changed (added to, created,
    /// removed), possibly repeated.
    changed: Vec<Voxel>,
}

impl VoxelHashMap {
    /// An empty map; points farther than `max_distance` from the sensor are pruned.
    pub fn new(voxel_size: f64, max_distance: f64, max_points_per_voxel: usize) -> Self {
        Self {
            voxel_size,
            max_distance,
            max_points_per_voxel,
            limits: MapLimits::default(),
            updates: 0,
            len: 0,
            map: VoxelMap::default(),
            changed: Vec::new(),
        }
    }

    /// How many times [`VoxelHashMap::update`] has run: the map's version.
    pub fn updates(&self) -> u64 {
        self.updates
    }

    /// The voxels whose points the last update changed (a voxel not listed holds the same
    /// points, in the same order, as before it); possibly repeated.
    pub fn changed_in_last_update(&self) -> &[Voxel] {
        &self.changed
    }

    /// The same map with recency bounds.
    pub fn with_limits(mut self, limits: MapLimits) -> Self {
        self.limits = limits;
        self
    }

    /// True when the map holds no point.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Number of points in the map.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Every map point.
    pub fn points(&self) -> Vec<Point3<f64>> {
        self.map
            .values()
            .flat_map(|b| b.points.iter())
            .copied()
            .collect()
    }

    /// Nearest map point to `query` among the 27 voxels around it, with its distance, if it is
    /// closer than `max_distance` (upstream searches all 27 voxels and then applies the
    /// threshold; skipping voxels that cannot hold a point closer than both the best so far and
    /// `max_distance` gives the same answer with far fewer lookups).
    #[inline]
    pub fn closest_neighbour_within(
        &self,
        query: &Point3<f64>,
        max_distance: f64,
    ) -> Option<(Point3<f64>, f64)> {
        let (v, faces) = self.faces(query);
        let mut nearest = Nearest::within(max_distance);
        for d in NEIGHBOURS {
            if gap2(&d, &faces) >= nearest.d2 {
                continue;
            }
            if let Some(block) = self.block_at(&v, &d) {
                nearest.scan(&block.points, query);
            }
        }
        nearest.found()
    }

    /// What [`VoxelHashMap::closest_neighbour_within`] returns, searching `around`, the blocks
    /// of [`VoxelHashMap::extend_with_blocks_around`] for `query`'s voxel, instead of looking
    /// them up: the same blocks in the same order, so the same answer.
    #[inline]
    pub(crate) fn closest_among(
        &self,
        query: &Point3<f64>,
        around: &[(u8, &[Point3<f64>])],
        max_distance: f64,
    ) -> Option<(Point3<f64>, f64)> {
        let (_, faces) = self.faces(query);
        let mut nearest = Nearest::within(max_distance);
        for &(k, points) in around {
            if gap2(&NEIGHBOURS[usize::from(k)], &faces) < nearest.d2 {
                nearest.scan(points, query);
            }
        }
        nearest.found()
    }

    /// Appends to `out` the points of every map voxel among the 27 around voxel `v` that
    /// holds any, with its index in [`NEIGHBOURS`], in that order.
    pub(crate) fn extend_with_blocks_around<'m>(
        &'m self,
        v: Voxel,
        out: &mut Vec<(u8, &'m [Point3<f64>])>,
    ) {
        for (k, d) in (0u8..).zip(NEIGHBOURS) {
            if let Some(block) = self.block_at(&v, &d) {
                out.push((k, &block.points));
            }
        }
    }

    /// The block of the voxel at offset `d` from voxel `v`, if the map holds one.
    #[inline]
    fn block_at(&self, v: &Voxel, d: &Voxel) -> Option<&Block> {
        self.map.get(&[v[0] + d[0], v[1] + d[1], v[2] + d[2]])
    }

    /// The voxel of `query` in this map.
    #[inline]
    pub(crate) fn voxel(&self, query: &Point3<f64>) -> Voxel {
        voxel_of(query, self.voxel_size)
    }

    /// The voxel edge (m).
    pub fn voxel_size(&self) -> f64 {
        self.voxel_size
    }

    /// The voxel of `query` and its distances to the voxel's low and high faces, per axis.
    #[inline]
    fn faces(&self, query: &Point3<f64>) -> (Voxel, Faces) {
        faces(query, self.voxel_size)
    }

    /// Appends to `out` the map points closer than `radius` (at most one voxel edge) to
    /// `query`, in the 27 voxels' order. Voxels farther than `radius` (with a margin far
    /// above rounding) are not looked up: they hold no such point.
    pub fn points_within(&self, query: &Point3<f64>, radius: f64, out: &mut Vec<Point3<f64>>) {
        let (v, faces) = self.faces(query);
        let r2 = radius * radius;
        let skip = r2 * (1.0 + 1e-9);
        for d in NEIGHBOURS {
            if gap2(&d, &faces) >= skip {
                continue;
            }
            let Some(block) = self.block_at(&v, &d) else {
                continue;
            };
            out.extend(
                block
                    .points
                    .iter()
                    .filter(|p| (*p - query).norm_squared() < r2),
            );
        }
    }

    /// Nearest map point among the 27 voxels around `query`, at any distance.
    pub fn closest_neighbour(&self, query: &Point3<f64>) -> Option<(Point3<f64>, f64)> {
        self.closest_neighbour_within(query, f64::INFINITY)
    }

    /// Adds `points` (sensor frame) seen from `pose`, then prunes far points and applies the
    /// recency bounds.
    pub fn update(&mut self, points: &[Point3<f64>], pose: &Isometry3<f64>) {
        self.updates += 1;
        self.changed.clear();
        let resolution2 = self.voxel_size * self.voxel_size / self.max_points_per_voxel as f64;
        for p in points {
            self.add_point(pose * p, resolution2);
        }
        self.prune(&pose.translation.vector);
        self.cap();
    }

    fn add_point(&mut self, point: Point3<f64>, resolution2: f64) {
        let voxel = voxel_of(&point, self.voxel_size);
        let max = self.max_points_per_voxel;
        let block = self.map.entry(voxel).or_insert_with(|| Block {
            points: Vec::with_capacity(max),
            seen: 0,
        });
        block.seen = self.updates;
        if block.points.len() >= max
            || block
                .points
                .iter()
                .any(|q| (q - point).norm_squared() < resolution2)
        {
            return;
        }
        block.points.push(point);
        self.len += 1;
        self.changed.push(voxel);
    }

    /// Drops voxels far from `origin` (upstream) and, with `max_age`, voxels unseen too long.
    fn prune(&mut self, origin: &Vector3<f64>) {
        let max2 = self.max_distance * self.max_distance;
        let (now, max_age) = (self.updates, self.limits.max_age);
        let mut removed = 0;
        let changed = &mut self.changed;
        self.map.retain(|voxel, block| {
            let keep = block
                .points
                .first()
                .is_some_and(|p| (p.coords - origin).norm_squared() < max2)
                && (max_age == 0 || now - block.seen <= max_age);
            if !keep {
                removed += block.points.len();
                changed.push(*voxel);
            }
            keep
        });
        self.len -= removed;
    }

    /// With `max_points`, drops the least recently seen voxels (ties: by voxel index, so the
    /// result does not depend on the hash order) until at most 95 % of the bound is left.
    fn cap(&mut self) {
        let bound = self.limits.max_points;
        if bound == 0 || self.len <= bound {
            return;
        }
        let target = bound - bound / 20;
        let mut order: Vec<(u64, Voxel, usize)> = self
            .map
            .iter()
            .map(|(v, b)| (b.seen, *v, b.points.len()))
            .collect();
        order.sort_unstable();
        for (_, voxel, n) in order {
            if self.len <= target {
                break;
            }
            self.map.remove(&voxel);
            self.len -= n;
            self.changed.push(voxel);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Brute force over the 27 voxels, as upstream does.
    fn brute(map: &VoxelHashMap, q: &Point3<f64>) -> Option<(Point3<f64>, f64)> {
        map.points()
            .into_iter()
            .filter(|p| {
                let (a, b) = (voxel_of(p, map.voxel_size), voxel_of(q, map.voxel_size));
                (0..3).all(|k| (a[k] - b[k]).abs() <= 1)
            })
            .map(|p| (p, (p - q).norm()))
            .min_by(|a, b| a.1.total_cmp(&b.1))
    }

    #[test]
    fn points_within_skips_only_voxels_without_such_points() {
        let mut state = 11u64;
        let mut rnd = move || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64 * 4.0 - 2.0
        };
        let pts: Vec<_> = (0..4000)
            .map(|_| Point3::new(rnd(), rnd(), rnd()))
            .collect();
        let mut map = VoxelHashMap::new(0.5, 100.0, 20);
        map.update(&pts, &Isometry3::identity());
        let mut out = Vec::new();
        for _ in 0..1000 {
            let q = Point3::new(rnd(), rnd(), rnd());
            out.clear();
            map.points_within(&q, 0.5, &mut out);
            let v = voxel_of(&q, 0.5);
            let mut all = Vec::new();
            for d in NEIGHBOURS {
                if let Some(b) = map.map.get(&[v[0] + d[0], v[1] + d[1], v[2] + d[2]]) {
                    all.extend(b.points.iter().filter(|p| (*p - q).norm_squared() < 0.25));
                }
            }
            assert_eq!(out, all);
        }
    }

    #[test]
    fn pruned_search_equals_brute_force() {
        let mut state = 7u64;
        let mut rnd = move || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64 * 6.0 - 3.0
        };
        let pts: Vec<_> = (0..3000)
            .map(|_| Point3::new(rnd(), rnd(), rnd()))
            .collect();
        let mut map = VoxelHashMap::new(0.5, 100.0, 20);
        map.update(&pts, &Isometry3::identity());
        for _ in 0..2000 {
            let q = Point3::new(rnd(), rnd(), rnd());
            let expected = brute(&map, &q);
            assert_eq!(map.closest_neighbour(&q), expected);
            let within = map.closest_neighbour_within(&q, 0.1);
            assert_eq!(within, expected.filter(|(_, d)| *d < 0.1));
        }
    }

    #[test]
    fn neighbours_cover_the_cube() {
        let mut n = NEIGHBOURS.to_vec();
        n.sort_unstable();
        n.dedup();
        assert_eq!(n.len(), 27);
        assert!(n.contains(&[0, 0, 0]) && n.contains(&[-1, 1, -1]));
    }

    #[test]
    fn caps_points_per_voxel_and_keeps_spacing() {
        let mut map = VoxelHashMap::new(1.0, 100.0, 4);
        let pts: Vec<_> = (0..100)
            .map(|i| Point3::new(0.01 * f64::from(i % 10), 0.5, 0.5))
            .collect();
        map.update(&pts, &Isometry3::identity());
        assert!(map.len() <= 4);
        // resolution = sqrt(1/4) = 0.5: points 0.01 apart are rejected
        assert_eq!(map.len(), 1);
    }

    #[test]
    fn finds_nearest_across_voxel_borders_and_prunes() {
        let mut map = VoxelHashMap::new(1.0, 5.0, 20);
        map.update(
            &[Point3::new(1.05, 0.0, 0.0), Point3::new(3.0, 0.0, 0.0)],
            &Isometry3::identity(),
        );
        let (p, d) = map.closest_neighbour(&Point3::new(0.95, 0.0, 0.0)).unwrap();
        assert!((p.x - 1.05).abs() < 1e-12 && (d - 0.1).abs() < 1e-12);
        assert!(map
            .closest_neighbour(&Point3::new(-5.0, 0.0, 0.0))
            .is_none());
        let far = Isometry3::translation(10.0, 0.0, 0.0);
        map.update(&[], &far);
        assert!(map.is_empty());
    }

    /// A wall of points 0.25 m apart at `x`, one per 1 m voxel row.
    fn wall(x: f64) -> Vec<Point3<f64>> {
        (0..20)
            .flat_map(|i| (0..4).map(move |j| Point3::new(x, f64::from(i), f64::from(j))))
            .collect()
    }

    #[test]
    fn unseen_voxels_age_out() {
        let limits = MapLimits {
            max_points: 0,
            max_age: 3,
        };
        let mut map = VoxelHashMap::new(1.0, 100.0, 20).with_limits(limits);
        let at = Isometry3::identity();
        map.update(&wall(0.5), &at);
        let one_wall = map.len();
        // A drifting estimate: the same wall lands 1 m further each update.
        for k in 1..50 {
            map.update(&wall(0.5 + f64::from(k)), &at);
            assert!(map.len() <= 4 * one_wall, "update {k}: {}", map.len());
        }
        assert_eq!(map.len(), map.points().len());
        // Voxels still being seen stay, however old they are.
        let mut still = VoxelHashMap::new(1.0, 100.0, 20).with_limits(limits);
        for _ in 0..50 {
            still.update(&wall(0.5), &at);
        }
        assert_eq!(still.len(), one_wall);
    }

    #[test]
    fn point_bound_drops_least_recently_seen() {
        let limits = MapLimits {
            max_points: 1000,
            max_age: 0,
        };
        let mut map = VoxelHashMap::new(1.0, 1000.0, 20).with_limits(limits);
        let at = Isometry3::identity();
        for k in 0..40 {
            map.update(&wall(0.5 + f64::from(k)), &at);
            assert!(map.len() <= 1000, "update {k}: {}", map.len());
        }
        assert_eq!(map.len(), map.points().len());
        assert!(map.len() >= 950 - wall(0.0).len());
        // What is left is the newest walls.
        let oldest = map
            .points()
            .iter()
            .map(|p| p.x)
            .fold(f64::INFINITY, f64::min);
        assert!(oldest > 25.0, "oldest kept wall at x = {oldest}");
        // Without bounds the map keeps everything, as upstream.
        let mut free = VoxelHashMap::new(1.0, 1000.0, 20);
        for k in 0..40 {
            free.update(&wall(0.5 + f64::from(k)), &at);
        }
        assert_eq!(free.len(), 40 * wall(0.0).len());
    }
}
