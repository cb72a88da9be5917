//! The live view: the Foxglove SDK's WebSocket server on its own context. The small messages
//! go every frame; the large ones (scan, registered cloud, images, map) at most `max_hz` times a
//! second of wall time, as a person can watch them (a file run may go at 200 frames/s).

use std::sync::Arc;
use std::time::{Duration, Instant};

use foxglove::{Context, WebSocketServerHandle};
use keylo_core::Trajectory;

use crate::frame_view::FrameView;
use crate::streams::Streams;
use crate::{ViewError, ViewOptions};

/// Messages queued per client before its oldest are dropped: about ten frames' worth, so a
/// stalled client holds tens of megabytes at most (a scan of 1024×128 is 4 MB), not the SDK's
/// default 1024 messages.
const BACKLOG: usize = 128;

/// How long the end of a run waits for the server to close its connections.
const STOP_WAIT: Duration = Duration::from_secs(2);

pub struct Live {
    streams: Streams,
    server: WebSocketServerHandle,
    host: String,
    /// Least wall time between two frames' large messages (`None`: every frame).
    interval: Option<Duration>,
    last_heavy: Option<Instant>,
    map_every: u64,
    frames_since_map: u64,
}

impl Live {
    pub fn start(
        address: &str,
        options: &ViewOptions,
        reference: Option<Trajectory>,
    ) -> Result<Self, ViewError> {
        let ctx = Context::new();
        let (host, server) = serve(&ctx, address)?;
        let frames = (options.world_frame.as_str(), options.sensor_frame.as_str());
        let streams = Streams::new(ctx, frames, reference, false)?;
        Ok(Self {
            streams,
            server,
            host,
            interval: (options.max_hz > 0.0).then(|| Duration::from_secs_f64(1.0 / options.max_hz)),
            last_heavy: None,
            map_every: options.map_every.max(1),
            frames_since_map: options.map_every.max(1),
        })
    }

    pub fn url(&self) -> String {
        format!("ws://{}:{}", self.host, self.server.port())
    }

    pub fn clients(&self) -> usize {
        self.server.client_count()
    }

    pub fn streams(&mut self) -> &mut Streams {
        &mut self.streams
    }

    pub fn any_subscribed(&self) -> bool {
        self.streams.any_subscribed()
    }

    /// Whether this frame may send the large messages: a fifth of the interval early still
    /// counts, so frames that come at `max_hz` with some jitter (a sensor played at its rate)
    /// all pass.
    fn due(&self) -> bool {
        match (self.interval, self.last_heavy) {
            (Some(i), Some(t)) => t.elapsed() >= i.mul_f64(0.8),
            _ => true,
        }
    }

    /// Whether the next frame sends the map (and a viewer takes it).
    pub fn wants_map(&self) -> bool {
        self.due() && self.frames_since_map >= self.map_every && self.streams.takes_map()
    }

    pub fn frame(&mut self, v: &FrameView) {
        let due = self.due();
        let paths = due && self.frames_since_map >= self.map_every;
        self.streams.light(v);
        if due {
            self.streams.heavy(v);
            self.last_heavy = Some(Instant::now());
        }
        self.frames_since_map += 1;
        if paths {
            match v.map {
                Some(map) => self.streams.map(v.result.stamp, map),
                // The frame became due after the caller asked: the map goes with the next one.
                None if self.streams.takes_map() => {
                    self.streams.paths();
                    return;
                }
                None => {}
            }
            self.streams.paths();
            self.frames_since_map = 0;
        }
    }

    /// Sends the last map and paths, lets the clients' queues drain, stops the server.
    pub fn finish(self, map: Option<&[nalgebra::Point3<f64>]>) {
        if let (Some(stamp), Some(map)) = (self.streams.last_stamp(), map) {
            self.streams.map(stamp, map);
        }
        self.streams.paths();
        if self.server.client_count() > 0 {
            std::thread::sleep(Duration::from_millis(300));
        }
        // A client that stopped reading never lets its close be written: wait for a clean
        // stop at most STOP_WAIT, then leave the server's tasks to end with the process.
        let shutdown = self.server.stop();
        let (done, waited) = std::sync::mpsc::channel();
        let waiter = std::thread::spawn(move || {
            shutdown.wait_blocking();
            let _ = done.send(());
        });
        if waited.recv_timeout(STOP_WAIT).is_ok() {
            let _ = waiter.join();
        }
    }
}

/// Starts the WebSocket server at `HOST:PORT`; the host as given.
fn serve(ctx: &Arc<Context>, address: &str) -> Result<(String, WebSocketServerHandle), ViewError> {
    let err = |message: String| ViewError::Serve {
        address: address.to_string(),
        message,
    };
    let (host, port) = address
        .rsplit_once(':')
        .ok_or_else(|| err("expected HOST:PORT, e.g. 127.0.0.1:8765".into()))?;
    let port: u16 = port
        .parse()
        .map_err(|_| err(format!("port `{port}` is not a number 0..=65535")))?;
    let bare = host.trim_start_matches('[').trim_end_matches(']');
    let server = ctx
        .websocket_server()
        .name("keylo")
        .message_backlog_size(BACKLOG)
        .bind(bare, port)
        .start_blocking()
        .map_err(|e| err(e.to_string()))?;
    Ok((host.to_string(), server))
}
