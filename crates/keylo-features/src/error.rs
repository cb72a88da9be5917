use keylo_core::CoreError;

/// Errors of the keypoint front end.
#[derive(Debug, thiserror::Error)]
pub enum FeaturesError {
    /// A parameter outside its valid range, or a combination that cannot work.
    #[error("`{field}` = {value}: {expected}")]
    BadParameter {
        field: String,
        value: String,
        expected: String,
    },
    /// A backend this build cannot offer (e.g. SURF without the cargo feature `nonfree`).
    #[error("{0}")]
    Unavailable(String),
    /// An input (image, keypoints, frame) the stage cannot use.
    #[error("{0}")]
    BadInput(String),
    /// OpenCV failed; `what` says which call.
    #[error("OpenCV {what}: {message}")]
    OpenCv { what: String, message: String },
}

impl FeaturesError {
    /// A [`FeaturesError::BadParameter`].
    pub fn bad_parameter(
        field: impl Into<String>,
        value: impl std::fmt::Debug,
        expected: impl Into<String>,
    ) -> Self {
        Self::BadParameter {
            field: field.into(),
            value: format!("{value:?}"),
            expected: expected.into(),
        }
    }

    /// Wraps an OpenCV error, naming the call that failed.
    pub fn opencv(what: impl Into<String>, e: opencv::Error) -> Self {
        Self::OpenCv {
            what: what.into(),
            message: e.message,
        }
    }

    /// Converts to the core error of `stage` (`image`, `detector`, `descriptor`, `downsampler`).
    pub fn in_stage(self, stage: &str) -> CoreError {
        CoreError::stage(stage, self.to_string())
    }
}

/// Checks `ok`, else a [`FeaturesError::BadParameter`].
pub(crate) fn check(
    ok: bool,
    field: &str,
    value: impl std::fmt::Debug,
    expected: &str,
) -> Result<(), FeaturesError> {
    if ok {
        Ok(())
    } else {
        Err(FeaturesError::bad_parameter(field, value, expected))
    }
}
