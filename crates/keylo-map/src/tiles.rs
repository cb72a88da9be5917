//! The global cloud in square tiles (x, y): the tiles within the sensor's reach stay in
//! memory, the others wait on disk (one file each in a scratch folder) until the sensor
//! comes back or the run ends, so memory follows the area in reach, not the run's length.

use std::collections::{BTreeMap, HashMap};
use std::path::{Path, PathBuf};

use keylo_core::voxel::voxel_of;
use nalgebra::Point3;

use crate::accumulate::{self, VoxelMean, Voxels};
use crate::MapError;

/// A tile's key: `floor(x / tile_size)`, `floor(y / tile_size)`.
pub(crate) type TileKey = (i32, i32);

/// The voxelised cloud of a run, tile by tile.
pub(crate) struct TiledCloud {
    voxel_size: f64,
    tile_size: f64,
    /// Tiles farther than this from the sensor (x, y) leave memory.
    reach: f64,
    resident: HashMap<TileKey, Voxels>,
    /// Tiles on disk and their voxel counts.
    spilled: BTreeMap<TileKey, usize>,
    scratch: PathBuf,
    /// The most voxels held in memory at once.
    pub peak_resident_voxels: usize,
}

impl TiledCloud {
    /// An empty cloud whose tiles spill into `scratch` (created).
    pub fn new(
        voxel_size: f64,
        tile_size: f64,
        reach: f64,
        scratch: &Path,
    ) -> Result<Self, MapError> {
        std::fs::create_dir_all(scratch).map_err(|e| MapError::io(scratch, e))?;
        Ok(Self {
            voxel_size,
            tile_size,
            reach,
            resident: HashMap::new(),
            spilled: BTreeMap::new(),
            scratch: scratch.to_path_buf(),
            peak_resident_voxels: 0,
        })
    }

    fn tile_of(&self, p: &Point3<f64>) -> TileKey {
        let k = voxel_of(&Point3::new(p.x, p.y, 0.0), self.tile_size);
        (k[0], k[1])
    }

    fn tile_path(&self, key: TileKey) -> PathBuf {
        self.scratch.join(format!("{}_{}.bin", key.0, key.1))
    }

    /// Adds world points with their intensities (tile by tile: one tile lookup per tile, not
    /// per point; within a tile in the points' order, so the means are the same).
    pub fn add(&mut self, points: &[Point3<f64>], intensities: &[f32]) -> Result<(), MapError> {
        let mut by_tile: Vec<(TileKey, u32)> = (points.iter().enumerate())
            .map(|(i, p)| (self.tile_of(p), i as u32))
            .collect();
        by_tile.sort_unstable();
        let size = self.voxel_size;
        for run in by_tile.chunk_by(|a, b| a.0 == b.0) {
            let voxels = self.tile_mut(run[0].0)?;
            for &(_, i) in run {
                let (p, v) = (&points[i as usize], f64::from(intensities[i as usize]));
                let xyz = [p.x, p.y, p.z];
                voxels
                    .entry(voxel_of(p, size))
                    .and_modify(|m| m.add(xyz, v))
                    .or_insert_with(|| VoxelMean::first(xyz, v));
            }
        }
        let held = self.resident.values().map(|v| v.len()).sum();
        self.peak_resident_voxels = self.peak_resident_voxels.max(held);
        Ok(())
    }

    /// The tile `key` in memory, read back from disk when it was spilled.
    fn tile_mut(&mut self, key: TileKey) -> Result<&mut Voxels, MapError> {
        if !self.resident.contains_key(&key) {
            let voxels = match self.spilled.remove(&key) {
                Some(_) => {
                    let path = self.tile_path(key);
                    let bytes = std::fs::read(&path).map_err(|e| MapError::io(&path, e))?;
                    accumulate::from_bytes(&bytes).map_err(|m| MapError::format(&path, m))?
                }
                None => Voxels::default(),
            };
            self.resident.insert(key, voxels);
        }
        // Present: inserted above when it was not.
        Ok(self.resident.entry(key).or_default())
    }

    /// Spills every resident tile farther than the reach from `sensor` (x, y).
    pub fn spill_far_from(&mut self, sensor: &Point3<f64>) -> Result<(), MapError> {
        let (t, r) = (self.tile_size, self.reach);
        let far: Vec<TileKey> = (self.resident.keys())
            .copied()
            .filter(|&(i, j)| {
                let (x0, y0) = (f64::from(i) * t, f64::from(j) * t);
                let dx = (x0 - sensor.x).max(sensor.x - (x0 + t)).max(0.0);
                let dy = (y0 - sensor.y).max(sensor.y - (y0 + t)).max(0.0);
                dx * dx + dy * dy > r * r
            })
            .collect();
        for key in far {
            self.spill(key)?;
        }
        Ok(())
    }

    fn spill(&mut self, key: TileKey) -> Result<(), MapError> {
        if let Some(voxels) = self.resident.remove(&key) {
            let path = self.tile_path(key);
            std::fs::write(&path, accumulate::to_bytes(&voxels))
                .map_err(|e| MapError::io(&path, e))?;
            self.spilled.insert(key, voxels.len());
        }
        Ok(())
    }

    /// Spills every tile: afterwards the whole cloud is on disk, and [`Self::tiles`] reads
    /// it back one tile at a time.
    pub fn spill_all(&mut self) -> Result<(), MapError> {
        let keys: Vec<TileKey> = self.resident.keys().copied().collect();
        for key in keys {
            self.spill(key)?;
        }
        Ok(())
    }

    /// Voxels of the whole cloud (after [`Self::spill_all`]).
    pub fn len(&self) -> usize {
        self.spilled.values().sum::<usize>()
            + self.resident.values().map(|v| v.len()).sum::<usize>()
    }

    /// Every spilled tile's voxels in key order, then within a tile in voxel-key order, as
    /// rows `[x, y, z, intensity]` (after [`Self::spill_all`]).
    pub fn rows(&self) -> impl Iterator<Item = Result<Vec<[f32; 4]>, MapError>> + '_ {
        self.spilled.keys().map(|&key| {
            let path = self.tile_path(key);
            let bytes = std::fs::read(&path).map_err(|e| MapError::io(&path, e))?;
            let voxels = accumulate::from_bytes(&bytes).map_err(|m| MapError::format(&path, m))?;
            let mut keyed: Vec<_> = voxels.into_iter().collect();
            keyed.sort_unstable_by_key(|(k, _)| *k);
            Ok(keyed.into_iter().map(|(_, v)| v.row()).collect())
        })
    }

    /// Removes the scratch folder.
    pub fn remove_scratch(&self) -> Result<(), MapError> {
        std::fs::remove_dir_all(&self.scratch).map_err(|e| MapError::io(&self.scratch, e))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rows(c: &TiledCloud) -> Vec<[f32; 4]> {
        c.rows().flat_map(Result::unwrap).collect()
    }

    #[test]
    fn spilled_tiles_come_back_and_the_cloud_is_the_same() {
        let dir = tempfile::tempdir().unwrap();
        // A walk 1 km along x: points around the sensor at every metre.
        let walk = |cloud: &mut TiledCloud, spill: bool| {
            for step in 0..1000 {
                let s = Point3::new(f64::from(step), 0.0, 0.0);
                let pts: Vec<Point3<f64>> = (0..50)
                    .map(|k| {
                        s + nalgebra::Vector3::new(f64::from(k % 10) - 5.0, f64::from(k / 10), 0.1)
                    })
                    .collect();
                cloud
                    .add(&pts, &vec![f32::from(step as u16 % 7); pts.len()])
                    .unwrap();
                if spill {
                    cloud.spill_far_from(&s).unwrap();
                }
            }
            cloud.spill_all().unwrap();
        };
        let mut bounded = TiledCloud::new(0.5, 20.0, 10.0, &dir.path().join("a")).unwrap();
        walk(&mut bounded, true);
        let mut all = TiledCloud::new(0.5, 20.0, 10.0, &dir.path().join("b")).unwrap();
        walk(&mut all, false);
        assert_eq!(rows(&bounded), rows(&all));
        assert_eq!(bounded.len(), all.len());
        // In memory: the tiles within 10 m of the sensor, not the whole kilometre.
        assert!(bounded.peak_resident_voxels * 10 < all.peak_resident_voxels);
        // A return to the start reads its tile back and adds to it.
        bounded.add(&[Point3::new(0.1, -3.0, 5.0)], &[1.0]).unwrap();
        bounded.spill_all().unwrap();
        assert_eq!(bounded.len(), all.len() + 1);
    }
}
