//! Reading and writing whole text files with errors that name the path.

use std::path::Path;

use super::TrajectoryError;

/// Reads `path` to a string.
pub(crate) fn read_text(path: &Path) -> Result<String, TrajectoryError> {
    std::fs::read_to_string(path).map_err(|source| TrajectoryError::Read {
        path: path.to_path_buf(),
        source,
    })
}

/// Writes `text` to `path`, replacing it.
pub(crate) fn write_text(path: &Path, text: &str) -> Result<(), TrajectoryError> {
    std::fs::write(path, text).map_err(|source| TrajectoryError::Write {
        path: path.to_path_buf(),
        source,
    })
}

/// The label used in error messages for `path`.
pub(crate) fn label(path: &Path) -> String {
    path.display().to_string()
}
