//! An existing map folder: checked on opening, its cloud read, exported or cropped.

use std::path::{Path, PathBuf};

use keylo_io::export::{write_xyzi, CloudFormat};
use keylo_io::folder::fields::FieldOptions;
use nalgebra::Point3;

use crate::keyframes::{keyframe_file, read_rows, write_rows};
use crate::manifest::files;
use crate::{Bounds, KeyframeRow, MapError, MapManifest};

/// A map folder, its `map.json` and `keyframes.csv` read and checked.
#[derive(Debug, Clone)]
pub struct Map {
    dir: PathBuf,
    manifest: MapManifest,
    keyframes: Vec<KeyframeRow>,
}

impl Map {
    /// Opens the map in `dir`; the error names a missing or foreign folder, a map of another
    /// version, or the file that does not hold what `map.json` says.
    pub fn open(dir: &Path) -> Result<Self, MapError> {
        let manifest = MapManifest::read(dir)?;
        for name in [files::CLOUD_PLY, files::CLOUD_PCD, files::KEYFRAMES] {
            let path = dir.join(name);
            if !path.is_file() {
                return Err(MapError::format(&path, "missing from the map folder"));
            }
        }
        let keyframes = read_rows(dir)?;
        if keyframes.len() != manifest.keyframes {
            let path = dir.join(files::KEYFRAMES);
            let message = format!(
                "{} keyframes; map.json says {}",
                keyframes.len(),
                manifest.keyframes
            );
            return Err(MapError::format(&path, message));
        }
        Ok(Self {
            dir: dir.to_path_buf(),
            manifest,
            keyframes,
        })
    }

    /// The map's folder.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// What `map.json` says.
    pub fn manifest(&self) -> &MapManifest {
        &self.manifest
    }

    /// The keyframes, in order.
    pub fn keyframes(&self) -> &[KeyframeRow] {
        &self.keyframes
    }

    /// The file of keyframe `k` with `suffix` (`ply`, `features.json`).
    pub fn keyframe_file(&self, k: usize, suffix: &str) -> PathBuf {
        keyframe_file(&self.dir, k, suffix)
    }

    /// The global cloud: `[x, y, z, intensity]` per point, world frame.
    pub fn cloud(&self) -> Result<Vec<[f32; 4]>, MapError> {
        let path = self.dir.join(files::CLOUD_PLY);
        let raw = keylo_io::ply::read_ply(&path, 0.0, &FieldOptions::default())?;
        if raw.points.len() != self.manifest.points {
            let message = format!(
                "{} points; map.json says {}",
                raw.points.len(),
                self.manifest.points
            );
            return Err(MapError::format(&path, message));
        }
        let intensity = raw.intensity.unwrap_or_else(|| vec![0.0; raw.points.len()]);
        Ok(raw
            .points
            .iter()
            .zip(intensity)
            .map(|(p, i)| [p[0], p[1], p[2], i])
            .collect())
    }

    /// The global cloud's points (world frame), e.g. to localise in ([`crate::localise`]).
    pub fn points(&self) -> Result<Vec<Point3<f64>>, MapError> {
        Ok(self.cloud()?.iter().map(|r| Point3::from(xyz(r))).collect())
    }

    /// Writes the global cloud to `path` (`.ply` or `.pcd`), keeping the points in `within`
    /// when given; returns the number written.
    pub fn export(&self, path: &Path, within: Option<&Bounds>) -> Result<usize, MapError> {
        let format = CloudFormat::of_path(path)
            .ok_or_else(|| MapError::format(path, "expected a .ply or .pcd file name"))?;
        let rows: Vec<[f32; 4]> = self
            .cloud()?
            .into_iter()
            .filter(|r| within.is_none_or(|b| b.contains(xyz(r))))
            .collect();
        let comment = format!(
            "keylo map export of {}: world frame (x y z metres, mean intensity)",
            self.dir.display()
        );
        write_xyzi(path, format, rows.len(), &comment, rows.iter().copied())?;
        Ok(rows.len())
    }

    /// A new map in `out` holding the points of this one inside `within` and the keyframes
    /// whose position is inside it (renumbered from 0, their files copied).
    pub fn crop(&self, within: &Bounds, out: &Path) -> Result<MapManifest, MapError> {
        if out == self.dir {
            return Err(MapError::format(
                out,
                "the cropped map must go to another folder",
            ));
        }
        std::fs::create_dir_all(out).map_err(|e| MapError::io(out, e))?;
        let rows: Vec<[f32; 4]> = (self.cloud()?.into_iter())
            .filter(|r| within.contains(xyz(r)))
            .collect();
        let mut bounds = Bounds::empty();
        rows.iter().for_each(|r| bounds.grow(xyz(r)));
        let comment = format!("keylo map: cropped from {}", self.dir.display());
        for (name, format) in [
            (files::CLOUD_PLY, CloudFormat::Ply),
            (files::CLOUD_PCD, CloudFormat::Pcd),
        ] {
            write_xyzi(
                &out.join(name),
                format,
                rows.len(),
                &comment,
                rows.iter().copied(),
            )?;
        }
        let kept = self.crop_keyframes(within, out)?;
        let manifest = MapManifest {
            points: rows.len(),
            bounds: (!rows.is_empty()).then_some(bounds),
            keyframes: kept.len(),
            keyframe_features: self.manifest.keyframe_features
                && kept.iter().any(|r| r.keypoints > 0),
            cropped_from: Some(self.dir.display().to_string()),
            ..self.manifest.clone()
        };
        manifest.write(out)?;
        Ok(manifest)
    }

    /// Copies the keyframes inside `within` to `out`, renumbered; returns their rows.
    fn crop_keyframes(&self, within: &Bounds, out: &Path) -> Result<Vec<KeyframeRow>, MapError> {
        let inside = (self.keyframes.iter()).filter(|r| {
            let t = r.pose.translation.vector;
            within.contains([t.x, t.y, t.z])
        });
        let mut kept = Vec::new();
        let dir = out.join(files::KEYFRAME_DIR);
        if dir.is_dir() {
            std::fs::remove_dir_all(&dir).map_err(|e| MapError::io(&dir, e))?;
        }
        std::fs::create_dir_all(&dir).map_err(|e| MapError::io(&dir, e))?;
        for (k, row) in inside.enumerate() {
            for suffix in ["ply", "features.json"] {
                let from = self.keyframe_file(row.keyframe, suffix);
                if from.is_file() {
                    let to = keyframe_file(out, k, suffix);
                    std::fs::copy(&from, &to).map_err(|e| MapError::io(&from, e))?;
                }
            }
            kept.push(KeyframeRow {
                keyframe: k,
                ..row.clone()
            });
        }
        write_rows(out, &kept)?;
        Ok(kept)
    }
}

fn xyz(r: &[f32; 4]) -> [f64; 3] {
    [f64::from(r[0]), f64::from(r[1]), f64::from(r[2])]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{MapBuilder, MapConfig};

    fn message(dir: &Path) -> String {
        Map::open(dir).unwrap_err().to_string()
    }

    #[test]
    fn missing_foreign_and_other_version_maps_are_named() {
        let dir = tempfile::tempdir().unwrap();
        let missing = dir.path().join("nowhere");
        assert!(message(&missing).ends_with("nowhere: no such map folder"));
        let foreign = dir.path().join("foreign");
        std::fs::create_dir(&foreign).unwrap();
        assert!(message(&foreign).contains("map.json: missing: this folder is not a keylo map"));
        std::fs::write(foreign.join("map.json"), "{\"format\": \"pcl\"}").unwrap();
        assert!(message(&foreign).contains("format is \"pcl\"; expected \"keylo-map\""));
        std::fs::write(foreign.join("map.json"), "not json").unwrap();
        assert!(message(&foreign).contains("map.json: not JSON"));

        // An empty map is a map; then its version, files and counts are checked.
        let map = dir.path().join("map");
        let m = MapBuilder::create(&map, MapConfig::default(), "test")
            .unwrap()
            .finish()
            .unwrap();
        assert_eq!((m.points, m.keyframes, m.bounds), (0, 0, None));
        assert!(Map::open(&map).unwrap().cloud().unwrap().is_empty());
        let json = std::fs::read_to_string(map.join("map.json")).unwrap();
        std::fs::write(
            map.join("map.json"),
            json.replace("\"version\": 1", "\"version\": 7"),
        )
        .unwrap();
        assert!(message(&map).contains("map version 7; this keylo reads version 1"));
        std::fs::write(
            map.join("map.json"),
            json.replace("\"keyframes\": 0", "\"keyframes\": 2"),
        )
        .unwrap();
        assert!(message(&map).contains("keyframes.csv: 0 keyframes; map.json says 2"));
        std::fs::write(map.join("map.json"), &json).unwrap();
        std::fs::remove_file(map.join("map.pcd")).unwrap();
        assert!(message(&map).contains("map.pcd: missing from the map folder"));
    }
}
