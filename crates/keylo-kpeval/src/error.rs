//! Errors of the keypoint evaluation suite.

use std::path::PathBuf;

/// What can go wrong while evaluating detectors and descriptors.
#[derive(Debug, thiserror::Error)]
pub enum KpEvalError {
    /// A combination name that no registered detector/descriptor pair spells.
    #[error("combination `{name}`: {message}")]
    Combo { name: String, message: String },
    /// A setting of the evaluation (file, key path, what was expected).
    #[error("{origin}: `{key}`: {message}")]
    Setting {
        origin: String,
        key: String,
        message: String,
    },
    /// A detector or descriptor could not be built or failed on an image.
    #[error("{combo}: {stage}: {source}")]
    Stage {
        combo: String,
        stage: String,
        #[source]
        source: Box<keylo_core::CoreError>,
    },
    /// An image operation failed.
    #[error(transparent)]
    Features(#[from] keylo_features::FeaturesError),
    /// A file could not be read or written.
    #[error("{}: {source}", path.display())]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// A file's content is not what was expected.
    #[error("{}: {message}", path.display())]
    Format { path: PathBuf, message: String },
    /// Not enough input.
    #[error("{0}")]
    Input(String),
}

impl KpEvalError {
    pub(crate) fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Self::Io {
            path: path.into(),
            source,
        }
    }

    pub(crate) fn stage(combo: &str, stage: &str, source: keylo_core::CoreError) -> Self {
        Self::Stage {
            combo: combo.into(),
            stage: stage.into(),
            source: Box::new(source),
        }
    }

    pub(crate) fn setting(origin: &str, key: &str, message: impl Into<String>) -> Self {
        Self::Setting {
            origin: origin.into(),
            key: key.into(),
            message: message.into(),
        }
    }
}
