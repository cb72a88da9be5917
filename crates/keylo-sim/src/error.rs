//! Errors of the simulator crate.

/// An error raised while validating a [`crate::SimConfig`] or building a scene.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SimError {
    /// A config field holds a value the simulator cannot use; `field` is its key.
    #[error("sim config `{field}`: {message}")]
    InvalidConfig {
        /// The key of the offending field, e.g. `columns`.
        field: &'static str,
        /// What is wrong and what is allowed.
        message: String,
    },
    /// The generated scene is unusable (e.g. the trajectory runs through an object).
    #[error("sim scene `{scene}`: {message}")]
    Scene {
        /// The scene name.
        scene: &'static str,
        /// What went wrong.
        message: String,
    },
}

impl SimError {
    /// Shorthand for [`SimError::InvalidConfig`].
    pub(crate) fn config(field: &'static str, message: impl Into<String>) -> Self {
        Self::InvalidConfig {
            field,
            message: message.into(),
        }
    }

    /// The config key this error is about, if any.
    pub fn field(&self) -> Option<&'static str> {
        match self {
            Self::InvalidConfig { field, .. } => Some(field),
            Self::Scene { .. } => None,
        }
    }
}
