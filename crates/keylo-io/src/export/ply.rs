//! Binary little-endian PLY (one `vertex` element: x y z float, then the chosen fields).

use std::io::Write;
use std::path::Path;

use super::ExportPoints;
use crate::IoError;

/// Writes `points` to `path`; returns the number of points.
pub fn write_ply(path: &Path, points: &ExportPoints, comment: &str) -> Result<usize, IoError> {
    let extra: Vec<(&str, &str)> = (points.fields.iter())
        .map(|f| (f.name(), if f.is_u16() { "ushort" } else { "float" }))
        .collect();
    let header = ply_header(points.items.len(), comment, &extra);
    let mut file = std::fs::File::create(path).map_err(|e| IoError::io(path, e))?;
    file.write_all(header.as_bytes())
        .and_then(|()| file.write_all(&points.binary_le()))
        .map_err(|e| IoError::io(path, e))?;
    Ok(points.items.len())
}

/// The header of a binary little-endian PLY of `n` vertices: float x, y, z, then the
/// `(name, PLY type)` properties in `extra`; each line of `comment` a `comment` line.
pub fn ply_header(n: usize, comment: &str, extra: &[(&str, &str)]) -> String {
    let mut header = String::from("ply\nformat binary_little_endian 1.0\n");
    for line in comment.lines() {
        header += &format!("comment {line}\n");
    }
    header += &format!("element vertex {n}\n");
    header += "property float x\nproperty float y\nproperty float z\n";
    for (name, ty) in extra {
        header += &format!("property {ty} {name}\n");
    }
    header += "end_header\n";
    header
}
