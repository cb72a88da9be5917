use std::path::PathBuf;

use keylo_core::CoreError;

/// Errors of the io crate; every variant names the file.
#[derive(Debug, thiserror::Error)]
pub enum IoError {
    #[error("{path}: {source}")]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("{path}: {message}")]
    Format { path: PathBuf, message: String },
}

impl IoError {
    pub(crate) fn io(path: &std::path::Path, source: std::io::Error) -> Self {
        Self::Io {
            path: path.to_path_buf(),
            source,
        }
    }
    pub(crate) fn format(path: &std::path::Path, message: impl std::fmt::Display) -> Self {
        Self::Format {
            path: path.to_path_buf(),
            message: message.to_string(),
        }
    }
}

impl From<IoError> for CoreError {
    fn from(e: IoError) -> Self {
        match e {
            IoError::Io { path, source } => CoreError::Io { path, source },
            IoError::Format { path, message } => CoreError::Input { path, message },
        }
    }
}
