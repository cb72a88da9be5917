//! The recording: its own Foxglove context with the MCAP writer, fed on a thread of its own so
//! that building and compressing the messages overlaps the run's next frames. Every frame is
//! recorded: when the thread falls behind by `QUEUE` frames, the run waits for it.

use std::path::{Path, PathBuf};
use std::sync::mpsc::{sync_channel, Receiver, SyncSender};
use std::thread::JoinHandle;

use foxglove::Context;
use keylo_core::{FrameFeatures, FrameResult, LidarFrame, PointCloud};
use nalgebra::Point3;

use crate::frame_view::{FrameView, RecordSummary};
use crate::streams::Streams;
use crate::{RunInfo, ViewError, ViewOptions};

/// Frames handed over and not yet written (each holds a copy of the frame: 4 MB at 1024×128).
const QUEUE: usize = 4;

/// A frame's results, owned, for the recording thread.
struct Owned {
    frame: LidarFrame,
    result: FrameResult,
    features: Option<FrameFeatures>,
    cloud: Option<PointCloud>,
    map: Option<Vec<Point3<f64>>>,
    seconds: f64,
}

enum Job {
    Frame(Box<Owned>),
    Finish(Option<Vec<Point3<f64>>>),
}

pub struct Recorder {
    tx: Option<SyncSender<Job>>,
    thread: Option<JoinHandle<Result<RecordSummary, ViewError>>>,
    path: PathBuf,
    /// Record the map every this many frames; `None`: a fixed map, recorded with the first.
    map_every: Option<u64>,
    frames: u64,
}

impl Recorder {
    /// Opens `path` (with the run's metadata and config) and starts the thread.
    pub fn start(path: &Path, options: &ViewOptions, info: &RunInfo) -> Result<Self, ViewError> {
        let ctx = Context::new();
        let handle = crate::record::open(&ctx, path, info)?;
        let frames = (options.world_frame.as_str(), options.sensor_frame.as_str());
        let mut streams = Streams::new(ctx, frames, info.reference.clone(), true)?;
        streams.announce_images(&info.images);
        let (tx, rx) = sync_channel(QUEUE);
        let owned_path = path.to_path_buf();
        let map_every = (!options.fixed_map).then_some(options.map_every.max(1));
        let thread = std::thread::Builder::new()
            .name("keylo-record".into())
            .spawn(move || {
                let frames = write(&mut streams, &rx, map_every);
                drop(streams);
                crate::record::close(handle, &owned_path)?;
                let bytes = std::fs::metadata(&owned_path).map_or(0, |m| m.len());
                Ok(RecordSummary {
                    path: owned_path,
                    bytes,
                    frames,
                })
            })
            .map_err(|e| ViewError::Record {
                path: path.to_path_buf(),
                message: format!("cannot start its thread: {e}"),
            })?;
        Ok(Self {
            tx: Some(tx),
            thread: Some(thread),
            path: path.to_path_buf(),
            map_every,
            frames: 0,
        })
    }

    /// Whether the next frame's map is recorded (every `map_every` frames from the first; a
    /// fixed map with the first frame only).
    pub fn wants_map(&self) -> bool {
        match self.map_every {
            Some(n) => self.frames.is_multiple_of(n),
            None => self.frames == 0,
        }
    }

    /// Hands a copy of the frame's results to the thread (waiting while it is `QUEUE` behind).
    pub fn frame(&mut self, v: &FrameView) {
        let owned = Owned {
            frame: v.frame.clone(),
            result: v.result.clone(),
            features: v.features.cloned(),
            cloud: v.cloud.cloned(),
            map: v.map.filter(|_| self.wants_map()).map(<[_]>::to_vec),
            seconds: v.seconds,
        };
        self.frames += 1;
        self.send(Job::Frame(Box::new(owned)));
    }

    fn send(&mut self, job: Job) {
        if let Some(tx) = &self.tx {
            if tx.send(job).is_err() {
                // The thread ended early: its error is reported by `finish`.
                tracing::error!("the recording {} stopped", self.path.display());
                self.tx = None;
            }
        }
    }

    /// Records the last map (not for a fixed map) and paths and closes the file.
    pub fn finish(mut self, map: Option<&[Point3<f64>]>) -> Result<RecordSummary, ViewError> {
        let map = map.filter(|_| self.map_every.is_some());
        self.send(Job::Finish(map.map(<[_]>::to_vec)));
        self.close()
    }

    fn close(&mut self) -> Result<RecordSummary, ViewError> {
        self.tx = None;
        let thread = self.thread.take().ok_or_else(|| ViewError::Record {
            path: self.path.clone(),
            message: "already closed".into(),
        })?;
        thread.join().unwrap_or_else(|_| {
            Err(ViewError::Record {
                path: self.path.clone(),
                message: "its thread panicked".into(),
            })
        })
    }
}

/// A run that ends early (an error before `finish`) still leaves a complete file: the frames
/// handed over, the paths, the summary.
impl Drop for Recorder {
    fn drop(&mut self) {
        if self.thread.is_some() {
            self.send(Job::Finish(None));
            if let Err(e) = self.close() {
                tracing::error!("{e}");
            }
        }
    }
}

/// The thread's loop: every frame's messages, the map and paths every `map_every` frames, the
/// last map and paths at the end. The frames written.
fn write(streams: &mut Streams, rx: &Receiver<Job>, map_every: Option<u64>) -> u64 {
    let mut frames = 0u64;
    while let Ok(job) = rx.recv() {
        match job {
            Job::Frame(o) => {
                let v = FrameView {
                    frame: &o.frame,
                    result: &o.result,
                    features: o.features.as_ref(),
                    cloud: o.cloud.as_ref(),
                    map: o.map.as_deref(),
                    seconds: o.seconds,
                };
                streams.light(&v);
                streams.heavy(&v);
                if frames.is_multiple_of(map_every.unwrap_or(u64::MAX)) {
                    if let Some(map) = &o.map {
                        streams.map(o.result.stamp, map);
                    }
                    streams.paths();
                }
                frames += 1;
            }
            Job::Finish(map) => {
                if let (Some(stamp), Some(map)) = (streams.last_stamp(), map) {
                    streams.map(stamp, &map);
                }
                streams.paths();
                break;
            }
        }
    }
    frames
}
