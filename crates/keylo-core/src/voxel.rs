//! Voxel keys, a fixed (deterministic) hasher for them, and first-point voxel downsampling.

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

use nalgebra::Point3;

/// Integer voxel coordinates.
pub type Voxel = [i32; 3];

/// The voxel holding `p` for voxels of edge `size`.
#[inline]
pub fn voxel_of(p: &Point3<f64>, size: f64) -> Voxel {
    [
        floor_i32(p.x / size),
        floor_i32(p.y / size),
        floor_i32(p.z / size),
    ]
}

/// `v.floor() as i32` (saturating, NaN → 0) without `floor`, which is a libm call on
/// baseline x86-64 and was ~4 % of a raw KISS-ICP frame.
#[inline]
fn floor_i32(v: f64) -> i32 {
    let t = v as i32;
    if f64::from(t) > v {
        t.saturating_sub(1)
    } else {
        t
    }
}

/// A fixed-seed (FxHash-style) hasher for voxel keys: the same input always gives the same
/// map layout and iteration order, so runs are reproducible.
#[derive(Default, Clone, Copy)]
pub struct VoxelHasher(u64);

const FX_SEED: u64 = 0x51_7c_c1_b7_27_22_0a_95;

impl VoxelHasher {
    #[inline]
    fn add(&mut self, word: u64) {
        self.0 = (self.0.rotate_left(5) ^ word).wrapping_mul(FX_SEED);
    }
}

impl Hasher for VoxelHasher {
    #[inline]
    fn finish(&self) -> u64 {
        self.0
    }
    #[inline]
    fn write(&mut self, bytes: &[u8]) {
        for chunk in bytes.chunks(4) {
            let mut word = [0u8; 4];
            word[..chunk.len()].copy_from_slice(chunk);
            self.add(u64::from(u32::from_le_bytes(word)));
        }
    }
    #[inline]
    fn write_i32(&mut self, v: i32) {
        self.add(u64::from(v as u32));
    }
    #[inline]
    fn write_usize(&mut self, v: usize) {
        self.add(v as u64);
    }
    #[inline]
    fn write_u64(&mut self, v: u64) {
        self.add(v);
    }
}

/// A hash map keyed by voxel with the deterministic hasher.
pub type VoxelMap<V> = HashMap<Voxel, V, BuildHasherDefault<VoxelHasher>>;

/// Keeps the first point of every voxel of edge `size`, in input order (as upstream does).
///
/// ```
/// use keylo_core::voxel::downsample_indices;
/// use nalgebra::Point3;
/// let pts = [Point3::new(0.1, 0.1, 0.1), Point3::new(0.2, 0.2, 0.2), Point3::new(2.0, 0.0, 0.0)];
/// assert_eq!(downsample_indices(&pts, 1.0), vec![0, 2]);
/// ```
pub fn downsample_indices(points: &[Point3<f64>], size: f64) -> Vec<usize> {
    let mut seen: VoxelMap<()> = VoxelMap::default();
    seen.reserve(points.len() / 4);
    let mut kept = Vec::new();
    for (i, p) in points.iter().enumerate() {
        if seen.insert(voxel_of(p, size), ()).is_none() {
            kept.push(i);
        }
    }
    kept
}

/// The points kept by [`downsample_indices`].
pub fn downsample(points: &[Point3<f64>], size: f64) -> Vec<Point3<f64>> {
    downsample_indices(points, size)
        .into_iter()
        .map(|i| points[i])
        .collect()
}

/// The mean of the points of every voxel of edge `size`, in first-seen voxel order (PCL's
/// `VoxelGrid` filter up to point order).
///
/// ```
/// use keylo_core::voxel::centroids;
/// use nalgebra::Point3;
/// let pts = [Point3::new(0.1, 0.1, 0.1), Point3::new(0.3, 0.3, 0.3), Point3::new(2.0, 0.0, 0.0)];
/// assert_eq!(centroids(&pts, 1.0), vec![Point3::new(0.2, 0.2, 0.2), pts[2]]);
/// ```
pub fn centroids(points: &[Point3<f64>], size: f64) -> Vec<Point3<f64>> {
    let mut slot: VoxelMap<usize> = VoxelMap::default();
    let mut sums: Vec<(nalgebra::Vector3<f64>, f64)> = Vec::new();
    for p in points {
        let k = *slot.entry(voxel_of(p, size)).or_insert_with(|| {
            sums.push((nalgebra::Vector3::zeros(), 0.0));
            sums.len() - 1
        });
        sums[k].0 += p.coords;
        sums[k].1 += 1.0;
    }
    sums.iter().map(|(s, n)| Point3::from(s / *n)).collect()
}

/// Upstream's voxel hash (`std::hash<Voxel>` in kiss-icp): 32-bit products XOR-ed.
#[inline]
fn upstream_hash(v: &Voxel) -> usize {
    ((v[0] as u32).wrapping_mul(73_856_093)
        ^ (v[1] as u32).wrapping_mul(19_349_669)
        ^ (v[2] as u32).wrapping_mul(83_492_791)) as usize
}

/// One bucket of [`UpstreamGrid`].
#[derive(Clone, Copy)]
struct Slot {
    voxel: Voxel,
    /// Index of the point in the input; `u32::MAX` marks an empty bucket.
    index: u32,
    /// Distance from the voxel's home bucket.
    dist: u32,
}

const EMPTY: Slot = Slot {
    voxel: [0; 3],
    index: u32::MAX,
    dist: 0,
};

/// The voxel grid of upstream KISS-ICP's `VoxelDownsample`, reproduced exactly: a
/// `tsl::robin_map` reserved for `points.len()` entries (power-of-two buckets, load factor 0.5,
/// robin-hood linear probing, upstream's voxel hash), keeping the first point of every voxel
/// and yielding the points in the table's iteration order.
///
/// That order decides which point represents a voxel in the second, coarser downsampling and
/// the order in which points enter the local map, so reproducing it makes keylo select exactly
/// the points upstream selects. The bucket array is reused between calls.
#[derive(Default)]
pub struct UpstreamGrid {
    slots: Vec<Slot>,
}

impl UpstreamGrid {
    /// Downsamples `points` with voxels of edge `size` into `out` (cleared first).
    pub fn downsample_into(
        &mut self,
        points: &[Point3<f64>],
        size: f64,
        out: &mut Vec<Point3<f64>>,
    ) {
        out.clear();
        let buckets = (2 * points.len()).max(1).next_power_of_two();
        self.slots.clear();
        self.slots.resize(buckets, EMPTY);
        let mask = buckets - 1;
        for (i, p) in points.iter().enumerate() {
            let voxel = voxel_of(p, size);
            self.insert(voxel, i as u32, upstream_hash(&voxel) & mask, mask);
        }
        out.extend(
            self.slots
                .iter()
                .filter(|s| s.index != u32::MAX)
                .map(|s| points[s.index as usize]),
        );
    }

    /// Robin-hood insertion; a voxel already present is left alone (first point wins).
    #[inline]
    fn insert(&mut self, voxel: Voxel, index: u32, home: usize, mask: usize) {
        let mut entry = Slot {
            voxel,
            index,
            dist: 0,
        };
        let mut b = home;
        let mut displacing = false;
        loop {
            let slot = &mut self.slots[b];
            if slot.index == u32::MAX {
                *slot = entry;
                return;
            }
            if !displacing && slot.voxel == voxel {
                return;
            }
            if slot.dist < entry.dist {
                std::mem::swap(slot, &mut entry);
                displacing = true;
            }
            b = (b + 1) & mask;
            entry.dist += 1;
        }
    }
}

/// [`UpstreamGrid::downsample_into`] with a fresh grid.
pub fn downsample_upstream_order(points: &[Point3<f64>], size: f64) -> Vec<Point3<f64>> {
    let mut out = Vec::new();
    UpstreamGrid::default().downsample_into(points, size, &mut out);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn upstream_order_keeps_the_same_points_in_bucket_order() {
        let pts: Vec<_> = (0..500)
            .map(|i| {
                Point3::new(
                    f64::from(i % 23) * 0.37 - 4.0,
                    f64::from(i % 7) * 0.51,
                    f64::from(i / 50) * 0.3 - 1.0,
                )
            })
            .collect();
        let mut a = downsample(&pts, 0.5);
        let mut b = downsample_upstream_order(&pts, 0.5);
        assert_ne!(a, b, "order should differ from scan order");
        let key = |p: &Point3<f64>| (p.x.to_bits(), p.y.to_bits(), p.z.to_bits());
        a.sort_by_key(key);
        b.sort_by_key(key);
        assert_eq!(a, b);
        // Home buckets are non-decreasing except where probing wrapped around the table end.
        let buckets = 1024usize;
        let homes: Vec<usize> = downsample_upstream_order(&pts, 0.5)
            .iter()
            .map(|p| upstream_hash(&voxel_of(p, 0.5)) & (buckets - 1))
            .collect();
        let descents = homes.windows(2).filter(|w| w[1] < w[0]).count();
        assert!(descents <= 1, "{descents}");
    }

    #[test]
    fn floor_i32_is_floor_then_a_saturating_cast() {
        for v in [
            0.0,
            -0.0,
            0.5,
            -0.5,
            1.0,
            -1.0,
            2.999,
            -2.999,
            1e9,
            -1e9,
            2147483647.5,
            -2147483648.0,
            -2147483648.5,
            -2147483649.0,
            1e300,
            -1e300,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
            f64::MIN_POSITIVE,
            -f64::MIN_POSITIVE,
        ] {
            assert_eq!(floor_i32(v), v.floor() as i32, "{v}");
        }
        let mut x = -1000.0;
        while x < 1000.0 {
            assert_eq!(floor_i32(x), x.floor() as i32, "{x}");
            x += 0.037_31;
        }
    }

    #[test]
    fn negative_coordinates_floor() {
        assert_eq!(voxel_of(&Point3::new(-0.1, 0.0, 1.0), 1.0), [-1, 0, 1]);
        assert_eq!(voxel_of(&Point3::new(-1.0, -1.5, 0.99), 0.5), [-2, -3, 1]);
    }

    #[test]
    fn one_point_per_voxel() {
        let pts: Vec<_> = (0..1000)
            .map(|i| Point3::new(f64::from(i % 10) * 0.1, f64::from(i / 100) * 0.1, 0.0))
            .collect();
        let out = downsample(&pts, 0.5);
        let mut voxels: Vec<_> = out.iter().map(|p| voxel_of(p, 0.5)).collect();
        voxels.sort_unstable();
        voxels.dedup();
        assert_eq!(voxels.len(), out.len());
        assert_eq!(out.len(), 4);
    }
}
