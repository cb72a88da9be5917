//! One voxel of the global cloud: the running mean of its points and their intensities.

use keylo_core::voxel::{Voxel, VoxelMap};

/// The points that fell into one voxel, as their mean.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct VoxelMean {
    pub mean: [f64; 3],
    pub intensity: f64,
    pub count: u32,
}

impl VoxelMean {
    /// Adds one point (a running mean: no sum grows with the count).
    #[inline]
    pub fn add(&mut self, p: [f64; 3], intensity: f64) {
        self.count = self.count.saturating_add(1);
        let w = 1.0 / f64::from(self.count);
        for (m, v) in self.mean.iter_mut().zip(p) {
            *m += (v - *m) * w;
        }
        self.intensity += (intensity - self.intensity) * w;
    }

    /// Takes in another mean of the same voxel (the points of both, weighted by count).
    pub fn merge(&mut self, other: &Self) {
        let count = self.count.saturating_add(other.count);
        let w = f64::from(other.count) / f64::from(count.max(1));
        for (m, v) in self.mean.iter_mut().zip(other.mean) {
            *m += (v - *m) * w;
        }
        self.intensity += (other.intensity - self.intensity) * w;
        self.count = count;
    }

    /// The mean of one point.
    pub fn first(p: [f64; 3], intensity: f64) -> Self {
        Self {
            mean: p,
            intensity,
            count: 1,
        }
    }

    /// As a row of the saved cloud: `[x, y, z, intensity]`.
    pub fn row(&self) -> [f32; 4] {
        [
            self.mean[0] as f32,
            self.mean[1] as f32,
            self.mean[2] as f32,
            self.intensity as f32,
        ]
    }
}

/// The voxels of one tile.
pub(crate) type Voxels = VoxelMap<VoxelMean>;

/// Bytes of one voxel in a tile file: key (3 × i32), mean (3 × f64), intensity (f64),
/// count (u32), little endian.
const RECORD: usize = 12 + 24 + 8 + 4;

/// A tile's voxels as bytes, ordered by key (the same tile always gives the same bytes).
pub(crate) fn to_bytes(voxels: &Voxels) -> Vec<u8> {
    let mut keys: Vec<&Voxel> = voxels.keys().collect();
    keys.sort_unstable();
    let mut out = Vec::with_capacity(RECORD * keys.len());
    for k in keys {
        let v = &voxels[k];
        for c in k {
            out.extend_from_slice(&c.to_le_bytes());
        }
        for m in v.mean {
            out.extend_from_slice(&m.to_le_bytes());
        }
        out.extend_from_slice(&v.intensity.to_le_bytes());
        out.extend_from_slice(&v.count.to_le_bytes());
    }
    out
}

/// The voxels of [`to_bytes`]' output, or of several such outputs one after the other (the
/// parts of a tile written at different times): records of the same voxel are merged. `Err`
/// says why the bytes are not a tile.
#[cfg(test)]
pub(crate) fn from_bytes(bytes: &[u8]) -> Result<Voxels, String> {
    from_reader(bytes).map_err(|e| e.to_string())
}

/// [`from_bytes`] reading record by record, so memory holds the tile's voxels, not its file
/// (whose parts may repeat voxels many times). The error says why the bytes are not a tile.
pub(crate) fn from_reader(mut reader: impl std::io::Read) -> std::io::Result<Voxels> {
    let mut voxels = Voxels::default();
    let mut r = [0u8; RECORD];
    loop {
        match read_record(&mut reader, &mut r)? {
            0 => break,
            RECORD => {}
            n => {
                return Err(std::io::Error::new(
                    std::io::ErrorKind::InvalidData,
                    format!(
                    "a last record of {n} bytes: not a whole number of {RECORD}-byte voxel records"
                ),
                ))
            }
        }
        let i32_at = |o: usize| i32::from_le_bytes([r[o], r[o + 1], r[o + 2], r[o + 3]]);
        let f64_at = |o: usize| {
            let mut b = [0u8; 8];
            b.copy_from_slice(&r[o..o + 8]);
            f64::from_le_bytes(b)
        };
        let key = [i32_at(0), i32_at(4), i32_at(8)];
        let count = u32::from_le_bytes([r[44], r[45], r[46], r[47]]);
        let v = VoxelMean {
            mean: [f64_at(12), f64_at(20), f64_at(28)],
            intensity: f64_at(36),
            count,
        };
        voxels.entry(key).and_modify(|m| m.merge(&v)).or_insert(v);
    }
    Ok(voxels)
}

/// Fills `r` from `reader` as far as it can: the bytes read (0 at the end).
fn read_record(reader: &mut impl std::io::Read, r: &mut [u8; RECORD]) -> std::io::Result<usize> {
    let mut filled = 0;
    while filled < RECORD {
        match reader.read(&mut r[filled..]) {
            Ok(0) => break,
            Ok(n) => filled += n,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
            Err(e) => return Err(e),
        }
    }
    Ok(filled)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn means_and_tile_bytes_round_trip() {
        let mut v = VoxelMean::first([1.0, 2.0, 3.0], 10.0);
        v.add([3.0, 4.0, 5.0], 20.0);
        v.add([2.0, 3.0, 4.0], 30.0);
        assert_eq!(v.mean, [2.0, 3.0, 4.0]);
        assert_eq!((v.intensity, v.count), (20.0, 3));
        let mut voxels = Voxels::default();
        voxels.insert([-1, 0, 7], v);
        voxels.insert([5, -9, 0], VoxelMean::first([0.5, -0.25, 1e3], 0.0));
        let bytes = to_bytes(&voxels);
        assert_eq!(from_bytes(&bytes).unwrap(), voxels);
        // Two parts of the same tile: the voxel in both is merged by count.
        let mut later = Voxels::default();
        later.insert([-1, 0, 7], VoxelMean::first([6.0, 7.0, 8.0], 40.0));
        let parts = [bytes.clone(), to_bytes(&later)].concat();
        let merged = from_bytes(&parts).unwrap();
        assert_eq!(merged.len(), 2);
        assert_eq!(merged[&[-1, 0, 7]].mean, [3.0, 4.0, 5.0]);
        assert_eq!(
            (merged[&[-1, 0, 7]].intensity, merged[&[-1, 0, 7]].count),
            (25.0, 4)
        );
        assert!(from_bytes(&bytes[1..])
            .unwrap_err()
            .contains("whole number"));
        assert!(from_bytes(&[]).unwrap().is_empty());
    }
}
