//! Binary little-endian PLY (one `vertex` element: x y z float, then the chosen fields).

use std::io::Write;
use std::path::Path;

use super::ExportPoints;
use crate::IoError;

/// Writes `points` to `path`; returns the number of points.
pub fn write_ply(path: &Path, points: &ExportPoints, comment: &str) -> Result<usize, IoError> {
    let mut header = String::from("ply\nformat binary_little_endian 1.0\n");
    for line in comment.lines() {
        header += &format!("comment {line}\n");
    }
    header += &format!("element vertex {}\n", points.items.len());
    header += "property float x\nproperty float y\nproperty float z\n";
    for f in &points.fields {
        let ty = if f.is_u16() { "ushort" } else { "float" };
        header += &format!("property {ty} {}\n", f.name());
    }
    header += "end_header\n";
    let mut file = std::fs::File::create(path).map_err(|e| IoError::io(path, e))?;
    file.write_all(header.as_bytes())
        .and_then(|()| file.write_all(&points.binary_le()))
        .map_err(|e| IoError::io(path, e))?;
    Ok(points.items.len())
}
