//! Errors of the core crate.

use std::path::PathBuf;

/// An error in a config file or a `--set` override. Every variant names the key path.
#[derive(Debug, thiserror::Error)]
pub enum ConfigError {
    /// The config file could not be read.
    #[error("cannot read config file {path}: {source}")]
    Read {
        path: PathBuf,
        source: std::io::Error,
    },
    /// The file is not valid TOML.
    #[error("{origin}: invalid TOML: {message}")]
    Syntax { origin: String, message: String },
    /// A top-level section that keylo does not know.
    #[error("{origin}: unknown section `[{section}]`; allowed sections: {allowed}")]
    UnknownSection {
        origin: String,
        section: String,
        allowed: String,
    },
    /// A `kind` that no registered backend provides.
    #[error("{origin}: `{section}.kind = \"{kind}\"` is not a known {section} backend; allowed: {allowed}")]
    UnknownKind {
        origin: String,
        section: String,
        kind: String,
        allowed: String,
    },
    /// A key or value rejected by a backend's parameter schema.
    #[error("{origin}: `{path}`: {message}")]
    Invalid {
        origin: String,
        path: String,
        message: String,
    },
    /// A malformed `--set key.path=value` override.
    #[error("--set `{text}`: {message}")]
    Override { text: String, message: String },
    /// A config naming shared libraries to load, without the caller's opt-in.
    #[error(
        "{origin} names code to load: {libraries}. A config's own libraries load only when you \
         trust it ({opt_in}); plugins installed in KEYLO_PLUGIN_PATH or \
         ~/.local/lib/keylo/plugins load without it",
        opt_in = crate::config::TRUST_OPT_IN
    )]
    Untrusted { origin: String, libraries: String },
}

/// A frame or scan whose arrays disagree in length, or hold an index or value out of range;
/// names the field.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ShapeError {
    /// An array of another length than the frame's shape says.
    #[error("{field} has {len} entries, expected {what} = {expected}")]
    Length {
        field: &'static str,
        len: usize,
        /// What the length should equal (`rows*cols`, `cols`, `points`).
        what: &'static str,
        expected: usize,
    },
    /// An index array with an entry beyond what it indexes.
    #[error("{field} has an entry >= {what} = {limit}")]
    IndexOutOfRange {
        field: &'static str,
        what: &'static str,
        limit: usize,
    },
    /// A scan point with a NaN or infinite coordinate.
    #[error("scan.points holds a non-finite coordinate")]
    NonFinitePoint,
}

/// An error raised while building or running a stage.
#[derive(Debug, thiserror::Error)]
pub enum CoreError {
    #[error(transparent)]
    Config(#[from] ConfigError),
    /// A frame or cloud whose content a stage cannot use.
    #[error("frame {frame}: {message}")]
    BadFrame { frame: u64, message: String },
    /// An input file problem, naming the file.
    #[error("{path}: {message}")]
    Input { path: PathBuf, message: String },
    /// A stage failed for a reason of its own (e.g. a registrar diverged).
    #[error("{stage}: {message}")]
    Stage { stage: String, message: String },
    #[error("I/O error on {path}: {source}")]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
}

impl CoreError {
    /// Shorthand for [`CoreError::Stage`].
    pub fn stage(stage: impl Into<String>, message: impl Into<String>) -> Self {
        Self::Stage {
            stage: stage.into(),
            message: message.into(),
        }
    }

    /// Shorthand for [`CoreError::Input`].
    pub fn input(path: impl Into<PathBuf>, message: impl Into<String>) -> Self {
        Self::Input {
            path: path.into(),
            message: message.into(),
        }
    }
}
