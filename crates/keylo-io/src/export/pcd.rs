//! PCD v0.7, `DATA binary` (x y z float, then the chosen fields), unorganised
//! (`HEIGHT 1`), as PCL's `savePCDFileBinary` writes it.

use std::io::Write;
use std::path::Path;

use super::ExportPoints;
use crate::IoError;

/// Writes `points` to `path`; returns the number of points.
pub fn write_pcd(path: &Path, points: &ExportPoints) -> Result<usize, IoError> {
    let n = points.items.len();
    let extra: Vec<(&str, u8, char)> = (points.fields.iter())
        .map(|f| match f.is_u16() {
            true => (f.name(), 2, 'U'),
            false => (f.name(), 4, 'F'),
        })
        .collect();
    let mut file = std::fs::File::create(path).map_err(|e| IoError::io(path, e))?;
    file.write_all(pcd_header(n, &extra).as_bytes())
        .and_then(|()| file.write_all(&points.binary_le()))
        .map_err(|e| IoError::io(path, e))?;
    Ok(n)
}

/// The header of an unorganised binary PCD of `n` points: float x, y, z, then the
/// `(name, size in bytes, PCD type)` fields in `extra`.
pub fn pcd_header(n: usize, extra: &[(&str, u8, char)]) -> String {
    let all: Vec<(&str, u8, char)> = [("x", 4, 'F'), ("y", 4, 'F'), ("z", 4, 'F')]
        .into_iter()
        .chain(extra.iter().copied())
        .collect();
    let join =
        |f: &dyn Fn(&(&str, u8, char)) -> String| all.iter().map(f).collect::<Vec<_>>().join(" ");
    format!(
        "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS {}\nSIZE {}\n\
         TYPE {}\nCOUNT {}\nWIDTH {n}\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS {n}\n\
         DATA binary\n",
        join(&|f| f.0.to_string()),
        join(&|f| f.1.to_string()),
        join(&|f| f.2.to_string()),
        join(&|_| "1".to_string()),
    )
}
