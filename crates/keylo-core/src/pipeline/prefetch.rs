//! A source read ahead on its own thread: frame N+1 is read and indexed while frame N is
//! registered. The frames and their order are the source's own, so results do not change.

use std::sync::mpsc::{sync_channel, Receiver};
use std::sync::{Arc, Mutex, PoisonError};
use std::thread::JoinHandle;

use crate::stages::{ImageSource, SourceInfo};
use crate::{CoreError, LidarFrame, Trajectory};

type Shared = Arc<Mutex<Box<dyn ImageSource>>>;

/// Reads up to `depth` frames ahead of the consumer on a background thread.
pub struct Prefetched {
    source: Shared,
    frames: Option<Receiver<Option<Result<LidarFrame, CoreError>>>>,
    reader: Option<JoinHandle<()>>,
}

impl Prefetched {
    /// Starts reading `source` ahead (`depth` ≥ 1 frames buffered). The thread stops at the
    /// end of the source, after an error, or when `self` is dropped.
    pub fn new(source: Box<dyn ImageSource>, depth: usize) -> Result<Self, CoreError> {
        let source: Shared = Arc::new(Mutex::new(source));
        let (tx, rx) = sync_channel(depth.max(1));
        let shared = Arc::clone(&source);
        let reader = std::thread::Builder::new()
            .name("keylo-source".into())
            .spawn(move || loop {
                let next = shared
                    .lock()
                    .unwrap_or_else(PoisonError::into_inner)
                    .next_frame();
                let last = !matches!(next, Some(Ok(_)));
                if tx.send(next).is_err() || last {
                    break;
                }
            })
            .map_err(|e| CoreError::stage("source", format!("cannot start the reader: {e}")))?;
        Ok(Self {
            source,
            frames: Some(rx),
            reader: Some(reader),
        })
    }

    fn with_source<T>(&self, f: impl FnOnce(&dyn ImageSource) -> T) -> T {
        f(self
            .source
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .as_ref())
    }
}

impl ImageSource for Prefetched {
    fn info(&self) -> SourceInfo {
        self.with_source(|s| s.info())
    }

    fn next_frame(&mut self) -> Option<Result<LidarFrame, CoreError>> {
        let received = self.frames.as_ref()?.recv();
        match received {
            Ok(Some(item)) => Some(item),
            // The end, or the reader is gone (it panicked: say so rather than end quietly).
            Ok(None) => None,
            Err(_) => {
                self.frames = None;
                let panicked = self.reader.take().map(JoinHandle::join);
                panicked.and_then(|r| r.err()).map(|_| {
                    Err(CoreError::stage(
                        "source",
                        "the reader thread panicked (a bug: please report it)",
                    ))
                })
            }
        }
    }

    fn details(&self) -> Vec<(String, String)> {
        self.with_source(|s| s.details())
    }

    fn frame_origin(&self, index: u64) -> Option<String> {
        self.with_source(|s| s.frame_origin(index))
    }

    fn counters(&self) -> Vec<(String, u64)> {
        self.with_source(|s| s.counters())
    }

    fn set_grid_needed(&mut self, needed: bool) {
        // Frames already read ahead keep the grid they were read with.
        self.source
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .set_grid_needed(needed);
    }

    fn ground_truth(&self) -> Option<Trajectory> {
        self.with_source(|s| s.ground_truth())
    }
}

impl Drop for Prefetched {
    fn drop(&mut self) {
        // Closing the channel stops the reader at its next send.
        self.frames = None;
        if let Some(reader) = self.reader.take() {
            let _ = reader.join();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::BeamGeometry;

    /// Frames 0..n, then an error when `fail` is set.
    struct Counter {
        next: u64,
        n: u64,
        fail: bool,
    }

    impl ImageSource for Counter {
        fn info(&self) -> SourceInfo {
            SourceInfo {
                description: "counter".into(),
                frames: Some(self.n as usize),
            }
        }
        fn next_frame(&mut self) -> Option<Result<LidarFrame, CoreError>> {
            let i = self.next;
            self.next += 1;
            if i == self.n && self.fail {
                return Some(Err(CoreError::stage("source", "broken file")));
            }
            (i < self.n).then(|| {
                let beams = Arc::new(BeamGeometry::unknown("t", 1));
                Ok(LidarFrame::empty(i, i as f64, 1, 1, beams))
            })
        }
        fn frame_origin(&self, index: u64) -> Option<String> {
            Some(format!("file{index}"))
        }
    }

    #[test]
    fn frames_come_in_order_then_the_end_or_the_error() {
        for fail in [false, true] {
            let source = Box::new(Counter {
                next: 0,
                n: 5,
                fail,
            });
            let mut p = Prefetched::new(source, 2).unwrap();
            assert_eq!(p.info().frames, Some(5));
            assert_eq!(p.frame_origin(3).as_deref(), Some("file3"));
            let mut seen = Vec::new();
            let mut error = None;
            while let Some(item) = p.next_frame() {
                match item {
                    Ok(f) => seen.push(f.index),
                    Err(e) => error = Some(e.to_string()),
                }
            }
            assert_eq!(seen, vec![0, 1, 2, 3, 4]);
            assert_eq!(error.is_some(), fail);
            assert!(p.next_frame().is_none());
        }
    }

    #[test]
    fn dropping_it_early_stops_the_reader() {
        let source = Box::new(Counter {
            next: 0,
            n: 1_000_000,
            fail: false,
        });
        let mut p = Prefetched::new(source, 1).unwrap();
        assert!(p.next_frame().is_some());
        drop(p);
    }
}
