//! One set of channels on one Foxglove context, and how a frame's results become their
//! messages. The live view and the recording each have one.

use std::collections::HashMap;
use std::sync::Arc;

use foxglove::messages::{ImageAnnotations, PoseInFrame, PosesInFrame, RawImage};
use foxglove::{Channel, Context, PartialMetadata};
use keylo_core::{FrameFeatures, Pose, Trajectory};
use nalgebra::Point3;

use crate::channels::Channels;
use crate::convert::{self, nanos, timestamp};
use crate::frame_view::FrameView;
use crate::{images, reference, scan_cdr, stats, ViewError};

pub struct Streams {
    ctx: Arc<Context>,
    ch: Channels,
    images: HashMap<String, (Channel<RawImage>, Channel<ImageAnnotations>)>,
    world: String,
    sensor: String,
    /// The scan as recorded (every pixel and channel, for `keylo run --data`) rather than as
    /// watched (the valid points, `x y z intensity`).
    full_scan: bool,
    trajectory: Vec<(f64, Pose)>,
    reference: Option<Trajectory>,
    aligned: Option<Vec<(f64, Pose)>>,
}

impl Streams {
    pub fn new(
        ctx: Arc<Context>,
        (world, sensor): (&str, &str),
        reference: Option<Trajectory>,
        full_scan: bool,
    ) -> Result<Self, ViewError> {
        Ok(Self {
            ch: Channels::new(&ctx)?,
            ctx,
            images: HashMap::new(),
            world: world.into(),
            sensor: sensor.into(),
            full_scan,
            trajectory: Vec::new(),
            reference,
            aligned: None,
        })
    }

    /// Whether any sink takes the map (only then is it worth fetching and sending).
    pub fn takes_map(&self) -> bool {
        self.ch.map.has_sinks()
    }

    /// Whether a live client subscribed to any fixed channel.
    pub fn any_subscribed(&self) -> bool {
        self.ch.any_subscribed()
    }

    /// Advertises the images `names` before the first frame.
    pub fn announce_images(&mut self, names: &[String]) {
        for n in names {
            self.image_channels(n);
        }
    }

    /// The small per-frame messages: the pose, the transform (at the scan's start and end, so
    /// the scan stamped at its start finds one), the figures; and the trajectory kept.
    pub fn light(&mut self, v: &FrameView) {
        let r = v.result;
        let stamp = r.stamp;
        for t in [v.frame.timestamp, stamp] {
            let tf = convert::transform(t, &self.world, &self.sensor, &r.pose);
            self.ch.tf.log_with_time(&tf, nanos(t));
        }
        let pose = PoseInFrame {
            timestamp: Some(timestamp(stamp)),
            frame_id: self.world.clone(),
            pose: Some(convert::pose(&r.pose)),
        };
        self.ch.pose.log_with_time(&pose, nanos(stamp));
        let meta = PartialMetadata::with_log_time(nanos(stamp));
        (self.ch.stats).log_with_meta(&stats::message(r, 1e3 * v.seconds), meta);
        self.trajectory.push((stamp, r.pose));
        if self.aligned.is_none() {
            self.aligned =
                (self.reference.as_ref()).and_then(|t| reference::aligned(t, stamp, &r.pose));
        }
    }

    /// The large per-frame messages, each only when a sink takes it: the scan, the registered
    /// cloud, the images and their keypoints.
    pub fn heavy(&mut self, v: &FrameView) {
        let stamp = v.result.stamp;
        if self.ch.scan.has_sinks() {
            let bytes = match self.full_scan {
                true => scan_cdr::scan(v.frame, &self.sensor),
                false => scan_cdr::points(v.frame, &self.sensor),
            };
            let meta = PartialMetadata::with_log_time(nanos(v.frame.timestamp));
            self.ch.scan.log_with_meta(&bytes, meta);
        }
        if let Some(c) = v.cloud.filter(|_| self.ch.registered.has_sinks()) {
            let msg = convert::cloud(stamp, &self.sensor, c.points.iter());
            self.ch.registered.log_with_time(&msg, nanos(stamp));
        }
        if let Some(f) = v.features {
            self.features(stamp, f);
        }
    }

    fn features(&mut self, stamp: f64, features: &FrameFeatures) {
        let sensor = self.sensor.clone();
        for c in &features.per_image {
            let (image, keypoints) = self.image_channels(&c.image.name());
            if image.has_sinks() {
                let msg = images::raw_image(stamp, &sensor, &c.image);
                image.log_with_time(&msg, nanos(stamp));
            }
            if keypoints.has_sinks() {
                let msg = images::keypoints(stamp, &c.keypoints);
                keypoints.log_with_time(&msg, nanos(stamp));
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

    /// The map (world frame).
    pub fn map(&self, stamp: f64, map: &[Point3<f64>]) {
        if self.takes_map() {
            let msg = convert::cloud(stamp, &self.world, map.iter());
            self.ch.map.log_with_time(&msg, nanos(stamp));
        }
    }

    /// The trajectory so far and the reference, at the last frame's stamp.
    pub fn paths(&self) {
        let Some(&(stamp, _)) = self.trajectory.last() else {
            return;
        };
        let send = |ch: &Channel<PosesInFrame>, poses: &[(f64, Pose)]| {
            if ch.has_sinks() {
                let msg = PosesInFrame {
                    timestamp: Some(timestamp(stamp)),
                    frame_id: self.world.clone(),
                    poses: reference::thinned(poses).map(convert::pose).collect(),
                };
                ch.log_with_time(&msg, nanos(stamp));
            }
        };
        send(&self.ch.trajectory, &self.trajectory);
        if let Some(a) = &self.aligned {
            send(&self.ch.reference, a);
        }
    }

    /// The stamp of the last frame sent.
    pub fn last_stamp(&self) -> Option<f64> {
        self.trajectory.last().map(|t| t.0)
    }
}
