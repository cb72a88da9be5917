//! PCD v0.7, `DATA binary` (x y z float, then the chosen fields), unorganised
//! (`HEIGHT 1`), as PCL's `savePCDFileBinary` writes it.

use std::io::Write;
use std::path::Path;

use super::ExportPoints;
use crate::IoError;

/// Writes `points` to `path`; returns the number of points.
pub fn write_pcd(path: &Path, points: &ExportPoints) -> Result<usize, IoError> {
    let n = points.items.len();
    let names: Vec<&str> = ["x", "y", "z"]
        .into_iter()
        .chain(points.fields.iter().map(|f| f.name()))
        .collect();
    let sizes: Vec<&str> = (0..3)
        .map(|_| "4")
        .chain(
            points
                .fields
                .iter()
                .map(|f| if f.is_u16() { "2" } else { "4" }),
        )
        .collect();
    let types: Vec<&str> = (0..3)
        .map(|_| "F")
        .chain(
            points
                .fields
                .iter()
                .map(|f| if f.is_u16() { "U" } else { "F" }),
        )
        .collect();
    let header = format!(
        "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS {}\nSIZE {}\n\
         TYPE {}\nCOUNT {}\nWIDTH {n}\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS {n}\n\
         DATA binary\n",
        names.join(" "),
        sizes.join(" "),
        types.join(" "),
        vec!["1"; names.len()].join(" ")
    );
    let mut file = std::fs::File::create(path).map_err(|e| IoError::io(path, e))?;
    file.write_all(header.as_bytes())
        .and_then(|()| file.write_all(&points.binary_le()))
        .map_err(|e| IoError::io(path, e))?;
    Ok(n)
}
