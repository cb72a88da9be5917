//! Point clouds as binary PLY (x, y, z float32, little endian): what `keylo run` writes for
//! the local map and the pictured frames, readable by CloudCompare, Open3D, PCL and
//! `keylo report`.

use std::io::Write;
use std::path::Path;

use anyhow::{Context, Result};
use nalgebra::Point3;

/// Writes `points` to `path`; `comment` goes in the header (one line).
pub fn write(path: &Path, points: &[Point3<f64>], comment: &str) -> Result<()> {
    let finite: Vec<&Point3<f64>> = points
        .iter()
        .filter(|p| p.coords.iter().all(|v| v.is_finite()))
        .collect();
    let mut bytes = Vec::with_capacity(200 + 12 * finite.len());
    let comment = comment.replace(['\n', '\r'], " ");
    write!(
        bytes,
        "ply\nformat binary_little_endian 1.0\ncomment {comment}\nelement vertex {}\n\
         property float x\nproperty float y\nproperty float z\nend_header\n",
        finite.len()
    )?;
    for p in finite {
        for v in p.coords.iter() {
            bytes.extend_from_slice(&(*v as f32).to_le_bytes());
        }
    }
    crate::atomic::write(path, bytes).with_context(|| format!("writing {}", path.display()))
}

/// Reads the x, y, z of the points of any PLY file keylo reads.
pub fn read(path: &Path) -> Result<Vec<[f32; 3]>> {
    let options = keylo::io::folder::fields::FieldOptions::default();
    let cloud = keylo::io::ply::read_ply(path, 0.0, &options)
        .with_context(|| format!("reading {}", path.display()))?;
    Ok(cloud.points)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_drops_non_finite_points() {
        let dir = tempfile::tempdir().expect("temp dir");
        let path = dir.path().join("c.ply");
        let pts = [
            Point3::new(1.0, 2.0, 3.5),
            Point3::new(f64::NAN, 0.0, 0.0),
            Point3::new(-4.0, 0.25, 1e3),
        ];
        write(&path, &pts, "two\npoints").expect("write");
        let back = read(&path).expect("read");
        assert_eq!(back, vec![[1.0, 2.0, 3.5], [-4.0, 0.25, 1e3]]);
    }
}
