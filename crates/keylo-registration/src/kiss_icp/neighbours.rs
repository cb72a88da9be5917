//! The map blocks around each source point, kept between ICP iterations.
//!
//! Within one alignment the map does not change and most points stay in their voxel from one
//! iteration to the next, so the voxels around a point are looked up once and searched again
//! until the point moves to another voxel. On the simulated road, 66 % of the lookups of a
//! nearest-neighbour search find no voxel and a search looks up 6.7 voxels; with the blocks
//! kept, a search reads only the ones that exist. The answer is the one of
//! [`VoxelHashMap::closest_neighbour_within`]: the same blocks, in the same order. The blocks
//! of a chunk of points share one vector (a vector per point made the allocator a tenth of
//! the hybrid registrar's time on KITTI).

use std::ops::Range;

use keylo_core::voxel::Voxel;
use nalgebra::Point3;

use super::voxel_map::VoxelHashMap;

/// The blocks around the source points of one chunk of an alignment: per point its voxel when
/// they were looked up and its range in `arena`, which holds the map voxels among the 27 around
/// it that hold points (index in the neighbour order, points). One arena per chunk instead of a
/// vector per point: a frame has tens of thousands of points.
#[derive(Default)]
pub(crate) struct ChunkAround<'m> {
    voxels: Vec<Option<Voxel>>,
    ranges: Vec<Range<u32>>,
    arena: Vec<(u8, &'m [Point3<f64>])>,
    /// Entries of `arena` some point's range still covers.
    live: usize,
}

impl<'m> ChunkAround<'m> {
    fn for_points(n: usize) -> Self {
        Self {
            voxels: vec![None; n],
            ranges: vec![0..0; n],
            arena: Vec::new(),
            live: 0,
        }
    }

    /// Nearest map point to `query` (the chunk's point `i`) closer than `max_distance`, as
    /// [`VoxelHashMap::closest_neighbour_within`] finds it; looks the blocks up again when
    /// `query` is in another voxel than last time.
    #[inline]
    pub(crate) fn closest(
        &mut self,
        i: usize,
        map: &'m VoxelHashMap,
        query: &Point3<f64>,
        max_distance: f64,
    ) -> Option<(Point3<f64>, f64)> {
        let v = map.voxel(query);
        if self.voxels[i] != Some(v) {
            self.compact_if_sparse();
            let start = self.arena.len();
            map.extend_with_blocks_around(v, &mut self.arena);
            let range = start as u32..self.arena.len() as u32;
            self.live = self.live + range.len() - self.ranges[i].len();
            self.ranges[i] = range;
            self.voxels[i] = Some(v);
        }
        let r = &self.ranges[i];
        map.closest_among(
            query,
            &self.arena[r.start as usize..r.end as usize],
            max_distance,
        )
    }

    /// Drops the entries no point uses any more once they outnumber the live ones.
    fn compact_if_sparse(&mut self) {
        if self.arena.len() < 2 * self.live + 4096 {
            return;
        }
        let mut arena = Vec::with_capacity(self.live);
        for r in &mut self.ranges {
            let start = arena.len() as u32;
            arena.extend_from_slice(&self.arena[r.start as usize..r.end as usize]);
            *r = start..arena.len() as u32;
        }
        self.arena = arena;
    }
}

/// The kept blocks of every source point of an alignment, in chunks of the source's order.
#[derive(Default)]
pub(crate) struct NeighbourCache<'m> {
    points: usize,
    chunk: usize,
    chunks: Vec<ChunkAround<'m>>,
}

impl<'m> NeighbourCache<'m> {
    /// The chunks for `n` source points split every `chunk` points (as `par_chunks(chunk)`
    /// splits them), started afresh if the cache was made for another split.
    pub(crate) fn chunks(&mut self, n: usize, chunk: usize) -> &mut [ChunkAround<'m>] {
        if self.points != n || self.chunk != chunk {
            let chunk = chunk.max(1);
            self.chunks = (0..n)
                .step_by(chunk)
                .map(|start| ChunkAround::for_points(chunk.min(n - start)))
                .collect();
            self.points = n;
            self.chunk = chunk;
        }
        &mut self.chunks
    }
}

#[cfg(test)]
mod tests {
    use nalgebra::Isometry3;

    use super::*;

    /// Points scattered over a few surfaces, some voxels empty.
    fn map() -> VoxelHashMap {
        let mut state = 99u64;
        let mut rnd = || crate::test_scenes::rnd(&mut state);
        let pts: Vec<_> = (0..4000)
            .map(|i| match i % 3 {
                0 => Point3::new(4.0 * rnd(), 4.0 * rnd(), 0.0),
                1 => Point3::new(4.0 * rnd(), 0.0, 2.0 * rnd()),
                _ => Point3::new(0.0, 4.0 * rnd(), 2.0 * rnd()),
            })
            .collect();
        let mut map = VoxelHashMap::new(0.3, 100.0, 20);
        map.update(&pts, &Isometry3::identity());
        map
    }

    #[test]
    fn cached_search_finds_what_the_plain_search_finds_as_points_move() {
        let map = map();
        let mut cache = NeighbourCache::default();
        let mut same_voxel = 0;
        for step in 0..400 {
            let t = f64::from(step) * 0.01;
            // A point walking through voxels near and far from the surfaces.
            let q = Point3::new(0.05 + t, 0.4 + 0.3 * t.sin(), 0.02 + 0.2 * t.cos().abs());
            let chunk = &mut cache.chunks(1, 512)[0];
            let before = chunk.voxels[0];
            for max_distance in [0.05, 0.3, 1.0, f64::INFINITY] {
                assert_eq!(
                    chunk.closest(0, &map, &q, max_distance),
                    map.closest_neighbour_within(&q, max_distance),
                    "{q:?} {max_distance}"
                );
            }
            same_voxel += usize::from(before == chunk.voxels[0]);
        }
        // The walk stayed in a voxel often enough that the kept blocks were used.
        assert!(same_voxel > 200, "{same_voxel}");
    }

    #[test]
    fn many_points_changing_voxels_keep_finding_the_same_neighbours() {
        // 512 points, each moving to another voxel at most steps: the chunk's arena fills with
        // entries no point uses and is compacted along the way.
        let map = map();
        let mut state = 7u64;
        let start: Vec<_> = (0..512)
            .map(|_| {
                let mut r = || crate::test_scenes::rnd(&mut state);
                Point3::new(3.0 * r(), 3.0 * r(), 1.5 * r())
            })
            .collect();
        let mut cache = NeighbourCache::default();
        let mut compacted = false;
        for step in 0..60 {
            let shift = nalgebra::Vector3::new(0.07, -0.05, 0.03) * f64::from(step % 20);
            let chunk = &mut cache.chunks(start.len(), 512)[0];
            let before = chunk.arena.len();
            for (i, p) in start.iter().enumerate() {
                let q = p + shift;
                assert_eq!(
                    chunk.closest(i, &map, &q, 0.5),
                    map.closest_neighbour_within(&q, 0.5),
                    "step {step}, point {i}"
                );
            }
            compacted |= chunk.arena.len() < before;
        }
        assert!(compacted, "the arena was never compacted");
    }
}
