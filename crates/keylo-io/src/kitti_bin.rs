//! KITTI-style `.bin` frames: `x y z intensity` as little-endian float32, valid points only.

use std::path::Path;

use keylo_core::LidarFrame;

use crate::cloud::RawCloud;
use crate::export::{ExportField, ExportPoints};
use crate::IoError;

/// Writes the valid, finite points of `frame` with their signal as intensity.
pub fn write_kitti_bin(path: &Path, frame: &LidarFrame) -> Result<usize, IoError> {
    write_kitti_bin_points(path, &ExportPoints::new(frame, &[ExportField::Signal]))
}

/// Writes the points of `points` as x y z + its first field (float32; 0 when it has no
/// field); returns the number of points.
pub fn write_kitti_bin_points(path: &Path, points: &ExportPoints) -> Result<usize, IoError> {
    let field = points.fields.first().copied();
    let mut bytes = Vec::with_capacity(points.items.len() * 16);
    for &i in &points.items {
        let [x, y, z] = points.xyz(i);
        for v in [x, y, z, field.map_or(0.0, |f| points.value(f, i))] {
            bytes.extend_from_slice(&v.to_le_bytes());
        }
    }
    std::fs::write(path, &bytes).map_err(|e| IoError::io(path, e))?;
    Ok(points.items.len())
}

/// Reads a `.bin` frame back as `[x, y, z, intensity]` rows.
pub fn read_kitti_bin(path: &Path) -> Result<Vec<[f32; 4]>, IoError> {
    let bytes = read_bytes(path)?;
    Ok(bytes.chunks_exact(16).map(row).collect())
}

/// Reads a `.bin` scan as a cloud (points and intensity) stamped `timestamp`, in one pass.
pub fn read_kitti_cloud(path: &Path, timestamp: f64) -> Result<RawCloud, IoError> {
    let bytes = read_bytes(path)?;
    let n = bytes.len() / 16;
    let (mut points, mut intensity) = (Vec::with_capacity(n), Vec::with_capacity(n));
    for r in bytes.chunks_exact(16).map(row) {
        points.push([r[0], r[1], r[2]]);
        intensity.push(r[3]);
    }
    Ok(RawCloud {
        timestamp,
        points,
        intensity: Some(intensity),
        ..RawCloud::default()
    })
}

fn read_bytes(path: &Path) -> Result<Vec<u8>, IoError> {
    let bytes = std::fs::read(path).map_err(|e| IoError::io(path, e))?;
    if bytes.len() % 16 != 0 {
        return Err(IoError::format(
            path,
            format!(
                "size {} is not a multiple of 16 bytes (4 float32 per point)",
                bytes.len()
            ),
        ));
    }
    Ok(bytes)
}

fn row(c: &[u8]) -> [f32; 4] {
    let f = |k: usize| f32::from_le_bytes([c[k], c[k + 1], c[k + 2], c[k + 3]]);
    [f(0), f(4), f(8), f(12)]
}
