//! One frame through the stages with a panic caught: a bug in a stage (keylo's or a plugin's)
//! fails that frame with an error instead of ending the program, so a run keeps the frames done
//! before it and a live node goes on with the next one.

use super::{FrameResult, Odometry};
use crate::{CoreError, FrameFeatures, LidarFrame};

impl Odometry {
    /// [`Odometry::process`] (with the features when `features`), a panic in a stage turned
    /// into a [`CoreError::Stage`] naming the frame.
    pub fn process_guarded(
        &mut self,
        frame: &LidarFrame,
        features: bool,
    ) -> Result<(FrameResult, Option<FrameFeatures>), CoreError> {
        let run = std::panic::AssertUnwindSafe(|| {
            if features {
                let (r, f) = self.process_with_features(frame)?;
                Ok((r, Some(f)))
            } else {
                self.process(frame).map(|r| (r, None))
            }
        });
        std::panic::catch_unwind(run).unwrap_or_else(|payload| {
            let what = payload
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| payload.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "no message".into());
            Err(CoreError::Stage {
                stage: "pipeline".into(),
                message: format!(
                    "frame {}: internal error (a stage panicked: {what}); please report it",
                    frame.index
                ),
            })
        })
    }
}
