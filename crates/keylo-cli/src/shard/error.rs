//! Errors of sharded studies: a bad `--shard`, a shard folder that is not one, and shards that
//! do not make one whole study.

use std::path::PathBuf;

#[derive(Debug, thiserror::Error)]
pub enum ShardError {
    /// `--shard` is not `I/N` with `0 ≤ I < N` (clap names the flag and value before it).
    #[error("{why}")]
    BadSpec { given: String, why: String },
    /// A file or folder could not be read or written.
    #[error("{}: {source}", path.display())]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    /// A folder without a readable manifest of this keylo.
    #[error("{}: {why}", dir.display())]
    NotAShard { dir: PathBuf, why: String },
    /// `--out` holds a shard of another study or another shard of this one: nothing is
    /// overwritten.
    #[error("{}: {why}; nothing was overwritten (use another --out, or delete it)", dir.display())]
    OutTaken { dir: PathBuf, why: String },
    /// The shards given to `merge` are not one complete study.
    #[error("{0}")]
    Mismatch(String),
}

impl ShardError {
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Self::Io {
            path: path.into(),
            source,
        }
    }
}
