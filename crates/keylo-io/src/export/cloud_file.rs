//! Clouds of x, y, z and intensity (float32) as binary PLY or PCD, written while their
//! points stream in (a map too large to hold twice): what `keylo-map` saves.

use std::io::{BufWriter, Write};
use std::path::Path;

use super::pcd::pcd_header;
use super::ply::ply_header;
use crate::IoError;

/// A cloud file format keylo writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CloudFormat {
    /// Binary little-endian PLY.
    Ply,
    /// PCD v0.7, `DATA binary`.
    Pcd,
}

impl CloudFormat {
    /// The format a path's extension names (`.ply`, `.pcd`, any case).
    pub fn of_path(path: &Path) -> Option<Self> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "ply" => Some(Self::Ply),
            "pcd" => Some(Self::Pcd),
            _ => None,
        }
    }
}

/// Writes the `n` points `rows` yields (`[x, y, z, intensity]`) to `path` in `format`;
/// `comment` goes into a PLY's header. `Err` when `rows` yields another count than `n`.
pub fn write_xyzi(
    path: &Path,
    format: CloudFormat,
    n: usize,
    comment: &str,
    rows: impl IntoIterator<Item = [f32; 4]>,
) -> Result<(), IoError> {
    let header = match format {
        CloudFormat::Ply => ply_header(n, comment, &[("intensity", "float")]),
        CloudFormat::Pcd => pcd_header(n, &[("intensity", 4, 'F')]),
    };
    let file = std::fs::File::create(path).map_err(|e| IoError::io(path, e))?;
    let mut out = BufWriter::with_capacity(1 << 20, file);
    out.write_all(header.as_bytes())
        .map_err(|e| IoError::io(path, e))?;
    let mut written = 0usize;
    for row in rows {
        for v in row {
            out.write_all(&v.to_le_bytes())
                .map_err(|e| IoError::io(path, e))?;
        }
        written += 1;
    }
    if written != n {
        return Err(IoError::format(
            path,
            format!("{written} points given for a header of {n}"),
        ));
    }
    out.flush().map_err(|e| IoError::io(path, e))
}
