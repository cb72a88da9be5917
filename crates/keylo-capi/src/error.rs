//! Errors of the C API.

/// Why a C API call failed; its text is what `keylo_pipeline_error` returns.
#[derive(Debug, thiserror::Error)]
pub enum CapiError {
    /// Building or feeding the pipeline failed (config, stage, plugin, points).
    #[error(transparent)]
    Frontend(#[from] keylo::Error),
    /// A bad argument, naming it.
    #[error("{0}")]
    Argument(String),
    /// keylo panicked inside the call (a bug); the pipeline should be freed.
    #[error("internal error (panic): {0}")]
    Panic(String),
}

impl From<keylo::CoreError> for CapiError {
    fn from(e: keylo::CoreError) -> Self {
        Self::Frontend(e.into())
    }
}
