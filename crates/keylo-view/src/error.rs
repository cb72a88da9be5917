//! Errors of the viewer and the recording.

use std::path::PathBuf;

/// What stops the viewer from starting or the recording from being written. A client that
/// disconnects is never an error.
#[derive(Debug, thiserror::Error)]
pub enum ViewError {
    /// `--view ADDRESS` is not `HOST:PORT`, or the server could not listen there.
    #[error("--view {address}: {message}")]
    Serve { address: String, message: String },
    /// The Foxglove SDK refused a channel.
    #[error("cannot make the channel {topic}: {message}")]
    Channel { topic: String, message: String },
    /// The MCAP file could not be created, written or closed.
    #[error("--record {}: {message}", path.display())]
    Record { path: PathBuf, message: String },
}
