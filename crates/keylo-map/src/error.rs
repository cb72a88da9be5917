use std::path::PathBuf;

/// Errors of map building and reading; every variant names the file or setting.
#[derive(Debug, thiserror::Error)]
pub enum MapError {
    #[error("{path}: {source}")]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    /// A file that is not what a map folder holds there.
    #[error("{path}: {message}")]
    Format { path: PathBuf, message: String },
    /// A `[map]` setting out of range.
    #[error("{origin}: {message}")]
    Config { origin: String, message: String },
}

impl MapError {
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

impl From<keylo_io::IoError> for MapError {
    fn from(e: keylo_io::IoError) -> Self {
        match e {
            keylo_io::IoError::Io { path, source } => Self::Io { path, source },
            keylo_io::IoError::Format { path, message } => Self::Format { path, message },
        }
    }
}
