//! Reading and writing trajectory files (TUM and KITTI formats), for evaluation (keylo-eval
//! computes on the [`Trajectory`] values; it reads no file) and for every tool that saves
//! poses.
//!
//! Every error names the file (or the label given to the `parse_*` functions) and, where
//! it applies, the 1-based line and column.

mod error;
mod file;
mod kitti;
mod labelled;
mod lines;
mod rotation;
mod tum;

use std::path::Path;

use keylo_core::Trajectory;

pub use error::TrajectoryError;
pub use kitti::{
    format_kitti, format_kitti_line, format_kitti_line_exact, parse_kitti, parse_kitti_with_times,
    read_kitti, read_kitti_with_times, write_kitti, KITTI_COLUMNS,
};
pub use labelled::{reconcile, Labelled};
pub use tum::{
    format_tum, format_tum_line, format_tum_line_exact, parse_tum, read_tum, write_tum, TUM_COLUMNS,
};

/// A trajectory file format.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub enum Format {
    /// `t tx ty tz qx qy qz qw`.
    Tum,
    /// Row-major 3x4 `[R|t]`, no stamps.
    Kitti,
}

/// Detects the format from the number of columns of the first data line.
///
/// ```
/// use keylo_io::trajectory::{detect_format, Format};
/// assert_eq!(detect_format("# c\n0 0 0 0 0 0 0 1\n", "a")?, Format::Tum);
/// assert!(detect_format("1 2 3\n", "a").is_err());
/// # Ok::<(), keylo_io::trajectory::TrajectoryError>(())
/// ```
pub fn detect_format(text: &str, file: &str) -> Result<Format, TrajectoryError> {
    let line = lines::first_line(text, file)?;
    match line.tokens.len() {
        TUM_COLUMNS => Ok(Format::Tum),
        KITTI_COLUMNS => Ok(Format::Kitti),
        found => Err(TrajectoryError::ColumnCount {
            file: file.to_string(),
            line: line.number,
            expected: format!("{TUM_COLUMNS} (TUM) or {KITTI_COLUMNS} (KITTI)"),
            found,
        }),
    }
}

/// Parses TUM or KITTI text, whichever the first data line looks like.
pub fn parse_trajectory(text: &str, file: &str) -> Result<Trajectory, TrajectoryError> {
    match detect_format(text, file)? {
        Format::Tum => parse_tum(text, file),
        Format::Kitti => parse_kitti(text, file),
    }
}

/// Reads a TUM or KITTI file, detected from its first data line (8 or 12 columns).
///
/// ```
/// let dir = tempfile::tempdir()?;
/// let path = dir.path().join("gt.tum");
/// std::fs::write(&path, "0.0 1 2 3 0 0 0 1\n0.1 2 2 3 0 0 0 1\n")?;
/// let traj = keylo_io::trajectory::read_trajectory(&path)?;
/// assert_eq!(traj.len(), 2);
/// std::fs::write(&path, "0.0 1 2 3 0\n")?;
/// let err = keylo_io::trajectory::read_trajectory(&path).unwrap_err().to_string();
/// assert!(err.ends_with("gt.tum line 1: expected 8 (TUM) or 12 (KITTI) numbers, found 5"));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn read_trajectory(path: impl AsRef<Path>) -> Result<Trajectory, TrajectoryError> {
    let path = path.as_ref();
    parse_trajectory(&file::read_text(path)?, &file::label(path))
}

/// Writes `traj` in `format`.
pub fn write_trajectory(
    path: impl AsRef<Path>,
    traj: &Trajectory,
    format: Format,
) -> Result<(), TrajectoryError> {
    match format {
        Format::Tum => write_tum(path, traj),
        Format::Kitti => write_kitti(path, traj),
    }
}
