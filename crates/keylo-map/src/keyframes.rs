//! Keyframes: chosen by distance and angle from the last one, each written as it is chosen
//! (a row of `keyframes.csv`, the keyframe's cloud, its features), so a run that stops
//! keeps every keyframe before it.

use std::io::{BufRead, BufWriter, Write};
use std::path::{Path, PathBuf};

use keylo_core::Pose;
use nalgebra::{Quaternion, Translation3, UnitQuaternion};

use crate::manifest::files;
use crate::MapError;

/// The header of `keyframes.csv`.
const HEADER: &str = "keyframe,frame,stamp,x,y,z,qx,qy,qz,qw,points,keypoints";

/// One row of `keyframes.csv`: a keyframe's pose (sensor in world) at its stamp.
#[derive(Debug, Clone, PartialEq)]
pub struct KeyframeRow {
    /// Number of the keyframe (from 0): its files are `keyframes/NNNNNN.*`.
    pub keyframe: usize,
    /// The frame's index in its source.
    pub frame: u64,
    /// The pose's time: the scan's end, seconds.
    pub stamp: f64,
    pub pose: Pose,
    /// Points of the keyframe's cloud.
    pub points: usize,
    /// Keypoints saved with it (0 without features).
    pub keypoints: usize,
}

impl KeyframeRow {
    fn csv(&self) -> String {
        let t = self.pose.translation.vector;
        let q = self.pose.rotation.coords; // x, y, z, w
        format!(
            "{},{},{:?},{:?},{:?},{:?},{:?},{:?},{:?},{:?},{},{}",
            self.keyframe,
            self.frame,
            self.stamp,
            t.x,
            t.y,
            t.z,
            q.x,
            q.y,
            q.z,
            q.w,
            self.points,
            self.keypoints
        )
    }

    fn parse(line: &str) -> Result<Self, String> {
        let cols: Vec<&str> = line.split(',').map(str::trim).collect();
        if cols.len() != 12 {
            return Err(format!("{} columns; expected 12 ({HEADER})", cols.len()));
        }
        let int = |k: usize| {
            cols[k]
                .parse::<u64>()
                .map_err(|e| format!("column {}: `{}`: {e}", k + 1, cols[k]))
        };
        let num = |k: usize| {
            let v: f64 = cols[k]
                .parse()
                .map_err(|e| format!("column {}: `{}`: {e}", k + 1, cols[k]))?;
            v.is_finite()
                .then_some(v)
                .ok_or_else(|| format!("column {}: {v} is not finite", k + 1))
        };
        let q = Quaternion::new(num(9)?, num(6)?, num(7)?, num(8)?);
        if (q.norm() - 1.0).abs() > 1e-6 {
            return Err(format!("the quaternion's norm is {}; expected 1", q.norm()));
        }
        Ok(Self {
            keyframe: int(0)? as usize,
            frame: int(1)?,
            stamp: num(2)?,
            pose: Pose::from_parts(
                Translation3::new(num(3)?, num(4)?, num(5)?),
                UnitQuaternion::new_unchecked(q),
            ),
            points: int(10)? as usize,
            keypoints: int(11)? as usize,
        })
    }
}

/// The path of keyframe `k`'s file with `suffix` (`ply`, `features.json`).
pub(crate) fn keyframe_file(dir: &Path, k: usize, suffix: &str) -> PathBuf {
    dir.join(files::KEYFRAME_DIR)
        .join(format!("{k:06}.{suffix}"))
}

/// Reads `keyframes.csv` of a map folder; the error names the line.
pub(crate) fn read_rows(dir: &Path) -> Result<Vec<KeyframeRow>, MapError> {
    let path = dir.join(files::KEYFRAMES);
    let file = std::fs::File::open(&path).map_err(|e| MapError::io(&path, e))?;
    let mut rows = Vec::new();
    for (i, line) in std::io::BufReader::new(file).lines().enumerate() {
        let line = line.map_err(|e| MapError::io(&path, e))?;
        if i == 0 {
            if line.trim() != HEADER {
                return Err(MapError::format(
                    &path,
                    format!("line 1 is `{line}`; expected `{HEADER}`"),
                ));
            }
            continue;
        }
        if line.trim().is_empty() {
            continue;
        }
        let row = KeyframeRow::parse(&line)
            .map_err(|m| MapError::format(&path, format!("line {}: {m}", i + 1)))?;
        rows.push(row);
    }
    Ok(rows)
}

/// Writes `keyframes.csv` with `rows` (a cropped map's).
pub(crate) fn write_rows(dir: &Path, rows: &[KeyframeRow]) -> Result<(), MapError> {
    let mut log = KeyframeLog::create(dir)?;
    for r in rows {
        log.push(r)?;
    }
    Ok(())
}

/// Decides which frames become keyframes.
pub(crate) struct KeyframePolicy {
    distance: f64,
    angle_rad: f64,
    last: Option<Pose>,
}

impl KeyframePolicy {
    pub fn new(distance: f64, angle_deg: f64) -> Self {
        Self {
            distance,
            angle_rad: angle_deg.to_radians(),
            last: None,
        }
    }

    /// Whether the frame at `pose` is a keyframe: the first one, and any frame `distance`
    /// or `angle` away from the last keyframe (either reached).
    pub fn take(&mut self, pose: &Pose) -> bool {
        let new = match &self.last {
            None => true,
            Some(last) => {
                let d = last.inverse() * pose;
                d.translation.vector.norm() >= self.distance || d.rotation.angle() >= self.angle_rad
            }
        };
        if new {
            self.last = Some(*pose);
        }
        new
    }
}

/// `keyframes.csv`, written a row at a time.
pub(crate) struct KeyframeLog {
    path: PathBuf,
    out: BufWriter<std::fs::File>,
}

impl KeyframeLog {
    /// Creates `dir/keyframes.csv` (with its header) and `dir/keyframes/`.
    pub fn create(dir: &Path) -> Result<Self, MapError> {
        let kf = dir.join(files::KEYFRAME_DIR);
        std::fs::create_dir_all(&kf).map_err(|e| MapError::io(&kf, e))?;
        let path = dir.join(files::KEYFRAMES);
        let file = std::fs::File::create(&path).map_err(|e| MapError::io(&path, e))?;
        let mut log = Self {
            out: BufWriter::new(file),
            path,
        };
        log.line(HEADER)?;
        Ok(log)
    }

    fn line(&mut self, line: &str) -> Result<(), MapError> {
        writeln!(self.out, "{line}")
            .and_then(|()| self.out.flush())
            .map_err(|e| MapError::io(&self.path, e))
    }

    /// Appends `row` (flushed: it survives a crash after it).
    pub fn push(&mut self, row: &KeyframeRow) -> Result<(), MapError> {
        self.line(&row.csv())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector3;

    #[test]
    fn keyframes_by_distance_or_angle_and_rows_round_trip() {
        let mut p = KeyframePolicy::new(1.0, 10.0);
        let at = |x: f64, yaw_deg: f64| {
            Pose::new(
                Vector3::new(x, 0.0, 0.0),
                Vector3::new(0.0, 0.0, yaw_deg.to_radians()),
            )
        };
        let taken: Vec<bool> = [
            at(0.0, 0.0),
            at(0.5, 0.0),
            at(1.0, 0.0),
            at(1.2, 9.0),
            at(1.2, 11.0),
        ]
        .iter()
        .map(|pose| p.take(pose))
        .collect();
        assert_eq!(taken, [true, false, true, false, true]);

        let dir = tempfile::tempdir().unwrap();
        let rows: Vec<KeyframeRow> = (0..3)
            .map(|k| KeyframeRow {
                keyframe: k,
                frame: 10 * k as u64,
                stamp: 0.1 * k as f64 + 1e9,
                pose: at(k as f64 / 3.0, 7.0 * k as f64),
                points: 100 + k,
                keypoints: k,
            })
            .collect();
        write_rows(dir.path(), &rows).unwrap();
        assert_eq!(read_rows(dir.path()).unwrap(), rows);
        let path = dir.path().join(files::KEYFRAMES);
        std::fs::write(&path, format!("{HEADER}\n0,0,1.0,0,0,0,0,0,0,2,5,0\n")).unwrap();
        let e = read_rows(dir.path()).unwrap_err().to_string();
        assert!(
            e.contains("keyframes.csv: line 2: the quaternion's norm is 2"),
            "{e}"
        );
    }
}
