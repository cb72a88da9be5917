//! The global cloud in square tiles (x, y). Memory holds only what the run added to the
//! tiles within the sensor's reach since it last came by: a tile that leaves the reach has
//! its voxels appended to its file in a scratch folder and leaves memory, and a run that comes
//! back starts the tile afresh in memory (it does not read the file back). When the voxels in
//! memory exceed a budget, every resident tile goes to disk the same way. At the end each
//! tile's file, one tile at a time, is merged into one mean per voxel. So memory is bounded by
//! the budget, however long the run and however often it passes the same place.

use std::collections::{BTreeMap, HashMap};
use std::io::Write;
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
    /// Voxels in memory at most, over all tiles (then every tile goes to disk).
    budget: usize,
    resident: HashMap<TileKey, Voxels>,
    held: usize,
    /// Tiles on disk: voxel records written (parts not yet merged) or, after
    /// [`Self::spill_all`], voxels.
    on_disk: BTreeMap<TileKey, usize>,
    merged: bool,
    scratch: PathBuf,
    /// The most voxels held in memory at once.
    pub peak_resident_voxels: usize,
}

impl TiledCloud {
    /// An empty cloud whose tiles spill into `scratch` (created), holding at most `budget`
    /// voxels in memory.
    pub fn new(
        voxel_size: f64,
        tile_size: f64,
        reach: f64,
        budget: usize,
        scratch: &Path,
    ) -> Result<Self, MapError> {
        std::fs::create_dir_all(scratch).map_err(|e| MapError::io(scratch, e))?;
        Ok(Self {
            voxel_size,
            tile_size,
            reach,
            budget: budget.max(1),
            resident: HashMap::new(),
            held: 0,
            on_disk: BTreeMap::new(),
            merged: false,
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
    /// per point; within a tile in the points' order).
    pub fn add(&mut self, points: &[Point3<f64>], intensities: &[f32]) -> Result<(), MapError> {
        let mut by_tile: Vec<(TileKey, u32)> = (points.iter().enumerate())
            .map(|(i, p)| (self.tile_of(p), i as u32))
            .collect();
        by_tile.sort_unstable();
        let size = self.voxel_size;
        self.merged = false;
        for run in by_tile.chunk_by(|a, b| a.0 == b.0) {
            let voxels = self.resident.entry(run[0].0).or_default();
            let before = voxels.len();
            for &(_, i) in run {
                let (p, v) = (&points[i as usize], f64::from(intensities[i as usize]));
                let xyz = [p.x, p.y, p.z];
                voxels
                    .entry(voxel_of(p, size))
                    .and_modify(|m| m.add(xyz, v))
                    .or_insert_with(|| VoxelMean::first(xyz, v));
            }
            self.held += voxels.len() - before;
        }
        self.peak_resident_voxels = self.peak_resident_voxels.max(self.held);
        if self.held > self.budget {
            self.spill_resident()?;
        }
        Ok(())
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

    fn spill_resident(&mut self) -> Result<(), MapError> {
        let keys: Vec<TileKey> = self.resident.keys().copied().collect();
        for key in keys {
            self.spill(key)?;
        }
        Ok(())
    }

    /// Appends the resident part of tile `key` to its file and drops it from memory.
    fn spill(&mut self, key: TileKey) -> Result<(), MapError> {
        if let Some(voxels) = self.resident.remove(&key) {
            let path = self.tile_path(key);
            let mut file = std::fs::OpenOptions::new()
                .create(true)
                .append(true)
                .open(&path)
                .map_err(|e| MapError::io(&path, e))?;
            file.write_all(&accumulate::to_bytes(&voxels))
                .map_err(|e| MapError::io(&path, e))?;
            *self.on_disk.entry(key).or_default() += voxels.len();
            self.held -= voxels.len();
        }
        Ok(())
    }

    /// Spills every tile and merges each tile's file into one mean per voxel (one tile in
    /// memory at a time): afterwards [`Self::len`] and [`Self::rows`] give the whole cloud.
    pub fn spill_all(&mut self) -> Result<(), MapError> {
        self.spill_resident()?;
        let keys: Vec<TileKey> = self.on_disk.keys().copied().collect();
        for key in keys {
            let voxels = self.read_tile(key)?;
            let path = self.tile_path(key);
            std::fs::write(&path, accumulate::to_bytes(&voxels))
                .map_err(|e| MapError::io(&path, e))?;
            self.on_disk.insert(key, voxels.len());
        }
        self.merged = true;
        Ok(())
    }

    /// Tile `key`'s file with its parts merged (read record by record).
    fn read_tile(&self, key: TileKey) -> Result<Voxels, MapError> {
        let path = self.tile_path(key);
        let file = std::fs::File::open(&path).map_err(|e| MapError::io(&path, e))?;
        accumulate::from_reader(std::io::BufReader::new(file)).map_err(|e| match e.kind() {
            std::io::ErrorKind::InvalidData => MapError::format(&path, e),
            _ => MapError::io(&path, e),
        })
    }

    /// Voxels of the whole cloud (after [`Self::spill_all`]).
    pub fn len(&self) -> usize {
        debug_assert!(self.merged, "len before spill_all");
        self.on_disk.values().sum::<usize>()
    }

    /// Every tile's voxels in key order, then within a tile in voxel-key order, as rows
    /// `[x, y, z, intensity]` (after [`Self::spill_all`]).
    pub fn rows(&self) -> impl Iterator<Item = Result<Vec<[f32; 4]>, MapError>> + '_ {
        self.on_disk.keys().map(|&key| {
            let voxels = self.read_tile(key)?;
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

    /// A budget far below the area in reach: the tiles go to disk in parts, often, and the
    /// merged cloud is the one built in memory (means equal to f32 rounding), while memory
    /// never holds more than the budget and one frame.
    #[test]
    fn a_memory_budget_bounds_the_voxels_held_and_keeps_the_cloud() {
        let dir = tempfile::tempdir().unwrap();
        let laps = |cloud: &mut TiledCloud| {
            for lap in 0..3 {
                for step in 0..200 {
                    let s = Point3::new(f64::from(step) * 0.5, 0.0, 0.0);
                    let pts: Vec<Point3<f64>> = (0..60)
                        .map(|k| {
                            let drift = 0.01 * f64::from(lap);
                            s + nalgebra::Vector3::new(
                                f64::from(k % 12) * 0.37 - 2.0 + drift,
                                f64::from(k / 12) * 0.41,
                                0.3,
                            )
                        })
                        .collect();
                    cloud
                        .add(&pts, &vec![f32::from(step as u16 % 5); pts.len()])
                        .unwrap();
                    cloud.spill_far_from(&s).unwrap();
                }
            }
            cloud.spill_all().unwrap();
        };
        let mut small = TiledCloud::new(0.2, 20.0, 1e9, 500, &dir.path().join("s")).unwrap();
        laps(&mut small);
        let mut big = TiledCloud::new(0.2, 20.0, 1e9, usize::MAX, &dir.path().join("b")).unwrap();
        laps(&mut big);
        assert!(
            small.peak_resident_voxels <= 500 + 60,
            "{}",
            small.peak_resident_voxels
        );
        assert!(
            big.peak_resident_voxels > 5 * 500,
            "{}",
            big.peak_resident_voxels
        );
        assert_eq!(small.len(), big.len());
        for (a, b) in rows(&small).iter().zip(rows(&big)) {
            for (x, y) in a.iter().zip(b) {
                assert!((x - y).abs() <= 1e-5 * y.abs().max(1.0), "{a:?} vs {b:?}");
            }
        }
    }

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
        let mut bounded =
            TiledCloud::new(0.5, 20.0, 10.0, usize::MAX, &dir.path().join("a")).unwrap();
        walk(&mut bounded, true);
        let mut all = TiledCloud::new(0.5, 20.0, 10.0, usize::MAX, &dir.path().join("b")).unwrap();
        walk(&mut all, false);
        assert_eq!(rows(&bounded), rows(&all));
        assert_eq!(bounded.len(), all.len());
        // In memory: the tiles within 10 m of the sensor, not the whole kilometre.
        assert!(bounded.peak_resident_voxels * 10 < all.peak_resident_voxels);
        // A return to the start adds to its tile: a new voxel, and a mean that moves.
        bounded.add(&[Point3::new(0.1, -3.0, 5.0)], &[1.0]).unwrap();
        bounded
            .add(&[Point3::new(-4.9, 0.1, 0.1)], &[100.0])
            .unwrap();
        bounded.spill_all().unwrap();
        assert_eq!(bounded.len(), all.len() + 1);
        let moved = (rows(&bounded).into_iter())
            .find(|r| (r[0] + 4.95).abs() < 1e-4 && r[1].abs() < 0.3)
            .unwrap();
        assert!(moved[3] > 3.0, "{moved:?}");
    }
}
