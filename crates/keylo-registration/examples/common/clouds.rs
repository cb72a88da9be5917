//! Cloud files and pose lines shared by the PCL-comparison examples (`ndt_pair`,
//! `gicp_pair`).

use std::path::Path;

use keylo_registration::voxel;
use nalgebra::{Isometry3, Point3};

/// KITTI `.bin` or a binary little-endian PLY whose vertex properties are all `float`.
pub fn load(path: &Path) -> Result<Vec<Point3<f64>>, String> {
    let bytes = std::fs::read(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let (body, stride) = if path.extension().is_some_and(|e| e == "ply") {
        let end = bytes
            .windows(11)
            .position(|w| w == b"end_header\n")
            .ok_or_else(|| format!("{}: no PLY header end", path.display()))?;
        let header = String::from_utf8_lossy(&bytes[..end]);
        if !header.contains("binary_little_endian") {
            return Err(format!("{}: only binary little-endian PLY", path.display()));
        }
        let props = header.lines().filter(|l| l.starts_with("property")).count();
        if header
            .lines()
            .any(|l| l.starts_with("property") && !l.starts_with("property float "))
        {
            return Err(format!("{}: only float properties", path.display()));
        }
        (&bytes[end + 11..], 4 * props)
    } else {
        (&bytes[..], 16)
    };
    let f =
        |c: &[u8], i: usize| f64::from(f32::from_le_bytes([c[i], c[i + 1], c[i + 2], c[i + 3]]));
    Ok(body
        .chunks_exact(stride)
        .map(|c| Point3::new(f(c, 0), f(c, 4), f(c, 8)))
        .filter(|p| p.coords.iter().all(|v| v.is_finite()))
        .collect())
}

pub fn filtered(points: Vec<Point3<f64>>, size: f64) -> Vec<Point3<f64>> {
    if size > 0.0 {
        voxel::centroids(&points, size)
    } else {
        points
    }
}

pub fn pose_line(t: f64, p: &Isometry3<f64>) -> String {
    let (v, q) = (p.translation.vector, p.rotation.coords);
    format!(
        "{t:.6} {:.6} {:.6} {:.6} {:.9} {:.9} {:.9} {:.9}",
        v.x, v.y, v.z, q.x, q.y, q.z, q.w
    )
}

/// The `.bin` and `.ply` clouds of `dir`, sorted by name (the sequence's order).
pub fn frame_files(dir: &str) -> Result<Vec<std::path::PathBuf>, String> {
    let mut files: Vec<std::path::PathBuf> = std::fs::read_dir(dir)
        .map_err(|e| format!("{dir}: {e}"))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "bin" || e == "ply"))
        .collect();
    files.sort();
    Ok(files)
}
