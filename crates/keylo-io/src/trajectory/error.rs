//! Errors of reading and writing trajectory files.

use std::path::PathBuf;

/// A trajectory file that cannot be read, parsed or written.
///
/// Variants carry a `file` label (the file path, or the label given to the in-memory
/// parsers) and a 1-based line number, so messages read like
/// `gt.tum line 7: expected 8 numbers, found 5`.
#[derive(Debug, thiserror::Error)]
pub enum TrajectoryError {
    /// The file could not be opened or read.
    #[error("{}: cannot read: {source}", path.display())]
    Read {
        /// File that failed.
        path: PathBuf,
        /// Underlying I/O error.
        source: std::io::Error,
    },
    /// The file could not be written.
    #[error("{}: cannot write: {source}", path.display())]
    Write {
        /// File that failed.
        path: PathBuf,
        /// Underlying I/O error.
        source: std::io::Error,
    },
    /// The file holds no data line (empty, or only blank lines and comments).
    #[error("{file}: no poses (the file is empty or holds only comments)")]
    Empty {
        /// File label.
        file: String,
    },
    /// A data line has the wrong number of columns.
    #[error("{file} line {line}: expected {expected} numbers, found {found}")]
    ColumnCount {
        /// File label.
        file: String,
        /// 1-based line number.
        line: usize,
        /// What the format requires, e.g. "8" or "8 (TUM) or 12 (KITTI)".
        expected: String,
        /// Columns found.
        found: usize,
    },
    /// A token is not a number.
    #[error("{file} line {line}, column {column}: '{token}' is not a number")]
    NotANumber {
        /// File label.
        file: String,
        /// 1-based line number.
        line: usize,
        /// 1-based column number.
        column: usize,
        /// The offending text.
        token: String,
    },
    /// A number is NaN or infinite.
    #[error("{file} line {line}, column {column}: value '{token}' is not finite")]
    NonFinite {
        /// File label.
        file: String,
        /// 1-based line number.
        line: usize,
        /// 1-based column number.
        column: usize,
        /// The offending text.
        token: String,
    },
    /// A quaternion cannot be normalised (norm close to zero).
    #[error("{file} line {line}: quaternion (qx qy qz qw) has norm {norm:e}, cannot normalise it")]
    BadQuaternion {
        /// File label.
        file: String,
        /// 1-based line number.
        line: usize,
        /// Its norm.
        norm: f64,
    },
    /// A 3x3 block is too far from a rotation matrix to be re-orthonormalised.
    #[error("{file} line {line}: the 3x3 block is not a rotation matrix ({reason})")]
    BadRotation {
        /// File label.
        file: String,
        /// 1-based line number.
        line: usize,
        /// What is wrong.
        reason: String,
    },
    /// A KITTI file (no stamps) paired one for one with a trajectory of another length.
    #[error(
        "{kitti} is a KITTI file (no time stamps) and {other} has {other_poses} time-stamped \
         poses, not {kitti_poses}: poses can only be paired one for one; give both as TUM or \
         both as KITTI"
    )]
    Unpairable {
        /// The KITTI file.
        kitti: String,
        /// Its poses.
        kitti_poses: usize,
        /// The other trajectory.
        other: String,
        /// Its poses.
        other_poses: usize,
    },
    /// `read_kitti_with_times` got a times vector of the wrong length.
    #[error("{file}: {poses} poses but {times} timestamps were given")]
    TimesMismatch {
        /// File label.
        file: String,
        /// Poses in the file.
        poses: usize,
        /// Timestamps given.
        times: usize,
    },
}
