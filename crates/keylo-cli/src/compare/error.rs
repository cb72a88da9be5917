//! Errors of `keylo compare`.

use std::path::PathBuf;

/// What can go wrong before or around the runs (a run's own failure is a row, not an error).
#[derive(Debug, thiserror::Error)]
pub enum CompareError {
    /// A `--grid` argument that is not `KEY=V1,V2,…` or whose key the config rejects.
    #[error("--grid {key}: {message}")]
    BadGrid { key: String, message: String },
    /// A file or folder could not be read or written.
    #[error("{}: {source}", path.display())]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    /// A plot could not be drawn or encoded.
    #[error("plot {}: {message}", path.display())]
    Plot { path: PathBuf, message: String },
    /// The keylo binary could not be started for a run.
    #[error("starting `keylo run` for {run}: {source}")]
    Spawn { run: String, source: std::io::Error },
}

impl CompareError {
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Self::Io {
            path: path.into(),
            source,
        }
    }
}
