//! The viewer: the live view and the recording, each on its own Foxglove context, fed the same
//! frames.

use std::time::{Duration, Instant};

use nalgebra::Point3;

use crate::frame_view::{FrameView, RecordSummary};
use crate::live::Live;
use crate::recorder::Recorder;
use crate::{RunInfo, ViewError, ViewOptions};

/// Streams a run's frames live and/or records them.
pub struct Viewer {
    live: Option<Live>,
    recorder: Option<Recorder>,
}

impl Viewer {
    /// Opens the recording (writing the run's metadata and config into it) and starts the
    /// server, as `options` ask.
    pub fn start(options: &ViewOptions, info: &RunInfo) -> Result<Self, ViewError> {
        // The server first: an address that cannot be served must not have emptied FILE.
        let live = match &options.serve {
            Some(address) => {
                let mut live = Live::start(address, options, info.reference.clone())?;
                live.streams().announce_images(&info.images);
                Some(live)
            }
            None => None,
        };
        let recorder = match &options.record {
            Some(path) => Some(Recorder::start(path, options, info)?),
            None => None,
        };
        Ok(Self { live, recorder })
    }

    /// `ws://HOST:PORT` of the live server (the port it took when asked for 0).
    pub fn url(&self) -> Option<String> {
        self.live.as_ref().map(Live::url)
    }

    /// Clients connected now.
    pub fn clients(&self) -> usize {
        self.live.as_ref().map_or(0, Live::clients)
    }

    /// Waits until a client has connected and subscribed to something (or a second after it
    /// connected), at most `timeout` (`None`: no limit) or until `stop` says so. Whether one
    /// came.
    pub fn wait_for_client(&self, timeout: Option<Duration>, stop: &dyn Fn() -> bool) -> bool {
        let start = Instant::now();
        let mut connected: Option<Instant> = None;
        loop {
            if self.clients() > 0 {
                let since = *connected.get_or_insert_with(Instant::now);
                let subscribed = self.live.as_ref().is_some_and(Live::any_subscribed);
                if subscribed || since.elapsed() > Duration::from_secs(1) {
                    return true;
                }
            }
            if stop() || timeout.is_some_and(|t| start.elapsed() >= t) {
                return false;
            }
            std::thread::sleep(Duration::from_millis(20));
        }
    }

    /// Whether the next frame sends the local map (the recording every `map_every` frames, the
    /// live view as often when a viewer takes it): only then is it worth fetching.
    pub fn wants_map(&self) -> bool {
        self.recorder.as_ref().is_some_and(Recorder::wants_map)
            || self.live.as_ref().is_some_and(Live::wants_map)
    }

    /// Sends one frame.
    pub fn frame(&mut self, v: &FrameView) {
        if let Some(r) = self.recorder.as_mut() {
            r.frame(v);
        }
        if let Some(l) = self.live.as_mut() {
            l.frame(v);
        }
    }

    /// Ends the run: sends the last map (`final_map`, when given) and paths, closes the
    /// recording and stops the server.
    pub fn finish(
        self,
        final_map: Option<&[Point3<f64>]>,
    ) -> Result<Option<RecordSummary>, ViewError> {
        let recorded = self.recorder.map(|r| r.finish(final_map)).transpose();
        if let Some(l) = self.live {
            l.finish(final_map);
        }
        recorded
    }
}
