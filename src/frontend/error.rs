//! Errors of [`crate::Frontend`].

/// Why building or feeding a [`crate::Frontend`] failed.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The config (TOML or built in code) is invalid; the message names the key.
    #[error(transparent)]
    Config(#[from] keylo_core::ConfigError),
    /// A stage failed to build or to process a frame.
    #[error(transparent)]
    Core(#[from] keylo_core::CoreError),
    /// A run-time plugin named by the config failed to load.
    #[cfg(feature = "plugins")]
    #[error(transparent)]
    Plugin(#[from] keylo_plugin::PluginError),
    /// A `[source.projection]` value the projection cannot take.
    #[error("[source.projection]: {0}")]
    Projection(keylo_io::cloud::CloudError),
    /// A cloud handed to `push_points`/`push_cloud` that cannot make a frame (fields of
    /// another length than the points, a ring outside the grid, …).
    #[error("frame {frame}: points: {source}")]
    Points {
        frame: u64,
        source: keylo_io::cloud::CloudError,
    },
    /// The map being saved ([`crate::Frontend::save_map`]) could not be written, or its
    /// settings are out of range.
    #[error(transparent)]
    Map(#[from] keylo_map::MapError),
    /// `push_points` with another number of times than points.
    #[error("frame {frame}: `times` has {times} values for {points} points (one time per point expected)")]
    TimesLength {
        frame: u64,
        times: usize,
        points: usize,
    },
}
