//! Errors of the C API.

/// Why a C API call failed; its text is what `keylo_pipeline_error` returns.
#[derive(Debug, thiserror::Error)]
pub enum CapiError {
    #[error(transparent)]
    Config(#[from] keylo::ConfigError),
    #[cfg(feature = "plugins")]
    #[error(transparent)]
    Plugin(#[from] keylo::plugin::PluginError),
    #[error(transparent)]
    Core(#[from] keylo::CoreError),
    /// A bad argument, naming it.
    #[error("{0}")]
    Argument(String),
    /// keylo panicked inside the call (a bug); the pipeline should be freed.
    #[error("internal error (panic): {0}")]
    Panic(String),
}
