//! The map blocks around each source point, kept between ICP iterations.
//!
//! Within one alignment the map does not change and most points stay in their voxel from one
//! iteration to the next, so the voxels around a point are looked up once and searched again
//! until the point moves to another voxel. On the simulated road, 66 % of the lookups of a
//! nearest-neighbour search find no voxel and a search looks up 6.7 voxels; with the blocks
//! kept, a search reads only the ones that exist. The answer is the one of
//! [`VoxelHashMap::closest_neighbour_within`]: the same blocks, in the same order.

use keylo_core::voxel::Voxel;
use nalgebra::Point3;

use super::voxel_map::VoxelHashMap;

/// The blocks around one source point: its voxel when they were looked up, and the map
/// voxels among the 27 around it that hold points (index in the neighbour order, points).
#[derive(Default)]
pub(crate) struct Around<'m> {
    voxel: Option<Voxel>,
    blocks: Vec<(u8, &'m [Point3<f64>])>,
}

impl<'m> Around<'m> {
    /// Nearest map point to `query` closer than `max_distance`, as
    /// [`VoxelHashMap::closest_neighbour_within`] finds it; looks the blocks up again when
    /// `query` is in another voxel than last time.
    #[inline]
    pub(crate) fn closest(
        &mut self,
        map: &'m VoxelHashMap,
        query: &Point3<f64>,
        max_distance: f64,
    ) -> Option<(Point3<f64>, f64)> {
        let v = map.voxel(query);
        if self.voxel != Some(v) {
            map.blocks_around(v, &mut self.blocks);
            self.voxel = Some(v);
        }
        map.closest_among(query, &self.blocks, max_distance)
    }
}

/// One [`Around`] per source point of an alignment, in the source's order.
#[derive(Default)]
pub(crate) struct NeighbourCache<'m> {
    pub(crate) points: Vec<Around<'m>>,
}

impl NeighbourCache<'_> {
    /// A cache for `n` source points, nothing looked up yet.
    pub(crate) fn for_points(n: usize) -> Self {
        let mut points = Vec::with_capacity(n);
        points.resize_with(n, Around::default);
        Self { points }
    }
}

#[cfg(test)]
mod tests {
    use nalgebra::Isometry3;

    use super::*;

    /// Points scattered over a few surfaces, some voxels empty.
    fn map() -> VoxelHashMap {
        let mut state = 99u64;
        let mut rnd = move || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
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
        let mut around = Around::default();
        let mut same_voxel = 0;
        for step in 0..400 {
            let t = f64::from(step) * 0.01;
            // A point walking through voxels near and far from the surfaces.
            let q = Point3::new(0.05 + t, 0.4 + 0.3 * t.sin(), 0.02 + 0.2 * t.cos().abs());
            let before = around.voxel;
            for max_distance in [0.05, 0.3, 1.0, f64::INFINITY] {
                assert_eq!(
                    around.closest(&map, &q, max_distance),
                    map.closest_neighbour_within(&q, max_distance),
                    "{q:?} {max_distance}"
                );
            }
            same_voxel += usize::from(before == around.voxel);
        }
        // The walk stayed in a voxel often enough that the kept blocks were used.
        assert!(same_voxel > 200, "{same_voxel}");
    }
}
