//! The viewer: a Foxglove SDK context with a WebSocket server and/or an MCAP writer as sinks.

use std::collections::HashMap;
use std::fs::File;
use std::io::BufWriter;
use std::path::PathBuf;
use std::sync::Arc;
use std::time::{Duration, Instant};

use foxglove::messages::{ImageAnnotations, PoseInFrame, PosesInFrame, RawImage};
use foxglove::{Channel, Context, McapWriterHandle, PartialMetadata, WebSocketServerHandle};
use keylo_core::{FrameFeatures, FrameResult, LidarFrame, PointCloud, Trajectory};
use nalgebra::Point3;

use crate::channels::Channels;
use crate::convert::{self, nanos, timestamp};
use crate::{images, reference, scan_cdr, stats, RunInfo, ViewError, ViewOptions};

/// One frame's results, as the viewer takes them.
pub struct FrameView<'a> {
    pub frame: &'a LidarFrame,
    pub result: &'a FrameResult,
    /// The images, keypoints and descriptors (`None` when the features were not kept).
    pub features: Option<&'a FrameFeatures>,
    /// The points the registrar was given (sensor frame).
    pub cloud: Option<&'a PointCloud>,
    /// The local map (world frame): give it when [`Viewer::wants_map`] said so.
    pub map: Option<&'a [Point3<f64>]>,
    /// Seconds every stage of the frame took.
    pub seconds: f64,
}

/// The recording written.
#[derive(Debug, Clone)]
pub struct RecordSummary {
    pub path: PathBuf,
    pub bytes: u64,
    pub frames: u64,
}

/// Streams a run's frames live and/or records them.
pub struct Viewer {
    ctx: Arc<Context>,
    server: Option<WebSocketServerHandle>,
    mcap: Option<(McapWriterHandle<BufWriter<File>>, PathBuf)>,
    options: ViewOptions,
    ch: Channels,
    images: HashMap<String, (Channel<RawImage>, Channel<ImageAnnotations>)>,
    trajectory: Vec<(f64, keylo_core::Pose)>,
    reference: Option<Trajectory>,
    aligned: Option<Vec<(f64, keylo_core::Pose)>>,
    frames: u64,
}

impl Viewer {
    /// Opens the recording (writing the run's metadata and config into it) and starts the
    /// server, as `options` ask.
    pub fn start(options: &ViewOptions, info: &RunInfo) -> Result<Self, ViewError> {
        let ctx = Context::new();
        let mcap = match &options.record {
            Some(path) => Some((crate::record::open(&ctx, path, info)?, path.clone())),
            None => None,
        };
        let server = match &options.serve {
            Some(address) => Some(serve(&ctx, address)?),
            None => None,
        };
        let ch = Channels::new(&ctx)?;
        Ok(Self {
            ctx,
            server,
            mcap,
            options: options.clone(),
            ch,
            images: HashMap::new(),
            trajectory: Vec::new(),
            reference: None,
            aligned: None,
            frames: 0,
        })
    }

    /// `ws://HOST:PORT` of the live server (the port it took when asked for 0).
    pub fn url(&self) -> Option<String> {
        let s = self.server.as_ref()?;
        let host = self
            .options
            .serve
            .as_deref()
            .and_then(|a| a.rsplit_once(':'))
            .map_or("127.0.0.1", |(h, _)| h);
        Some(format!("ws://{host}:{}", s.port()))
    }

    /// Clients connected now.
    pub fn clients(&self) -> usize {
        self.server
            .as_ref()
            .map_or(0, WebSocketServerHandle::client_count)
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
                if self.ch.any_subscribed() || since.elapsed() > Duration::from_secs(1) {
                    return true;
                }
            }
            if stop() || timeout.is_some_and(|t| start.elapsed() >= t) {
                return false;
            }
            std::thread::sleep(Duration::from_millis(20));
        }
    }

    /// Advertises the images `names` before the first frame, so a client can subscribe to them
    /// from the start.
    pub fn announce_images(&mut self, names: &[String]) {
        for n in names {
            self.image_channels(n);
        }
    }

    /// The reference trajectory (ground truth) to draw beside the estimate.
    pub fn set_reference(&mut self, reference: Trajectory) {
        self.reference = Some(reference);
    }

    /// Whether the next frame sends the local map (every `map_every` frames, when anyone
    /// takes it): only then is it worth fetching.
    pub fn wants_map(&self) -> bool {
        self.frames.is_multiple_of(self.options.map_every.max(1)) && self.ch.map.has_sinks()
    }

    /// Sends one frame.
    pub fn frame(&mut self, v: &FrameView) {
        let r = v.result;
        let stamp = r.stamp;
        let meta = PartialMetadata::with_log_time(nanos(stamp));
        let (world, sensor) = (&self.options.world_frame, &self.options.sensor_frame);
        // The sensor's pose at the frame's start too, so that the scan (stamped there) finds a
        // transform from the first frame on.
        for t in [v.frame.timestamp, stamp] {
            let tf = convert::transform(t, world, sensor, &r.pose);
            self.ch.tf.log_with_time(&tf, nanos(t));
        }
        self.ch.pose.log_with_time(
            &PoseInFrame {
                timestamp: Some(timestamp(stamp)),
                frame_id: world.clone(),
                pose: Some(convert::pose(&r.pose)),
            },
            nanos(stamp),
        );
        if self.ch.scan.has_sinks() {
            let bytes = scan_cdr::scan(v.frame, sensor);
            self.ch.scan.log_with_meta(
                &bytes,
                PartialMetadata::with_log_time(nanos(v.frame.timestamp)),
            );
        }
        if let Some(c) = v.cloud.filter(|_| self.ch.registered.has_sinks()) {
            let msg = convert::cloud(stamp, sensor, c.points.iter());
            self.ch.registered.log_with_time(&msg, nanos(stamp));
        }
        if let Some(f) = v.features {
            self.features(stamp, f);
        }
        self.ch
            .stats
            .log_with_meta(&stats::message(r, 1e3 * v.seconds), meta);
        self.trajectory.push((stamp, r.pose));
        if self.aligned.is_none() {
            self.aligned =
                (self.reference.as_ref()).and_then(|t| reference::aligned(t, stamp, &r.pose));
        }
        if let Some(map) = v.map {
            self.map(stamp, map);
        }
        if self.frames.is_multiple_of(self.options.map_every.max(1)) {
            self.paths(stamp);
        }
        self.frames += 1;
    }

    fn features(&mut self, stamp: f64, features: &FrameFeatures) {
        let sensor = self.options.sensor_frame.clone();
        for c in &features.per_image {
            let (image, keypoints) = self.image_channels(&c.image.name());
            if image.has_sinks() {
                image.log_with_time(&images::raw_image(stamp, &sensor, &c.image), nanos(stamp));
            }
            if keypoints.has_sinks() {
                keypoints.log_with_time(&images::keypoints(stamp, &c.keypoints), nanos(stamp));
            }
        }
    }

    fn image_channels(&mut self, name: &str) -> &(Channel<RawImage>, Channel<ImageAnnotations>) {
        let ctx = &self.ctx;
        self.images.entry(name.to_string()).or_insert_with(|| {
            (
                ctx.channel_builder(crate::topics::image(name)).build(),
                ctx.channel_builder(crate::topics::keypoints(name)).build(),
            )
        })
    }

    /// Sends the local map (world frame).
    fn map(&self, stamp: f64, map: &[Point3<f64>]) {
        let msg = convert::cloud(stamp, &self.options.world_frame, map.iter());
        self.ch.map.log_with_time(&msg, nanos(stamp));
    }

    /// Sends the trajectory so far and the reference.
    fn paths(&self, stamp: f64) {
        let world = &self.options.world_frame;
        let send = |ch: &Channel<PosesInFrame>, poses: &[(f64, keylo_core::Pose)]| {
            if ch.has_sinks() {
                let step = poses.len().div_ceil(reference::MAX_POSES).max(1);
                let msg = PosesInFrame {
                    timestamp: Some(timestamp(stamp)),
                    frame_id: world.clone(),
                    poses: (poses.iter().enumerate())
                        .filter(|(i, _)| i % step == 0 || *i + 1 == poses.len())
                        .map(|(_, (_, p))| convert::pose(p))
                        .collect(),
                };
                ch.log_with_time(&msg, nanos(stamp));
            }
        };
        send(&self.ch.trajectory, &self.trajectory);
        if let Some(a) = &self.aligned {
            send(&self.ch.reference, a);
        }
    }

    /// Ends the run: sends the last map (`final_map`, when given) and paths, stops the server
    /// and closes the recording.
    pub fn finish(
        self,
        final_map: Option<&[Point3<f64>]>,
    ) -> Result<Option<RecordSummary>, ViewError> {
        if let Some(&(stamp, _)) = self.trajectory.last() {
            if let Some(map) = final_map.filter(|_| self.ch.map.has_sinks()) {
                self.map(stamp, map);
            }
            self.paths(stamp);
        }
        if let Some(server) = self.server {
            // Let the clients' queues drain before the connections close.
            if server.client_count() > 0 {
                std::thread::sleep(Duration::from_millis(300));
            }
            server.stop().wait_blocking();
        }
        match self.mcap {
            Some((handle, path)) => {
                crate::record::close(handle, &path)?;
                let bytes = std::fs::metadata(&path).map(|m| m.len()).unwrap_or(0);
                Ok(Some(RecordSummary {
                    path,
                    bytes,
                    frames: self.frames,
                }))
            }
            None => Ok(None),
        }
    }

    /// Whether anything will see the frames (a recording, or a server).
    pub fn is_active(&self) -> bool {
        self.mcap.is_some() || self.server.is_some()
    }
}

/// Messages queued per client before its oldest are dropped: about ten frames' worth, so a
/// stalled client holds tens of megabytes at most (a scan of 1024×128 is 4 MB), not the SDK's
/// default 1024 messages.
const BACKLOG: usize = 128;

/// Starts the WebSocket server at `HOST:PORT`.
fn serve(ctx: &Arc<Context>, address: &str) -> Result<WebSocketServerHandle, ViewError> {
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
    let host = host.trim_start_matches('[').trim_end_matches(']');
    ctx.websocket_server()
        .name("keylo")
        .message_backlog_size(BACKLOG)
        .bind(host, port)
        .start_blocking()
        .map_err(|e| err(e.to_string()))
}
