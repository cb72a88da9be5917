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
    /// Points handed to `push_points`/`push_cloud` that cannot make a frame (wrong lengths,
    /// a ring outside the grid, …), or a bad `[source.projection]`.
    #[error("{0}")]
    Points(String),
}
