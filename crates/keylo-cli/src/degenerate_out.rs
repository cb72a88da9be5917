//! Degenerate frames in a run's output (`keylo_core::Degenerate`): a warning naming each of
//! the first few, the flag of every one in frames.csv and summary.json, and the closing
//! verdict when no frame was constrained.

use keylo::Degenerate;
use serde::Serialize;

/// Frames warned about one by one; the rest are counted (frames.csv flags each).
const WARNED: usize = 10;

/// Frames listed in summary.json at most (a node may run for days; frames.csv flags every
/// one and `frames_degenerate` counts them all).
const LISTED: usize = 100_000;

/// One degenerate frame in summary.json: `{"frame": 3, "reason": "too-few-points",
/// "points": 1, "minimum": 3}`.
#[derive(Debug, Clone, Serialize)]
pub struct DegenerateFrame {
    pub frame: u64,
    #[serde(flatten)]
    pub why: Degenerate,
}

/// The degenerate frames of a run so far.
#[derive(Debug, Default)]
pub struct DegenerateLog {
    /// The first [`LISTED`] of them.
    pub frames: Vec<DegenerateFrame>,
    /// All of them.
    pub count: usize,
}

impl DegenerateLog {
    /// Records frame `frame` (`name` in messages, `cloud_points` handed to the registrar)
    /// and warns about it while fewer than [`WARNED`] were.
    pub fn record(&mut self, frame: u64, name: &str, why: Degenerate, cloud_points: usize) {
        let n = self.count;
        self.count += 1;
        if n < WARNED {
            let hint = match why {
                Degenerate::TooFewPoints { points: 0, .. } => format!(
                    " ({cloud_points} points in the cloud, none within the registrar's range \
                     limits; registrar.empty_frame = \"error\" stops instead)"
                ),
                _ => String::new(),
            };
            tracing::warn!("{name} is degenerate: {}{hint}", why.describe());
        } else if n == WARNED {
            tracing::warn!(
                "more degenerate frames: not logged one by one; frames.csv (`degenerate`) and \
                 summary.json flag each"
            );
        }
        if self.frames.len() < LISTED {
            self.frames.push(DegenerateFrame { frame, why });
        }
    }

    /// Whether no pose of a run of `frames` frames, the first at index `first`, came from a
    /// registration that constrained it: every frame after the first is degenerate (the
    /// first is the origin, registered against nothing), or the only frame is.
    pub fn all_of(&self, frames: usize, first: u64) -> bool {
        let listed_first = self.frames.iter().any(|f| f.frame == first);
        let after_first = self.count - usize::from(listed_first);
        match frames {
            0 => false,
            1 => self.count > 0,
            n => after_first >= n - 1,
        }
    }

    /// The closing line of a run of `frames` frames with degenerate ones, if any.
    pub fn closing(&self, frames: usize) -> Option<String> {
        let first = self.frames.first()?;
        Some(format!(
            "{} of {frames} frames degenerate (the first, frame {}: {}); frames.csv and \
             summary.json flag each",
            self.count,
            first.frame,
            first.why.describe()
        ))
    }
}

/// The error stopping a run at a degenerate frame (`output.on_degenerate = "error"`).
pub fn stop_message(why: &Degenerate) -> String {
    format!(
        "degenerate frame: {} (output.on_degenerate = \"error\"; \"warn\" flags it and goes on)",
        why.describe()
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_frame_is_kept_and_the_verdict_counts_them() {
        let mut log = DegenerateLog::default();
        let why = Degenerate::TooFewPoints {
            points: 1,
            minimum: 3,
        };
        for k in 0..12 {
            log.record(k, &format!("frame {k}"), why, 1);
        }
        assert_eq!(log.frames.len(), 12);
        assert!(log.all_of(12, 0));
        // A first frame that is not degenerate does not save a run whose others all are.
        assert!(log.all_of(13, 99));
        assert!(!log.all_of(14, 0));
        assert!(!DegenerateLog::default().all_of(0, 0));
        assert!(!DegenerateLog::default().all_of(1, 0));
        let line = log.closing(13).unwrap();
        assert!(
            line.starts_with("12 of 13 frames degenerate (the first, frame 0: 1 registered point"),
            "{line}"
        );
        let json = serde_json::to_string(&log.frames[0]).unwrap();
        assert_eq!(
            json,
            r#"{"frame":0,"reason":"too-few-points","points":1,"minimum":3}"#
        );
    }
}
