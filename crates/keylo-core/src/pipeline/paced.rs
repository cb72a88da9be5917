//! A source played back at its sensor's rate: each frame is released at its timestamp (relative
//! to the first frame's, divided by `speed`), as a live sensor delivers it, so CPU use and memory
//! are measured at that rate, the paper's measure. The frames and their order are the source's
//! own, so results do not change.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use crate::stages::{ImageSource, SourceInfo};
use crate::{CoreError, LidarFrame, Trajectory};

/// A frame asked for more than this after its release time counts as late.
const LATE_AFTER: Duration = Duration::from_millis(1);

/// Releases the frames of a source at their timestamps.
pub struct Paced {
    source: Box<dyn ImageSource>,
    speed: f64,
    /// Wall time and timestamp of the first frame.
    start: Option<(Instant, f64)>,
    late: Arc<AtomicU64>,
}

impl Paced {
    /// Plays `source` back at `speed` × its own rate (1: real time).
    pub fn new(source: Box<dyn ImageSource>, speed: f64) -> Result<Self, CoreError> {
        if !(speed.is_finite() && speed > 0.0) {
            return Err(CoreError::stage(
                "source",
                format!("playback speed {speed}: expected a number above 0"),
            ));
        }
        Ok(Self {
            source,
            speed,
            start: None,
            late: Arc::new(AtomicU64::new(0)),
        })
    }

    /// The count of frames asked for after their release time (the consumer did not keep
    /// up), readable after `self` is boxed away into a pipeline.
    pub fn late_frames(&self) -> Arc<AtomicU64> {
        Arc::clone(&self.late)
    }

    /// Waits until `frame` is due (the first frame is due at once).
    fn release(&mut self, frame: &LidarFrame) {
        let Some((wall0, t0)) = self.start else {
            self.start = Some((Instant::now(), frame.timestamp));
            return;
        };
        let after = ((frame.timestamp - t0) / self.speed).max(0.0);
        let due = wall0 + Duration::try_from_secs_f64(after).unwrap_or(Duration::MAX / 2);
        let now = Instant::now();
        if due > now {
            std::thread::sleep(due - now);
        } else if now - due > LATE_AFTER {
            self.late.fetch_add(1, Ordering::Relaxed);
        }
    }
}

impl ImageSource for Paced {
    fn info(&self) -> SourceInfo {
        self.source.info()
    }

    fn next_frame(&mut self) -> Option<Result<LidarFrame, CoreError>> {
        let next = self.source.next_frame()?;
        if let Ok(frame) = &next {
            self.release(frame);
        }
        Some(next)
    }

    fn details(&self) -> Vec<(String, String)> {
        self.source.details()
    }

    fn set_grid_needed(&mut self, needed: bool) {
        self.source.set_grid_needed(needed);
    }

    fn frame_origin(&self, index: u64) -> Option<String> {
        self.source.frame_origin(index)
    }

    fn counters(&self) -> Vec<(String, u64)> {
        self.source.counters()
    }

    fn ground_truth(&self) -> Option<Trajectory> {
        self.source.ground_truth()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::BeamGeometry;

    /// Frames 0..n at 10 Hz.
    struct Ticks {
        next: u64,
        n: u64,
    }

    impl ImageSource for Ticks {
        fn info(&self) -> SourceInfo {
            SourceInfo {
                description: "ticks".into(),
                frames: Some(self.n as usize),
            }
        }

        fn next_frame(&mut self) -> Option<Result<LidarFrame, CoreError>> {
            (self.next < self.n).then(|| {
                let i = self.next;
                self.next += 1;
                let beams = Arc::new(BeamGeometry::unknown("t", 1));
                Ok(LidarFrame::empty(i, 0.1 * i as f64, 1, 1, beams))
            })
        }
    }

    #[test]
    fn frames_are_released_at_their_timestamps_and_unchanged() {
        let mut paced = Paced::new(Box::new(Ticks { next: 0, n: 4 }), 2.0).unwrap();
        let start = Instant::now();
        let mut indices = Vec::new();
        while let Some(frame) = paced.next_frame() {
            indices.push(frame.unwrap().index);
        }
        // Frame 3 is due 0.3 s / 2 after frame 0.
        assert!(
            start.elapsed() >= Duration::from_millis(150),
            "{:?}",
            start.elapsed()
        );
        assert_eq!(indices, vec![0, 1, 2, 3]);
    }

    #[test]
    fn a_slow_consumer_makes_frames_late() {
        let mut paced = Paced::new(Box::new(Ticks { next: 0, n: 3 }), 10.0).unwrap();
        while let Some(frame) = paced.next_frame() {
            frame.unwrap();
            std::thread::sleep(Duration::from_millis(30)); // frames are 10 ms apart
        }
        assert_eq!(paced.late_frames().load(Ordering::Relaxed), 2);
    }

    #[test]
    fn a_speed_that_is_not_positive_is_refused() {
        for speed in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            let err = Paced::new(Box::new(Ticks { next: 0, n: 1 }), speed).err();
            assert!(
                err.is_some_and(|e| e.to_string().contains("above 0")),
                "{speed}"
            );
        }
    }
}
